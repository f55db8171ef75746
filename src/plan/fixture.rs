//! The fixture the part is measured on, and the datum features of the DMIS program's alignment.
//!
//! **Which features, and why the fixture's.** The part frame the analysis assumes
//! (`shared/spec/s-shape.md`: origin at the part origin, Z = 0 at the bottom of the walls, Z up)
//! is the one set on the machine tool, where the part origin is touched off with B = C = 0.
//! The only finished faces the part itself offers are the two flanks, and they are what the
//! test measures: an alignment on them would absorb into the frame part of the very defect the
//! identification reads (a translation or rotation of the flank is a signature of EX0B, EC0B and
//! the squareness errors). The top face of the wall and its end faces are left by the roughing,
//! not finished. So the frame is taken from the fixture the part is machined on and measured
//! on without unclamping: the base plate of the program's replay (its top at
//! [`PLATE_TOP_Z`] = −10 mm, the same value as `program::motion::PLATE_TOP_Z`, a test checks
//! it), stated here as a 320 × 240 × 20 mm plate centred on the part origin whose top face and
//! two ground edge faces (x = +160 mm, y = +120 mm) are the fixture's reference faces:
//!
//! | datum | feature | fixes |
//! |---|---|---|
//! | A | the plate's top face, plane z = −10, outward normal +Z, 4 touches | Z direction, Z origin |
//! | B | the back edge face, plane y = +120, normal +Y, 3 touches | rotation about Z, Y origin |
//! | C | the right edge face, plane x = +160, normal +X, 3 touches | X origin |
//!
//! `DATSET/DA(A),ZDIR,ZORIG,DA(B),YDIR,YORIG,DA(C),XORIG` puts the origin at the corner of the
//! three faces, (160, 120, −10) in the part frame; `TRANS/XORIG,-160,YORIG,-120,ZORIG,10`
//! then moves it to the part origin ([`PART_ORIGIN_IN_DATUM_FRAME`]). The datum features are
//! measured in manual mode (`MODE/MAN`: before the alignment the program's coordinates mean
//! nothing to the CMM), everything after it in programmed mode. Units: mm.

use nalgebra::Vector3;

/// Top of the base plate (mm, part frame): the plate of the program's clearance replay.
pub const PLATE_TOP_Z: f64 = -10.0;
/// Bottom of the base plate (mm, part frame): the plate is 20 mm thick.
pub const PLATE_BOTTOM_Z: f64 = -30.0;
/// The plate's edge faces are at x = ±`PLATE_HALF_X` (mm).
pub const PLATE_HALF_X: f64 = 160.0;
/// The plate's edge faces are at y = ±`PLATE_HALF_Y` (mm).
pub const PLATE_HALF_Y: f64 = 120.0;
/// The part origin in the frame `DATSET` makes (origin at the corner of datums A, B, C), mm.
pub const PART_ORIGIN_IN_DATUM_FRAME: [f64; 3] = [-PLATE_HALF_X, -PLATE_HALF_Y, -PLATE_TOP_Z];

/// One datum feature: a plane of the fixture, its DMIS feature label and datum letter, a point
/// of it and its outward unit normal, and the nominal touches (mm, part frame).
#[derive(Debug, Clone, PartialEq)]
pub struct DatumPlane {
    pub label: &'static str,
    pub datum: char,
    pub point: Vector3<f64>,
    pub normal: Vector3<f64>,
    pub touches: Vec<Vector3<f64>>,
}

/// Datums A, B and C of the module docs, in that order.
pub fn datum_planes() -> [DatumPlane; 3] {
    let v = Vector3::new;
    let (x, y, z) = (PLATE_HALF_X, PLATE_HALF_Y, PLATE_TOP_Z);
    [
        DatumPlane {
            label: "DATUM_A",
            datum: 'A',
            point: v(0.0, 0.0, z),
            normal: v(0.0, 0.0, 1.0),
            touches: vec![
                v(-150.0, -110.0, z),
                v(150.0, -110.0, z),
                v(150.0, 110.0, z),
                v(-150.0, 110.0, z),
            ],
        },
        DatumPlane {
            label: "DATUM_B",
            datum: 'B',
            point: v(0.0, y, z - 10.0),
            normal: v(0.0, 1.0, 0.0),
            touches: vec![
                v(-120.0, y, z - 5.0),
                v(0.0, y, z - 15.0),
                v(120.0, y, z - 5.0),
            ],
        },
        DatumPlane {
            label: "DATUM_C",
            datum: 'C',
            point: v(x, 0.0, z - 10.0),
            normal: v(1.0, 0.0, 0.0),
            touches: vec![
                v(x, -80.0, z - 5.0),
                v(x, 0.0, z - 15.0),
                v(x, 80.0, z - 5.0),
            ],
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every touch lies on its plane, and the corner of the three planes is where
    /// [`PART_ORIGIN_IN_DATUM_FRAME`] says the part origin is not: at minus it.
    #[test]
    fn touches_lie_on_their_planes() {
        for d in datum_planes() {
            for t in &d.touches {
                assert!((t - d.point).dot(&d.normal).abs() < 1e-12, "{}", d.label);
            }
        }
        let corner = Vector3::new(PLATE_HALF_X, PLATE_HALF_Y, PLATE_TOP_Z);
        let o = Vector3::from(PART_ORIGIN_IN_DATUM_FRAME);
        assert!((corner + o).norm() < 1e-12);
    }
}
