//! `testpiece budget` end to end (cli.md row `budget`) on the example files of
//! `tests/data/budget/`: the JSON fields of the contract, the CSV rows, the sum per point, the
//! messages of a bad CL file and of missing options.

use crate::cli_common::testpiece;

fn data(name: &str) -> String {
    format!("{}/tests/data/budget/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn budget_json_has_the_cli_md_fields_and_adds_up() {
    let (cl, tr, cmm) = (
        data("example_cl.apt"),
        data("example_trace.csv"),
        data("example_measured.csv"),
    );
    let (ok, out, err) = testpiece(&[
        "budget",
        &cmm,
        "--cl",
        &cl,
        "--trace",
        &tr,
        "--tool-radius",
        "--json",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let points = v["points"].as_array().unwrap();
    assert_eq!(points.len(), 100);
    for p in points {
        let f = |k: &str| p[k].as_f64().unwrap_or_else(|| panic!("field {k} in {p}"));
        let sum = f("design") + f("cam") + f("nc") + f("machine") + f("tool") + f("residual");
        assert!((sum - f("measured")).abs() < 1e-12, "{p}");
        assert!(p["id"].is_string());
    }
    for s in ["design", "cam", "nc", "machine", "tool", "residual", "cmm"] {
        let r = &v["summary"][s];
        assert!(
            r["min"].as_f64().unwrap() <= r["max"].as_f64().unwrap(),
            "{s}"
        );
    }
    assert!(v["trace"]["positions"].as_u64().unwrap() > 100);
    // the CSV form: one row per point, same numbers
    let (ok, csv, _) = testpiece(&["budget", &cmm, "--cl", &cl, "--trace", &tr, "--tool-radius"]);
    assert!(ok);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "id,curve,measured,design,cam,nc,machine,tool,residual,cmm,cam_chord_bound,nc_chord_bound"
    );
    assert_eq!(lines.len(), 101);
    let first: Vec<f64> = lines[1]
        .split(',')
        .skip(2)
        .map(|x| x.parse().unwrap())
        .collect();
    assert!((first[1] - points[0]["design"].as_f64().unwrap()).abs() < 1e-15);
}

#[test]
fn budget_errors_and_help() {
    let (ok, out, _) = testpiece(&["budget", "--help"]);
    assert!(ok && out.contains("--cl PATH") && out.contains("--trace PATH"));
    let cmm = data("example_measured.csv");
    let (ok, _, err) = testpiece(&["budget", &cmm]);
    assert!(!ok && err.contains("needs --cl PATH"), "{err}");
    let dir = std::env::temp_dir().join(format!("testpiece-budget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.apt");
    std::fs::write(&bad, "UNITS/MM\nGOTO/1,2,3,0,0,1\nGOTO/1,2,abc,0,0,1\n").unwrap();
    let (ok, _, err) = testpiece(&["budget", &cmm, "--cl", bad.to_str().unwrap()]);
    assert!(!ok);
    assert!(
        err.contains("bad.apt: 1 bad line(s)")
            && err.contains("line 3, column 3 'GOTO field 3': not a number: found 'abc'"),
        "{err}"
    );
    // a CL path of one surface does not reach the points of the other: named
    let one = dir.join("one.csv");
    std::fs::write(&one, "x,y,z,i,j,k\n0,0,0,0,0,1\n").unwrap();
    let (ok, _, err) = testpiece(&["budget", &cmm, "--cl", one.to_str().unwrap()]);
    assert!(
        !ok && err.contains("point 1 (A_Z11)") && err.contains("is not reached"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
