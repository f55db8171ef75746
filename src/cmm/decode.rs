//! Bytes to text: size limit, binary detection, UTF-8 with or without BOM, UTF-16 with BOM,
//! otherwise Windows-1252 (`µ` as byte 0xB5), as cmm-csv.md asks.

use std::borrow::Cow;

use super::error::CmmError;

/// The text of a file and how it was encoded: the file's own bytes when they are UTF-8 (a dense
/// scan's 15 MB not copied, issue 31), else the text converted.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoded<'a> {
    pub text: Cow<'a, str>,
    /// `"UTF-8"`, `"UTF-8 with BOM"`, `"UTF-16LE with BOM"`, `"UTF-16BE with BOM"` or `"Windows-1252"`.
    pub encoding: &'static str,
}

/// Windows-1252 code points of bytes 0x80..=0x9F (the rest is Latin-1). The five undefined
/// bytes map to the C1 control of the same value, as browsers do.
const CP1252_80_9F: [u32; 32] = [
    0x20AC, 0x81, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021, 0x02C6, 0x2030, 0x0160, 0x2039,
    0x0152, 0x8D, 0x017D, 0x8F, 0x90, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2013, 0x2014,
    0x02DC, 0x2122, 0x0161, 0x203A, 0x0153, 0x9D, 0x017E, 0x0178,
];

fn windows_1252(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|&b| match b {
            0x80..=0x9F => {
                char::from_u32(CP1252_80_9F[usize::from(b - 0x80)]).unwrap_or('\u{FFFD}')
            }
            _ => char::from(b),
        })
        .collect()
}

fn utf16(body: &[u8], little_endian: bool) -> Option<String> {
    if body.len() % 2 != 0 {
        return None;
    }
    let units: Vec<u16> = body
        .chunks_exact(2)
        .map(|c| {
            if little_endian {
                u16::from_le_bytes([c[0], c[1]])
            } else {
                u16::from_be_bytes([c[0], c[1]])
            }
        })
        .collect();
    String::from_utf16(&units).ok()
}

/// Recognised binary formats people upload by mistake, by their first bytes.
fn binary_hint(bytes: &[u8], name: &str) -> String {
    let lower = name.to_lowercase();
    if bytes.starts_with(b"PK\x03\x04") {
        "; this looks like a ZIP container such as an Excel .xlsx workbook: save it as CSV".into()
    } else if bytes.starts_with(&[0xD0, 0xCF, 0x11, 0xE0]) {
        "; this looks like an old Excel .xls workbook: save it as CSV".into()
    } else if bytes.starts_with(b"%PDF") {
        "; this is a PDF report, not the point data".into()
    } else if lower.ends_with(".prg") || lower.ends_with(".cmm") {
        "; this looks like a CMM program file: export the points as text".into()
    } else {
        String::new()
    }
}

/// Rejects binary data: a NUL byte, or more than 1 % control characters other than tab, line
/// feed, carriage return, form feed and DOS end-of-file (0x1A) in the first 64 KiB.
fn check_binary(bytes: &[u8], name: &str) -> Result<(), CmmError> {
    let head = &bytes[..bytes.len().min(1 << 16)];
    let binary = |detail: String| CmmError::Binary {
        name: name.to_string(),
        detail,
        hint: binary_hint(bytes, name),
    };
    if let Some(pos) = head.iter().position(|&b| b == 0) {
        return Err(binary(format!("byte 0x00 at offset {pos}")));
    }
    let controls: Vec<usize> = head
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0C | 0x1A))
        .map(|(i, _)| i)
        .collect();
    if controls.len() * 100 > head.len() {
        return Err(binary(format!(
            "{} control bytes in the first {} bytes, the first 0x{:02X} at offset {}",
            controls.len(),
            head.len(),
            head[controls[0]],
            controls[0]
        )));
    }
    Ok(())
}

/// Decodes `bytes` after checking the size limit (`max_bytes`) and that they are text.
pub fn decode<'a>(bytes: &'a [u8], name: &str, max_bytes: usize) -> Result<Decoded<'a>, CmmError> {
    if bytes.len() > max_bytes {
        return Err(CmmError::TooLarge {
            bytes: bytes.len(),
            limit: max_bytes,
            limit_mb: max_bytes as f64 / (1024.0 * 1024.0),
        });
    }
    if bytes.is_empty() {
        return Err(CmmError::Empty {
            name: name.to_string(),
            detail: "0 bytes".into(),
        });
    }
    for (bom, le, label) in [
        (&[0xFF, 0xFE][..], true, "UTF-16LE with BOM"),
        (&[0xFE, 0xFF][..], false, "UTF-16BE with BOM"),
    ] {
        if let Some(body) = bytes.strip_prefix(bom) {
            if let Some(text) = utf16(body, le) {
                check_binary(text.as_bytes(), name)?;
                return Ok(Decoded {
                    text: Cow::Owned(text),
                    encoding: label,
                });
            }
        }
    }
    check_binary(bytes, name)?;
    if let Some(body) = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]) {
        if let Ok(text) = std::str::from_utf8(body) {
            return Ok(Decoded {
                text: Cow::Borrowed(text),
                encoding: "UTF-8 with BOM",
            });
        }
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => Ok(Decoded {
            text: Cow::Borrowed(text),
            encoding: "UTF-8",
        }),
        Err(_) => Ok(Decoded {
            text: Cow::Owned(windows_1252(bytes)),
            encoding: "Windows-1252",
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodings() {
        let d = decode(b"\xEF\xBB\xBFdev [\xC2\xB5m]", "f", 100).unwrap();
        assert_eq!(
            (d.text.as_ref(), d.encoding),
            ("dev [µm]", "UTF-8 with BOM")
        );
        let d = decode(b"dev [\xB5m] \x80", "f", 100).unwrap();
        assert_eq!(
            (d.text.as_ref(), d.encoding),
            ("dev [µm] €", "Windows-1252")
        );
        let d = decode(b"\xFF\xFEx\0,\0y\0", "f", 100).unwrap();
        assert_eq!((d.text.as_ref(), d.encoding), ("x,y", "UTF-16LE with BOM"));
        assert!(matches!(
            decode(b"a\0b", "f", 100),
            Err(CmmError::Binary { .. })
        ));
        assert!(matches!(decode(b"", "f", 100), Err(CmmError::Empty { .. })));
        assert!(matches!(
            decode(b"abc", "f", 2),
            Err(CmmError::TooLarge { .. })
        ));
    }
}
