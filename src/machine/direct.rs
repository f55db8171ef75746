//! Direct kinematics with geometric errors (paper 000 eq. 12) and its analytic Jacobian.
//!
//! `p = W⁻¹ · T · (o_tool + h·ẑ, 1)` and `w = W⁻¹ · T · (ẑ, 0)` with, for every axis,
//! `F_i(q) = Trans(o_i) · D_i · M_i(q) · E_i(q)` (see [`super::chain`]): `D_i` the location-error
//! matrix of eq. 11 (exact, with its square-root diagonal), `E_i(q)` the error-motion matrix of
//! paper 004 eq. S2. Paper 000: `p = (D_Y T_Y D_C T_C)⁻¹ D_X T_X D_Z T_Z D_B T_B T_tool`.
//! The tool-point deviation is `ΔP = p(ξ) − p(0)` and the tool-direction deviation
//! `ΔV = w(ξ) − w(0)` (paper 004 eq. S3). `h` is the height of the tool point above the tip
//! along the tool axis (mm; `h = 0`: the tip).
//!
//! The Jacobian is exact at any error vector (product rule on the factor list:
//! `∂(W⁻¹) = −W⁻¹ ∂W W⁻¹`), and at ξ = 0 it is the linearised model of eq. 13.

use nalgebra::{Matrix3xX, Matrix4, Vector3, Vector4};
use serde::{Deserialize, Serialize};

use super::chain::{AxisKind, AxisName, AxisValues, Chain, ChainAxis};
use super::error_motion::{motion_name, parse_motion_name, ErrorMotion, MotionComponent};
use super::location_errors::{kind_typical, LocationError};
use super::transform::{
    affine_inverse, location_matrix, location_matrix_derivative, motion_matrix,
    motion_matrix_derivative, translation, Rigid,
};
use super::unit::Unit;
use super::MachineError;

/// The tool point (mm) and unit tool direction in the workpiece frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolPoint {
    pub point: Vector3<f64>,
    pub direction: Vector3<f64>,
}

impl ToolPoint {
    /// `[x, y, z, i, j, k]`: the point (mm) then the unit direction.
    pub fn to_array(&self) -> [f64; 6] {
        let (p, d) = (&self.point, &self.direction);
        [p.x, p.y, p.z, d.x, d.y, d.z]
    }
}

/// One scalar error parameter of the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ErrorParam {
    /// A location error `E{c}0{axis}` (eq. 11).
    Location(LocationError),
    /// The coefficient of `q^power` of the error motion `E{component}{axis}` (eq. S2).
    Motion {
        component: MotionComponent,
        axis: AxisName,
        power: u32,
    },
}

impl ErrorParam {
    /// A change of the value of `axis`: its own positioning error motion `E{axis}{axis}` of power
    /// 0 (the axis moved by δ; a Jacobian column of it is `∂/∂q_axis`).
    pub fn axis_value(axis: AxisName) -> Self {
        ErrorParam::Motion {
            component: axis,
            axis,
            power: 0,
        }
    }

