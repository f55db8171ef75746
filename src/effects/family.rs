//! A candidate's family of shapes (effects.md, "Shapes are families"): its signatures at every
//! value of its shape grid, and, for the warm-up, at every pause between the passes too, for a
//! backlash once the diagnosis has found its lost motion, with and without the play's take-up (a
//! second shape parameter the fit profiles out, [`crate::gap::shape`]).
//!
//! Members are numbered shape-major: member `k` is the shape value `k / m` and the profiled
//! value `k % m` (`m` the profiled grid's size, 1 without one). No family stores its members:
//! a backlash's are computed when asked from the lags of the passes and the axis's gains
//! ([`LagMembers`], its 18 lags × 3 overshoots), the warm-up's from three vectors
//! ([`WarmUpBasis`], its 12 constants × 6 pauses), so that a family costs no more memory than
//! one or two columns a point.

use std::borrow::Cow;
use std::sync::Arc;

use nalgebra::DMatrix;

use crate::effects::effect::WarmUp;
use crate::machine::AxisName;
use crate::parameter::Shape;
use crate::sensitivity::reversal::{lagged_column_at, GridSpots, Lag};

/// The signatures of a family: the diagnosis fits the amplitude linearly at each member and
/// keeps the best shape.
#[derive(Debug, Clone, PartialEq)]
pub struct Family {
    pub shape: Shape,
    /// A second shape parameter profiled out by the fit (the warm-up's pause between the passes,
    /// [`crate::parameter::Effect::profiled`]; a backlash's take-up,
    /// [`crate::effects::builtin::take_up_shape`]); `None` for a family of one parameter.
    pub profiled: Option<Shape>,
    pub members: Members,
}

/// How a family's members are held.
#[derive(Debug, Clone, PartialEq)]
pub enum Members {
    /// One `n × q` matrix per member, columns as the candidate's signature.
    Stored(Vec<DMatrix<f64>>),
    /// The warm-up's members, each computed from the basis when asked.
    WarmUp(WarmUpBasis),
    /// A backlash's members, each computed from its lags when asked.
    Lagged(LagMembers),
}

/// What every member of a backlash family is made of: the lags of the passes A and B of each
/// member, in member order (shared by the candidates of every axis), where each point falls on
/// the passes' grid, and the axis's gain `(∂x/∂q)·N` at each point
/// ([`crate::sensitivity::reversal::lagged_column_at`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LagMembers {
    pub lags: Arc<Vec<[Lag; 2]>>,
    pub axis: AxisName,
    pub spots: Arc<GridSpots>,
    pub gain: Vec<f64>,
}

/// What the backlash families of every axis are made of: the members' lags
/// ([`crate::effects::PathModel::settling`]), where the points fall on the passes' grid, and the
/// gains of the lags' axes (one vector per axis of the lags, in their order).
#[derive(Debug, Clone, PartialEq)]
pub struct LagBasis {
    pub lags: Arc<Vec<[Lag; 2]>>,
    pub spots: Arc<GridSpots>,
    pub gains: Vec<(AxisName, Vec<f64>)>,
}

impl LagBasis {
    /// The members of `axis`'s family; `None` when the lags do not hold the axis.
    pub fn members(&self, axis: AxisName) -> Option<LagMembers> {
        let (_, gain) = self.gains.iter().find(|(a, _)| *a == axis)?;
        Some(LagMembers {
            lags: self.lags.clone(),
            axis,
            spots: self.spots.clone(),
            gain: gain.clone(),
        })
    }
}

impl LagMembers {
    /// The column of member `k` (zeros where its lags do not hold the axis).
    pub fn column(&self, k: usize) -> Vec<f64> {
        let lags = &self.lags[k];
        match lags[0].position(self.axis) {
            Some(a) => lagged_column_at(lags, a, &self.spots, &self.gain),
            None => vec![0.0; self.gain.len()],
        }
    }

    /// The rows `rows` (in that order).
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        Self {
            lags: self.lags.clone(),
            axis: self.axis,
            spots: Arc::new(self.spots.select_rows(rows)),
            gain: rows.iter().map(|&i| self.gain[i]).collect(),
        }
    }
}

