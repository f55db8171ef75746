//! Paper 002's surface frame (eq. 3-6) and sensitivity coefficients (eq. 11-14) on the M3_15
//! cone frustum (B-C tilting table of eq. 1) and the S-shape: the paper's qualitative findings
//! (§4.2, §3.4) as tests.

use nalgebra::Vector3;
use testpiece::machine::{AxisName, Branch, Chain, ErrorParam};
use testpiece::sensitivity::cone_frustum::ConeFrustum;
use testpiece::sensitivity::frenet::{
    coefficients, cone_frames, Coefficients, Cutting, SurfaceFrame,
};

fn motion(c: AxisName) -> ErrorParam {
    ErrorParam::Motion {
        component: c,
        axis: c,
        power: 0,
    }
}

fn cone_frames_720(cone: &ConeFrustum) -> (Chain, Vec<SurfaceFrame>) {
    let chain = Chain::paper002();
    let (_, frames) = cone_frames(cone, &chain, Branch::Positive, 720).unwrap();
    (chain, frames)
}

fn coef(chain: &Chain, frames: &[SurfaceFrame], c: AxisName) -> Coefficients {
    coefficients(chain, frames, motion(c)).unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn frame_is_orthonormal_and_normal_points_out_of_the_cone() {
    let cone = ConeFrustum::m3_15();
    let (_, frames) = cone_frames_720(&cone);
    let a = Vector3::new(cone.inclination.sin(), 0.0, cone.inclination.cos());
    for f in &frames {
        // t ⊥ b holds for a flank path on a cone only to first order in the step.
        assert!((f.b.norm() - 1.0).abs() < 1e-12 && (f.t.norm() - 1.0).abs() < 1e-12);
        assert!(f.t.dot(&f.b).abs() < 0.01);
        // n (up-cutting, counter-clockwise) points away from the cone axis.
        let radial = f.tip - a * f.tip.dot(&a);
        assert!(f.n.dot(&radial) > 0.0);
    }
}

#[test]
fn m3_15_without_offset_matches_paper002_findings() {
    let cone = ConeFrustum::m3_15();
    let (chain, frames) = cone_frames_720(&cone);
    let exx = coef(&chain, &frames, AxisName::X);
    let eyy = coef(&chain, &frames, AxisName::Y);
    let ezz = coef(&chain, &frames, AxisName::Z);
    let ebb = coef(&chain, &frames, AxisName::B);
    let ecc = coef(&chain, &frames, AxisName::C);
    // §4.2: "the sensitivity coefficients of E_XX are always negative".
    assert!(
        exx.k_n.iter().all(|k| *k < 0.0),
        "max {}",
        exx.k_n.iter().cloned().fold(f64::MIN, f64::max)
    );
    // "E_YY positive where Y > 0 and negative where Y < 0" (Y of the tool tip, workpiece frame).
    for (f, k) in frames.iter().zip(&eyy.k_n) {
        if f.tip.y.abs() > 1.0 {
            assert_eq!(k.signum(), f.tip.y.signum(), "y = {} k_n = {k}", f.tip.y);
        }
    }
    // A unit positioning error moves the tip by one unit: k = 1 for the linear axes (eq. 11).
    assert!(exx.k.iter().chain(&eyy.k).all(|k| (k - 1.0).abs() < 1e-12));
    // §3.4: E_ZZ acts along the spindle (on a table-table machine exactly): k_n = 0.
    assert!(max_abs(&ezz.k_n) < 1e-12);
    eprintln!(
        "max |k_n|: EXX {:.3}, EYY {:.3}, EZZ {:.3}, EBB {:.3} mm/rad, ECC {:.3} mm/rad",
        max_abs(&exx.k_n),
        max_abs(&eyy.k_n),
        max_abs(&ezz.k_n),
        max_abs(&ebb.k_n),
        max_abs(&ecc.k_n)
    );
    // "the sensitivity coefficients for the rotary axes error motions are approximately 0":
    // the normal error of a rotation about an axis through (or near) the cone is far below that
    // of the same rotation with the 62.5 mm / 30 mm offsets.
    let off = ConeFrustum::m3_15().with_offsets();
    let (chain_o, frames_o) = cone_frames_720(&off);
    let ebb_o = coef(&chain_o, &frames_o, AxisName::B);
    let ecc_o = coef(&chain_o, &frames_o, AxisName::C);
    eprintln!(
        "with offsets max |k_n|: EBB {:.3}, ECC {:.3} mm/rad",
        max_abs(&ebb_o.k_n),
        max_abs(&ecc_o.k_n)
    );
    assert!(max_abs(&ecc.k_n) < 0.25 * max_abs(&ecc_o.k_n));
    assert!(max_abs(&ebb.k_n) < 0.5 * max_abs(&ebb_o.k_n));
    // With offsets the translational coefficients are unchanged (§4.2).
    let exx_o = coef(&chain_o, &frames_o, AxisName::X);
    for (a, b) in exx.k_n.iter().zip(&exx_o.k_n) {
        assert!((a - b).abs() < 1e-9);
    }
}

#[test]
fn s_shape_frames_agree_with_the_spec_normal() {
    use testpiece::part::{SShape, Surface};
    use testpiece::sensitivity::frenet::flank_frames;
    use testpiece::sensitivity::SensitivityOptions;
    let part = SShape::iso();
    let opts = SensitivityOptions::default();
    for (s, cutting) in [(Surface::A, Cutting::Down), (Surface::B, Cutting::Up)] {
        let frames = flank_frames(&part, s, &opts, 400, cutting).unwrap();
        let mut worst: f64 = 1.0;
        for (k, f) in frames.iter().enumerate() {
            let u = k as f64 / 400.0;
            let n = part.frame_at(s, u, 1.0).n;
            worst = worst.min(f.n.normalize().dot(&n));
        }
        // n = ±t × b is the normal of the tip path's surface; N(u,1) that of the wall's top.
        assert!(worst > 0.95, "{s:?}: min cos {worst}");
        // Linear-axis positioning errors move the tip by exactly one unit (eq. 11, k = 1).
        let chain = &opts.chain;
        let k = coefficients(chain, &frames, motion(AxisName::X)).unwrap();
        assert!(k.k.iter().all(|v| (v - 1.0).abs() < 1e-12));
    }
}