    /// `EC0Y`, `EXX` (power 0), `EXX1` (coefficient of q¹).
    pub fn name(&self) -> String {
        match self {
            ErrorParam::Location(l) => l.name(),
            ErrorParam::Motion {
                component,
                axis,
                power,
            } => {
                let base = motion_name(*component, *axis);
                if *power == 0 {
                    base
                } else {
                    format!("{base}{power}")
                }
            }
        }
    }
    /// Parses either form (`EC0Y` is a location error, `EXX`/`EXX1` an error motion).
    pub fn parse(s: &str) -> Result<Self, MachineError> {
        let t: String = s.chars().filter(|&c| c != '_').collect();
        let c: Vec<char> = t.chars().collect();
        if c.len() == 4 && (c[2] == '0' || c[2] == 'O') && c[3].is_ascii_alphabetic() {
            return LocationError::parse(s).map(ErrorParam::Location);
        }
        let (component, axis, power) = parse_motion_name(s)?;
        Ok(ErrorParam::Motion {
            component,
            axis,
            power,
        })
    }
    pub fn axis(&self) -> AxisName {
        match self {
            ErrorParam::Location(l) => l.axis,
            ErrorParam::Motion { axis, .. } => *axis,
        }
    }
    /// The unit of its value: a location error's (`mm` or `rad`); an error motion's coefficient
    /// of `q^k`: its component's unit per the axis's unit to the `k` (`mm/mm`, `rad/mm^2`, ...).
    pub fn unit(&self) -> Unit {
        match self {
            ErrorParam::Location(l) => l.unit(),
            ErrorParam::Motion {
                component,
                power: 0,
                ..
            } => Unit::of_kind(component.kind()),
            ErrorParam::Motion {
                component,
                axis,
                power,
            } => Unit::Per {
                of: component.kind(),
                per: axis.kind(),
                power: *power,
            },
        }
    }
    /// Whether its value is an angle (a rotary component, `rad`, or a coefficient of one).
    pub fn is_angular(&self) -> bool {
        let component = match self {
            ErrorParam::Location(l) => l.component,
            ErrorParam::Motion { component, .. } => *component,
        };
        component.kind() == AxisKind::Rotary
    }
    /// Its typical size on a real machine, in its unit: that of its component's kind
    /// ([`kind_typical`]).
    pub fn typical(&self) -> f64 {
        kind_typical(if self.is_angular() {
            AxisKind::Rotary
        } else {
            AxisKind::Linear
        })
    }
}

/// A set of error values (unlisted errors are zero). Location errors in mm / rad, error-motion
/// coefficients in mm or rad per unit of `q^k`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MachineErrors {
    pub values: Vec<(ErrorParam, f64)>,
}

impl MachineErrors {
    pub fn none() -> Self {
        Self::default()
    }
    /// From parameters and values of the same length.
    pub fn from_pairs(params: &[ErrorParam], values: &[f64]) -> Self {
        Self {
            values: params.iter().copied().zip(values.iter().copied()).collect(),
        }
    }
    /// Adds `value` to parameter `p`.
    pub fn with(mut self, p: ErrorParam, value: f64) -> Self {
        self.values.push((p, value));
        self
    }
    /// Adds every coefficient of an error motion.
    pub fn with_motion(mut self, m: &ErrorMotion) -> Self {
        for (k, c) in m.coefficients.iter().enumerate() {
            self.values.push((
                ErrorParam::Motion {
                    component: m.component,
                    axis: m.axis,
                    power: k as u32,
                },
                *c,
            ));
        }
        self
    }
    fn location_of(&self, axis: AxisName) -> [f64; 6] {
        let mut e = [0.0; 6];
        for (p, v) in &self.values {
            if let ErrorParam::Location(l) = p {
                if l.axis == axis {
                    e[l.component_index()] += v;
                }
            }
        }
        e
    }
    fn motion_of(&self, axis: &ChainAxis, q: f64) -> [f64; 6] {
        let mut m = [0.0; 6];
        for (p, v) in &self.values {
            if let ErrorParam::Motion {
                component,
                axis: a,
                power,
            } = p
            {
                if *a == axis.name {
                    m[component.index()] += axis.sign * v * q.powi(*power as i32);
                }
            }
        }
        m
    }
    /// Checks that every parameter names an axis of the chain and that eq. 11 is defined.
    pub fn validate(&self, chain: &Chain) -> Result<(), MachineError> {
        for (p, v) in &self.values {
            if chain.axis(p.axis()).is_none() {
                return Err(MachineError::UnknownAxis {
                    name: p.name(),
                    axis: p.axis().to_string(),
                    code: chain.code().to_string(),
                });
            }
            if !v.is_finite() {
                return Err(MachineError::ErrorTooLarge {
                    name: p.name(),
                    value: *v,
                });
            }
        }
        for axis in chain.axes() {
            let [_, _, _, a, b, c] = self.location_of(axis.name);
            if a * a + b * b >= 1.0 || a * a + c * c >= 1.0 || b * b + c * c >= 1.0 {
                let worst =
                    [a, b, c]
                        .into_iter()
                        .fold(0.0_f64, |m, x| if x.abs() > m.abs() { x } else { m });
                return Err(MachineError::ErrorTooLarge {
                    name: format!("E?0{}", axis.name),
                    value: worst,
                });
            }
        }
        Ok(())
    }
}

