//! The moves of the program around the cut, in machine axes: how the tool gets from the
//! machine's home to each pass and away from it without passing near the part.
//!
//! Per surface, from wherever the tool is:
//! 1. rapid up to the safe machine height `Z_safe` (Z alone; at the start, the machine's own
//!    home `G53 Z0`, assumed at or above `Z_safe`);
//! 2. rapid of the rotary axes alone to the pass's first orientation;
//! 3. rapid of X and Y alone above the approach point;
//! 4. rapid of Z alone down to the approach point: the first position raised along the tool
//!    axis until the tool clears the part by [`DESIGN_CLEARANCE`];
//! 5. feed along the tool axis down to the first position, the pass at feed, feed along the
//!    tool axis back up until the tool clears the part again (the flank is left the way it was
//!    cut, not by a move across it).
//!
//! **The clearance rule.** At rotary angles `q`, a move of machine Z by δ moves the tool by
//! δ·`d` relative to the part (`d` the unit direction of machine Z in the part frame, from the
//! nominal kinematics). The tool (a cylinder of radius `R` above its tip, axis `w`, `w·d > 0`)
//! reaches down along `d` to `tip·d − R|d − (d·w)w|`; the part (both walls: their boundary
//! curves, since a ruled surface's extreme along a direction lies on its boundary, and the
//! stated base plate's top corners, [`PLATE_TOP_Z`]) reaches up to `max p·d`. When the first
//! exceeds the second by `c`, no point of the tool is within `c` of the part, wherever X and Y
//! are. `Z_safe` is the lowest machine Z where this holds with `c` = [`DESIGN_CLEARANCE`] at
//! every orientation the rotary moves pass through (64 samples of each, and B = C = 0), and at
//! least every approach point's Z. The approach and retract lengths along the axis use the same
//! rule at the pass's first and last orientations. Units: mm, rad.

use nalgebra::Vector3;
use serde::Serialize;

use super::{Position, ProgramError};
use crate::machine::direct::nominal;
use crate::machine::inverse::solve_linear;
use crate::machine::{AxisKind, AxisName, AxisValues, Chain};
use crate::part::{SShape, Surface};
use crate::toolpath::TOOL_RADIUS;

/// Clearance (mm) the moves are placed with: the safe height, the approach and the retract.
pub const DESIGN_CLEARANCE: f64 = 3.0;
/// Top of the stated base plate under the part (mm, part frame): below the lowest tool tip of
/// the pass (about −6.3 mm), over the part's xy extent plus [`PLATE_MARGIN`].
pub const PLATE_TOP_Z: f64 = -10.0;
/// Margin (mm) of the base plate beyond the walls' xy extent.
pub const PLATE_MARGIN: f64 = 20.0;
/// Samples of each rotary move for the safe height.
const ROTARY_SAMPLES: usize = 64;
/// Samples of each boundary curve for the part's extremes.
const CURVE_SAMPLES: usize = 1000;

/// What a move is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StepKind {
    /// Retract of Z to the machine's home in machine coordinates (`G53 G00 Z0`).
    Home,
    /// A rapid positioning move (one group of axes: Z, the rotaries, or X and Y).
    Rapid,
    /// Feed along the tool axis into the pass.
    Approach,
    /// A position of the pass.
    Cut,
    /// Feed along the tool axis out of the pass.
    Exit,
}

/// The axes a move commands: Z alone, the rotary axes alone, X and Y, or all of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Group {
    Z,
    Rotary,
    Xy,
    /// X, Y and Z (the tip's words with TCP).
    Linear,
    All,
}

impl Group {
    /// Whether the move names axis `n`.
    pub fn names(self, n: AxisName) -> bool {
        match self {
            Group::Z => n == AxisName::Z,
            Group::Rotary => n.kind() == AxisKind::Rotary,
            Group::Xy => matches!(n, AxisName::X | AxisName::Y),
            Group::Linear => n.kind() == AxisKind::Linear,
            Group::All => true,
        }
    }
}

/// One move: its kind, the axes it commands and the machine axes it ends at (mm, rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Step {
    pub kind: StepKind,
    pub group: Group,
    pub q: AxisValues,
    /// The surface of a pass's move (approach, cut, exit).
    pub surface: Option<Surface>,
}

