//! A scanning CMM's layout of the S-shape: each flank scanned along lines of constant height
//! (`z`), each line sampled at equal arc length of the curve `S(·, v)`, `v = z/30`, over the
//! built-in layout's range (5 %-95 % of the curve, [`super::points::arc_fraction`]). Surface A's
//! lines first, bottom to top, each in increasing `u`; then surface B's. Units: mm.
//!
//! The heights are spread evenly over [`SCAN_Z_RANGE`] (3-27 mm: clear of the part's floor and
//! top edge, as a stylus of 1-3 mm radius leaves them); each point is labelled with the nearer
//! measurement curve only because [`MeasurementPoint`] carries one: a scan file written from
//! them has no curve label and no id ([`crate::cmm::write::scan_csv`]).

use super::points::{arc_fraction, arc_length_table, evenly, Curve, MeasurementPoint};
use super::s_shape::{SShape, Surface, HEIGHT};

/// Lowest and highest scanned height (mm).
pub const SCAN_Z_RANGE: (f64, f64) = (3.0, 27.0);

/// A scan layout: lines of constant height on each surface, points per line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScanLayout {
    /// Scan lines on each surface (heights), ≥ 1.
    pub heights: usize,
    /// Points on each line (rulings), ≥ 1.
    pub rulings: usize,
}

impl ScanLayout {
    /// Points of the whole scan: 2 surfaces × heights × rulings.
    pub fn points(&self) -> usize {
        2 * self.heights * self.rulings
    }

    /// Height of line `k` of `n` (mm): evenly over [`SCAN_Z_RANGE`], the middle for one line.
    pub fn height(k: usize, n: usize) -> f64 {
        evenly(k, n, SCAN_Z_RANGE)
    }

    /// The points of the scan in scan order, ids 1, 2, … in that order.
    pub fn scan_points(&self, part: &SShape) -> Vec<MeasurementPoint> {
        let mut out = Vec::with_capacity(self.points());
        for s in [Surface::A, Surface::B] {
            for k in 0..self.heights {
                let z = Self::height(k, self.heights);
                let v = z / HEIGHT;
                let curve = nearer_curve(s, z);
                let table = arc_length_table(part, s, v);
                for r in 0..self.rulings {
                    let frac = arc_fraction(r, self.rulings);
                    // inside [0, 1], so the length is in range: param_at cannot fail
                    let u = table
                        .param_at(frac * table.total())
                        .unwrap_or(frac)
                        .clamp(0.0, 1.0);
                    out.push(MeasurementPoint::at(part, out.len() + 1, curve, u, v));
                }
            }
        }
        out
    }
}

/// The measurement curve of surface `s` nearer to height `z` (mm).
fn nearer_curve(s: Surface, z: f64) -> Curve {
    let on: Vec<Curve> = Curve::ALL
        .into_iter()
        .filter(|c| c.surface() == s)
        .collect();
    if (on[0].z() - z).abs() <= (on[1].z() - z).abs() {
        on[0]
    } else {
        on[1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn dense_scan_lines_lie_at_their_heights_in_scan_order() {
        let part = SShape::iso();
        let l = ScanLayout {
            heights: 5,
            rulings: 7,
        };
        let pts = l.scan_points(&part);
        assert_eq!(pts.len(), 70);
        for (i, p) in pts.iter().enumerate() {
            let line = i / 7;
            let z = ScanLayout::height(line % 5, 5);
            // tolerance: 1e-9 mm, the surface evaluation's rounding at v = z/30
            assert_near!(p.point.z, z, 1e-9);
            assert_eq!(p.surface, if line < 5 { Surface::A } else { Surface::B });
            if i % 7 > 0 {
                assert!(p.u > pts[i - 1].u, "point {i}");
            }
        }
        assert_eq!(ScanLayout::height(0, 40), 3.0);
        assert_eq!(ScanLayout::height(39, 40), 27.0);
    }
}