/// Where a parameter acts: side (0 workpiece, 1 tool), factor index, derivative matrix.
struct FactorDerivative {
    tool_side: bool,
    factor: usize,
    d: Matrix4<f64>,
}

/// The factor lists `[Trans(o), D, M(q), E(q)]` per axis, per side.
struct Factors {
    w: Vec<Matrix4<f64>>,
    t: Vec<Matrix4<f64>>,
}

fn factors_of(axes: &[ChainAxis], q: &AxisValues, errors: &MachineErrors) -> Vec<Matrix4<f64>> {
    let mut f = Vec::with_capacity(4 * axes.len());
    for a in axes {
        f.push(translation(&a.offset));
        f.push(location_matrix(&errors.location_of(a.name)));
        f.push(Chain::motion(a, q.get(a.name)));
        f.push(motion_matrix(&errors.motion_of(a, q.get(a.name))));
    }
    f
}

fn factors(chain: &Chain, q: &AxisValues, errors: &MachineErrors) -> Factors {
    Factors {
        w: factors_of(chain.workpiece_axes(), q, errors),
        t: factors_of(chain.tool_axes(), q, errors),
    }
}

fn product(f: &[Matrix4<f64>]) -> Matrix4<f64> {
    f.iter().fold(Matrix4::identity(), |acc, m| acc * m)
}

fn inverse_product(f: &[Matrix4<f64>]) -> Result<Matrix4<f64>, MachineError> {
    let mut r = Matrix4::identity();
    for m in f {
        let inv = affine_inverse(m).ok_or_else(|| MachineError::SingularErrorMatrix {
            det: m.fixed_view::<3, 3>(0, 0).determinant(),
        })?;
        r = inv * r;
    }
    Ok(r)
}

fn tool_vectors(chain: &Chain, h: f64) -> (Vector4<f64>, Vector4<f64>) {
    let o = chain.tool_offset();
    (
        Vector4::new(o.x, o.y, o.z + h, 1.0),
        Vector4::new(0.0, 0.0, 1.0, 0.0),
    )
}

/// Nominal direct kinematics (no errors): tool point `h` above the tip and tool direction.
/// Evaluated on rigid motions directly (the same chain as [`tool_point`] with all errors 0).
pub fn nominal(chain: &Chain, q: &AxisValues, h: f64) -> ToolPoint {
    let rotary = RotaryMotions::of(chain, q);
    let w = side_motion(chain.workpiece_axes(), q, &rotary).inverse();
    let t = side_motion(chain.tool_axes(), q, &rotary);
    nominal_from_sides(chain, &w, &t, h)
}

/// The rigid motion of each rotary axis of a chain at given angles, `Rot(k, sign·q)`: computed
/// once for several nominal chains at the same angles (the linear axes solved for them).
pub(crate) struct RotaryMotions(Vec<(AxisName, Rigid)>);

impl RotaryMotions {
    /// The motions of the rotary axes of `chain` at the angles of `q` (rad).
    pub(crate) fn of(chain: &Chain, q: &AxisValues) -> Self {
        Self(
            chain
                .axes()
                .filter(|a| a.name.kind() == AxisKind::Rotary)
                .map(|a| {
                    let m = Rigid::rotation(a.name.direction(), a.sign * q.get(a.name));
                    (a.name, m)
                })
                .collect(),
        )
    }
}

