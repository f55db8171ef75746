//! `testpiece simulate`: a synthetic measured part.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece simulate` is not available in this version yet (issue 5)".to_string())
}
