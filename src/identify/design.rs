//! The linear model `y ≈ A·x`: a design matrix whose columns are named parameters with units.
//!
//! Row `i` of `A` is the machined defect at measured point `i` per unit of each parameter
//! (paper 000 eq. 13-14: mm/rad for angles, mm/mm for `EX0B`), so `A·x` is the predicted deviation
//! `(machined - nominal)·N` in mm (+ = material left, - = overcut). The design knows nothing of the
//! kinematics: the sensitivity stage (or a test, or the page) supplies the columns.

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use super::IdentifyError;

/// The 8 ISO 230-1 location errors of the B-head/C-table machine (paper 000 Table 3), in the
/// column order of the sensitivity files.
pub const ISO_LOCATION_ERRORS: [&str; 8] = [
    "EC0Y", "EA0Z", "EB0Z", "EA0C", "EB0C", "EX0B", "EA0B", "EC0B",
];

/// Name of the tool-radius term (cli.md): mm, + = a larger tool, column = -1 (s-shape.md).
pub const TOOL_RADIUS: &str = "dR";

use crate::machine::location_errors::TYPICAL_LENGTH_MM;
use crate::machine::ErrorParam;

/// One unknown: its name, unit, and a typical magnitude used to judge whether the part shows it
/// above the measurement noise (see [`crate::identify`] "weak directions").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// Name as in files and APIs (ISO 230-1 without underscores, e.g. `EX0B`; `dR`).
    pub name: String,
    /// `"mm"` or `"rad"` (any text is accepted for user columns).
    pub unit: String,
    /// A typical size of this error on a real machine, in `unit` (> 0).
    pub typical: f64,
}

impl Parameter {
    /// A parameter with a unit and typical magnitude.
    pub fn new(name: &str, unit: &str, typical: f64) -> Self {
        Parameter {
            name: name.to_string(),
            unit: unit.to_string(),
            typical,
        }
    }

    /// A machine error parameter: its unit and typical size are those of its kind
    /// ([`ErrorParam::unit`], [`ErrorParam::typical`]: a location error's component, X/Y/Z in
    /// mm, A/B/C in rad), set where the parameter is defined.
    pub fn of_error(e: &ErrorParam) -> Self {
        Parameter {
            name: e.name(),
            unit: e.unit().to_string(),
            typical: e.typical(),
        }
    }

    /// The tool-radius term `dR` (mm, + = a larger tool).
    pub fn tool_radius() -> Self {
        Parameter::new(TOOL_RADIUS, "mm", TYPICAL_LENGTH_MM)
    }

    /// A parameter named in text that comes in (a file's or a caller's column names): `dR`, a
    /// machine error parameter ([`ErrorParam::parse`]: `EX0B`, `EA0C`, `EXX1`), or a column of
    /// the lab's own, taken as a length in mm (typical 0.01 mm).
    pub fn parse(name: &str) -> Self {
        if name == TOOL_RADIUS {
            return Parameter::tool_radius();
        }
        match ErrorParam::parse(name) {
            Ok(e) => Parameter {
                name: name.to_string(),
                ..Parameter::of_error(&e)
            },
            Err(_) => Parameter::new(name, "mm", TYPICAL_LENGTH_MM),
        }
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
        for (j, p) in parameters.iter().enumerate() {
            if p.name.trim().is_empty() {
                return Err(IdentifyError::EmptyName { index: j });
            }
            if let Some(k) = parameters[..j].iter().position(|q| q.name == p.name) {
                return Err(IdentifyError::DuplicateName {
                    name: p.name.clone(),
                    first: k,
                    second: j,
                });
            }
            if !(p.typical.is_finite() && p.typical > 0.0) {
                return Err(IdentifyError::BadTypical {
                    name: p.name.clone(),
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
                        column: parameters[j].name.clone(),
                        value: v,
                    });
                }
            }
        }
        Ok(Design { parameters, matrix })
    }

    /// From column-major data (`data[j*n + i]` = row i, column j), parameter names following
    /// [`Parameter::parse`].
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
        let params = names.iter().map(|s| Parameter::parse(s)).collect();
        Design::try_new(params, DMatrix::from_column_slice(n, p, data))
    }

    /// The design of a sensitivity matrix (paper 000 eq. 14 per unit error, Figure 19 columns);
    /// units and typical magnitudes follow [`Parameter::parse`].
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
    /// Column index of a parameter name.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.parameters.iter().position(|p| p.name == name)
    }
    /// `A·x` (mm).
    pub fn predict(&self, x: &[f64]) -> Vec<f64> {
        let xv = nalgebra::DVector::from_column_slice(x);
        (&self.matrix * xv).iter().copied().collect()
    }
    /// Parameter vector from `(name, value)` pairs (others 0); unknown names are an error.
    pub fn vector_from(&self, values: &[(String, f64)]) -> Result<Vec<f64>, IdentifyError> {
        let mut x = vec![0.0; self.cols()];
        for (name, v) in values {
            let j = self
                .index_of(name)
                .ok_or_else(|| IdentifyError::UnknownParameter {
                    name: name.clone(),
                    known: self.names().join(", "),
                })?;
            x[j] = *v;
        }
        Ok(x)
    }
    /// The parameter names.
    pub fn names(&self) -> Vec<String> {
        self.parameters.iter().map(|p| p.name.clone()).collect()
    }
}
