//! # testpiece
//!
//! From one machined ISO 10791-7 S-shape test piece measured on a CMM, which geometric errors a
//! five-axis machine tool has, and how sure that answer is.
//!
//! The pipeline, one folder per stage: part geometry ([`geometry`], [`part`]) → flank tool path
//! and envelope ([`toolpath`]) → machine kinematics and error models ([`machine`]) → machined
//! defect per error ([`sensitivity`]) → CMM files ([`cmm`]) → least-squares identification
//! ([`identify`]) → sim-to-real gap diagnosis ([`gap`]). Every stage is a plain function from data
//! to data; what the settings alone determine (the machine's error set, the path model, the
//! built-in points' model) is a value the caller builds once and passes
//! ([`effects::prepared::Prepared`], kept with the last point sets' models by an
//! [`analysis::Session`]), never a cache behind its back. `wasm` (compiled for `wasm32` only) is
//! the only module that knows about the browser.
//!
//! Units: mm and rad everywhere (degrees only where a file says so). Sign convention
//! (`shared/spec/s-shape.md`): a deviation is `(machined or measured − nominal) · N` with `N` the
//! outward normal; **positive = material left, negative = overcut**.

pub mod analysis;
#[cfg(feature = "bench")]
pub mod bench;
pub mod budget;
pub mod cmm;
pub mod compare;
pub mod compensation;
pub mod effects;
pub mod examples;
pub mod final_fit;
pub mod gap;
pub mod geometry;
pub mod identify;
pub mod machine;
pub mod measurement;
pub mod numerics;
pub mod parameter;
pub mod part;
pub mod plan;
pub mod pool;
pub mod program;
pub mod sensitivity;
pub mod settings;
pub mod simulate;
pub mod summary;
pub mod tolerance;
pub mod toolpath;
pub mod validate;
#[cfg(target_arch = "wasm32")]
pub mod wasm;

/// The crate version, printed by the CLI and on the page's report.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
