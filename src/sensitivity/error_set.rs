//! Each machine's location errors, derived from what the part can see (issue 20).
//!
//! **The rule.** Start from the whole ISO 230-1 list of location errors of the chain's axes:
//! for a linear axis its zero offset (`EX0X` …) and its two squareness angles; for a rotary axis
//! the two positions of its line across it, its two tilts, and its angular zero (`EC0C` …). Take
//! their columns at the design's points (the linear machined defect per unit error, `physical`
//! mode, the chain's branch: [`super::defect::jacobian_rows`]), each scaled by its typical size
//! (1e-4 rad, 0.01 mm: paper 000 Figure 19's units), and go through them in the order below. A
//! column is **kept** when the part of it that the columns kept before it cannot absorb (its
//! residual after projection, i.e. a Gram-Schmidt step of the design's QR) has an RMS over the
//! points of at least [`VISIBLE_FRACTION`] of its own RMS: below that, the design's condition
//! index for it would exceed 30, where the identification already calls parameters not separable
//! ([`crate::identify`]). It is **invisible** when its column is zero (below
//! [`INVISIBLE_NM`] nm per typical size at every point), **absorbed** when it is visible but the
//! kept ones absorb it (it is reported with the combination the part cannot see).
//!
//! **The order** (which of two errors the part cannot tell apart carries the name):
//! 1. the free errors of the ISO 230-1 convention of paper 000 Table 3, derived from the chain
//!    ([`crate::machine::location_errors::minimal_set`]: X primary, Y secondary, origin on the
//!    first rotary axis line), in its order;
//! 2. then what the convention sets to zero, which a machine may still show: positions of the
//!    rotary axis lines (workpiece to tool), their tilts, the squareness angles, the linear
//!    axes' zero offsets;
//! 3. angular zeros of rotary axes are never kept: an index error of the axis next to the part
//!    is the rotation the effect catalogue diagnoses (`c_index`; `a_index` on the A-B head), and
//!    the others are fixed by the reference pose; their rows say how much of them the kept set
//!    absorbs.
//!
//! On paper 000's B head / C table this gives Table 3's eight (EC0Y, EA0Z, EB0Z, EA0C, EB0C,
//! EX0B, EA0B, EC0B); the C axis's offsets EX0C, EY0C are absorbed by them (the C axis line fixes
//! X = Y = 0 of the part). On paper 002's tilting table EB0C and EA0B are the same as
//! combinations of EA0Z, EB0Z, EA0C on these points (the tool moves along its own axis) and the
//! offsets of the C line across Y (EY0C) and of the B line along Z (EZ0B) are kept.
//!
//! The set is derived on the design of the part's 100 built-in points (s-shape.md: 25 per curve
//! at equal arc length), so that a machine has one set whatever the file; a file's own points
//! then decide rank and groups in the identification, as before. [`error_set`] derives it at
//! each call: a caller that needs it again keeps the value (the prepared settings,
//! [`crate::effects::prepared::Prepared`], hold their machine's set).

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::machine::chain::{AxisKind, AxisName, Chain, Side};
use crate::machine::location_errors::{minimal_set, LocationError, LocationStatus};
use crate::machine::{Branch, ErrorParam, Unit};
use crate::numerics::terms::{dominant, magnitude_text, Term};
use crate::part::{builtin_points, SShape};

use crate::sensitivity::defect::{axis_values, jacobian_displacements, Mode, SensitivityOptions};
use crate::sensitivity::SensitivityError;

/// A column is kept when at least this fraction of its RMS is left after projection on the
/// columns kept before it (condition index 30, the identification's limit of separability).
pub const VISIBLE_FRACTION: f64 = 1.0 / 30.0;

/// A column whose deviation is below this (nm per typical size) at every point is invisible.
pub const INVISIBLE_NM: f64 = 1e-3;

/// What became of one location error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorStatus {
    /// Identified: one of the machine's set.
    Kept,
    /// Visible, but the same on these points as a combination of the kept ones.
    Absorbed,
    /// Leaves no deviation on a flank-milled wall.
    Invisible,
    /// An angular zero: not part of the location set (module docs, order 3).
    Index,
}

/// One location error of the full ISO 230-1 list and what the part sees of it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorRow {
    /// The location error.
    #[serde(skip)]
    pub error: LocationError,
    /// `EY0C` …
    pub name: String,
    /// `mm` or `rad` ([`LocationError::unit`]).
    pub unit: Unit,
    pub status: ErrorStatus,
    /// RMS over the points of the deviation of one typical size of the error (mm per 1e-4 rad
    /// or per 0.01 mm).
    pub rms: f64,
    /// RMS of what the errors kept before it cannot absorb, same units.
    pub unabsorbed: f64,
    /// For an absorbed (or index) error: what one unit of it looks like on the part in terms
    /// of the kept errors (physical units), e.g. `EB0C ≈ -EB0Z`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub looks_like: Option<Equivalent>,
    /// Why, in words.
    pub reason: String,
}

