//! The part models kept for later files (issue 21): everything a diagnosis takes from the
//! geometry and the machine depends on the settings (part design, chain with its L0, B branch)
//! and on the measured points' nominal positions, never on the measured deviations. Two small
//! caches, most recently used first:
//! - [`path_model`]: the [`PathModel`] (reversal passes, lags, path lengths) by settings, reused
//!   by every file with the same settings whatever its points;
//! - [`part_model`]: the whole [`PartModel`] by settings and points (every field of every
//!   [`MeasurementPoint`], compared bit for bit), reused by a further file with the same points
//!   (a re-analysis after a change of σ, outliers or effects, the several parts of one design,
//!   the cases of `validate`).
//!
//! A value served from a cache is the value computed for the same inputs: every computation is
//! deterministic, so the results are bit-identical with or without the caches (checked in the
//! tests below and by the parity snapshots). The caches are per thread (the page's wasm is one
//! thread and keeps them for its session; each test thread has its own) and bounded by count
//! ([`PATH_CAPACITY`], [`MODEL_CAPACITY`]).

use std::cell::RefCell;
use std::rc::Rc;

use crate::effects::builtin::PartModel;
use crate::effects::path_model::PathModel;
use crate::effects::GapError;
use crate::machine::{Branch, Chain};
use crate::numerics::memo::Memo;
use crate::part::{MeasurementPoint, SShape};
use crate::sensitivity::SensitivityOptions;

/// Path models kept (each ~100 kB: the envelope's two pose tables, the lags in closed form between turns).
pub const PATH_CAPACITY: usize = 4;
/// Part models kept (each `points × ~40` numbers: 30 kB for 100 points).
pub const MODEL_CAPACITY: usize = 4;
/// Part models of more points are not kept (a dense scan's model, ~10 MB for 20,000 points,
/// would stay in memory beside its copy in use; the path model is kept for it all the same).
pub const MODEL_MAX_POINTS: usize = 2000;

/// What a path model depends on.
#[derive(Debug, Clone, PartialEq)]
struct Settings {
    part: SShape,
    chain: Chain,
    branch: Branch,
}

impl Settings {
    fn of(part: &SShape, opts: &SensitivityOptions) -> Self {
        Self {
            part: part.clone(),
            chain: opts.chain.clone(),
            branch: opts.branch,
        }
    }
}

/// What a part model depends on: the settings and the points.
struct ModelKey {
    settings: Settings,
    points: Vec<MeasurementPoint>,
}

/// The same point to the bit (a `-0.0` and a `0.0` are different points here).
fn same_point(a: &MeasurementPoint, b: &MeasurementPoint) -> bool {
    let bits = |p: &MeasurementPoint| {
        [
            p.u, p.v, p.h, p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z,
        ]
        .map(f64::to_bits)
    };
    a.id == b.id && a.curve == b.curve && a.surface == b.surface && bits(a) == bits(b)
}

fn same_points(a: &[MeasurementPoint], b: &[MeasurementPoint]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| same_point(p, q))
}

thread_local! {
    static PATHS: RefCell<Memo<Settings, PathModel>> = const { RefCell::new(Memo::new(PATH_CAPACITY)) };
    static MODELS: RefCell<Memo<ModelKey, PartModel>> = const { RefCell::new(Memo::new(MODEL_CAPACITY)) };
}

/// The path model of `part` on the chain and branch of `opts`, computed once per settings.
pub fn path_model(part: &SShape, opts: &SensitivityOptions) -> Result<Rc<PathModel>, GapError> {
    let key = Settings::of(part, opts);
    if let Some(m) = PATHS.with_borrow_mut(|c| c.find(|k| *k == key)) {
        return Ok(m);
    }
    let m = Rc::new(PathModel::new(part, opts)?);
    PATHS.with_borrow_mut(|c| c.insert(key, Rc::clone(&m)));
    Ok(m)
}

/// The part model of `points` on `opts` ([`crate::effects::builtin::part_model_on`]), computed once per
/// settings and points with `compute`.
pub fn part_model(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
    compute: impl FnOnce() -> Result<PartModel, GapError>,
) -> Result<PartModel, GapError> {
    let settings = Settings::of(part, opts);
    let hit = MODELS
        .with_borrow_mut(|c| c.find(|k| k.settings == settings && same_points(&k.points, points)));
    if let Some(m) = hit {
        return Ok((*m).clone());
    }
    let m = compute()?;
    if points.len() <= MODEL_MAX_POINTS {
        let key = ModelKey {
            settings,
            points: points.to_vec(),
        };
        MODELS.with_borrow_mut(|c| c.insert(key, Rc::new(m.clone())));
    }
    Ok(m)
}

/// Forgets every kept model of this thread (the benchmark of a first file; tests).
pub fn clear() {
    PATHS.with_borrow_mut(Memo::clear);
    clear_part_models();
}

/// Forgets the part models of this thread (and the axis values of [`crate::sensitivity::path`],
/// which belong to the points), keeps the path models (the benchmark of a further file with the
/// same settings).
pub fn clear_part_models() {
    crate::sensitivity::path::clear_kept();
    MODELS.with_borrow_mut(Memo::clear);
}

/// Number of (path, part) models kept by this thread.
pub fn len() -> (usize, usize) {
    (PATHS.with_borrow(Memo::len), MODELS.with_borrow(Memo::len))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::builtin::part_model_on;
    use crate::part::builtin_points;

    #[test]
    fn a_kept_model_is_the_model_computed_afresh() {
        // Bit-identical (`==` on every number): the whole model from the cache, and the model of
        // other points on a kept path model, against the same computed on empty caches.
        let part = SShape::iso();
        let opts = SensitivityOptions::default();
        let pts = builtin_points(&part);
        let other: Vec<MeasurementPoint> = pts[..60]
            .iter()
            .map(|p| MeasurementPoint {
                u: p.u * 0.999,
                ..*p
            })
            .collect();
        clear();
        let cold = part_model_on(&part, &pts, &opts).unwrap();
        assert_eq!(len(), (1, 1));
        let warm = part_model_on(&part, &pts, &opts).unwrap();
        assert_eq!(len(), (1, 1));
        assert_eq!(warm, cold);
        let other_on_kept_path = part_model_on(&part, &other, &opts).unwrap();
        assert_eq!(len(), (1, 2));
        clear();
        let other_cold = part_model_on(&part, &other, &opts).unwrap();
        assert_eq!(other_on_kept_path, other_cold);
        // Other settings are other models.
        let positive = opts.clone().with_branch(Branch::Positive);
        part_model_on(&part, &pts, &positive).unwrap();
        assert_eq!(len(), (2, 2));
    }
}
