//! The flat form every measurement point shares, whatever the part: surface parameters `u, v`,
//! the point `x, y, z` (mm), its outward unit normal `nx, ny, nz` and the contact height `h` above
//! the flank tool's tip (mm). Used by the serde forms of [`MeasurementPoint`](super::MeasurementPoint)
//! and [`ConePoint`](super::ConePoint) and by the CLI's CSV, so the columns are written in one place.

use nalgebra::Vector3;
use serde::ser::SerializeStruct;

/// The columns written by [`write_fields`] and [`csv_fields`], in order.
pub const FLAT_COLUMNS: &str = "u,v,x,y,z,nx,ny,nz,h";

/// The geometry of one measurement point, borrowed for writing.
#[derive(Debug, Clone, Copy)]
pub struct Flat<'a> {
    pub u: f64,
    pub v: f64,
    pub point: &'a Vector3<f64>,
    pub normal: &'a Vector3<f64>,
    pub h: f64,
}

impl Flat<'_> {
    fn values(&self) -> [(&'static str, f64); 9] {
        [
            ("u", self.u),
            ("v", self.v),
            ("x", self.point.x),
            ("y", self.point.y),
            ("z", self.point.z),
            ("nx", self.normal.x),
            ("ny", self.normal.y),
            ("nz", self.normal.z),
            ("h", self.h),
        ]
    }

    /// Writes the nine fields into a serde struct being serialised.
    pub fn write_fields<S: SerializeStruct>(&self, st: &mut S) -> Result<(), S::Error> {
        for (name, value) in self.values() {
            st.serialize_field(name, &value)?;
        }
        Ok(())
    }

    /// The nine values as CSV fields (shortest round-trip form), in [`FLAT_COLUMNS`] order.
    pub fn csv_fields(&self) -> String {
        let v: Vec<String> = self
            .values()
            .iter()
            .map(|(_, x)| format!("{x:?}"))
            .collect();
        v.join(",")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Source: the column list of `testpiece points` in the CLI spec (cli.md).
    #[test]
    fn columns_and_values_agree() {
        let p = Vector3::new(1.0, 2.0, 3.0);
        let n = Vector3::new(0.0, 0.6, 0.8);
        let f = Flat {
            u: 0.25,
            v: 0.5,
            point: &p,
            normal: &n,
            h: 7.5,
        };
        let names: Vec<&str> = f.values().iter().map(|(k, _)| *k).collect();
        assert_eq!(names.join(","), FLAT_COLUMNS);
        assert_eq!(f.csv_fields(), "0.25,0.5,1.0,2.0,3.0,0.0,0.6,0.8,7.5");
    }
}
