//! General numerics below every stage: distribution functions for the tests ([`stats`]), the
//! seeded random source of simulated parts and Monte Carlo ([`random`]), a small bounded memo
//! ([`memo`]), sorting by a number with one copy of the sort code ([`order`]), and a map over independent items
//! on the threads a caller gives ([`parallel`]), sums of exponentials at uneven positions by a
//! nonuniform fast Fourier transform ([`uneven_sums`]). Nothing here knows the part, the machine or a CMM.

pub mod fast_hash;
pub mod memo;
pub mod order;
pub mod parallel;
pub mod products;
pub mod random;
pub mod stats;
pub mod terms;
pub mod uneven_sums;
