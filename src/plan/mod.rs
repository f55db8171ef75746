//! The measurement plan (issue 19, step 1): before a part is machined, where to probe it and
//! what the identification and the gap diagnosis will then be able to tell.
//!
//! Pipeline position: part geometry → **plan** → (machining, CMM) → identify → gap. A plan is
//! - the points ([`layout`]): `n` per curve at equal arc length, ids, curve, position, outward
//!   normal (mm);
//! - the predicted std of every location error and the groups the part cannot separate
//!   ([`predict`]: the identification itself on the plan's design with an a priori σ, so the
//!   figures equal those of `identify --sigma σ --effects none` on a part measured there);
//! - the detection limit of every effect of `shared/spec/effects.md` ([`detection`]: the size
//!   whose unabsorbed part reaches the `2.5 σ` rule);
//! - the CMM program ([`dmis`], ISO 22093: probe, datum alignment on the fixture
//!   ([`fixture`]), clearance moves from the replay of the probe path ([`probe_path`]), output
//!   of the measured points; read back by [`dmis_read`]) and the nominal table
//!   ([`nominal_csv`]).
//!
//! σ is the CMM's standard uncertainty of one deviation: given (mm), or from its MPE
//! `A + L/K` µm by the analysis's own rule ([`crate::settings::cmm_noise::noise_from_mpe`]: the median over
//! the plan's points of `max(MPE_E(L)/√3, R0/1.693)`), by default the CMM of paper 000 §6
//! (`3 + L/75` µm, `R0` = 3 µm). Units: mm and rad.

pub mod detection;
pub mod dmis;
pub mod dmis_read;
mod error;
pub mod fixture;
pub mod layout;
pub mod predict;
pub mod probe_path;
pub mod stylus;

use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, Serializer};

pub use detection::{detection_limits, DetectionLimit, DetectionLimits, ParameterLimit};
pub use dmis::{write_dmis, DmisProgram};
pub use dmis_read::{dmis_statements, read_dmis_points, DmisPoint};
pub use error::PlanError;
pub use layout::{plan_points, split_total, MAX_PER_CURVE};
pub use predict::{predicted_identification, PredictedParameter, Prediction};

use crate::analysis::AnalysisOptions;
use crate::effects::prepared::Prepared;
use crate::gap::DiagnoseOptions;
use crate::identify::monte_carlo::CmmMpe;
use crate::identify::Group;
use crate::machine::chain::PAPER000_L0;
use crate::machine::Branch;
use crate::part::MeasurementPoint;
use crate::sensitivity::Mode;
use crate::settings::MachineChoice;
use crate::settings::{CmmNoise, NoiseKind};

/// Settings of a plan; `Default`: 25 points per curve, the CMM of paper 000 (MPE `3 + L/75` µm,
/// `R0` 3 µm), paper 000's machine with L0 = 499.889 mm, `physical` mode, signed B, no `dR`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PlanOptions {
    /// Points on each curve `A_Z11, A_Z25, B_Z11, B_Z25` (each 1..=1000).
    pub per_curve: [usize; 4],
    /// CMM σ of one deviation (mm); `None`: from `mpe`.
    pub sigma: Option<f64>,
    /// CMM MPE (used when `sigma` is `None`; absent: paper 000's CMM).
    pub mpe: Option<CmmMpe>,
    pub machine: MachineChoice,
    pub mode: Mode,
    pub branch: Branch,
    /// Pivot-to-tip length (mm).
    pub l0: f64,
    /// Include the tool-radius term `dR` (mm) in the predicted identification.
    pub tool_radius: bool,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            per_curve: [25; 4],
            sigma: None,
            mpe: None,
            machine: MachineChoice::Paper000,
            mode: Mode::Physical,
            branch: Branch::Signed,
            l0: PAPER000_L0,
            tool_radius: false,
        }
    }
}

impl PlanOptions {
    /// The prepared settings of the plan's machine, L0, branch and mode (for [`plan`]; a
    /// non-positive or non-finite L0 is [`PlanError::BadL0`]).
    pub fn prepare(&self) -> Result<Prepared, PlanError> {
        if !(self.l0.is_finite() && self.l0 > 0.0) {
            return Err(PlanError::BadL0(self.l0));
        }
        crate::analysis::prepare(&self.analysis(0.0)).map_err(PlanError::Design)
    }

    /// The analysis settings an identification of the planned part uses (σ given).
    pub fn analysis(&self, sigma: f64) -> AnalysisOptions {
        AnalysisOptions {
            machine: self.machine,
            mode: self.mode,
            branch: self.branch,
            l0: self.l0,
            tool_radius: self.tool_radius,
            noise_sigma: Some(sigma),
            effects: crate::final_fit::correct::EffectsChoice::None,
            ..AnalysisOptions::default()
        }
    }
}

/// The σ a plan uses and where it comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanNoise {
    /// `given` or `mpe`.
    pub source: NoiseKind,
    /// σ of one deviation (mm).
    pub sigma: f64,
    /// The MPE it came from (source `mpe`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mpe: Option<CmmMpe>,
    pub summary: String,
}

/// A measurement plan (`testpiece plan --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    pub version: &'static str,
    pub settings: PlanOptions,
    pub noise: PlanNoise,
    /// The points to measure (`id, curve, surface, u, v, x, y, z, nx, ny, nz, h`).
    pub points: Vec<MeasurementPoint>,
    /// `{NAME: {std, status, unit}}`, predicted, in design order.
    pub parameters: PredictedMap,
    /// The groups the part cannot separate (and the weak ones), as `identify` reports them.
    pub groups: Vec<Group>,
    /// Numerical rank and condition number of the unit-scaled design.
    pub rank: usize,
    pub condition: f64,
    /// `{effect id: {parameter: smallest visible size}}` (the parameter's unit; null: never).
    pub detection_limits: DetectionLimits,
    /// The same with units, absorbed fractions and plain names, for reports.
    pub detection_detail: Vec<DetectionLimit>,
    /// `k` of the `k σ` rule (2.5).
    pub detect_factor: f64,
    pub notes: Vec<String>,
}

