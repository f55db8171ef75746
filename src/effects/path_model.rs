//! What the diagnosis needs of the tool path that depends only on the settings (the part design,
//! the machine's chain with its L0, the B branch), not on the measured points: the lag of every
//! backlash axis of the chain along the two reversal passes ([`crate::sensitivity::reversal`], the
//! first-order lag of 2 mm of tool-tip path, paper 002 §4.3), where each axis reverses, the
//! tool-tip path lengths of the surfaces ([`crate::effects::path_length`]) and the envelope's tables of
//! tool poses ([`crate::toolpath::envelope`]). It is the expensive part of a part model (two
//! passes of ~1,000 inverse kinematics and axis rates each): built once with the prepared
//! settings ([`crate::effects::prepared::Prepared`]) for every file with the same settings.
//!
//! Units: mm for path lengths, the lag per unit lost motion (mm/mm or rad/rad).

use crate::effects::data::Reversal;
use crate::effects::machine::reversals;
use crate::effects::GapError;
use crate::machine::AxisName;
use crate::numerics::parallel::{join, map, Threads};
use std::sync::Arc;

use crate::parameter::effect::{damping_of_overshoot, OVERSHOOT_GRID};
use crate::parameter::{backlash_axes, Effect};
use crate::part::{SShape, Surface};
use crate::sensitivity::reversal::{passes_on, Lag};
use crate::sensitivity::take_up::{travels, TurnTravel};
use crate::sensitivity::SensitivityOptions;
use crate::toolpath::envelope::pose_table;
use crate::toolpath::flank::ToolPose;
use crate::toolpath::tip_length::TipLength;

/// The settings-only part of a part model.
#[derive(Debug, Clone, PartialEq)]
pub struct PathModel {
    /// The lags of the chain's backlash axes ([`backlash_axes`]) on the passes of A and B.
    pub lags: [Lag; 2],
    /// The backlash family's members: at each lag of the backlash family's grid
    /// ([`crate::parameter::Effect::shape`]), each overshoot of [`OVERSHOOT_GRID`] (the first
    /// order, then settling in second order, [`Lag::with_settling`]), in the family's order
    /// (lag-major; [`PathModel::first_order`] the lags of the first order).
    pub settling: Arc<Vec<[Lag; 2]>>,
    /// Each backlash axis's travel after each of its turns on the passes of A and B
    /// ([`crate::sensitivity::take_up::travels`]): what the play's take-up is made of.
    pub travel: [Vec<Vec<TurnTravel>>; 2],
    /// Where each axis reverses, by tool-tip path length from the start of A (mm).
    pub reversals: Vec<Reversal>,
    /// The envelope's pose tables of A and B ([`crate::toolpath::envelope::pose_table`]).
    pub pose_tables: [Vec<ToolPose>; 2],
}

impl PathModel {
    /// Computes the path model of `part` on the chain and branch of `opts` (its mode is not
    /// used: the passes follow the tool, not a displaced point).
    pub fn new(part: &SShape, opts: &SensitivityOptions) -> Result<Self, GapError> {
        Self::on(part, opts, Threads::ONE)
    }

    /// [`PathModel::new`], the family's lags and the passes' travels each side by side on
    /// `threads` threads: the same model.
    pub fn on(
        part: &SShape,
        opts: &SensitivityOptions,
        threads: Threads,
    ) -> Result<Self, GapError> {
        let passes = passes_on(part, opts, threads)?;
        let axes = backlash_axes(&opts.chain);
        let grid = Effect::Backlash(AxisName::X)
            .shape()
            .map_or_else(Vec::new, |s| s.grid);
        let members: Vec<(f64, Option<f64>)> = grid
            .iter()
            .flat_map(|&tau| OVERSHOOT_GRID.map(|m| (tau, damping_of_overshoot(m))))
            .collect();
        let settling = map(threads, &members, |&(tau, zeta)| {
            [0, 1].map(|i| Lag::with_settling(part, &passes[i], &axes, tau, zeta))
        });
        let (a, b) = join(
            threads,
            || travels(part, &passes[0], &axes, opts),
            || travels(part, &passes[1], &axes, opts),
        );
        Ok(Self {
            lags: [
                Lag::of(part, &passes[0], &axes),
                Lag::of(part, &passes[1], &axes),
            ],
            settling: Arc::new(settling),
            travel: [a?, b?],
            reversals: reversals(part, &passes, &axes),
            pose_tables: [pose_table(part, Surface::A), pose_table(part, Surface::B)],
        })
    }

    /// Tool-tip path lengths of A and B (the lags' tables).
    pub fn lengths(&self) -> [&TipLength; 2] {
        [&self.lags[0].length, &self.lags[1].length]
    }

    /// The first-order lag at each lag of the family's grid, in grid order (the first member of
    /// each lag in [`PathModel::settling`]: [`OVERSHOOT_GRID`] starts with no overshoot).
    pub fn first_order(&self) -> impl Iterator<Item = &[Lag; 2]> {
        const _: () = assert!(OVERSHOOT_GRID[0] == 0.0);
        self.settling.iter().step_by(OVERSHOOT_GRID.len())
    }

    /// Every first-order lag of the family on the axes with a lost motion `b > 0` (per axis of
    /// [`PathModel::lags`], in its unit) only, with its take-up ([`Lag::taken_up`]), in the
    /// family's order.
    pub fn taken_up(&self, b: &[f64]) -> Vec<[Lag; 2]> {
        self.first_order()
            .map(|l| {
                [
                    l[0].taken_up(&self.travel[0], b),
                    l[1].taken_up(&self.travel[1], b),
                ]
            })
            .collect()
    }

    /// Tool-tip path length of A then B (mm).
    pub fn s_total(&self) -> f64 {
        self.lags.iter().map(|l| l.length.total()).sum()
    }
}
