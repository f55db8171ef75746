//! The error budget per point, per curve and over the part (paper 000 §3-§6, the summary of its
//! conclusion: overcut 0.0387 mm, CAM 0.01 mm, NC 0.034 mm, machine, measurement).
//!
//! At every matched measurement point, with `P` the nominal foot and `N` the outward normal:
//! - `design` = deviation of the exact envelope of the ideal flank path (eq. 2-5, §3.1,
//!   [`crate::toolpath::points_deviation`]): the overcut / undercut the non-developable surface
//!   leaves even with a perfect machine;
//! - `cam` = `d_CL − design`, `d_CL` the deviation of the CAM path's discrete positions
//!   ([`super::discrete`], §4.1 Fig. 13, with its eq. 7 chord bound);
//! - `nc` = `d_NC − d_CL`, `d_NC` the same for the controller trace's positions (§5.1); 0 without
//!   a trace;
//! - `machine` = the identified location errors' defect (eq. 14, `Σ_k A_ik·x_k` over the
//!   identified parameters except `dR`): [`crate::analysis::analyse`] with the known path
//!   deviation (`d_NC`, else `d_CL`) subtracted from the measurement first
//!   ([`crate::analysis::KnownDeviation`]), so the path's share is not blamed on the machine;
//!   The identification is the final answer of the analysis: when the gap diagnosis names an
//!   effect, its columns (`<id>.<parameter>`) are fitted with the location errors and their
//!   defect is part of `machine` (backlash, scale, thermal growth, set-up, ...), except the
//!   tool's own effects (`tool_radius.*`, `tool_taper.*`), which go to `tool`;
//! - `tool` = `−dR` (§3.2, the tool-radius column −1) where `dR` is fitted (and the tool effects
//!   the diagnosis names), else 0;
//! - `residual` = `measured − (design + cam + nc + machine + tool)`: by construction the sources
//!   add up to the measured deviation point by point;
//! - `cmm` = the CMM's MPE band `±(a + L/b)` µm with `L` the point's distance from the part
//!   origin (paper 000 §6: Trimesure, `MPE_E = ±(3 + L/75)` µm), not a term of the sum.
//!
//! All in mm; + = material left, − = overcut.

use serde::{Deserialize, Serialize};

use super::discrete::PreparedPath;
use super::{BudgetError, ToolPath};
use crate::analysis::{analyse, measurement_points, AnalysisOptions, KnownDeviation, Session};
use crate::cmm::{read_and_match, MatchedPart, ReadOptions};
use crate::parameter::{Effect, ParamId};
use crate::part::{MeasurementPoint, SShape};
use crate::toolpath::{points_deviation, TOOL_RADIUS};

/// Settings of a budget (`Default`: the analysis defaults, the 10 mm tool of eq. 2, paper 000's
/// CMM `MPE_E = ±(3 + L/75)` µm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BudgetOptions {
    /// Identification settings (mode, branch, L0, `tool_radius` to fit `dR`, …); `known` is set
    /// by the budget.
    pub analysis: AnalysisOptions,
    /// Radius of the cylinder intersected at every tool position (mm; the programmed 10 mm).
    pub tool_radius: f64,
    /// Constant part of the CMM's MPE_E (µm).
    pub mpe_constant_um: f64,
    /// Length per µm of the CMM's MPE_E (mm): `MPE_E = a + L / b` µm.
    pub mpe_length_mm_per_um: f64,
}

impl Default for BudgetOptions {
    fn default() -> Self {
        Self {
            analysis: AnalysisOptions::default(),
            tool_radius: TOOL_RADIUS,
            mpe_constant_um: 3.0,
            mpe_length_mm_per_um: 75.0,
        }
    }
}

impl BudgetOptions {
    pub fn with_analysis(mut self, a: AnalysisOptions) -> Self {
        self.analysis = a;
        self
    }
    pub fn with_tool_radius(mut self, r: f64) -> Self {
        self.tool_radius = r;
        self
    }
}

