//! What the page receives from the core, run under Node: `start` gives the examples as their
//! files, the curves in id order, a word for every tag the results carry and the cones and
//! surfaces of the path curves; `curvesFor` gives every parameter its unit from its definition.

use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

use testpiece::wasm::curves::curves_for;
use testpiece::wasm::page::start;

#[wasm_bindgen_test]
fn start_gives_the_examples_curves_and_words() {
    let v: serde_json::Value = serde_wasm_bindgen::from_value(start().expect("start")).unwrap();
    assert_eq!(v["version"], testpiece::VERSION);
    assert_eq!(v["machines"].as_array().unwrap().len(), 3);
    for e in v["examples"].as_array().unwrap() {
        let name = e["name"].as_str().unwrap();
        assert_eq!(
            e["text"].as_str(),
            testpiece::examples::example_text(name).as_deref()
        );
    }
    assert_eq!(
        v["curves"],
        serde_json::json!(["A_Z11", "A_Z25", "B_Z11", "B_Z25"])
    );
    let w = &v["words"];
    for (kind, tags) in [
        ("groups", &["curve", "region", "lean", "reversal"][..]),
        ("error_status", &["kept", "absorbed", "invisible", "index"]),
        ("parameter_status", &["identified", "weak", "not_separable"]),
        ("group_kind", &["not_separable", "weak"]),
        ("effect_status", &["offered", "invisible", "left_out"]),
        (
            "flags",
            &["different", "suspect", "consistent", "undetermined"],
        ),
    ] {
        let keys: Vec<&str> = w[kind]
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        let mut want = tags.to_vec();
        want.sort();
        assert_eq!(keys, want, "{kind}");
    }
    assert_eq!(w["flags"]["different"], "different (|z| ≥ 3)");
    let t = &v["thresholds"];
    assert_eq!(t["reversal_window_mm"], 10.0);
    // identify::report's t for "clearly non-zero" (exact).
    assert_eq!(t["nonzero_t"], 3.0);
    // 0.27 % and 4.6 % of false alarms per parameter at |z| ≥ 3 and 2.
    assert!((t["different_false_alarm"].as_f64().unwrap() - 0.0027).abs() < 1e-5);
    assert!((t["suspect_false_alarm"].as_f64().unwrap() - 0.0455).abs() < 1e-4);
    // The cones of paper 002 §4 and the two flank passes, as `coneCoefficients` and `curvesFor`
    // take them.
    let p = &v["paths"];
    assert_eq!(p["cones"][0]["kind"], "M3_15");
    assert_eq!(p["cones"][1]["half_apex_deg"], 45.0);
    assert_eq!(p["cone_offsets"][0], 62.5);
    assert_eq!(p["cone_offsets"][1], 30.0);
    assert_eq!(p["surfaces"][1]["cutting"], "up-cutting");
}

#[wasm_bindgen_test]
fn curves_carry_each_parameter_with_its_unit() {
    let js = curves_for(&crate::prepared(), "A", 20).expect("curves");
    let sens = js_sys::Reflect::get(&js, &JsValue::from_str("sensitivity")).unwrap();
    let get = |k: &str| -> serde_json::Value {
        serde_wasm_bindgen::from_value(js_sys::Reflect::get(&sens, &JsValue::from_str(k)).unwrap())
            .unwrap()
    };
    let (params, units, scales) = (get("params"), get("units"), get("scales"));
    let n = params.as_array().unwrap().len();
    assert_eq!(n, 8);
    for k in 0..n {
        // Paper 000's machine: EX0B is its only position error (mm); the others are angles.
        let (unit, scale) = if params[k] == "EX0B" {
            ("mm", 0.01)
        } else {
            ("rad", 1e-4)
        };
        assert_eq!(units[k], unit, "{}", params[k]);
        assert_eq!(scales[k], scale, "{}", params[k]);
        // Each parameter also crosses as its id: kind, name and unit.
        let id = &get("parameters")[k];
        assert_eq!(id["kind"], "location_error");
        assert_eq!((&id["name"], &id["unit"]), (&params[k], &units[k]));
    }
    let path: serde_json::Value = serde_wasm_bindgen::from_value(
        js_sys::Reflect::get(&js, &JsValue::from_str("path")).unwrap(),
    )
    .unwrap();
    for c in path["coefficients"].as_array().unwrap() {
        let k = params
            .as_array()
            .unwrap()
            .iter()
            .position(|p| *p == c["param"])
            .unwrap();
        assert_eq!(c["unit"], units[k]);
        assert_eq!(c["k_n"].as_array().unwrap().len(), 21);
    }
}
