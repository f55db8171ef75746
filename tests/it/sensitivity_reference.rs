//! Machined defect (paper 000 eq. 12-14) against the reference vectors of
//! tests/data/reference/ (independent implementation; README there): the axis path
//! (machine_path.csv), the Figure-19 sensitivity matrices in both modes and both branches, and
//! the Table-4 check (table4_paper.csv, linear and exact).

use testpiece::machine::{Branch, ErrorParam, LocationError, MachineErrors};
use testpiece::part::{builtin_points, SShape, Surface};
use testpiece::sensitivity::{
    defect, linear_defect, machine_path, sensitivity_matrix, Mode, SensitivityOptions,
};
use testpiece::tolerance::SENSITIVITY_REL;

fn data(name: &str) -> String {
    format!("{}/tests/data/reference/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn read(name: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut rdr = csv::Reader::from_path(data(name)).unwrap();
    let h = rdr.headers().unwrap().iter().map(String::from).collect();
    let rows = rdr
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (h, rows)
}

#[test]
fn axis_path_matches_machine_path_csv() {
    let part = SShape::iso();
    let opts = SensitivityOptions::default();
    let (_, rows) = read("machine_path.csv");
    let mut worst = [0.0f64; 5];
    for s in Surface::BOTH {
        let sel: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == s.name()).collect();
        let us: Vec<f64> = sel.iter().map(|r| r[1].parse().unwrap()).collect();
        let path = machine_path(&part, &opts.chain, s, Branch::Signed, &us).unwrap();
        for (r, p) in sel.iter().zip(&path) {
            let want: Vec<f64> = r[2..7].iter().map(|x| x.parse().unwrap()).collect();
            let got = [p.values.x, p.values.y, p.values.z, p.values.b, p.values.c];
            for k in 0..5 {
                worst[k] = worst[k].max((got[k] - want[k]).abs());
            }
        }
    }
    eprintln!("machine_path.csv max |diff| X,Y,Z (mm), B,C (rad): {worst:?}");
    for (k, w) in worst.iter().enumerate() {
        assert!(*w < 1e-9, "axis {k}: {w:e}");
    }
}

fn check_matrix(file: &str, mode: Mode, branch: Branch) {
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let opts = SensitivityOptions::default()
        .with_mode(mode)
        .with_branch(branch);
    let m = sensitivity_matrix(
        &part,
        &pts,
        &testpiece::sensitivity::axis_values(&part, &pts, &opts).unwrap(),
        &opts,
        &testpiece::sensitivity::error_set::error_set(&opts.chain, opts.branch)
            .unwrap()
            .params(),
    )
    .unwrap();
    let (h, rows) = read(file);
    assert_eq!(&h[2..], m.names().as_slice());
    assert_eq!(rows.len(), m.values.nrows());
    let mut worst: f64 = 0.0;
    for k in 0..8 {
        let col: Vec<f64> = rows.iter().map(|r| r[k + 2].parse().unwrap()).collect();
        let scale = col.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (i, want) in col.iter().enumerate() {
            assert_eq!(rows[i][0].parse::<usize>().unwrap(), m.ids[i]);
            assert_eq!(rows[i][1], m.curves[i]);
            let rel = (m.values[(i, k)] - want).abs() / scale;
            worst = worst.max(rel);
            assert!(
                rel <= SENSITIVITY_REL,
                "{file} point {} {}: {} vs {want} (rel {rel:e})",
                m.ids[i],
                m.names()[k],
                m.values[(i, k)]
            );
        }
    }
    eprintln!("{file}: max relative difference {worst:e} (of each column's largest value)");
}

#[test]
fn sensitivity_physical_signed() {
    check_matrix("sensitivity_physical.csv", Mode::Physical, Branch::Signed);
}

#[test]
fn sensitivity_paper_signed() {
    check_matrix("sensitivity_paper.csv", Mode::Paper, Branch::Signed);
}

#[test]
fn sensitivity_paper_positive() {
    check_matrix(
        "sensitivity_paper_bpositive.csv",
        Mode::Paper,
        Branch::Positive,
    );
}

#[test]
fn sensitivity_physical_positive() {
    check_matrix(
        "sensitivity_physical_bpositive.csv",
        Mode::Physical,
        Branch::Positive,
    );
}

/// Paper 000 Table 4's errors: EX0B = 0.0294 mm, EA0B = 3.2419e-4 rad.
fn table4_errors() -> MachineErrors {
    MachineErrors::none()
        .with(
            ErrorParam::Location(LocationError::parse("EX0B").unwrap()),
            0.0294,
        )
        .with(
            ErrorParam::Location(LocationError::parse("EA0B").unwrap()),
            3.2419e-4,
        )
}

