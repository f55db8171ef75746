//! The physics generator of `testpiece validate --generator physics` (issue 29 item 4): its servo
//! loops against the time-domain columns of `servo_signatures.csv`, its independence from the
//! fitter's signature code, its determinism per seed, and clean parts without visible structure.

use testpiece::machine::AxisName;
use testpiece::part::{builtin_points, SShape};
use testpiece::validate::physics::machining::{Machining, Workshop, AXES};
use testpiece::validate::physics::servo::{AxisLoop, Response};

const SERVO: &str = include_str!("../data/reference/servo_signatures.csv");
use testpiece::tolerance::SERVO_COLUMNS_MM;

/// Column `name` of `servo_signatures.csv` (mm), in point order (also read by
/// `sensitivity_servo`).
pub(crate) fn servo_column(name: &str) -> Vec<f64> {
    let mut lines = SERVO.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let j = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(j).unwrap().parse().unwrap())
        .collect()
}

/// The servo case of the reference: feed (mm/min), the gain of every axis but one, the odd axis
/// and its gain, second-order velocity loops or not.
fn servo_part(feed: f64, kv: f64, odd: Option<(AxisName, f64)>, second: bool) -> Vec<f64> {
    let part = SShape::iso();
    // the reference integrates every 0.5 ms: a sample every F·0.5 ms of path
    let step = feed / 60.0 * 5e-4;
    let w = Workshop::new(&part, &builtin_points(&part), 499.889, step).unwrap();
    let response = if second {
        Response::SecondOrder {
            omega: 2.0 * std::f64::consts::PI * 30.0,
            zeta: 0.7,
        }
    } else {
        Response::FirstOrder
    };
    let loops = AXES.map(|a| AxisLoop {
        kv: match odd {
            Some((o, k)) if o == a => k,
            _ => kv,
        },
        response,
    });
    w.machine(&Machining {
        feed,
        loops: Some(loops),
        ..Machining::default()
    })
    .unwrap()
}

/// The position loops integrated in time, the actual poses through the direct kinematics and
/// the envelope of the tool cylinders against the commanded one reproduce the reference's
/// simulated parts `sim_a`..`sim_d` and `sim_ref1`, `sim_ref2` (servo_signatures.csv, same feeds,
/// gains, loops and timing: a step of 0.5 ms). Tolerance 0.001 µm at every point: the README's
/// own convergence of these columns ("halving the step changes the columns by ≤ 0.001 µm"); we
/// agree to about 1e-5 µm.
#[test]
fn servo_loops_reproduce_the_reference_time_domain_columns() {
    for (name, ours) in [
        (
            "sim_a",
            servo_part(1500.0, 40.0, Some((AxisName::C, 30.0)), false),
        ),
        (
            "sim_b",
            servo_part(1500.0, 40.0, Some((AxisName::X, 25.0)), false),
        ),
        ("sim_c", servo_part(2000.0, 30.0, None, false)),
        (
            "sim_d",
            servo_part(1500.0, 40.0, Some((AxisName::C, 30.0)), true),
        ),
        ("sim_ref1", servo_part(1500.0, 40.0, None, false)),
        ("sim_ref2", servo_part(1500.0, 40.0, None, true)),
    ] {
        let reference = servo_column(name);
        let diff: Vec<f64> = ours.iter().zip(&reference).map(|(a, b)| a - b).collect();
        let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        let max = diff.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        println!(
            "{name}: rms {:.4} µm; ours − reference: rms {:.2e} µm, max {:.2e} µm",
            rms(&reference) * 1e3,
            rms(&diff) * 1e3,
            max * 1e3,
        );
        assert!(max <= SERVO_COLUMNS_MM, "{name}: {max:e} mm");
    }
}

use testpiece::machine::chain::PAPER000_L0;
use testpiece::validate::physics::case::Generator;
use testpiece::validate::physics::machining::Warmup;
use testpiece::validate::physics::measuring::{Measuring, Placement};
use testpiece::validate::physics::motion::{Law, PositionError};
use testpiece::validate::physics::Kind;
use testpiece::validate::physics_bench::{physics_table, PhysicsBench, PhysicsOptions};

