//! Machined defect at the measurement points (paper 000 eq. 12-14) and the Figure-19 sensitivity
//! matrix (module docs of [`super`] for the two modes).
//!
//! For a point of surface `s` at parameter `u` with axis values `q(u)` of the flank path:
//! - exact (eq. 12): `d = [(p(q, h, ξ) − p(q, h, 0)) − (p(q_ref, 0, ξ) − p(q_ref, 0, 0))] · N`;
//! - linear (eq. 13-14): `d = [J(q, h) − J(q_ref, 0)] ξ · N`, `J = ∂p/∂ξ` at ξ = 0;
//!
//! with `h`, `N` and `q_ref` set by the mode. The sensitivity matrix holds, per point (row) and
//! per location error of the chain's set (column, [`super::error_set`]), the linear
//! defect per unit error: for paper 000's machine the Figure 19 curves, columns
//! `EC0Y, EA0Z, EB0Z, EA0C, EB0C, EX0B, EA0B, EC0B`.

use nalgebra::{DMatrix, Matrix3xX, Vector3};
use serde::{Deserialize, Serialize};

use crate::machine::chain::PAPER000_L0;
use crate::machine::direct::{point_and_body_jacobians, point_jacobian, tool_point};
use crate::machine::inverse::inverse;
use crate::machine::{AxisValues, Branch, Chain, ErrorParam, MachineErrors, PathSample};
use crate::numerics::parallel::{map, Threads};
use crate::part::{MeasurementPoint, SShape, Surface};

use super::path::machine_path;
use super::SensitivityError;

/// Which displaced point, normal and reference (module docs of [`super`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Tool-axis point at the contact height, `N(u,v)`, reference at the part origin.
    #[default]
    Physical,
    /// Tool tip, `N(u,1)`, reference at all axes 0 (paper 000 eq. 14 as printed).
    Paper,
}

impl Mode {
    pub fn parse(s: &str) -> Result<Self, SensitivityError> {
        match s {
            "physical" => Ok(Mode::Physical),
            "paper" => Ok(Mode::Paper),
            _ => Err(SensitivityError::BadMode(s.to_string())),
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Mode::Physical => "physical",
            Mode::Paper => "paper",
        }
    }
}

/// Options of the defect computations (`Default`: physical mode, signed branch, paper 000's
/// machine with `L0 = 499.889` mm).
#[derive(Debug, Clone, PartialEq)]
pub struct SensitivityOptions {
    pub mode: Mode,
    pub branch: Branch,
    pub chain: Chain,
}

impl Default for SensitivityOptions {
    fn default() -> Self {
        Self {
            mode: Mode::Physical,
            branch: Branch::Signed,
            chain: Chain::paper000(PAPER000_L0),
        }
    }
}

impl SensitivityOptions {
    pub fn with_mode(mut self, mode: Mode) -> Self {
        self.mode = mode;
        self
    }
    pub fn with_branch(mut self, branch: Branch) -> Self {
        self.branch = branch;
        self
    }
    pub fn with_chain(mut self, chain: Chain) -> Self {
        self.chain = chain;
        self
    }
}

/// Per point: axis values, tool-point height and normal used by the mode.
struct PointPose {
    q: AxisValues,
    h: f64,
    n: Vector3<f64>,
}

pub(crate) fn reference_pose(opts: &SensitivityOptions) -> Result<AxisValues, SensitivityError> {
    Ok(match opts.mode {
        Mode::Paper => AxisValues::default(),
        // The tip at the part origin with the tool vertical: (0, 0, L0, 0, 0) on paper 000.
        Mode::Physical => inverse(
            &opts.chain,
            &Vector3::zeros(),
            &Vector3::z(),
            Branch::Signed,
            0.0,
        )?,
    })
}

