//! Delimited tables with a header row: finding the header and its separator (comma, semicolon,
//! tab or runs of spaces, detected from the header and the first rows) and splitting the data
//! rows, with every row of the wrong shape reported (truncated, too many fields, another
//! separator than the header's). Fields are split with the `csv` crate one line at a time, so a
//! stray quote can never swallow the lines after it.

use serde::{Deserialize, Serialize};

use super::error::{RowProblem, RowProblemKind};
use super::header::{recognised, Layout};
use super::number::has_decimal_comma;
use crate::numerics::parallel::{map, Threads};

/// Field separator of a delimited table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Separator {
    Tab,
    Semicolon,
    Comma,
    /// One or more spaces (or tabs mixed with spaces).
    Spaces,
}

impl Separator {
    /// Candidates, in the order ties are broken.
    pub const ALL: [Separator; 4] = [Self::Tab, Self::Semicolon, Self::Comma, Self::Spaces];

    pub fn describe(self) -> &'static str {
        match self {
            Self::Tab => "tab",
            Self::Semicolon => "semicolon ';'",
            Self::Comma => "comma ','",
            Self::Spaces => "runs of spaces",
        }
    }

    fn byte(self) -> Option<u8> {
        match self {
            Self::Tab => Some(b'\t'),
            Self::Semicolon => Some(b';'),
            Self::Comma => Some(b','),
            Self::Spaces => None,
        }
    }
}

/// Splits one line into trimmed fields.
pub fn split(line: &str, sep: Separator) -> Vec<String> {
    match sep.byte() {
        None => line.split_whitespace().map(str::to_string).collect(),
        // Without quotes or carriage returns the csv crate splits at every separator and trims
        // (Unicode whitespace): the same fields without building a reader per line (the header
        // search and the mixed-separator check split many lines).
        Some(b) if !line.is_empty() && !line.bytes().any(|c| c == b'"' || c == b'\r') => line
            .split(b as char)
            .map(|f| f.trim().to_string())
            .collect(),
        Some(b) => {
            let mut reader = csv::ReaderBuilder::new()
                .delimiter(b)
                .has_headers(false)
                .flexible(true)
                .trim(csv::Trim::All)
                .buffer_capacity(line.len() + 64)
                .from_reader(line.as_bytes());
            let mut record = csv::StringRecord::new();
            match reader.read_record(&mut record) {
                Ok(true) => record.iter().map(str::to_string).collect(),
                // The input is valid UTF-8 text of one line, so a read cannot fail; an empty
                // line has no fields.
                _ => Vec::new(),
            }
        }
    }
}

/// One record of a table: where it starts, its fields, and the last line it reached when an
/// unbalanced quote carried it over several lines.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Index into the lines given to [`split_all`].
    pub index: usize,
    pub line: usize,
    pub fields: Vec<String>,
    pub spans_to: Option<usize>,
}

/// Splits all `data` lines in one pass of the `csv` crate (runs of spaces: per line). A record
/// that a stray quote carried over several lines is marked (`spans_to`), never merged silently.
pub fn split_all(data: &[(usize, &str)], sep: Separator) -> Vec<Record> {
    split_all_on(data, sep, Threads::ONE)
}

/// Lines split a chunk at a time on the threads given ([`split_all_on`]), in chunks of this many
/// (the chunks do not depend on the threads).
pub const SPLIT_CHUNK: usize = 4096;

/// [`split_all`], the lines of the common case (no quote, no carriage return) split in chunks
/// of [`SPLIT_CHUNK`] side by side on `threads` threads: the same records (a scan's 200,000
/// lines were 0.1 s of one thread, issue 31).
pub fn split_all_on(data: &[(usize, &str)], sep: Separator, threads: Threads) -> Vec<Record> {
    let Some(b) = sep.byte() else {
        return data
            .iter()
            .enumerate()
            .map(|(index, &(line, t))| Record {
                index,
                line,
                fields: split(t, sep),
                spans_to: None,
            })
            .collect();
    };
    // Lines without quotes or carriage returns split exactly as the `csv` crate splits them:
    // one record per line, fields between the separators (the common case, without the copy
    // of the whole table and the per-record overhead of the reader).
    if data
        .iter()
        .all(|(_, t)| !t.bytes().any(|c| c == b'"' || c == b'\r'))
    {
        let sep = b as char;
        let starts: Vec<usize> = (0..data.len()).step_by(SPLIT_CHUNK).collect();
        return map(threads, &starts, |&first| {
            data[first..data.len().min(first + SPLIT_CHUNK)]
                .iter()
                .enumerate()
                .map(|(i, &(line, t))| Record {
                    index: first + i,
                    line,
                    fields: t.split(sep).map(|f| f.trim().to_string()).collect(),
                    spans_to: None,
                })
                .collect::<Vec<_>>()
        })
        .into_iter()
        .flatten()
        .collect();
    }
    split_all_csv(data, b)
}

