//! Scans read as scans (issue 31): a scanning CMM's file (`testpiece simulate --scan`: lines of
//! constant height on each surface, no id, no curve label) made with the exact eq. 12 defect of
//! the location errors ([`testpiece::simulate::simulate_at`]) plus an effect's signature or a
//! waviness along the tool path, diagnosed as the CLI and the page do ([`analyse_once`]). The
//! scans are 2 surfaces × 20 lines × 25 points (1,000 points, the benchmark's smallest), so the
//! tests stay quick in the debug build.

use testpiece::analysis::{analyse_once, AnalysisOptions};
use testpiece::cmm::write::{scan_csv, Precision};
use testpiece::effects::prepared::Prepared;
use testpiece::machine::AxisName;
use testpiece::parameter::{Effect, ParamId};
use testpiece::part::{Curve, MeasurementPoint, SShape, ScanLayout, Surface};
use testpiece::sensitivity::SensitivityOptions;
use testpiece::simulate::simulate_at;

const LAYOUT: ScanLayout = ScanLayout {
    heights: 20,
    rulings: 25,
};
/// The CMM noise of the scans (mm), as `simulate --noise 0.0015`.
const SIGMA: f64 = 0.0015;

/// What is added to the machine's part at each point: nothing, an effect's signature, or a
/// function of the tool-path length `s` (mm).
enum Extra {
    None,
    Effect(Effect, f64),
    Wave(fn(f64) -> f64),
}

/// The scan's file: the exact defect of EX0B = 0.01 mm and EA0B = 1e-4 rad, plus `extra`, plus
/// the noise (seed 7).
fn scan_file(extra: Extra) -> String {
    file_at(&LAYOUT.scan_points(&SShape::iso()), extra)
}

/// A scan along the rulings at staggered heights, as an optical scanner's cloud or a probe
/// sweeping each ruling from its own start: `rulings` rulings a surface at equal arc length of
/// the mid-height curve, each with `heights` points evenly over 3-27 mm shifted by its own
/// fraction of a step (the golden ratio's multiples), so that no two rulings share a height and
/// the heights form no lines.
fn staggered_points(heights: usize, rulings: usize) -> Vec<MeasurementPoint> {
    use testpiece::part::points::{arc_fraction, arc_length_table};
    let part = SShape::iso();
    let mut pts = Vec::with_capacity(2 * heights * rulings);
    for s in Surface::BOTH {
        let curve = Curve::ALL.into_iter().find(|c| c.surface() == s).unwrap();
        let table = arc_length_table(&part, s, 0.5);
        for r in 0..rulings {
            let u = table
                .param_at(arc_fraction(r, rulings) * table.total())
                .unwrap();
            let phase = (r as f64 * 0.618_033_988_749_895).fract();
            for k in 0..heights {
                let z = 3.0 + 24.0 * (k as f64 + phase) / heights as f64;
                pts.push(MeasurementPoint::at(
                    &part,
                    pts.len() + 1,
                    curve,
                    u,
                    z / 30.0,
                ));
            }
        }
    }
    pts
}

/// [`scan_file`] at the points `pts`.
fn file_at(pts: &[MeasurementPoint], extra: Extra) -> String {
    let part = SShape::iso();
    let opts = SensitivityOptions::default();
    let errors = [
        (ParamId::parse("EX0B").unwrap(), 0.01),
        (ParamId::parse("EA0B").unwrap(), 1e-4),
    ];
    let mut dev = simulate_at(&part, pts, &opts, &errors, SIGMA, 7).unwrap();
    let prepared = Prepared::new(part, opts).unwrap();
    let q = prepared.axis_values(pts).unwrap();
    let model = prepared.part_model(pts, &q).unwrap();
    let add: Vec<f64> = match extra {
        Extra::None => vec![0.0; pts.len()],
        Extra::Effect(e, v) => model.effect_deviation(&[(e, 0, v)]).unwrap(),
        Extra::Wave(f) => model.points.iter().map(|p| f(p.s)).collect(),
    };
    for (d, a) in dev.iter_mut().zip(add) {
        *d += a;
    }
    scan_csv(pts.iter().zip(dev), Precision::Decimals(6), None)
}

fn verdict(file: &str) -> (String, testpiece::analysis::Analysis) {
    let a = analyse_once(file.as_bytes(), "scan.csv", &AnalysisOptions::default()).unwrap();
    let r = a.diagnosis.report().expect("a diagnosis");
    (r.verdict.id().as_str().to_string(), a.clone())
}

