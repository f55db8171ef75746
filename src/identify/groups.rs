//! Parameter combinations the part cannot separate (null space and near-dependencies) or can see
//! only weakly, turned into named groups such as `EA0Z - 0.98 EA0C`.
//!
//! **Naming rule.** A direction `v` (unit length in a scaled space where parameters are
//! comparable) is named by its largest components, taken in decreasing `|v_j|` until they carry
//! 90 % of `‖v‖²`; the rest (≤ 10 % of the direction's energy) is dropped. Coefficients are then
//! written in physical units (mm, rad), normalised so that the leading term (largest `|v_j|`) has
//! coefficient 1, with two decimals (a coefficient within 0.005 of ±1 is written as the sign only).
//!
//! **Not separable** (condition index `η ≥ 30`, or numerically null): directions whose named
//! parameters overlap are merged into one group over parameters `J`. The data fix every linear
//! functional `c·x` with `c ⊥ d_k` for the group's unresolved directions `d_k = D⁻¹ v_k`
//! (restricted to `J`); a basis of them is found by Gauss-Jordan elimination of the `d_k` with
//! pivots on the largest scaled component: each non-pivot parameter `f` gives
//! `c = e_f - Σ (d_pivot,f / d_pivot,pivot)·e_pivot`, which is exactly orthogonal to the `d_k`.
//! These are the *estimable combinations*, reported with value and std.
//!
//! **Weak** directions: eigenvectors of the covariance expressed in typical magnitudes
//! (`T⁻¹ Cov T⁻¹`, `T` = 1e-4 rad / 0.01 mm, the units of paper 000 Figure 19) whose std exceeds
//! a fraction (default 1/4) of a typical error: their ±2 std (95 %) interval is as wide as one
//! typical error, so the part cannot tell a typical error along them from none.

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::numerics::order::sort_by_key_f64_descending;
use crate::numerics::terms::{by_decreasing_magnitude, dominant, magnitude_text, Term};

/// A named linear combination of parameters, e.g. `EA0Z - 0.98 EA0C`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Combination {
    /// Readable form.
    pub text: String,
    /// The terms (leading term first, coefficient 1).
    pub terms: Vec<Term>,
}

impl Combination {
    /// `Σ coefficient · x[name]` for a full parameter vector in `names` order.
    pub fn apply(&self, names: &[String], x: &[f64]) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                names
                    .iter()
                    .position(|n| *n == t.name)
                    .map_or(0.0, |j| t.coefficient * x[j])
            })
            .sum()
    }

    /// The coefficient vector in `names` order.
    pub fn vector(&self, names: &[String]) -> Vec<f64> {
        let mut c = vec![0.0; names.len()];
        for t in &self.terms {
            if let Some(j) = names.iter().position(|n| *n == t.name) {
                c[j] = t.coefficient;
            }
        }
        c
    }
}

/// Why a group is reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GroupKind {
    /// The design cannot separate these parameters (null space or condition index ≥ limit); the
    /// unresolved combination is fixed at 0 in the scaled space (minimum norm within the group).
    NotSeparable,
    /// Estimated, but the noise leaves a std above the weak limit along these directions.
    Weak,
}

/// A direction in parameter space.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Direction {
    pub combination: Combination,
    /// `s₁/s_k` of the unit-scaled design (not-separable directions).
    pub condition_index: Option<f64>,
    /// Std along the direction in typical magnitudes (weak directions).
    pub std_in_typical: Option<f64>,
    /// Value of the combination (weak directions; not determined for not-separable ones).
    pub value: Option<f64>,
    /// Std of the combination.
    pub std: Option<f64>,
}

/// A combination the data do determine, with its value and std.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Estimable {
    pub combination: Combination,
    pub value: f64,
    pub std: Option<f64>,
}

/// A group of parameters the part cannot separate, or sees only weakly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Group {
    pub kind: GroupKind,
    /// The parameters involved.
    pub parameters: Vec<String>,
    /// The unresolved (not separable) or poorly resolved (weak) directions.
    pub directions: Vec<Direction>,
    /// What the data do determine inside the group (not-separable groups).
    pub estimable: Vec<Estimable>,
    /// One sentence for the report.
    pub explanation: String,
    /// Parameters outside the group whose value the group's convention also moves (not-separable
    /// groups): a nearly, not exactly, null direction has small components on parameters that
    /// are otherwise determined, and fixing the direction fixes that part of their value too.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also_convention: Vec<ConventionShare>,
}

