//! A candidate's family of shapes (effects.md, "Shapes are families"): its signatures at every
//! value of its shape grid, and, for the warm-up, at every pause between the passes too, for a
//! backlash once the diagnosis has found its lost motion, with and without the play's take-up (a
//! second shape parameter the fit profiles out, [`crate::gap::shape`]).
//!
//! Members are numbered shape-major: member `k` is the shape value `k / m` and the profiled
//! value `k % m` (`m` the profiled grid's size, 1 without one). A backlash's members are stored
//! ([`Members::Stored`]); the warm-up's are computed when asked from three vectors
//! ([`WarmUpBasis`]), so that its 12 × 6 members cost no more memory than one column a point.

use std::borrow::Cow;

use nalgebra::DMatrix;

use crate::effects::effect::warm_up_paused;
use crate::parameter::Shape;

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
}

/// What every member of the warm-up family is made of: at each point the share `x = s/s_total`
/// of the tool-tip path machined before it, whether it lies on the second pass (B, machined
/// after the pause), and `z`, the deviation per unit of machine-Z growth (`(R_W(q)ᵀẑ)·N`). The
/// member at warm-up constant `f` and pause `π` is `−warm_up_paused(x, second, f, π)·z`
/// ([`warm_up_paused`]).
#[derive(Debug, Clone, PartialEq)]
pub struct WarmUpBasis {
    pub x: Vec<f64>,
    pub second: Vec<bool>,
    pub z: Vec<f64>,
}

impl WarmUpBasis {
    /// The column at warm-up constant `f` and pause `pause` (a share of the cutting path).
    pub fn column(&self, f: f64, pause: f64) -> Vec<f64> {
        self.x
            .iter()
            .zip(&self.second)
            .zip(&self.z)
            .map(|((&x, &second), &z)| -warm_up_paused(x, second, f, pause) * z)
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
        }
    }

    /// Whether its members can be computed between the grid's values ([`Family::member_at`]).
    pub fn is_computed(&self) -> bool {
        matches!(self.members, Members::WarmUp(_))
    }

    /// The signature at any shape value `shape` and profiled value `profiled` (0 without one),
    /// for a family whose members are computed ([`Members::WarmUp`]); `None` for stored members,
    /// which exist at the grid's values only.
    pub fn member_at(&self, shape: f64, profiled: f64) -> Option<DMatrix<f64>> {
        match &self.members {
            Members::Stored(_) => None,
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
            },
        }
    }
}
