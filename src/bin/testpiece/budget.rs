//! `testpiece budget`: error budget per point from a CMM file, a CL file and an NC trace.

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece budget` is not available in this version yet (issue 10)".to_string())
}
