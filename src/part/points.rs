//! The 100 built-in measurement points of the S-shape (`shared/spec/s-shape.md`, "Measurement
//! points"; paper 000 §2.1, Fig. 4: four curves at Z = 11 and 25 mm on surfaces A and B).
//!
//! The ISO point list is not public; testpiece's layout: 25 points per curve at equal arc length
//! of the curve `S(·, v)`, `v = Z/30`, at fractions `5 % + k·90 %/24` (k = 0…24) of its length, in
//! increasing `u`. Ids 1-25 `A_Z11`, 26-50 `A_Z25`, 51-75 `B_Z11`, 76-100 `B_Z25`.
//! Each point carries its outward normal `N(u,v)` and its contact height `h` above the flank
//! tool's tip (`h = 35 - (1-v)|C1(u) - C0(u)|`, eq. 2). Units: mm.

use std::fmt;
use std::str::FromStr;

use nalgebra::Vector3;
use serde::ser::SerializeStruct;
use serde::Serialize;

use super::flat::Flat;
use super::s_shape::{SShape, Surface, HEIGHT};
use crate::geometry::{ArcLength, BSplineCurve, GeometryError};
use crate::part::ruled::contact_height;

/// Points per measurement curve.
pub const POINTS_PER_CURVE: usize = 25;
/// First and last arc-length fraction of the points on a curve.
pub const ARC_FRACTION_RANGE: (f64, f64) = (0.05, 0.95);

/// One of the four measurement curves, in id order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Curve {
    AZ11,
    AZ25,
    BZ11,
    BZ25,
}

impl Curve {
    /// The curves in id order (ids 1-25, 26-50, 51-75, 76-100).
    pub const ALL: [Curve; 4] = [Curve::AZ11, Curve::AZ25, Curve::BZ11, Curve::BZ25];

    /// `A_Z11`, `A_Z25`, `B_Z11`, `B_Z25`.
    pub fn name(self) -> &'static str {
        match self {
            Curve::AZ11 => "A_Z11",
            Curve::AZ25 => "A_Z25",
            Curve::BZ11 => "B_Z11",
            Curve::BZ25 => "B_Z25",
        }
    }
    pub fn surface(self) -> Surface {
        match self {
            Curve::AZ11 | Curve::AZ25 => Surface::A,
            Curve::BZ11 | Curve::BZ25 => Surface::B,
        }
    }
    /// Height of the curve (mm).
    pub fn z(self) -> f64 {
        match self {
            Curve::AZ11 | Curve::BZ11 => 11.0,
            Curve::AZ25 | Curve::BZ25 => 25.0,
        }
    }
    /// `v = z/30`.
    pub fn v(self) -> f64 {
        self.z() / HEIGHT
    }
    /// Position in [`Curve::ALL`] (0-3).
    pub fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for Curve {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Curve {
    type Err = GeometryError;
    /// Parses `A_Z11` etc. (case-insensitive).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Curve::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| GeometryError::UnknownCurve {
                name: s.to_string(),
            })
    }
}

impl Serialize for Curve {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// A nominal measurement point with its frame data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasurementPoint {
    /// 1-100
    pub id: usize,
    pub curve: Curve,
    pub surface: Surface,
    /// Surface parameters of the point, `v = z/30`
    pub u: f64,
    pub v: f64,
    /// `S(u,v)` (mm)
    pub point: Vector3<f64>,
    /// Outward unit normal `N(u,v)`
    pub normal: Vector3<f64>,
    /// Contact height above the flank tool's tip along its axis (mm)
    pub h: f64,
}

/// Serialises flat, with the columns of `testpiece points`:
/// `id, curve, surface, u, v, x, y, z, nx, ny, nz, h`.
impl Serialize for MeasurementPoint {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("MeasurementPoint", 12)?;
        st.serialize_field("id", &self.id)?;
        st.serialize_field("curve", &self.curve)?;
        st.serialize_field("surface", &self.surface)?;
        self.flat().write_fields(&mut st)?;
        st.end()
    }
}

impl MeasurementPoint {
    /// The geometry columns shared with every part's points.
    pub fn flat(&self) -> Flat<'_> {
        Flat {
            u: self.u,
            v: self.v,
            point: &self.point,
            normal: &self.normal,
            h: self.h,
        }
    }

    /// The point of surface `s` at `(u, v)`, with its normal and contact height.
    pub fn at(part: &SShape, id: usize, curve: Curve, u: f64, v: f64) -> Self {
        let s = curve.surface();
        let f = part.frame_at(s, u, v);
        Self {
            id,
            curve,
            surface: s,
            u,
            v,
            point: f.point,
            normal: f.n,
            h: contact_height(part, s, u, v),
        }
    }
}

