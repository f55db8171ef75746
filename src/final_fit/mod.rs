//! The final identification: the machine's location errors fitted together with what the gap
//! diagnosis found ([`correct`]): with the named effect's columns, or with the unexplained
//! structure as a correlated error whose covariance along the tool path is estimated by REML
//! ([`structure`]), or the baseline when the residual is noise. The errors reported and exported
//! for compensation are these; their std include what the choice among the candidate models
//! can move them by ([`model_spread`]), the linear axes' error motions among those models as one
//! random effect whose size the part says ([`pooled`]).

pub mod correct;
pub mod model_spread;
pub mod pooled;
pub mod structure;