/// The error-free poses of the points for the mode of `opts`: their axis values `q` (from
/// [`axis_values`], one per point in the points' order) with the tool-point height and normal
/// of the mode.
fn point_poses(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
) -> Result<Vec<PointPose>, SensitivityError> {
    check_poses(points, q)?;
    Ok(points
        .iter()
        .zip(q)
        .map(|(p, q)| {
            let (h, n) = match opts.mode {
                Mode::Physical => (p.h, p.normal),
                Mode::Paper => (0.0, part.frame_at(p.surface, p.u, 1.0).n),
            };
            PointPose { q: *q, h, n }
        })
        .collect())
}

/// Axis values `q` given for `points` must be one per point.
pub(crate) fn check_poses(
    points: &[MeasurementPoint],
    q: &[AxisValues],
) -> Result<(), SensitivityError> {
    if q.len() == points.len() {
        Ok(())
    } else {
        Err(SensitivityError::PoseCount {
            poses: q.len(),
            points: points.len(),
        })
    }
}

/// The Figure-19 sensitivity matrix: one row per point (in the given order), one column per
/// location error of the set of `opts.chain` ([`super::error_set`]; paper 000: EC0Y, EA0Z,
/// EB0Z, EA0C, EB0C, EX0B, EA0B, EC0B). Entry = linear defect (mm) per unit error (rad, or mm for EX0B).
#[derive(Debug, Clone, PartialEq)]
pub struct SensitivityMatrix {
    pub ids: Vec<usize>,
    pub curves: Vec<String>,
    /// The parameters (`EC0Y`, ...: each with its unit, [`ErrorParam::unit`]), in column order.
    pub errors: Vec<ErrorParam>,
    /// `points × params`
    pub values: DMatrix<f64>,
}

impl SensitivityMatrix {
    /// The parameters' names, in column order (for the reports).
    pub fn names(&self) -> Vec<String> {
        self.errors.iter().map(ErrorParam::name).collect()
    }
}

/// The sensitivity matrix of the points (linear eq. 14 per unit error, mode of `opts`), at
/// their axis values `q` ([`axis_values`] with the same `opts`), one column per error of
/// `errors`: the location errors of the chain's set ([`super::error_set::ErrorSet::params`];
/// paper 000: Table 3's eight).
pub fn sensitivity_matrix(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
    errors: &[ErrorParam],
) -> Result<SensitivityMatrix, SensitivityError> {
    let params = errors.to_vec();
    let values = jacobian_rows(part, points, q, opts, &params)?;
    Ok(SensitivityMatrix {
        ids: points.iter().map(|p| p.id).collect(),
        curves: points.iter().map(|p| p.curve.name().to_string()).collect(),
        errors: params,
        values,
    })
}

/// Linear defect per unit of each parameter in `params` (any location error or error motion),
/// at the points' axis values `q` ([`axis_values`] with the same `opts`).
pub fn jacobian_rows(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
    params: &[ErrorParam],
) -> Result<DMatrix<f64>, SensitivityError> {
    let poses = point_poses(part, points, q, opts)?;
    let mut m = DMatrix::zeros(points.len(), params.len());
    for (r, (pp, j)) in poses
        .iter()
        .zip(displacements(&poses, opts, params)?)
        .enumerate()
    {
        let d = j.transpose() * pp.n;
        for k in 0..params.len() {
            m[(r, k)] = d[k];
        }
    }
    Ok(m)
}

