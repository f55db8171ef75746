//! The example parts built into the page (so a newcomer sees a result at once, and the
//! single-file build needs no fetch): the three synthetic measured parts of
//! `tests/data/reference/examples/` (canonical CSV; their answer keys stay in the tests). Plain
//! Rust, so the native tests check them; `wasm::page::start` gives them to the page.
//!
//! The three files share their first eight columns: the 100 built-in points (ids, curves,
//! positions to 6 decimals, normals to 9, mm); only the deviation differs. To keep the wasm
//! small, only the deviation columns are embedded (`examples/*.deviation`, one value per line as
//! written in the file) and [`example_text`] rebuilds each file byte for byte from
//! [`crate::part::builtin_points`] (checked against the files in tests/it/wasm_examples.rs).

/// (file name, what it is, deviation column), menu order.
pub const EXAMPLES: [(&str, &str, &str); 3] = [
    (
        "example_backlash_c.csv",
        "S-shape part machined with C-axis backlash (synthetic, σ = 1.5 µm)",
        include_str!("examples/backlash_c.deviation"),
    ),
    (
        "example_tool_radius.csv",
        "S-shape part machined with an oversize tool (synthetic, σ = 1.5 µm)",
        include_str!("examples/tool_radius.deviation"),
    ),
    (
        "example_clean.csv",
        "S-shape part with machine errors only (synthetic, σ = 1.5 µm)",
        include_str!("examples/clean.deviation"),
    ),
];

/// The text of a built-in example file, by name.
pub fn example_text(name: &str) -> Option<String> {
    use std::fmt::Write;
    let (_, _, dev) = EXAMPLES.iter().find(|(n, _, _)| *n == name)?;
    let pts = crate::part::builtin_points(&crate::part::SShape::iso());
    // The files write a tiny negative normal component as `0.000000000`, not `-0.000000000`.
    let fixed = |v: f64, d: usize| {
        let t = format!("{v:.d$}");
        match t.strip_prefix('-') {
            Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
            _ => t,
        }
    };
    let mut out = String::from("id,curve,x,y,z,nx,ny,nz,deviation\n");
    let mut devs = dev.lines();
    for p in &pts {
        let (x, n) = (p.point, p.normal);
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{}",
            p.id,
            p.curve.name(),
            fixed(x.x, 6),
            fixed(x.y, 6),
            fixed(x.z, 6),
            fixed(n.x, 9),
            fixed(n.y, 9),
            fixed(n.z, 9),
            devs.next()?
        );
    }
    devs.next().is_none().then_some(out)
}
