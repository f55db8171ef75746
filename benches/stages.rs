//! Benchmarks of each pipeline stage (`cargo bench`): median wall time of repeated calls.
//! A plain harness (no external crate) so it runs on stable; `scripts/bench.sh` prints the
//! native/wasm table of BENCHMARKS.md.

use std::hint::black_box;
use std::time::{Duration, Instant};

/// Runs `f` repeatedly for about `budget`, returns the median time of one call.
fn median<F: FnMut()>(mut f: F, budget: Duration) -> Duration {
    f();
    let mut times = Vec::new();
    let start = Instant::now();
    while start.elapsed() < budget || times.len() < 5 {
        let t = Instant::now();
        f();
        times.push(t.elapsed());
        if times.len() >= 100_000 {
            break;
        }
    }
    times.sort();
    times[times.len() / 2]
}

fn report(stage: &str, d: Duration) {
    println!("{stage:<40} {:>12.3} µs", d.as_secs_f64() * 1e6);
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let budget = Duration::from_millis(300);
    let run = |name: &str| filter.as_deref().is_none_or(|f| name.contains(f));

    if run("bspline_eval") {
        let part = testpiece::part::SShape::iso();
        let c = &part.a[0];
        report(
            "bspline_eval (1000 derivs_at)",
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
    if run("part_summary") {
        report(
            "part_summary (4 curve lengths)",
            median(
                || drop(black_box(testpiece::summary::part_summary())),
                budget,
            ),
        );
    }
}
