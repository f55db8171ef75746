//! Multi-layer flank milling with a tool rotation-profile error and inter-layer interference
//! (paper 001 §3, Fig. 2, 6, 7, 12).
//!
//! **Layer plan.** The wall is cut in `n` axial layers, in order `j = 1 … n`. Layer `j` runs the
//! flank path of eq. 2 (paper 000) with the tool lifted along its axis by
//! `lift_j = (n - j)·pitch` (mm), so the last layer is the nominal path and each earlier one sits
//! `pitch` higher; the tool cuts over heights `0 ≤ h ≤ L_c` above its (lifted) tip, with radius
//! `r_eq(h)` of its [`ToolProfile`]. Consecutive layers overlap by `L_c - pitch` along the axis
//! (paper 001 Fig. 12: 9 layers 3 mm apart, the k-th layer engaging k + 1 rows).
//!
//! **Interference.** A point is first cut by its own layer (the first whose tool reaches it);
//! every later layer whose cutting length still covers it sweeps it again at a different height
//! `h_j = h - lift_j` of the tool, hence with a different radius. Where a later radius is larger,
//! it cuts deeper (paper 001 §3.2 step 4: replace `Q0` by `Q1` if the later surface lies below).
//! The final surface at a point is therefore the deepest cut of all layers reaching it:
//!
//! `deviation(P) = min over layers j, poses u' of t_enter,j(u')`   (mm; + material left)
//!
//! with `t_enter,j` the entry of the normal line `P + tN` into the lifted tool of profile `r_eq`
//! (paper 000 §4.1, Fig. 13, as in [`super::envelope`]). With one layer and a constant radius this
//! is exactly the plain envelope deviation.

use nalgebra::Vector3;
use serde::Serialize;

use super::envelope::{cylinder_interval, FlankPath};
use super::flank::ToolPose;
use super::profile::ToolProfile;
use super::ToolpathError;
use crate::part::ruled::TIP_OFFSET;
use crate::part::{Curve, MeasurementPoint, SShape, Surface};

/// The axial layers of a multi-layer flank milling.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct LayerPlan {
    /// number of layers `n ≥ 1`
    pub layers: usize,
    /// axial step between the tips of consecutive layers (mm, ≥ 0)
    pub pitch: f64,
    /// cutting length of the tool above its tip (mm, > 0)
    pub cutting_length: f64,
}

impl LayerPlan {
    /// A plan of `layers` layers `pitch` mm apart, with a tool cutting over `cutting_length` mm.
    pub fn try_new(layers: usize, pitch: f64, cutting_length: f64) -> Result<Self, ToolpathError> {
        let ok = layers >= 1
            && pitch.is_finite()
            && pitch >= 0.0
            && cutting_length.is_finite()
            && cutting_length > 0.0;
        if !ok {
            return Err(ToolpathError::BadLayerPlan {
                layers,
                pitch,
                cutting_length,
            });
        }
        Ok(Self {
            layers,
            pitch,
            cutting_length,
        })
    }

    /// Layers each engaging an axial band of `band` mm, consecutive bands overlapping by
    /// `overlap` mm (`0 ≤ overlap < band`): pitch `band - overlap`, cutting length `band`.
    pub fn with_overlap(layers: usize, band: f64, overlap: f64) -> Result<Self, ToolpathError> {
        if !(overlap >= 0.0 && overlap < band) {
            return Err(ToolpathError::BadLayerPlan {
                layers,
                pitch: band - overlap,
                cutting_length: band,
            });
        }
        Self::try_new(layers, band - overlap, band)
    }

    /// One layer: the plain flank path with a tool cutting over `cutting_length` mm.
    pub fn single(cutting_length: f64) -> Result<Self, ToolpathError> {
        Self::try_new(1, 0.0, cutting_length)
    }

    /// Paper 001 §4: 9 layers, 3 mm apart, tool of 45 mm cutting length (Φ20×50×120 end mill,
    /// Table 2 measured up to 45 mm).
    pub fn paper_001() -> Self {
        Self {
            layers: 9,
            pitch: 3.0,
            cutting_length: 45.0,
        }
    }

    /// Axial lift of layer `j` (1-based, in machining order) above the nominal path (mm).
    pub fn lift(&self, j: usize) -> f64 {
        (self.layers - j) as f64 * self.pitch
    }

    /// Axial overlap of consecutive layers (mm).
    pub fn overlap(&self) -> f64 {
        (self.cutting_length - self.pitch).max(0.0)
    }
}