/// The arc-length table of the curve `S(·, v)` of surface `s` (per knot span, 8 Gauss pieces).
pub fn arc_length_table(part: &SShape, s: Surface, v: f64) -> ArcLength<impl Fn(f64) -> f64 + '_> {
    let [c0, c1] = part.curves(s);
    // |S_u(u, v)| from the hodograph of the curve S(·, v) = (1-v)·C0 + v·C1 (one degree-2
    // basis evaluation per call; the same speed as the two curves' derivatives, to rounding).
    let hodograph = (c0.knots() == c1.knots() && c0.degree() == c1.degree())
        .then(|| {
            let blend = c0
                .control_points()
                .iter()
                .zip(c1.control_points())
                .map(|(p0, p1)| p0 * (1.0 - v) + p1 * v)
                .collect();
            BSplineCurve::try_new(c0.degree(), c0.knots().to_vec(), blend).ok()
        })
        .flatten()
        .filter(|_| c0.weights().iter().chain(c1.weights()).all(|w| *w == 1.0))
        .and_then(|c| c.hodograph());
    let speed = move |u: f64| match &hodograph {
        Some(h) => h.point_at(u).norm(),
        None => (c0.derivs_at(u).d1 * (1.0 - v) + c1.derivs_at(u).d1 * v).norm(),
    };
    ArcLength::new(speed, c0.knots(), 8)
}

/// The 25 points of one curve, ids starting at `first_id`.
pub fn curve_points(part: &SShape, curve: Curve, first_id: usize) -> Vec<MeasurementPoint> {
    curve_points_n(part, curve, first_id, POINTS_PER_CURVE)
}

/// The arc-length fraction of point `k` of `n` on a curve: `5 % + k·90 %/(n − 1)` (the
/// built-in layout's range), or 50 % for a single point.
pub fn arc_fraction(k: usize, n: usize) -> f64 {
    evenly(k, n, ARC_FRACTION_RANGE)
}

/// Value `k` of `n` spread evenly over `(a, b)`, ends included; the middle for one.
pub fn evenly(k: usize, n: usize, (a, b): (f64, f64)) -> f64 {
    if n <= 1 {
        0.5 * (a + b)
    } else {
        a + (b - a) * k as f64 / (n - 1) as f64
    }
}

/// `count` points of one curve at equal arc length over the built-in layout's range of the
/// curve ([`arc_fraction`]; another layout than the standard's 25, for a measurement plan or a
/// validation), ids starting at `first_id`.
pub fn curve_points_n(
    part: &SShape,
    curve: Curve,
    first_id: usize,
    count: usize,
) -> Vec<MeasurementPoint> {
    let v = curve.v();
    let table = arc_length_table(part, curve.surface(), v);
    (0..count)
        .map(|k| {
            let frac = arc_fraction(k, count);
            // The fraction is inside [0, 1], so the length is in range: param_at cannot fail.
            let u = table
                .param_at(frac * table.total())
                .unwrap_or(frac)
                .clamp(0.0, 1.0);
            MeasurementPoint::at(part, first_id + k, curve, u, v)
        })
        .collect()
}

/// The 100 built-in points in id order (s-shape.md).
pub fn builtin_points(part: &SShape) -> Vec<MeasurementPoint> {
    Curve::ALL
        .into_iter()
        .flat_map(|c| curve_points(part, c, 1 + c.index() * POINTS_PER_CURVE))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn ids_curves_and_spacing() {
        let part = SShape::iso();
        let pts = builtin_points(&part);
        assert_eq!(pts.len(), 100);
        for (i, p) in pts.iter().enumerate() {
            assert_eq!(p.id, i + 1);
            assert_eq!(p.curve, Curve::ALL[i / 25]);
            assert_near!(p.point.z, p.curve.z(), 1e-12);
        }
        // equal arc length: consecutive points are 0.9/24 of the curve apart along it
        for c in Curve::ALL {
            let t = arc_length_table(&part, c.surface(), c.v());
            let on: Vec<_> = pts.iter().filter(|p| p.curve == c).collect();
            for w in on.windows(2) {
                assert!(w[1].u > w[0].u);
                let d = t.length_at(w[1].u) - t.length_at(w[0].u);
                assert_near!(d, t.total() * 0.9 / 24.0, 1e-9);
            }
        }
    }

    #[test]
    fn curve_names_round_trip() {
        for c in Curve::ALL {
            assert_eq!(c.name().parse::<Curve>().unwrap(), c);
            assert_eq!(c.to_string(), c.name());
        }
        assert_eq!(
            "C_Z3".parse::<Curve>().unwrap_err().to_string(),
            "unknown measurement curve `C_Z3` (expected A_Z11, A_Z25, B_Z11 or B_Z25)"
        );
    }
}
