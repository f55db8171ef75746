//! Which identified location errors a compensation enters (issue 32 item 4).
//!
//! An error is entered only if it is
//! 1. **separable**: not a member of a not-separable group of the final answer (its value there
//!    is a convention, the minimum-norm one, not a property of the machine), and
//! 2. **significant**: `|value| ≥ k·std` with `k` = [`SIGNIFICANCE_T`] = 2 (two-sided 95 % for a
//!    normal estimate), the std being the final answer's (the fit's covariance widened by the
//!    model spread, [`crate::final_fit::model_spread`]).
//!
//! Every other location error is listed with why: not significant (its value, std and
//! `t = |value|/std`), not separable (its group, and why the group's estimable combination is not
//! entered either: a combination of several errors is not one controller parameter), or no std
//! (no residual degrees of freedom). A not-entered error stays on the part: the compensation's
//! predicted part keeps its fitted part ([`super::part`]).

use serde::Serialize;

use crate::identify::GroupKind;
use crate::identify::{Identification, Status};
use crate::machine::{LocationError, Unit};

/// `|value| / std` at or above which an error is entered (two-sided 95 %, normal).
pub const SIGNIFICANCE_T: f64 = 2.0;

/// Why a location error is not entered.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum NotEnteredReason {
    /// `|value| < 2 std`.
    NotSignificant { t: f64 },
    /// Member of a not-separable group: `group` names its parameters, `estimable` its
    /// determined combinations (none is one controller parameter).
    NotSeparable {
        group: Vec<String>,
        estimable: Vec<String>,
    },
    /// The fit gave no std (no residual degrees of freedom).
    NoStd,
}

/// One location error of the final answer, as the entry rule sees it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorEntry {
    pub name: String,
    #[serde(skip)]
    pub error: LocationError,
    pub value: f64,
    pub unit: Unit,
    pub std: Option<f64>,
    pub status: Status,
    /// `None`: entered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_entered: Option<NotEnteredReason>,
    /// Why it is not entered, in a sentence ([`why_not`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

impl ErrorEntry {
    pub fn entered(&self) -> bool {
        self.not_entered.is_none()
    }
}

/// The entry decision for each `(name, error)` of the final answer `id` (module docs).
pub fn entry_rule(id: &Identification, errors: &[(String, LocationError)]) -> Vec<ErrorEntry> {
    errors
        .iter()
        .map(|(name, l)| {
            let p = id.parameters.0.iter().find(|p| p.name() == *name);
            let (value, std, status) = p.map_or((0.0, None, Status::NotSeparable), |p| {
                (p.value, p.std, p.status)
            });
            let group = id.groups.iter().find(|g| {
                g.kind == GroupKind::NotSeparable && g.parameters.iter().any(|n| n == name)
            });
            let not_entered = if let Some(g) = group.filter(|_| status == Status::NotSeparable) {
                Some(NotEnteredReason::NotSeparable {
                    group: g.parameters.clone(),
                    estimable: g
                        .estimable
                        .iter()
                        .map(|e| format!("{} = {:.4e}", e.combination.text, e.value))
                        .collect(),
                })
            } else if status == Status::NotSeparable {
                Some(NotEnteredReason::NotSeparable {
                    group: vec![name.clone()],
                    estimable: Vec::new(),
                })
            } else {
                match std {
                    None => Some(NotEnteredReason::NoStd),
                    Some(s) if value.abs() < SIGNIFICANCE_T * s => {
                        Some(NotEnteredReason::NotSignificant { t: value.abs() / s })
                    }
                    Some(_) => None,
                }
            };
            let mut e = ErrorEntry {
                name: name.clone(),
                error: *l,
                value,
                unit: l.unit(),
                std,
                status,
                not_entered,
                why: None,
            };
            e.why = why_not(&e);
            e
        })
        .collect()
}

/// One sentence for a not-entered error.
pub fn why_not(e: &ErrorEntry) -> Option<String> {
    let unit = &e.unit;
    Some(match e.not_entered.as_ref()? {
        NotEnteredReason::NotSignificant { t } => format!(
            "{} = {:.3e} ± {:.2e} {unit} (t = {:.2} < {SIGNIFICANCE_T}): not significant, not \
             entered",
            e.name,
            e.value,
            e.std.unwrap_or(f64::NAN),
            t
        ),
        NotEnteredReason::NotSeparable { group, estimable } => format!(
            "{} is not separable from {} on this part: its value is a convention, not entered{}",
            e.name,
            group
                .iter()
                .filter(|n| **n != e.name)
                .cloned()
                .collect::<Vec<_>>()
                .join(", "),
            if estimable.is_empty() {
                String::new()
            } else {
                format!(
                    " (the part determines {}: a combination of several errors, which no \
                     single controller parameter holds)",
                    estimable.join("; ")
                )
            }
        ),
        NotEnteredReason::NoStd => format!(
            "{} = {:.3e} {unit} has no std (no residual degrees of freedom): not entered",
            e.name, e.value
        ),
    })
}
