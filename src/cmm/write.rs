//! Writing a measured part in the canonical CMM format of `shared/spec/cmm-csv.md`:
//! `id,curve,x,y,z,nx,ny,nz,deviation` (mm; deviation = (measured − nominal)·N, + = material
//! left), optionally after `#` comment lines. The reader ([`super::read_and_match`]) reads it
//! back exactly when the numbers are written [`Precision::Shortest`].

use std::fmt::Write;

use crate::part::MeasurementPoint;

/// The header row of the canonical format.
pub const CANONICAL_HEADER: &str = "id,curve,x,y,z,nx,ny,nz,deviation";

/// How the numbers are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// Rust's shortest form that reads back to the same `f64` (no rounding).
    Shortest,
    /// A fixed number of decimals (mm), as a CMM export would round.
    Decimals(usize),
}

/// The canonical CSV of `rows` (a point and its deviation, mm), each line of `comment` written
/// first as a `# ` comment line.
pub fn canonical_csv<'a>(
    rows: impl IntoIterator<Item = (&'a MeasurementPoint, f64)>,
    precision: Precision,
    comment: Option<&str>,
) -> String {
    let mut s = header(CANONICAL_HEADER, comment);
    for (p, d) in rows {
        // Writing to a String cannot fail.
        let _ = write!(s, "{},{},", p.id, p.curve.name());
        row(&mut s, p, d, precision);
    }
    s
}

/// The `# ` comment lines of `comment`, then the header row `names`.
fn header(names: &str, comment: Option<&str>) -> String {
    let mut s = String::new();
    for line in comment.into_iter().flat_map(str::lines) {
        s.push_str("# ");
        s.push_str(line);
        s.push('\n');
    }
    s.push_str(names);
    s.push('\n');
    s
}

/// `x,y,z,nx,ny,nz,deviation` of one point and its line end.
fn row(s: &mut String, p: &MeasurementPoint, d: f64, precision: Precision) {
    let values = [
        p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z, d,
    ];
    for (k, v) in values.into_iter().enumerate() {
        let sep = if k == 0 { "" } else { "," };
        // Writing to a String cannot fail.
        let _ = match precision {
            Precision::Shortest => write!(s, "{sep}{v}"),
            Precision::Decimals(n) => write!(s, "{sep}{v:.n$}"),
        };
    }
    s.push('\n');
}

/// The header row of a scan ([`scan_csv`]): no id, no curve label.
pub const SCAN_HEADER: &str = "x,y,z,nx,ny,nz,deviation";

/// A scan as a scanning CMM exports it: `x,y,z,nx,ny,nz,deviation` per point in scan order
/// (mm), no point id and no curve label, each line of `comment` written first as a `# ` line.
pub fn scan_csv<'a>(
    rows: impl IntoIterator<Item = (&'a MeasurementPoint, f64)>,
    precision: Precision,
    comment: Option<&str>,
) -> String {
    let mut s = header(SCAN_HEADER, comment);
    for (p, d) in rows {
        row(&mut s, p, d, precision);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cmm::{read_and_match, ReadOptions};
    use crate::part::{builtin_points, SShape};

    #[test]
    fn the_shortest_form_reads_back_bit_for_bit() {
        let part = SShape::iso();
        let pts = builtin_points(&part);
        let dev: Vec<f64> = (0..pts.len()).map(|i| 1e-3 * (i as f64).sin()).collect();
        let text = canonical_csv(
            pts.iter().zip(dev.iter().copied()),
            Precision::Shortest,
            Some("synthetic\ntwo lines"),
        );
        assert!(text.starts_with("# synthetic\n# two lines\nid,curve,"));
        let m = read_and_match(text.as_bytes(), "w.csv", &ReadOptions::default()).unwrap();
        assert_eq!(m.points.len(), 100);
        for (q, d) in m.points.iter().zip(&dev) {
            // tolerance: none (the shortest round-trip form is exact)
            assert_eq!(q.deviation.to_bits(), d.to_bits(), "point {}", q.file.id);
        }
    }

    #[test]
    fn fixed_decimals_round_each_number() {
        let pts = builtin_points(&SShape::iso());
        let text = canonical_csv([(&pts[0], 0.0012345)], Precision::Decimals(6), None);
        let row = text.lines().nth(1).unwrap();
        assert!(
            row.ends_with(",0.001235") || row.ends_with(",0.001234"),
            "{row}"
        );
        assert_eq!(row.split(',').count(), 9);
    }
}