/// One error in terms of others: `text` = `EX0C ≈ EX0B + …`, `terms` the right-hand side
/// (coefficient: unit of the term's error per unit of the left-hand one).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Equivalent {
    pub text: String,
    pub terms: Vec<Term>,
}

/// The location errors of one machine the part is identified with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorSet {
    /// The chain's structural code.
    pub code: String,
    /// The kept errors, in the order of the rule (the design's columns).
    pub kept: Vec<String>,
    /// Every error of the full list, in the order considered.
    pub rows: Vec<ErrorRow>,
    /// Points of the design the set was derived on.
    pub points: usize,
    /// [`VISIBLE_FRACTION`].
    pub visible_fraction: f64,
    /// The machine's coordinate convention, sentence by sentence: the reference pose where the
    /// part origin is set, what fixes X = Y = 0 and the axes' directions, and what a convention
    /// absorbs on this machine (with the figures of [`ErrorSet::rows`]).
    pub conventions: Vec<String>,
}

impl ErrorSet {
    /// The kept errors as parameters of the chain.
    pub fn params(&self) -> Vec<ErrorParam> {
        self.rows
            .iter()
            .filter(|r| r.status == ErrorStatus::Kept)
            .map(|r| ErrorParam::Location(r.error))
            .collect()
    }
    /// The row of `name`.
    pub fn row(&self, name: &str) -> Option<&ErrorRow> {
        self.rows.iter().find(|r| r.name == name)
    }
}

/// The full ISO 230-1 list of the chain, in the order of the rule (module docs), each with the
/// order group it belongs to (1, 2 or 3).
pub fn full_list(chain: &Chain) -> Vec<(LocationError, u8)> {
    let ms = minimal_set(chain);
    let mut out: Vec<(LocationError, u8)> = ms.free().into_iter().map(|e| (e, 1)).collect();
    let rotary = |e: &LocationError| e.axis.kind() == AxisKind::Rotary;
    let position = |e: &LocationError| e.component.kind() == AxisKind::Linear;
    let along_itself = |e: &LocationError| e.component.direction() == e.axis.direction();
    // The ISO 230-1 location errors the convention sets to zero (the "meaningless" rows of the
    // convention are not location errors: a linear axis line's position, a rotation of a
    // direction about itself, a rotary line's position along itself).
    let zero: Vec<LocationError> = ms
        .rows
        .iter()
        .filter(|r| r.status == LocationStatus::Zero)
        .map(|r| r.error)
        .collect();
    let classes: [&dyn Fn(&LocationError) -> bool; 4] = [
        &|e| rotary(e) && position(e),
        &|e| rotary(e) && !position(e) && !along_itself(e),
        &|e| !rotary(e) && !position(e),
        &|e| !rotary(e) && position(e),
    ];
    for class in classes {
        out.extend(zero.iter().filter(|e| class(e)).map(|&e| (e, 2)));
    }
    out.extend(
        zero.iter()
            .filter(|e| rotary(e) && !position(e) && along_itself(e))
            .map(|&e| (e, 3)),
    );
    out
}

fn typical(e: &LocationError) -> f64 {
    e.typical()
}

/// The set of `chain` with `branch`, derived on the built-in design of [`SShape::iso`]
/// ([`derive`] at its 100 built-in points).
pub fn error_set(chain: &Chain, branch: Branch) -> Result<ErrorSet, SensitivityError> {
    let part = SShape::iso();
    let points = builtin_points(&part);
    let opts = SensitivityOptions::default()
        .with_chain(chain.clone())
        .with_branch(branch)
        .with_mode(Mode::Physical);
    derive(&part, &points, &opts)
}