/// The rigid motion of one side of the chain (`axes`, frame → body) at the linear values of `q`
/// and the rotary motions `rotary` (made at `q`'s angles): [`nominal`]'s, step for step.
pub(crate) fn side_motion(axes: &[ChainAxis], q: &AxisValues, rotary: &RotaryMotions) -> Rigid {
    axes.iter().fold(Rigid::IDENTITY, |acc, a| {
        let m = match a.name.kind() {
            AxisKind::Linear => {
                let mut d = Vector3::zeros();
                d[a.name.direction()] = a.sign * q.get(a.name);
                Rigid::translation(&d)
            }
            AxisKind::Rotary => rotary
                .0
                .iter()
                .find(|(n, _)| *n == a.name)
                .map_or(Rigid::IDENTITY, |(_, m)| *m),
        };
        acc.then(&Rigid::translation(&a.offset)).then(&m)
    })
}

/// The tool point `h` above the tip and the tool direction from the workpiece side's inverse
/// motion `w` and the tool side's motion `t` ([`side_motion`]).
pub(crate) fn nominal_from_sides(chain: &Chain, w: &Rigid, t: &Rigid, h: f64) -> ToolPoint {
    let o = chain.tool_offset();
    ToolPoint {
        point: w.point(&t.point(&Vector3::new(o.x, o.y, o.z + h))),
        direction: w.vector(&t.vector(&Vector3::z())),
    }
}

/// Exact direct kinematics with errors (eq. 12): tool point `h` above the tip (mm) and tool
/// direction (unit when the error matrices are rotations; eq. 11 is only nearly one).
pub fn tool_point(
    chain: &Chain,
    q: &AxisValues,
    h: f64,
    errors: &MachineErrors,
) -> Result<ToolPoint, MachineError> {
    errors.validate(chain)?;
    let f = factors(chain, q, errors);
    let wi = inverse_product(&f.w)?;
    let t = product(&f.t);
    let (vp, vd) = tool_vectors(chain, h);
    let p = wi * t * vp;
    let d = wi * t * vd;
    Ok(ToolPoint {
        point: p.xyz(),
        direction: d.xyz(),
    })
}

/// Paper 004 eq. S3: tool-point deviation `ΔP = p(ξ) − p(0)` (mm) and tool-direction deviation
/// `ΔV = w(ξ) − w(0)` of the exact model at pose `q`, for the tool point `h` above the tip.
pub fn deviation(
    chain: &Chain,
    q: &AxisValues,
    h: f64,
    errors: &MachineErrors,
) -> Result<(Vector3<f64>, Vector3<f64>), MachineError> {
    let real = tool_point(chain, q, h, errors)?;
    let ideal = nominal(chain, q, h);
    Ok((real.point - ideal.point, real.direction - ideal.direction))
}

fn derivative_factor(
    chain: &Chain,
    q: &AxisValues,
    errors: &MachineErrors,
    p: &ErrorParam,
) -> Result<FactorDerivative, MachineError> {
    let axis_name = p.axis();
    let (tool_side, pos, axis) = chain
        .workpiece_axes()
        .iter()
        .enumerate()
        .map(|(i, a)| (false, i, a))
        .chain(
            chain
                .tool_axes()
                .iter()
                .enumerate()
                .map(|(i, a)| (true, i, a)),
        )
        .find(|(_, _, a)| a.name == axis_name)
        .ok_or_else(|| MachineError::UnknownAxis {
            name: p.name(),
            axis: axis_name.to_string(),
            code: chain.code().to_string(),
        })?;
    Ok(match p {
        ErrorParam::Location(l) => FactorDerivative {
            tool_side,
            factor: 4 * pos + 1,
            d: location_matrix_derivative(&errors.location_of(axis_name), l.component_index()),
        },
        ErrorParam::Motion {
            component, power, ..
        } => FactorDerivative {
            tool_side,
            factor: 4 * pos + 3,
            d: motion_matrix_derivative(component.index())
                * (axis.sign * q.get(axis_name).powi(*power as i32)),
        },
    })
}

