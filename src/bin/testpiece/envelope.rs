//! `testpiece envelope`: flank-path deviation at the points (--surface-max: largest overcut per surface).

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece envelope` is not available in this version yet (issue 3)".to_string())
}
