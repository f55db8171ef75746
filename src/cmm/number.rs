//! Numbers as CMM exports write them: `-0.0123`, `1.5e-3`, `+2`, a decimal comma (`0,0123`)
//! where the separator is not a comma, the Unicode minus `−`. `NaN`, `inf` and values beyond the
//! range of a double are refused as not finite.

/// Why a field is not a usable number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberError {
    Empty,
    NotNumeric,
    NotFinite,
}

/// Whether `text` uses a decimal comma (`0,0123`: one comma, no point).
pub fn has_decimal_comma(text: &str) -> bool {
    let t = text.trim();
    t.matches(',').count() == 1 && !t.contains('.') && t.chars().any(|c| c.is_ascii_digit())
}

/// Parses one field. `decimal_comma`: accept `0,0123` (only where the separator is not a comma).
pub fn parse_number(text: &str, decimal_comma: bool) -> Result<f64, NumberError> {
    let t = text.trim();
    // Quotes are rare: strip them only when there is one at an end (same result, no scan).
    let t = if t.starts_with('"') || t.ends_with('"') {
        t.trim_matches('"').trim()
    } else {
        t
    };
    if t.is_empty() {
        return Err(NumberError::Empty);
    }
    if let Ok(v) = t.parse::<f64>() {
        return if v.is_finite() {
            Ok(v)
        } else {
            Err(NumberError::NotFinite)
        };
    }
    let mut s = t.replace('\u{2212}', "-");
    if decimal_comma && has_decimal_comma(&s) {
        s = s.replace(',', ".");
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(NumberError::NotFinite),
        Err(_) => {
            let l = s.to_lowercase();
            if l.contains("nan") || l.contains("inf") || l.contains("#ind") {
                Err(NumberError::NotFinite)
            } else {
                Err(NumberError::NotNumeric)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number(" -0.0123 ", false), Ok(-0.0123));
        assert_eq!(parse_number("-0,0123", true), Ok(-0.0123));
        assert_eq!(parse_number("-0,0123", false), Err(NumberError::NotNumeric));
        assert_eq!(parse_number("\u{2212}1.5e-3", false), Ok(-1.5e-3));
        assert_eq!(parse_number("NaN", false), Err(NumberError::NotFinite));
        assert_eq!(parse_number("-inf", false), Err(NumberError::NotFinite));
        assert_eq!(parse_number("1e400", false), Err(NumberError::NotFinite));
        assert_eq!(parse_number("-1.#IND", false), Err(NumberError::NotFinite));
        assert_eq!(parse_number("", false), Err(NumberError::Empty));
        assert_eq!(parse_number("12a", false), Err(NumberError::NotNumeric));
    }
}
