//! The controllers' dialects of the part program: the statement forms each one reads for the
//! few things the finishing pass needs (start block, tool call, length compensation, spindle,
//! coolant, retract in machine coordinates, inverse-time feed, tool-centre-point mode, end),
//! its comment syntax and its word lengths.
//!
//! | | iso | fanuc | linuxcnc | sinumerik | heidenhain |
//! |---|---|---|---|---|---|
//! | source | ISO 6983-1 words as RS274/NGC reads them (NIST IR 6556) | Series 30i-B operator's manual (B-64484EN) | LinuxCNC G-code reference | SINUMERIK 840D sl programming manual, Fundamentals | TNC 640 Klartext user's manual |
//! | comment | `( … )` | `( … )` | `( … )` | `; …` | `; …` |
//! | start | `G21 G17 G90 G94 G40 G49 G80` | same | same | `G17 G71 G90 G94 G40` + `TRAFOOF` | `BEGIN PGM … MM` |
//! | tool | `T1 M06`, `G43 H1` | same | same | `T1 M6`, `D1` | `TOOL CALL 1 Z S…` (length from the tool table) |
//! | machine-Z retract | `G53 G00 Z0` | same | same | `G0 SUPA Z0` | `L Z+0 R0 FMAX M91` |
//! | rotary feed | `G93` (F = 1/min) | `G93` | `G93` (F on every block) | `G93` | F per block (see below) |
//! | TCP | none | `G43.4 H1` … `G49` | none (a kinematics module, set in the INI file) | `TRAORI` … `TRAFOOF` | `FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS` … `FUNCTION RESET TCPM` |
//!
//! Heidenhain's Klartext has no inverse-time feed: a block's F is written so that the
//! controller's contouring feed over the combined axis distance (degrees counted as mm, no
//! M116) gives the programmed tool-tip speed; `--tcp` (FUNCTION TCPM F TCP) is the form that
//! needs no such assumption.
//!
//! Numbers: every word has at most 8 significant digits (the common controller limit, Fanuc's
//! 8-digit input): linear axes in mm and rotary axes in degrees with [`Dialect::decimals`]
//! decimals (|value| < 1000), F with at most 8 digits. Comments are ASCII, without parentheses
//! or `;` inside (a `;` ends the block on LinuxCNC and is rejected inside `( … )` by parsers).

use serde::{Deserialize, Serialize};

/// A controller's dialect of the part program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    /// ISO 6983-1 words as RS274/NGC reads them.
    #[default]
    Iso,
    Fanuc,
    Linuxcnc,
    Sinumerik,
    Heidenhain,
}

impl Dialect {
    pub const ALL: [Dialect; 5] = [
        Dialect::Iso,
        Dialect::Fanuc,
        Dialect::Linuxcnc,
        Dialect::Sinumerik,
        Dialect::Heidenhain,
    ];

    /// `iso`, `fanuc`, `linuxcnc`, `sinumerik`, `heidenhain`.
    pub fn id(self) -> &'static str {
        match self {
            Dialect::Iso => "iso",
            Dialect::Fanuc => "fanuc",
            Dialect::Linuxcnc => "linuxcnc",
            Dialect::Sinumerik => "sinumerik",
            Dialect::Heidenhain => "heidenhain",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Dialect::ALL.into_iter().find(|d| d.id() == s)
    }

    /// The controller family's name for headers.
    pub fn describe(self) -> &'static str {
        match self {
            Dialect::Iso => "ISO 6983-1 (RS274/NGC words)",
            Dialect::Fanuc => "Fanuc (Series 30i-B)",
            Dialect::Linuxcnc => "LinuxCNC",
            Dialect::Sinumerik => "Siemens SINUMERIK 840D sl",
            Dialect::Heidenhain => "Heidenhain TNC 640 Klartext",
        }
    }

    /// Decimals of the axis words (mm and degrees): 4 on Fanuc (increment system IS-C,
    /// 0.0001 mm / 0.0001 deg, 8 digits up to 9999.9999), 5 elsewhere (|value| < 1000: 8 digits).
    pub fn decimals(self) -> usize {
        match self {
            Dialect::Fanuc => 4,
            _ => 5,
        }
    }

    /// Whether the controller has a tool-centre-point mode this program can use.
    pub fn offers_tcp(self) -> bool {
        matches!(
            self,
            Dialect::Fanuc | Dialect::Sinumerik | Dialect::Heidenhain
        )
    }

    /// Whether the controller has inverse-time feed (G93).
    pub fn inverse_time(self) -> bool {
        self != Dialect::Heidenhain
    }

    /// One comment line in the dialect's syntax, ASCII only: `(text)` or `; text`.
    pub fn comment(self, text: &str) -> String {
        let clean = ascii_comment(text);
        match self {
            Dialect::Sinumerik | Dialect::Heidenhain => format!("; {clean}"),
            _ => format!("({clean})"),
        }
    }
}

/// `text` with every character a comment of any dialect accepts: printable ASCII without
/// parentheses or `;` (`(`/`)` → `[`/`]`, `;` → `,`, `µ` → `u`, others → `?`).
pub fn ascii_comment(text: &str) -> String {
    text.trim_end()
        .chars()
        .map(|c| match c {
            '(' => '[',
            ')' => ']',
            ';' => ',',
            'µ' | 'μ' => 'u',
            '°' => 'd',
            c if c == ' ' || c.is_ascii_graphic() => c,
            _ => '?',
        })
        .collect()
}

/// `value` with `decimals` decimals, trailing zeros kept off only after the point; `-0` → `0`;
/// `signed` writes `+` before positive values (Klartext).
pub fn number(value: f64, decimals: usize, signed: bool) -> String {
    let mut s = format!("{value:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s.remove(0);
    }
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if signed && !s.starts_with('-') {
        s.insert(0, '+');
    }
    s
}

/// A feed word's value with at most 8 significant digits and at most 4 decimals.
pub fn feed_number(value: f64) -> String {
    let int_digits = if value.abs() >= 1.0 {
        value.abs().log10().floor() as usize + 1
    } else {
        1
    };
    number(value, 8usize.saturating_sub(int_digits).min(4), false)
}

/// Significant digits of a word's number (`-012.3400` → 6: leading zeros not counted).
pub fn significant_digits(num: &str) -> usize {
    let digits: String = num.chars().filter(|c| c.is_ascii_digit()).collect();
    let trimmed = digits.trim_start_matches('0');
    trimmed.len().max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_comments() {
        assert_eq!(number(499.889, 5, false), "499.889");
        assert_eq!(number(-0.000001, 5, false), "0");
        assert_eq!(number(12.0, 4, true), "+12");
        assert_eq!(number(-1.23456789, 5, true), "-1.23457");
        assert_eq!(feed_number(3533.568912), "3533.5689");
        assert_eq!(feed_number(123456.789), "123456.79");
        assert_eq!(significant_digits("-0499.88900"), 8);
        assert_eq!(
            Dialect::Fanuc.comment("tol (1 µm); L0 = 5"),
            "(tol [1 um], L0 = 5)"
        );
        assert_eq!(Dialect::Heidenhain.comment("a;b"), "; a,b");
    }
}
