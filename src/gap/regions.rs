//! Regions of the S-shape, defined from the curve parameter `u` and the lean of the wall.
//!
//! The S (s-shape.md) has 13 knot spans of width 1/13. Bands of `u`:
//! - `end_start`:  `u < 2/13`   — the first straight leg (where the pass starts);
//! - `turn_1`:     `2/13 ≤ u < 6/13` — the first turn of the S;
//! - `vertical`:   `6/13 ≤ u ≤ 8/13` — the zone where both curves share control points 7-11 and the
//!   ruling is exactly vertical (s-shape.md);
//! - `turn_2`:     `8/13 < u ≤ 11/13` — the second turn;
//! - `end_finish`: `u > 11/13` — the last leg (where the pass ends).
//!
//! The open/close-angle zones are where the wall leans: the outward normal's Z component `N_z`
//! is the sine of the lean. `open_angle` when `N_z > 0.05` (the wall faces upward: the angle
//! between the wall and the base, measured outside the material, is above 90°), `close_angle` when
//! `N_z < −0.05`, `upright` otherwise. On the built-in points A leans open on its first half and
//! closed on its second; B does the opposite.

use serde::{Deserialize, Serialize};

/// A band of `u` along the S.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Region {
    EndStart,
    #[serde(rename = "turn_1")]
    Turn1,
    Vertical,
    #[serde(rename = "turn_2")]
    Turn2,
    EndFinish,
}

impl Region {
    pub const ALL: [Region; 5] = [
        Region::EndStart,
        Region::Turn1,
        Region::Vertical,
        Region::Turn2,
        Region::EndFinish,
    ];

    /// The band that contains `u`.
    pub fn of_u(u: f64) -> Self {
        let k = u * 13.0;
        if k < 2.0 {
            Region::EndStart
        } else if k < 6.0 {
            Region::Turn1
        } else if k <= 8.0 {
            Region::Vertical
        } else if k <= 11.0 {
            Region::Turn2
        } else {
            Region::EndFinish
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Region::EndStart => "end_start",
            Region::Turn1 => "turn_1",
            Region::Vertical => "vertical",
            Region::Turn2 => "turn_2",
            Region::EndFinish => "end_finish",
        }
    }
}

/// Lean of the wall at a point, from the normal's Z component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Lean {
    OpenAngle,
    Upright,
    CloseAngle,
}

/// `|N_z|` below this is `upright` (sin of about 2.9°).
pub const LEAN_NZ: f64 = 0.05;

impl Lean {
    pub const ALL: [Lean; 3] = [Lean::OpenAngle, Lean::Upright, Lean::CloseAngle];

    pub fn of_nz(nz: f64) -> Self {
        if nz > LEAN_NZ {
            Lean::OpenAngle
        } else if nz < -LEAN_NZ {
            Lean::CloseAngle
        } else {
            Lean::Upright
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Lean::OpenAngle => "open_angle",
            Lean::Upright => "upright",
            Lean::CloseAngle => "close_angle",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_follow_the_knots() {
        assert_eq!(Region::of_u(0.0), Region::EndStart);
        assert_eq!(Region::of_u(2.0 / 13.0), Region::Turn1);
        assert_eq!(Region::of_u(6.0 / 13.0), Region::Vertical);
        assert_eq!(Region::of_u(8.0 / 13.0), Region::Vertical);
        assert_eq!(Region::of_u(9.0 / 13.0), Region::Turn2);
        assert_eq!(Region::of_u(1.0), Region::EndFinish);
    }
}