/// Analytic Jacobian of [`tool_point`] at `errors` with respect to `params`: columns
/// `∂p/∂θ_k` (3 × n, mm per unit) and `∂w/∂θ_k` (3 × n, per unit).
pub fn jacobian(
    chain: &Chain,
    q: &AxisValues,
    h: f64,
    errors: &MachineErrors,
    params: &[ErrorParam],
) -> Result<(Matrix3xX<f64>, Matrix3xX<f64>), MachineError> {
    let (jp, jd) = tool_point_columns(chain, q, h, errors, params, true)?;
    Ok((jp, jd.unwrap_or_default()))
}

/// The point columns `∂p/∂θ_k` of [`jacobian`] alone (the same bits; the direction columns,
/// half the arithmetic a parameter, are not computed: the defect's columns read only these).
pub fn point_jacobian(
    chain: &Chain,
    q: &AxisValues,
    h: f64,
    errors: &MachineErrors,
    params: &[ErrorParam],
) -> Result<Matrix3xX<f64>, MachineError> {
    Ok(tool_point_columns(chain, q, h, errors, params, false)?.0)
}

/// [`jacobian`]'s columns, the direction's only with `directions`.
fn tool_point_columns(
    chain: &Chain,
    q: &AxisValues,
    h: f64,
    errors: &MachineErrors,
    params: &[ErrorParam],
    directions: bool,
) -> Result<(Matrix3xX<f64>, Option<Matrix3xX<f64>>), MachineError> {
    errors.validate(chain)?;
    let f = factors(chain, q, errors);
    let (vp, _) = tool_vectors(chain, h);
    let pre = Prefixes::of(&f);
    let wi = inverse_product(&f.w)?;
    jacobian_of(chain, q, errors, params, &f, &pre, wi, vp, directions)
}

/// Jacobian of the displacement of the **tool-body point** that sits at `x` (workpiece frame, mm)
/// at pose `q` with `errors` (e.g. the contact point of a flank-milled wall, off the tool axis):
/// `∂x/∂θ_k` (3 × n) and the tool-direction columns `∂w/∂θ_k` (3 × n).
pub fn jacobian_body_point(
    chain: &Chain,
    q: &AxisValues,
    x: &Vector3<f64>,
    errors: &MachineErrors,
    params: &[ErrorParam],
) -> Result<(Matrix3xX<f64>, Matrix3xX<f64>), MachineError> {
    let (jp, jd) = body_point_columns(chain, q, x, errors, params, true)?;
    Ok((jp, jd.unwrap_or_default()))
}

/// The point columns `∂x/∂θ_k` of [`jacobian_body_point`] alone (the same bits, as
/// [`point_jacobian`] is [`jacobian`]'s).
pub fn body_point_jacobian(
    chain: &Chain,
    q: &AxisValues,
    x: &Vector3<f64>,
    errors: &MachineErrors,
    params: &[ErrorParam],
) -> Result<Matrix3xX<f64>, MachineError> {
    Ok(body_point_columns(chain, q, x, errors, params, false)?.0)
}

/// [`point_jacobian`] at the tool point `h` above the tip with `tool_params` and
/// [`body_point_jacobian`] at the tool-body point `x` with `body_params`, at the same pose `q`
/// and `errors`: the chain's factors, their products and `W⁻¹` evaluated once for both, each
/// Jacobian's arithmetic otherwise its own (the same bits as each alone, test). A dense scan's
/// design rows and axis gains are both taken at every point's pose (issue 31: the factors,
/// products and inverse had been ~3 % of a 20,000-point scan's instructions a second time).
pub fn point_and_body_jacobians(
    chain: &Chain,
    q: &AxisValues,
    h: f64,
    x: &Vector3<f64>,
    errors: &MachineErrors,
    tool_params: &[ErrorParam],
    body_params: &[ErrorParam],
) -> Result<(Matrix3xX<f64>, Matrix3xX<f64>), MachineError> {
    errors.validate(chain)?;
    let f = factors(chain, q, errors);
    let pre = Prefixes::of(&f);
    let wi = inverse_product(&f.w)?;
    let (vp, _) = tool_vectors(chain, h);
    let tool = jacobian_of(chain, q, errors, tool_params, &f, &pre, wi, vp, false)?.0;
    let vb = body_vector(&f, &pre, x)?;
    let body = jacobian_of(chain, q, errors, body_params, &f, &pre, wi, vb, false)?.0;
    Ok((tool, body))
}