/// [`jacobian_rows`] of `params` and the gains of `axes`
/// ([`super::reversal::backlash_gains`]) at the same points, from one evaluation of the chain a
/// point ([`point_and_body_jacobians`]: a dense scan takes both at every point, issue 31): the
/// same numbers as each alone (test).
pub fn jacobian_rows_and_gains(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
    params: &[ErrorParam],
    axes: &[crate::machine::AxisName],
) -> Result<(DMatrix<f64>, Vec<Vec<f64>>), SensitivityError> {
    let poses = point_poses(part, points, q, opts)?;
    let none = MachineErrors::none();
    let jref = point_jacobian(&opts.chain, &reference_pose(opts)?, 0.0, &none, params)?;
    let axis_params: Vec<ErrorParam> = axes.iter().map(|&a| ErrorParam::axis_value(a)).collect();
    let mut m = DMatrix::zeros(points.len(), params.len());
    let mut gains = vec![Vec::with_capacity(points.len()); axes.len()];
    for (r, (pp, pt)) in poses.iter().zip(points).enumerate() {
        // the tool point at `h` for the rows, the contact point for the gains (their normal is
        // the poses' in both modes)
        let (j, jb) = point_and_body_jacobians(
            &opts.chain,
            &pp.q,
            pp.h,
            &pt.point,
            &none,
            params,
            &axis_params,
        )?;
        let d = (j - &jref).transpose() * pp.n;
        for k in 0..params.len() {
            m[(r, k)] = d[k];
        }
        for (a, col) in gains.iter_mut().enumerate() {
            col.push(jb.column(a).dot(&pp.n));
        }
    }
    Ok((m, gains))
}

/// The linear displacement of the displaced tool point (mode of `opts`) per unit of each
/// parameter, minus that of the reference (3 × params per point, mm per unit): what
/// [`jacobian_rows`] projects on the normal (`q`: the points' axis values, [`axis_values`]).
pub fn jacobian_displacements(
    part: &SShape,
    points: &[MeasurementPoint],
    q: &[AxisValues],
    opts: &SensitivityOptions,
    params: &[ErrorParam],
) -> Result<Vec<Matrix3xX<f64>>, SensitivityError> {
    displacements(&point_poses(part, points, q, opts)?, opts, params)
}

fn displacements(
    poses: &[PointPose],
    opts: &SensitivityOptions,
    params: &[ErrorParam],
) -> Result<Vec<Matrix3xX<f64>>, SensitivityError> {
    let none = MachineErrors::none();
    let jref = point_jacobian(&opts.chain, &reference_pose(opts)?, 0.0, &none, params)?;
    poses
        .iter()
        .map(|pp| {
            let j = point_jacobian(&opts.chain, &pp.q, pp.h, &none, params)?;
            Ok(j - &jref)
        })
        .collect()
}

/// The axis values of the flank path at each point (in the points' order), by the chain and
/// branch of `opts` (inverse kinematics, eq. 8-10; the mode is not used): the points' poses,
/// solved once per point set and passed to every computation at those points (the design's
/// columns, the exact model, every effect family's signature).
pub fn axis_values(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
) -> Result<Vec<AxisValues>, SensitivityError> {
    axis_values_on(part, points, opts, Threads::ONE)
}

/// [`axis_values`], the two surfaces' paths side by side on `threads` threads: the same values.
pub fn axis_values_on(
    part: &SShape,
    points: &[MeasurementPoint],
    opts: &SensitivityOptions,
    threads: Threads,
) -> Result<Vec<AxisValues>, SensitivityError> {
    if let Some(p) = points.iter().find(|p| !(0.0..=1.0).contains(&p.u)) {
        return Err(SensitivityError::BadPoint { id: p.id, u: p.u });
    }
    // each surface's points and their path samples
    let path_of = |&s: &Surface| -> Result<(Vec<usize>, Vec<PathSample>), SensitivityError> {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].surface == s)
            .collect();
        if idx.is_empty() {
            return Ok((idx, Vec::new()));
        }
        let us: Vec<f64> = idx.iter().map(|&i| points[i].u).collect();
        let path = machine_path(part, &opts.chain, s, opts.branch, &us)?;
        Ok((idx, path))
    };
    let mut out = vec![AxisValues::default(); points.len()];
    for surface in map(threads, &Surface::BOTH, path_of) {
        let (idx, path) = surface?;
        for (&i, sample) in idx.iter().zip(path) {
            out[i] = sample.values;
        }
    }
    Ok(out)
}