/// Entry of the line `p + t·n` into the tool at `pose` lifted by `lift` along its axis, with the
/// rotation profile `profile` over heights `[0, cutting_length]` above the lifted tip; `None`
/// when the line misses it, or when the point `p` itself or the entry lies outside the cutting
/// length (a tool above the point does not cut it, even if the outward line rises into it).
///
/// Solved as a fixed point: `t` = entry into the cylinder of radius `r_eq(h(t))`. Since `N ⊥ R`
/// at the contact, `h` hardly depends on `t`, and two or three iterations suffice.
pub fn profile_entry(
    pose: &ToolPose,
    profile: &ToolProfile,
    lift: f64,
    cutting_length: f64,
    p: &Vector3<f64>,
    n: &Vector3<f64>,
) -> Option<f64> {
    let lifted = ToolPose {
        tip: pose.tip + pose.axis * lift,
        axis: pose.axis,
    };
    let h_of = |t: f64| (p + n * t - lifted.tip).dot(&lifted.axis);
    let mut r = profile.radius_at(h_of(0.0));
    let mut t = cylinder_interval(&lifted, r, p, n)?.0;
    for _ in 0..50 {
        let r_new = profile.radius_at(h_of(t));
        if (r_new - r).abs() <= 1e-15 * r {
            break;
        }
        r = r_new;
        t = cylinder_interval(&lifted, r, p, n)?.0;
    }
    let band = 0.0..=cutting_length;
    (t.is_finite() && band.contains(&h_of(t)) && band.contains(&h_of(0.0))).then_some(t)
}

/// The multi-layer result at one point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LayeredDeviation {
    pub id: usize,
    pub curve: Curve,
    /// final deviation: the deepest cut of all layers reaching the point (mm)
    pub deviation: f64,
    /// layer (1-based) that cut deepest
    pub layer: usize,
    /// contact height on that layer's tool, above its lifted tip (mm)
    pub height: f64,
    /// the point's own layer: the first that reaches it
    pub own_layer: usize,
    /// deviation left by the own layer alone, i.e. without inter-layer interference (mm)
    pub own_deviation: f64,
}

