//! Least squares of the gap diagnosis: the column-scaled SVD solve with a numerical rank of
//! [`crate::identify::solve`] (one core for identification and diagnosis), re-exported here under
//! the names the gap modules use.

pub use crate::identify::solve::{hstack, max_abs, rms, Factor, RANK_TOL};
