//! What the page's settings offer, from the core (so that no label is copied into `www/`).

use wasm_bindgen::prelude::*;

use crate::settings::MachineChoice;

/// The machines of the "Kinematic chain" setting: `[{id, name, uses_l0}]`, `id` being the
/// value of the analysis setting `machine`.
#[wasm_bindgen]
pub fn machines() -> Result<JsValue, JsError> {
    super::to_js(&MachineChoice::ALL.map(MachineChoice::info))
}

/// The analysis settings of a settings-only call, with L0 checked.
fn settings(options: JsValue) -> Result<crate::analysis::AnalysisOptions, JsError> {
    let opts: crate::analysis::AnalysisOptions = if options.is_undefined() || options.is_null() {
        Default::default()
    } else {
        super::from_js(options).map_err(|e| JsError::new(&format!("bad analysis settings: {e}")))?
    };
    if !(opts.l0.is_finite() && opts.l0 > 0.0) {
        return Err(JsError::new(&format!(
            "L0 = {} mm is not a positive finite length",
            opts.l0
        )));
    }
    Ok(opts)
}

/// The location errors the machine of the analysis settings `options` (`{machine, l0, branch}`)
/// is identified with, derived from what the part sees ([`crate::sensitivity::error_set`]):
/// `{code, kept, rows: [{name, unit, status, rms, unabsorbed, looks_like?, reason}], points,
/// visible_fraction, conventions}` (rms in mm of deviation per 1e-4 rad or 0.01 mm).
#[wasm_bindgen(js_name = errorSet)]
pub fn error_set(options: JsValue) -> Result<JsValue, JsError> {
    let opts = settings(options)?;
    let set = crate::sensitivity::error_set::error_set(&opts.machine.chain(opts.l0), opts.branch)
        .map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&*set)
}

/// The machine's own effect catalogue for the settings `options`
/// ([`crate::effects::catalogue`]): `[{effect, status, reason}]`, `status` = `offered`,
/// `invisible` or `left_out`.
#[wasm_bindgen(js_name = machineEffects)]
pub fn machine_effects(options: JsValue) -> Result<JsValue, JsError> {
    let opts = settings(options)?;
    let effects =
        crate::effects::catalogue::machine_effects(&crate::analysis::sensitivity_options(&opts))
            .map_err(|e| JsError::new(&e.to_string()))?;
    super::to_js(&effects)
}
