//! The benchmark stages of issue 8, defined once so that `cargo bench --bench stages` (native)
//! and `scripts/bench-wasm.mjs` (the release wasm under Node, through the exports `benchPrepare`
//! and `benchRun` of `wasm::bench`) time the same core calls on the same inputs. Preparation
//! (building the part, the points, a CMM file's text, a design) is outside the timed call; one
//! timed call returns a number derived from the result so that nothing is optimised away.
//!
//! Stages (inputs: the ISO S-shape and its 100 built-in points):
//! `bspline_eval_1000` (1000 evaluations of `C0` of surface A with two derivatives),
//! `builtin_points`, `projection_100` (the points offset 0.01 mm along `N`, projected onto the
//! part by one `Projector`, as the reader does), `envelope_100`, `surface_max_overcut` (surface A), `inverse_kinematics_path` (the
//! flank path of both surfaces at the points), `figure19_matrix`, `read_cmm_100` and
//! `read_cmm_100000` (canonical CSV, the built-in points repeated), `identify_100` and
//! `identify_100000` (the Figure-19 design with `dR`, the rows repeated, synthetic deviations),
//! `analyse_100` (read, match, identify, refine and the full gap diagnosis of a 100-row file),
//! `diagnose_100` (the gap diagnosis alone: part model with all candidates, cross-validation).
//! Those two are the *first file*: each call prepares its settings ([`Session::new`]: the error
//! set, the path model, the built-in points' model and the location equivalents). `analyse_100_further`
//! and `diagnose_100_further` are a *further file with the same settings* (other deviations, so
//! other matched points): the stage holds one [`Session`] and forgets its point models before
//! each call. `analyse_100_again` and `diagnose_100_again` are the same points again (a
//! re-analysis after a change of σ, outliers or effects; several parts of one design): the
//! session keeps the points' model. `diagnose_scan_1000`, `_20000` and `_200000` (issue 31) are
//! `testpiece diagnose` of a scanning CMM's file (2 surfaces × 20 × 25, 40 × 250, 100 × 1000
//! points, [`SCAN_STAGES`]) as a first file: read, match, identify and diagnose;
//! `diagnose_scan_20000_backlash_c` the 20,000-point scan of a part with a C backlash of 4e-4
//! rad ([`BACKLASH_SCAN`]): a part with structure, whose diagnosis also searches pairs of effects,
//! each curve's strongest wave and the backlash's take-up.

use nalgebra::{DMatrix, Vector3};

use crate::analysis::{analyse, AnalysisOptions, Session};
use crate::cmm::write::{canonical_csv, Precision};
use crate::identify::{identify, Design, IdentifyOptions, Observations, Parameter};
use crate::machine::ErrorParam;
use crate::part::{builtin_points, MeasurementPoint, SShape, ScanLayout, Surface};
use crate::sensitivity::defect::axis_values;
use crate::sensitivity::error_set::error_set;
use crate::sensitivity::path::machine_path;
use crate::sensitivity::{sensitivity_matrix, SensitivityOptions};

/// The stage names, in table order.
pub const STAGES: [&str; 21] = [
    "bspline_eval_1000",
    "builtin_points",
    "projection_100",
    "envelope_100",
    "surface_max_overcut",
    "inverse_kinematics_path",
    "figure19_matrix",
    "read_cmm_100",
    "read_cmm_100000",
    "identify_100",
    "identify_100000",
    "analyse_100",
    "analyse_100_further",
    "analyse_100_again",
    "diagnose_100",
    "diagnose_100_further",
    "diagnose_100_again",
    "diagnose_scan_1000",
    "diagnose_scan_20000",
    "diagnose_scan_200000",
    "diagnose_scan_20000_backlash_c",
];

/// The scans of the `diagnose_scan_*` stages: points and their layout (lines a surface ×
/// points a line; the 1,000-point scan is the 20,000-point one thinned).
pub const SCAN_STAGES: [(&str, ScanLayout); 3] = [
    (
        "diagnose_scan_1000",
        ScanLayout {
            heights: 20,
            rulings: 25,
        },
    ),
    (
        "diagnose_scan_20000",
        ScanLayout {
            heights: 40,
            rulings: 250,
        },
    ),
    (
        "diagnose_scan_200000",
        ScanLayout {
            heights: 100,
            rulings: 1000,
        },
    ),
];

