//! Shared helpers of the gap tests: the reference vectors of `tests/data/reference/` as a
//! [`GapInput`] (baseline = the 8 location-error columns of `sensitivity_physical.csv`,
//! candidates = the groups of `effect_signatures.csv`, metadata from `points.csv`).
#![allow(dead_code)]

mod table;
pub use table::Table;
use testpiece::effects::{GapInput, NamedColumns, PointMeta};
use testpiece::part::Surface;

pub const ERRORS: [&str; 8] = [
    "EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B",
];

pub fn reference_text(name: &str) -> String {
    let path = format!("{}/tests/data/reference/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

pub fn table(name: &str) -> Table {
    Table::parse(&reference_text(name)).unwrap()
}

/// Metadata of the 100 built-in points from points.csv and the `s` column of the signatures.
pub fn points() -> Vec<PointMeta> {
    let p = table("points.csv");
    let sig = table("effect_signatures.csv");
    let ids = p.numbers("id").unwrap();
    let curves = p.text("curve").unwrap();
    let u = p.numbers("u").unwrap();
    let h = p.numbers("h").unwrap();
    let nz = p.numbers("nz").unwrap();
    let s = sig.numbers("s").unwrap();
    let mut order: Vec<usize> = (0..ids.len()).collect();
    order.sort_by(|&a, &b| s[a].total_cmp(&s[b]));
    let mut rank = vec![0; ids.len()];
    for (k, &i) in order.iter().enumerate() {
        rank[i] = k;
    }
    (0..ids.len())
        .map(|i| PointMeta {
            id: ids[i] as u32,
            curve: curves[i].clone(),
            surface: if curves[i].starts_with('A') {
                Surface::A
            } else {
                Surface::B
            },
            u: u[i],
            h: h[i],
            s: s[i],
            order: rank[i],
            nz: nz[i],
        })
        .collect()
}

pub fn baseline() -> NamedColumns {
    table("sensitivity_physical.csv").columns(&ERRORS).unwrap()
}

/// The reference input with deviations `y` (no reversals, sigma estimated).
pub fn input(y: Vec<f64>) -> GapInput<'static> {
    GapInput {
        deviations: y,
        points: points().into(),
        baseline: std::borrow::Cow::Owned(baseline()),
        candidates: table("effect_signatures.csv").candidates().unwrap().into(),
        noise_sigma: None,
        reversals: Vec::new(),
    }
}

/// Deviations of an example part.
pub fn example(name: &str) -> Vec<f64> {
    table(&format!("examples/{name}.csv"))
        .numbers("deviation")
        .unwrap()
}

pub fn key(name: &str) -> serde_json::Value {
    serde_json::from_str(&reference_text(&format!("examples/{name}.key.json"))).unwrap()
}
