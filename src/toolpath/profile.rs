//! Tool rotation profile: the radius of the rotating tool as a function of height along its axis
//! (paper 001 §2, Fig. 3, Table 2), including the tool setup error.
//!
//! - **Dimension error** (Fig. 3a): measured rotation radii `R'_i` at heights `h_i` above the tip
//!   (paper 001 Table 2: 15 radii every 3 mm, 10.022 mm at 3 mm down to 9.995 mm at 45 mm),
//!   linearly interpolated between the measured heights, held constant beyond the first and last.
//! - **Setup error** (Fig. 3b): the tool axis is offset from the spindle axis by `ρ` (mm, at the
//!   tip) and inclined to it by `φ` (rad), both in the same axial plane. At height `h` the tool's
//!   cross-section in the plane ⊥ spindle axis is an ellipse of semi-axes `r(h)` and `r(h)/cos φ`
//!   centred `ρ + h·tan φ` off the spindle axis, so the spinning tool sweeps the equivalent radius
//!   `r_eq(h) = |ρ + h·tan φ| + r(h)/cos φ`.
//!
//! Sign: a radius larger than the programmed one (10 mm for eq. 2) cuts deeper, so to first order
//! the deviation at a point of contact height `h` changes by `-(r_eq(h) - 10)` (paper 000 §3.2).
//! Units: mm, rad.

use super::ToolpathError;

/// Heights (mm above the tip) and radii (mm) of paper 001 Table 2 (Renishaw NC4, step d = 3 mm).
pub const PAPER_001_TABLE_2: [(f64, f64); 15] = [
    (3.0, 10.022),
    (6.0, 10.019),
    (9.0, 10.020),
    (12.0, 10.016),
    (15.0, 10.014),
    (18.0, 10.012),
    (21.0, 10.011),
    (24.0, 10.009),
    (27.0, 10.005),
    (30.0, 10.003),
    (33.0, 10.002),
    (36.0, 10.001),
    (39.0, 9.998),
    (42.0, 9.999),
    (45.0, 9.995),
];

/// The rotation radius of a tool along its axis.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ToolProfile {
    /// measurement heights above the tip (mm), increasing
    heights: Vec<f64>,
    /// rotation radius at each height (mm)
    radii: Vec<f64>,
    /// setup error: parallel offset `ρ` of the tool axis at the tip (mm)
    offset: f64,
    /// setup error: inclination `φ` of the tool axis to the spindle axis (rad)
    inclination: f64,
}

impl ToolProfile {
    /// A profile from measured `(height, radius)` pairs (mm): at least one pair, heights finite and
    /// strictly increasing, radii positive and finite.
    pub fn try_new(table: &[(f64, f64)]) -> Result<Self, ToolpathError> {
        if table.is_empty() {
            return Err(ToolpathError::EmptyProfile);
        }
        for (i, &(h, r)) in table.iter().enumerate() {
            if !h.is_finite() || (i > 0 && h <= table[i - 1].0) {
                return Err(ToolpathError::ProfileHeights {
                    index: i,
                    height: h,
                });
            }
            if !(r.is_finite() && r > 0.0) {
                return Err(ToolpathError::BadRadius { radius: r });
            }
        }
        Ok(Self {
            heights: table.iter().map(|p| p.0).collect(),
            radii: table.iter().map(|p| p.1).collect(),
            offset: 0.0,
            inclination: 0.0,
        })
    }

    /// A perfect cylinder of radius `radius` (mm).
    pub fn constant(radius: f64) -> Result<Self, ToolpathError> {
        Self::try_new(&[(0.0, radius)])
    }

    /// The measured profile of paper 001 Table 2.
    pub fn paper_001_table_2() -> Self {
        Self {
            heights: PAPER_001_TABLE_2.iter().map(|p| p.0).collect(),
            radii: PAPER_001_TABLE_2.iter().map(|p| p.1).collect(),
            offset: 0.0,
            inclination: 0.0,
        }
    }