/// The part of `diagnose_scan_20000_backlash_c`: its layout, and the backlash of the C axis
/// (rad) added to it, as `testpiece simulate --effect backlash_c=4e-4 --scan 40x250`.
pub const BACKLASH_SCAN: (ScanLayout, f64) = (
    ScanLayout {
        heights: 40,
        rulings: 250,
    },
    4e-4,
);

/// A scanning CMM's file of `layout` (`testpiece simulate --scan HxR --errors EX0B=0.01
/// --noise 0.0015`: the exact defect of EX0B = 0.01 mm, noise σ = 1.5 µm, seed 7).
pub fn scan_text(layout: ScanLayout) -> Result<String, BenchError> {
    scan_text_with(layout, None)
}

/// [`scan_text`], with a C backlash of `backlash_c` rad added by its signature when given (as
/// `simulate --effect backlash_c=B`).
pub fn scan_text_with(layout: ScanLayout, backlash_c: Option<f64>) -> Result<String, BenchError> {
    let scan_err = |e: &dyn std::fmt::Display| BenchError::Scan(e.to_string());
    let part = SShape::iso();
    let pts = layout.scan_points(&part);
    let ex0b = crate::parameter::ParamId::parse("EX0B").map_err(|e| scan_err(&e))?;
    let opts = SensitivityOptions::default();
    let mut dev = crate::simulate::simulate_at(&part, &pts, &opts, &[(ex0b, 0.01)], 0.0015, 7)
        .map_err(|e| scan_err(&e))?;
    if let Some(b) = backlash_c {
        let prepared =
            crate::effects::prepared::Prepared::new(part, opts).map_err(|e| scan_err(&e))?;
        let q = prepared.axis_values(&pts).map_err(|e| scan_err(&e))?;
        let model = prepared.part_model(&pts, &q).map_err(|e| scan_err(&e))?;
        let effect = crate::parameter::Effect::Backlash(crate::machine::AxisName::C);
        let add = model
            .effect_deviation(&[(effect, 0, b)])
            .map_err(|e| scan_err(&e))?;
        for (d, a) in dev.iter_mut().zip(add) {
            *d += a;
        }
    }
    Ok(crate::cmm::write::scan_csv(
        pts.iter().zip(dev),
        Precision::Shortest,
        None,
    ))
}

/// A canonical CMM file of `rows` rows: the 100 built-in points repeated with unique ids and a
/// small deterministic deviation.
pub fn cmm_text(rows: usize) -> String {
    cmm_text_with(rows, 8)
}

/// [`cmm_text`] with another deviation pattern (`0.001·((i mod 17) − offset)` mm): another file
/// of the same part, whose matched points differ from the first file's in the last digits.
pub fn cmm_text_with(rows: usize, offset: usize) -> String {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let repeated: Vec<MeasurementPoint> = (0..rows)
        .map(|i| MeasurementPoint {
            id: i + 1,
            ..pts[i % pts.len()]
        })
        .collect();
    canonical_csv(
        repeated
            .iter()
            .enumerate()
            .map(|(i, p)| (p, 0.001 * ((i % 17) as f64 - offset as f64))),
        Precision::Shortest,
        None,
    )
}

/// The Figure-19 design with the tool-radius column, its rows repeated to `rows`, and
/// deviations from known errors plus a deterministic ±2 µm pattern.
pub fn identify_input(rows: usize) -> Result<(Design, Observations), BenchError> {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let opts = SensitivityOptions::default();
    let errors = error_set(&opts.chain, opts.branch)?.params();
    let m = sensitivity_matrix(
        &part,
        &pts,
        &axis_values(&part, &pts, &opts)?,
        &opts,
        &errors,
    )?;
    let tiled = DMatrix::from_fn(rows, m.values.ncols(), |i, j| m.values[(i % pts.len(), j)]);
    let params = m.errors.iter().map(Parameter::of_error).collect();
    let design = Design::try_new(params, tiled).and_then(Design::with_tool_radius)?;
    let truth: Vec<f64> = (0..design.cols())
        .map(|j| 1e-5 * (j as f64 - 3.5))
        .collect();
    let mut y = design.predict(&truth);
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.002 * (((i * 7919) % 1000) as f64 / 500.0 - 1.0);
    }
    Ok((design, Observations::plain(y)))
}

