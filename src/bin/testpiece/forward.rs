//! `testpiece forward`: tool tip and axis from axis values X,Y,Z,B,C on stdin (--machine FILE).

pub fn run(_rest: &[String]) -> Result<(), String> {
    Err("`testpiece forward` is not available in this version yet (issue 4)".to_string())
}
