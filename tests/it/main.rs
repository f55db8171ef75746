//! The native integration tests, one binary (issue 21 item 5: one crate to compile and link
//! instead of one per file), a module per stage file; run one module with
//! `cargo test --test it gap_lab::`. The helpers are declared once here; `parity_common` is
//! shared with the wasm tests (`tests/wasm_node/`, run by `wasm-pack test --node`) and stays
//! beside them. proptest keeps the seeds of past failures in
//! `tests/proptest-regressions/<module>.txt` (its default for a crate rooted at a `main.rs`).
#![cfg(not(target_arch = "wasm32"))]

// Shared helpers.
mod cli_common;
mod edge_common;
mod gap_common;
mod identify_common;
#[path = "../parity_common/mod.rs"]
mod parity_common;
mod pool_common;

// The tests, one module per stage file.
mod architecture;
mod budget_cli;
mod budget_envelope;
mod budget_examples;
mod budget_files;
mod budget_sum;
mod budget_trace;
mod cmm_broken;
mod cmm_formats;
mod cmm_matching;
mod edge_fuzz_regressions;
mod edge_limits;
mod edge_numeric;
mod edge_parity;
mod effects_families_physics;
mod gap_correct;
mod gap_dense;
mod gap_effect_physics;
mod gap_effects;
mod gap_examples;
mod gap_lab;
mod gap_machines;
mod gap_noise;
mod gap_outliers;
mod gap_pairs;
mod gap_scans;
mod gap_scans_physics;
mod gap_validate;
mod gap_validate_machines;
mod geometry_cli;
mod geometry_envelope;
mod geometry_points;
mod geometry_table2;
mod identify_cli;
mod identify_export;
mod identify_formats;
mod identify_progress;
mod identify_properties;
mod identify_reference;
mod identify_refine;
mod identify_timing;
mod identify_uncertainty;
mod kinematics_chain;
mod kinematics_inverse;
mod kinematics_jacobian;
mod kinematics_peer;
mod machine_error_set;
mod plan_dmis;
mod pool_identify;
mod pool_refine;
mod program_dialects;
mod proptest_bspline;
mod proptest_identify;
mod proptest_kinematics;
mod proptest_projection;
mod sensitivity_cli;
mod sensitivity_frenet;
mod sensitivity_gauge_block;
mod sensitivity_reference;
mod sensitivity_reversal;
mod sensitivity_servo;
mod validate_physics;
mod wasm_examples;
mod workflow_compensation;
mod workflow_controller;
mod workflow_plan;
mod workflow_program;