/// Prepared input of one stage.
pub enum Stage {
    Eval(SShape),
    Points(SShape),
    Project(SShape, Vec<Vector3<f64>>),
    Envelope(SShape, Vec<MeasurementPoint>),
    SurfaceMax(SShape),
    Path(SShape, Vec<MeasurementPoint>),
    Matrix(SShape, Vec<MeasurementPoint>, Vec<ErrorParam>),
    Read(String),
    Identify(Design, Observations),
    Analyse(String, Kept, Session),
    Diagnose(Vec<MeasurementPoint>, Vec<f64>, Kept, Session),
}

/// What a stage keeps of its [`Session`] between its calls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kept {
    /// Nothing: every call is a first file.
    Nothing,
    /// The prepared settings (path model, error set, …), not the model of the points: a further
    /// file.
    Paths,
    /// Everything: the same points again.
    Everything,
}

impl Kept {
    /// The session a call runs on: a new one (a first file), the stage's own without its point
    /// models (a further file; the decompositions of the final fit's structure belong to the
    /// points, like the part models), or the stage's own as it is.
    fn session(self, held: &Session) -> Result<Option<Session>, BenchError> {
        Ok(match self {
            Kept::Nothing => Some(Session::new(&AnalysisOptions::default())?),
            Kept::Paths => {
                held.forget_points();
                None
            }
            Kept::Everything => None,
        })
    }
}

/// The session of the default settings a stage holds.
fn session() -> Result<Session, BenchError> {
    Ok(Session::new(&AnalysisOptions::default())?)
}

/// The deviations of a CMM text and the points matched to them (as `analyse` finds them).
fn matched(part: &SShape, text: &str) -> Result<(Vec<MeasurementPoint>, Vec<f64>), BenchError> {
    let m = crate::cmm::read_and_match(text.as_bytes(), "bench.csv", &Default::default())?;
    Ok((
        crate::analysis::measurement_points(part, &m),
        m.deviations(),
    ))
}

