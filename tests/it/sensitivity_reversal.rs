//! Reversal (backlash) model against the `backlash_*` columns of
//! tests/data/reference/effect_signatures.csv (physical mode, signed B; conventions in the
//! reference README) and its reversal counts per pass (X 8/8, Y 6/6, Z 7/9, B 6/8, C 1/1).

use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::AxisName;
use testpiece::machine::{Branch, Chain};
use testpiece::part::{builtin_points, SShape, Surface};
use testpiece::sensitivity::machine_path;
use testpiece::sensitivity::reversal::{
    backlash_signatures, directions, directions_of, pass, reversal_count, REVERSAL_GRID,
};
use testpiece::sensitivity::SensitivityOptions;

fn reference(col: &str) -> Vec<f64> {
    let path = format!(
        "{}/tests/data/reference/effect_signatures.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut rdr = csv::Reader::from_path(path).unwrap();
    let i = rdr
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == col)
        .unwrap();
    rdr.records()
        .map(|r| r.unwrap()[i].parse().unwrap())
        .collect()
}

#[test]
fn reversal_counts_per_pass() {
    let part = SShape::iso();
    let opts = SensitivityOptions::default();
    let pa = pass(&part, Surface::A, &opts).unwrap();
    let pb = pass(&part, Surface::B, &opts).unwrap();
    for (axis, a, b) in [
        (AxisName::X, 8, 8),
        (AxisName::Y, 6, 6),
        (AxisName::Z, 7, 9),
        (AxisName::B, 6, 8),
        (AxisName::C, 1, 1),
    ] {
        let (ga, gb) = (reversal_count(&pa, axis), reversal_count(&pb, axis));
        eprintln!("{axis}: {ga}/{gb}");
        assert_eq!((ga, gb), (a, b), "{axis}");
    }
}

#[test]
fn backlash_signatures_match_reference() {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let opts = SensitivityOptions::default();
    let axes = [
        AxisName::X,
        AxisName::Y,
        AxisName::Z,
        AxisName::B,
        AxisName::C,
    ];
    let all = backlash_signatures(&part, &pts, &axes, &opts).unwrap();
    for (got, col) in all.iter().zip([
        "backlash_x.b",
        "backlash_y.b",
        "backlash_z.b",
        "backlash_b.b",
        "backlash_c.b",
    ]) {
        let want = reference(col);
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = got
            .iter()
            .zip(&want)
            .map(|(g, w)| (g - w).abs() / scale)
            .fold(0.0f64, f64::max);
        eprintln!("{col}: max relative difference {worst:e}");
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            if (g - w).abs() / scale > 1e-6 {
                eprintln!("  point {}: {g} vs {w}", i + 1);
            }
        }
        assert!(worst < 1e-6, "{col}: {worst:e}");
    }
}

/// `pass` finds the turns from the axis rates and solves the grid only around them; its
/// directions must equal those of the full fine solution (20,001 samples), exactly, on every
/// axis, for the three chains (and other L0 and pivot lengths), both branches and both surfaces.
#[test]
fn coarse_then_fine_directions_equal_the_full_grid() {
    let part = SShape::iso();
    let us: Vec<f64> = (0..=REVERSAL_GRID)
        .map(|k| k as f64 / REVERSAL_GRID as f64)
        .collect();
    for chain in [
        Chain::paper000(PAPER000_L0),
        Chain::paper002(),
        Chain::paper001(120.0, 80.0),
        // other settings of the page: a short and a long L0, other pivot lengths
        Chain::paper000(250.0),
        Chain::paper000(750.0),
        Chain::paper001(60.0, 150.0),
    ] {
        for branch in [Branch::Signed, Branch::Positive] {
            let opts = SensitivityOptions::default()
                .with_chain(chain.clone())
                .with_branch(branch);
            for surface in Surface::BOTH {
                let p = pass(&part, surface, &opts).unwrap();
                let full: Vec<_> = machine_path(&part, &chain, surface, branch, &us)
                    .unwrap()
                    .into_iter()
                    .map(|s| s.values)
                    .collect();
                for &axis in &p.axes {
                    let want = directions_of(&full, axis);
                    let got = directions(&p, axis);
                    let diff = want.iter().zip(&got).filter(|(a, b)| a != b).count();
                    assert_eq!(
                        diff,
                        0,
                        "{} {branch:?} {surface:?} {axis}: {diff} steps differ",
                        chain.code()
                    );
                }
                println!(
                    "{} {branch:?} {surface:?}: solved {} of {} samples",
                    chain.code(),
                    p.solved,
                    us.len()
                );
            }
        }
    }
}