/// [`split_all`] by the `csv` crate over the whole table (quotes may carry a record over lines).
fn split_all_csv(data: &[(usize, &str)], b: u8) -> Vec<Record> {
    let joined = data.iter().map(|(_, t)| *t).collect::<Vec<_>>().join("\n");
    // No csv-level trimming (it copies every record); fields are trimmed when made Strings.
    let mut reader = csv::ReaderBuilder::new()
        .delimiter(b)
        .has_headers(false)
        .flexible(true)
        .from_reader(joined.as_bytes());
    let mut starts: Vec<(usize, Vec<String>)> = Vec::with_capacity(data.len());
    let mut record = csv::ByteRecord::new();
    let last = data.len().saturating_sub(1);
    // Reading from a byte slice cannot fail (no I/O, byte records need no UTF-8 check).
    while let Ok(true) = reader.read_byte_record(&mut record) {
        let index = record
            .position()
            .map_or(starts.len(), |p| (p.line() as usize).saturating_sub(1));
        let fields = record
            .iter()
            .map(|f| match std::str::from_utf8(f) {
                Ok(t) => t.trim().to_string(),
                Err(_) => String::from_utf8_lossy(f).trim().to_string(),
            })
            .collect();
        starts.push((index.min(last), fields));
    }
    let ends: Vec<usize> = starts
        .iter()
        .skip(1)
        .map(|s| s.0)
        .chain(std::iter::once(data.len()))
        .collect();
    starts
        .into_iter()
        .zip(ends)
        .map(|((index, fields), end)| Record {
            index,
            line: data[index].0,
            fields,
            spans_to: (end > index + 1).then(|| data[end - 1].0),
        })
        .collect()
}

/// Splits a header row; with runs of spaces a bracketed unit standing alone (`dev (um)`) is
/// joined to the name before it. Trailing empty names (a trailing separator) are dropped.
pub fn split_header(line: &str, sep: Separator) -> Vec<String> {
    let mut fields = split(line, sep);
    if sep == Separator::Spaces {
        let mut joined: Vec<String> = Vec::with_capacity(fields.len());
        for f in fields {
            let unit_only = (f.starts_with('[') && f.ends_with(']'))
                || (f.starts_with('(') && f.ends_with(')'));
            match joined.last_mut() {
                Some(prev) if unit_only => {
                    prev.push(' ');
                    prev.push_str(&f);
                }
                _ => joined.push(f),
            }
        }
        fields = joined;
    }
    while fields.last().is_some_and(|f| f.is_empty()) {
        fields.pop();
    }
    fields
}

/// The header row found: index into the content lines, separator, names.
#[derive(Debug, Clone, PartialEq)]
pub struct HeaderRow {
    pub content_index: usize,
    pub line: usize,
    pub separator: Separator,
    pub fields: Vec<String>,
}

/// How many of the first content lines may precede the header (report titles and the like).
const HEADER_SEARCH: usize = 10;

/// Finds the header: the first of the first content lines where some separator gives at least
/// two recognised names; among separators the one recognising most names wins, ties broken by
/// agreement with the next data row's field count, then by the order of [`Separator::ALL`].
pub fn find_header(content: &[(usize, &str)]) -> Option<HeaderRow> {
    for (index, &(line, text)) in content.iter().take(HEADER_SEARCH).enumerate() {
        let next = content.get(index + 1).map(|&(_, t)| t);
        let mut best: Option<(usize, bool, Separator, Vec<String>)> = None;
        for sep in Separator::ALL {
            let fields = split_header(text, sep);
            if fields.len() < 2 {
                continue;
            }
            let score = recognised(&fields);
            let agrees = next.is_some_and(|t| split(t, sep).len() == fields.len());
            let better = match &best {
                None => true,
                Some((s, a, _, _)) => score > *s || (score == *s && agrees && !*a),
            };
            if better {
                best = Some((score, agrees, sep, fields));
            }
        }
        if let Some((score, _, separator, fields)) = best {
            if score >= 2 {
                return Some(HeaderRow {
                    content_index: index,
                    line,
                    separator,
                    fields,
                });
            }
        }
    }
    None
}

/// One data row split into fields.
#[derive(Debug, Clone, PartialEq)]
pub struct RawRow {
    pub line: usize,
    pub fields: Vec<String>,
}

/// Rows of a delimited table and whether any number used a decimal comma.
#[derive(Debug, Clone, PartialEq)]
pub struct SplitRows {
    pub rows: Vec<RawRow>,
    pub problems: Vec<RowProblem>,
    pub decimal_comma: bool,
}

/// The first 120 characters of a line, for messages.
pub fn excerpt(text: &str) -> String {
    let t = text.trim();
    if t.chars().count() > 120 {
        format!("{}…", t.chars().take(120).collect::<String>())
    } else {
        t.to_string()
    }
}

