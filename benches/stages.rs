//! Benchmarks of each pipeline stage (`cargo bench --bench stages [-- FILTER]`): median wall time
//! of repeated calls, printed as `stage<TAB>median_us`. A plain harness (no external crate) so it
//! runs on stable; `scripts/bench.sh` puts these medians beside the same calls through the release
//! wasm under Node (`scripts/bench-wasm.mjs`, same stage names) for BENCHMARKS.md.

use std::hint::black_box;
use std::time::{Duration, Instant};

use testpiece::analysis::{analyse, AnalysisOptions};
use testpiece::part::{builtin_points, SShape, Surface};
use testpiece::sensitivity::{sensitivity_matrix, SensitivityOptions};

/// Runs `f` repeatedly for about `budget` (at least 5 times), returns the median of one call.
fn median<F: FnMut()>(mut f: F, budget: Duration) -> Duration {
    f();
    let mut times = Vec::new();
    let start = Instant::now();
    while (start.elapsed() < budget || times.len() < 5) && times.len() < 100_000 {
        let t = Instant::now();
        f();
        times.push(t.elapsed());
    }
    times.sort();
    times[times.len() / 2]
}

/// A canonical CMM file of `rows` rows: the 100 built-in points repeated with unique ids.
fn cmm_text(rows: usize) -> String {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let mut s = String::from("id,curve,x,y,z,nx,ny,nz,deviation\n");
    for i in 0..rows {
        let p = &pts[i % pts.len()];
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{}\n",
            i + 1,
            p.curve.name(),
            p.point.x,
            p.point.y,
            p.point.z,
            p.normal.x,
            p.normal.y,
            p.normal.z,
            0.001 * ((i % 17) as f64 - 8.0)
        ));
    }
    s
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let run = |name: &str| filter.as_deref().is_none_or(|f| name.contains(f));
    let budget = Duration::from_millis(500);
    let report = |stage: &str, d: Duration| println!("{stage}\t{:.3}", d.as_secs_f64() * 1e6);
    let part = SShape::iso();
    let points = builtin_points(&part);

    if run("bspline_eval_1000") {
        let c = &part.a[0];
        report(
            "bspline_eval_1000",
            median(
                || {
                    for i in 0..1000 {
                        black_box(c.derivs_at(black_box(i as f64 / 999.0)));
                    }
                },
                budget,
            ),
        );
    }
    if run("builtin_points") {
        report(
            "builtin_points",
            median(|| drop(black_box(builtin_points(black_box(&part)))), budget),
        );
    }
    if run("envelope_100") {
        report(
            "envelope_100",
            median(
                || {
                    drop(black_box(testpiece::toolpath::envelope::points_deviation(
                        &part, &points, 0.0,
                    )))
                },
                budget,
            ),
        );
    }
    if run("surface_max_overcut") {
        report(
            "surface_max_overcut",
            median(
                || {
                    drop(black_box(
                        testpiece::toolpath::envelope::surface_max_overcut(&part, Surface::A),
                    ));
                },
                Duration::from_millis(100),
            ),
        );
    }
    if run("figure19_matrix") {
        let o = SensitivityOptions::default();
        report(
            "figure19_matrix",
            median(
                || drop(black_box(sensitivity_matrix(&part, &points, &o))),
                budget,
            ),
        );
    }
    for rows in [100usize, 100_000] {
        let name = format!("read_cmm_{rows}");
        if run(&name) {
            let text = cmm_text(rows);
            report(
                &name,
                median(
                    || {
                        drop(black_box(testpiece::cmm::read_cmm(
                            text.as_bytes(),
                            "bench.csv",
                        )))
                    },
                    budget,
                ),
            );
        }
    }
    if run("analyse_100") {
        let text = cmm_text(100);
        let o = AnalysisOptions::default();
        report(
            "analyse_100",
            median(
                || drop(black_box(analyse(text.as_bytes(), "bench.csv", &o))),
                budget,
            ),
        );
    }
}
