//! The plain-data inputs of a diagnosis: deviations, point metadata, the baseline design and the
//! candidate signatures. Nothing here knows where the numbers came from (CMM file, simulation,
//! reference vectors), so the engine can be tested with any of them.
//!
//! Units: mm for deviations, lengths and heights; parameters in the units of their column
//! (mm/rad for an angle, mm/mm for a length). Deviation sign (s-shape.md):
//! `(measured − nominal)·N`, + = material left, − = overcut.

use std::sync::Arc;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::effects::GapError;
use crate::machine::AxisName;
use crate::numerics::order::{groups_in_order, sort_by_key_f64};
use crate::parameter::{Effect, ParamId};
use crate::part::Surface;

/// Where a measured point lies on the part and on the tool path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointMeta {
    /// Point id as in the file.
    pub id: u32,
    /// Curve label: `A_Z11`, `A_Z25`, `B_Z11`, `B_Z25` (any label works: points are grouped by it).
    pub curve: String,
    /// Surface machined by the pass that generated the point.
    pub surface: Surface,
    /// Curve parameter `u ∈ [0, 1]` of the nominal point (s-shape.md).
    pub u: f64,
    /// Contact height: height of the generating tool point above the tool tip (mm).
    pub h: f64,
    /// Tool-tip path length from the start of surface A to the point's generating pose (mm).
    pub s: f64,
    /// Machining order (0 = first point machined): A before B, increasing `u`.
    pub order: usize,
    /// Z component of the outward normal at the point (sign of the wall's lean).
    pub nz: f64,
}

/// A matrix with one column per parameter (`n × p`, one row per point), each column with its
/// parameter's id (kind, name and unit).
#[derive(Debug, Clone, PartialEq)]
pub struct NamedColumns {
    pub params: Vec<ParamId>,
    pub matrix: DMatrix<f64>,
}

impl NamedColumns {
    /// Checks that there is one id per column and that every entry is finite.
    pub fn try_new(params: Vec<ParamId>, matrix: DMatrix<f64>) -> Result<Self, GapError> {
        if params.len() != matrix.ncols() {
            return Err(GapError::NameMismatch {
                what: "named columns".into(),
                count: params.len(),
                columns: matrix.ncols(),
            });
        }
        for (j, id) in params.iter().enumerate() {
            for i in 0..matrix.nrows() {
                let v = matrix[(i, j)];
                if !v.is_finite() {
                    return Err(GapError::NotFinite {
                        what: format!("column `{id}`"),
                        index: i,
                        value: v,
                    });
                }
            }
        }
        Ok(Self { params, matrix })
    }

    /// Builds the matrix from columns (each of length `n`).
    pub fn from_columns(params: Vec<ParamId>, columns: &[Vec<f64>]) -> Result<Self, GapError> {
        let n = columns.first().map_or(0, Vec::len);
        for (id, c) in params.iter().zip(columns) {
            if c.len() != n {
                return Err(GapError::LengthMismatch {
                    what: format!("column `{id}`"),
                    got: c.len(),
                    expected: n,
                });
            }
        }
        let matrix = DMatrix::from_fn(n, columns.len(), |i, j| columns[j][i]);
        Self::try_new(params, matrix)
    }

    /// The columns' names, in order.
    pub fn names(&self) -> Vec<String> {
        self.params.iter().map(ParamId::name).collect()
    }

    pub fn nrows(&self) -> usize {
        self.matrix.nrows()
    }
    pub fn ncols(&self) -> usize {
        self.matrix.ncols()
    }

    /// The rows `rows` (in that order).
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        Self {
            params: self.params.clone(),
            matrix: self.matrix.select_rows(rows),
        }
    }
}

/// A candidate unmodelled effect of effects.md and its signature per unit of each parameter
/// (`n × q`, one column per parameter of the effect, in the order of
/// [`Effect::parameters`]), at the reference value of its shape when it has one.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    pub effect: Effect,
    /// Shared: a part model rebuilt with a backlash's take-up
    /// ([`crate::effects::builtin::PartModel::with_take_up`]) and a candidate at a shape
    /// ([`Candidate::at_shape`]) keep the columns they do not change without copying them (a
    /// dense scan's ~100 signature columns: 0.15 GB at 200,000 points).
    pub signature: Arc<NamedColumns>,
    /// The signatures at every value of the effect's shape grid ([`Effect::shape`]), `None` for
    /// an effect of one shape.
    pub family: Option<Family>,
}

pub use crate::effects::family::Family;

impl Candidate {
    /// A candidate of one shape.
    pub fn new(effect: Effect, signature: NamedColumns) -> Self {
        Self {
            effect,
            signature: Arc::new(signature),
            family: None,
        }
    }