/// The budget at one point (mm).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BudgetPoint {
    /// Point id as written in the CMM file.
    pub id: String,
    pub curve: String,
    pub measured: f64,
    pub design: f64,
    pub cam: f64,
    pub nc: f64,
    pub machine: f64,
    pub tool: f64,
    pub residual: f64,
    /// Half-width of the CMM's MPE band at this point.
    pub cmm: f64,
    /// Eq. 7 chord bound of the CAM path's discretisation here.
    pub cam_chord_bound: f64,
    /// Eq. 7 chord bound of the trace's discretisation here.
    pub nc_chord_bound: Option<f64>,
    /// Line of the CL file whose position cuts deepest here.
    pub cam_line: usize,
    /// Line of the trace whose position cuts deepest here.
    pub nc_line: Option<usize>,
}

/// Smallest and largest value of a source (mm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SourceRange {
    pub min: f64,
    pub max: f64,
}

impl SourceRange {
    fn of(v: impl Iterator<Item = f64>) -> Self {
        let (min, max) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        Self { min, max }
    }
}

/// Min / max of every source (the `summary` of cli.md), in budget order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sources {
    pub design: SourceRange,
    pub cam: SourceRange,
    pub nc: SourceRange,
    pub machine: SourceRange,
    pub tool: SourceRange,
    pub residual: SourceRange,
    /// `±` the largest MPE band.
    pub cmm: SourceRange,
    pub measured: SourceRange,
}

impl Sources {
    fn of(p: &[&BudgetPoint]) -> Self {
        let r = |f: fn(&BudgetPoint) -> f64| SourceRange::of(p.iter().map(|q| f(q)));
        let band = p.iter().fold(0.0f64, |m, q| m.max(q.cmm));
        Self {
            design: r(|q| q.design),
            cam: r(|q| q.cam),
            nc: r(|q| q.nc),
            machine: r(|q| q.machine),
            tool: r(|q| q.tool),
            residual: r(|q| q.residual),
            cmm: SourceRange {
                min: -band,
                max: band,
            },
            measured: r(|q| q.measured),
        }
    }
}

/// The sources over one measurement curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurveBudget {
    pub curve: String,
    pub n: usize,
    pub summary: Sources,
}

/// What was read from a tool-path file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathSummary {
    pub name: String,
    pub format: String,
    pub positions: usize,
    /// Runs of positions without a jump over 5 mm.
    pub passes: usize,
    /// Largest tip step within a pass (mm).
    pub max_step: f64,
    /// Largest eq. 7 chord bound at the points (mm).
    pub chord_bound: f64,
    /// Duration of a trace with times (s).
    pub duration: Option<f64>,
    pub cutter_diameter: Option<f64>,
    pub notes: Vec<String>,
}

/// An identified parameter as the budget used it (serialised as `{kind, name, unit, value}`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsedParameter {
    #[serde(flatten)]
    pub id: ParamId,
    pub value: f64,
}

/// The whole budget.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Budget {
    pub version: &'static str,
    pub settings: BudgetOptions,
    /// The CMM file's name.
    pub file: String,
    pub points: Vec<BudgetPoint>,
    /// Min / max per source over all points.
    pub summary: Sources,
    pub per_curve: Vec<CurveBudget>,
    pub cl: PathSummary,
    pub trace: Option<PathSummary>,
    /// The identified parameters behind `machine` and `tool`.
    pub parameters: Vec<UsedParameter>,
    /// The largest `|design + cam + nc + machine + tool + residual − measured|` (mm): rounding.
    pub sum_check: f64,
    /// The first line of the gap diagnosis made with the known deviation subtracted.
    pub verdict: Option<String>,
    pub notes: Vec<String>,
}