#[test]
fn dense_scan_layout_is_read_from_the_data() {
    let (_, a) = verdict(&scan_file(Extra::None));
    let s = a.scan.as_ref().expect("read as a scan");
    assert_eq!(s.points, 1000);
    assert_eq!(s.lines_per_surface, vec![20, 20]);
    assert_eq!(s.points_per_line.min, 25.0);
    assert_eq!(s.points_per_line.max, 25.0);
    // 24 mm over 19 steps (part::scan); tolerance 1e-6 mm: the file's 6 decimals
    assert!(
        (s.line_step.median - 24.0 / 19.0).abs() < 1e-6,
        "{:?}",
        s.line_step
    );
    // the diagnosis groups by the 40 lines, not by the four measurement curves
    let r = a.diagnosis.report().unwrap();
    assert_eq!(r.layout.curves.len(), 40);
    assert!(r.layout.not_measured.is_empty());
}

#[test]
fn dense_scan_of_a_clean_part_is_none() {
    let (v, a) = verdict(&scan_file(Extra::None));
    assert_eq!(v, "none", "{}", a.diagnosis.report().unwrap().summary);
}

#[test]
fn dense_scan_with_c_backlash_is_backlash_c() {
    // b = 5e-4 rad (the reference example's size is 6e-4): visible well above the limit
    let (v, a) = verdict(&scan_file(Extra::Effect(
        "backlash_c".parse::<Effect>().unwrap(),
        5e-4,
    )));
    assert_eq!(v, "backlash_c", "{}", a.diagnosis.report().unwrap().summary);
}

/// A scan whose heights form no lines (staggered along the rulings, 2 × 25 × 24 = 1,200 points)
/// is read in height bands, not as one line a surface, and diagnosed as the scan of lines is:
/// clean `none`, a C backlash of 5e-4 rad `backlash_c`. The bands: √(n·Δz/L) = √(600 · 23.96 mm
/// / 587.5 mm) = 4.95, so 5 a surface of 120 points, with `L` 90 % of the mid-height curve's
/// length (`arc_length_table`; the reader estimates it from the points, within a few per cent).
/// Read as one line a surface, such a file of 20,000 points (`staggered_points(40, 250)`) had
/// withheld whole surfaces in its cross-validation and reported its lines 0.000 mm apart.
#[test]
fn a_scan_of_staggered_heights_is_read_in_height_bands() {
    let pts = staggered_points(24, 25);
    let (v, a) = verdict(&file_at(&pts, Extra::None));
    let s = a.scan.as_ref().expect("read as a scan");
    assert_eq!(s.banded, vec![Surface::A, Surface::B]);
    assert_eq!(s.lines_per_surface, vec![5, 5], "{s:?}");
    assert_eq!(
        (s.points_per_line.min, s.points_per_line.max),
        (120.0, 120.0)
    );
    let r = a.diagnosis.report().unwrap();
    assert!(r.summary.contains("5 height bands on A"), "{}", r.summary);
    assert_eq!(r.layout.curves.len(), 10);
    assert_eq!(v, "none", "{}", r.summary);
    let (v, a) = verdict(&file_at(
        &pts,
        Extra::Effect("backlash_c".parse::<Effect>().unwrap(), 5e-4),
    ));
    assert_eq!(v, "backlash_c", "{}", a.diagnosis.report().unwrap().summary);
}

#[test]
fn dense_scan_with_a_300_mm_wave_is_unexplained() {
    // 10 µm amplitude, 300 mm of tool path a period: no candidate of effects.md has this shape
    let (v, a) = verdict(&scan_file(Extra::Wave(|s| {
        0.010 * (2.0 * std::f64::consts::PI * s / 300.0).sin()
    })));
    assert_eq!(
        v,
        "unexplained",
        "{}",
        a.diagnosis.report().unwrap().summary
    );
}

/// What a scan's heights tell apart (issue 31 item 2), against the 100 built-in points, on the
/// same settings: the built-in points against themselves change nothing and leave exactly the
/// near-equivalent pairs the validation counts (`ValidationModel::near_equivalence`); the
/// special cases by construction are nested on every layout (`tool_radius` is `tool_taper`'s
/// `dR0` column, `c_index` is `setup_error`'s rotation on paper 000's C table: smallest
/// principal cosine 1 to 1e-9); and a 40 × 250 scan tells `backlash_z` from `backlash_b` where
/// the built-in points cannot (cosines 0.973 and 0.986, measured here, ± 0.002: the B axis's
/// reversals move the tool along its own axis's arc, Z's along z, and the heights see it).
#[test]
fn a_scan_reports_what_its_heights_tell_apart() {
    use testpiece::gap::separability::separability;
    let part = SShape::iso();
    let prepared = Prepared::new(part.clone(), SensitivityOptions::default()).unwrap();
    let builtin = prepared.builtin_model();
    let same = separability(builtin, builtin);
    assert!(
        same.told_apart.is_empty() && same.merged.is_empty(),
        "{same:?}"
    );
    let vm =
        testpiece::validate::ValidationModel::at(&part, &testpiece::part::builtin_points(&part))
            .unwrap();
    let near = vm.near_equivalence();
    for p in &same.neither {
        assert!(near(p.a, p.b), "{p:?}");
    }
    let pts = ScanLayout {
        heights: 40,
        rulings: 250,
    }
    .scan_points(&part);
    let q = prepared.axis_values(&pts).unwrap();
    let scan = separability(&prepared.part_model(&pts, &q).unwrap(), builtin);
    for (a, b) in [
        (Effect::ToolRadius, Effect::ToolTaper),
        (Effect::CIndex, Effect::SetupError),
    ] {
        let p = scan
            .neither
            .iter()
            .find(|p| p.a == a && p.b == b)
            .unwrap_or_else(|| panic!("{a:?} within {b:?}: {scan:?}"));
        assert!(p.nested && (p.here - 1.0).abs() < 1e-9, "{p:?}");
    }
    let zb = scan
        .told_apart
        .iter()
        .find(|p| [p.a, p.b] == [Effect::Backlash(AxisName::Z), Effect::Backlash(AxisName::B)])
        .unwrap_or_else(|| panic!("{scan:?}"));
    assert!(
        (zb.here - 0.973).abs() < 0.002 && (zb.builtin - 0.986).abs() < 0.002,
        "{zb:?}"
    );
}

