//! Issue 20 item 1: each machine's location errors are derived from what the part sees
//! (`sensitivity::error_set`), checked here against an independent least-squares projection of
//! the whole ISO 230-1 list, and the tilting table's C-axis offset is identified.

use nalgebra::{DMatrix, DVector};
use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::cmm::write::{canonical_csv, Precision};
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::location_errors::LocationError;
use testpiece::machine::{Branch, ErrorParam, MachineErrors};
use testpiece::numerics::random::Sampler;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::defect::jacobian_rows;
use testpiece::sensitivity::error_set::{
    error_set, full_list, ErrorStatus, INVISIBLE_NM, VISIBLE_FRACTION,
};
use testpiece::sensitivity::{defect, SensitivityOptions};
use testpiece::settings::MachineChoice;

/// Columns of the whole list in typical sizes (1e-4 rad, 0.01 mm), mm.
fn columns(m: MachineChoice, branch: Branch) -> (Vec<LocationError>, Vec<DVector<f64>>) {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let chain = m.chain(PAPER000_L0);
    let list: Vec<LocationError> = full_list(&chain).into_iter().map(|(e, _)| e).collect();
    let params: Vec<ErrorParam> = list.iter().map(|&e| ErrorParam::Location(e)).collect();
    let opts = SensitivityOptions::default()
        .with_chain(chain)
        .with_branch(branch);
    let j = jacobian_rows(
        &part,
        &pts,
        &testpiece::sensitivity::axis_values(&part, &pts, &opts).unwrap(),
        &opts,
        &params,
    )
    .unwrap();
    let cols = list
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let t = if e.component.index() < 3 { 0.01 } else { 1e-4 };
            j.column(k) * t
        })
        .collect();
    (list, cols)
}

/// RMS of what the columns `by` leave of `c` (least squares by SVD).
fn left(c: &DVector<f64>, by: &[DVector<f64>]) -> f64 {
    let n = c.len() as f64;
    if by.is_empty() {
        return (c.norm_squared() / n).sqrt();
    }
    let a = DMatrix::from_columns(by);
    let x = a.clone().svd(true, true).solve(c, 1e-14).unwrap();
    ((c - a * x).norm_squared() / n).sqrt()
}

#[test]
fn each_set_follows_the_rule_on_an_independent_projection() {
    for m in MachineChoice::ALL {
        for branch in [Branch::Signed, Branch::Positive] {
            let set = error_set(&m.chain(PAPER000_L0), branch).unwrap();
            let (list, cols) = columns(m, branch);
            assert_eq!(set.rows.len(), list.len());
            let mut kept: Vec<DVector<f64>> = Vec::new();
            for (k, row) in set.rows.iter().enumerate() {
                assert_eq!(row.name, list[k].name());
                let total = left(&cols[k], &[]);
                let rest = left(&cols[k], &kept);
                assert!((total - row.rms).abs() < 1e-12, "{m:?} {}", row.name);
                // Gram-Schmidt in the core, SVD least squares here: agree to 1e-9 µm.
                assert!((rest - row.unabsorbed).abs() < 1e-12, "{m:?} {}", row.name);
                let zero = cols[k].amax() < INVISIBLE_NM * 1e-6;
                match row.status {
                    ErrorStatus::Kept => {
                        assert!(rest >= VISIBLE_FRACTION * total, "{m:?} {}", row.name);
                        kept.push(cols[k].clone());
                    }
                    ErrorStatus::Absorbed => {
                        assert!(rest < VISIBLE_FRACTION * total, "{m:?} {}", row.name)
                    }
                    ErrorStatus::Invisible => assert!(zero, "{m:?} {}", row.name),
                    ErrorStatus::Index => assert!(
                        list[k].component.direction() == list[k].axis.direction(),
                        "{m:?} {}",
                        row.name
                    ),
                }
            }
            // The kept set spans everything the part sees except the angular zeros.
            for (k, row) in set.rows.iter().enumerate() {
                if row.status != ErrorStatus::Index {
                    let total = left(&cols[k], &[]);
                    assert!(
                        left(&cols[k], &kept) <= VISIBLE_FRACTION * total + 1e-15,
                        "{m:?} {}",
                        row.name
                    );
                }
            }
            let names: Vec<&str> = set.kept.iter().map(String::as_str).collect();
            let expected: &[&str] = match m {
                // Paper 000 Table 3, out of the same rule.
                MachineChoice::Paper000 => &[
                    "EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B",
                ],
                MachineChoice::Paper002 => &[
                    "EC0Y", "EA0Z", "EB0Z", "EA0C", "EX0B", "EC0B", "EY0C", "EZ0B",
                ],
                MachineChoice::Paper001 => &[
                    "EC0Y", "EA0Z", "EB0Z", "EA0B", "EC0B", "EZ0A", "EB0A", "EC0A", "EA0Y",
                ],
            };
            assert_eq!(names, expected, "{m:?} {branch:?}");
        }
    }
}

