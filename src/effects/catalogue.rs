//! A machine's own effect catalogue (issue 20 item 3): which candidates of effects.md it is
//! diagnosed with, which ones exist there but cannot show on a flank-milled wall, and which it
//! does not have, each with why. Decided on the part's 100 built-in points, like the machine's
//! location errors ([`crate::sensitivity::error_set`]).

use serde::Serialize;

use crate::effects::prepared::Prepared;
use crate::parameter::Effect;

/// One candidate and what becomes of it on the machine.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectStatus {
    pub effect: Effect,
    /// `offered` (a candidate of the diagnosis), `invisible` (a candidate whose signature is
    /// exactly zero there: the diagnosis says it adds nothing), or `left_out` (not a candidate).
    pub status: &'static str,
    /// Why (empty for an offered effect).
    pub reason: String,
}

/// The catalogue of the machine of the prepared settings (chain, branch), in effects.md order,
/// decided on the built-in points' model ([`Prepared::builtin_model`]).
pub fn machine_effects(prepared: &Prepared) -> Vec<EffectStatus> {
    let chain = &prepared.options().chain;
    let model = prepared.builtin_model();
    let same = prepared.location_equivalents();
    Effect::ALL
        .into_iter()
        .map(|effect| {
            let (status, reason) = if let Some(why) = effect.absent_from(chain) {
                ("left_out", why)
            } else if let Some((_, why)) = same.iter().find(|(e, _)| *e == effect) {
                ("left_out", why.clone())
            } else if model
                .candidates
                .iter()
                .any(|c| c.effect == effect && c.signature.matrix.iter().all(|v| *v == 0.0))
            {
                (
                    "invisible",
                    "its signature is exactly zero on this machine: it moves the tool only \
                     along its own axis, which lies in the flank-milled walls"
                        .to_string(),
                )
            } else {
                ("offered", String::new())
            };
            EffectStatus {
                effect,
                status,
                reason,
            }
        })
        .collect()
}
