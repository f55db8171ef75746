//! Tool-tip path length along the flank path (paper 000 eq. 2, effects.md): `s(u) = ∫₀ᵘ
//! |dT_tool/du| du` on one surface, the tip speed from the analytic derivative of the tool pose
//! ([`super::flank::tool_pose_derivs`]). The table is [`crate::geometry::arc_length`]'s: 5-point
//! Gauss–Legendre on 8 pieces of each knot span, where the speed is smooth, so a length at any `u`
//! costs one piece's 5 speed evaluations. It is owned data (no borrowed part), kept with the
//! settings-only path model. Units: mm; `u` unitless.

use crate::geometry::arc_length::LengthTable;
use crate::part::{SShape, Surface};

use super::flank::tool_pose_derivs;

/// Gauss pieces per knot span.
pub const PIECES_PER_SPAN: usize = 8;

/// The tool-tip path length of one surface's pass.
#[derive(Debug, Clone, PartialEq)]
pub struct TipLength {
    surface: Surface,
    table: LengthTable,
}

impl TipLength {
    /// The table of surface `surface` of `part`.
    pub fn new(part: &SShape, surface: Surface) -> Self {
        let knots = part.curves(surface)[0].knots();
        Self {
            surface,
            table: LengthTable::new(&speed(part, surface), knots, PIECES_PER_SPAN),
        }
    }

    /// The surface of the pass.
    pub fn surface(&self) -> Surface {
        self.surface
    }

    /// Length of the whole pass (mm).
    pub fn total(&self) -> f64 {
        self.table.total()
    }

    /// Length from `u = 0` to `u` (clamped to [0, 1]) on `part`, the part the table was built
    /// for (mm).
    pub fn at(&self, part: &SShape, u: f64) -> f64 {
        self.table.length_at(&speed(part, self.surface), u)
    }
}

/// `|dT_tool/du|` (mm per unit u).
fn speed(part: &SShape, s: Surface) -> impl Fn(f64) -> f64 + '_ {
    move |u| tool_pose_derivs(part, s, u).tip_u.norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::flank::tool_pose;

    /// Against the chords of a 200,000-step grid (chord = arc·(1 − κ²h²/24): below 1e-9 mm
    /// over a pass at this step), at the ends of the pass and inside.
    #[test]
    fn tip_length_equals_a_fine_chord_sum() {
        let part = SShape::iso();
        for s in Surface::BOTH {
            let t = TipLength::new(&part, s);
            let n = 200_000;
            let mut acc = 0.0;
            let mut prev = tool_pose(&part, s, 0.0).tip;
            for k in 1..=n {
                let u = k as f64 / n as f64;
                let tip = tool_pose(&part, s, u).tip;
                acc += (tip - prev).norm();
                prev = tip;
                if k % 20_000 == 0 {
                    let got = t.at(&part, u);
                    assert!(
                        (got - acc).abs() < 1e-7,
                        "{s:?} u = {u}: {got} vs chords {acc}"
                    );
                }
            }
            assert!(
                (t.total() - acc).abs() < 1e-7,
                "{s:?}: {} vs {acc}",
                t.total()
            );
        }
    }
}
