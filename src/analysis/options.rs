//! The settings of an analysis ([`AnalysisOptions`]) and a deviation the process explains.

use serde::Serialize;

use crate::final_fit::correct::EffectsChoice;
use crate::identify::monte_carlo::CmmMpe;
use crate::machine::chain::PAPER000_L0;
use crate::machine::Branch;
use crate::numerics::parallel::Threads;
use crate::sensitivity::Mode;
use crate::settings::MachineChoice;

/// Settings of an analysis; `Default` is the spec's default (physical mode, signed B, paper
/// 000's machine with L0 = 499.889 mm, no tool-radius term, rows with problems reject the file).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(default)]
pub struct AnalysisOptions {
    /// The kinematic chain (default paper 000's B head / C table).
    pub machine: MachineChoice,
    /// `physical` (default) or `paper` (s-shape.md "Errors and machined defect").
    pub mode: Mode,
    /// `signed` (default) or `positive` B branch.
    pub branch: Branch,
    /// Pivot-to-tip length of the machine (mm): B axis to tip on paper 000's machine, A axis to
    /// tip (`ls + lt`) on paper 001's; not used by the tilting table of paper 002.
    pub l0: f64,
    /// Fit the tool-radius error `dR` (mm) with the location errors.
    pub tool_radius: bool,
    /// Exclude the rows the reader lists instead of rejecting the file (shown in every result).
    pub exclude_bad_rows: bool,
    /// CMM standard uncertainty of one deviation (mm, 1σ); `None` uses the residual (or
    /// `noise_mpe`).
    pub noise_sigma: Option<f64>,
    /// The CMM's maximum permissible error `MPE_E = A + L/K` µm (and its `R0`), turned into σ by
    /// [`noise_from_mpe`]; not together with `noise_sigma`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_mpe: Option<CmmMpe>,
    /// Keep the single-point outliers ([`crate::measurement::outliers`]) in the identification and the
    /// diagnosis (they are still found and named).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub keep_outliers: bool,
    /// Refine with the exact eq. 12 where the linearisation error matters (default on).
    pub refine: bool,
    /// Deviation already explained by the process (the CAM path or NC trace of issue 10, mm per
    /// matched point in file order): subtracted from the measured deviations before the
    /// identification and the gap diagnosis, so it is not blamed on the machine.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub known: Option<KnownDeviation>,
    /// Effects fitted with the location errors in the final answer: `auto` (default, what the
    /// diagnosis names), `none` (the baseline), or ids (`--effects`).
    pub effects: EffectsChoice,
    /// The feed the part was cut with (mm/min; default the finishing programme's,
    /// [`crate::settings::feed::PROGRAMME_FEED`]): a servo lag in mm of path is reported as the
    /// position loop's time constant at it.
    pub feed: f64,
    /// Threads the part model and the diagnosis may use (the same numbers on any count; the CLI
    /// gives the machine's cores, the page and `validate`'s parts one). Not a setting of the
    /// result: not written out.
    #[serde(skip)]
    pub threads: Threads,
}

/// A deviation the process explains, per matched point (mm, + = material left).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct KnownDeviation {
    /// What it is, in words (e.g. `NC trace trace.csv`), for the report.
    pub source: String,
    /// One value per matched point, in the order of the file's points.
    pub values: Vec<f64>,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        Self {
            machine: MachineChoice::Paper000,
            mode: Mode::Physical,
            branch: Branch::Signed,
            l0: PAPER000_L0,
            tool_radius: false,
            exclude_bad_rows: false,
            noise_sigma: None,
            noise_mpe: None,
            keep_outliers: false,
            refine: true,
            known: None,
            effects: EffectsChoice::Auto,
            feed: crate::settings::feed::PROGRAMME_FEED,
            threads: Threads::ONE,
        }
    }
}
