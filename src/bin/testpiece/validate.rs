//! `testpiece validate`: the withheld-effect benchmark of the diagnosis.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece validate` is not available in this version yet (issue 6)".to_string())
}
