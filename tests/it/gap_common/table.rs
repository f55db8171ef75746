//! Test support: tables of named columns from CSV text (the reference vectors of
//! `tests/data/reference/`; no file access: the caller passes the text).
//!
//! Used for the signature tables in the format of `effect_signatures.csv`
//! (`id,curve,s,<effect>.<param>,…`, one candidate = its group of `<effect>.<param>` columns)
//! and the sensitivity tables (`id,curve,EC0Y,…`).

use nalgebra::DMatrix;

use testpiece::effects::{Candidate, NamedColumns};
use testpiece::parameter::ParamId;

/// Why a table could not be read (test support: the message is what a failing test prints).
pub type TableError = String;

/// A CSV table: header names and rows of text fields.
#[derive(Debug, Clone)]
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// Parses comma-separated text with a header row.
    pub fn parse(text: &str) -> Result<Self, TableError> {
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| format!("table line 1: {e}"))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (k, rec) in rdr.records().enumerate() {
            let rec = rec.map_err(|e| format!("table line {}: {e}", k + 2))?;
            if rec.len() != header.len() {
                return Err(format!(
                    "table line {}: {} fields, expected {}",
                    k + 2,
                    rec.len(),
                    header.len()
                ));
            }
            rows.push(rec.iter().map(str::to_string).collect());
        }
        Ok(Self { header, rows })
    }

    fn index(&self, name: &str) -> Result<usize, TableError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("column `{name}` not found in the table"))
    }

    /// A numeric column.
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>, TableError> {
        let j = self.index(name)?;
        self.rows
            .iter()
            .enumerate()
            .map(|(k, r)| {
                r[j].parse::<f64>().map_err(|_| {
                    format!(
                        "table line {}: `{}` in column `{name}` is not a number",
                        k + 2,
                        r[j]
                    )
                })
            })
            .collect()
    }

    /// A text column.
    pub fn text(&self, name: &str) -> Result<Vec<String>, TableError> {
        let j = self.index(name)?;
        Ok(self.rows.iter().map(|r| r[j].clone()).collect())
    }

    /// The named numeric columns as a matrix.
    pub fn columns(&self, names: &[&str]) -> Result<NamedColumns, TableError> {
        let cols: Vec<Vec<f64>> = names
            .iter()
            .map(|n| self.numbers(n))
            .collect::<Result<_, _>>()?;
        let n = self.rows.len();
        let m = DMatrix::from_fn(n, cols.len(), |i, j| cols[j][i]);
        // The header's names are read into parameter ids (text that comes in).
        let params = names
            .iter()
            .map(|s| s.parse::<ParamId>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        NamedColumns::try_new(params, m).map_err(|e| e.to_string())
    }

    /// Candidates from every `<effect>.<param>` column, grouped by effect in header order.
    pub fn candidates(&self) -> Result<Vec<Candidate>, TableError> {
        let mut groups: Vec<(String, Vec<String>)> = Vec::new();
        for h in &self.header {
            let Some((effect, param)) = h.split_once('.') else {
                continue;
            };
            match groups.iter_mut().find(|(e, _)| e == effect) {
                Some((_, ps)) => ps.push(param.to_string()),
                None => groups.push((effect.to_string(), vec![param.to_string()])),
            }
        }
        groups
            .into_iter()
            .map(|(effect, params)| {
                let full: Vec<String> = params.iter().map(|p| format!("{effect}.{p}")).collect();
                let refs: Vec<&str> = full.iter().map(String::as_str).collect();
                let cols = self.columns(&refs)?;
                Ok(Candidate {
                    effect: effect.parse().map_err(|e| format!("{e}"))?,
                    signature: cols.into(),
                    family: None,
                })
            })
            .collect()
    }
}