/// The rule of the module docs on the design of `points` (any points of the part; `opts.mode`
/// is taken as `physical`).
pub fn derive(
    part: &SShape,
    points: &[crate::part::MeasurementPoint],
    opts: &SensitivityOptions,
) -> Result<ErrorSet, SensitivityError> {
    let opts = opts.clone().with_mode(Mode::Physical);
    let list = full_list(&opts.chain);
    let params: Vec<ErrorParam> = list.iter().map(|(e, _)| ErrorParam::Location(*e)).collect();
    let q = axis_values(part, points, &opts)?;
    let disp = jacobian_displacements(part, points, &q, &opts, &params)?;
    let n = points.len();
    let rms = |v: &DVector<f64>| (v.norm_squared() / n.max(1) as f64).sqrt();
    // Columns in typical units (mm of deviation per typical size).
    let columns: Vec<DVector<f64>> = (0..list.len())
        .map(|k| {
            let t = typical(&list[k].0);
            DVector::from_iterator(
                n,
                disp.iter()
                    .zip(points)
                    .map(|(d, p)| d.column(k).dot(&p.normal) * t),
            )
        })
        .collect();
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut kept: Vec<usize> = Vec::new();
    let mut rows = Vec::with_capacity(list.len());
    for (k, &(e, group)) in list.iter().enumerate() {
        let col = &columns[k];
        let mut r = col.clone();
        for q in &basis {
            let d = r.dot(q);
            r -= q * d;
        }
        let (total, left) = (rms(col), rms(&r));
        let zero = col.amax() < INVISIBLE_NM * 1e-6;
        let visible = !zero && left >= VISIBLE_FRACTION * total;
        let status = if zero {
            ErrorStatus::Invisible
        } else if group == 3 {
            ErrorStatus::Index
        } else if visible {
            ErrorStatus::Kept
        } else {
            ErrorStatus::Absorbed
        };
        let moved = disp
            .iter()
            .map(|d| d.column(k).norm())
            .fold(0.0_f64, f64::max)
            * typical(&e);
        let (combo, reason) = match status {
            ErrorStatus::Kept => (None, kept_reason(&e, group)),
            ErrorStatus::Invisible => (None, invisible_reason(moved)),
            ErrorStatus::Absorbed | ErrorStatus::Index => {
                let combo = equivalent(&list, &columns, &kept, k);
                let reason = if status == ErrorStatus::Index {
                    index_reason(&e, &opts.chain, left)
                } else {
                    format!(
                        "the part cannot tell it from the errors kept before it ({}): {:.3} µm \
                         RMS per typical size is left, {:.1} % of its {:.3} µm (kept from {:.1} %)",
                        combo
                            .as_ref()
                            .map_or("a combination".to_string(), |c| format!("`{}`", c.text)),
                        left * 1e3,
                        100.0 * left / total,
                        total * 1e3,
                        100.0 * VISIBLE_FRACTION
                    )
                };
                (combo, reason)
            }
        };
        if status == ErrorStatus::Kept {
            let norm = r.norm();
            basis.push(r / norm);
            kept.push(k);
        }
        rows.push(ErrorRow {
            error: e,
            name: e.name(),
            unit: e.unit(),
            status,
            rms: total,
            unabsorbed: left,
            looks_like: combo,
            reason,
        });
    }
    let conventions = conventions(&opts, &rows)?;
    Ok(ErrorSet {
        conventions,
        code: opts.chain.code().to_string(),
        kept: kept.iter().map(|&k| list[k].0.name()).collect(),
        rows,
        points: n,
        visible_fraction: VISIBLE_FRACTION,
    })
}

/// What one unit of error `k` looks like on the part in terms of the kept errors: the least
/// squares fit of its column by theirs, `Σ c_j kept_j` in physical units (unit of the kept
/// error per unit of `k`), over the terms carrying 99 % of the fit (in typical sizes).
fn equivalent(
    list: &[(LocationError, u8)],
    columns: &[DVector<f64>],
    kept: &[usize],
    k: usize,
) -> Option<Equivalent> {
    if kept.is_empty() {
        return None;
    }
    let a = DMatrix::from_columns(&kept.iter().map(|&j| columns[j].clone()).collect::<Vec<_>>());
    let c = a.svd(true, true).solve(&columns[k], 1e-12).ok()?;
    let scaled: Vec<f64> = c.iter().copied().collect();
    let t0 = typical(&list[k].0);
    let mut terms = Vec::new();
    let mut text = format!("{} ≈", list[k].0.name());
    for (n, i) in dominant(&scaled, 0.99).into_iter().enumerate() {
        let j = kept[i];
        let coefficient = c[i] * typical(&list[j].0) / t0;
        let name = list[j].0.name();
        let num = magnitude_text(coefficient.abs());
        let sign = match (n, coefficient < 0.0) {
            (0, true) => " -",
            (0, false) => " ",
            (_, true) => " - ",
            (_, false) => " + ",
        };
        text.push_str(&format!("{sign}{num}{name}"));
        terms.push(Term { name, coefficient });
    }
    Some(Equivalent { text, terms })
}