/// A parameter outside a not-separable group that the group's convention also moves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConventionShare {
    pub name: String,
    /// `‖P_g e_j‖`: the length of the part of the parameter's unit vector (scaled space) that
    /// lies in the group's unresolved directions (0: not moved; 1: entirely in them).
    pub share: f64,
}

/// Smallest [`ConventionShare::share`] reported (3 % of the unit vector). In paper mode the
/// `EA0Z, EA0C` direction has a share of 4 % on EX0B (the backlash example); over random error
/// vectors (tests/it/proptest_identify.rs) that moved EX0B by up to 0.24 of the vector's largest
/// component in typical units (1e-4 rad, 0.01 mm), since EX0B's column scale is small.
pub const CONVENTION_SHARE_FLOOR: f64 = 0.03;

/// Formats `coef` (physical units) over the indices `keep` (leading first), normalised so that
/// the leading coefficient is 1.
pub fn combination(names: &[String], coef: &[f64], keep: &[usize]) -> Combination {
    let lead = keep.first().map_or(1.0, |&j| coef[j]);
    let lead = if lead == 0.0 { 1.0 } else { lead };
    let mut text = String::new();
    let mut terms = Vec::new();
    for (k, &j) in keep.iter().enumerate() {
        let c = coef[j] / lead;
        terms.push(Term {
            name: names[j].clone(),
            coefficient: c,
        });
        let num = magnitude_text(c.abs());
        if k == 0 {
            let sign = if c < 0.0 { "-" } else { "" };
            text.push_str(&format!("{sign}{num}{}", names[j]));
        } else {
            let sign = if c < 0.0 { " - " } else { " + " };
            text.push_str(&format!("{sign}{num}{}", names[j]));
        }
    }
    Combination { text, terms }
}

/// Merges index sets that overlap; returns, per merged set, the indices of the input sets.
pub fn merge_overlapping(sets: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut groups: Vec<(Vec<usize>, Vec<usize>)> = Vec::new(); // (members, set ids)
    for (k, s) in sets.iter().enumerate() {
        let mut members = s.clone();
        let mut ids = vec![k];
        let mut i = 0;
        while i < groups.len() {
            if groups[i].0.iter().any(|m| members.contains(m)) {
                let (gm, gi) = groups.remove(i);
                for m in gm {
                    if !members.contains(&m) {
                        members.push(m);
                    }
                }
                ids.extend(gi);
                i = 0;
            } else {
                i += 1;
            }
        }
        groups.push((members, ids));
    }
    groups
        .into_iter()
        .map(|(_, mut ids)| {
            ids.sort_unstable();
            ids
        })
        .collect()
}

/// Std of `c·x` under covariance `cov` (None if there is no covariance).
pub fn std_of(c: &[f64], cov: Option<&DMatrix<f64>>) -> Option<f64> {
    let cov = cov?;
    let mut s = 0.0;
    for i in 0..c.len() {
        for j in 0..c.len() {
            s += c[i] * cov[(i, j)] * c[j];
        }
    }
    Some(s.max(0.0).sqrt())
}