/// Why a stage's input could not be built or its run failed: the stage's own error.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("unknown stage `{name}` (expected one of {STAGES:?})")]
    UnknownStage { name: String },
    #[error(transparent)]
    Geometry(#[from] crate::geometry::GeometryError),
    #[error(transparent)]
    Toolpath(#[from] crate::toolpath::ToolpathError),
    #[error(transparent)]
    Machine(#[from] crate::machine::MachineError),
    #[error(transparent)]
    Sensitivity(#[from] crate::sensitivity::SensitivityError),
    #[error(transparent)]
    Cmm(#[from] crate::cmm::CmmError),
    #[error(transparent)]
    Identify(#[from] crate::identify::IdentifyError),
    #[error(transparent)]
    Gap(#[from] crate::effects::GapError),
    #[error(transparent)]
    Analysis(#[from] crate::analysis::AnalysisError),
    /// The scan of a `diagnose_scan_*` stage could not be simulated.
    #[error("the scan could not be simulated: {0}")]
    Scan(String),
}

impl Stage {
    /// Builds the input of stage `name` (one of [`STAGES`]).
    pub fn prepare(name: &str) -> Result<Stage, BenchError> {
        let part = SShape::iso();
        let pts = builtin_points(&part);
        Ok(match name {
            "bspline_eval_1000" => Stage::Eval(part),
            "builtin_points" => Stage::Points(part),
            "projection_100" => {
                let ps = pts.iter().map(|p| p.point + p.normal * 0.01).collect();
                Stage::Project(part, ps)
            }
            "envelope_100" => Stage::Envelope(part, pts),
            "surface_max_overcut" => Stage::SurfaceMax(part),
            "inverse_kinematics_path" => Stage::Path(part, pts),
            "figure19_matrix" => {
                let o = SensitivityOptions::default();
                let errors = error_set(&o.chain, o.branch)?.params();
                Stage::Matrix(part, pts, errors)
            }
            "read_cmm_100" => Stage::Read(cmm_text(100)),
            "read_cmm_100000" => Stage::Read(cmm_text(100_000)),
            "identify_100" => {
                let (d, o) = identify_input(100)?;
                Stage::Identify(d, o)
            }
            "identify_100000" => {
                let (d, o) = identify_input(100_000)?;
                Stage::Identify(d, o)
            }
            "analyse_100" => Stage::Analyse(cmm_text(100), Kept::Nothing, session()?),
            "analyse_100_further" => Stage::Analyse(cmm_text_with(100, 5), Kept::Paths, session()?),
            "analyse_100_again" => {
                Stage::Analyse(cmm_text_with(100, 5), Kept::Everything, session()?)
            }
            "diagnose_100" => {
                let devs = crate::cmm::read_cmm(cmm_text(100).as_bytes(), "bench.csv")?
                    .points
                    .iter()
                    .map(|p| p.deviation.unwrap_or(0.0))
                    .collect();
                Stage::Diagnose(pts, devs, Kept::Nothing, session()?)
            }
            "diagnose_100_further" => {
                let (pts, devs) = matched(&part, &cmm_text_with(100, 5))?;
                Stage::Diagnose(pts, devs, Kept::Paths, session()?)
            }
            "diagnose_100_again" => {
                let (pts, devs) = matched(&part, &cmm_text_with(100, 5))?;
                Stage::Diagnose(pts, devs, Kept::Everything, session()?)
            }
            "diagnose_scan_20000_backlash_c" => {
                let (layout, b) = BACKLASH_SCAN;
                Stage::Analyse(scan_text_with(layout, Some(b))?, Kept::Nothing, session()?)
            }
            scan if scan.starts_with("diagnose_scan_") => {
                let Some((_, layout)) = SCAN_STAGES.iter().find(|(n, _)| *n == scan) else {
                    return Err(BenchError::UnknownStage {
                        name: name.to_string(),
                    });
                };
                Stage::Analyse(scan_text(*layout)?, Kept::Nothing, session()?)
            }
            _ => {
                return Err(BenchError::UnknownStage {
                    name: name.to_string(),
                })
            }
        })
    }

    /// Runs the stage once; returns a number taken from the result.
    pub fn run(&self) -> Result<f64, BenchError> {
        Ok(match self {
            Stage::Eval(part) => {
                let c = &part.curves(crate::part::Surface::A)[0];
                (0..1000).map(|i| c.derivs_at(i as f64 / 999.0).d2.x).sum()
            }
            Stage::Points(part) => builtin_points(part)[99].u,
            Stage::Project(part, ps) => {
                // As the reader does: the start rulings once per file, then each point.
                let projector = crate::part::projection::Projector::new(part);
                let mut s = 0.0;
                for p in ps {
                    s += projector.project(p)?.distance;
                }
                s
            }
            Stage::Envelope(part, pts) => {
                crate::toolpath::envelope::points_deviation(part, pts, 0.0)?.len() as f64
            }
            Stage::SurfaceMax(part) => {
                crate::toolpath::envelope::surface_max_overcut(part, Surface::A)?.max_overcut
            }
            Stage::Path(part, pts) => {
                let o = SensitivityOptions::default();
                let mut s = 0.0;
                for surf in Surface::BOTH {
                    let us: Vec<f64> = pts
                        .iter()
                        .filter(|p| p.surface == surf)
                        .map(|p| p.u)
                        .collect();
                    let path = machine_path(part, &o.chain, surf, o.branch, &us)?;
                    s += path.len() as f64;
                }
                s
            }
            Stage::Matrix(part, pts, errors) => {
                // the kernel: the points' axis values, then their Jacobians
                let o = SensitivityOptions::default();
                let q = axis_values(part, pts, &o)?;
                sensitivity_matrix(part, pts, &q, &o, errors)?.values[(0, 0)]
            }
            Stage::Read(text) => crate::cmm::read_cmm(text.as_bytes(), "bench.csv")?
                .points
                .len() as f64,
            Stage::Identify(d, o) => identify(d, o, &IdentifyOptions::default())?.rank as f64,
            Stage::Analyse(text, kept, held) => {
                let fresh = kept.session(held)?;
                let session = fresh.as_ref().unwrap_or(held);
                analyse(
                    session,
                    text.as_bytes(),
                    "bench.csv",
                    &AnalysisOptions::default(),
                )?;
                1.0
            }
            Stage::Diagnose(pts, devs, kept, held) => {
                let fresh = kept.session(held)?;
                let session = fresh.as_ref().unwrap_or(held);
                let at = session.points_model(pts);
                crate::analysis::diagnose_points(&at, devs, None)?
                    .baseline
                    .rms
            }
        })
    }
}
