//! The page's main call: one measured part through the whole pipeline, with everything the
//! page shows of it in one answer (the analysis, the verdict line, the machine's location errors
//! and effect catalogue).

use serde::Serialize;
use wasm_bindgen::prelude::*;

use super::columns::{packed, packed_numbers};
use super::prepared::PreparedSettings;
use crate::analysis::{
    analyse_parts_with, Analysis, AnalysisError, AnalysisOptions, Diagnosis, Progress,
};
use crate::effects::catalogue::{machine_effects, EffectStatus};
use crate::effects::prepared::Prepared;
use crate::sensitivity::error_set::ErrorSet;

/// The machine's location errors ([`crate::sensitivity::error_set`]) with its own effect
/// catalogue ([`crate::effects::catalogue`]): what the identification and the diagnosis of
/// the analysis could use.
#[derive(Serialize)]
struct MachineSet<'a> {
    #[serde(flatten)]
    set: &'a ErrorSet,
    effects: Vec<EffectStatus>,
}

/// An [`Analysis`] as the page receives it: its fields, plus
/// - `verdict_line`: the diagnosis's verdict in one line ([`crate::gap::report::verdict_line`]),
///   or why there is none;
/// - `error_set`: `{code, kept, rows: [{name, unit, status, rms, unabsorbed, looks_like?,
///   reason}], points, visible_fraction, conventions, effects: [{effect, status, reason}]}`
///   for the machine of the settings (rms in mm of deviation per 1e-4 rad or 0.01 mm).
#[derive(Serialize)]
struct PageAnalysis<'a> {
    #[serde(flatten)]
    analysis: &'a Analysis,
    verdict_line: String,
    error_set: MachineSet<'a>,
}

