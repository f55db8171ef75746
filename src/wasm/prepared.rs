//! The prepared settings the page's worker holds (issue 28 item 2): what the machine, L0, branch
//! and mode determine (the machine's location errors, the path model, the built-in points'
//! model, the location equivalents) and the point models of the last files analysed with them
//! ([`Session`]), built once and passed back on every call that needs them. The worker builds
//! another when those four settings change ([`PreparedSettings::is_for`]) and frees the old one;
//! a change of σ, outliers or effects keeps it, so a re-analysis of the same file reuses its
//! points' model.

use wasm_bindgen::prelude::*;

use crate::analysis::{AnalysisOptions, Session};

/// The prepared settings of one machine setting (JS: `new Prepared(settings)`, `settings` an
/// analysis settings object of which `machine`, `l0`, `branch` and `mode` are read).
#[wasm_bindgen(js_name = Prepared)]
pub struct PreparedSettings {
    session: Session,
}

#[wasm_bindgen(js_class = Prepared)]
impl PreparedSettings {
    /// Prepares the settings of `settings` (a bad L0 throws its message).
    #[wasm_bindgen(constructor)]
    pub fn new(settings: JsValue) -> Result<PreparedSettings, JsError> {
        let opts: AnalysisOptions = super::settings_from_js(settings, "bad analysis settings")?;
        let session = Session::new(&opts).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(PreparedSettings { session })
    }

    /// Whether these are the prepared settings of `settings` (its machine, L0, branch and mode).
    #[wasm_bindgen(js_name = isFor)]
    pub fn is_for(&self, settings: JsValue) -> Result<bool, JsError> {
        let opts: AnalysisOptions = super::settings_from_js(settings, "bad analysis settings")?;
        Ok(self.session.is_for(&opts))
    }
}

impl PreparedSettings {
    /// The session the exports analyse on.
    pub(crate) fn session(&self) -> &Session {
        &self.session
    }
}