/// Builds the not-separable groups from the unresolved right singular vectors.
///
/// `dirs` holds, per unresolved direction, its unit vector in the scaled space and its
/// condition index; `scale` is `D`; `x` the solution and `cov` its covariance.
pub fn not_separable_groups(
    names: &[String],
    scale: &[f64],
    dirs: &[(Vec<f64>, f64)],
    x: &[f64],
    cov: Option<&DMatrix<f64>>,
    share: f64,
) -> Vec<Group> {
    let p = names.len();
    let sel: Vec<Vec<usize>> = dirs.iter().map(|(v, _)| dominant(v, share)).collect();
    let mut out = Vec::new();
    for ids in merge_overlapping(&sel) {
        let mut members: Vec<usize> = ids.iter().flat_map(|&k| sel[k].iter().copied()).collect();
        members.sort_unstable();
        members.dedup();
        let mut directions = Vec::new();
        // Rows: the unresolved directions in physical units d = D⁻¹ v, restricted to the members.
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for &k in &ids {
            let (v, eta) = &dirs[k];
            let d: Vec<f64> = (0..p).map(|j| v[j] / scale[j]).collect();
            directions.push(Direction {
                combination: combination(names, &d, &sel[k]),
                condition_index: Some(*eta),
                std_in_typical: None,
                value: None,
                std: None,
            });
            rows.push(members.iter().map(|&j| d[j]).collect());
        }
        // Gauss-Jordan with pivots on the largest scaled component (|d_j|·D_j).
        let m = members.len();
        let mut pivots: Vec<usize> = Vec::new(); // column (within members) of each row's pivot
        for r in 0..rows.len() {
            let free: Vec<(usize, f64)> = (0..m)
                .filter(|c| !pivots.contains(c))
                .map(|c| (c, rows[r][c].abs() * scale[members[c]]))
                .collect();
            let Some(&c) = by_decreasing_magnitude(free).first() else {
                break;
            };
            let pv = rows[r][c];
            if pv == 0.0 {
                continue;
            }
            for e in rows[r].iter_mut() {
                *e /= pv;
            }
            for r2 in 0..rows.len() {
                if r2 != r {
                    let f = rows[r2][c];
                    if f != 0.0 {
                        let pivot_row = rows[r].clone();
                        for (e, pr) in rows[r2].iter_mut().zip(&pivot_row) {
                            *e -= f * pr;
                        }
                    }
                }
            }
            pivots.push(c);
        }
        let mut estimable = Vec::new();
        for f in (0..m).filter(|c| !pivots.contains(c)) {
            let mut c = vec![0.0; p];
            c[members[f]] = 1.0;
            for (r, &pc) in pivots.iter().enumerate() {
                c[members[pc]] = -rows[r][f];
            }
            // Leading term: largest scaled coefficient |c_j| / D_j.
            let keep = by_decreasing_magnitude(
                (0..p)
                    .filter(|&j| c[j] != 0.0)
                    .map(|j| (j, c[j].abs() / scale[j]))
                    .collect(),
            );
            let comb = combination(names, &c, &keep);
            let cv = comb.vector(names);
            estimable.push(Estimable {
                value: cv.iter().zip(x).map(|(a, b)| a * b).sum(),
                std: std_of(&cv, cov),
                combination: comb,
            });
        }
        let pnames: Vec<String> = members.iter().map(|&j| names[j].clone()).collect();
        let unresolved: Vec<String> = directions
            .iter()
            .map(|d| d.combination.text.clone())
            .collect();
        let explanation = if estimable.is_empty() {
            format!(
                "the data do not determine {} at all; the solution sets {} to 0",
                pnames.join(", "),
                unresolved.join(" and ")
            )
        } else {
            format!(
                "{} cannot be separated: the data do not determine {}, they determine only {}; \
                 the values shown are a convention, not a measurement: the minimum-norm solution \
                 within the group (each parameter weighted by the deviation its unit value makes on \
                 the part; the unresolved combination set to 0); only the determined combinations \
                 are measured",
                pnames.join(", "),
                unresolved.join(" and "),
                estimable.iter().map(|e| e.combination.text.clone()).collect::<Vec<_>>().join(", ")
            )
        };
        // Parameters outside every not-separable group with a share in these directions.
        let also_convention: Vec<ConventionShare> = (0..p)
            .filter(|j| !sel.iter().any(|s| s.contains(j)))
            .map(|j| ConventionShare {
                name: names[j].clone(),
                share: ids
                    .iter()
                    .map(|&k| dirs[k].0[j].powi(2))
                    .sum::<f64>()
                    .sqrt(),
            })
            .filter(|c| c.share >= CONVENTION_SHARE_FLOOR)
            .collect();
        let explanation =
            if also_convention.is_empty() {
                explanation
            } else {
                let one = also_convention.len() == 1;
                format!(
                "{explanation}; outside the group, {} {} on this convention too ({} of the unit \
                 vector in the unresolved directions): part of {} value is set by it, not measured",
                also_convention.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", "),
                if one { "depends" } else { "depend" },
                also_convention
                    .iter()
                    .map(|c| format!("{} {:.0} %", c.name, 100.0 * c.share))
                    .collect::<Vec<_>>()
                    .join(", "),
                if one { "its" } else { "their" },
            )
            };
        out.push(Group {
            kind: GroupKind::NotSeparable,
            parameters: pnames,
            directions,
            estimable,
            explanation,
            also_convention,
        });
    }
    out
}