/// Exact machined defect (eq. 12, mm) at the points for the errors `errors` (any location errors
/// and error motions of the chain; unlisted ones are 0).
pub fn defect(
    part: &SShape,
    points: &[MeasurementPoint],
    errors: &MachineErrors,
    opts: &SensitivityOptions,
) -> Result<Vec<f64>, SensitivityError> {
    errors.validate(&opts.chain)?;
    let q = axis_values(part, points, opts)?;
    DefectPoses::new(part, points, &q, opts)?.defect(errors)
}

/// What [`defect`] needs of the points that does not depend on the errors: the axis values of
/// the flank path at each point (inverse kinematics, eq. 8-10), the tool point and the reference
/// tool point of the error-free chain (`p(q, h, 0)`, `p(q_ref, 0, 0)` of eq. 12). Built once, it
/// evaluates eq. 12 for any errors with the same arithmetic as [`defect`] (an iterative
/// refinement evaluates it ~2p times per step: the path is solved once, not each time).
pub struct DefectPoses {
    chain: Chain,
    poses: Vec<PointPose>,
    /// `p(q, h, 0)` per point (mm).
    nominal: Vec<Vector3<f64>>,
    q_ref: AxisValues,
    /// `p(q_ref, 0, 0)` (mm).
    nominal_ref: Vector3<f64>,
    /// The threads the points are evaluated on ([`DefectPoses::on`]).
    threads: Threads,
}

impl DefectPoses {
    /// The poses of `points` on the flank path of `opts` (chain, branch, mode), at their axis
    /// values `q` ([`axis_values`] with the same `opts`).
    pub fn new(
        part: &SShape,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        opts: &SensitivityOptions,
    ) -> Result<Self, SensitivityError> {
        Self::on(part, points, q, opts, Threads::ONE)
    }

    /// [`DefectPoses::new`], the points' tool points (here and in every [`DefectPoses::defect`])
    /// computed on `threads` threads, the points shared out in blocks: the same values.
    pub fn on(
        part: &SShape,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        opts: &SensitivityOptions,
        threads: Threads,
    ) -> Result<Self, SensitivityError> {
        let poses = point_poses(part, points, q, opts)?;
        let none = MachineErrors::none();
        let c = &opts.chain;
        let q_ref = reference_pose(opts)?;
        let nominal_ref = tool_point(c, &q_ref, 0.0, &none)?.point;
        let nominal = in_blocks(threads, poses.len(), |i| {
            Ok(tool_point(c, &poses[i].q, poses[i].h, &none)?.point)
        })?;
        Ok(Self {
            chain: c.clone(),
            poses,
            nominal,
            q_ref,
            nominal_ref,
            threads,
        })
    }

    /// Exact machined defect (eq. 12, mm) at the points for `errors` (validated against the
    /// chain).
    pub fn defect(&self, errors: &MachineErrors) -> Result<Vec<f64>, SensitivityError> {
        self.defect_on(errors, self.threads)
    }

    /// [`DefectPoses::defect`] on `threads` threads (one, inside work already shared out).
    pub fn defect_on(
        &self,
        errors: &MachineErrors,
        threads: Threads,
    ) -> Result<Vec<f64>, SensitivityError> {
        errors.validate(&self.chain)?;
        let c = &self.chain;
        let d_ref = tool_point(c, &self.q_ref, 0.0, errors)?.point - self.nominal_ref;
        in_blocks(threads, self.poses.len(), |i| {
            let pp = &self.poses[i];
            let d = tool_point(c, &pp.q, pp.h, errors)?.point - self.nominal[i];
            Ok((d - d_ref).dot(&pp.n))
        })
    }
}

/// Points a block of [`in_blocks`]: a few hundred microseconds of tool points.
const POINT_BLOCK: usize = 2048;

