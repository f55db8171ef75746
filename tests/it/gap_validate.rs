//! The withheld-effect benchmark on the built-in points (the points of `example_clean.csv`), each
//! simulated part through the analysis the CLI and the page run: accuracy floors on a fixed
//! seed. 19 cases = one per kind (15 effects, 2 none, waviness, bump) to stay near 10 s in debug;
//! the CLI runs the full benchmark (`testpiece validate --cases 418 --seed 1`), as does the test of
//! the final answer's parameter error (the groups need that many cases).
use testpiece::parameter::Effect;
use testpiece::validate::{table, validate, ValidateOptions, ValidationModel};

fn model() -> ValidationModel {
    let part = testpiece::part::SShape::iso();
    ValidationModel::at(&part, &testpiece::part::builtin_points(&part))
        .unwrap()
        .without_shapes()
}

#[test]
fn accuracy_floors_on_a_fixed_seed() {
    let n: usize = std::env::var("GAP_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(19);
    let r = validate(
        &model(),
        &ValidateOptions::default().with_cases(n).with_seed(1),
    )
    .unwrap();
    println!("{}", table(&r));
    for c in r.results.iter().filter(|c| !c.correct) {
        println!(
            "wrong: case {} truth {} ratio {:.2} expected {} got {} (σ used {:.2} µm)",
            c.case,
            c.truth,
            c.ratio,
            c.expected,
            c.verdict,
            c.sigma_used * 1e3
        );
    }
    assert_eq!(r.cases, n);
    // Issue 6 floors: ≥ 90 % on detectable effects, ≥ 90 % `none` on none/undetectable.
    assert!(r.detectable.rate >= 0.9, "{}", table(&r));
    assert!(r.none_or_undetectable.rate >= 0.9, "{}", table(&r));
    // Out-of-list: issue floor 75 % (σ from the variogram nugget: 96.8 % over 418 cases, seed 1).
    assert!(
        r.out_of_list.cases == 0 || r.out_of_list.rate >= 0.75,
        "{}",
        table(&r)
    );
    // The shrink achieved on a correct verdict is the achievable one (same fit); a family's
    // (backlash lag, warm-up) fits its shape too, so it may shrink more than the true shape's
    // fit, never less; but a backlash is refitted with the play's take-up, which these parts
    // (made by the signatures, a play switched at the reversal) do not have: there it may shrink
    // up to 1 point less (measured on seed 1: backlash_b 0.83674 against 0.83686).
    for e in &r.per_effect {
        if e.detectable.cases > 0 && e.detectable.correct == e.detectable.cases {
            if matches!(e.effect, Effect::Backlash(_)) {
                assert!(e.shrink_achieved >= e.shrink_achievable - 0.01, "{e:?}");
            } else if e.effect.shape().is_some() {
                assert!(e.shrink_achieved >= e.shrink_achievable - 1e-9, "{e:?}");
            } else {
                assert!(
                    (e.shrink_achieved - e.shrink_achievable).abs() < 1e-9,
                    "{e:?}"
                );
            }
        }
    }
}

/// Issue 17 item 6: the final answer (location errors fitted with what the diagnosis names,
/// `gap::correct`) against the simulated truth. 19 cases hold no detectable out-of-list part on
/// seed 1 and 13 detectable effects, too few for a median and a coverage: this runs the full
/// benchmark, 418 cases (22 per kind; about 5 s in the test profile).
#[test]
fn final_answer_floors_on_a_fixed_seed() {
    use testpiece::final_fit::correct::Basis;
    use testpiece::gap::verdict::VerdictId;

    let r = validate(
        &model(),
        &ValidateOptions::default().with_cases(418).with_seed(1),
    )
    .unwrap();
    let e = &r.parameter_error;
    println!("{}", table(&r));
    // Issue 17 "Done when", detectable single-effect parts: median largest error <= 0.7 typical
    // units and coverage >= 90 % for the final answer. Measured here: 0.50 and 93.9 % (baseline
    // 6.78 and 56.5 %, 197 cases).
    assert_eq!(e.detectable.cases, r.detectable.cases);
    assert!(
        e.detectable.final_answer.median_largest_error <= 0.7,
        "{e:?}"
    );
    assert!(e.detectable.final_answer.coverage >= 0.9, "{e:?}");
    // Issue 17, `unexplained` parts: coverage >= 85 %. Measured here: 94.8 % (baseline 62.1 %,
    // 31 cases).
    assert_eq!(e.unexplained.cases, r.out_of_list.cases);
    assert!(e.unexplained.cases >= 20, "{e:?}");
    assert!(e.unexplained.final_answer.coverage >= 0.85, "{e:?}");
    // Issue 17, `none` parts unchanged: whenever the verdict is `none`, the final answer is the
    // baseline itself (its values; issue 29 widens its std by the model spread). (An expected-`none` part on which the diagnosis names something is
    // corrected for it: that is the verdict's error, counted by the accuracy test.)
    let mut kept = 0;
    for c in r.results.iter().filter(|c| c.verdict == VerdictId::Noise) {
        assert_eq!(c.basis, Basis::Baseline, "case {}", c.case);
        for (p, f) in &c.final_error.per_parameter {
            assert_eq!(
                f.error, c.baseline_error.per_parameter[p].error,
                "case {} {p}",
                c.case
            );
        }
        kept += 1;
    }
    assert!(kept >= e.none.cases * 9 / 10, "{kept} of {}", e.none.cases);
    // Every case is compared on the 8 location errors, whatever was fitted with them.
    for c in &r.results {
        assert_eq!(c.final_error.parameters, 8, "case {}", c.case);
        assert_eq!(c.baseline_error.parameters, 8, "case {}", c.case);
    }
}

#[test]
fn same_seed_same_report() {
    let o = ValidateOptions::default().with_cases(3).with_seed(42);
    let a = validate(&model(), &o).unwrap();
    let b = validate(&model(), &o).unwrap();
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
}

/// The diagnosis fits the linear baseline; simulating the machine part with the exact eq. 12
/// defect instead (differences < 0.3 µm at these magnitudes, simulate.rs) must not change a
/// verdict. Measured over 418 cases, seed 1 (`testpiece validate --exact`): 0 verdicts differ.
#[test]
fn verdicts_hold_on_the_exact_model() {
    use testpiece::part::SShape;
    use testpiece::validate::{exact_machine_part, validate_with};

    let part = SShape::iso();
    let model = ValidationModel::at(&part, &testpiece::part::builtin_points(&part))
        .unwrap()
        .without_shapes();
    let machine = exact_machine_part(&model.baseline.params).unwrap();
    let o = ValidateOptions::default().with_cases(19).with_seed(1);
    let lin = validate(&model, &o).unwrap();
    let ex = validate_with(&model, &o, machine.as_ref()).unwrap();
    for (a, b) in lin.results.iter().zip(&ex.results) {
        assert_eq!(a.verdict, b.verdict, "case {} ({})", a.case, a.truth);
        // The exact and linear machine parts differ by well under the 1.5 µm noise.
        assert!(
            (a.rms_before - b.rms_before).abs() < 1e-4,
            "case {}",
            a.case
        );
    }
}
