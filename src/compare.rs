//! Side-by-side comparison of two identifications (before / after compensation, two machines,
//! two dates): per parameter the difference `d = b − a` and its standard deviation.
//!
//! The two parts are measured and identified independently, so their estimates are independent
//! and `σ_d = √(σ_a² + σ_b²)` (same unit as the parameter: rad, or mm for `EX0B`, `dR`). With
//! `z = d / σ_d` the flags are:
//! - `different`: `|z| ≥ 3` — for one Gaussian parameter a false alarm has probability 0.27 %
//!   (about 2 % over 8 parameters), so this is the level at which testpiece says "changed";
//! - `suspect`: `2 ≤ |z| < 3` — 4.6 % per parameter by chance alone (about 31 % that at least one
//!   of 8 is flagged), so worth a look but not evidence on its own;
//! - `consistent`: `|z| < 2`;
//! - `undetermined`: a parameter without a standard deviation on either side (not separable:
//!   its value is the minimum-norm one, so its difference means nothing), or absent on one side.

use serde::{Deserialize, Serialize};

use crate::identify::Identification;
use crate::machine::Unit;

/// `|z|` from which a difference is flagged `different`.
pub const DIFFERENT_Z: f64 = 3.0;
/// `|z|` from which a difference is flagged `suspect`.
pub const SUSPECT_Z: f64 = 2.0;

/// One parameter of one side: value and standard deviation in `unit`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterValue {
    pub name: String,
    pub value: f64,
    /// `None` when the parameter is not separable (no std of its own).
    pub std: Option<f64>,
    /// Its unit, as the identification gave it (read back from its text where it comes in).
    pub unit: Unit,
}

/// How a difference compares with its standard deviation (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Flag {
    Consistent,
    Suspect,
    Different,
    Undetermined,
}

/// The difference of one parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Difference {
    pub name: String,
    pub unit: Unit,
    pub a: Option<f64>,
    pub a_std: Option<f64>,
    pub b: Option<f64>,
    pub b_std: Option<f64>,
    /// `b − a`.
    pub diff: Option<f64>,
    /// `√(σ_a² + σ_b²)`.
    pub std: Option<f64>,
    /// `diff / std`.
    pub z: Option<f64>,
    pub flag: Flag,
}

/// A comparison of two parts' parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    pub a: String,
    pub b: String,
    pub differences: Vec<Difference>,
    /// Names flagged `different` and `suspect`.
    pub different: Vec<String>,
    pub suspect: Vec<String>,
    /// One line in words.
    pub summary: String,
}

/// Failures of a comparison.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CompareError {
    #[error("parameter {name}: unit {a} in {a_name} but {b} in {b_name}")]
    Unit {
        name: String,
        a: Unit,
        b: Unit,
        a_name: String,
        b_name: String,
    },
    #[error("parameter {name}: value {value} or std {std:?} is not a finite number (std ≥ 0)")]
    NotFinite {
        name: String,
        value: f64,
        std: Option<f64>,
    },
}

/// The parameters of an identification as comparison inputs.
pub fn parameters_of(id: &Identification) -> Vec<ParameterValue> {
    id.parameters
        .0
        .iter()
        .map(|p| ParameterValue {
            name: p.name(),
            value: p.value,
            std: p.std,
            unit: p.unit(),
        })
        .collect()
}

fn check(p: &ParameterValue) -> Result<(), CompareError> {
    let std_ok = p.std.is_none_or(|s| s.is_finite() && s >= 0.0);
    if p.value.is_finite() && std_ok {
        Ok(())
    } else {
        Err(CompareError::NotFinite {
            name: p.name.clone(),
            value: p.value,
            std: p.std,
        })
    }
}

