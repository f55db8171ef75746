//! Effects outside the catalogue of effects.md that `testpiece validate` puts on simulated parts:
//! what the diagnosis must call `unexplained`.
//!
//! - **waviness** `a·sin(2π s/λ + φ)` along the tool path, λ in [`WAVE_MIN_MM`]..[`WAVE_MAX_MM`];
//! - **short waviness**, λ in [`SHORT_WAVE_MIN_MM`]..[`WAVE_MIN_MM`] (down to about three points a
//!   wavelength at the built-in 25 mm spacing);
//! - **bump** `a·exp(−½((s − s₀)/w)²)`, w in 10..30 mm;
//! - **gouge**: a cut into the wall, `−a·(1 − ((s − s₀)/w)²)` for `|s − s₀| < w`, w in
//!   [`GOUGE_MIN_MM`]..[`GOUGE_MAX_MM`] (two to four points of the built-in layout; always
//!   material removed);
//! - **straightness**: the quadratic straightness error of one linear axis in one of the two
//!   directions across it, `E_{YX} = c·X²` (ISO 230-1 error motion, coefficient of `q²`), its
//!   linear defect from the machine's Jacobian ([`crate::sensitivity::jacobian_rows`]);
//! - **cyclic C**: an angular positioning error of the C axis of two periods per turn,
//!   `E_{CC}(C) = a·sin(2C + φ)` (eccentric mounting of an encoder); its defect at a point is the
//!   defect of a constant `E_{CC}` there times `sin(2C_i + φ)`, `C_i` the C value of the tool
//!   path at the point.

use nalgebra::DVector;

use crate::effects::GapError;
use crate::machine::{AxisName, AxisValues, ErrorParam};
use crate::numerics::random::Sampler;
use crate::part::{MeasurementPoint, SShape};
use crate::sensitivity::defect::jacobian_rows;
use crate::sensitivity::SensitivityOptions;

/// Shortest simulated waviness wavelength of the standard set (mm of tool path).
pub const WAVE_MIN_MM: f64 = 150.0;
/// Longest simulated waviness wavelength (mm of tool path).
pub const WAVE_MAX_MM: f64 = 600.0;
/// Shortest wavelength of the short waviness (mm of tool path).
pub const SHORT_WAVE_MIN_MM: f64 = 80.0;
/// Half-widths of a gouge (mm of tool path).
pub const GOUGE_MIN_MM: f64 = 25.0;
pub const GOUGE_MAX_MM: f64 = 50.0;

/// The out-of-list shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Waviness,
    ShortWave,
    Bump,
    Gouge,
    Straightness,
    CyclicC,
}

impl Shape {
    /// The standard set (today's conditions).
    pub const STANDARD: [Shape; 2] = [Shape::Waviness, Shape::Bump];
    /// The shapes beyond it (issue 18).
    pub const EXTENDED: [Shape; 4] = [
        Shape::ShortWave,
        Shape::Gouge,
        Shape::Straightness,
        Shape::CyclicC,
    ];
    pub fn as_str(self) -> &'static str {
        match self {
            Shape::Waviness => "waviness",
            Shape::ShortWave => "short_wave",
            Shape::Bump => "bump",
            Shape::Gouge => "gouge",
            Shape::Straightness => "straightness",
            Shape::CyclicC => "cyclic_c",
        }
    }
}

/// The columns the machine-made shapes need at the points of a model.
#[derive(Debug, Clone, Default)]
pub struct ShapeColumns {
    /// Quadratic straightness of each linear axis across it (`EYX2`: Y error of X per mm⁻¹).
    pub straightness: Vec<(String, DVector<f64>)>,
    /// `E_CC` column times `sin 2C` and `cos 2C` at the points.
    pub cyclic_c: Option<[DVector<f64>; 2]>,
}