fn summary_of(path: &ToolPath, prepared: &PreparedPath, bounds: &[f64]) -> PathSummary {
    PathSummary {
        name: path.name.clone(),
        format: path.format.clone(),
        positions: path.len(),
        passes: prepared.passes(),
        max_step: prepared.max_step(),
        chord_bound: bounds.iter().fold(0.0, |m: f64, b| m.max(*b)),
        duration: path
            .times
            .as_ref()
            .and_then(|t| Some(t.last()? - t.first()?)),
        cutter_diameter: path.cutter_diameter,
        notes: path.notes.clone(),
    }
}

/// Deviation of a discrete path at every matched point, errors naming the file's point id.
fn deviations(
    path: &ToolPath,
    prepared: &PreparedPath,
    matched: &MatchedPart,
    points: &[MeasurementPoint],
    radius: f64,
) -> Result<Vec<super::DiscreteHit>, BudgetError> {
    points
        .iter()
        .zip(&matched.points)
        .map(|(p, m)| {
            prepared
                .deviation_at(&p.point, &p.normal, radius)
                .ok_or_else(|| BudgetError::NotReached {
                    name: path.name.clone(),
                    id: m.file.id.clone(),
                    curve: p.curve.name().to_string(),
                    x: p.point.x,
                    y: p.point.y,
                    z: p.point.z,
                    limit: super::discrete::MAX_ABSCISSA,
                })
        })
        .collect()
}

