//! General numerics below every stage: distribution functions for the tests ([`stats`]), the
//! seeded random source of simulated parts and Monte Carlo ([`random`]), a small bounded memo
//! ([`memo`]), and sorting by a number with one copy of the sort code ([`order`]). Nothing here knows the part, the machine or a CMM.

pub mod memo;
pub mod order;
pub mod random;
pub mod stats;
pub mod terms;
