//! The part after compensation predicted on curves the fit did not see (issue 32 item 4).
//!
//! The in-sample residual of a fit flatters it: the fit chose its values to make exactly those
//! points small. Here each curve of the file is withheld in turn: the final answer's design
//! (its location errors and the columns fitted with them, [`crate::analysis::Analysis::design`])
//! is fitted by least squares on the other curves' used points, the entry rule
//! ([`super::entry`]) picks the errors that fit would enter, and the withheld curve's part
//! after compensation is predicted as `measured_i − Σ_{j entered} A_ij x_j` (the entered
//! errors' part removed, everything else kept: [`super::part`]). The report is the spread of
//! those predictions over all withheld points: what the compensation would leave on points it
//! was not fitted to. (With the S-shape's four curves `A_Z11`, `A_Z25`, `B_Z11`, `B_Z25`,
//! shared/spec/s-shape.md, every fit sees three curves, both heights of one flank and one of
//! the other.) The std of these refits are the fit's alone (no model spread: no diagnosis is
//! run on a part of the file).

use nalgebra::DMatrix;
use serde::Serialize;

use super::entry::entry_rule;
use super::part::Spread;
use crate::analysis::Analysis;
use crate::identify::{identify, Design, IdentifyOptions, Observations, Parameter};
use crate::machine::{ErrorParam, LocationError};
use crate::parameter::ParamId;

/// One withheld curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WithheldCurve {
    pub curve: String,
    /// Used points on the curve.
    pub points: usize,
    /// The errors the fit without this curve enters, and their values (same order).
    pub entered: Vec<String>,
    pub values: Vec<f64>,
    /// Measured deviations on the curve.
    pub measured: Spread,
    /// Predicted deviations after compensation on the curve.
    pub after: Spread,
}

/// One withheld point's prediction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WithheldPoint {
    pub id: String,
    pub curve: String,
    pub measured: f64,
    /// Predicted deviation after compensation by the fit without its curve (mm).
    pub after: f64,
}

/// The prediction on withheld curves.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Withheld {
    pub curves: Vec<WithheldCurve>,
    pub points: Vec<WithheldPoint>,
    /// Over every withheld point.
    pub measured: Spread,
    pub after: Spread,
    /// Curves that could not be withheld, with why (too few points left, the fit failed).
    pub skipped: Vec<String>,
}

/// The location errors of the design (index, error).
pub fn location_columns(a: &Analysis) -> Vec<(usize, LocationError)> {
    let chain = a.settings.machine.chain(a.settings.l0);
    a.design
        .parameters
        .iter()
        .enumerate()
        .filter_map(|(j, p)| match p {
            ParamId::Machine(ErrorParam::Location(l)) if chain.axis(l.axis).is_some() => {
                Some((j, *l))
            }
            _ => None,
        })
        .collect()
}

/// The final answer's design as an identification design; a parameter without a typical size
/// (an effect's) gets the size that moves the part by 1 µm at most.
fn design_of(a: &Analysis) -> Option<Design> {
    let cols = &a.design.columns;
    let n = cols.first()?.len();
    let params = a
        .design
        .parameters
        .iter()
        .zip(cols)
        .map(|(id, c)| {
            let peak = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let typical = id
                .typical()
                .unwrap_or(if peak > 0.0 { 1e-3 / peak } else { 1.0 });
            Parameter::new(id.clone(), typical)
        })
        .collect();
    let matrix = DMatrix::from_fn(n, cols.len(), |i, j| cols[j][i]);
    Design::try_new(params, matrix).ok()
}

/// Each curve withheld in turn (module docs).
pub fn withheld(a: &Analysis) -> Withheld {
    let pts = &a.identification.points;
    let mut curves: Vec<String> = Vec::new();
    for p in pts.iter().filter(|p| p.used) {
        if !curves.contains(&p.curve) {
            curves.push(p.curve.clone());
        }
    }
    let location = location_columns(a);
    let names: Vec<(String, LocationError)> = location
        .iter()
        .map(|(j, l)| (a.design.parameters[*j].name(), *l))
        .collect();
    let mut out = Withheld {
        curves: Vec::new(),
        points: Vec::new(),
        measured: Spread::of(&[]),
        after: Spread::of(&[]),
        skipped: Vec::new(),
    };
    let Some(design) = design_of(a) else {
        out.skipped
            .push("the final answer has no design columns".to_string());
        return out;
    };
    let mut iopts = IdentifyOptions::default();
    if a.settings.noise_sigma.is_some() {
        if let Some(s) = a.identification.sigma {
            iopts = iopts.with_sigma(s);
        }
    }
    for c in &curves {
        let weights: Vec<f64> = pts
            .iter()
            .map(|p| if p.used && p.curve != *c { 1.0 } else { 0.0 })
            .collect();
        let fitted = weights.iter().filter(|w| **w > 0.0).count();
        if fitted <= design.cols() {
            out.skipped.push(format!(
                "{c}: {fitted} points left for {} parameters",
                design.cols()
            ));
            continue;
        }
        let obs = Observations::new(
            pts.iter().map(|p| p.id.clone()).collect(),
            pts.iter().map(|p| p.curve.clone()).collect(),
            pts.iter().map(|p| p.measured).collect(),
        )
        .with_weights(weights);
        let id = match identify(&design, &obs, &iopts) {
            Ok(id) => id,
            Err(e) => {
                out.skipped.push(format!("{c}: {e}"));
                continue;
            }
        };
        let entries = entry_rule(&id, &names);
        let removed: Vec<(usize, f64)> = location
            .iter()
            .zip(&entries)
            .filter(|(_, e)| e.entered())
            .map(|((j, _), e)| (*j, e.value))
            .collect();
        let on: Vec<WithheldPoint> = pts
            .iter()
            .enumerate()
            .filter(|(_, p)| p.used && p.curve == *c)
            .map(|(i, p)| WithheldPoint {
                id: p.id.clone(),
                curve: c.clone(),
                measured: p.measured,
                after: p.measured
                    - removed
                        .iter()
                        .map(|(j, x)| a.design.columns[*j][i] * x)
                        .sum::<f64>(),
            })
            .collect();
        out.curves.push(WithheldCurve {
            curve: c.clone(),
            points: on.len(),
            entered: entries
                .iter()
                .filter(|e| e.entered())
                .map(|e| e.name.clone())
                .collect(),
            values: removed.iter().map(|(_, x)| *x).collect(),
            measured: Spread::of(&on.iter().map(|p| p.measured).collect::<Vec<_>>()),
            after: Spread::of(&on.iter().map(|p| p.after).collect::<Vec<_>>()),
        });
        out.points.extend(on);
    }
    out.measured = Spread::of(&out.points.iter().map(|p| p.measured).collect::<Vec<_>>());
    out.after = Spread::of(&out.points.iter().map(|p| p.after).collect::<Vec<_>>());
    out
}