/// The error budget of a measured part (CMM file bytes) machined with the CAM path `cl` and,
/// where given, traced by the controller as `trace` (module docs), analysed on `session` (the
/// prepared settings of `opts.analysis`, [`Session::new`]).
pub fn error_budget(
    session: &Session,
    cmm: &[u8],
    cmm_name: &str,
    cl: &ToolPath,
    trace: Option<&ToolPath>,
    opts: &BudgetOptions,
) -> Result<Budget, BudgetError> {
    let r = opts.tool_radius;
    if !(r.is_finite() && r > 0.0) {
        return Err(BudgetError::BadRadius(r));
    }
    let (a_um, b_mm) = (opts.mpe_constant_um, opts.mpe_length_mm_per_um);
    if !(a_um.is_finite() && a_um >= 0.0 && b_mm.is_finite() && b_mm > 0.0) {
        return Err(BudgetError::BadMpe {
            constant_um: a_um,
            per_um_mm: b_mm,
        });
    }
    let part = SShape::iso();
    let ropts = ReadOptions::default().with_exclude_bad_rows(opts.analysis.exclude_bad_rows);
    let matched =
        read_and_match(cmm, cmm_name, &ropts).map_err(crate::analysis::AnalysisError::from)?;
    let points = measurement_points(&part, &matched);

    // design: the exact envelope of eq. 2 with the same cylinder
    let design: Vec<f64> = points_deviation(&part, &points, r - TOOL_RADIUS)?
        .iter()
        .map(|d| d.deviation)
        .collect();
    let cl_prep = PreparedPath::new(cl);
    let d_cl = deviations(cl, &cl_prep, &matched, &points, r)?;
    let nc = match trace {
        Some(t) => {
            let prep = PreparedPath::new(t);
            let d = deviations(t, &prep, &matched, &points, r)?;
            Some((t, prep, d))
        }
        None => None,
    };
    let known: Vec<f64> = match &nc {
        Some((_, _, d)) => d.iter().map(|h| h.deviation).collect(),
        None => d_cl.iter().map(|h| h.deviation).collect(),
    };
    let source = match &nc {
        Some((t, _, _)) => format!("NC trace {}", t.name),
        None => format!("CAM path {}", cl.name),
    };
    let mut aopts = opts.analysis.clone();
    aopts.known = Some(KnownDeviation {
        source: source.clone(),
        values: known,
    });
    let analysis = analyse(session, cmm, cmm_name, &aopts)?;

    // machine and tool terms from the identified parameters and the design columns
    let n = points.len();
    let (mut machine, mut tool) = (vec![0.0; n], vec![0.0; n]);
    let mut parameters = Vec::new();
    for (k, id) in analysis.design.parameters.iter().enumerate() {
        let value = analysis
            .identification
            .parameters
            .of(id)
            .map_or(0.0, |p| p.value);
        // The tool's terms: dR and the tool effects' parameters; the rest is the machine's.
        let of_the_tool = matches!(
            id,
            ParamId::ToolRadius
                | ParamId::Effect {
                    effect: Effect::ToolRadius | Effect::ToolTaper,
                    ..
                }
        );
        let target = if of_the_tool { &mut tool } else { &mut machine };
        for (i, t) in target.iter_mut().enumerate() {
            *t += analysis.design.columns[k][i] * value;
        }
        parameters.push(UsedParameter {
            id: id.clone(),
            value,
        });
    }
    let lengths = analysis.lengths();
    let mut out = Vec::with_capacity(n);
    let mut sum_check: f64 = 0.0;
    for i in 0..n {
        let measured = matched.points[i].deviation;
        let cam = d_cl[i].deviation - design[i];
        let (nc_dev, nc_bound, nc_line) = match &nc {
            Some((_, _, d)) => (
                d[i].deviation - d_cl[i].deviation,
                Some(d[i].chord_bound),
                Some(d[i].line),
            ),
            None => (0.0, None, None),
        };
        let explained = design[i] + cam + nc_dev + machine[i] + tool[i];
        let residual = measured - explained;
        let sum = design[i] + cam + nc_dev + machine[i] + tool[i] + residual;
        sum_check = sum_check.max((sum - measured).abs());
        out.push(BudgetPoint {
            id: matched.points[i].file.id.clone(),
            curve: points[i].curve.name().to_string(),
            measured,
            design: design[i],
            cam,
            nc: nc_dev,
            machine: machine[i],
            tool: tool[i],
            residual,
            cmm: (a_um + lengths[i] / b_mm) * 1e-3,
            cam_chord_bound: d_cl[i].chord_bound,
            nc_chord_bound: nc_bound,
            cam_line: d_cl[i].line,
            nc_line,
        });
    }
    let all: Vec<&BudgetPoint> = out.iter().collect();
    let summary = Sources::of(&all);
    let per_curve = crate::part::Curve::ALL
        .iter()
        .filter_map(|c| {
            let on: Vec<&BudgetPoint> = out.iter().filter(|p| p.curve == c.name()).collect();
            (!on.is_empty()).then(|| CurveBudget {
                curve: c.name().to_string(),
                n: on.len(),
                summary: Sources::of(&on),
            })
        })
        .collect();
    let cl_bounds: Vec<f64> = d_cl.iter().map(|h| h.chord_bound).collect();
    let trace_summary = nc.as_ref().map(|(t, prep, d)| {
        let b: Vec<f64> = d.iter().map(|h| h.chord_bound).collect();
        summary_of(t, prep, &b)
    });
    let mut notes = vec![format!(
        "The deviation of the {source} was subtracted from the measurement before the machine was identified."
    )];
    if let Some(r) = analysis
        .refinement
        .as_ref()
        .filter(|r| r.performed && r.success)
    {
        notes.push(format!(
            "machine term: the linearised eq. 14 at the values refined with the exact eq. 12 ({}); the linearisation error is in the residual",
            r.reason
        ));
    }
    if let Some(d) = cl.cutter_diameter.filter(|d| (d / 2.0 - r).abs() > 1e-9) {
        notes.push(format!(
            "the CL file declares CUTTER/{d} (radius {} mm) but the budget intersects a {r} mm radius",
            d / 2.0
        ));
    }
    let verdict = analysis
        .diagnosis
        .report()
        .and_then(|d| d.summary.lines().next().map(str::to_string));
    let mut settings = opts.clone();
    settings.analysis.known = None;
    Ok(Budget {
        version: crate::VERSION,
        settings,
        file: cmm_name.to_string(),
        points: out,
        summary,
        per_curve,
        cl: summary_of(cl, &cl_prep, &cl_bounds),
        trace: trace_summary,
        parameters,
        sum_check,
        verdict,
        notes,
    })
}