/// `(0..len).map(f).collect()`, the indices shared out between `threads` threads in blocks of
/// [`POINT_BLOCK`] (the first error in the indices' order when any).
fn in_blocks<R: Send>(
    threads: Threads,
    len: usize,
    f: impl Fn(usize) -> Result<R, SensitivityError> + Sync,
) -> Result<Vec<R>, SensitivityError> {
    if threads.get() <= 1 || len <= POINT_BLOCK {
        return (0..len).map(f).collect();
    }
    let starts: Vec<usize> = (0..len).step_by(POINT_BLOCK).collect();
    let mut out = Vec::with_capacity(len);
    for block in map(threads, &starts, |&a| {
        (a..len.min(a + POINT_BLOCK))
            .map(&f)
            .collect::<Result<Vec<R>, _>>()
    }) {
        out.extend(block?);
    }
    Ok(out)
}

/// Linearised machined defect (eq. 14, mm): the Jacobian at ξ = 0 times the error values.
pub fn linear_defect(
    part: &SShape,
    points: &[MeasurementPoint],
    errors: &MachineErrors,
    opts: &SensitivityOptions,
) -> Result<Vec<f64>, SensitivityError> {
    errors.validate(&opts.chain)?;
    let params: Vec<ErrorParam> = errors.values.iter().map(|(p, _)| *p).collect();
    let values: Vec<f64> = errors.values.iter().map(|(_, v)| *v).collect();
    let q = axis_values(part, points, opts)?;
    let m = jacobian_rows(part, points, &q, opts, &params)?;
    Ok((m * nalgebra::DVector::from_vec(values))
        .iter()
        .copied()
        .collect())
}

/// [`defect`] for a vector `xi` of the errors `params`, in their order (the chain's set,
/// [`super::error_set::ErrorSet::params`]; paper 000: EC0Y, EA0Z, EB0Z, EA0C, EB0C, EX0B, EA0B,
/// EC0B; rad, EX0B in mm). Exact eq. 12.
pub fn defect_xi(
    part: &SShape,
    points: &[MeasurementPoint],
    xi: &[f64],
    params: &[ErrorParam],
    opts: &SensitivityOptions,
) -> Result<Vec<f64>, SensitivityError> {
    if xi.len() != params.len() {
        return Err(SensitivityError::ErrorCount {
            values: xi.len(),
            params: params.len(),
        });
    }
    defect(part, points, &MachineErrors::from_pairs(params, xi), opts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::direct::all_params;

    /// [`jacobian_rows_and_gains`] is [`jacobian_rows`] and
    /// [`crate::sensitivity::reversal::backlash_gains`] bit for bit (tolerance: none): the
    /// built-in 100 points on the three chains of the papers (every location error and constant
    /// error motion of each, the gains of every axis), in both modes.
    #[test]
    fn rows_and_gains_together_are_each_alone() {
        let part = SShape::iso();
        let points = crate::part::builtin_points(&part);
        for chain in [
            Chain::paper000(PAPER000_L0),
            Chain::paper002(),
            Chain::paper001(120.0, 80.0),
        ] {
            for mode in [Mode::Physical, Mode::Paper] {
                let opts = SensitivityOptions::default()
                    .with_chain(chain.clone())
                    .with_mode(mode);
                let q = axis_values(&part, &points, &opts).unwrap();
                let params = all_params(&chain);
                let axes: Vec<_> = chain.axes().map(|a| a.name).collect();
                let (rows, gains) =
                    jacobian_rows_and_gains(&part, &points, &q, &opts, &params, &axes).unwrap();
                let want_rows = jacobian_rows(&part, &points, &q, &opts, &params).unwrap();
                let want_gains =
                    crate::sensitivity::reversal::backlash_gains(&part, &points, &q, &axes, &opts)
                        .unwrap();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(rows.as_slice()),
                    bits(want_rows.as_slice()),
                    "{mode:?}"
                );
                assert_eq!(gains.len(), axes.len());
                for (g, w) in gains.iter().zip(&want_gains) {
                    assert_eq!(bits(g), bits(w), "{mode:?}");
                }
            }
        }
    }
}
