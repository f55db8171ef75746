//! The linear model `y ≈ A·x`: a design matrix whose columns are parameters, each with its typed
//! id (kind, name and unit: [`crate::parameter::ParamId`]).
//!
//! Row `i` of `A` is the machined defect at measured point `i` per unit of each parameter
//! (paper 000 eq. 13-14: mm/rad for angles, mm/mm for `EX0B`), so `A·x` is the predicted deviation
//! `(machined - nominal)·N` in mm (+ = material left, - = overcut). The design knows nothing of the
//! kinematics: the sensitivity stage (or a test, or the page) supplies the columns.

use nalgebra::DMatrix;

use super::IdentifyError;
use crate::machine::location_errors::TYPICAL_LENGTH_MM;
use crate::machine::{ErrorParam, Unit};
use crate::parameter::ParamId;

/// One unknown: its id (kind, name and unit: [`ParamId`]) and a typical magnitude used to judge
/// whether the part shows it above the measurement noise (see [`crate::identify`] "weak
/// directions").
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub id: ParamId,
    /// A typical size of this error on a real machine, in its unit (> 0).
    pub typical: f64,
}

impl Parameter {
    /// A parameter with a typical magnitude (in its unit).
    pub fn new(id: ParamId, typical: f64) -> Self {
        Parameter { id, typical }
    }

    /// A machine error parameter: its unit and typical size are those of its kind
    /// ([`ErrorParam::unit`], [`ErrorParam::typical`]: a location error's component, X/Y/Z in
    /// mm, A/B/C in rad), set where the parameter is defined.
    pub fn of_error(e: &ErrorParam) -> Self {
        Parameter {
            id: ParamId::Machine(*e),
            typical: e.typical(),
        }
    }

    /// The tool-radius term `dR` (mm, + = a larger tool).
    pub fn tool_radius() -> Self {
        Parameter {
            id: ParamId::ToolRadius,
            typical: TYPICAL_LENGTH_MM,
        }
    }

    /// A column of the caller's own, with the name and unit it came in with (a file's header).
    pub fn user(name: &str, unit: Unit, typical: f64) -> Self {
        Parameter {
            id: ParamId::User {
                name: name.to_string(),
                unit,
            },
            typical,
        }
    }

    /// A parameter named in text that comes in (a file's or a caller's column names): `dR` or
    /// a machine error parameter ([`ParamId::parse`]: `EX0B`, `EA0C`, `EXX1`), with the typical
    /// size of its kind ([`ParamId::typical`]). An effect's parameter has none of its own:
    /// give it with [`Parameter::new`].
    pub fn parse(name: &str) -> Result<Self, IdentifyError> {
        let id = ParamId::parse(name)?;
        let typical = id.typical().ok_or_else(|| IdentifyError::NoTypical {
            name: name.to_string(),
        })?;
        Ok(Parameter { id, typical })
    }

    /// Its name ([`ParamId::name`]).
    pub fn name(&self) -> String {
        self.id.name()
    }

    /// Its unit ([`ParamId::unit`]).
    pub fn unit(&self) -> Unit {
        self.id.unit()
    }
}

/// The design matrix `A` (n points x p parameters) with its named columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    parameters: Vec<Parameter>,
    matrix: DMatrix<f64>,
}

impl Design {
    /// Validates names (non-empty, unique), typical magnitudes (> 0) and entries (finite).
    pub fn try_new(
        parameters: Vec<Parameter>,
        matrix: DMatrix<f64>,
    ) -> Result<Self, IdentifyError> {
        if matrix.ncols() == 0 || parameters.is_empty() {
            return Err(IdentifyError::NoParameters);
        }
        if parameters.len() != matrix.ncols() {
            return Err(IdentifyError::NameCount {
                names: parameters.len(),
                cols: matrix.ncols(),
            });
        }
        let names: Vec<String> = parameters.iter().map(Parameter::name).collect();
        for (j, (p, name)) in parameters.iter().zip(&names).enumerate() {
            if name.trim().is_empty() {
                return Err(IdentifyError::EmptyName { index: j });
            }
            if let Some(k) = names[..j].iter().position(|q| q == name) {
                return Err(IdentifyError::DuplicateName {
                    name: name.clone(),
                    first: k,
                    second: j,
                });
            }
            if !(p.typical.is_finite() && p.typical > 0.0) {
                return Err(IdentifyError::BadTypical {
                    name: name.clone(),
                    value: p.typical,
                });
            }
        }
        for j in 0..matrix.ncols() {
            for i in 0..matrix.nrows() {
                let v = matrix[(i, j)];
                if !v.is_finite() {
                    return Err(IdentifyError::NonFiniteDesign {
                        row: i,
                        column: names[j].clone(),
                        value: v,
                    });
                }
            }
        }
        Ok(Design { parameters, matrix })
    }

