//! The sim-to-real gap: after the baseline (location errors, `physical` mode) is fitted to a
//! measured part, where the residual lies, which unmodelled effect of `shared/spec/effects.md`
//! causes it, and how far it shrinks when that effect is added.
//!
//! The domain words are types: an [`Effect`] ([`effect`]: id, parameters and units, plain name,
//! signature formula), a [`verdict::Verdict`] whose [`verdict::Finding`] is noise, unexplained
//! (with a partial candidate) or named (with an optional second effect of a pair and the
//! equivalents), and typed where-groups ([`location::Group`]: curve, region, lean, axis
//! reversal). They serialise to the JSON of shared/spec/cli.md, which the page only draws.
//!
//! The engine works on plain data ([`GapInput`]: deviations, point metadata, a named baseline
//! design and the candidates' signatures), so the same call serves measured files, simulated
//! parts and the reference vectors; [`effects`] builds that data from the part and the machine
//! (the part model). Pipeline of [`diagnose`]:
//! 1. baseline least squares ([`lsq`]) and its residual;
//! 2. WHERE ([`location`], [`regions`], [`noise`], [`smooth_noise`]): per curve, region, lean,
//!    reversal, trends; noise σ independent of smooth structure; runs / lag-1 / χ² tests;
//! 3. WHICH ([`which`], [`folds`]): each candidate added on its own; F-test with Bonferroni, BIC,
//!    k-fold by curve and by region; equivalences from the unabsorbed spans ([`equivalence`]);
//! 4. VERDICT ([`verdict`]) by the decision rule of effects.md and two checks of ours; when no
//!    single candidate is named, the pair search ([`pairs`], which knows nothing of verdicts);
//!    HOW FAR per curve;
//! 5. a serialisable [`DiagnosisReport`] with a plain-language summary ([`report`]).
//!
//! Before it, [`outliers`] names the single-point faults (a chip, dirt, a probing error) by
//! externally studentised residuals against a robust σ with a Bonferroni bound; the analysis
//! leaves them out of the identification and the diagnosis and reports the verdict with them too.
//!
//! After the diagnosis, [`correct`] makes the final identification: the location errors fitted
//! with the named effect, or with the unexplained structure as a correlated error
//! ([`structure`]), or the baseline when the residual is noise.
//!
//! One option, [`DiagnoseOptions::detect_factor`] (`k` of the `k σ` rule, 2.5), reaches every
//! step that compares with the noise. The benchmark that simulates parts and diagnoses them
//! (`testpiece validate`) is [`crate::validate`], beside the pipeline.
//!
//! Units: mm (deviations, residuals, RMS), parameters in their own units. Sign: deviation =
//! `(measured − nominal)·N`, + = material left, − = overcut.

pub mod beside;
pub mod diagnose;
pub mod equivalence;
pub mod folds;
pub mod location;
pub mod pairs;
pub mod regions;
pub mod report;
pub mod separability;
pub mod shape;
pub mod span_gram;
pub mod verdict;
pub mod which;

pub use diagnose::{
    diagnose, diagnose_on, diagnose_with, diagnose_with_smooth, ground, DiagnoseOptions, Ground,
};
pub use report::DiagnosisReport;
