//! What one analysis reports: the serialisable [`Analysis`] and its parts.

use serde::ser::SerializeStruct;
use serde::{Serialize, Serializer};

use crate::gap::separability::Separability;
use crate::measurement::scan_lines::ScanLayout;

use crate::cmm::MatchedPart;
use crate::final_fit::correct::Correction;
use crate::gap::verdict::VerdictId;
use crate::gap::DiagnosisReport;
use crate::identify::refine::RefineReport;
use crate::identify::{Design, Identification, Observations};
use crate::machine::Unit;
use crate::measurement::outliers::{outlier_sentence, OutlierTest};
use crate::measurement::repeat::{LackOfFit, PureError};
use crate::parameter::ParamId;
use crate::part::MeasurementPoint;
use crate::settings::NoiseKind;

use super::diagnosis::Diagnosis;
use super::known::known_note;
use super::options::{AnalysisOptions, KnownDeviation};

/// The design at the measured points: one row per point, one column per parameter. Serialised
/// as `{params (names), units, columns, parameters: [{kind, name, unit}]}`.
#[derive(Debug, Clone)]
pub struct DesignColumns {
    /// The parameters (`EC0Y` … `EC0B`, then `dR` when fitted, then the effect columns), each
    /// with its kind and unit.
    pub parameters: Vec<ParamId>,
    /// `columns[k][i]`: defect at point `i` per unit of parameter `k` (mm/rad or mm/mm).
    pub columns: Vec<Vec<f64>>,
}

impl DesignColumns {
    /// The parameters' names, in column order.
    pub fn names(&self) -> Vec<String> {
        self.parameters.iter().map(ParamId::name).collect()
    }
    /// The parameters' units, in column order.
    pub fn units(&self) -> Vec<Unit> {
        self.parameters.iter().map(ParamId::unit).collect()
    }
}

impl Serialize for DesignColumns {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_struct("DesignColumns", 4)?;
        m.serialize_field("params", &self.names())?;
        m.serialize_field("units", &self.units())?;
        m.serialize_field("columns", &self.columns)?;
        m.serialize_field("parameters", &self.parameters)?;
        m.end()
    }
}

/// Everything one analysis reports.
#[derive(Debug, Clone, Serialize)]
pub struct Analysis {
    pub version: &'static str,
    pub settings: AnalysisOptions,
    /// The file as read and matched: format, points, excluded rows, warnings.
    pub file: MatchedPart,
    /// The measurement points at the matched positions (same order as `file.points`).
    pub points: Vec<MeasurementPoint>,
    /// The design of the final answer: the location errors, then the effect columns fitted
    /// with them (`<id>.<parameter>`), when any.
    pub design: DesignColumns,
    /// The final answer (what every report and export uses): the location errors fitted with
    /// what the diagnosis found ([`crate::final_fit::correct`]).
    pub identification: Identification,
    /// What the exact-model refinement of the final answer did (absent when switched off).
    pub refinement: Option<RefineReport>,
    /// The sim-to-real gap diagnosis, or why it could not be made.
    pub diagnosis: Diagnosis,
    /// How the final answer was obtained: basis, effects included, shift from the baseline.
    pub correction: Correction,
    /// The baseline identification (the location errors alone), as before the diagnosis.
    pub baseline: BaselineFit,
    /// The single-point outliers found, and whether they were left out.
    pub outliers: Outliers,
    /// The σ of the CMM noise the analysis used, and where it came from.
    pub noise: NoiseSource,
    /// Repeat measurements of the part: the pure error and the lack of fit (absent with one
    /// file).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub repeat: Option<RepeatReport>,
    /// The points read as a scan: surfaces, lines, points per line, spacing (absent for a
    /// discrete layout; [`crate::measurement::scan_lines`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scan: Option<ScanLayout>,
    /// For a scan: the pairs of candidates its layout tells apart that the 100 built-in points
    /// cannot, and the other way round ([`crate::gap::separability`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separability: Option<Separability>,
    /// Each point's position along the tool path: the tool-tip path length (mm) from the start
    /// of surface A's pass to the pose that generated the point (the `s` of the diagnosis's axis
    /// reversals; [`crate::effects::data::PointMeta::s`]), in the order of `points`. Absent when
    /// the diagnosis has no part model for the points.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_position: Option<Vec<f64>>,
}

/// What repeat measurements of the part gave ([`crate::measurement::repeat`]).
#[derive(Debug, Clone, Serialize)]
pub struct RepeatReport {
    /// σ from the differences of the measurements (pure error).
    pub pure_error: PureError,
    /// The lack-of-fit test of the baseline (the location errors alone) against it.
    pub lack_of_fit: LackOfFit,
    /// One sentence for the reports.
    pub summary: String,
}

/// The single-point outliers of an analysis ([`crate::measurement::outliers`]).
#[derive(Debug, Clone, Serialize)]
pub struct Outliers {
    /// Whether the test was made (it needs the diagnosis's part model).
    pub tested: bool,
    /// The test: `points` (`id` as in the file, `curve`, `size` in mm = the deleted residual,
    /// `statistic` = |t|), `rule`, `alpha`, `threshold`, `sigma` (mm), `sigma_source`,
    /// `structured` (points over the bound kept as structure).
    #[serde(flatten)]
    pub test: Option<OutlierTest>,
    /// `true`: the outliers were left out of the identification and the diagnosis (default);
    /// `false`: kept (`keep_outliers`).
    pub excluded: bool,
    /// The verdict of the diagnosis on every point, outliers included (when some were left
    /// out; otherwise the verdict itself).
    pub verdict_all_points: Option<VerdictId>,
    /// One sentence for the reports (empty when there is none).
    pub summary: String,
}

