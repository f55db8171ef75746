//! Signatures that need the machine's axis path (kinematics stage, [`crate::sensitivity`]):
//! `scale_x/y/z` with the error motions of the linear axes ([`crate::effects::nuisance`]), the
//! index columns of `a_index` (and of `c_index` where the C axis is not the table next to the part), machine Z
//! in the part frame for `thermal_drift`, and the axis reversals along the path.
//!
//! Index (zero offset, `q_real = q_cmd + dq`): the constant positioning error motion of the axis
//! (`EAA`, `ECC` of power 0) is exactly a change of its value; its Jacobian at the tool-body point
//! at the contact point, minus the tip's at the reference pose (the tip at the part origin, the
//! tool vertical, where the origin is set), dotted with the normal, as for the location errors
//! in `physical` mode.
//!
//! Scale error (effects.md): `E_XX = k·X`, `E_YY = k·Y`, `E_ZZ = k·(Z − L0)`, i.e. the linear
//! coefficient (power 1) of the axis's own positioning error motion, evaluated by
//! [`crate::sensitivity::jacobian_rows`] like the location errors (defect per unit at the point,
//! minus the tip displacement at the reference pose `(0, 0, L0, 0, 0)` where the part origin is
//! set, which removes the constant `k·L0` of Z). The backlash columns, at the reference lag and
//! at each lag of the family, are [`crate::sensitivity::reversal::lagged_columns`] on the path
//! model's lags ([`crate::effects::builtin`]).

use nalgebra::{DMatrix, Rotation3, Vector3};

use crate::effects::data::Reversal;
use crate::effects::nuisance::Nuisance;
use crate::effects::GapError;
use crate::machine::direct::{body_point_jacobian, point_jacobian};
use crate::machine::inverse::inverse;
use crate::machine::{AxisKind, AxisName, AxisValues, Branch, Chain, ErrorParam, MachineErrors};
use crate::numerics::order::sort_by_key_f64;
use crate::parameter::SCALE_AXES;
use crate::part::{MeasurementPoint, SShape};
use crate::sensitivity::defect::check_poses;
use crate::sensitivity::defect::jacobian_rows;
use crate::sensitivity::reversal::{grid_u, Pass};
use crate::sensitivity::SensitivityOptions;

/// One column per axis: the axis and its values at the points.
pub type AxisColumns = Vec<(AxisName, Vec<f64>)>;

/// The linear axes' error motions at the points of axis values `q`, evaluated by
/// [`jacobian_rows`] like the location errors: the `scale_<axis>.k` columns (mm/mm), axes of
/// [`SCALE_AXES`], and the [`Nuisance`] families of [`crate::effects::nuisance`]
/// `motion_E{c}{q}` for each linear axis `q` and translation `c`, the coefficients of `q^2`,
/// `q^3` (and `q^1`, the scale's, for `c = q`) of `E{c}{q}` (power `k`: mm per mm^k). One
/// evaluation for both: the scale's column is the own-axis family's first.
pub fn scale_and_motions(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
) -> Result<(AxisColumns, Vec<Nuisance>), GapError> {
    let motions = MotionParams::new();
    let m = jacobian_rows(part, points, q, opts, &motions.params)?;
    Ok(motions.columns(&m))
}

/// The error motions of [`scale_and_motions`]: their parameters in column order, each family's
/// columns and where each scale error's column is (so that a caller can put them beside other
/// parameters in one Jacobian a point: the part model, issue 31).
pub struct MotionParams {
    pub params: Vec<ErrorParam>,
    /// `motion_E<component><axis>` and its columns `start..end`.
    families: Vec<(String, usize, usize)>,
    /// Each axis's scale error (`E<axis><axis>` of power 1): its column.
    scale: Vec<(AxisName, usize)>,
}

impl MotionParams {
    pub fn new() -> Self {
        let mut params = Vec::new();
        let mut families = Vec::new();
        let mut scale = Vec::new();
        for &axis in &SCALE_AXES {
            for &component in &SCALE_AXES {
                let lo = if component == axis { 1 } else { 2 };
                let start = params.len();
                if component == axis {
                    scale.push((axis, start));
                }
                for power in lo..=3 {
                    params.push(ErrorParam::Motion {
                        component,
                        axis,
                        power,
                    });
                }
                families.push((format!("motion_E{component}{axis}"), start, params.len()));
            }
        }
        Self {
            params,
            families,
            scale,
        }
    }

    /// The scale columns and the motion families from `m`, whose columns are [`Self::params`]'
    /// (`points × params`).
    pub fn columns(&self, m: &DMatrix<f64>) -> (AxisColumns, Vec<Nuisance>) {
        let scale = self
            .scale
            .iter()
            .map(|&(a, j)| (a, m.column(j).iter().copied().collect()))
            .collect();
        let motions = self
            .families
            .iter()
            .map(|(id, a, b)| Nuisance {
                id: id.clone(),
                columns: m.columns(*a, b - a).into_owned(),
                pooled: true,
            })
            .collect();
        (scale, motions)
    }
}