impl ShapeColumns {
    /// The columns at `points` (axis values `q`, [`crate::sensitivity::axis_values`]) on the
    /// machine of `opts` (B-C machines; without a C axis no cyclic column).
    pub fn at(
        part: &SShape,
        points: &[MeasurementPoint],
        q: &[AxisValues],
        opts: &SensitivityOptions,
    ) -> Result<Self, GapError> {
        let linear = [AxisName::X, AxisName::Y, AxisName::Z];
        let params: Vec<ErrorParam> = linear
            .iter()
            .flat_map(|&axis| {
                linear
                    .iter()
                    .filter(move |&&c| c != axis)
                    .map(move |&component| ErrorParam::Motion {
                        component,
                        axis,
                        power: 2,
                    })
            })
            .collect();
        let m = jacobian_rows(part, points, q, opts, &params)?;
        let straightness = params
            .iter()
            .enumerate()
            .map(|(j, p)| (p.name(), m.column(j).into_owned()))
            .filter(|(_, c)| c.amax() > 1e-15)
            .collect();
        let cyclic_c = if opts.chain.axis(AxisName::C).is_some() {
            let ecc = ErrorParam::axis_value(AxisName::C);
            let col = jacobian_rows(part, points, q, opts, &[ecc])?;
            let c: Vec<f64> = q.iter().map(|q| q.c).collect();
            let n = points.len();
            Some([
                DVector::from_iterator(n, (0..n).map(|i| col[(i, 0)] * (2.0 * c[i]).sin())),
                DVector::from_iterator(n, (0..n).map(|i| col[(i, 0)] * (2.0 * c[i]).cos())),
            ])
        } else {
            None
        };
        Ok(Self {
            straightness,
            cyclic_c,
        })
    }
}

/// A drawn shape: unit-amplitude values at the points and the parameters drawn.
pub type Drawn = (DVector<f64>, Vec<(String, f64)>);

/// A unit-amplitude shape (before scaling to the wanted RMS) and its parameters; `None` when the
/// model has no column for it.
pub fn draw(
    shape: Shape,
    s_path: &[f64],
    columns: &ShapeColumns,
    rng: &mut Sampler,
) -> Option<Drawn> {
    use std::f64::consts::PI;
    let n = s_path.len();
    let s_max = s_path.iter().cloned().fold(0.0, f64::max);
    let wave = |lambda: f64, rng: &mut Sampler| {
        let phase = rng.uniform(0.0, 2.0 * PI);
        (
            DVector::from_iterator(
                n,
                s_path.iter().map(|s| (2.0 * PI * s / lambda + phase).sin()),
            ),
            vec![("lambda".to_string(), lambda)],
        )
    };
    Some(match shape {
        Shape::Waviness => {
            let lambda = rng.uniform(WAVE_MIN_MM, WAVE_MAX_MM);
            wave(lambda, rng)
        }
        Shape::ShortWave => {
            let lambda = rng.uniform(SHORT_WAVE_MIN_MM, WAVE_MIN_MM);
            wave(lambda, rng)
        }
        Shape::Bump => {
            let w = rng.uniform(10.0, 30.0);
            let s0 = rng.uniform(0.0, s_max);
            (
                DVector::from_iterator(
                    n,
                    s_path.iter().map(|s| (-0.5 * ((s - s0) / w).powi(2)).exp()),
                ),
                vec![("width".into(), w), ("s0".into(), s0)],
            )
        }
        Shape::Gouge => {
            let w = rng.uniform(GOUGE_MIN_MM, GOUGE_MAX_MM);
            let s0 = rng.uniform(0.0, s_max);
            (
                DVector::from_iterator(
                    n,
                    s_path
                        .iter()
                        .map(|s| -(1.0 - ((s - s0) / w).powi(2)).max(0.0)),
                ),
                vec![("width".into(), w), ("s0".into(), s0)],
            )
        }
        Shape::Straightness => {
            if columns.straightness.is_empty() {
                return None;
            }
            let k = ((rng.unit() * columns.straightness.len() as f64) as usize)
                .min(columns.straightness.len() - 1);
            let (name, col) = &columns.straightness[k];
            let scale = col.amax();
            (
                col / scale,
                vec![(format!("{name} (per {scale:.3e})"), k as f64)],
            )
        }
        Shape::CyclicC => {
            let [sin2, cos2] = columns.cyclic_c.as_ref()?;
            let phase = rng.uniform(0.0, 2.0 * PI);
            let v = sin2 * phase.cos() + cos2 * phase.sin();
            let scale = v.amax().max(1e-300);
            (v / scale, vec![("phase".into(), phase)])
        }
    })
}
