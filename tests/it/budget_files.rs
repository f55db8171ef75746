//! Bad CL and trace files get the CMM reader's kind of message: the line, the column, the text
//! found and what was expected (cmm-csv.md), never a panic; limits are named.

use testpiece::budget::{read_cl, read_trace, BudgetError, TraceMachine, MAX_FILE_BYTES};

fn cl_err(text: &str) -> String {
    read_cl(text.as_bytes(), "p.cl").unwrap_err().to_string()
}

#[test]
fn cl_messages_name_line_column_and_text() {
    let cases: [(&str, &str); 10] = [
        ("", "p.cl: 'p.cl' is empty"),
        ("x,y,z,i,j,k\n", "p.cl: no tool position in the file"),
        ("1,2,3,0,0,1\n", "p.cl: line 1: no recognisable header: found '1,2,3,0,0,1', expected a header row x,y,z,i,j,k (CSV) or APT records such as GOTO/x,y,z,i,j,k (the first line holds numbers: the header row is missing)"),
        ("x,y,z,i,j\n1,2,3,0,0\n", "p.cl: line 1: required column missing: k; found columns: x, y, z, i, j"),
        ("x,y,z,i,j,k\n1,2,NaN,0,0,1\n", "line 2, column 3 'z': not a finite number: found 'NaN', expected a finite number (mm)"),
        ("x;y;z;i;j;k\n1;2;3;0;0;1\n1;2,5;x3;0;0;1\n", "line 3, column 3 'z': not a number: found 'x3', expected a finite number (mm)"),
        ("x,y,z,i,j,k\n1,2,3,0,0\n", "line 2, column 6 'k': truncated row"),
        ("x,y,z,i,j,k\n1,2,3,0,0,0\n", "line 2: tool axis is not a unit vector: found '(0, 0, 0) of length 0'"),
        ("UNITS/MM\nGOTO/1,2,3\n", "line 2: tool axis missing"),
        ("PARTNO/X\nUNITS/FEET\nGOTO/1,2,3,0,0,1,7\nCIRCLE/0,0,0,5\n", "3 bad line(s)"),
    ];
    for (text, want) in cases {
        let e = cl_err(text);
        assert!(e.contains(want), "{text:?}:\n{e}\nwanted: {want}");
    }
    let e = cl_err("PARTNO/X\nUNITS/FEET\nGOTO/1,2,3,0,0,1,7\nCIRCLE/0,0,0,5\n");
    for want in [
        "line 2, column 1 'UNITS field 1': unknown unit: found 'FEET', expected UNITS/MM or UNITS/INCHES",
        "line 3: wrong number of values: found '7 value(s) in 'GOTO/1,2,3,0,0,1,7'",
        "line 4: unsupported record: found 'CIRCLE/0,0,0,5'",
    ] {
        assert!(e.contains(want), "{e}\nwanted: {want}");
    }
    // binary data and the size limit: the CMM reader's words
    assert!(cl_err("GOTO/\u{0}\u{1}\u{2}").contains("binary data"));
    let big = vec![b'x'; MAX_FILE_BYTES + 1];
    let e = read_cl(&big, "big.cl").unwrap_err();
    assert!(matches!(e, BudgetError::Decode { .. }));
    assert!(
        e.to_string().contains("over the limit of 52428800 bytes"),
        "{e}"
    );
}

#[test]
fn trace_messages_name_line_column_and_text() {
    let m = TraceMachine::default();
    let err = |t: &str| {
        read_trace(t.as_bytes(), "nc.csv", &m)
            .unwrap_err()
            .to_string()
    };
    assert!(err("time,X,Y,Z,B\n0,1,2,3,4\n")
        .contains("nc.csv: line 1: required column missing: C (axes of w C Y' b X Z B t)"));
    let e0 = err("foo,bar\n1,2\n");
    assert!(e0.contains("nc.csv: line 1: no recognisable header: found 'foo,bar', expected a header row naming the axes of w C Y' b X Z B t: X,Y,Z,B,C (and optionally time)"));
    let e = err("X,Y,Z,B,C\n1,2,3,4,5\n1,2,3,4,-inf\n1,2,3\n");
    assert!(e.contains("2 bad line(s)"), "{e}");
    assert!(e.contains("line 3, column 5 'C': not a finite number: found '-inf', expected a finite number (degrees)"), "{e}");
    assert!(e.contains("line 4, column 4 'B': truncated row"), "{e}");
}