    /// The rows `rows` (in that order), of the signature and of every member of the family.
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        Self {
            effect: self.effect,
            signature: Arc::new(self.signature.select_rows(rows)),
            family: self.family.as_ref().map(|f| f.select_rows(rows)),
        }
    }

    /// The candidate of one shape at the member `index` of its family (itself when it has
    /// none): what the final fit uses once the diagnosis has fitted the shape.
    pub fn at_shape(&self, index: Option<usize>) -> Self {
        match (&self.family, index) {
            (Some(f), Some(k)) if k < f.len() => Self {
                effect: self.effect,
                signature: Arc::new(NamedColumns {
                    params: self.signature.params.clone(),
                    matrix: f.member(k).into_owned(),
                }),
                family: None,
            },
            _ => Self {
                family: None,
                ..self.clone()
            },
        }
    }
}

/// Everything a diagnosis needs, as plain data.
#[derive(Debug, Clone)]
pub struct GapInput<'a> {
    /// Measured normal deviations (mm), one per point.
    pub deviations: Vec<f64>,
    /// Metadata of the points, same order (borrowed from the part model like the candidates:
    /// 22 MB at 200,000 points).
    pub points: std::borrow::Cow<'a, [PointMeta]>,
    /// The baseline design: defect per unit of each baseline parameter (location errors;
    /// borrowed from the part model, 21 MB at 200,000 points).
    pub baseline: std::borrow::Cow<'a, NamedColumns>,
    /// The candidates tried one at a time on top of the baseline: borrowed from the part model
    /// (a dense scan's ~100 signature columns are not copied: 0.15 GB at 200,000 points,
    /// issue 31), owned when rows are left out ([`crate::measurement::outliers::without_rows`]).
    pub candidates: std::borrow::Cow<'a, [Candidate]>,
    /// CMM repeatability (mm, 1σ) when known; otherwise the noise is estimated from the data.
    pub noise_sigma: Option<f64>,
    /// Axis reversals along the tool path, when known (for the WHERE part).
    pub reversals: Vec<Reversal>,
}

/// An axis reversal along the tool path: the axis and the tool-tip path length where it happens.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Reversal {
    pub axis: AxisName,
    /// Tool-tip path length from the start of A (mm).
    pub s: f64,
}

impl GapInput<'_> {
    /// Validates lengths, finiteness, the sigma and candidate ids.
    pub fn validate(&self) -> Result<(), GapError> {
        let n = self.deviations.len();
        for (i, &y) in self.deviations.iter().enumerate() {
            if !y.is_finite() {
                return Err(GapError::NotFinite {
                    what: "deviation".into(),
                    index: i,
                    value: y,
                });
            }
        }
        if self.points.len() != n {
            return Err(GapError::LengthMismatch {
                what: "point metadata".into(),
                got: self.points.len(),
                expected: n,
            });
        }
        for (i, p) in self.points.iter().enumerate() {
            for (what, v) in [("u", p.u), ("h", p.h), ("s", p.s), ("nz", p.nz)] {
                if !v.is_finite() {
                    return Err(GapError::NotFinite {
                        what: format!("point metadata `{what}`"),
                        index: i,
                        value: v,
                    });
                }
            }
        }
        if self.baseline.nrows() != n {
            return Err(GapError::LengthMismatch {
                what: "baseline design rows".into(),
                got: self.baseline.nrows(),
                expected: n,
            });
        }
        let p = self.baseline.ncols();
        let needed = p + 6;
        if n < needed {
            return Err(GapError::TooFewPoints {
                points: n,
                parameters: p,
                needed,
            });
        }
        let mut seen = std::collections::BTreeSet::new();
        for c in self.candidates.iter() {
            if !seen.insert(c.effect) {
                return Err(GapError::DuplicateCandidate(c.effect));
            }
            if c.signature.ncols() == 0 {
                return Err(GapError::EmptyCandidate(c.effect));
            }
            if c.signature.nrows() != n {
                return Err(GapError::LengthMismatch {
                    what: format!("signature of `{}`", c.effect),
                    got: c.signature.nrows(),
                    expected: n,
                });
            }
        }
        if let Some(s) = self.noise_sigma {
            if !(s.is_finite() && s > 0.0) {
                return Err(GapError::BadSigma(s));
            }
        }
        Ok(())
    }
}

/// Indices of the points of each curve, in increasing `u`, curves in order of first appearance.
pub fn curve_sequences(points: &[PointMeta]) -> Vec<(String, Vec<usize>)> {
    groups_in_order(
        points
            .iter()
            .enumerate()
            .map(|(i, p)| (i, p.curve.as_str())),
    )
    .into_iter()
    .map(|(curve, mut v)| {
        sort_by_key_f64(&mut v, |&i| points[i].u);
        (curve.to_string(), v)
    })
    .collect()
}

/// Whether the points' groups are a scan's lines ([`crate::measurement::scan_lines`]): more
/// than two on a surface. A discrete layout labels each point with one of its surface's two
/// measurement curves.
pub fn is_scan(points: &[PointMeta]) -> bool {
    Surface::BOTH.into_iter().any(|s| {
        let mut labels: Vec<&str> = Vec::new();
        for p in points.iter().filter(|p| p.surface == s) {
            if !labels.contains(&p.curve.as_str()) {
                labels.push(&p.curve);
                if labels.len() > 2 {
                    return true;
                }
            }
        }
        false
    })
}
