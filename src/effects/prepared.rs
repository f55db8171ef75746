//! The prepared settings (issue 28 item 2): everything the diagnosis and the identification take
//! from the geometry and the machine that depends on the settings alone (the part design, the
//! machine's chain with its L0, the B branch, the mode), never on the measured points or
//! deviations, built once by [`Prepared::new`] and passed to every stage that needs it:
//! - the machine's location errors ([`ErrorSet`], [`crate::sensitivity::error_set`]: the
//!   design's columns);
//! - the path model ([`PathModel`]: the reversal passes and lags, the path lengths, the
//!   envelope's pose tables; the expensive part of a part model);
//! - the part model of the part's 100 built-in points with every candidate the chain has
//!   ([`Prepared::builtin_model`]), from which the candidates that are a location error under
//!   another name ([`crate::effects::location_equivalent`]) and the machine's effect catalogue
//!   ([`crate::effects::catalogue`]) are decided.
//!
//! It is a plain value that its caller holds (the CLI one per command, the page one per machine,
//! L0, branch and mode, `validate` one per run): nothing is kept behind the caller's back. At any
//! points, [`Prepared::axis_values`] solves the points' poses once; [`Prepared::sensitivity_matrix`]
//! and [`Prepared::part_model`] take them, so that the design's columns and every effect family
//! share one inverse kinematics. The values are those computed without it, bit for bit: every
//! computation is deterministic and the same (the parity snapshots check it).

use crate::effects::builtin::{every_candidate_model, PartModel};
use crate::effects::location_equivalent::location_equivalents;
use crate::effects::path_model::PathModel;
use crate::effects::GapError;
use crate::machine::{AxisValues, ErrorParam};
use crate::numerics::parallel::Threads;
use crate::parameter::Effect;
use crate::part::{builtin_points, MeasurementPoint, SShape};
use crate::sensitivity::error_set::{error_set, ErrorSet};
use crate::sensitivity::{
    axis_values, axis_values_on, sensitivity_matrix, Mode, SensitivityError, SensitivityMatrix,
    SensitivityOptions,
};

/// The settings-only models of one part design on one machine (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Prepared {
    part: SShape,
    options: SensitivityOptions,
    error_set: ErrorSet,
    path: PathModel,
    builtin: PartModel,
    location_equivalents: Vec<(Effect, String)>,
}

impl Prepared {
    /// Prepares `part` on the chain, branch and mode of `options`: derives the machine's error
    /// set, the path model and the built-in points' model (`physical` mode for those, as
    /// effects.md defines the baseline; `options.mode` is the mode of
    /// [`Prepared::sensitivity_matrix`]).
    pub fn new(part: SShape, options: SensitivityOptions) -> Result<Self, GapError> {
        Self::on(part, options, Threads::ONE)
    }

    /// [`Prepared::new`], its path model and built-in model computed on `threads` threads: the
    /// same settings.
    pub fn on(
        part: SShape,
        options: SensitivityOptions,
        threads: Threads,
    ) -> Result<Self, GapError> {
        let physical = options.clone().with_mode(Mode::Physical);
        let error_set = error_set(&options.chain, options.branch)?;
        let path = PathModel::on(&part, &physical, threads)?;
        let errors = error_set.params();
        let points = builtin_points(&part);
        let q = axis_values(&part, &points, &physical)?;
        let builtin =
            every_candidate_model(&part, &points, &q, &physical, &errors, &path, threads)?;
        let typical: Vec<f64> = errors.iter().map(ErrorParam::typical).collect();
        let location_equivalents =
            location_equivalents(&builtin.baseline, &typical, &builtin.candidates);
        Ok(Self {
            part,
            options,
            error_set,
            path,
            builtin,
            location_equivalents,
        })
    }

    /// The settings-only path model (lags, travels, reversals, pose tables).
    pub fn path(&self) -> &PathModel {
        &self.path
    }

    /// The part design.
    pub fn part(&self) -> &SShape {
        &self.part
    }

    /// The chain (with its L0), the branch and the mode prepared for.
    pub fn options(&self) -> &SensitivityOptions {
        &self.options
    }

    /// Whether these are the prepared settings of `part` on `options` (chain, branch, mode).
    pub fn is_for(&self, part: &SShape, options: &SensitivityOptions) -> bool {
        self.part == *part && self.options == *options
    }

    /// The machine's location errors ([`crate::sensitivity::error_set`]).
    pub fn error_set(&self) -> &ErrorSet {
        &self.error_set
    }

