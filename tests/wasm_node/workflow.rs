//! The whole test of issue 19 compiled to wasm and run under Node: the exported `measurementPlan`,
//! `partProgram` and `compensate` calls give the core's numbers (the plan's predicted std, the
//! program's positions and files, the compensation of the example part).

use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::plan::{plan, PlanOptions};
use testpiece::program::{program, ProgramOptions};
use testpiece::wasm::compensation::compensate;
use testpiece::wasm::plan::measurement_plan;
use testpiece::wasm::program::part_program;

#[wasm_bindgen_test]
fn the_exported_plan_equals_the_core() {
    let js = measurement_plan(&crate::prepared(), JsValue::UNDEFINED)
        .ok()
        .expect("plan");
    let v: serde_json::Value = serde_wasm_bindgen::from_value(js).unwrap();
    let opts = PlanOptions::default();
    let core = plan(&opts.prepare().unwrap(), &opts).unwrap();
    let std = core.parameters.get("EX0B").unwrap().std.unwrap();
    assert_eq!(
        v["plan"]["parameters"]["EX0B"]["std"].as_f64().unwrap(),
        std
    );
    let dmis = core.dmis().unwrap();
    assert_eq!(v["dmis"].as_str().unwrap(), dmis.text);
    assert_eq!(
        v["dmis_replay"]["min_distance"].as_f64().unwrap(),
        dmis.replay.min_distance
    );
}

#[wasm_bindgen_test]
fn the_exported_program_equals_the_core() {
    let js = part_program(JsValue::UNDEFINED).ok().expect("program");
    let v: serde_json::Value = serde_wasm_bindgen::from_value(js).unwrap();
    let core = program(&ProgramOptions::default()).unwrap();
    assert_eq!(v["cl"].as_str().unwrap(), core.cl_apt());
    assert_eq!(v["gcode"].as_str().unwrap(), core.gcode());
    assert_eq!(v["dialects"].as_array().unwrap().len(), 5);
    assert_eq!(v["rounding_bound"].as_f64().unwrap(), core.rounding_bound());
}

#[wasm_bindgen_test]
fn the_exported_compensation_equals_the_core() {
    let text = testpiece::examples::example_text("example_backlash_c.csv").expect("example");
    let js = compensate(
        &crate::prepared(),
        text.as_bytes(),
        "example_backlash_c.csv",
        JsValue::UNDEFINED,
    )
    .ok()
    .expect("compensate");
    let v: serde_json::Value = serde_wasm_bindgen::from_value(js).unwrap();
    let a = analyse_once(
        text.as_bytes(),
        "example_backlash_c.csv",
        &AnalysisOptions::default(),
    )
    .unwrap();
    let core = testpiece::compensation::compensation(&a);
    assert_eq!(
        v["part"]["after"]["rms"].as_f64().unwrap(),
        core.part.after.rms
    );
    assert_eq!(v["notes"].as_array().unwrap().len(), core.notes.len());
}
