//! `testpiece diagnose`: diagnose the sim-to-real gap of a CMM file.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece diagnose` is not available in this version yet (issue 6)".to_string())
}