/// A step from the page's object to one of its per-point arrays: a key or an index.
enum Step {
    Key(&'static str),
    Index(usize),
}

impl Step {
    fn js(&self) -> JsValue {
        match self {
            Step::Key(k) => JsValue::from_str(k),
            Step::Index(i) => JsValue::from(*i as u32),
        }
    }
}

/// The per-point arrays of `a` (www/columns.js `PER_POINT`) as packed columns
/// ([`super::columns`]), each with where it goes; each one written is left empty in `a`, so
/// that the JSON of the rest holds `[]` in its place (an array refused, `NotColumns`, stays
/// whole in the JSON: the worker packs it).
fn take_columns(a: &mut Analysis) -> Vec<(Vec<Step>, JsValue)> {
    use Step::{Index, Key};
    let mut out = Vec::new();
    fn table<T: Serialize>(
        list: &mut Vec<T>,
        path: Vec<Step>,
        out: &mut Vec<(Vec<Step>, JsValue)>,
    ) {
        if let Ok(col) = packed(list) {
            *list = Vec::new();
            out.push((path, col));
        }
    }
    fn numbers(list: &mut Vec<f64>, path: Vec<Step>, out: &mut Vec<(Vec<Step>, JsValue)>) {
        if !list.is_empty() {
            out.push((path, packed_numbers(list)));
            *list = Vec::new();
        }
    }
    fn ids(list: &mut Vec<u32>, path: Vec<Step>, out: &mut Vec<(Vec<Step>, JsValue)>) {
        if !list.is_empty() {
            let v: Vec<f64> = list.iter().map(|&i| f64::from(i)).collect();
            out.push((path, packed_numbers(&v)));
            *list = Vec::new();
        }
    }
    table(&mut a.points, vec![Key("points")], &mut out);
    table(
        &mut a.file.points,
        vec![Key("file"), Key("points")],
        &mut out,
    );
    table(
        &mut a.identification.points,
        vec![Key("identification"), Key("points")],
        &mut out,
    );
    table(
        &mut a.baseline.identification.points,
        vec![Key("baseline"), Key("identification"), Key("points")],
        &mut out,
    );
    if let Some(p) = &mut a.path_position {
        numbers(p, vec![Key("path_position")], &mut out);
    }
    for (k, c) in a.design.columns.iter_mut().enumerate() {
        numbers(c, vec![Key("design"), Key("columns"), Index(k)], &mut out);
    }
    for (k, c) in a.baseline.design.columns.iter_mut().enumerate() {
        let path = vec![Key("baseline"), Key("design"), Key("columns"), Index(k)];
        numbers(c, path, &mut out);
    }
    if let Diagnosis::Made { report, .. } = &mut a.diagnosis {
        for (k, e) in report.where_.iter_mut().enumerate() {
            let path = vec![
                Key("diagnosis"),
                Key("report"),
                Key("where"),
                Index(k),
                Key("ids"),
            ];
            ids(&mut e.ids, path, &mut out);
        }
        for (k, e) in report.structure.entries.iter_mut().enumerate() {
            let path = vec![
                Key("diagnosis"),
                Key("report"),
                Key("structure"),
                Key("entries"),
                Index(k),
                Key("ids"),
            ];
            ids(&mut e.ids, path, &mut out);
        }
    }
    out
}

/// Puts `value` at `path` under `root` (a path [`take_columns`] gave: it exists in the JSON).
fn place(root: &JsValue, path: &[Step], value: &JsValue) -> Result<(), JsError> {
    let missing = || {
        JsError::new(
            "could not convert the result for the page: a per-point array's place is missing",
        )
    };
    let (last, steps) = path.split_last().ok_or_else(missing)?;
    let mut holder = root.clone();
    for step in steps {
        holder = js_sys::Reflect::get(&holder, &step.js()).map_err(|_| missing())?;
    }
    js_sys::Reflect::set(&holder, &last.js(), value).map_err(|_| missing())?;
    Ok(())
}

/// `a` as the page receives it: the JSON of [`PageAnalysis`] with its per-point arrays as
/// packed columns ([`take_columns`]).
fn page_analysis(mut a: Analysis, prepared: &Prepared) -> Result<JsValue, JsError> {
    let set = prepared.error_set();
    let effects = machine_effects(prepared);
    let verdict_line = match &a.diagnosis {
        Diagnosis::Made { report, .. } => crate::gap::report::verdict_line(&report.verdict),
        Diagnosis::NotMade { reason } => format!("Verdict: not available ({reason})"),
    };
    let columns = take_columns(&mut a);
    let page = super::to_js(&PageAnalysis {
        analysis: &a,
        verdict_line,
        error_set: MachineSet { set, effects },
    })?;
    for (path, col) in &columns {
        place(&page, path, col)?;
    }
    Ok(page)
}

/// A failed analysis as a JS `Error` whose message is the core's; when the file was refused
/// for bad rows that the setting `exclude_bad_rows` would leave out, the error also carries
/// `bad_rows` (their number), so that the page can offer to exclude them.
fn analysis_error(e: AnalysisError) -> JsValue {
    let error = js_sys::Error::new(&e.to_string());
    if let AnalysisError::File(f) = &e {
        let rows = f.row_problems().len();
        if rows > 0 {
            // Setting a property on a fresh Error cannot fail.
            let _ = js_sys::Reflect::set(
                &error,
                &JsValue::from_str("bad_rows"),
                &JsValue::from(rows as u32),
            );
        }
    }
    error.into()
}

/// A progress sink calling the page's `progress` function (when given) with each stage as a
/// plain object `{stage, step, steps, fraction, text}` ([`Progress`]); a failing call is ignored
/// (the progress line is not the result).
fn sink_of(progress: Option<js_sys::Function>) -> impl FnMut(Progress) {
    move |p: Progress| {
        if let (Some(f), Ok(v)) = (&progress, super::to_js(&p)) {
            let _ = f.call1(&JsValue::NULL, &v);
        }
    }
}

/// Reads, matches and identifies one CMM file on `prepared` (the settings of `options`, held by
/// the worker: [`super::prepared`]). `options` is `{machine, mode, branch, l0,
/// tool_radius, exclude_bad_rows, noise_sigma, noise_mpe: {a_um, k_mm, r0_um}, keep_outliers,
/// effects}` (any may be absent: defaults of `AnalysisOptions`; `noise_sigma` and `noise_mpe`
/// not both). Returns the [`Analysis`] as a plain object with `verdict_line` and `error_set`
/// (see `PageAnalysis`); a bad file throws the reader's message (line, column, text found,
/// what was expected) and, for rejected rows, `bad_rows`. `progress` (optional): a function
/// called with each stage of the analysis as it begins ([`sink_of`]).
#[wasm_bindgen]
pub fn analyse(
    prepared: &PreparedSettings,
    bytes: &[u8],
    name: &str,
    options: JsValue,
    progress: Option<js_sys::Function>,
) -> Result<JsValue, JsValue> {
    let opts: AnalysisOptions = super::settings_from_js(options, "bad analysis settings")?;
    let session = prepared.session();
    let (a, _) = analyse_parts_with(session, &[(bytes, name)], &opts, &mut sink_of(progress))
        .map_err(analysis_error)?;
    Ok(page_analysis(a, session.prepared())?)
}

/// Repeat measurements of one part on `prepared` (as for `analyse`): `files` = `[{name, bytes:
/// Uint8Array}]`, the first file then
/// its repeats (the same point ids measured again, at least 2 files); `options` as for
/// `analyse`, without `noise_sigma` or `noise_mpe` (σ comes from the repeats). Returns what
/// `analyse` returns for their mean, with `repeat` = {pure_error {sigma, dof, sigma_mean,
/// largest}, lack_of_fit {f, dof_fit, dof_pure, p_value}, summary}; `progress` as for `analyse`.
#[wasm_bindgen(js_name = analyseRepeats)]
pub fn analyse_repeats_js(
    prepared: &PreparedSettings,
    files: JsValue,
    options: JsValue,
    progress: Option<js_sys::Function>,
) -> Result<JsValue, JsValue> {
    let files = super::pool::files_from_js(&files, "repeat files: expected [{name, bytes}]")?;
    let opts: AnalysisOptions = super::settings_from_js(options, "bad analysis settings")?;
    let list: Vec<(&[u8], &str)> = files
        .iter()
        .map(|(name, bytes)| (bytes.as_slice(), name.as_str()))
        .collect();
    let session = prepared.session();
    let (a, _) = analyse_parts_with(session, &list, &opts, &mut sink_of(progress))
        .map_err(analysis_error)?;
    Ok(page_analysis(a, session.prepared())?)
}
