//! General numerics below every stage: distribution functions for the tests ([`stats`]), the
//! seeded random source of simulated parts and Monte Carlo ([`random`]), and a small bounded memo
//! ([`memo`]). Nothing here knows the part, the machine or a CMM.

pub mod memo;
pub mod random;
pub mod stats;
pub mod terms;
