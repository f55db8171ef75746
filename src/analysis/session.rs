//! What an analysis takes from the settings and from the points, built once and passed (issue 28
//! item 2): no per-thread or process-wide cache, only values the caller holds.
//!
//! - [`prepare`]: the prepared settings ([`Prepared`]: error set, path model, built-in points'
//!   model, location equivalents) of an analysis's machine, L0, branch and mode;
//! - [`PointsModel`]: one set of measured points on them: their axis values (solved once, shared
//!   by the design, the exact model and every effect family), their part model, and the final
//!   fit's decompositions for them;
//! - [`Session`]: the prepared settings with the point models of the last files analysed with
//!   them, what the CLI holds for one command and the page for one machine setting: a
//!   re-analysis of the same points (after a change of σ, outliers or effects) reuses their
//!   model.
//!
//! Every value served is the value computed for the same inputs (the computations are
//! deterministic): the results are the same, bit for bit, whatever was analysed before.

use std::cell::RefCell;
use std::sync::Arc;

use crate::effects::builtin::PartModel;
use crate::effects::prepared::Prepared;
use crate::effects::GapError;
use crate::final_fit::structure::Decompositions;
use crate::machine::AxisValues;
use crate::measurement::scan_lines::{read_scan, ScanReading};
use crate::numerics::memo::Memo;
use crate::numerics::parallel::{join, Threads};
use crate::part::{MeasurementPoint, SShape};
use crate::sensitivity::SensitivityError;

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::points::sensitivity_options;

/// Point models a [`Session`] keeps (each `points × ~40` numbers: 30 kB for 100 points).
pub const KEPT_POINT_SETS: usize = 4;
/// Point sets of more points are not kept (a dense scan's model, ~10 MB for 20,000 points,
/// would stay in memory beside its copy in use).
pub const KEPT_MAX_POINTS: usize = 2000;

/// The prepared settings of `opts` (its machine with its L0, branch and mode) on the ISO part.
/// A non-positive or non-finite L0 is [`AnalysisError::BadL0`].
pub fn prepare(opts: &AnalysisOptions) -> Result<Prepared, AnalysisError> {
    if !(opts.l0.is_finite() && opts.l0 > 0.0) {
        return Err(AnalysisError::BadL0(opts.l0));
    }
    Prepared::on(SShape::iso(), sensitivity_options(opts), opts.threads).map_err(|e| match e {
        GapError::Sensitivity(s) => AnalysisError::Sensitivity(s),
        other => AnalysisError::Correction(other),
    })
}

/// The prepared settings must be those of the analysis's options.
pub(super) fn check_prepared(
    prepared: &Prepared,
    opts: &AnalysisOptions,
) -> Result<(), AnalysisError> {
    let wanted = sensitivity_options(opts);
    if prepared.options() == &wanted {
        return Ok(());
    }
    let describe = |o: &crate::sensitivity::SensitivityOptions| {
        let t = o.chain.tool_offset();
        format!(
            "chain {} with the tool offset ({}, {}, {}) mm, {} mode, {:?} B branch",
            o.chain.code(),
            t.x,
            t.y,
            t.z,
            o.mode.name(),
            o.branch
        )
    };
    Err(AnalysisError::OtherSettings {
        prepared: describe(prepared.options()),
        asked: describe(&wanted),
    })
}

/// One set of measured points on the prepared settings (module docs): what the analysis of any
/// deviations at them needs from the points alone.
#[derive(Debug)]
pub struct PointsModel {
    points: Vec<MeasurementPoint>,
    /// The points' axis values (or why they could not be solved: reported by the design).
    axis_values: Result<Vec<AxisValues>, SensitivityError>,
    /// The part model of the diagnosis (or why there is none: the diagnosis is then not made).
    part_model: Result<PartModel, GapError>,
    /// The points read as a scan, when they are one ([`read_scan`]).
    scan: Option<ScanReading>,
    decompositions: Decompositions,
    /// The threads its computations run on (the part model's, the exact model's Jacobian).
    threads: Threads,
}

impl PointsModel {
    /// Solves the points' axis values and builds their part model on `prepared`; the points of
    /// a scan are grouped by their scan lines ([`read_scan`]), the others by the nearer
    /// measurement curve.
    pub fn new(prepared: &Prepared, points: &[MeasurementPoint]) -> Self {
        Self::on(prepared, points, Threads::ONE)
    }

