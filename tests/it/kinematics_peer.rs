//! Real data from outside: the peer B-C tilting table (tests/data/reference/peer_bc_table,
//! README there). The committed description tests/data/peer_bc_table.json, read by the library
//! and by `testpiece forward --machine`, must reproduce the peer's tool tips to 1e-9 mm.

use std::io::Write;
use std::process::{Command, Stdio};

use testpiece::machine::description::MachineDescription;
use testpiece::machine::direct::tool_point;
use testpiece::machine::AxisValues;
use testpiece::tolerance::KINEMATICS_MM;

fn path(rel: &str) -> String {
    format!("{}/tests/data/{rel}", env!("CARGO_MANIFEST_DIR"))
}

struct Row {
    q: [f64; 5],
    tip: [f64; 3],
}

fn rows() -> Vec<Row> {
    let mut rdr = csv::Reader::from_path(path("reference/peer_bc_table/axes_and_tip.csv")).unwrap();
    rdr.records()
        .map(|r| {
            let r = r.unwrap();
            let f = |i: usize| r[i].parse::<f64>().unwrap();
            Row {
                q: [f(1), f(2), f(3), f(4), f(5)],
                tip: [f(6), f(7), f(8)],
            }
        })
        .collect()
}

#[test]
fn library_reproduces_peer_tips() {
    let desc = MachineDescription::from_json(
        &std::fs::read_to_string(path("peer_bc_table.json")).unwrap(),
    )
    .unwrap();
    let chain = desc.chain().unwrap();
    let errors = desc.machine_errors().unwrap();
    let k = desc.angle_unit.to_rad();
    let mut worst: f64 = 0.0;
    let rows = rows();
    assert_eq!(rows.len(), 2068);
    for r in &rows {
        let q = AxisValues::xyzbc(r.q[0], r.q[1], r.q[2], r.q[3] * k, r.q[4] * k);
        let p = tool_point(&chain, &q, 0.0, &errors).unwrap().point;
        let d =
            ((p.x - r.tip[0]).powi(2) + (p.y - r.tip[1]).powi(2) + (p.z - r.tip[2]).powi(2)).sqrt();
        worst = worst.max(d);
    }
    eprintln!(
        "peer_bc_table: max tip distance {worst:e} mm over {} rows",
        rows.len()
    );
    assert!(worst <= KINEMATICS_MM, "max distance {worst:e} mm");
}

#[test]
fn cli_forward_reproduces_peer_tips() {
    let input = std::fs::read_to_string(path("reference/peer_bc_table/axes_and_tip.csv")).unwrap();
    let out = run_forward(&path("peer_bc_table.json"), &input);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("tip_x,tip_y,tip_z,i,j,k"));
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for (line, r) in lines.zip(rows()) {
        let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
        let d = ((v[0] - r.tip[0]).powi(2) + (v[1] - r.tip[1]).powi(2) + (v[2] - r.tip[2]).powi(2))
            .sqrt();
        worst = worst.max(d);
        // The tool axis is a unit vector 15° from the cone's plane normal; here just unit.
        assert!(((v[3] * v[3] + v[4] * v[4] + v[5] * v[5]).sqrt() - 1.0).abs() < 1e-12);
        n += 1;
    }
    assert_eq!(n, 2068);
    assert!(worst <= KINEMATICS_MM, "max distance {worst:e} mm");
}

#[test]
fn cli_forward_reports_bad_input_with_the_offending_values() {
    let run = |machine: &str, stdin: &str| {
        let out = run_forward(machine, stdin);
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let m = path("peer_bc_table.json");
    let (ok, err) = run(&m, "X,Y,Z,B\n1,2,3,4\n");
    assert!(!ok && err.contains("no column `C`"), "{err}");
    let (ok, err) = run(&m, "X,Y,Z,B,C\n1,2,x3,4,5\n");
    assert!(!ok && err.contains("Z = `x3`"), "{err}");
    let dir = std::env::temp_dir().join(format!("tp_forward_{}.json", std::process::id()));
    std::fs::write(
        &dir,
        r#"{"code": "w C' B' b X Y Z t", "tool_ofset": [0, 0, 1]}"#,
    )
    .unwrap();
    let (ok, err) = run(dir.to_str().unwrap(), "X,Y,Z,B,C\n0,0,0,0,0\n");
    std::fs::remove_file(&dir).ok();
    assert!(!ok && err.contains("tool_ofset"), "{err}");
}

/// `testpiece forward --machine MACHINE` with `stdin` piped in. A child that rejects its machine
/// file exits before reading its input, so a broken pipe on writing is not a failure.
fn run_forward(machine: &str, stdin: &str) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_testpiece"))
        .args(["forward", "--machine", machine])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(stdin.as_bytes()).ok();
    child.wait_with_output().unwrap()
}