/// Compares `b` with `a` parameter by parameter (in `a`'s order, then `b`'s extra ones).
pub fn compare(
    a_name: &str,
    a: &[ParameterValue],
    b_name: &str,
    b: &[ParameterValue],
) -> Result<Comparison, CompareError> {
    let mut names: Vec<&str> = a.iter().map(|p| p.name.as_str()).collect();
    for p in b {
        if !names.contains(&p.name.as_str()) {
            names.push(&p.name);
        }
    }
    let mut differences = Vec::new();
    for name in names {
        let pa = a.iter().find(|p| p.name == name);
        let pb = b.iter().find(|p| p.name == name);
        for p in pa.iter().chain(pb.iter()) {
            check(p)?;
        }
        if let (Some(x), Some(y)) = (pa, pb) {
            if x.unit != y.unit {
                return Err(CompareError::Unit {
                    name: name.to_string(),
                    a: x.unit.clone(),
                    b: y.unit.clone(),
                    a_name: a_name.to_string(),
                    b_name: b_name.to_string(),
                });
            }
        }
        let unit = pa
            .or(pb)
            .map_or(Unit::Text(String::new()), |p| p.unit.clone());
        let diff = match (pa, pb) {
            (Some(x), Some(y)) => Some(y.value - x.value),
            _ => None,
        };
        let std = match (pa.and_then(|p| p.std), pb.and_then(|p| p.std)) {
            (Some(sa), Some(sb)) if diff.is_some() => Some(sa.hypot(sb)),
            _ => None,
        };
        let z = match (diff, std) {
            (Some(d), Some(s)) if s > 0.0 => Some(d / s),
            _ => None,
        };
        let flag = match z {
            None => Flag::Undetermined,
            Some(z) if z.abs() >= DIFFERENT_Z => Flag::Different,
            Some(z) if z.abs() >= SUSPECT_Z => Flag::Suspect,
            Some(_) => Flag::Consistent,
        };
        differences.push(Difference {
            name: name.to_string(),
            unit,
            a: pa.map(|p| p.value),
            a_std: pa.and_then(|p| p.std),
            b: pb.map(|p| p.value),
            b_std: pb.and_then(|p| p.std),
            diff,
            std,
            z,
            flag,
        });
    }
    let pick = |f: Flag| -> Vec<String> {
        differences
            .iter()
            .filter(|d| d.flag == f)
            .map(|d| d.name.clone())
            .collect()
    };
    let different = pick(Flag::Different);
    let suspect = pick(Flag::Suspect);
    let undetermined = pick(Flag::Undetermined);
    let mut summary = if different.is_empty() {
        format!("{b_name} vs {a_name}: no parameter differs by 3 σ or more")
    } else {
        format!(
            "{b_name} vs {a_name}: {} differ{} by 3 σ or more",
            different.join(", "),
            if different.len() == 1 { "s" } else { "" }
        )
    };
    if !suspect.is_empty() {
        summary += &format!("; between 2 and 3 σ: {}", suspect.join(", "));
    }
    if !undetermined.is_empty() {
        summary += &format!("; no uncertainty to compare: {}", undetermined.join(", "));
    }
    summary.push('.');
    Ok(Comparison {
        a: a_name.to_string(),
        b: b_name.to_string(),
        differences,
        different,
        suspect,
        summary,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(name: &str, value: f64, std: Option<f64>) -> ParameterValue {
        ParameterValue {
            name: name.into(),
            value,
            std,
            unit: Unit::Rad,
        }
    }

    #[test]
    fn differences_and_their_std_follow_the_closed_form() {
        // σ_d = √(3² + 4²) = 5 (×1e-6); d = 16e-6 → z = 3.2; d = 12e-6 → z = 2.4; 5e-6 → 1.
        let a = [
            p("EA0B", 0.0, Some(3e-6)),
            p("EB0C", 1e-5, Some(3e-6)),
            p("EC0B", 0.0, Some(3e-6)),
            p("EA0Z", 0.0, None),
        ];
        let b = [
            p("EA0B", 16e-6, Some(4e-6)),
            p("EB0C", 22e-6, Some(4e-6)),
            p("EC0B", -5e-6, Some(4e-6)),
            p("EA0Z", 1.0, Some(1e-6)),
        ];
        let c = compare("before", &a, "after", &b).unwrap();
        let d = &c.differences;
        assert!((d[0].std.unwrap() - 5e-6).abs() < 1e-18);
        assert!((d[0].z.unwrap() - 3.2).abs() < 1e-9);
        assert_eq!(d[0].flag, Flag::Different);
        assert!((d[1].z.unwrap() - 2.4).abs() < 1e-9);
        assert_eq!(d[1].flag, Flag::Suspect);
        assert!((d[2].z.unwrap() + 1.0).abs() < 1e-9);
        assert_eq!(d[2].flag, Flag::Consistent);
        assert_eq!(d[3].flag, Flag::Undetermined);
        assert_eq!(c.different, ["EA0B"]);
        assert_eq!(c.suspect, ["EB0C"]);
        assert!(c.summary.contains("EA0B differs by 3 σ"), "{}", c.summary);
    }

    #[test]
    fn units_must_agree_and_values_be_finite() {
        let mut q = p("EX0B", 0.0, Some(1e-3));
        q.unit = Unit::Mm;
        let e = compare("a", &[p("EX0B", 0.0, Some(1e-3))], "b", &[q]).unwrap_err();
        assert!(e.to_string().contains("unit rad in a but mm in b"), "{e}");
        let e = compare("a", &[p("EA0B", f64::NAN, None)], "b", &[]).unwrap_err();
        assert!(e.to_string().contains("EA0B"), "{e}");
    }
}