impl Default for MotionParams {
    fn default() -> Self {
        Self::new()
    }
}

/// Where each axis of `axes` reverses along the passes (A then B): tool-tip path length from the
/// start of A (mm), at the grid sample where the new direction starts.
pub fn reversals(part: &SShape, passes: &[Pass; 2], axes: &[AxisName]) -> Vec<Reversal> {
    let mut out = Vec::new();
    let mut offset = 0.0;
    for p in passes {
        for &axis in axes {
            for &(k, _) in p.turns_of(axis).map_or(&[][..], |t| &t.at[..]) {
                out.push(Reversal {
                    axis,
                    s: offset + p.length.at(part, grid_u(k)),
                });
            }
        }
        offset += p.length.total();
    }
    sort_by_key_f64(&mut out, |r| r.s);
    out
}

/// `s_C` (+1, or −1 when primed) when the C axis of `chain` is the workpiece-side axis next to
/// the part with no offset (paper 000's `C`, paper 002's `C'`): a zero offset `dC` then turns the
/// part frame by `s_C·dC` about z through the origin, and `c_index` is the rotation
/// `−s_C·(ẑ × p)·N` ([`crate::parameter::Effect::signature`]). `None` otherwise.
pub fn c_table_sign(chain: &Chain) -> Option<f64> {
    chain
        .workpiece_axes()
        .last()
        .filter(|a| a.name == AxisName::C && a.offset == Vector3::zeros())
        .map(|a| a.sign)
}

/// The index axes of `chain` whose column comes from the Jacobian: A, and C when
/// [`c_table_sign`] does not give it.
pub fn index_axes(chain: &Chain) -> Vec<AxisName> {
    [AxisName::C, AxisName::A]
        .into_iter()
        .filter(|&a| chain.axis(a).is_some())
        .filter(|&a| a != AxisName::C || c_table_sign(chain).is_none())
        .collect()
}

/// Whether machine Z stays the part's z at every pose: every workpiece-side rotary axis turns
/// about z (paper 000's C table, paper 001's X table; not paper 002's B-C tilting table).
pub fn machine_z_is_fixed(chain: &Chain) -> bool {
    chain
        .workpiece_axes()
        .iter()
        .all(|a| a.name.kind() == AxisKind::Linear || a.name == AxisName::C)
}

/// Machine Z in the part frame at axis values `q`: `R_W(q)ᵀẑ`, `R_W` the product of the
/// workpiece-side rotations (frame → workpiece; a vector of the frame is `R_Wᵀ·v` in the part).
pub fn machine_z_in_part(chain: &Chain, q: &AxisValues) -> Vector3<f64> {
    let r = chain
        .workpiece_axes()
        .iter()
        .filter(|a| a.name.kind() == AxisKind::Rotary)
        .fold(Rotation3::identity(), |r, a| {
            let mut e = Vector3::zeros();
            e[a.name.direction()] = 1.0;
            r * Rotation3::from_axis_angle(
                &nalgebra::Unit::new_normalize(e),
                a.sign * q.get(a.name),
            )
        });
    r.transpose() * Vector3::z()
}

/// Machine Z in the part frame at each point of axis values `q` (`thermal_drift`), `None` when
/// it is `ẑ` at every pose ([`machine_z_is_fixed`]).
pub fn machine_z_columns(q: &[AxisValues], opts: &SensitivityOptions) -> Option<Vec<Vector3<f64>>> {
    if machine_z_is_fixed(&opts.chain) {
        return None;
    }
    Some(
        q.iter()
            .map(|q| machine_z_in_part(&opts.chain, q))
            .collect(),
    )
}

/// `<axis>_index.d<axis>` columns (mm/rad) for the axes of [`index_axes`] (module docs) at the
/// points of axis values `q`: `opts` in `physical` mode.
pub fn index_signatures(
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
) -> Result<Vec<(AxisName, Vec<f64>)>, GapError> {
    let axes = index_axes(&opts.chain);
    if axes.is_empty() {
        return Ok(Vec::new());
    }
    let params: Vec<ErrorParam> = axes.iter().map(|&a| ErrorParam::axis_value(a)).collect();
    let chain = &opts.chain;
    let none = MachineErrors::none();
    let q_ref = inverse(chain, &Vector3::zeros(), &Vector3::z(), Branch::Signed, 0.0)?;
    let jref = point_jacobian(chain, &q_ref, 0.0, &none, &params)?;
    check_poses(points, q)?;
    let mut cols = vec![vec![0.0; points.len()]; axes.len()];
    for (i, (pt, q)) in points.iter().zip(q).enumerate() {
        let j = body_point_jacobian(chain, q, &pt.point, &none, &params)?;
        let d = (j - &jref).transpose() * pt.normal;
        for (k, col) in cols.iter_mut().enumerate() {
            col[i] = d[k];
        }
    }
    Ok(axes.into_iter().zip(cols).collect())
}
