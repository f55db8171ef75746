//! `testpiece points`: the 100 built-in measurement points.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece points` is not available in this version yet (issue 3)".to_string())
}
