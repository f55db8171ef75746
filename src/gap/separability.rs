//! What a scan's many heights make separable (issue 31 item 2): the candidates this layout tells
//! apart that the 100 built-in points cannot, and the other way round.
//!
//! Two candidates are told apart when the cosine of the smallest principal angle between their
//! unabsorbed spans is under [`EQUIVALENT_COS`] ([`crate::gap::equivalence`]: only what the
//! location errors cannot absorb can be seen). The cosines are computed on both layouts with the
//! same settings: the measured points' part model and the built-in points' (the prepared
//! settings', [`crate::effects::prepared::Prepared::builtin_model`]). A family is compared by its
//! signature at the reference shape (the table's).
//!
//! Units: cosines are dimensionless, in [0, 1].

use serde::Serialize;

use crate::effects::builtin::PartModel;
use crate::gap::equivalence::{compare_spans, unabsorbed_spans, SpanPairs, EQUIVALENT_COS};
use crate::numerics::parallel::Threads;
use crate::parameter::Effect;

/// The smallest principal cosine at or above which the smaller span is inside the larger: a
/// special case of it by construction (`tool_radius`'s column is `tool_taper`'s `dR0`), not a
/// near coincidence (those are the pairs at [`EQUIVALENT_COS`]).
pub const NESTED_COS: f64 = 0.999;

/// One pair of candidates, the cosine of the smallest principal angle between their unabsorbed
/// spans on each layout.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PairCosines {
    pub a: Effect,
    pub b: Effect,
    /// On the measured points (`a` the candidate of the smaller span).
    pub here: f64,
    /// On the 100 built-in points.
    pub builtin: f64,
    /// One span lies inside the other here (every effect of the smaller is also one of the
    /// larger: `tool_radius` in `tool_taper`): the larger is told apart by its own extra
    /// parameters' significance, never by the angle.
    pub nested: bool,
}

/// The pairs whose separability differs between the layouts, and those neither separates.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Separability {
    /// Near-equivalent (cosine ≥ [`EQUIVALENT_COS`]) on the built-in points, told apart here.
    pub told_apart: Vec<PairCosines>,
    /// Told apart on the built-in points, near-equivalent here.
    pub merged: Vec<PairCosines>,
    /// Near-equivalent on both.
    pub neither: Vec<PairCosines>,
}

/// The separability of the candidates on `here` against `builtin` (the same settings' built-in
/// points): every pair visible on both layouts, sorted into [`Separability`]'s three lists in
/// the candidates' order.
pub fn separability(here: &PartModel, builtin: &PartModel) -> Separability {
    let sh = unabsorbed_spans(&here.baseline, &here.candidates);
    let sb = unabsorbed_spans(&builtin.baseline, &builtin.candidates);
    let on_builtin = |e: Effect| sb.iter().find(|s| s.0 == e).map(|s| (e, &s.1));
    // a dense scan's pairs off one Gram matrix of its spans (on this thread: the separability
    // runs beside the fit)
    let here_pairs = SpanPairs::new(sh.iter().map(|(e, q)| (*e, q)).collect(), Threads::ONE);
    let mut out = Separability::default();
    for (i, (ea, _)) in sh.iter().enumerate() {
        for (j, (eb, _)) in sh.iter().enumerate().skip(i + 1) {
            let (Some(p), Some(ba), Some(bb)) =
                (here_pairs.compare(i, j), on_builtin(*ea), on_builtin(*eb))
            else {
                continue;
            };
            let Some(q) = compare_spans(ba, bb) else {
                continue;
            };
            let pair = PairCosines {
                a: p.a,
                b: p.b,
                here: p.cosine,
                builtin: q.cosine,
                nested: p.smaller && p.a_within_b >= NESTED_COS,
            };
            match (pair.here >= EQUIVALENT_COS, pair.builtin >= EQUIVALENT_COS) {
                (false, true) => out.told_apart.push(pair),
                (true, false) => out.merged.push(pair),
                (true, true) => out.neither.push(pair),
                (false, false) => {}
            }
        }
    }
    out
}

/// One sentence for the report: what this layout tells apart that the built-in points cannot,
/// what it cannot that they can, and what neither can (each pair with its two cosines).
pub fn sentence(s: &Separability) -> String {
    let list = |v: &[PairCosines]| {
        v.iter()
            .map(|p| {
                format!(
                    "{} {} {} ({:.3}; {:.3})",
                    p.a.id(),
                    if p.nested { "within" } else { "/" },
                    p.b.id(),
                    p.here,
                    p.builtin
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut parts = Vec::new();
    parts.push(if s.told_apart.is_empty() {
        "this layout tells apart no pair of effects that the 100 built-in points cannot".to_string()
    } else {
        format!(
            "this layout tells apart {} that the 100 built-in points cannot",
            list(&s.told_apart)
        )
    });
    if !s.merged.is_empty() {
        parts.push(format!(
            "it cannot tell apart {}, which the built-in points can",
            list(&s.merged)
        ));
    }
    if !s.neither.is_empty() {
        parts.push(format!("neither tells apart {}", list(&s.neither)));
    }
    format!(
        "Separability: {} (in brackets the cosine of the smallest angle between the two \
         effects' visible parts here; on the built-in points; {EQUIVALENT_COS} or more: not told \
         apart; `within`: the first is a special case of the second, which is told apart by the \
         significance of its own further parameters).",
        parts.join("; ")
    )
}
