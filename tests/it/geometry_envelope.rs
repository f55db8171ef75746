//! Flank-path envelope against `tests/data/reference/envelope.csv` (deviation at the 100 points,
//! 1e-5 mm) and `envelope_surface_max.csv` (largest overcut per surface, 1e-4 mm); both from an
//! independent implementation (tests/data/reference/README.md).

use testpiece::part::{SShape, Surface};
use testpiece::tolerance::{ENVELOPE_MM, SURFACE_MAX_MM};
use testpiece::toolpath::{builtin_envelope, surface_max_overcut};

fn read(name: &str) -> Vec<csv::StringRecord> {
    let path = format!("{}/tests/data/reference/{name}", env!("CARGO_MANIFEST_DIR"));
    csv::Reader::from_path(path)
        .unwrap()
        .records()
        .map(Result::unwrap)
        .collect()
}

#[test]
fn envelope_at_the_points_matches_the_reference() {
    let dev = builtin_envelope(&SShape::iso()).unwrap();
    let rows = read("envelope.csv");
    assert_eq!(rows.len(), dev.len());
    let mut worst: f64 = 0.0;
    for (d, r) in dev.iter().zip(&rows) {
        assert_eq!(d.id.to_string(), &r[0]);
        assert_eq!(d.curve.name(), &r[1]);
        let want: f64 = r[2].parse().unwrap();
        worst = worst.max((d.deviation - want).abs());
    }
    println!("max |deviation - envelope.csv| = {worst:e} mm");
    assert!(worst <= ENVELOPE_MM, "{worst:e}");
    // s-shape.md: in [-0.0099, 0] at the points
    assert!(dev
        .iter()
        .all(|d| d.deviation <= 1e-12 && d.deviation > -0.0099));
}

#[test]
fn surface_max_overcut_matches_the_reference() {
    let part = SShape::iso();
    for r in read("envelope_surface_max.csv") {
        let s = if &r[0] == "A" { Surface::A } else { Surface::B };
        let m = surface_max_overcut(&part, s).unwrap();
        let want: Vec<f64> = (1..4).map(|i| r[i].parse().unwrap()).collect();
        println!(
            "surface {}: max overcut {} (ref {}, diff {:e}) mm at u = {} (ref {}), z = {} (ref {})",
            &r[0],
            m.max_overcut,
            want[0],
            m.max_overcut - want[0],
            m.u,
            want[1],
            m.z,
            want[2]
        );
        assert!((m.max_overcut - want[0]).abs() <= SURFACE_MAX_MM);
        assert!((m.u - want[1]).abs() < 1e-3);
        assert!((m.z - want[2]).abs() < 0.5);
    }
}

#[test]
fn no_sampled_point_overcuts_more_than_the_surface_maximum() {
    // Independent of the search: exact deviations on a 201 x 3 grid and around the reported
    // maximum never go below -max_overcut.
    use testpiece::toolpath::{FlankPath, TOOL_RADIUS};
    let part = SShape::iso();
    for s in Surface::BOTH {
        let m = surface_max_overcut(&part, s).unwrap();
        let path = FlankPath::new(&part, s);
        let mut lowest = f64::INFINITY;
        let grid = (0..=200).flat_map(|i| [0.0, 0.5, 1.0].map(|v| (i as f64 / 200.0, v)));
        let near = (-20..=20)
            .flat_map(|i| [0.0, 0.01, 0.05].map(|v| ((m.u + i as f64 * 1e-4).clamp(0.0, 1.0), v)));
        for (u, v) in grid.chain(near) {
            let d = path.deviation_at_uv(u, v, TOOL_RADIUS).unwrap().deviation;
            lowest = lowest.min(d);
        }
        println!(
            "surface {:?}: lowest sampled {lowest}, reported -{}",
            s, m.max_overcut
        );
        assert!(lowest >= -m.max_overcut - 1e-12);
        assert!(
            lowest <= -m.max_overcut + 1e-6,
            "the maximum is where the samples say"
        );
    }
}