/// The moves of a whole program and the heights they were placed with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Motion {
    pub steps: Vec<Step>,
    /// The safe machine height (mm, machine Z).
    pub z_safe: f64,
    /// Where the replay of a program starts (the home of [`StepKind::Home`] modelled as
    /// `Z_safe` with B = C = 0 and X, Y of the first rapid above a pass).
    pub start: AxisValues,
    /// Lengths (mm) of the feed moves along the tool axis into and out of each pass.
    pub approach_lengths: Vec<f64>,
}

/// The part's points that bound it along any direction: the walls' boundary curves and the
/// stated base plate's top corners (part frame, mm).
pub fn extreme_points(part: &SShape) -> Vec<Vector3<f64>> {
    let mut pts = Vec::new();
    for s in Surface::BOTH {
        for k in 0..=CURVE_SAMPLES {
            let u = k as f64 / CURVE_SAMPLES as f64;
            pts.push(part.point_at(s, u, 0.0));
            pts.push(part.point_at(s, u, 1.0));
        }
    }
    let (lo, hi) = xy_extent(&pts);
    for x in [lo[0] - PLATE_MARGIN, hi[0] + PLATE_MARGIN] {
        for y in [lo[1] - PLATE_MARGIN, hi[1] + PLATE_MARGIN] {
            pts.push(Vector3::new(x, y, PLATE_TOP_Z));
        }
    }
    pts
}

fn xy_extent(pts: &[Vector3<f64>]) -> ([f64; 2], [f64; 2]) {
    pts.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p.x), lo[1].min(p.y)],
                [hi[0].max(p.x), hi[1].max(p.y)],
            )
        },
    )
}

/// The separation (mm) along machine Z between the tool at `q` and the part: lowest tool
/// point minus highest part point along `d` (module docs), and `d`, `w` (unit).
fn separation(chain: &Chain, q: &AxisValues, part: &[Vector3<f64>]) -> (f64, f64) {
    let t = nominal(chain, q, 0.0);
    let mut up = *q;
    up.z += 1.0;
    let d = nominal(chain, &up, 0.0).point - t.point;
    let w = t.direction;
    let across = (d - w * d.dot(&w)).norm();
    let low = t.point.dot(&d) - TOOL_RADIUS * across;
    let high = part
        .iter()
        .map(|p| p.dot(&d))
        .fold(f64::NEG_INFINITY, f64::max);
    (low - high, w.dot(&d))
}

/// The position raised along the tool axis until the tool clears the part by
/// [`DESIGN_CLEARANCE`]: its axis values and the length raised (mm).
fn raised(
    chain: &Chain,
    p: &Position,
    part: &[Vector3<f64>],
    surface: Surface,
) -> Result<(AxisValues, f64), ProgramError> {
    let (s, wd) = separation(chain, &p.axes, part);
    let a = ((DESIGN_CLEARANCE - s) / wd.max(1e-6)).max(0.0);
    let tip = Vector3::from(p.tip) + Vector3::from(p.axis) * a;
    let q = solve_linear(chain, &p.axes, &tip).map_err(|e| ProgramError::Kinematics {
        surface: if surface == Surface::A { 'A' } else { 'B' },
        source: e.into(),
    })?;
    Ok((q, a))
}

fn with_rotaries(q: &AxisValues, from: &AxisValues) -> AxisValues {
    let mut r = *q;
    for n in AxisName::ALL {
        if n.kind() == AxisKind::Rotary {
            r.set(n, from.get(n));
        }
    }
    r
}

