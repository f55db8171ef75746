//! Reading tables of named columns from CSV text (no file access: the caller passes the text).
//!
//! Used for the signature tables in the format of `effect_signatures.csv`
//! (`id,curve,s,<effect>.<param>,…`, one candidate = its group of `<effect>.<param>` columns)
//! and the sensitivity tables (`id,curve,EC0Y,…`).

use nalgebra::DMatrix;

use super::data::{Candidate, NamedColumns};
use super::GapError;

/// A CSV table: header names and rows of text fields.
#[derive(Debug, Clone)]
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// Parses comma-separated text with a header row.
    pub fn parse(text: &str) -> Result<Self, GapError> {
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| GapError::Table {
                line: 1,
                reason: e.to_string(),
            })?
            .iter()
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (k, rec) in rdr.records().enumerate() {
            let rec = rec.map_err(|e| GapError::Table {
                line: k + 2,
                reason: e.to_string(),
            })?;
            if rec.len() != header.len() {
                return Err(GapError::Table {
                    line: k + 2,
                    reason: format!("{} fields, expected {}", rec.len(), header.len()),
                });
            }
            rows.push(rec.iter().map(str::to_string).collect());
        }
        Ok(Self { header, rows })
    }

    fn index(&self, name: &str) -> Result<usize, GapError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| GapError::MissingColumn(name.to_string()))
    }

    /// A numeric column.
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>, GapError> {
        let j = self.index(name)?;
        self.rows
            .iter()
            .enumerate()
            .map(|(k, r)| {
                r[j].parse::<f64>().map_err(|_| GapError::Table {
                    line: k + 2,
                    reason: format!("`{}` in column `{name}` is not a number", r[j]),
                })
            })
            .collect()
    }

    /// A text column.
    pub fn text(&self, name: &str) -> Result<Vec<String>, GapError> {
        let j = self.index(name)?;
        Ok(self.rows.iter().map(|r| r[j].clone()).collect())
    }

    /// The named numeric columns as a matrix.
    pub fn columns(&self, names: &[&str]) -> Result<NamedColumns, GapError> {
        let cols: Vec<Vec<f64>> = names
            .iter()
            .map(|n| self.numbers(n))
            .collect::<Result<_, _>>()?;
        let n = self.rows.len();
        let m = DMatrix::from_fn(n, cols.len(), |i, j| cols[j][i]);
        NamedColumns::try_new(names.iter().map(|s| s.to_string()).collect(), m)
    }

    /// Candidates from every `<effect>.<param>` column, grouped by effect in header order.
    pub fn candidates(&self) -> Result<Vec<Candidate>, GapError> {
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
                let mut cols = self.columns(&refs)?;
                cols.names = params;
                Ok(Candidate {
                    id: effect,
                    signature: cols,
                })
            })
            .collect()
    }
}