/// The convention sentences of [`ErrorSet::conventions`].
fn conventions(
    opts: &SensitivityOptions,
    rows: &[ErrorRow],
) -> Result<Vec<String>, SensitivityError> {
    let chain = &opts.chain;
    let q = crate::sensitivity::defect::reference_pose(opts)?;
    let pose: Vec<String> = chain
        .code_order()
        .iter()
        .map(|a| match a.name.kind() {
            AxisKind::Linear => format!("{} = {:.3} mm", a.name, q.get(a.name)),
            AxisKind::Rotary => format!("{} = {:.1}°", a.name, q.get(a.name).to_degrees()),
        })
        .collect();
    let mut out = vec![
        format!(
            "Reference pose: the part origin is set with the tool tip on it and the tool \
             vertical, at {}; a constant displacement of the tool relative to the part is \
             removed there (the physical mode).",
            pose.join(", ")
        ),
        "Directions: X is the primary axis (it defines x), Y the secondary (with X, the xy \
         plane); the part's x, y, z are the machine's at the reference pose (ISO 230-1, paper \
         000 Table 3)."
            .to_string(),
    ];
    let first = chain
        .code_order()
        .into_iter()
        .find(|a| a.name.kind() == AxisKind::Rotary)
        .map(|a| a.name);
    if let Some(r) = first {
        let across: Vec<&ErrorRow> = rows
            .iter()
            .filter(|row| {
                let e = row.error;
                e.axis == r
                    && e.component.kind() == AxisKind::Linear
                    && e.component.direction() != r.direction()
            })
            .collect();
        let what: Vec<String> = across
            .iter()
            .map(|row| match row.status {
                ErrorStatus::Kept => format!(
                    "{} is seen ({:.3} µm RMS per 0.01 mm beyond the errors before it) and \
                     identified",
                    row.name,
                    row.unabsorbed * 1e3
                ),
                ErrorStatus::Invisible => format!("{} leaves nothing on the part", row.name),
                _ => format!(
                    "{} is absorbed by the set to {:.3} µm RMS per 0.01 mm{}",
                    row.name,
                    row.unabsorbed * 1e3,
                    row.looks_like
                        .as_ref()
                        .map_or(String::new(), |l| format!(" ({})", l.text))
                ),
            })
            .collect();
        let on_part_side = chain.axis(r).is_some_and(|a| a.side == Side::Workpiece);
        out.push(if on_part_side {
            format!(
                "X = Y = 0: the convention puts the origin on the {r} axis line (the rotary axis \
                 nearest the part); an offset of that line from where the part origin was set: \
                 {}.",
                what.join("; ")
            )
        } else {
            format!(
                "X = Y = 0: where the tool tip is at the reference pose (no rotary axis carries \
                 the part); the head's {r} axis line carries the tool with it, so an offset of \
                 it only moves the tool as a whole: {}.",
                what.join("; ")
            )
        });
    }
    Ok(out)
}

fn kept_reason(e: &LocationError, group: u8) -> String {
    let what = match (e.axis.kind(), e.component.kind()) {
        (AxisKind::Rotary, AxisKind::Linear) => "position of the axis line",
        (AxisKind::Rotary, AxisKind::Rotary) => "tilt of the axis line",
        (AxisKind::Linear, AxisKind::Rotary) => "squareness",
        (AxisKind::Linear, AxisKind::Linear) => "zero offset",
    };
    if group == 1 {
        format!("{what} (ISO 230-1 convention, paper 000 Table 3), seen by the part")
    } else {
        format!("{what}: set to zero by the convention of paper 000 Table 3, but on this machine the part sees it and the errors before it cannot absorb it")
    }
}

fn invisible_reason(moved_mm: f64) -> String {
    if moved_mm < INVISIBLE_NM * 1e-6 {
        "a constant displacement of the tool relative to the part, removed where the part \
         origin is set (the reference pose)"
            .to_string()
    } else {
        format!(
            "moves the tool (up to {:.3} µm per typical size) only within the flank-milled \
             walls, along the tool's own axis: no normal component at any point",
            moved_mm * 1e3
        )
    }
}

fn index_reason(e: &LocationError, chain: &Chain, left: f64) -> String {
    let next_to_part = chain
        .code_order()
        .first()
        .is_some_and(|a| a.name == e.axis && a.name.kind() == AxisKind::Rotary);
    let tool_side_last = chain.tool_axes().last().is_some_and(|a| a.name == e.axis);
    let effect = match e.axis {
        AxisName::C if next_to_part => Some("c_index"),
        AxisName::A if tool_side_last => Some("a_index"),
        _ => None,
    };
    match effect {
        Some(id) => format!(
            "angular zero of the {} axis: diagnosed as the effect `{id}`, not fitted with the \
             location errors ({:.3} µm RMS per 1e-4 rad beyond them)",
            e.axis,
            left * 1e3
        ),
        None => format!(
            "angular zero of the {} axis: fixed by the reference pose (the tool vertical at \
             {} = 0, where the part origin is set) as in paper 000 Table 3; the part would see \
             {:.3} µm RMS per 1e-4 rad beyond the kept errors, not fitted",
            e.axis,
            e.axis,
            left * 1e3
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::chain::PAPER000_L0;

    #[test]
    fn the_full_list_has_three_errors_per_linear_and_five_per_rotary_axis() {
        let l = full_list(&Chain::paper000(PAPER000_L0));
        assert_eq!(l.len(), 3 * 3 + 2 * 5);
        assert_eq!(l.iter().filter(|(_, g)| *g == 3).count(), 2);
    }
}