/// Deviation at `points` after milling with `plan` and a tool of rotation profile `profile`
/// (the path is the nominal eq. 2 path, programmed for a 10 mm radius).
pub fn multilayer_deviation(
    part: &SShape,
    points: &[MeasurementPoint],
    profile: &ToolProfile,
    plan: &LayerPlan,
) -> Result<Vec<LayeredDeviation>, ToolpathError> {
    let paths = [
        FlankPath::new(part, Surface::A),
        FlankPath::new(part, Surface::B),
    ];
    points
        .iter()
        .map(|pt| {
            let path = &paths[pt.surface.index()];
            let (p, n) = (&pt.point, &pt.normal);
            let mut own: Option<(usize, f64)> = None;
            let mut best: Option<(usize, f64, f64)> = None;
            for j in 1..=plan.layers {
                let lift = plan.lift(j);
                // quick reach test: the point's height on this layer's tool at its own u
                let h_here = pt.h - lift;
                if h_here < -plan.cutting_length.max(TIP_OFFSET)
                    || h_here > 2.0 * plan.cutting_length + TIP_OFFSET
                {
                    continue;
                }
                let entry =
                    |pose: &ToolPose| profile_entry(pose, profile, lift, plan.cutting_length, p, n);
                let hit = match path.deviation_with(p, n, pt.u, &entry) {
                    Ok(h) if h.deviation.is_finite() => h,
                    Ok(_) | Err(ToolpathError::NoToolReaches { .. }) => continue,
                    Err(e) => return Err(e),
                };
                own.get_or_insert((j, hit.deviation));
                if best.is_none_or(|b| hit.deviation < b.1) {
                    best = Some((j, hit.deviation, hit.height - lift));
                }
            }
            match (own, best) {
                (Some((own_layer, own_deviation)), Some((layer, deviation, height))) => {
                    Ok(LayeredDeviation {
                        id: pt.id,
                        curve: pt.curve,
                        deviation,
                        layer,
                        height,
                        own_layer,
                        own_deviation,
                    })
                }
                _ => Err(ToolpathError::NotReachedByLayers { id: pt.id }),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::part::builtin_points;
    /// The first-order model takes the radius at the point's own contact height; the deepest
    /// tool position touches up to ~0.09 mm higher or lower on the tool (the surface twists, e.g.
    /// point 11: 15.176 vs 15.260 mm), and Table 2 changes by up to 1e-3 mm per mm, so the two
    /// agree to about 6e-5 mm.
    const FIRST_ORDER_MM: f64 = 1e-4;
    use crate::toolpath::{builtin_envelope, TOOL_RADIUS};

    #[test]
    fn one_layer_with_constant_radius_is_the_plain_envelope() {
        let part = SShape::iso();
        let pts = builtin_points(&part);
        let plain = builtin_envelope(&part).unwrap();
        let tool = ToolProfile::constant(TOOL_RADIUS).unwrap();
        let one =
            multilayer_deviation(&part, &pts, &tool, &LayerPlan::single(50.0).unwrap()).unwrap();
        for (a, b) in plain.iter().zip(&one) {
            assert_near!(a.deviation, b.deviation, 1e-12);
            assert_eq!((b.layer, b.own_layer), (1, 1));
        }
    }

    #[test]
    fn table_2_profile_single_layer_shifts_by_minus_radius_error_at_h() {
        // paper 001 §2 / paper 000 §3.2: deviation ≈ envelope - (r(h) - 10) at the contact height
        let part = SShape::iso();
        let pts = builtin_points(&part);
        let plain = builtin_envelope(&part).unwrap();
        let tool = ToolProfile::paper_001_table_2();
        let res =
            multilayer_deviation(&part, &pts, &tool, &LayerPlan::single(50.0).unwrap()).unwrap();
        for ((pt, a), b) in pts.iter().zip(&plain).zip(&res) {
            let expect = a.deviation + tool.deviation_at(pt.h, TOOL_RADIUS);
            assert_near!(b.deviation, expect, FIRST_ORDER_MM);
            // the deepest tool position is near, not at, the point's own u
            assert_near!(b.height, pt.h, 0.1);
        }
    }

    #[test]
    fn layers_keep_the_deepest_cut() {
        // Table 2 (radius largest near the tip) and the same profile reversed (largest at the
        // top). Closed form to first order: final = envelope - max_j (r(h - lift_j) - 10) over the
        // layers whose cutting length covers the point.
        let part = SShape::iso();
        let pts = builtin_points(&part);
        let plain = builtin_envelope(&part).unwrap();
        let plan = LayerPlan::paper_001();
        let reversed: Vec<(f64, f64)> = crate::toolpath::profile::PAPER_001_TABLE_2
            .iter()
            .map(|&(h, r)| (48.0 - h, r))
            .rev()
            .collect();
        let mut interfered = 0;
        for tool in [
            ToolProfile::paper_001_table_2(),
            ToolProfile::try_new(&reversed).unwrap(),
        ] {
            let res = multilayer_deviation(&part, &pts, &tool, &plan).unwrap();
            for ((pt, a), b) in pts.iter().zip(&plain).zip(&res) {
                let reach: Vec<f64> = (1..=plan.layers)
                    .map(|j| pt.h - plan.lift(j))
                    .filter(|h| (0.0..=plan.cutting_length).contains(h))
                    .collect();
                let deepest = reach
                    .iter()
                    .map(|h| tool.radius_at(*h) - TOOL_RADIUS)
                    .fold(f64::NEG_INFINITY, f64::max);
                assert_near!(b.deviation, a.deviation - deepest, FIRST_ORDER_MM);
                // own layer: the first reaching one
                let first = reach[0];
                assert_near!(
                    b.own_deviation,
                    a.deviation - (tool.radius_at(first) - TOOL_RADIUS),
                    FIRST_ORDER_MM
                );
                assert!(b.deviation <= b.own_deviation + 1e-12);
                if b.deviation < b.own_deviation - 1e-4 {
                    interfered += 1;
                }
            }
        }
        // the reversed tool grows upward: later layers recut the earlier surfaces
        assert!(interfered > 50, "{interfered} points with interference");
    }

    #[test]
    fn plan_validation() {
        assert!(LayerPlan::try_new(0, 3.0, 45.0).is_err());
        assert!(LayerPlan::with_overlap(3, 10.0, 12.0).is_err());
        let p = LayerPlan::with_overlap(3, 10.0, 2.0).unwrap();
        assert_near!(p.pitch, 8.0, 1e-15);
        assert_near!(p.overlap(), 2.0, 1e-15);
        assert_near!(p.lift(1), 16.0, 1e-15);
        assert_near!(p.lift(3), 0.0, 1e-15);
    }
}
