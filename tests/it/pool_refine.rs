//! Exact-model refinement of the pooled identification (src/pool.rs, module docs): parts of a
//! machine whose errors are far beyond a real machine's, so that the linearised eq. 13 is biased;
//! LM on the exact eq. 12 at every part's points recovers the truth.

use crate::pool_common::{part_csv, NOISE, TRUTH};
use testpiece::analysis::{prepare, AnalysisOptions};
use testpiece::effects::prepared::Prepared;
use testpiece::identify::refine::ExactModel;
use testpiece::machine::Unit;
use testpiece::pool::{identify_pooled, pool_part, stack, PoolOptions, PooledExactModel};
use testpiece::tolerance::FD_REL;

/// Truth × `SCALE`: angles of 0.75e-3 to 3e-3 rad, EX0B 0.18 mm (deviations up to 1.6 mm),
/// where the linearisation error is many σ.
const SCALE: f64 = 10.0;

/// A part of the machine with every error × `scale`.
fn part(seed: u64, scale: f64) -> String {
    let errs: Vec<(String, f64)> = TRUTH
        .iter()
        .map(|(n, v)| (n.to_string(), v * scale))
        .collect();
    part_csv(&errs, seed)
}

/// The prepared settings of the pools here (paper 000's machine, the default L0, branch, mode).
fn prepared() -> Prepared {
    prepare(&AnalysisOptions::default()).unwrap()
}

fn opts(refine: bool, setup: bool) -> PoolOptions {
    PoolOptions {
        analysis: AnalysisOptions {
            noise_sigma: Some(NOISE),
            refine,
            ..Default::default()
        },
        setup_per_part: setup,
    }
}

/// Tolerance: 4 standard deviations of the refined pooled estimate (its covariance at σ = the
/// simulated CMM noise), per parameter; the truth is the simulation's input.
#[test]
fn pooled_refinement_recovers_a_strongly_non_linear_machine() {
    let (a, b) = (part(31, SCALE), part(32, SCALE));
    let files = [(a.as_bytes(), "a.csv"), (b.as_bytes(), "b.csv")];
    let exact = identify_pooled(&prepared(), &files, &opts(true, false)).unwrap();
    let linear = identify_pooled(&prepared(), &files, &opts(false, false)).unwrap();
    let r = exact.refinement.as_ref().unwrap();
    assert!(r.performed && r.success, "{r:?}");
    println!(
        "linearisation error {:.2} µm RMS (σ {:.2} µm); {}; warning: {:?}",
        r.linearisation_error_rms * 1e3,
        NOISE * 1e3,
        r.reason,
        r.warning
    );
    assert!(exact
        .identification
        .notes
        .iter()
        .any(|n| n.starts_with("values refined with the exact eq. 12 at every part's points")));
    let mut worst_linear: f64 = 0.0;
    for (name, truth) in TRUTH {
        let truth = truth * SCALE;
        let p = exact.identification.parameters.get(name).unwrap();
        let std = p.std.unwrap();
        let z = (p.value - truth) / std;
        let zl = (linear.identification.parameters.get(name).unwrap().value - truth) / std;
        println!(
            "{name}: truth {truth:.4e}, exact {:.4e} (z {z:+.2}), linear z {zl:+.1}",
            p.value
        );
        assert!(
            z.abs() <= 4.0,
            "{name}: refined {} vs truth {truth} (std {std})",
            p.value
        );
        worst_linear = worst_linear.max(zl.abs());
    }
    // The refinement matters here: the linear estimate misses by more than 4 std.
    assert!(worst_linear > 4.0, "linear worst |z| {worst_linear}");
}

/// At a real machine's magnitudes the linearisation error is far below 0.1 σ: LM is skipped
/// and the pooled values are the linear ones, bit for bit.
#[test]
fn pooled_refinement_is_skipped_at_real_magnitudes() {
    let (a, b) = (part(41, 1.0), part(42, 1.0));
    let files = [(a.as_bytes(), "a.csv"), (b.as_bytes(), "b.csv")];
    let exact = identify_pooled(&prepared(), &files, &opts(true, true)).unwrap();
    let linear = identify_pooled(&prepared(), &files, &opts(false, true)).unwrap();
    let r = exact.refinement.as_ref().unwrap();
    assert!(!r.performed, "{}", r.reason);
    assert!(r.reason.starts_with("skipped"), "{}", r.reason);
    assert_eq!(
        exact.identification.values(),
        linear.identification.values()
    );
    assert!(linear.refinement.is_none());
}

/// The pooled model's Jacobian (finite differences of eq. 12 for the shared block, the stack's
/// own columns for the per-part terms) against central differences of its deviations.
#[test]
fn pooled_model_jacobian_matches_finite_differences() {
    let o = opts(true, true);
    let o = PoolOptions {
        analysis: AnalysisOptions {
            tool_radius: true,
            ..o.analysis
        },
        ..o
    };
    let parts: Vec<_> = [(part(51, SCALE), "a.csv"), (part(52, SCALE), "b.csv")]
        .iter()
        .map(|(t, n)| pool_part(&prepared(), t.as_bytes(), n, &o.analysis).unwrap())
        .collect();
    let (design, _, per_part) = stack(&parts, &o).unwrap();
    assert_eq!(per_part.len(), 8, "dR, Rz, Tx, Ty per part");
    let m = PooledExactModel::new(&parts, &design, &o).unwrap();
    let mut x: Vec<f64> = TRUTH.iter().map(|(_, v)| v * SCALE).collect();
    x.extend([0.01, 2e-4, 0.005, -0.004, -0.02, -1e-4, 0.003, 0.002]);
    let j = m.jacobian(&x).unwrap();
    for c in 0..x.len() {
        let h = if design.parameters()[c].unit() == Unit::Rad {
            1e-7
        } else {
            1e-5
        };
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[c] += h;
        xm[c] -= h;
        let (fp, fm) = (m.deviation(&xp).unwrap(), m.deviation(&xm).unwrap());
        let colmax = (0..j.nrows()).map(|i| j[(i, c)].abs()).fold(0.0, f64::max);
        for i in 0..j.nrows() {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            testpiece::assert_near!(fd, j[(i, c)], FD_REL * colmax);
        }
    }
}
