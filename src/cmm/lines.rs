//! Lines of a text file: numbered from 1, comment lines (`#`, `//`) and blank lines set aside
//! (cmm-csv.md: "`#` or `//` starts a comment line. Blank lines are ignored.").

/// The lines of a file that carry content, with their 1-based line numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Lines<'a> {
    /// Every physical line (without its terminator), index = line number - 1.
    pub all: Vec<&'a str>,
    /// `(line number, text)` of the non-blank, non-comment lines.
    pub content: Vec<(usize, &'a str)>,
    pub comments: usize,
    pub blanks: usize,
}

/// Whether a line is a comment (`#` or `//` after optional leading white space).
pub fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with('#') || t.starts_with("//")
}

/// Splits `text` into lines (`\n`, `\r\n`, or lone `\r` in old Mac files) and classifies them.
pub fn classify(text: &str) -> Lines<'_> {
    let all: Vec<&str> = if text.contains('\n') {
        text.split('\n')
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
            .collect()
    } else {
        text.split('\r').collect()
    };
    let mut content = Vec::new();
    let (mut comments, mut blanks) = (0, 0);
    for (k, line) in all.iter().enumerate() {
        // A DOS end-of-file mark (0x1A) at the end counts as blank.
        let t = line.trim_matches(|c: char| c.is_whitespace() || c == '\u{1A}');
        if t.is_empty() {
            blanks += 1;
        } else if is_comment(t) {
            comments += 1;
        } else {
            content.push((k + 1, *line));
        }
    }
    Lines {
        all,
        content,
        comments,
        blanks,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classify_lines() {
        let l = classify("# c\r\nx,y\r\n\r\n // c2\r\n1,2\r\n");
        assert_eq!(l.content, vec![(2, "x,y"), (5, "1,2")]);
        assert_eq!((l.comments, l.blanks), (2, 2));
        assert_eq!(classify("a\rb").content, vec![(1, "a"), (2, "b")]);
    }
}