/// The problems of a record that an unbalanced quote carried from `data[index]` to the line
/// `last`: one per line, so every swallowed line is listed.
pub fn unbalanced_quote(data: &[(usize, &str)], index: usize, last: usize) -> Vec<RowProblem> {
    let (line, text) = data[index];
    let mut out = vec![RowProblem {
        line,
        column: None,
        kind: RowProblemKind::UnbalancedQuote,
        found: excerpt(text),
        expected: format!(
            "a closing '\"' on the same line; lines {line} to {last} were read as one row and none of them is used"
        ),
    }];
    for &(l, t) in data[index + 1..].iter().take_while(|(l, _)| *l <= last) {
        out.push(RowProblem {
            line: l,
            column: None,
            kind: RowProblemKind::UnbalancedQuote,
            found: excerpt(t),
            expected: format!("a row of its own; the quote opened on line {line} swallowed it"),
        });
    }
    out
}

/// Splits the data rows after the header and checks their shape against `layout` (the lines
/// split side by side on `threads` threads, [`split_all_on`]).
pub fn split_rows(
    data: &[(usize, &str)],
    sep: Separator,
    layout: &Layout,
    threads: Threads,
) -> SplitRows {
    let width = layout.width();
    let mut out = SplitRows {
        rows: Vec::with_capacity(data.len()),
        problems: Vec::new(),
        decimal_comma: false,
    };
    let header_names = layout
        .columns
        .iter()
        .map(|c| c.header.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    for rec in split_all_on(data, sep, threads) {
        let (line, text, mut fields) = (rec.line, data[rec.index].1, rec.fields);
        if let Some(last) = rec.spans_to {
            out.problems.extend(unbalanced_quote(data, rec.index, last));
            continue;
        }
        // A trailing separator leaves empty fields beyond the header: harmless.
        while fields.len() > width && fields.last().is_some_and(|f| f.is_empty()) {
            fields.pop();
        }
        // Missing trailing columns that are only extra columns (comments) count as empty.
        if fields.len() < width
            && layout.columns[fields.len()..]
                .iter()
                .all(|c| c.role.is_none())
        {
            fields.resize(width, String::new());
        }
        if fields.len() == width {
            if sep != Separator::Comma && !out.decimal_comma {
                out.decimal_comma = fields.iter().any(|f| has_decimal_comma(f));
            }
            out.rows.push(RawRow { line, fields });
            continue;
        }
        let other = Separator::ALL
            .into_iter()
            .find(|&s| s != sep && split(text, s).len() == width);
        let (kind, expected) = if let Some(s) = other {
            (
                RowProblemKind::MixedSeparators,
                format!(
                    "{width} fields separated by {} as in the header, but this line uses {}",
                    sep.describe(),
                    s.describe()
                ),
            )
        } else if fields.len() < width {
            (
                RowProblemKind::Truncated,
                format!(
                    "{width} fields ({header_names}), found only {}: the row looks cut short",
                    fields.len()
                ),
            )
        } else {
            let hint = if sep == Separator::Comma && fields.iter().any(|f| f.is_empty()) {
                ""
            } else if sep == Separator::Comma {
                "; a decimal comma in a comma-separated file? use '.' for decimals or ';' as separator"
            } else {
                ""
            };
            (
                RowProblemKind::TooManyFields,
                format!(
                    "{width} fields ({header_names}), found {}{hint}",
                    fields.len()
                ),
            )
        };
        out.problems.push(RowProblem {
            line,
            column: None,
            kind,
            found: excerpt(text),
            expected,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quote_free_lines_split_as_the_csv_reader_splits_them() {
        let lines = [
            "1, A_Z11 ,1.5,2,3,,",
            "2;x,y",
            " 3 ,\t4\t, 5e-3 ",
            ",",
            "7,\u{a0}8\u{a0},9",
        ];
        let data: Vec<(usize, &str)> = lines.iter().enumerate().map(|(i, t)| (i + 2, *t)).collect();
        for sep in [Separator::Comma, Separator::Semicolon, Separator::Tab] {
            let b = sep.byte().unwrap();
            assert_eq!(split_all(&data, sep), split_all_csv(&data, b), "{sep:?}");
            for (_, t) in &data {
                let csv_fields: Vec<String> = split_all_csv(&[(1, t)], b)
                    .into_iter()
                    .flat_map(|r| r.fields)
                    .collect();
                assert_eq!(split(t, sep), csv_fields, "{sep:?} {t:?}");
            }
        }
    }

    #[test]
    fn header_detection() {
        let c = [(1, "id;x;y;z;dev"), (2, "1;0,5;1;2;0,001")];
        let h = find_header(&c).unwrap();
        assert_eq!(h.separator, Separator::Semicolon);
        let c = [(1, "Point  X  Y  Z  dev (um)"), (2, "1 0.5 1 2 1")];
        let h = find_header(&c).unwrap();
        assert_eq!(h.separator, Separator::Spaces);
        assert_eq!(h.fields[4], "dev (um)");
        let c = [(1, "id\tx\ty\tz"), (2, "1\t2\t3\t4")];
        assert_eq!(find_header(&c).unwrap().separator, Separator::Tab);
        assert!(find_header(&[(1, "1,2,3,4")]).is_none());
        assert_eq!(split("a,\"b,c\", d", Separator::Comma), ["a", "b,c", "d"]);
    }
}