const SIGNATURES: &str = include_str!("../data/reference/effect_signatures.csv");

/// Column `name` of `effect_signatures.csv` (per unit of the parameter), in point order.
fn signature(name: &str) -> Vec<f64> {
    let mut lines = SIGNATURES.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let j = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(j).unwrap().parse().unwrap())
        .collect()
}

/// The generator's workshop on the built-in points (0.05 mm of path a sample, as the benchmark).
fn workshop() -> Workshop {
    let part = SShape::iso();
    Workshop::new(&part, &builtin_points(&part), PAPER000_L0, 0.05).unwrap()
}

/// `max |ours − value·reference| / max |value·reference|`.
fn relative_gap(ours: &[f64], reference: &[f64], value: f64) -> f64 {
    let top = reference
        .iter()
        .fold(0.0f64, |m, r| m.max((r * value).abs()));
    ours.iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, r)| m.max((a - r * value).abs()))
        / top
}

/// At the reference settings of effects.md the physics gives the catalogue's shapes (the
/// independent vectors of `effect_signatures.csv`, first order in the effect): a head growing
/// slowly for a long time is the linear drift; a scale error of X; an offset of C; a longer
/// pivot; a larger tool; the part rotated and shifted on the CMM. Tolerance: 1 % of the column's
/// largest value (the vectors are first order; the physics is the exact chain and envelope).
#[test]
fn the_physics_gives_the_catalogue_shapes_at_their_reference_settings() {
    let w = workshop();
    let total = w.total_length();
    let g = 0.01;
    let thermal = w
        .machine(&Machining {
            feed: 60.0 * 1e6, // the whole part in a fraction of the time constant: linear growth
            warmup: Some(Warmup {
                growth: g * 1e4,
                minutes: total / (60.0 * 1e6) * 1e4,
                pause_s: 0.0,
            }),
            ..Machining::default()
        })
        .unwrap();
    assert!(
        relative_gap(&thermal, &signature("thermal_drift.g"), g) < 0.01,
        "thermal"
    );
    let k = 1e-4;
    let scale = w
        .machine(&Machining {
            motions: vec![PositionError::new(
                AxisName::X,
                AxisName::X,
                Law::Linear { k },
            )],
            ..Machining::default()
        })
        .unwrap();
    assert!(
        relative_gap(&scale, &signature("scale_x.k"), k) < 0.01,
        "scale_x"
    );
    let dc = 1e-4;
    let index = w
        .machine(&Machining {
            c_offset: dc,
            ..Machining::default()
        })
        .unwrap();
    assert!(
        relative_gap(&index, &signature("c_index.dC"), dc) < 0.01,
        "c_index"
    );
    let dl = 0.05;
    let pivot = w
        .machine(&Machining {
            pivot_error: dl,
            ..Machining::default()
        })
        .unwrap();
    assert!(
        relative_gap(&pivot, &signature("pivot_length.dL0"), dl) < 0.01,
        "pivot"
    );
    let dr = 0.01;
    let radius = w
        .machine(&Machining {
            radius_error: dr,
            ..Machining::default()
        })
        .unwrap();
    assert!(
        relative_gap(&radius, &signature("tool_radius.dR"), dr) < 0.01,
        "tool radius"
    );
    let theta = 1e-4;
    let placed = Measuring {
        placement: Some(Placement {
            theta_z: theta,
            tx: 0.0,
            ty: 0.0,
        }),
        ..Measuring::default()
    }
    .record(&w.points, &vec![0.0; w.points.len()]);
    assert!(
        relative_gap(&placed, &signature("setup_error.thetaz"), theta) < 0.01,
        "setup"
    );
}