/// The tool-body point `x` (workpiece frame) in the tool frame, homogeneous: `T⁻¹ W x` from the
/// sides' whole products.
fn body_vector(
    f: &Factors,
    pre: &Prefixes,
    x: &Vector3<f64>,
) -> Result<Vector4<f64>, MachineError> {
    let t = pre.t[f.t.len()];
    let ti = affine_inverse(&t).ok_or_else(|| MachineError::SingularErrorMatrix {
        det: t.fixed_view::<3, 3>(0, 0).determinant(),
    })?;
    Ok(ti * pre.w[f.w.len()] * Vector4::new(x.x, x.y, x.z, 1.0))
}

/// [`jacobian_body_point`]'s columns, the direction's only with `directions`.
fn body_point_columns(
    chain: &Chain,
    q: &AxisValues,
    x: &Vector3<f64>,
    errors: &MachineErrors,
    params: &[ErrorParam],
    directions: bool,
) -> Result<(Matrix3xX<f64>, Option<Matrix3xX<f64>>), MachineError> {
    errors.validate(chain)?;
    let f = factors(chain, q, errors);
    let pre = Prefixes::of(&f);
    let vp = body_vector(&f, &pre, x)?;
    let wi = inverse_product(&f.w)?;
    jacobian_of(chain, q, errors, params, &f, &pre, wi, vp, directions)
}

/// The columns of [`jacobian`] and [`jacobian_body_point`] from the factors `f`, `W⁻¹` (`wi`,
/// [`inverse_product`] of `f.w`) and the tool point `vp` (homogeneous, tool frame): with the tip at `p = W⁻¹ T v` (`W`, `T` the products of
/// the workpiece's and the tool's factor lists, `pre` their prefix products), a parameter of factor `k` of a list whose
/// products before and after it are `P` and `S` (`∂F_k = D`) moves it by `W⁻¹ P D S v` on the
/// tool side and by `−W⁻¹ P D S W⁻¹ T v` on the workpiece side (`∂W⁻¹ = −W⁻¹ ∂W W⁻¹`), the
/// direction `v = ẑ` alike. Evaluated right to left, as matrix-vector products: each list's
/// products before its factors ([`prefix_products`]) and the vectors after them
/// ([`suffix_vectors`]: `S v`, `S W⁻¹ T v`) once for all its factors, `W⁻¹P` once per factor
/// (the location errors of an axis share it), then `D` and `W⁻¹P` on each parameter's two
/// vectors (64 multiplications a parameter, where the products of 4 × 4 matrices had been 224,
/// and a list's products once instead of once per factor: a dense scan's 38 columns at every
/// point, issue 31). The direction columns only with `directions` (`None` without).
#[allow(clippy::too_many_arguments)]
fn jacobian_of(
    chain: &Chain,
    q: &AxisValues,
    errors: &MachineErrors,
    params: &[ErrorParam],
    f: &Factors,
    pre: &Prefixes,
    wi: Matrix4<f64>,
    vp: Vector4<f64>,
    directions: bool,
) -> Result<(Matrix3xX<f64>, Option<Matrix3xX<f64>>), MachineError> {
    let t = pre.t[f.t.len()];
    let vd = Vector4::new(0.0, 0.0, 1.0, 0.0);
    // the tool's point and direction in the workpiece's frame before `W⁻¹`, then after it
    let (tp, td) = (t * vp, t * vd);
    let (wtp, wtd) = (wi * tp, wi * td);
    // the vectors each side's factors act on, after each factor
    let (post_tp, post_wp) = (suffix_vectors(&f.t, vp), suffix_vectors(&f.w, wtp));
    let (post_td, post_wd) = if directions {
        (suffix_vectors(&f.t, vd), suffix_vectors(&f.w, wtd))
    } else {
        (Vec::new(), Vec::new())
    };
    let mut jp = Matrix3xX::zeros(params.len());
    let mut jd = Matrix3xX::zeros(if directions { params.len() } else { 0 });
    // `W⁻¹P` per factor
    let mut left_of: Vec<((bool, usize), Matrix4<f64>)> = Vec::new();
    for (k, p) in params.iter().enumerate() {
        let fd = derivative_factor(chain, q, errors, p)?;
        let key = (fd.tool_side, fd.factor);
        let left = match left_of.iter().find(|a| a.0 == key) {
            Some(a) => a.1,
            None => {
                let before = if fd.tool_side { &pre.t } else { &pre.w };
                let left = wi * before[fd.factor];
                left_of.push((key, left));
                left
            }
        };
        let (post_p, post_d, sign) = if fd.tool_side {
            (&post_tp, &post_td, 1.0)
        } else {
            (&post_wp, &post_wd, -1.0)
        };
        let dp = left * (fd.d * post_p[fd.factor + 1]);
        jp.set_column(k, &(dp.xyz() * sign));
        if directions {
            let dd = left * (fd.d * post_d[fd.factor + 1]);
            jd.set_column(k, &(dd.xyz() * sign));
        }
    }
    Ok((jp, directions.then_some(jd)))
}

