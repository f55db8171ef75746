//! The shapes of the backlash and warm-up families against the physics generator (issue 30 item
//! 4: checked against physics, not against the formula the fitter uses): the play taken up after
//! each reversal ([`testpiece::sensitivity::take_up`]) against the generator's dead band behind a
//! first-order servo (`validate::physics::backlash`), the family's members that ring against
//! the generator's underdamped slide, and the warm-up with a pause between the
//! passes against the generator's head warming in machining time (`validate::physics::machining`),
//! and a servo lag's estimate, with the rounding every lagging axis shares, against the
//! generator's position loops integrated in time (`validate::physics::servo`).
//! The generator shares no code with the fitter's signatures (`validate_physics`'s architecture
//! test).

use testpiece::effects::family::Members;
use testpiece::effects::prepared::Prepared;
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::AxisName;
use testpiece::parameter::effect::{damping_of_overshoot, OVERSHOOT_GRID};
use testpiece::parameter::Effect;
use testpiece::part::{builtin_points, SShape};
use testpiece::sensitivity::SensitivityOptions;
use testpiece::validate::physics::backlash::{LostMotion, Settling};
use testpiece::validate::physics::machining::{Machining, Warmup, Workshop};

fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|a| a * a).sum::<f64>() / x.len() as f64).sqrt()
}

/// `rms(ours − physics) / rms(physics)`.
fn gap(physics: &[f64], ours: &[f64]) -> f64 {
    let d: Vec<f64> = physics.iter().zip(ours).map(|(p, o)| p - o).collect();
    rms(&d) / rms(physics)
}

/// The product's prepared settings (paper 000's machine, signed B) and the generator's workshop
/// on the built-in points (0.05 mm of path a sample, as the benchmark).
fn settings_and_workshop() -> (Prepared, Workshop) {
    let part = SShape::iso();
    let w = Workshop::new(&part, &builtin_points(&part), PAPER000_L0, 0.05).unwrap();
    (
        Prepared::new(part, SensitivityOptions::default()).unwrap(),
        w,
    )
}

/// Column 0 of member `k` of the family of `effect` in `model`.
fn member(model: &testpiece::effects::builtin::PartModel, effect: Effect, k: usize) -> Vec<f64> {
    let c = model
        .candidates
        .iter()
        .find(|c| c.effect == effect)
        .unwrap();
    c.family
        .as_ref()
        .unwrap()
        .member(k)
        .column(0)
        .iter()
        .copied()
        .collect()
}

/// A large play (X 0.05 mm, C 1e-3 rad, B 2e-4 rad: the generator's largest) behind a
/// first-order servo of 1.18 mm (a value of the family's grid, 2·1.3⁻² mm): the family's member
/// with the take-up of that `b` is within 3 % RMS of the physics on every axis, and at most a
/// quarter of the gap of the member that switches at the reversal (measured: X 1.7 % against
/// 22.5 %, C 1.0 % against 6.4 %, B 0.7 % against 18.3 %; the rest is the envelope's neighbouring
/// tools next to a reversal, as in `validate_physics`'s quick-play test).
#[test]
fn the_play_taken_up_after_a_reversal_is_the_physics_of_a_dead_band() {
    let (prepared, w) = settings_and_workshop();
    let base = prepared.builtin_model();
    let k = 7; // 2·1.3^(7−9) mm
    let tau = 2.0 * 1.3f64.powi(k as i32 - 9);
    for (axis, b) in [
        (AxisName::X, 0.05),
        (AxisName::C, 1e-3),
        (AxisName::B, 2e-4),
    ] {
        let physics = w
            .machine(&Machining {
                backlash: Some((
                    axis,
                    LostMotion {
                        b,
                        settling: Settling::FirstOrder { tau },
                    },
                )),
                ..Machining::default()
            })
            .unwrap();
        let effect = Effect::Backlash(axis);
        // the family holds each lag at every overshoot, the first order first
        let m = OVERSHOOT_GRID.len();
        let switched: Vec<f64> = member(base, effect, k * m).iter().map(|v| v * b).collect();
        // the rebuilt family holds each lag switched and taken up, in that order
        let taken = base.with_take_up(prepared.path(), &[(axis, b)]).unwrap();
        let taken_up: Vec<f64> = member(&taken, effect, 2 * k + 1)
            .iter()
            .map(|v| v * b)
            .collect();
        assert_eq!(member(&taken, effect, 2 * k), member(base, effect, k * m));
        let (g_switch, g_take) = (gap(&physics, &switched), gap(&physics, &taken_up));
        println!("{axis:?}: switched {g_switch:.3}, taken up {g_take:.3}");
        assert!(g_take < 0.03, "{axis:?}: {g_take}");
        assert!(g_take < 0.25 * g_switch, "{axis:?}: {g_take} vs {g_switch}");
    }
}

