//! Tool-tip path length along the flank path (paper 000 eq. 2, effects.md): `s(u) = ∫₀ᵘ
//! |dT_tool/du| du` on one surface, the tip speed from the analytic derivative of the tool pose
//! ([`super::flank::tool_pose_derivs`]). The table is [`crate::geometry::arc_length`]'s: 5-point
//! Gauss–Legendre on 8 pieces of each knot span, where the speed is smooth, so a length at any `u`
//! costs one piece's 5 speed evaluations. It is owned data (no borrowed part), kept with the
//! settings-only path model. Units: mm; `u` unitless.

use crate::geometry::arc_length::LengthTable;
use crate::geometry::length_series::LengthSeries;
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

impl TipLength {
    /// The length as a Chebyshev series a piece ([`LengthSeries`]), on `part`, the part the
    /// table was built for: `L(u)` without evaluating the tool pose, for a dense scan's tens of
    /// thousands of path positions (1e-12 mm from [`TipLength::at`], the test below).
    pub fn series(&self, part: &SShape) -> LengthSeries {
        LengthSeries::new(&self.table, &speed(part, self.surface))
    }
}

/// The tool-tip path lengths of both passes (A then B) at any `u`: from the tables
/// ([`TipLength::at`]: five tool-pose derivatives a length), or from their series
/// ([`TipLength::series`]: a dense scan's, where the tables' evaluations had been ~5 % of the
/// diagnosis's CPU at 20,000 points, issue 31).
#[derive(Debug, Clone, Copy)]
pub enum PassLengths<'a> {
    Tables(&'a SShape, [&'a TipLength; 2]),
    Series(&'a [LengthSeries; 2]),
}

impl PassLengths<'_> {
    /// Length from the start of pass `surface` (0 for A, 1 for B) to `u` (mm).
    pub fn at(&self, surface: usize, u: f64) -> f64 {
        match self {
            PassLengths::Tables(part, t) => t[surface].at(part, u),
            PassLengths::Series(s) => s[surface].length_at(u),
        }
    }

    /// Length of pass `surface` (mm).
    pub fn total(&self, surface: usize) -> f64 {
        match self {
            PassLengths::Tables(_, t) => t[surface].total(),
            PassLengths::Series(s) => s[surface].total(),
        }
    }

    /// Whether a length costs a few flops (a series), so that sharing one between points is
    /// not worth a lookup.
    pub fn is_cheap(&self) -> bool {
        matches!(self, PassLengths::Series(_))
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

    /// The series against the table's Gauss–Legendre, at 100,001 parameters of each pass and
    /// at the pieces' ends (tolerance 1e-12 mm: the two rules' own errors are below it; the
    /// largest difference found is printed).
    #[test]
    fn the_series_is_the_tables_length_to_a_picometre() {
        let part = SShape::iso();
        for s in Surface::BOTH {
            let t = TipLength::new(&part, s);
            let series = t.series(&part);
            assert_eq!(series.total(), t.total());
            let mut worst: f64 = 0.0;
            for k in 0..=100_000 {
                let u = k as f64 / 100_000.0;
                let d = (series.length_at(u) - t.at(&part, u)).abs();
                worst = worst.max(d);
                assert!(d < 1e-12, "{s:?} u = {u}: {d:e} mm");
            }
            println!("{s:?}: largest difference {worst:e} mm");
        }
    }
}
