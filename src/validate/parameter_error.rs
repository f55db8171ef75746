//! The parameter error of an identified answer against the simulated truth: how far the location
//! errors a user would export are from the `ξ` the part was simulated with, and whether their std
//! says so honestly.
//!
//! For an answer `x̂` with std `s` and the truth `ξ` over the location errors `j` (the baseline's
//! columns; effect parameters of a final answer are not counted):
//! - **largest error** `max_j |x̂_j − ξ_j| / t_j`, in typical units `t_j` of
//!   [`crate::machine::location_errors::LocationError::typical`] (1e-4 rad for angles, 0.01 mm for `EX0B`): issue 17
//!   measures "how wrong the answer is" by it;
//! - **covered**: the number of `j` with `|x̂_j − ξ_j| ≤ 2 s_j` ([`COVER_STD`]); a parameter without
//!   std (not separable) is not covered. With an honest std about 95 % are.
//!
//! Summaries over a group of cases give the median largest error and the coverage
//! `Σ covered / Σ parameters`, for the baseline and the final answer side by side.

use std::collections::BTreeMap;

use nalgebra::DVector;
use serde::Serialize;

use crate::identify::{Identification, Parameter};

/// `|x̂ − ξ| ≤ COVER_STD · std` counts as covered (2: 95 % for a Gaussian error).
pub const COVER_STD: f64 = 2.0;

/// The error of one answer against the truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnswerError {
    /// `max_j |x̂_j − ξ_j| / typical_j` (typical units; ∞ when a location error is missing or
    /// not finite).
    pub largest_error: f64,
    /// The location error where it is largest.
    pub largest_at: String,
    /// Location errors with `|x̂_j − ξ_j| ≤ 2 std_j`.
    pub covered: usize,
    /// Location errors compared.
    pub parameters: usize,
    /// Per location error, by name: how far and in which direction the answer is off.
    pub per_parameter: BTreeMap<String, Miss>,
}

/// One location error of an answer against its true value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Miss {
    /// `(x̂ − ξ) / typical` (signed, typical units).
    pub error: f64,
    /// The answer's std over the typical magnitude; `None` without std.
    pub std: Option<f64>,
    /// `(x̂ − ξ) / std`: an honest std gives |z| ≤ 2 for about 95 % of the cases; `None` without
    /// std.
    pub z: Option<f64>,
}

/// The error of `answer` on the location errors `parameters` whose true values are `truth`
/// (same order; rad and mm).
pub fn answer_error(
    parameters: &[Parameter],
    truth: &DVector<f64>,
    answer: &Identification,
) -> AnswerError {
    let mut out = AnswerError {
        largest_error: 0.0,
        largest_at: String::new(),
        covered: 0,
        parameters: parameters.len(),
        per_parameter: BTreeMap::new(),
    };
    for (p, &xi) in parameters.iter().zip(truth.iter()) {
        let est = answer.parameters.of(&p.id);
        let signed = est.map_or(f64::NAN, |e| e.value - xi);
        let miss = if signed.is_finite() {
            signed.abs()
        } else {
            f64::INFINITY
        };
        let std = est
            .and_then(|e| e.std)
            .filter(|s| s.is_finite() && *s > 0.0);
        out.per_parameter.insert(
            p.name(),
            Miss {
                error: signed / p.typical,
                std: std.map(|s| s / p.typical),
                z: std.map(|s| signed / s),
            },
        );
        let typical = miss / p.typical;
        if out.largest_at.is_empty() || typical > out.largest_error {
            out.largest_error = typical;
            out.largest_at = p.name();
        }
        let within = std.is_some_and(|s| miss <= COVER_STD * s);
        out.covered += usize::from(within);
    }
    out
}

/// The errors of a group of answers.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct ErrorSummary {
    /// Median over the cases of the largest error (typical units; NaN without cases).
    pub median_largest_error: f64,
    /// Location errors within 2 std of the truth, over all cases.
    pub covered: usize,
    /// Location errors compared, over all cases.
    pub parameters: usize,
    /// `covered / parameters` (NaN without cases).
    pub coverage: f64,
}

impl ErrorSummary {
    /// The summary of `errors`.
    pub fn of<'a>(errors: impl Iterator<Item = &'a AnswerError>) -> Self {
        let mut largest = Vec::new();
        let (mut covered, mut parameters) = (0, 0);
        for e in errors {
            largest.push(e.largest_error);
            covered += e.covered;
            parameters += e.parameters;
        }
        ErrorSummary {
            median_largest_error: crate::numerics::stats::median(&mut largest),
            covered,
            parameters,
            coverage: if parameters > 0 {
                covered as f64 / parameters as f64
            } else {
                f64::NAN
            },
        }
    }
}