/// Predicted parameters in design order, serialised as `{name: {std, status, unit}}`.
#[derive(Debug, Clone, PartialEq)]
pub struct PredictedMap(pub Vec<(String, PredictedParameter)>);

impl Serialize for PredictedMap {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (n, p) in &self.0 {
            m.serialize_entry(n, p)?;
        }
        m.end()
    }
}

impl PredictedMap {
    /// The prediction of a parameter by name.
    pub fn get(&self, name: &str) -> Option<&PredictedParameter> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, p)| p)
    }
}

/// The σ of `opts` at `points` (checked).
pub fn plan_noise(opts: &PlanOptions, points: &[MeasurementPoint]) -> Result<PlanNoise, PlanError> {
    // No figure given: the plan assumes paper 000's CMM.
    let paper000 = CmmMpe::paper000();
    let mpe = opts
        .mpe
        .as_ref()
        .or(opts.sigma.is_none().then_some(&paper000));
    let lengths: Vec<f64> = points.iter().map(|p| p.point.norm()).collect();
    let noise = CmmNoise::try_new(opts.sigma, mpe)?.resolve(&lengths);
    let sigma = noise.sigma.unwrap_or_default();
    let summary = match noise.mpe {
        Some(r) => format!(
            "CMM σ = {:.2} µm from MPE_E = {} + L/{} µm (R0 = {} µm): \
             max(MPE_E(L)/√3, R0/1.693) = {:.2}..{:.2} µm over the points, median used.",
            sigma * 1e3,
            r.mpe.a_um,
            r.mpe.k_mm,
            r.mpe.r0_um,
            r.lo * 1e3,
            r.hi * 1e3
        ),
        None => format!("CMM σ = {:.2} µm, as given.", sigma * 1e3),
    };
    Ok(PlanNoise {
        source: noise.kind,
        sigma,
        mpe: noise.mpe.map(|r| r.mpe),
        summary,
    })
}

/// The measurement plan of `opts` on its prepared settings ([`PlanOptions::prepare`]).
pub fn plan(prepared: &Prepared, opts: &PlanOptions) -> Result<Plan, PlanError> {
    if !(opts.l0.is_finite() && opts.l0 > 0.0) {
        return Err(PlanError::BadL0(opts.l0));
    }
    let points = plan_points(prepared.part(), opts.per_curve)?;
    let noise = plan_noise(opts, &points)?;
    let q = prepared
        .axis_values(&points)
        .map_err(|e| PlanError::Design(e.into()))?;
    let analysis = opts.analysis(noise.sigma);
    let id = predicted_identification(prepared, &points, &q, &analysis, noise.sigma)?;
    let pred = Prediction::of(&id);
    let mut notes = vec![format!(
        "Predicted with σ = {:.3} µm for `testpiece identify FILE --sigma {} --effects none` on a \
         part measured at these {} points (the same design: {} mode, {} B branch).",
        noise.sigma * 1e3,
        noise.sigma,
        points.len(),
        match opts.mode {
            Mode::Physical => "physical",
            Mode::Paper => "paper",
        },
        match opts.branch {
            Branch::Signed => "signed",
            Branch::Positive => "positive",
        }
    )];
    // The machine's own candidates (Effect::on_chain), as the analysis diagnoses them.
    let model = prepared
        .part_model(&points, &q)
        .map_err(PlanError::Effects)?;
    let k = DiagnoseOptions::default().detect_factor;
    let limits = detection_limits(&model, noise.sigma, k);
    notes.push(format!(
        "Detection limit: the size of each effect whose part the location errors cannot absorb \
         has an RMS of {k} σ = {:.2} µm over the points (effects.md decision rule); null: the \
         location errors absorb it entirely on this plan.",
        k * noise.sigma * 1e3
    ));
    Ok(Plan {
        version: crate::VERSION,
        settings: opts.clone(),
        noise,
        parameters: PredictedMap(pred.names.into_iter().zip(pred.parameters).collect()),
        groups: pred.groups,
        rank: pred.rank,
        condition: pred.condition,
        detection_detail: limits.0.clone(),
        detection_limits: limits,
        detect_factor: k,
        points,
        notes,
    })
}

impl Plan {
    /// The DMIS program of the plan ([`write_dmis`]), its probe path replayed against the part
    /// on its plate; its header names the software version, the points per curve, the σ and
    /// the machine.
    pub fn dmis(&self) -> Result<DmisProgram, PlanError> {
        let header = format!(
            "testpiece {} measurement plan: {} points ({} per curve A_Z11, A_Z25, B_Z11, B_Z25)\n{}\nmachine: {}",
            self.version,
            self.points.len(),
            self.settings.per_curve.map(|n| n.to_string()).join(", "),
            self.noise.summary,
            self.settings.machine.describe()
        );
        write_dmis(
            &self.points,
            &header,
            &probe_path::Obstacles::s_shape_on_plate(),
        )
    }
}

/// The nominal table for a CMM: `id,curve,x,y,z,nx,ny,nz` (mm, outward unit normal), the
/// columns of `shared/spec/cmm-csv.md` without a deviation.
pub fn nominal_csv(points: &[MeasurementPoint]) -> String {
    let mut s = String::from("id,curve,x,y,z,nx,ny,nz\n");
    for p in points {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            p.id, p.curve, p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z
        ));
    }
    s
}
