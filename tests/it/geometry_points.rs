//! The 100 built-in points against `tests/data/reference/points.csv` (an independent
//! implementation of the spec, see tests/data/reference/README.md): points, normals, u, v, h.

use testpiece::part::{builtin_points, SShape};
use testpiece::tolerance::POINTS_MM;

fn reference() -> Vec<Vec<String>> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/reference/points.csv"
    );
    let mut r = csv::Reader::from_path(path).unwrap();
    r.records()
        .map(|rec| rec.unwrap().iter().map(str::to_string).collect())
        .collect()
}

#[test]
fn builtin_points_match_the_reference() {
    let pts = builtin_points(&SShape::iso());
    let rows = reference();
    assert_eq!(rows.len(), 100);
    let mut worst = [0.0f64; 4]; // point (mm), normal, u/v, h (mm)
    for (p, row) in pts.iter().zip(&rows) {
        let f: Vec<f64> = row.iter().skip(2).map(|x| x.parse().unwrap()).collect();
        assert_eq!(p.id.to_string(), row[0]);
        assert_eq!(p.curve.name(), row[1]);
        let (u, v, x, y, z, nx, ny, nz, h) = (f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8]);
        worst[0] = worst[0].max((p.point - nalgebra::Vector3::new(x, y, z)).amax());
        worst[1] = worst[1].max((p.normal - nalgebra::Vector3::new(nx, ny, nz)).amax());
        worst[2] = worst[2].max((p.u - u).abs().max((p.v - v).abs()));
        worst[3] = worst[3].max((p.h - h).abs());
    }
    println!(
        "max |diff| vs points.csv: point {:.3e} mm, normal {:.3e}, u/v {:.3e}, h {:.3e} mm",
        worst[0], worst[1], worst[2], worst[3]
    );
    for w in worst {
        assert!(w <= POINTS_MM, "{worst:?}");
    }
}
