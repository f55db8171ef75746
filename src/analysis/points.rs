//! The measured points as the part model sees them, and the design of the location errors at them.

use nalgebra::DMatrix;

use crate::cmm::{MatchedPart, MatchedPoint};
use crate::effects::prepared::Prepared;
use crate::effects::GapError;
use crate::final_fit::correct::EffectsChoice;
use crate::identify::{Design, Parameter};
use crate::machine::AxisValues;
use crate::machine::ErrorParam;
use crate::numerics::parallel::{map, Threads};
use crate::parameter::ParamId;
use crate::part::{Curve, MeasurementPoint, SShape, Surface};
use crate::sensitivity::{Mode, SensitivityOptions};

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::report::DesignColumns;
use super::session::{check_prepared, PointsModel};

/// The measurement curve (Z = 11 or 25 mm) nearer to height `z` on surface `s`.
pub fn nearest_curve(s: Surface, z: f64) -> Curve {
    let near = |c: &Curve| (c.z() - z).abs();
    Curve::ALL
        .into_iter()
        .filter(|c| c.surface() == s)
        .min_by(|a, b| near(a).total_cmp(&near(b)))
        .unwrap_or(Curve::ALL[0])
}

/// The measurement points of a matched part, at each point's own `(surface, u, v)`.
pub fn measurement_points(part: &SShape, matched: &MatchedPart) -> Vec<MeasurementPoint> {
    measurement_points_on(part, matched, Threads::ONE)
}

/// [`measurement_points`], the points side by side on `threads` threads (a frame each: 60 ms of
/// one thread at 200,000 points, issue 31): the same points.
pub fn measurement_points_on(
    part: &SShape,
    matched: &MatchedPart,
    threads: Threads,
) -> Vec<MeasurementPoint> {
    let indexed: Vec<(usize, &MatchedPoint)> = matched.points.iter().enumerate().collect();
    map(threads, &indexed, |&(i, p)| {
        let curve = nearest_curve(p.surface, p.foot[2]);
        let mut m = MeasurementPoint::at(part, i + 1, curve, p.u, p.v);
        m.surface = p.surface;
        m
    })
}

/// The sensitivity settings of an analysis: mode, branch, the chosen chain with its L0.
pub fn sensitivity_options(opts: &AnalysisOptions) -> SensitivityOptions {
    SensitivityOptions::default()
        .with_mode(opts.mode)
        .with_branch(opts.branch)
        .with_chain(opts.machine.chain(opts.l0))
}

/// The effects given to fit (`--effects ID[,ID]`) must exist on the chosen machine
/// ([`Effect::absent_from`], and not be one of its location errors under another name,
/// [`Prepared::location_equivalents`]): otherwise [`GapError::NotOnMachine`], naming the machine
/// and why.
pub fn effects_on_machine(prepared: &Prepared, opts: &AnalysisOptions) -> Result<(), GapError> {
    let EffectsChoice::Given(effects) = &opts.effects else {
        return Ok(());
    };
    let chain = opts.machine.chain(opts.l0);
    let same = prepared.location_equivalents();
    for &effect in effects {
        let located = same
            .iter()
            .find(|(e, _)| *e == effect)
            .map(|(_, r)| r.clone());
        if let Some(reason) = effect.absent_from(&chain).or(located) {
            return Err(GapError::NotOnMachine {
                effect,
                machine: opts.machine.describe().to_string(),
                reason,
            });
        }
    }
    Ok(())
}

/// The sensitivity design at `points` (axis values `q`, [`Prepared::axis_values`]) for `opts`
/// on its prepared settings (plus the `dR` column when asked).
pub fn design_at(
    prepared: &Prepared,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &AnalysisOptions,
) -> Result<(Design, DesignColumns), AnalysisError> {
    design_with(prepared, opts, || {
        let m = prepared.sensitivity_matrix(points, q)?;
        Ok((m.errors, m.values))
    })
}