/// A play taken up at once (`b` = 1e-6 mm or rad: its command travel is a few nm) behind a
/// first-order settling of 2 mm of path is the catalogue's backlash (effects.md;
/// `effect_signatures.csv`, per unit of `b`) on every axis: RMS over the points within 3 % of the
/// column's RMS (1.7 % at most). Single points next to a reversal differ by up to 13 % of the
/// column's largest value: there the true envelope takes the deepest of the neighbouring tools,
/// which the first-order signature (the offset at the point's own pose) does not.
#[test]
fn a_quick_play_behind_a_two_mm_lag_is_the_catalogues_backlash() {
    use testpiece::validate::physics::backlash::{LostMotion, Settling};
    let w = workshop();
    let b = 1e-6;
    let rms = |x: &[f64]| (x.iter().map(|a| a * a).sum::<f64>() / x.len() as f64).sqrt();
    for (axis, column) in [
        (AxisName::X, "backlash_x.b"),
        (AxisName::Y, "backlash_y.b"),
        (AxisName::Z, "backlash_z.b"),
        (AxisName::B, "backlash_b.b"),
        (AxisName::C, "backlash_c.b"),
    ] {
        let ours = w
            .machine(&Machining {
                backlash: Some((
                    axis,
                    LostMotion {
                        b,
                        settling: Settling::FirstOrder { tau: 2.0 },
                    },
                )),
                ..Machining::default()
            })
            .unwrap();
        let reference: Vec<f64> = signature(column).iter().map(|r| r * b).collect();
        let gap: Vec<f64> = ours.iter().zip(&reference).map(|(o, r)| o - r).collect();
        let rel = rms(&gap) / rms(&reference);
        println!("{column}: rms gap {:.2} %", 100.0 * rel);
        assert!(rel < 0.03, "{column}: {rel}");
    }
}

/// The generator is not the fitter: no file of `src/validate/physics/` uses the candidate
/// effects or their signatures (`crate::effects`), the simulator that adds effects by their
/// signatures (`crate::simulate`), the diagnosis (`crate::gap`), the measurement model
/// (`crate::measurement`), the analysis, the identification or the sensitivity stage (the
/// product's defect model). Its `crate::` paths name the part, the tool path, the machine and the
/// numerics only (and the test macro); comments are left out.
#[test]
fn the_physics_generator_does_not_use_the_fitters_code() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/src/validate/physics");
    let allowed = [
        "machine",
        "part",
        "toolpath",
        "geometry",
        "numerics",
        "assert_near",
    ];
    let mut files = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        files += 1;
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for forbidden in [
                "effects::",
                "simulate::",
                "gap::",
                "analysis::",
                "signature",
            ] {
                assert!(
                    !code.contains(forbidden),
                    "{}:{}: `{forbidden}` in `{line}`",
                    path.display(),
                    i + 1
                );
            }
            for (k, _) in code.match_indices("crate::") {
                let stage: String = code[k + 7..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                assert!(
                    allowed.contains(&stage.as_str()),
                    "{}:{}: crate::{stage} is not the part, path, machine or numerics",
                    path.display(),
                    i + 1
                );
            }
        }
    }
    assert!(files >= 9, "{files} files read");
}

/// The bench's generator over the built-in points, its visible structure from the baseline.
fn with_generator<T>(f: impl FnOnce(&Generator, &PhysicsBench) -> T) -> T {
    let bench = PhysicsBench::builtin().unwrap();
    let base = testpiece::identify::solve::Factor::new(&bench.model.baseline.matrix, None);
    let visible = |d: &[f64]| {
        let u = base.unabsorbed_vec(&nalgebra::DVector::from_column_slice(d));
        u.norm() / (d.len() as f64).sqrt()
    };
    let g = Generator::new(
        &bench.workshop,
        bench.location.clone(),
        &visible,
        bench.detect_factor,
    );
    f(&g, &bench)
}

