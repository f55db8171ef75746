//! The measurement plan (issue 19, step 1) for the page: one call per change of the plan's
//! settings, returning the figures and the two CMM programs as text (downloads need no second
//! call).

use wasm_bindgen::prelude::*;

use super::prepared::PreparedSettings;
use crate::plan::{nominal_csv, plan, PlanOptions};

/// The plan of `options` on `prepared` (the settings of its machine, L0, branch and mode, held
/// by the worker), `options` a [`PlanOptions`] object (`{per_curve: [n, n, n, n], sigma (mm) |
/// mpe: {a_um, k_mm, r0_um}, machine, mode, branch, l0, tool_radius}`, any part absent:
/// defaults). Returns `{plan, dmis, dmis_replay, csv}`: the [`crate::plan::Plan`] (JSON of
/// `testpiece plan --json`), the DMIS program, the replay of its probe path
/// ([`crate::plan::probe_path::ProbeReplay`]) and the nominal table of `testpiece plan --dmis /
/// --csv`.
#[wasm_bindgen(js_name = measurementPlan)]
pub fn measurement_plan(prepared: &PreparedSettings, options: JsValue) -> Result<JsValue, JsError> {
    let opts: PlanOptions = super::settings_from_js(options, "bad plan settings")?;
    let p = plan(prepared.session().prepared(), &opts).map_err(|e| JsError::new(&e.to_string()))?;
    let dmis = p.dmis().map_err(|e| JsError::new(&e.to_string()))?;
    let csv = nominal_csv(&p.points);
    super::to_js(&serde_json::json!({
        "plan": p,
        "dmis": dmis.text,
        "dmis_replay": dmis.replay,
        "csv": csv
    }))
}