/// The prefix products of each factor list ([`prefix_products`]; the last, the list's
/// [`product`]), made once for a pose: the Jacobian's products before each factor and, for a
/// tool-body point, the two sides' whole products.
struct Prefixes {
    w: Vec<Matrix4<f64>>,
    t: Vec<Matrix4<f64>>,
}

impl Prefixes {
    fn of(f: &Factors) -> Self {
        Self {
            w: prefix_products(&f.w),
            t: prefix_products(&f.t),
        }
    }
}

/// The products of the first `k` factors of `f`, `k = 0..=f.len()` ([`product`]'s, the same bits:
/// each the one before it times the next factor).
fn prefix_products(f: &[Matrix4<f64>]) -> Vec<Matrix4<f64>> {
    let mut out = Vec::with_capacity(f.len() + 1);
    let mut acc = Matrix4::identity();
    out.push(acc);
    for m in f {
        // `product`'s own expression (not `*=`), so its bits
        #[allow(clippy::assign_op_pattern)]
        {
            acc = acc * m;
        }
        out.push(acc);
    }
    out
}

/// `f[k..]·v` for `k = 0..=f.len()` (the last `v` itself), each from the one after it.
fn suffix_vectors(f: &[Matrix4<f64>], v: Vector4<f64>) -> Vec<Vector4<f64>> {
    let mut out = vec![v; f.len() + 1];
    for k in (0..f.len()).rev() {
        out[k] = f[k] * out[k + 1];
    }
    out
}

