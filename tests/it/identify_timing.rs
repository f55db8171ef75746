//! Wall time of one identification of a 100-point part (not a timed test: run with
//! `cargo test --release --test it identify_timing:: -- --ignored --nocapture`; issue 5 asks < 5 ms).

use crate::identify_common::*;
use std::time::Instant;
use testpiece::identify::*;

#[test]
#[ignore]
fn identify_100_points_wall_time() {
    let d = design("physical").with_tool_radius().unwrap();
    let obs = observations("examples/example_tool_radius.csv", "deviation");
    let opts = IdentifyOptions::default();
    let mut times = Vec::new();
    for _ in 0..200 {
        let t = Instant::now();
        std::hint::black_box(identify(&d, &obs, &opts).unwrap());
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    println!(
        "identify (100 points x 9 parameters): median {:.3} ms",
        times[100]
    );
}