/// What every member of the warm-up family is made of: at each point the share `x = s/s_total`
/// of the tool-tip path machined before it, whether it lies on the second pass (B, machined
/// after the pause), and `z`, the deviation per unit of machine-Z growth (`(R_W(q)ᵀẑ)·N`). The
/// member at warm-up constant `f` and pause `π` is `−warm_up_paused(x, second, f, π)·z`
/// ([`crate::effects::effect::warm_up_paused`]).
#[derive(Debug, Clone, PartialEq)]
pub struct WarmUpBasis {
    pub x: Vec<f64>,
    pub second: Vec<bool>,
    pub z: Vec<f64>,
}

impl WarmUpBasis {
    /// The column at warm-up constant `f` and pause `pause` (a share of the cutting path).
    pub fn column(&self, f: f64, pause: f64) -> Vec<f64> {
        let law = WarmUp::new(f, pause);
        self.x
            .iter()
            .zip(&self.second)
            .zip(&self.z)
            .map(|((&x, &second), &z)| -law.at(x, second) * z)
            .collect()
    }

    /// The rows `rows` (in that order).
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        Self {
            x: rows.iter().map(|&i| self.x[i]).collect(),
            second: rows.iter().map(|&i| self.second[i]).collect(),
            z: rows.iter().map(|&i| self.z[i]).collect(),
        }
    }
}

impl Family {
    /// A family of one parameter with its members stored.
    pub fn stored(shape: Shape, members: Vec<DMatrix<f64>>) -> Self {
        Self {
            shape,
            profiled: None,
            members: Members::Stored(members),
        }
    }

    /// The size of the profiled grid (1 without one).
    pub fn profiled_len(&self) -> usize {
        self.profiled.as_ref().map_or(1, |p| p.grid.len())
    }

    /// The number of members.
    pub fn len(&self) -> usize {
        match &self.members {
            Members::Stored(m) => m.len(),
            Members::WarmUp(_) => self.shape.grid.len() * self.profiled_len(),
            Members::Lagged(l) => l.lags.len(),
        }
    }

    /// Whether the family has no member.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the members are as many as the grids' values (a family the fit can search).
    pub fn is_complete(&self) -> bool {
        self.len() == self.shape.grid.len() * self.profiled_len()
    }

    /// The shape value and the profiled value of member `k` (module doc).
    pub fn values(&self, k: usize) -> (f64, Option<f64>) {
        let m = self.profiled_len();
        (
            self.shape.grid[k / m],
            self.profiled.as_ref().map(|p| p.grid[k % m]),
        )
    }

    /// Member `k`'s `n × q` signature.
    pub fn member(&self, k: usize) -> Cow<'_, DMatrix<f64>> {
        match &self.members {
            Members::Stored(m) => Cow::Borrowed(&m[k]),
            Members::WarmUp(basis) => {
                let (f, pause) = self.values(k);
                let col = basis.column(f, pause.unwrap_or(0.0));
                Cow::Owned(DMatrix::from_vec(col.len(), 1, col))
            }
            Members::Lagged(l) => {
                let col = l.column(k);
                Cow::Owned(DMatrix::from_vec(col.len(), 1, col))
            }
        }
    }

    /// Whether its members can be computed between the grid's values ([`Family::member_at`]).
    pub fn is_computed(&self) -> bool {
        matches!(self.members, Members::WarmUp(_))
    }

    /// The signature at any shape value `shape` and profiled value `profiled` (0 without one),
    /// for a family whose members are computed ([`Members::WarmUp`]); `None` for the others,
    /// whose members exist at the grid's values only.
    pub fn member_at(&self, shape: f64, profiled: f64) -> Option<DMatrix<f64>> {
        match &self.members {
            Members::Stored(_) | Members::Lagged(_) => None,
            Members::WarmUp(basis) => {
                let col = basis.column(shape, profiled);
                Some(DMatrix::from_vec(col.len(), 1, col))
            }
        }
    }

    /// The rows `rows` (in that order) of every member.
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        Self {
            shape: self.shape.clone(),
            profiled: self.profiled.clone(),
            members: match &self.members {
                Members::Stored(m) => {
                    Members::Stored(m.iter().map(|x| x.select_rows(rows)).collect())
                }
                Members::WarmUp(b) => Members::WarmUp(b.select_rows(rows)),
                Members::Lagged(l) => Members::Lagged(l.select_rows(rows)),
            },
        }
    }
}