/// All 6 location errors and the constant error motions of every axis of the chain, in chain
/// order (useful for identifiability checks).
pub fn all_params(chain: &Chain) -> Vec<ErrorParam> {
    let mut v = Vec::new();
    for a in chain.axes() {
        for c in AxisName::ALL {
            v.push(ErrorParam::Location(LocationError::new(c, a.name)));
        }
    }
    for a in chain.axes() {
        for c in AxisName::ALL {
            v.push(ErrorParam::Motion {
                component: c,
                axis: a.name,
                power: 0,
            });
        }
    }
    v
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::machine::chain::PAPER000_L0;

    /// The prefix products are [`product`]'s of each prefix bit for bit, and the suffix vectors
    /// the products of each suffix times the vector to 1e-12 (another order of the same sums),
    /// on the three chains' factor lists at spread poses with errors.
    #[test]
    fn prefix_products_and_suffix_vectors() {
        let errors = MachineErrors::none().with(
            ErrorParam::Location(LocationError::new(AxisName::X, AxisName::C)),
            1e-3,
        );
        for (chain, q) in spread_poses(true).iter().step_by(37) {
            let f = factors(chain, q, &errors);
            for list in [&f.w, &f.t] {
                let pre = prefix_products(list);
                let v = Vector4::new(12.5, -3.0, 40.0, 1.0);
                let post = suffix_vectors(list, v);
                for k in 0..=list.len() {
                    let want = product(&list[..k]);
                    assert!(pre[k]
                        .iter()
                        .zip(want.iter())
                        .all(|(a, b)| a.to_bits() == b.to_bits()));
                    let want = product(&list[k..]) * v;
                    assert!(
                        (post[k] - want).norm() <= 1e-12 * (1.0 + want.norm()),
                        "{k}"
                    );
                }
            }
        }
    }

    /// The three chains of the papers, each with 200 axis values spread over its axes: rotary
    /// angles within ±3 rad, linear values within ±80 mm (or 0 when `linear` is false).
    pub(crate) fn spread_poses(linear: bool) -> Vec<(Chain, AxisValues)> {
        let mut out = Vec::new();
        for chain in [
            Chain::paper000(PAPER000_L0),
            Chain::paper002(),
            Chain::paper001(120.0, 80.0),
        ] {
            for k in 0..200 {
                let mut q = AxisValues::default();
                for (j, a) in chain.axes().enumerate() {
                    let x = (0.37 * k as f64 + 1.3 * j as f64).sin();
                    match a.name.kind() {
                        AxisKind::Rotary => q.set(a.name, 3.0 * x),
                        AxisKind::Linear if linear => q.set(a.name, 80.0 * x),
                        AxisKind::Linear => {}
                    }
                }
                out.push((chain.clone(), q));
            }
        }
        out
    }

    /// The sides' motions made from rotary motions made once and reused for other linear values
    /// give [`nominal`]'s tool point and direction bit for bit (tolerance: none), on the three
    /// chains over a spread of angles and positions.
    #[test]
    fn rotary_motions_made_once_give_nominal() {
        for (k, (chain, q)) in spread_poses(true).into_iter().enumerate() {
            let rotary = RotaryMotions::of(&chain, &q);
            for lin in [AxisName::X, AxisName::Y, AxisName::Z] {
                let mut e = q;
                e.set(lin, 0.25 * (k % 200) as f64 - 7.0);
                let w = side_motion(chain.workpiece_axes(), &e, &rotary).inverse();
                let tool = side_motion(chain.tool_axes(), &e, &rotary);
                let a = nominal_from_sides(&chain, &w, &tool, 1.5);
                let b = nominal(&chain, &e, 1.5);
                assert_eq!(
                    (a.point, a.direction),
                    (b.point, b.direction),
                    "{}",
                    chain.code()
                );
            }
        }
    }

    /// The point columns alone ([`point_jacobian`], [`body_point_jacobian`]) are the whole
    /// Jacobians' first halves bit for bit (tolerance: none), on the three chains at spread poses
    /// with errors, for every location error, constant motion and positioning error of the chain
    /// and a quadratic motion of each axis.
    #[test]
    fn point_columns_alone_are_the_jacobians_point_columns() {
        let x = Vector3::new(12.5, -3.0, 40.0);
        for (chain, q) in spread_poses(true).iter().step_by(23) {
            let first = chain.axes().next().unwrap().name;
            let errors = MachineErrors::none().with(
                ErrorParam::Location(LocationError::new(AxisName::X, first)),
                1e-3,
            );
            let mut params = all_params(chain);
            params.extend(chain.axes().map(|a| ErrorParam::axis_value(a.name)));
            params.extend(chain.axes().map(|a| ErrorParam::Motion {
                component: AxisName::B,
                axis: a.name,
                power: 2,
            }));
            let (jp, _) = jacobian(chain, q, 1.5, &errors, &params).unwrap();
            assert_eq!(point_jacobian(chain, q, 1.5, &errors, &params).unwrap(), jp);
            let (jp, _) = jacobian_body_point(chain, q, &x, &errors, &params).unwrap();
            assert_eq!(
                body_point_jacobian(chain, q, &x, &errors, &params).unwrap(),
                jp
            );
        }
    }
}