/// `a·x` at its least-squares amplitude `a` for `y`.
fn best_multiple(x: &[f64], y: &[f64]) -> Vec<f64> {
    let a = x.iter().zip(y).map(|(x, y)| x * y).sum::<f64>() / x.iter().map(|x| x * x).sum::<f64>();
    x.iter().map(|v| v * a).collect()
}

/// A small play (X 5 µm, C 5e-5 rad: the generator's, whose take-up is short) behind a servo that
/// rings: second order of natural length 5.9 mm (a lag of the grid, 2·1.3⁴ mm) overshooting by
/// 40 % (ζ 0.28, a value of the overshoot grid). The family's member at that lag and overshoot,
/// at its best amplitude, is within 6 % RMS of the physics; the best first-order member (every
/// lag of the grid, each at its best amplitude) misses by at least four times as much (measured:
/// X 4.0 % against 29.6 %, C 2.8 % against 18.3 %; the rest is the take-up and the envelope's
/// neighbouring tools).
#[test]
fn the_members_that_overshoot_are_the_physics_of_a_ringing_slide() {
    let (prepared, w) = settings_and_workshop();
    let base = prepared.builtin_model();
    let m = OVERSHOOT_GRID.len();
    let (k, o) = (13, 2); // 2·1.3^(13−9) mm, 40 %
    let tau = 2.0 * 1.3f64.powi(k as i32 - 9);
    let zeta = damping_of_overshoot(OVERSHOOT_GRID[o]).unwrap();
    for (axis, b) in [(AxisName::X, 0.005), (AxisName::C, 5e-5)] {
        let physics = w
            .machine(&Machining {
                backlash: Some((
                    axis,
                    LostMotion {
                        b,
                        settling: Settling::Underdamped { tau, zeta },
                    },
                )),
                ..Machining::default()
            })
            .unwrap();
        let effect = Effect::Backlash(axis);
        let ringing = gap(
            &physics,
            &best_multiple(&member(base, effect, k * m + o), &physics),
        );
        let first = (0..18)
            .map(|j| {
                gap(
                    &physics,
                    &best_multiple(&member(base, effect, j * m), &physics),
                )
            })
            .fold(f64::INFINITY, f64::min);
        println!("{axis:?}: ringing member {ringing:.3}, best first order {first:.3}");
        assert!(ringing < 0.06, "{axis:?}: {ringing}");
        assert!(first > 4.0 * ringing, "{axis:?}: {first} vs {ringing}");
    }
}

/// A head warming with a time constant of 0.3 of the machining time, paused for 0.35 of it
/// between the passes (a value of the pause grid): the warm-up family's member at that constant
/// and pause is the physics to 0.5 % RMS; the member without the pause, even at its best
/// amplitude, misses it by more than ten times that (measured: 0.10 % against 4.3 %).
#[test]
fn the_warm_up_with_a_pause_is_the_physics_of_a_head_warming_in_time() {
    let (prepared, w) = settings_and_workshop();
    let model = prepared.builtin_model();
    let (feed, f, pause, growth) = (1500.0, 0.3, 0.35, 0.02);
    let cut_minutes = w.total_length() / feed;
    let physics = w
        .machine(&Machining {
            feed,
            warmup: Some(Warmup {
                growth,
                minutes: f * cut_minutes,
                pause_s: pause * cut_minutes * 60.0,
            }),
            ..Machining::default()
        })
        .unwrap();
    let c = model
        .candidates
        .iter()
        .find(|c| c.effect == Effect::ThermalDrift)
        .unwrap();
    let family = c.family.as_ref().unwrap();
    let Members::WarmUp(basis) = &family.members else {
        panic!("the warm-up's members are computed from its basis");
    };
    // the drift reached at the end of B
    let g = growth * (1.0 - (-(1.0 + pause) / f).exp());
    let paused: Vec<f64> = basis.column(f, pause).iter().map(|v| v * g).collect();
    // without the pause, at its best amplitude (least squares)
    let col = basis.column(f, 0.0);
    let g0 = col.iter().zip(&physics).map(|(c, p)| c * p).sum::<f64>()
        / col.iter().map(|c| c * c).sum::<f64>();
    let unpaused: Vec<f64> = col.iter().map(|v| v * g0).collect();
    let (g_p, g_0) = (gap(&physics, &paused), gap(&physics, &unpaused));
    println!("paused {g_p:.4}, without the pause {g_0:.4}");
    assert!(g_p < 0.005, "{g_p}");
    assert!(g_0 > 10.0 * g_p, "{g_0} vs {g_p}");
}