/// The analysis of a scan says what its heights tell apart, in its JSON and in the summary the
/// CLI and the page show; a file of the built-in points says nothing of it.
#[test]
fn the_analysis_of_a_scan_carries_its_separability() {
    let (_, a) = verdict(&scan_file(Extra::None));
    let s = a.separability.as_ref().expect("a scan's separability");
    assert!(!s.neither.is_empty(), "{s:?}");
    let summary = &a.diagnosis.report().unwrap().summary;
    assert!(summary.contains("Separability: "), "{summary}");
    let example = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/reference/examples/example_clean.csv"
    ))
    .unwrap();
    let b = analyse_once(&example, "example_clean.csv", &AnalysisOptions::default()).unwrap();
    assert!(b.separability.is_none());
    assert!(!b
        .diagnosis
        .report()
        .unwrap()
        .summary
        .contains("Separability"));
}

/// The analysis on 1 and on 3 threads (the reading, the axis values, the part model, the outlier
/// test's and the diagnosis's candidates, the whiteness test's lags, the periodogram's lines and
/// the exact model's columns shared out, [`testpiece::numerics::parallel`]) gives the same result
/// bit for bit: the JSON of both is the same text (a scan with a C backlash, so the families'
/// scans, a verdict and a final fit with the effect all run).
#[test]
fn a_scan_is_analysed_the_same_on_any_number_of_threads() {
    use testpiece::numerics::parallel::Threads;
    let file = scan_file(Extra::Effect("backlash_c".parse::<Effect>().unwrap(), 5e-4));
    let on = |n: usize| {
        let opts = AnalysisOptions {
            threads: Threads::new(n),
            ..AnalysisOptions::default()
        };
        let a = analyse_once(file.as_bytes(), "scan.csv", &opts).unwrap();
        serde_json::to_string(&a).unwrap()
    };
    let one = on(1);
    assert!(one.contains("backlash_c"));
    assert!(one == on(3), "the analysis on 3 threads differs from 1");
}

/// A scan's rows are split and converted in chunks of 4,096 side by side (issue 31): on 3
/// threads the file reads as on one, point for point (ids generated from the row's position,
/// lines) and bad row for bad row, with bad rows in the first, second and third chunk and the
/// 10,000 rows of a 2 × 50 × 100 scan (`exclude_bad_rows`, so that they are reported).
#[test]
fn a_scan_reads_the_same_in_chunks_on_any_threads() {
    use testpiece::cmm::{read_cmm_with, ReadOptions};
    use testpiece::numerics::parallel::Threads;
    let part = SShape::iso();
    let pts = ScanLayout {
        heights: 50,
        rulings: 100,
    }
    .scan_points(&part);
    let file = scan_csv(pts.iter().map(|p| (p, 0.001)), Precision::Decimals(6), None);
    // three rows made bad: a letter in a number (data rows 10, 5000 and 9000)
    let mut lines: Vec<String> = file.lines().map(String::from).collect();
    let header = lines.iter().position(|l| l.starts_with("x,")).unwrap();
    for row in [10, 5000, 9000] {
        lines[header + 1 + row] = lines[header + 1 + row].replacen('.', "q", 1);
    }
    let bytes = lines.join("\n").into_bytes();
    let opts = ReadOptions::default().with_exclude_bad_rows(true);
    let one = read_cmm_with(&bytes, "scan.csv", &opts.clone().with_threads(Threads::ONE)).unwrap();
    let three = read_cmm_with(&bytes, "scan.csv", &opts.with_threads(Threads::new(3))).unwrap();
    assert_eq!(one.points.len(), 9997);
    assert_eq!(one.excluded.len(), 3);
    assert_eq!(one, three);
    // the generated ids count the data rows, bad ones included
    assert_eq!(three.points[9996].id, "10000");
}