    /// From column-major data (`data[j*n + i]` = row i, column j), parameter names as they come
    /// in (a file's header), read by [`Parameter::parse`].
    pub fn from_column_major(
        names: &[&str],
        n: usize,
        data: &[f64],
    ) -> Result<Self, IdentifyError> {
        let p = names.len();
        if data.len() != n * p {
            return Err(IdentifyError::DesignShape {
                rows: n,
                cols: p,
                found: data.len(),
            });
        }
        let params = names
            .iter()
            .map(|s| Parameter::parse(s))
            .collect::<Result<_, _>>()?;
        Design::try_new(params, DMatrix::from_column_slice(n, p, data))
    }

    /// The design of a sensitivity matrix (paper 000 eq. 14 per unit error, Figure 19 columns);
    /// units and typical magnitudes those of its errors' kinds ([`Parameter::of_error`]).
    pub fn from_sensitivity(
        m: &crate::sensitivity::SensitivityMatrix,
    ) -> Result<Self, IdentifyError> {
        let params = m.errors.iter().map(Parameter::of_error).collect();
        Design::try_new(params, m.values.clone())
    }

    /// Adds the tool-radius column `dR` (mm): a tool larger by dR overcuts by dR, so the
    /// column is -1 at every point (s-shape.md "A tool-radius error dR changes the deviation by -dR").
    pub fn with_tool_radius(self) -> Result<Self, IdentifyError> {
        let minus_one = vec![-1.0; self.rows()];
        self.with_column(Parameter::tool_radius(), &minus_one)
    }

    /// Adds one column (e.g. an effect signature).
    pub fn with_column(self, parameter: Parameter, column: &[f64]) -> Result<Self, IdentifyError> {
        let n = self.rows();
        if column.len() != n {
            return Err(IdentifyError::LengthMismatch {
                what: "extra design column",
                found: column.len(),
                expected: n,
            });
        }
        let p = self.cols();
        let mut m = self.matrix.insert_column(p, 0.0);
        m.column_mut(p).copy_from_slice(column);
        let mut params = self.parameters;
        params.push(parameter);
        Design::try_new(params, m)
    }

    /// Number of points (rows).
    pub fn rows(&self) -> usize {
        self.matrix.nrows()
    }
    /// Number of parameters (columns).
    pub fn cols(&self) -> usize {
        self.matrix.ncols()
    }
    /// The parameters, in column order.
    pub fn parameters(&self) -> &[Parameter] {
        &self.parameters
    }
    /// The matrix `A` (mm per unit of each parameter).
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.matrix
    }
    /// Column index of a parameter.
    pub fn index_of(&self, id: &ParamId) -> Option<usize> {
        self.parameters.iter().position(|p| p.id == *id)
    }
    /// `A·x` (mm).
    pub fn predict(&self, x: &[f64]) -> Vec<f64> {
        let xv = nalgebra::DVector::from_column_slice(x);
        (&self.matrix * xv).iter().copied().collect()
    }
    /// Parameter vector from `(id, value)` pairs (others 0); a parameter not in the design is
    /// an error.
    pub fn vector_from(&self, values: &[(ParamId, f64)]) -> Result<Vec<f64>, IdentifyError> {
        let mut x = vec![0.0; self.cols()];
        for (id, v) in values {
            let j = self
                .index_of(id)
                .ok_or_else(|| IdentifyError::UnknownParameter {
                    name: id.name(),
                    known: self.names().join(", "),
                })?;
            x[j] = *v;
        }
        Ok(x)
    }
    /// The parameter names.
    pub fn names(&self) -> Vec<String> {
        self.parameters.iter().map(Parameter::name).collect()
    }
    /// The parameter ids, in column order.
    pub fn ids(&self) -> Vec<ParamId> {
        self.parameters.iter().map(|p| p.id.clone()).collect()
    }
}