/// The deviations of a part whose Y axis trails the others (position loops integrated in time
/// by the generator; no location errors), in the order of `ids`.
fn y_lagging_part(
    w: &Workshop,
    feed: f64,
    kv: f64,
    kv_y: f64,
    response: testpiece::validate::physics::servo::Response,
    ids: &[usize],
) -> Vec<f64> {
    use testpiece::validate::physics::machining::AXES;
    use testpiece::validate::physics::servo::AxisLoop;
    let loops = AXES.map(|a| AxisLoop {
        kv: if a == AxisName::Y { kv_y } else { kv },
        response,
    });
    let d = w
        .machine(&Machining {
            feed,
            loops: Some(loops),
            ..Machining::default()
        })
        .unwrap();
    let order: Vec<usize> = builtin_points(&SShape::iso())
        .iter()
        .map(|p| p.id)
        .collect();
    ids.iter()
        .map(|id| d[order.iter().position(|o| o == id).unwrap()])
        .collect()
}

/// A Y axis trailing the others, with the common lag `L = F/Kv` of 0.86 and 1.09 mm (first- and
/// second-order velocity loops: two parts of the held-out seeds 112 and 111 of
/// `validate --generator physics`), σ 1.5 µm, through the shipped analysis: the verdict is
/// `servo_lag_y` (with `servo_common` when the rounding is above the limit), `l` lies within 3 %
/// of the truth `(1/Kv_y − 1/Kv)·F/60` on each of 4 noise draws and within its reported 95 %
/// interval, and the final answer holds `servo_common.L2`. Fitted alone, the lag took up the
/// rounding of the path that every lagging axis leaves (unabsorbed correlation 0.70 with Y's
/// lag): +14 % and −24 % on these parts, noise-free (BENCHMARKS.md, ninth session); with the
/// rounding fitted as a nuisance, 1.3 % and 0.5 %.
#[test]
fn a_servo_lag_is_estimated_with_the_rounding_every_lagging_axis_shares() {
    use testpiece::analysis::{fit_points, Diagnosis};
    use testpiece::numerics::random::Sampler;
    use testpiece::validate::physics::servo::Response;
    use testpiece::validate::ValidationModel;
    let part = SShape::iso();
    let model = ValidationModel::at(&part, &builtin_points(&part)).unwrap();
    let (_, w) = settings_and_workshop();
    let ids: Vec<usize> = model.measured.iter().map(|p| p.id).collect();
    let names: Vec<String> = ids.iter().map(|i| i.to_string()).collect();
    let mut rng = Sampler::new(30);
    for (feed, kv, kv_y, response) in [
        (1201.2, 23.21, 19.43, Response::FirstOrder),
        (
            1630.3,
            24.99,
            27.7,
            Response::SecondOrder {
                omega: 323.6,
                zeta: 0.756,
            },
        ),
    ] {
        let truth = (1.0 / kv_y - 1.0 / kv) * feed / 60.0;
        let clean = y_lagging_part(&w, feed, kv, kv_y, response, &ids);
        for _ in 0..4 {
            let y: Vec<f64> = clean.iter().map(|d| d + 0.0015 * rng.normal()).collect();
            let fit = fit_points(&model.prepared, &model.at, &y, &names, &model.settings).unwrap();
            let Diagnosis::Made { report, .. } = &fit.diagnosis else {
                panic!("not diagnosed")
            };
            // the lag alone, or with the rounding as the pair's second effect
            let named = report.verdict.finding.effects();
            assert!(
                named[0] == Effect::ServoLag(AxisName::Y)
                    && named[1..].iter().all(|e| *e == Effect::ServoCommon),
                "{:?} {:?}",
                report.verdict.id(),
                report.verdict.finding.effects()
            );
            let l = report
                .verdict
                .parameter(Effect::ServoLag(AxisName::Y), "l")
                .unwrap();
            eprintln!(
                "Kv {kv} / {kv_y}: l = {:.4} ± {:.4} mm, truth {truth:.4} ({:+.1} %)",
                l.value,
                l.std,
                100.0 * (l.value / truth - 1.0)
            );
            assert!(
                (l.value / truth - 1.0).abs() < 0.03,
                "{} vs {truth}",
                l.value
            );
            assert!((l.value - truth).abs() <= 1.96 * l.std);
            // the final answer is fitted with the rounding too
            assert!(fit
                .identification
                .parameters
                .0
                .iter()
                .any(|p| p.name() == "servo_common.L2"));
        }
    }
}