    /// The kept location errors of the set, in the design's column order.
    pub fn errors(&self) -> Vec<ErrorParam> {
        self.error_set.params()
    }

    /// The path model of the settings.
    pub fn path_model(&self) -> &PathModel {
        &self.path
    }

    /// The model of the part's 100 built-in points with every candidate whose physics the chain
    /// has, the location equivalents included ([`Prepared::part_model_every_candidate`] there).
    pub fn builtin_model(&self) -> &PartModel {
        &self.builtin
    }

    /// The candidates of the machine that are its location errors under another name, each with
    /// why ([`crate::effects::location_equivalent`]; decided on the built-in points).
    pub fn location_equivalents(&self) -> &[(Effect, String)] {
        &self.location_equivalents
    }

    /// The axis values of the flank path at `points` on the prepared chain and branch (inverse
    /// kinematics, [`crate::sensitivity::axis_values`]): the points' poses, for
    /// [`Prepared::sensitivity_matrix`] and [`Prepared::part_model`].
    pub fn axis_values(
        &self,
        points: &[MeasurementPoint],
    ) -> Result<Vec<AxisValues>, SensitivityError> {
        axis_values(&self.part, points, &self.options)
    }

    /// [`Prepared::axis_values`] on `threads` threads: the same values.
    pub fn axis_values_on(
        &self,
        points: &[MeasurementPoint],
        threads: Threads,
    ) -> Result<Vec<AxisValues>, SensitivityError> {
        axis_values_on(&self.part, points, &self.options, threads)
    }

    /// The sensitivity matrix at `points` (axis values `q` from [`Prepared::axis_values`]) in the
    /// prepared mode, one column per location error of the set (mm per unit error).
    pub fn sensitivity_matrix(
        &self,
        points: &[MeasurementPoint],
        q: &[AxisValues],
    ) -> Result<SensitivityMatrix, SensitivityError> {
        sensitivity_matrix(&self.part, points, q, &self.options, &self.errors())
    }

    /// The part model of `points` (axis values `q` from [`Prepared::axis_values`]): the
    /// baseline of the machine's location errors in `physical` mode whatever the prepared mode
    /// (effects.md), the candidates whose physics the chain has ([`Effect::on_chain`]) except its
    /// location equivalents, each with its signature derived from the chain, and the axis
    /// reversals along the path.
    pub fn part_model(
        &self,
        points: &[MeasurementPoint],
        q: &[AxisValues],
    ) -> Result<PartModel, GapError> {
        self.part_model_on(points, q, Threads::ONE)
    }

    /// [`Prepared::part_model`] computed on `threads` threads: the same numbers.
    pub fn part_model_on(
        &self,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        threads: Threads,
    ) -> Result<PartModel, GapError> {
        let mut m = self.every_candidate_on(points, q, threads)?;
        m.candidates.retain(|c| {
            !self
                .location_equivalents
                .iter()
                .any(|(e, _)| *e == c.effect)
        });
        Ok(m)
    }

    /// [`Prepared::part_model`] with every candidate whose physics the chain has, the location
    /// equivalents included: what the formulas give, for tests of the physics.
    pub fn part_model_every_candidate(
        &self,
        points: &[MeasurementPoint],
        q: &[AxisValues],
    ) -> Result<PartModel, GapError> {
        self.every_candidate_on(points, q, Threads::ONE)
    }

    /// Every candidate's model at `points` in `physical` mode, on `threads` threads.
    fn every_candidate_on(
        &self,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        threads: Threads,
    ) -> Result<PartModel, GapError> {
        let physical = self.options.clone().with_mode(Mode::Physical);
        every_candidate_model(
            &self.part,
            points,
            q,
            &physical,
            &self.errors(),
            &self.path,
            threads,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::Branch;

    #[test]
    fn the_builtin_model_is_the_part_model_of_the_builtin_points() {
        // Bit-identical (`==` on every number): the model computed at preparation and the model
        // of the same points computed afresh; other settings are other models.
        let part = SShape::iso();
        let p = Prepared::new(part.clone(), SensitivityOptions::default()).unwrap();
        let pts = builtin_points(&part);
        let q = p.axis_values(&pts).unwrap();
        assert_eq!(
            &p.part_model_every_candidate(&pts, &q).unwrap(),
            p.builtin_model()
        );
        let positive = SensitivityOptions::default().with_branch(Branch::Positive);
        assert!(!p.is_for(&part, &positive));
        let other = Prepared::new(part.clone(), positive).unwrap();
        assert_ne!(other.builtin_model(), p.builtin_model());
    }
}