/// Builds the weak groups from the covariance: directions whose std exceeds `limit` typical
/// magnitudes. `typical` holds the typical magnitude of each parameter.
pub fn weak_groups(
    names: &[String],
    typical: &[f64],
    x: &[f64],
    cov: &DMatrix<f64>,
    limit: f64,
    share: f64,
) -> Vec<Group> {
    let p = names.len();
    let ct = DMatrix::from_fn(p, p, |i, j| cov[(i, j)] / (typical[i] * typical[j]));
    let eig = nalgebra::SymmetricEigen::new(ct);
    let mut dirs: Vec<(Vec<f64>, f64)> = Vec::new();
    for k in 0..p {
        let sd = eig.eigenvalues[k].max(0.0).sqrt();
        if sd > limit && sd.is_finite() {
            dirs.push((eig.eigenvectors.column(k).iter().copied().collect(), sd));
        }
    }
    sort_by_key_f64_descending(&mut dirs, |d| d.1);
    let sel: Vec<Vec<usize>> = dirs.iter().map(|(v, _)| dominant(v, share)).collect();
    let mut out = Vec::new();
    for ids in merge_overlapping(&sel) {
        let mut members: Vec<usize> = ids.iter().flat_map(|&k| sel[k].iter().copied()).collect();
        members.sort_unstable();
        members.dedup();
        let mut directions = Vec::new();
        for &k in &ids {
            let (v, sd) = &dirs[k];
            let d: Vec<f64> = (0..p).map(|j| v[j] * typical[j]).collect();
            let comb = combination(names, &d, &sel[k]);
            let cv = comb.vector(names);
            directions.push(Direction {
                value: Some(cv.iter().zip(x).map(|(a, b)| a * b).sum()),
                std: std_of(&cv, Some(cov)),
                combination: comb,
                condition_index: None,
                std_in_typical: Some(*sd),
            });
        }
        let pnames: Vec<String> = members.iter().map(|&j| names[j].clone()).collect();
        let explanation = format!(
            "{} are only weakly identifiable: along {} the std is {} typical errors \
             (1e-4 rad, 0.01 mm), above the limit {limit}; their values are uncertain",
            pnames.join(", "),
            directions
                .iter()
                .map(|d| d.combination.text.clone())
                .collect::<Vec<_>>()
                .join(" and "),
            directions
                .iter()
                .map(|d| format!("{:.2}", d.std_in_typical.unwrap_or(0.0)))
                .collect::<Vec<_>>()
                .join(" and "),
        );
        out.push(Group {
            kind: GroupKind::Weak,
            parameters: pnames,
            directions,
            estimable: Vec::new(),
            explanation,
            also_convention: Vec::new(),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Magnitudes tied to within rounding (1e-13 relative, far below `TIE`) give the same order
    /// whichever one rounding made larger; a real difference (1e-6) still wins.
    #[test]
    fn ties_within_rounding_go_to_the_lower_index() {
        let a = by_decreasing_magnitude(vec![(0, 0.5), (1, 1.0), (2, 1.0 + 1e-13)]);
        let b = by_decreasing_magnitude(vec![(0, 0.5), (1, 1.0 + 1e-13), (2, 1.0)]);
        assert_eq!(a, vec![1, 2, 0]);
        assert_eq!(b, a);
        assert_eq!(
            by_decreasing_magnitude(vec![(1, 1.0), (2, 1.0 + 1e-6)]),
            vec![2, 1]
        );
    }
}