/// [`design_at`] at the points of `at`: when the prepared mode is `physical`, the mode of the
/// part model, its baseline is that design's sensitivity matrix (the same call on the same points
/// and errors: the same numbers) and is not computed again (a 20,000-point scan: 3 % of
/// `diagnose`, issue 31).
pub fn design_of_points(
    prepared: &Prepared,
    at: &PointsModel,
    opts: &AnalysisOptions,
) -> Result<(Design, DesignColumns), AnalysisError> {
    let q = at.axis_values()?;
    let errors = prepared.errors();
    let baseline = at.part_model().ok().map(|m| &m.baseline).filter(|b| {
        prepared.options().mode == Mode::Physical
            && b.matrix.shape() == (at.points().len(), errors.len())
            && b.params
                .iter()
                .zip(&errors)
                .all(|(p, e)| *p == ParamId::Machine(*e))
    });
    match baseline {
        Some(b) => design_with(prepared, opts, || Ok((errors, b.matrix.clone()))),
        None => design_at(prepared, at.points(), q, opts),
    }
}

/// The design of the location errors and values `sensitivity()` gives (`points × errors`, mm
/// per unit), after the checks of the options (L0, feed, settings, effects), plus the `dR`
/// column when asked.
fn design_with(
    prepared: &Prepared,
    opts: &AnalysisOptions,
    sensitivity: impl FnOnce() -> Result<(Vec<ErrorParam>, DMatrix<f64>), AnalysisError>,
) -> Result<(Design, DesignColumns), AnalysisError> {
    if !(opts.l0.is_finite() && opts.l0 > 0.0) {
        return Err(AnalysisError::BadL0(opts.l0));
    }
    if !(opts.feed.is_finite() && opts.feed > 0.0) {
        return Err(AnalysisError::BadFeed(opts.feed));
    }
    check_prepared(prepared, opts)?;
    effects_on_machine(prepared, opts).map_err(AnalysisError::Correction)?;
    let (errors, values) = sensitivity()?;
    let mut params: Vec<Parameter> = errors.iter().map(Parameter::of_error).collect();
    let mut matrix = values;
    if opts.tool_radius {
        params.push(Parameter::tool_radius());
        matrix = matrix.insert_column(params.len() - 1, -1.0);
    }
    let design = Design::try_new(params, DMatrix::from(matrix))?;
    let columns = columns_of(&design);
    Ok((design, columns))
}

/// The named columns of a design, as the reports carry them.
pub fn columns_of(design: &Design) -> DesignColumns {
    let m = design.matrix();
    DesignColumns {
        parameters: design.ids(),
        columns: (0..m.ncols())
            .map(|k| m.column(k).iter().copied().collect())
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part::builtin_points;

    /// The design from the part model's baseline is [`design_at`]'s, bit for bit (tolerance:
    /// none), with and without the `dR` column; in `paper` mode (not the part model's) it is
    /// computed afresh, as [`design_at`].
    #[test]
    fn design_of_the_points_model_is_design_at() {
        let part = SShape::iso();
        let points = builtin_points(&part);
        for (mode, tool_radius) in [
            (Mode::Physical, false),
            (Mode::Physical, true),
            (Mode::Paper, true),
        ] {
            let opts = AnalysisOptions {
                mode,
                tool_radius,
                ..AnalysisOptions::default()
            };
            let prepared = Prepared::new(part.clone(), sensitivity_options(&opts)).unwrap();
            let at = PointsModel::new(&prepared, &points);
            let (a, _) = design_of_points(&prepared, &at, &opts).unwrap();
            let q = at.axis_values().unwrap();
            let (b, _) = design_at(&prepared, &points, q, &opts).unwrap();
            assert_eq!(a.matrix(), b.matrix(), "{mode:?} dR {tool_radius}");
            assert_eq!(a.ids(), b.ids(), "{mode:?} dR {tool_radius}");
        }
    }
}