/// Nothing but the command leaves the nominal part exactly; the location errors alone leave no
/// visible structure beyond the chain's non-linearity (the exact eq. 12 and the envelope against
/// the linear columns: reference README, < 0.2 µm at these magnitudes; 0.03 µm here), which is
/// < 5 % of any limit (2.5 × 0.8 µm at the least). The same seed makes the same parts; another seed others.
#[test]
fn clean_parts_have_no_visible_structure_and_parts_follow_their_seed() {
    with_generator(|g, _| {
        let nothing = g.workshop.machine(&Machining::default()).unwrap();
        assert!(nothing.iter().all(|d| *d == 0.0));
        for case in [0, 3] {
            let p = g
                .part(Kind::Clean, &mut PhysicsBench::stream(7, case))
                .unwrap();
            let v = (g.visible)(&p.noise_free);
            println!("clean part {case}: visible {:.4} µm", v * 1e3);
            assert!(v < 0.05 * 2.5 * 0.0008, "visible {v}");
        }
        let make = |seed| {
            g.part(Kind::Backlash, &mut PhysicsBench::stream(seed, 1))
                .unwrap()
                .measurements
        };
        assert_eq!(make(5), make(5));
        assert_ne!(make(5), make(6));
    });
}

/// A few parts through the whole benchmark (one of each clean kind and three effects): the
/// report is made, every case judged, every figure finite where it has cases.
#[test]
fn a_few_parts_through_the_benchmark() {
    let bench = PhysicsBench::builtin().unwrap();
    let r = bench
        .run(&PhysicsOptions {
            cases: 6,
            seed: 1,
            cmm_sigma: false,
            threads: 1,
        })
        .unwrap();
    println!("{}", physics_table(&r));
    assert_eq!(r.results.len(), 6);
    for c in &r.results {
        assert!(c.visible.is_finite() && c.limit > 0.0, "{c:?}");
        assert_eq!(c.judged.final_error.parameters, 8);
    }
}

/// The report does not depend on how many threads share the cases: 9 parts (every clean kind and
/// six effects) on one thread and on three give the same JSON, byte for byte.
#[test]
fn the_report_is_the_same_on_any_number_of_threads() {
    let bench = PhysicsBench::builtin().unwrap();
    let json = |threads| {
        let r = bench
            .run(&PhysicsOptions {
                cases: 9,
                seed: 2,
                cmm_sigma: false,
                threads,
            })
            .unwrap();
        serde_json::to_string(&r).unwrap()
    };
    assert_eq!(json(1), json(3));
}

/// Issue 29's figures on the development seed 1 (300 parts; the held-out seeds 101-103 are
/// scored by `validate --generator physics --seed 101` and reported in the README, never tuned
/// on): `none` never when the visible structure exceeds twice the limit; clean parts and repeats
/// of a scattered part `none` at least 95 %; the final location errors within 2 std of the truth
/// in at least 90 % in every group of the report but the mixed 1-2x one (measured with the
/// nuisance families of the model spread, `effects::nuisance`, the error motions pooled beside
/// the answer's model, the pooled σ̂'s correlated dof, the axes' error motions measured from
/// their ISO 230-1 reference: min 93.4 %, the named verdicts; 94.5 % clean, 96.4 % below the
/// limit, 93.9 % in-catalogue above 2x, 98.2 % out-of-catalogue above 2x, 97.4 % wrong
/// verdicts, 98.8 % `unexplained` verdicts);
/// and the std not inflated
/// where the model can be right: median final std over the true model's fit's <= 2 on clean
/// parts and on in-catalogue parts above 2x the limit (measured 1.06 and 1.09).
#[test]
fn the_final_errors_are_covered_by_their_std_in_every_group() {
    let bench = PhysicsBench::builtin().unwrap();
    let r = bench
        .run(&PhysicsOptions {
            cases: 300,
            seed: 1,
            cmm_sigma: false,
            ..PhysicsOptions::default()
        })
        .unwrap();
    let s = &r.summary;
    println!("{}", physics_table(&r));
    assert_eq!(s.none_above_twice, 0, "{s:?}");
    assert!(s.clean_none >= 0.95 && s.repeats_none >= 0.95, "{s:?}");
    assert!(s.min_coverage >= 0.9, "{s:?}");
    for name in ["clean", "in-catalogue > 2x"] {
        let g = r.groups.iter().find(|g| g.group == name).unwrap();
        assert!(g.median_std_ratio <= 2.0, "{name}: {}", g.median_std_ratio);
    }
}
