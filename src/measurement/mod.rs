//! The measurement model: what the CMM and the part add to a deviation besides the machine, and
//! what a layout of points can tell, before any effect is diagnosed.
//!
//! - [`noise`]: the noise σ of a part (one calibrated estimator, the CMM's share as a floor,
//!   a plausibility ceiling), and the whiteness tests of a residual;
//! - [`ruling_pairs`]: σ from the two heights of a ruling, which structure along the path cannot
//!   inflate;
//! - [`smooth_noise`]: the residual of the baseline augmented with a smooth basis per curve;
//! - [`outliers`]: single-point faults (a chip, dirt, a probing error), by externally studentised
//!   residuals against a robust σ with a Bonferroni bound;
//! - [`repeat`]: repeat measurements of one part, pure error and lack of fit;
//! - [`layout`]: what a layout of measured points limits (points per curve, curves not measured);
//! - [`scan_lines`]: a scanning CMM's points grouped by surface and scan line, from the data.
//!
//! Units: mm (deviations, σ). Sign: deviation = `(measured − nominal)·N`.

pub mod layout;
pub mod noise;
pub mod outliers;
pub mod repeat;
pub mod ruling_pairs;
pub mod scan_lines;
pub mod smooth_noise;