#[test]
fn the_c_axis_offset_is_absorbed_on_paper_000_and_seen_on_the_tilting_table() {
    let s0 = error_set(&MachineChoice::Paper000.chain(PAPER000_L0), Branch::Signed).unwrap();
    let ey0c = s0.row("EY0C").unwrap();
    assert_eq!(ey0c.status, ErrorStatus::Absorbed);
    // Issue 20: "which its eight absorb to under 1 µm per 0.01 mm" (measured 0.062 µm).
    assert!(ey0c.unabsorbed < 1e-4, "{}", ey0c.unabsorbed);
    assert_eq!(s0.row("EX0C").unwrap().status, ErrorStatus::Absorbed);
    let s2 = error_set(&MachineChoice::Paper002.chain(PAPER000_L0), Branch::Signed).unwrap();
    let ey0c = s2.row("EY0C").unwrap();
    assert_eq!(ey0c.status, ErrorStatus::Kept);
    // Issue 20: "3.9 µm RMS per 0.01 mm that the eight cannot absorb" (measured 3.868 µm).
    assert!(
        (ey0c.unabsorbed - 3.9e-3).abs() < 0.1e-3,
        "{}",
        ey0c.unabsorbed
    );
    // The two pairs that move the tool along its own axis: one of each is kept.
    for (gone, with) in [("EA0B", "EA0Z"), ("EB0C", "EB0Z")] {
        let r = s2.row(gone).unwrap();
        assert_eq!(r.status, ErrorStatus::Absorbed, "{gone}");
        assert!(r.unabsorbed < 1e-9, "{gone}");
        let l = r.looks_like.as_ref().unwrap();
        assert_eq!(l.terms.len(), 1, "{}", l.text);
        assert_eq!(l.terms[0].name, with);
        assert!((l.terms[0].coefficient + 1.0).abs() < 1e-6, "{}", l.text);
    }
}

/// Clean tilting-table parts whose C axis sits 10-30 µm off the part origin (and random
/// location errors, CMM noise 1.5 µm), simulated by the exact eq. 12: the verdict is `none` and
/// EY0C is identified within 2 std.
#[test]
fn tilting_table_parts_with_a_c_axis_offset_are_clean_and_the_offset_is_identified() {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let chain = MachineChoice::Paper002.chain(PAPER000_L0);
    let opts = SensitivityOptions::default().with_chain(chain);
    let set = error_set(&opts.chain, Branch::Signed).unwrap();
    let mut rng = Sampler::new(20);
    let (mut clean, mut within, cases) = (0, 0, 40);
    for case in 0..cases {
        let mut params = Vec::new();
        let mut values = Vec::new();
        for name in &set.kept {
            let e = LocationError::parse(name).unwrap();
            if name == "EY0C" {
                continue;
            }
            params.push(ErrorParam::Location(e));
            values.push(if e.component.index() < 3 {
                rng.uniform(-0.02, 0.02)
            } else {
                rng.uniform(-1e-4, 1e-4)
            });
        }
        let ey0c = rng.sign() * rng.uniform(0.010, 0.030);
        for (name, v) in [
            ("EX0C", rng.sign() * rng.uniform(0.010, 0.030)),
            ("EY0C", ey0c),
        ] {
            params.push(ErrorParam::Location(LocationError::parse(name).unwrap()));
            values.push(v);
        }
        let d = defect(
            &part,
            &pts,
            &MachineErrors::from_pairs(&params, &values),
            &opts,
        )
        .unwrap();
        let rows: Vec<_> = pts
            .iter()
            .zip(d)
            .map(|(p, v)| (p, v + 0.0015 * rng.normal()))
            .collect();
        let csv = canonical_csv(rows, Precision::Decimals(5), None);
        let a = analyse_once(
            csv.as_bytes(),
            "offset.csv",
            &AnalysisOptions {
                machine: MachineChoice::Paper002,
                ..AnalysisOptions::default()
            },
        )
        .unwrap();
        let verdict = a.diagnosis.report().unwrap().verdict.id().to_string();
        let p = a
            .identification
            .parameters
            .0
            .iter()
            .find(|p| p.name() == "EY0C")
            .unwrap();
        let z = (p.value - ey0c) / p.std.unwrap();
        println!(
            "case {case}: EY0C {ey0c:.4} -> {:.4} ± {:.4} (z {z:.2}), {verdict}",
            p.value,
            p.std.unwrap()
        );
        clean += usize::from(verdict == "none");
        within += usize::from(z.abs() <= 2.0);
    }
    // Seed 20: 40/40 `none`, 35/40 within 2 std (z RMS 1.30). EX0C is absorbed by EX0B to
    // 1.6 % of its column (`testpiece machine --machine paper002`), and the least-squares
    // image of that 1.6 % puts -0.0168 mm of EY0C per mm of EX0C: a 30 µm EX0C biases EY0C by
    // 0.5 µm, about 1.2 std; without EX0C, 10 of the first 12 parts fall within 2 std.
    assert!(clean * 100 >= cases * 95, "{clean}/{cases} none");
    assert!(within * 100 >= cases * 80, "{within}/{cases} within 2 std");
}
