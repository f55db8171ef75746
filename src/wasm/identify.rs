//! wasm exports of the `identify` stage.

use wasm_bindgen::prelude::*;

use crate::identify::{self, Design, IdentifyOptions, Observations};

/// Guards of the array arguments: at least one point, one deviation per point, weights empty or
/// one per point (the core checks the values: finite, weights >= 0).
fn check_rows(n: usize, deviation: &[f64], weights: &[f64]) -> Result<(), JsError> {
    if n == 0 {
        return Err(JsError::new("the design has no points (n = 0)"));
    }
    if deviation.len() != n {
        return Err(JsError::new(&format!(
            "{} deviations for {n} points",
            deviation.len()
        )));
    }
    if !weights.is_empty() && weights.len() != n {
        return Err(JsError::new(&format!(
            "{} weights for {n} points (give none or one per point)",
            weights.len()
        )));
    }
    Ok(())
}

/// The compensation table of an identification as CSV text (`name,iso_230_1,value,unit,std,status`).
///
/// - `design`: the n x p design matrix, **column-major** (`design[j*n + i]` = point i, column j),
///   in mm per unit of each parameter (mm/rad for angles, mm/mm for lengths);
/// - `n`: number of points (rows);
/// - `names`: the p column names (`EC0Y`, ..., `EX0B`: units follow the ISO names, rad for
///   `E[ABC]..`, mm otherwise);
/// - `deviation`: n measured deviations (mm, + = material left);
/// - `weights`: n relative weights (1/σ²; 0 excludes a point), or an empty array for all 1;
/// - `tool_radius`: adds the tool-radius column `dR` (-1 at every point).
#[wasm_bindgen(js_name = compensationCsv)]
pub fn compensation_csv(
    design: &[f64],
    n: usize,
    names: Vec<String>,
    deviation: &[f64],
    weights: &[f64],
    tool_radius: bool,
) -> Result<String, JsError> {
    check_rows(n, deviation, weights)?;
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut d = Design::from_column_major(&name_refs, n, design)
        .map_err(|e| JsError::new(&e.to_string()))?;
    if tool_radius {
        d = d
            .with_tool_radius()
            .map_err(|e| JsError::new(&e.to_string()))?;
    }
    let mut obs = Observations::plain(deviation.to_vec());
    if !weights.is_empty() {
        obs = obs.with_weights(weights.to_vec());
    }
    let id = identify::identify(&d, &obs, &IdentifyOptions::default())
        .map_err(|e| JsError::new(&e.to_string()))?;
    Ok(identify::export::compensation_csv(&id, "none"))
}
