//! `testpiece identify`: identify the machine's errors from a CMM file.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece identify` is not available in this version yet (issue 5)".to_string())
}
