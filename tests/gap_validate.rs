//! The withheld-effect benchmark on the reference columns (baseline = the 8 location errors of
//! `sensitivity_physical.csv`, candidates = `effect_signatures.csv`): accuracy floors on a fixed
//! seed. 19 cases = one per kind (15 effects, 2 none, waviness, bump) to stay near 10 s in debug;
//! the CLI runs the full benchmark (`testpiece validate --cases 418 --seed 1`).
#![cfg(not(target_arch = "wasm32"))]
mod gap_common;
use gap_common::*;
use testpiece::gap::validate::{table, validate, ValidateOptions, ValidationModel};

fn model() -> ValidationModel {
    let inp = input(example("example_clean"));
    ValidationModel {
        points: inp.points,
        baseline: inp.baseline,
        candidates: inp.candidates,
    }
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
    // The shrink achieved on a correct verdict is the achievable one (same fit).
    for e in &r.per_effect {
        if e.detectable.cases > 0 && e.detectable.correct == e.detectable.cases {
            assert!(
                (e.shrink_achieved - e.shrink_achievable).abs() < 1e-9,
                "{e:?}"
            );
        }
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