    /// Adds a setup error: parallel offset `rho` (mm, at the tip) and inclination `phi` (rad,
    /// |φ| < π/2), in the same axial plane.
    pub fn with_setup_error(mut self, rho: f64, phi: f64) -> Result<Self, ToolpathError> {
        if !(rho.is_finite() && phi.is_finite() && phi.abs() < std::f64::consts::FRAC_PI_2) {
            return Err(ToolpathError::BadSetupError { rho, phi });
        }
        self.offset = rho;
        self.inclination = phi;
        Ok(self)
    }

    /// The measured radius `r(h)` (mm) at height `h` above the tip, without setup error:
    /// piecewise linear through the table, constant outside it.
    pub fn measured_radius_at(&self, h: f64) -> f64 {
        let (hs, rs) = (&self.heights, &self.radii);
        let n = hs.len();
        if h <= hs[0] {
            return rs[0];
        }
        if h >= hs[n - 1] {
            return rs[n - 1];
        }
        let k = hs.partition_point(|x| *x <= h) - 1;
        let s = (h - hs[k]) / (hs[k + 1] - hs[k]);
        rs[k] + s * (rs[k + 1] - rs[k])
    }

    /// The swept (equivalent) radius `r_eq(h) = |ρ + h·tan φ| + r(h)/cos φ` (mm).
    pub fn radius_at(&self, h: f64) -> f64 {
        let phi = self.inclination;
        (self.offset + h * phi.tan()).abs() + self.measured_radius_at(h) / phi.cos()
    }

    /// First-order deviation change at contact height `h` for a path programmed with radius
    /// `nominal` (mm): `-(r_eq(h) - nominal)`.
    pub fn deviation_at(&self, h: f64, nominal: f64) -> f64 {
        -(self.radius_at(h) - nominal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn table_2_values_and_interpolation() {
        let p = ToolProfile::paper_001_table_2();
        assert_near!(p.radius_at(3.0), 10.022, 1e-15);
        assert_near!(p.radius_at(45.0), 9.995, 1e-15);
        // halfway between 12 mm (10.016) and 15 mm (10.014)
        assert_near!(p.radius_at(13.5), 10.015, 1e-12);
        // held constant outside the measured heights
        assert_near!(p.radius_at(0.0), 10.022, 1e-15);
        assert_near!(p.radius_at(60.0), 9.995, 1e-15);
        assert_near!(p.deviation_at(3.0, 10.0), -0.022, 1e-12);
    }

    #[test]
    fn setup_error_closed_form() {
        // parallel offset only: every radius grows by rho
        let p = ToolProfile::constant(10.0)
            .unwrap()
            .with_setup_error(0.005, 0.0)
            .unwrap();
        assert_near!(p.radius_at(20.0), 10.005, 1e-12);
        // inclination only: |h tan φ| + r / cos φ
        let phi = 1e-3;
        let p = ToolProfile::constant(10.0)
            .unwrap()
            .with_setup_error(0.0, phi)
            .unwrap();
        assert_near!(
            p.radius_at(30.0),
            30.0 * phi.tan() + 10.0 / phi.cos(),
            1e-14
        );
        // offset and inclination cancelling at h = 10 mm
        let p = ToolProfile::constant(10.0)
            .unwrap()
            .with_setup_error(-10.0 * phi.tan(), phi)
            .unwrap();
        assert_near!(p.radius_at(10.0), 10.0 / phi.cos(), 1e-14);
    }

    #[test]
    fn rejects_bad_tables() {
        assert_eq!(
            ToolProfile::try_new(&[(3.0, 10.0), (3.0, 10.1)])
                .unwrap_err()
                .to_string(),
            "profile height 1 = 3 mm is not finite or not above the previous one"
        );
        assert!(ToolProfile::try_new(&[]).is_err());
        assert!(ToolProfile::try_new(&[(0.0, -1.0)]).is_err());
        assert!(ToolProfile::constant(10.0)
            .unwrap()
            .with_setup_error(0.0, 2.0)
            .is_err());
    }
}