#[test]
fn table4_linear_and_exact() {
    // Paper 000 Table 4 values EX0B = 0.0294 mm, EA0B = 3.2419e-4 rad, paper mode, signed B.
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let opts = SensitivityOptions::default().with_mode(Mode::Paper);
    let e = table4_errors();
    let lin = linear_defect(&part, &pts, &e, &opts).unwrap();
    let exact = defect(&part, &pts, &e, &opts).unwrap();
    let (h, rows) = read("table4_paper.csv");
    let col = |n: &str| h.iter().position(|x| x == n).unwrap();
    let (mut wl, mut we) = (0.0f64, 0.0f64);
    for (i, r) in rows.iter().enumerate() {
        wl = wl.max((lin[i] - r[col("machine_linear")].parse::<f64>().unwrap()).abs());
        we = we.max((exact[i] - r[col("machine_exact")].parse::<f64>().unwrap()).abs());
    }
    eprintln!("table4_paper.csv: max |diff| linear {wl:e} mm, exact {we:e} mm");
    // 1e-6 of the 0.2 mm range.
    assert!(wl < 2e-7 && we < 2e-7, "linear {wl:e}, exact {we:e}");
}

#[test]
fn exact_and_linear_defect_agree_to_first_order_in_both_modes() {
    // s-shape.md: exact eq. 12 and its linearisation differ by < 0.1 µm at |ξ| = 3e-4 rad,
    // EX0B = 0.03 mm (the second-order terms, |ξ|²·L0 ≈ 5e-5 mm at most).
    let part = SShape::iso();
    let pts = builtin_points(&part);
    let xi = [3e-4, -3e-4, 2e-4, -1e-4, 3e-4, 0.03, -3e-4, 2.5e-4];
    for mode in [Mode::Physical, Mode::Paper] {
        let opts = SensitivityOptions::default().with_mode(mode);
        let params = testpiece::sensitivity::error_set::error_set(&opts.chain, opts.branch)
            .unwrap()
            .params();
        let exact = testpiece::sensitivity::defect_xi(&part, &pts, &xi, &params, &opts).unwrap();
        let m = sensitivity_matrix(
            &part,
            &pts,
            &testpiece::sensitivity::axis_values(&part, &pts, &opts).unwrap(),
            &opts,
            &testpiece::sensitivity::error_set::error_set(&opts.chain, opts.branch)
                .unwrap()
                .params(),
        )
        .unwrap();
        let lin = &m.values * nalgebra::DVector::from_row_slice(&xi);
        let worst = exact
            .iter()
            .zip(lin.iter())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        eprintln!("{mode:?}: max |exact - linear| = {worst:e} mm");
        assert!(worst < 1e-4, "{mode:?}: {worst:e}");
    }
    let opts = SensitivityOptions::default();
    let params = testpiece::sensitivity::error_set::error_set(&opts.chain, opts.branch)
        .unwrap()
        .params();
    assert!(testpiece::sensitivity::defect_xi(
        &part,
        &pts,
        &xi[..3],
        &params,
        &SensitivityOptions::default()
    )
    .is_err());
}

/// Eq. 12 at 3,000 points (the built-in 100, thirty times: two blocks of 2,048 and more) and
/// their axis values are the same bit for bit on 1 and on 2 threads: the points are shared out
/// in blocks, each point computed by the same code (issue 31).
#[test]
fn the_exact_defect_is_the_same_on_two_threads() {
    use testpiece::numerics::parallel::Threads;
    use testpiece::sensitivity::axis_values_on;
    use testpiece::sensitivity::defect::DefectPoses;
    let part = SShape::iso();
    let pts: Vec<_> = (0..30).flat_map(|_| builtin_points(&part)).collect();
    let opts = SensitivityOptions::default();
    let q = axis_values_on(&part, &pts, &opts, Threads::ONE).unwrap();
    assert_eq!(
        q,
        axis_values_on(&part, &pts, &opts, Threads::new(2)).unwrap()
    );
    let e = table4_errors();
    let bits = |threads| -> Vec<u64> {
        DefectPoses::on(&part, &pts, &q, &opts, threads)
            .unwrap()
            .defect(&e)
            .unwrap()
            .iter()
            .map(|v| v.to_bits())
            .collect()
    };
    let one = bits(Threads::ONE);
    assert_eq!(one.len(), 3000);
    assert_eq!(one, bits(Threads::new(2)));
}
