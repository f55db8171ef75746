//! A large part (an optical scan's density): the structure that no candidate explains is
//! estimated on groups along the path and the final identification uses its covariance in
//! closed form (`gap::structure::CovarianceForm::Grouped`, `identify::correlated::Whitener`),
//! and the sinusoid search of the noise estimate works from sums over each curve
//! (`gap::noise::curve_reduction`); before, a 20,000-point scan with structure ran out of
//! memory (3.2 GB n × n matrices) and 2,500 points took 336 s.

use crate::parity_common::structured_scan as scan;
use testpiece::analysis::{analyse_once, AnalysisOptions};

#[test]
fn a_large_part_with_structure_is_identified_with_the_grouped_covariance() {
    let a = analyse_once(scan().as_bytes(), "scan.csv", &AnalysisOptions::default()).unwrap();
    assert_eq!(a.identification.points_used, 600);
    let report = a.diagnosis.report().unwrap();
    assert_eq!(
        report.verdict.id().as_str(),
        "unexplained",
        "{}",
        report.summary
    );
    let s = a
        .correction
        .structure
        .as_ref()
        .expect("the structure's covariance");
    let g = s.grouped.as_ref().expect("grouped above 400 points");
    assert!(g.groups <= 256 && g.groups > 100, "{} groups", g.groups);
    // The wave (10 µm, 3.5 periods a surface: about 115 mm of tool path) is found as structure
    // of about its size: amplitude within a factor 2 of its RMS 7.1 µm.
    assert!(
        s.amplitude > 0.0035 && s.amplitude < 0.0142,
        "τ = {}",
        s.amplitude
    );
    // The std include the structure: each is at least the baseline's (white-noise) std.
    for p in &a.identification.parameters.0 {
        let std = p.std.expect("a std");
        assert!(std.is_finite() && std > 0.0, "{}", p.name());
        let base = a
            .baseline
            .identification
            .parameters
            .0
            .iter()
            .find(|b| b.name() == p.name())
            .and_then(|b| b.std)
            .unwrap();
        assert!(std >= 0.9 * base, "{}: {std} < {base}", p.name());
    }
}
