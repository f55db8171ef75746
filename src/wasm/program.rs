//! The part program (issue 19, step 2) for the page: one call per "make the program" action,
//! returning what it guarantees and the two files as text.

use wasm_bindgen::prelude::*;

use crate::program::{program, Dialect, ProgramOptions};

/// The program of `options`, a [`ProgramOptions`] object (`{machine, l0, branch, tolerance
/// (mm), feed (mm/min), dialect, tcp, spindle, tool}`, any part absent: defaults). Returns `{settings, machine, header,
/// passes: [{surface, positions, singular_positions, max_interval_error, max_step,
/// max_scallop}], notes, cl, gcode, rounding_bound (mm: the read-back bound of the G-code's
/// words), z_safe (mm), dialects: [{id, name, tcp}]}`; `cl` and `gcode` are the texts of `testpiece program
/// --format cl|gcode --dialect D [--tcp]`.
#[wasm_bindgen(js_name = partProgram)]
pub fn part_program(options: JsValue) -> Result<JsValue, JsError> {
    let opts: ProgramOptions = super::settings_from_js(options, "bad program settings")?;
    let p = program(&opts).map_err(|e| JsError::new(&e.to_string()))?;
    let gcode = p.gcode();
    super::to_js(&serde_json::json!({
        "settings": p.settings,
        "machine": p.machine,
        "header": p.header(),
        "passes": p.summary(),
        "notes": p.notes,
        "cl": p.cl_apt(),
        "gcode": gcode,
        "rounding_bound": p.rounding_bound(),
        "z_safe": p.motion.z_safe,
        "dialects": Dialect::ALL.map(|d| serde_json::json!({
            "id": d, "name": d.describe(), "tcp": d.offers_tcp()
        })),
    }))
}