/// The baseline and the final answer of the same cases, side by side.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct ErrorComparison {
    pub cases: usize,
    /// The location errors fitted alone.
    pub baseline: ErrorSummary,
    /// The final answer ([`crate::final_fit::correct`]).
    pub final_answer: ErrorSummary,
}

impl ErrorComparison {
    /// The comparison over cases given as `(baseline error, final error)`.
    pub fn of<'a>(cases: impl Iterator<Item = (&'a AnswerError, &'a AnswerError)> + Clone) -> Self {
        ErrorComparison {
            cases: cases.clone().count(),
            baseline: ErrorSummary::of(cases.clone().map(|c| c.0)),
            final_answer: ErrorSummary::of(cases.map(|c| c.1)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::identify::{identify, Design, IdentifyOptions, Observations};
    use nalgebra::DMatrix;

    /// A two-parameter fit with a known answer: `y = x₀·1 + x₁·t` on 5 points, no noise except a
    /// given residual, so values and std are known in closed form.
    fn fit(y: &[f64]) -> (Vec<Parameter>, Identification) {
        let a = DMatrix::from_fn(5, 2, |i, j| if j == 0 { 1.0 } else { i as f64 - 2.0 });
        let ps: Vec<Parameter> = ["EA0B", "EX0B"]
            .iter()
            .map(|n| Parameter::parse(n).unwrap())
            .collect();
        let d = Design::try_new(ps.clone(), a).unwrap();
        let id = identify(
            &d,
            &Observations::plain(y.to_vec()),
            &IdentifyOptions::default().with_sigma(1e-4),
        )
        .unwrap();
        (ps, id)
    }

    #[test]
    fn largest_error_is_in_typical_units_and_coverage_uses_two_std() {
        // y = 3e-4 + 0·t exactly: x̂ = (3e-4, 0); std with σ = 1e-4 mm: x₀ 1e-4/√5 = 4.47e-5,
        // x₁ 1e-4/√10 = 3.16e-5.
        let (ps, id) = fit(&[3e-4; 5]);
        // Truth (2.5e-4 rad, 0.05 mm): x₀ off by 5e-5 rad = 0.5 typical (1e-4 rad), within
        // 2·4.47e-5; x₁ off by 0.05 mm = 5 typical (0.01 mm), not covered.
        let e = answer_error(&ps, &DVector::from_vec(vec![2.5e-4, 0.05]), &id);
        assert!((e.largest_error - 5.0).abs() < 1e-9, "{e:?}");
        assert_eq!(e.largest_at, "EX0B");
        assert_eq!((e.covered, e.parameters), (1, 2));
        let m = &e.per_parameter["EX0B"];
        assert!((m.error + 5.0).abs() < 1e-9, "{m:?}");
        assert!(
            (m.std.unwrap() - 1e-4 / 10f64.sqrt() / 0.01).abs() < 1e-12,
            "{m:?}"
        );
        assert!(
            (m.z.unwrap() + 0.05 / (1e-4 / 10f64.sqrt())).abs() < 1e-6,
            "{m:?}"
        );
        let e = answer_error(&ps, &DVector::from_vec(vec![3e-4, 0.0]), &id);
        assert!(e.largest_error < 1e-9, "{e:?}");
        assert_eq!(e.covered, 2);
    }

    #[test]
    fn summaries_take_the_median_and_pool_the_coverage() {
        let e = |l: f64, c: usize| AnswerError {
            largest_error: l,
            largest_at: "EA0B".into(),
            covered: c,
            parameters: 8,
            per_parameter: BTreeMap::new(),
        };
        let b = [e(1.0, 8), e(5.0, 4), e(3.0, 6), e(2.0, 7)];
        let f = [e(0.5, 8), e(0.7, 8), e(0.1, 8), e(0.2, 7)];
        let c = ErrorComparison::of(b.iter().zip(f.iter()));
        assert_eq!(c.cases, 4);
        assert_eq!(c.baseline.median_largest_error, 2.5);
        assert_eq!((c.baseline.covered, c.baseline.parameters), (25, 32));
        assert_eq!(c.final_answer.median_largest_error, 0.35);
        assert_eq!(c.final_answer.coverage, 31.0 / 32.0);
        assert!(ErrorSummary::of([].iter()).median_largest_error.is_nan());
    }
}
