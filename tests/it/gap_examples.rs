//! The three example parts of `tests/data/reference/examples/` get their keyed verdicts
//! (`*.key.json`: `accept`, `achievable_rms_after`, `unexplained_rms`, `equivalence_corr`), and the
//! near-equivalences named in the reference README are found from the signatures.
use crate::gap_common::*;
use nalgebra::DVector;
use testpiece::assert_near;
use testpiece::effects::GapError;
use testpiece::gap::diagnose;
use testpiece::gap::equivalence::cos_to_span;
use testpiece::identify::solve::Factor;
use testpiece::parameter::Effect;

/// The examples are written with 6 decimals (0.5 µm rounding, ≈0.29 µm RMS): the residual RMS
/// after the true effect is fitted agrees with the key's `achievable_rms_after` within 0.1 µm.
const RMS_AFTER_TOL: f64 = 1e-4;

fn accepts(name: &str) -> Vec<String> {
    key(name)["accept"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect()
}

#[test]
fn clean_part_is_none() {
    let r = diagnose(&input(example("example_clean"))).unwrap();
    assert_eq!(r.verdict.id().as_str(), "none", "{}", r.summary);
    assert!(accepts("example_clean").contains(&r.verdict.id().to_string()));
    let k = key("example_clean");
    assert_near!(
        r.verdict.rms_after,
        k["achievable_rms_after"].as_f64().unwrap(),
        RMS_AFTER_TOL
    );
    assert_near!(
        r.baseline.rms,
        k["baseline_rms"].as_f64().unwrap(),
        RMS_AFTER_TOL
    );
    assert!(
        r.summary.starts_with("Verdict: no unmodelled effect"),
        "{}",
        r.summary
    );
    // The detection limit is 2.5 σ with σ near the simulated 1.5 µm (±20 %).
    assert!((0.8 * 3.75e-3..1.2 * 3.75e-3).contains(&r.verdict.detection_limit));
}

#[test]
fn tool_radius_part_names_tool_radius_and_its_equivalent() {
    let name = "example_tool_radius";
    let r = diagnose(&input(example(name))).unwrap();
    let k = key(name);
    assert!(
        accepts(name).contains(&r.verdict.id().to_string()),
        "{}",
        r.summary
    );
    assert_eq!(r.verdict.id().as_str(), "tool_radius", "{}", r.summary);
    assert!(r.verdict.finding.equivalent().contains(&Effect::ToolTaper));
    assert_near!(
        r.verdict.rms_after,
        k["achievable_rms_after"].as_f64().unwrap(),
        RMS_AFTER_TOL
    );
    assert_near!(
        r.verdict.rms_before,
        k["baseline_rms"].as_f64().unwrap(),
        RMS_AFTER_TOL
    );
    // Fitted dR agrees with the key's fit of the true effect within its std (≈0.17 µm).
    let dr = r.verdict.parameters["dR"];
    assert_near!(dr.value, k["true_effect_fit"]["dR"].as_f64().unwrap(), 2e-4);
    assert!(r
        .summary
        .starts_with("Verdict: tool radius error (`tool_radius`)"));
}

#[test]
fn backlash_c_part_names_backlash_c() {
    let name = "example_backlash_c";
    let r = diagnose(&input(example(name))).unwrap();
    let k = key(name);
    assert_eq!(r.verdict.id().as_str(), "backlash_c", "{}", r.summary);
    assert_near!(
        r.verdict.rms_after,
        k["achievable_rms_after"].as_f64().unwrap(),
        RMS_AFTER_TOL
    );
    let b = r.verdict.parameters["b"];
    assert_near!(b.value, k["true_effect_fit"]["b"].as_f64().unwrap(), 2e-6);
}

/// README: "`tool_radius` ⊂ `tool_taper` (1.0), `c_index` ⊂ `setup_error` (1.0),
/// `pivot_length`/`scale_z` 0.992 and `backlash_b`/`backlash_z` 0.986" (3 decimals: tol 5e-4).
#[test]
fn near_equivalences_of_the_readme_are_found() {
    let r = diagnose(&input(example("example_clean"))).unwrap();
    let find = |a: &str, b: &str| {
        r.equivalences
            .iter()
            .find(|e| (e.a.id() == a && e.b.id() == b) || (e.a.id() == b && e.b.id() == a))
            .unwrap_or_else(|| panic!("{a}/{b} not found in {:?}", r.equivalences))
            .clone()
    };
    let e = find("tool_radius", "tool_taper");
    assert_near!(e.cosine, 1.0, 5e-4);
    assert_eq!(e.a, Effect::ToolRadius);
    assert_near!(e.a_within_b.unwrap(), 1.0, 5e-4);
    let e = find("c_index", "setup_error");
    assert_near!(e.a_within_b.unwrap(), 1.0, 5e-4);
    assert_near!(find("pivot_length", "scale_z").cosine, 0.992, 5e-4);
    assert_near!(find("backlash_b", "backlash_z").cosine, 0.986, 5e-4);
    assert_eq!(r.equivalences.len(), 4, "{:?}", r.equivalences);
}

/// The keys' `unexplained_rms` (the part of the true effect the 8-error fit cannot absorb) and
/// `equivalence_corr` (its cosine with each candidate's unabsorbed span), 6 decimals in the key.
#[test]
fn unabsorbed_parts_match_the_keys() {
    let inp = input(example("example_clean"));
    let base = Factor::new(&inp.baseline.matrix, None);
    for (name, id, value) in [
        ("example_tool_radius", "tool_radius", 0.015),
        ("example_backlash_c", "backlash_c", 6e-4),
    ] {
        let k = key(name);
        let c = inp.candidates.iter().find(|c| c.effect.id() == id).unwrap();
        let e: DVector<f64> = c.signature.matrix.column(0).into_owned() * value;
        let u = base.unabsorbed_vec(&e);
        assert_near!(
            u.norm() / 10.0,
            k["unexplained_rms"].as_f64().unwrap(),
            1e-9
        );
        for other in inp.candidates.iter() {
            if other.effect.id() == id {
                continue;
            }
            let uo = base.unabsorbed(&other.signature.matrix);
            let qo = Factor::new(&uo, None).basis;
            let expected = k["equivalence_corr"][other.effect.id()].as_f64().unwrap();
            assert_near!(cos_to_span(&u, &qo), expected, 1e-5);
        }
    }
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let mut inp = input(example("example_clean"));
    inp.deviations.pop();
    assert!(matches!(
        diagnose(&inp),
        Err(GapError::LengthMismatch {
            got: 100,
            expected: 99,
            ..
        })
    ));
    let mut inp = input(example("example_clean"));
    inp.deviations[3] = f64::NAN;
    assert!(matches!(
        diagnose(&inp),
        Err(GapError::NotFinite { index: 3, .. })
    ));
    let mut inp = input(example("example_clean"));
    inp.noise_sigma = Some(-1.0);
    assert!(matches!(diagnose(&inp), Err(GapError::BadSigma(_))));
}

#[test]
fn json_has_the_fields_of_cli_md() {
    let r = diagnose(&input(example("example_backlash_c"))).unwrap();
    let v = serde_json::to_value(&r).unwrap();
    for f in ["rms", "max_abs"] {
        assert!(v["baseline"][f].is_number());
    }
    assert!(v["where"].is_array());
    let c = &v["candidates"][0];
    for f in [
        "effect",
        "parameters",
        "rms",
        "cv_rms",
        "shrink",
        "evidence",
    ] {
        assert!(!c[f].is_null(), "candidate field {f}");
    }
    for f in [
        "effect",
        "equivalent",
        "rms_before",
        "rms_after",
        "detection_limit",
    ] {
        assert!(!v["verdict"][f].is_null(), "verdict field {f}");
    }
}

/// Timing of one full diagnosis (not an assertion: the target, < 50 ms natively, is for release).
#[test]
fn time_one_diagnosis() {
    let inp = input(example("example_backlash_c"));
    let t = std::time::Instant::now();
    let k = 3;
    for _ in 0..k {
        diagnose(&inp).unwrap();
    }
    println!(
        "diagnosis of 100 points: {:.1} ms",
        t.elapsed().as_secs_f64() * 1e3 / k as f64
    );
}
