//! The page's built-in examples (src/examples.rs: one file embedded whole, two as their
//! deviation column) are the reference files of tests/data/reference/examples/, byte for byte.

use testpiece::examples::{example_text, EXAMPLES};

#[test]
fn built_in_examples_are_the_reference_files() {
    for (name, _, _) in EXAMPLES {
        let path = format!(
            "{}/tests/data/reference/examples/{name}",
            env!("CARGO_MANIFEST_DIR")
        );
        let disk = std::fs::read_to_string(&path).unwrap();
        // tolerance: none (the same bytes)
        assert!(
            example_text(name).as_deref() == Some(disk.as_str()),
            "{name}"
        );
    }
    assert!(example_text("nope.csv").is_none());
}
