//! Benchmarks of each pipeline stage (`cargo bench --bench stages [-- FILTER]`): median wall time
//! of repeated calls, printed as `stage<TAB>median_us` and written to
//! `target/bench-native.json` (`{stage: median_us}`). A plain harness (no external crate) so it
//! runs on stable. The stages and their inputs are `testpiece::bench` (one definition for
//! this harness and for `scripts/bench-wasm.mjs`, which times the same calls in the release wasm
//! under Node and prints the native | wasm | ratio table).

use std::hint::black_box;
use std::time::{Duration, Instant};

use testpiece::bench::{Stage, STAGES};

/// Runs `f` repeatedly for about `budget` (at least 5 times), returns the median of one call; a
/// call longer than the budget is timed once.
/// A zero budget times one call (for `valgrind --tool=callgrind`: instruction counts).
fn median<F: FnMut()>(mut f: F, budget: Duration) -> Duration {
    if budget.is_zero() {
        let t = Instant::now();
        f();
        return t.elapsed();
    }
    // a call longer than the budget (a 200,000-point scan) is timed once: its first call
    let first = Instant::now();
    f();
    if first.elapsed() > budget {
        return first.elapsed();
    }
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

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let budget_ms: u64 = std::env::var("BENCH_BUDGET_MS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(500);
    let mut json = Vec::new();
    for name in STAGES {
        if filter.as_deref().is_some_and(|f| !name.contains(f)) {
            continue;
        }
        let stage = Stage::prepare(name).expect("stage input");
        let d = median(
            || {
                black_box(stage.run().expect("stage run"));
            },
            Duration::from_millis(budget_ms),
        );
        let us = d.as_secs_f64() * 1e6;
        println!("{name}\t{us:.3}");
        json.push(format!("  \"{name}\": {us:.3}"));
    }
    let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench-native.json");
    if let Err(e) = std::fs::write(&out, format!("{{\n{}\n}}\n", json.join(",\n"))) {
        eprintln!("could not write {}: {e}", out.display());
    }
}
