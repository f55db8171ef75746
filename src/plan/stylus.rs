//! The orientation of the probe's stylus: an indexable probe head (steps of
//! [`INDEX_STEP_DEG`] in tilt and azimuth, as a Renishaw PH10-type head) turns the stylus so
//! that its shaft does not meet the wall above the touch.
//!
//! The walls of the S-shape overhang in places (the outward normal points down by up to about
//! 14°, `N.z` ≈ −0.24): there a vertical stylus touching at Z = 11 mm would meet the wall
//! higher up. The shaft clears a wall above the touch when it leans away from it or runs
//! parallel to it, `w·N ≥ 0` (`w` the unit vector from the tip centre up the stylus to the
//! head; the walls are ruled surfaces whose rulings are ⊥ `N`). Rule: vertical (`w` = +Z)
//! where `N.z ≥ 0`; elsewhere the smallest tilt on the grid, then the azimuth nearest to `N`'s,
//! for which `w·N ≥` [`LEAN_AWAY`]. Angles in degrees: tilt from +Z, azimuth about +Z from +X.

use nalgebra::Vector3;
use serde::Serialize;

/// The head's indexing step (degrees).
pub const INDEX_STEP_DEG: f64 = 7.5;
/// Largest tilt of the head (degrees).
pub const MAX_TILT_DEG: f64 = 105.0;
/// The least `w·N` of a tilted stylus: it leans away from the wall.
pub const LEAN_AWAY: f64 = 0.02;

/// One indexed orientation of the stylus (degrees, multiples of [`INDEX_STEP_DEG`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stylus {
    pub tilt_deg: f64,
    pub azimuth_deg: f64,
}

impl Stylus {
    pub const VERTICAL: Stylus = Stylus {
        tilt_deg: 0.0,
        azimuth_deg: 0.0,
    };

    /// `w`: the unit vector from the tip centre up the stylus.
    pub fn direction(&self) -> Vector3<f64> {
        let (t, a) = (self.tilt_deg.to_radians(), self.azimuth_deg.to_radians());
        Vector3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos())
    }

    /// The DMIS label of the sensor: `A<tilt in 0.1°>B<azimuth + 180 in 0.1°>`, e.g.
    /// `A150B1725` for tilt 15°, azimuth −7.5°.
    pub fn label(&self) -> String {
        format!(
            "A{:03}B{:04}",
            (self.tilt_deg * 10.0).round() as i64,
            ((self.azimuth_deg + 180.0) * 10.0).round() as i64
        )
    }

    /// The orientation for a touch along `−normal` (module docs).
    pub fn for_normal(normal: &Vector3<f64>) -> Stylus {
        if normal.z >= 0.0 {
            return Stylus::VERTICAL;
        }
        let az = normal.y.atan2(normal.x).to_degrees();
        let steps = (MAX_TILT_DEG / INDEX_STEP_DEG).round() as i64;
        for k in 1..=steps {
            let tilt_deg = k as f64 * INDEX_STEP_DEG;
            let near = (az / INDEX_STEP_DEG).round() * INDEX_STEP_DEG;
            for d in [0.0, -INDEX_STEP_DEG, INDEX_STEP_DEG] {
                let mut azimuth_deg = near + d;
                if azimuth_deg >= 180.0 {
                    azimuth_deg -= 360.0;
                }
                let s = Stylus {
                    tilt_deg,
                    azimuth_deg,
                };
                if s.direction().dot(normal) >= LEAN_AWAY {
                    return s;
                }
            }
        }
        Stylus {
            tilt_deg: 90.0,
            azimuth_deg: (az / INDEX_STEP_DEG).round() * INDEX_STEP_DEG,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_overhang_tilts_the_stylus_away_from_the_wall() {
        let n = Vector3::new(0.6, 0.77, -0.22).normalize();
        let s = Stylus::for_normal(&n);
        assert_eq!(s.tilt_deg, 15.0);
        assert!(s.direction().dot(&n) >= LEAN_AWAY);
        assert_eq!(
            Stylus::for_normal(&Vector3::new(1.0, 0.0, 0.1)),
            Stylus::VERTICAL
        );
        assert_eq!(Stylus::VERTICAL.label(), "A000B1800");
    }
}
