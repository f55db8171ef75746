//! `testpiece sensitivity`: Figure-19 defect per unit of each location error.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece sensitivity` is not available in this version yet (issue 4)".to_string())
}