/// The σ of the CMM noise an analysis used.
#[derive(Debug, Clone, Serialize)]
pub struct NoiseSource {
    /// `given` (σ), `mpe` (from the CMM's MPE), `repeat` (σ of the mean of repeat
    /// measurements, from their differences) or `estimated` (from the residual).
    pub source: NoiseKind,
    /// The σ given or from the MPE (mm); `None` when estimated (the diagnosis's own estimate is
    /// `diagnosis.report.verdict.sigma`).
    pub sigma: Option<f64>,
    /// Smallest and largest per-point σ from the MPE (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mpe_range: Option<(f64, f64)>,
    /// One sentence for the reports.
    pub summary: String,
}

/// The baseline identification of an analysis: the location errors alone (`--effects none`).
#[derive(Debug, Clone, Serialize)]
pub struct BaselineFit {
    pub design: DesignColumns,
    pub identification: Identification,
    pub refinement: Option<RefineReport>,
}

/// What an analysis fitted, for further work on the same part (Monte Carlo): the design and
/// the observations of the final identification.
#[derive(Debug, Clone)]
pub struct Fitted {
    pub design: Design,
    pub observations: Observations,
}

/// The diagnosis's summary as the reports show it, composed from typed results: the gap report's
/// own ([`crate::gap::report::summary`], the verdict first), for a scan its layout and what its
/// heights tell apart ([`crate::gap::separability::sentence`]), then the single-point outliers
/// ([`outlier_sentence`], each named by its point's id in the part model, as the diagnosis saw
/// it) and, when they were left out, the verdict with every point; the known deviation
/// subtracted ([`known_note`]); the CMM noise when its σ was not given.
pub(super) fn diagnosis_summary(
    report: &DiagnosisReport,
    outliers: &Outliers,
    points: &[MeasurementPoint],
    known: Option<&KnownDeviation>,
    noise: &NoiseSource,
    feed: f64,
    (scan, separability): (Option<&ScanLayout>, Option<&Separability>),
) -> String {
    let mut s = crate::gap::report::summary(report);
    if let Some(l) = scan {
        s = format!(
            "{}\n{}\n",
            s.trim_end(),
            crate::measurement::scan_lines::sentence(l)
        );
    }
    if let Some(sep) = separability {
        s = format!(
            "{}\n{}\n",
            s.trim_end(),
            crate::gap::separability::sentence(sep)
        );
    }
    if let Some(servo) = servo_sentence(report, feed) {
        s = format!("{}\n{servo}\n", s.trim_end());
    }
    if let Some(test) = outliers.test.as_ref().filter(|t| !t.points.is_empty()) {
        let mut named = test.clone();
        for o in &mut named.points {
            o.id = points[o.index].id.to_string();
        }
        let sentence = outlier_sentence(&named, !outliers.excluded);
        s = format!("{}\nOutliers: {sentence}\n", s.trim_end());
        if let (true, Some(v)) = (outliers.excluded, outliers.verdict_all_points) {
            s += &format!("With every point, outliers included, the verdict would be `{v}`.\n");
        }
    }
    if let Some(k) = known {
        s = format!("{}\n{}", s.trim_end(), known_note(k));
    }
    if noise.source.is_derived() {
        s = format!("{}\n{}\n", s.trim_end(), noise.summary);
    }
    s
}

/// The servo effects a verdict names, in the machine owner's terms (effects.md, "Shapes are
/// families"): an axis trailing the others by `l` mm of path is a position-loop time constant
/// longer by `l/F` at the feed `F`; a common lag `L` (from `L²`) is `1/Kv = L/F` on every axis.
/// Only the mismatch of the axes moves the part to first order: all lagging alike leaves it right.
fn servo_sentence(report: &DiagnosisReport, feed: f64) -> Option<String> {
    use crate::parameter::Effect;
    use crate::settings::feed::lag_ms;
    let v = &report.verdict;
    let effects = v.finding.effects();
    let mut out = Vec::new();
    for e in effects {
        match e {
            Effect::ServoLag(axis) => {
                let est = v.parameter(e, "l")?;
                let (ms, sd) = (lag_ms(est.value, feed), lag_ms(est.std, feed));
                let (who, adjust) = if est.value >= 0.0 {
                    ("trails", "raise its Kv (or feed-forward) to match theirs")
                } else {
                    ("leads", "lower its Kv, or raise the others', to match")
                };
                out.push(format!(
                    "Servo: the {axis} axis {who} the others by {:.3} ± {:.3} mm of path: at {feed:.0} mm/min \
                     (the feed the part was cut with: --feed) its position loop's time constant (1/Kv) is {:.2} ± {:.2} ms \
                     {} theirs; {adjust}. Only the mismatch shows on the part.",
                    est.value.abs(),
                    est.std,
                    ms.abs(),
                    sd,
                    if est.value >= 0.0 { "longer than" } else { "shorter than" },
                ));
            }
            Effect::ServoCommon => {
                let est = v.parameter(e, "L2")?;
                let l = est.value.max(0.0).sqrt();
                let ms = lag_ms(l, feed);
                out.push(format!(
                    "Servo: the path is rounded by a lag all axes share, L² = {:.3} ± {:.3} mm² (L = {l:.2} mm of path): \
                     at {feed:.0} mm/min (--feed) 1/Kv ≈ {ms:.1} ms on every axis (Kv ≈ {:.0} 1/s); \
                     a higher Kv or velocity feed-forward reduces it.",
                    est.value,
                    est.std,
                    if ms > 0.0 { 1000.0 / ms } else { f64::INFINITY },
                ));
            }
            _ => {}
        }
    }
    (!out.is_empty()).then(|| out.join("\n"))
}

impl Analysis {
    /// Distance of each point from the part origin (mm): the length `L` of a CMM's MPE_E.
    pub fn lengths(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.point.norm()).collect()
    }
}