    /// [`PointsModel::new`] with the part model computed on `threads` threads: the same numbers.
    pub fn on(prepared: &Prepared, points: &[MeasurementPoint], threads: Threads) -> Self {
        let axis_values = prepared.axis_values_on(points, threads);
        // the scan's lines read beside the part model (on another thread when there is one:
        // ~30 ms of one thread at 200,000 points, issue 31)
        let (part_model, scan) = join(
            threads,
            || match &axis_values {
                Ok(q) => prepared.part_model_on(points, q, threads),
                Err(e) => Err(e.clone().into()),
            },
            || read_scan(points),
        );
        let part_model = part_model.map(|mut m| {
            if let Some(s) = &scan {
                // (the model's points are its own here: not yet shared)
                for (p, l) in Arc::make_mut(&mut m.points).iter_mut().zip(&s.labels) {
                    p.curve.clone_from(l);
                }
            }
            m
        });
        Self {
            points: points.to_vec(),
            axis_values,
            part_model,
            scan,
            decompositions: Decompositions::default(),
            threads,
        }
    }

    /// The points' group labels: their scan lines for a scan, else their measurement curves.
    pub fn labels(&self) -> Vec<String> {
        match &self.scan {
            Some(s) => s.labels.clone(),
            None => self
                .points
                .iter()
                .map(|p| p.curve.name().to_string())
                .collect(),
        }
    }

    /// The points read as a scan, when they are one.
    pub fn scan(&self) -> Option<&ScanReading> {
        self.scan.as_ref()
    }

    /// The measured points.
    pub fn points(&self) -> &[MeasurementPoint] {
        &self.points
    }

    /// Their axis values on the prepared chain and branch.
    pub fn axis_values(&self) -> Result<&[AxisValues], SensitivityError> {
        self.axis_values.as_deref().map_err(Clone::clone)
    }

    /// Their part model ([`Prepared::part_model`]).
    pub fn part_model(&self) -> Result<&PartModel, GapError> {
        self.part_model.as_ref().map_err(Clone::clone)
    }

    /// The threads its computations run on.
    pub fn threads(&self) -> Threads {
        self.threads
    }

    /// The final fit's decompositions kept for these points.
    pub fn decompositions(&self) -> &Decompositions {
        &self.decompositions
    }
}

/// The same points to the bit (a `-0.0` and a `0.0` are different points here).
fn same_points(a: &[MeasurementPoint], b: &[MeasurementPoint]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| same_point(p, q))
}

fn same_point(a: &MeasurementPoint, b: &MeasurementPoint) -> bool {
    let bits = |p: &MeasurementPoint| {
        [
            p.u, p.v, p.h, p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z,
        ]
        .map(f64::to_bits)
    };
    a.id == b.id && a.curve == b.curve && a.surface == b.surface && bits(a) == bits(b)
}

/// The prepared settings of one machine setting and the point models of the last files analysed
/// with them ([`KEPT_POINT_SETS`], most recent first): held by the CLI for one command and by the
/// page until the machine, L0, branch or mode change.
pub struct Session {
    prepared: Prepared,
    kept: RefCell<Memo<Vec<MeasurementPoint>, PointsModel>>,
    /// The threads a points' model is built on ([`AnalysisOptions::threads`]).
    threads: Threads,
}

impl Session {
    /// The session of the settings of `opts` ([`prepare`]).
    pub fn new(opts: &AnalysisOptions) -> Result<Self, AnalysisError> {
        Ok(Self {
            threads: opts.threads,
            ..Self::of(prepare(opts)?)
        })
    }

    /// A session on settings already prepared.
    pub fn of(prepared: Prepared) -> Self {
        Self {
            prepared,
            kept: RefCell::new(Memo::new(KEPT_POINT_SETS)),
            threads: Threads::ONE,
        }
    }

    /// The prepared settings.
    pub fn prepared(&self) -> &Prepared {
        &self.prepared
    }

    /// Whether the session's settings are those of `opts` (machine, L0, branch, mode): when not,
    /// the caller prepares another.
    pub fn is_for(&self, opts: &AnalysisOptions) -> bool {
        check_prepared(&self.prepared, opts).is_ok()
    }

    /// The model of `points`: kept from an earlier analysis at the same points, or built (and
    /// kept when it has at most [`KEPT_MAX_POINTS`] points).
    pub fn points_model(&self, points: &[MeasurementPoint]) -> Arc<PointsModel> {
        let mut kept = self.kept.borrow_mut();
        if let Some(m) = kept.find(|k| same_points(k, points)) {
            return m;
        }
        let m = Arc::new(PointsModel::on(&self.prepared, points, self.threads));
        if points.len() <= KEPT_MAX_POINTS {
            kept.insert(points.to_vec(), Arc::clone(&m));
        }
        m
    }

    /// Forgets the kept point models (the benchmark of a further file with the same settings).
    pub fn forget_points(&self) {
        self.kept.borrow_mut().clear();
    }
}