/// The moves of the program for the passes `passes` (surface, positions) on `chain`.
pub fn motion(chain: &Chain, passes: &[(Surface, &[Position])]) -> Result<Motion, ProgramError> {
    let part = extreme_points(&SShape::iso());
    let mut ends = Vec::new();
    let mut lengths = Vec::new();
    for &(s, pos) in passes {
        let (Some(first), Some(last)) = (pos.first(), pos.last()) else {
            continue;
        };
        let (a, la) = raised(chain, first, &part, s)?;
        let (b, lb) = raised(chain, last, &part, s)?;
        lengths.push(la.max(lb));
        ends.push((s, pos, a, b));
    }
    // Orientations the rotary moves pass through: from B = C = 0 to the first pass, and from
    // each pass's last orientation to the next one's first.
    let mut rot_from = AxisValues::default();
    let mut z_safe = f64::NEG_INFINITY;
    for (_, _, a, b) in &ends {
        z_safe = z_safe.max(a.z).max(b.z);
        for k in 0..=ROTARY_SAMPLES {
            let t = k as f64 / ROTARY_SAMPLES as f64;
            let mut q = *a;
            for n in AxisName::ALL {
                if n.kind() == AxisKind::Rotary {
                    q.set(n, rot_from.get(n) + t * (a.get(n) - rot_from.get(n)));
                }
            }
            let (s, _) = separation(chain, &q, &part);
            z_safe = z_safe.max(q.z + DESIGN_CLEARANCE - s);
        }
        rot_from = *b;
    }
    // With tool-centre-point management a rotary move keeps the tip where it is: the tool
    // turns about its tip. Raise Z_safe until that too keeps the clearance (from the start, and
    // from each pass's retract at Z_safe).
    for _ in 0..10 {
        let mut deficit = 0.0f64;
        let mut from = AxisValues {
            x: ends.first().map_or(0.0, |e| e.2.x),
            y: ends.first().map_or(0.0, |e| e.2.y),
            z: z_safe,
            ..AxisValues::default()
        };
        for (_, _, a, b) in &ends {
            let tip = nominal(chain, &from, 0.0).point;
            for k in 0..=ROTARY_SAMPLES {
                let t = k as f64 / ROTARY_SAMPLES as f64;
                let mut q = from;
                for n in AxisName::ALL {
                    if n.kind() == AxisKind::Rotary {
                        q.set(n, from.get(n) + t * (a.get(n) - from.get(n)));
                    }
                }
                if let Ok(q) = solve_linear(chain, &q, &tip) {
                    deficit = deficit.max(DESIGN_CLEARANCE - separation(chain, &q, &part).0);
                }
            }
            from = AxisValues { z: z_safe, ..*b };
        }
        if deficit <= 0.0 {
            break;
        }
        z_safe += deficit + 1e-6;
    }
    let mut steps = vec![];
    let mut start = AxisValues::default();
    let mut cur: Option<AxisValues> = None;
    for (k, (s, pos, a, b)) in ends.iter().enumerate() {
        if k == 0 {
            steps.push(Step {
                kind: StepKind::Home,
                group: Group::Z,
                q: AxisValues {
                    z: z_safe,
                    ..AxisValues::default()
                },
                surface: None,
            });
            start = AxisValues {
                x: a.x,
                y: a.y,
                z: z_safe,
                ..AxisValues::default()
            };
            cur = Some(start);
        }
        let mut q = cur.unwrap_or(start);
        let rapid = |group, q: AxisValues, steps: &mut Vec<Step>| {
            steps.push(Step {
                kind: StepKind::Rapid,
                group,
                q,
                surface: None,
            })
        };
        if k > 0 {
            q.z = z_safe;
            rapid(Group::Z, q, &mut steps);
        }
        q = with_rotaries(&q, a);
        rapid(Group::Rotary, q, &mut steps);
        q.x = a.x;
        q.y = a.y;
        rapid(Group::Xy, q, &mut steps);
        rapid(Group::Z, *a, &mut steps);
        let pass = |kind, q| Step {
            kind,
            group: Group::All,
            q,
            surface: Some(*s),
        };
        for (j, p) in pos.iter().enumerate() {
            steps.push(pass(
                if j == 0 {
                    StepKind::Approach
                } else {
                    StepKind::Cut
                },
                p.axes,
            ));
        }
        steps.push(pass(StepKind::Exit, *b));
        cur = Some(*b);
    }
    if let Some(mut q) = cur {
        q.z = z_safe;
        steps.push(Step {
            kind: StepKind::Rapid,
            group: Group::Z,
            q,
            surface: None,
        });
        steps.push(Step {
            kind: StepKind::Home,
            group: Group::Z,
            q,
            surface: None,
        });
    }
    Ok(Motion {
        steps,
        z_safe,
        start,
        approach_lengths: lengths,
    })
}
