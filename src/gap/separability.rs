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

use nalgebra::DMatrix;
use serde::Serialize;

use crate::effects::builtin::PartModel;
use crate::effects::data::{Candidate, NamedColumns};
use crate::gap::equivalence::{principal_cosines, EQUIVALENT_COS};
use crate::identify::solve::Factor;
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

/// Orthonormal bases of the candidates' unabsorbed spans `(I − P) S_c` on `model` (`P` the
/// projector on its baseline), for the candidates that leave something visible.
pub fn unabsorbed_spans(model: &PartModel) -> Vec<(Effect, DMatrix<f64>)> {
    spans_of(&model.baseline, &model.candidates)
}

/// [`unabsorbed_spans`] of `candidates` on the baseline design `baseline`.
pub fn spans_of(baseline: &NamedColumns, candidates: &[Candidate]) -> Vec<(Effect, DMatrix<f64>)> {
    let base = Factor::new(&baseline.matrix, None);
    candidates
        .iter()
        .map(|c| {
            let u = base.unabsorbed(&c.signature.matrix);
            (c.effect, Factor::new(&u, None).basis)
        })
        .filter(|(_, q)| q.ncols() > 0)
        .collect()
}

/// The largest and the smallest principal cosine of the spans of `a` and `b` in `spans` (`None`
/// when one of them has none).
fn cosines(spans: &[(Effect, DMatrix<f64>)], a: Effect, b: Effect) -> Option<(f64, f64)> {
    let qa = &spans.iter().find(|s| s.0 == a)?.1;
    let qb = &spans.iter().find(|s| s.0 == b)?.1;
    let c = principal_cosines(qa, qb);
    Some((*c.first()?, *c.last()?))
}

/// The dimension of the span of `e` in `spans` (0 when it has none).
fn qa_dim(spans: &[(Effect, DMatrix<f64>)], e: Effect) -> usize {
    spans.iter().find(|s| s.0 == e).map_or(0, |s| s.1.ncols())
}

/// The separability of the candidates on `here` against `builtin` (the same settings' built-in
/// points): every pair visible on both layouts, sorted into [`Separability`]'s three lists in
/// the candidates' order.
pub fn separability(here: &PartModel, builtin: &PartModel) -> Separability {
    let (sh, sb) = (unabsorbed_spans(here), unabsorbed_spans(builtin));
    let mut out = Separability::default();
    for (i, (a, _)) in sh.iter().enumerate() {
        for (b, _) in &sh[i + 1..] {
            let (Some((here, smallest)), Some((builtin, _))) =
                (cosines(&sh, *a, *b), cosines(&sb, *a, *b))
            else {
                continue;
            };
            // the smaller span first; nested when its every direction is in the larger one
            // (its last principal cosine)
            let (a, b) = if qa_dim(&sh, *a) <= qa_dim(&sh, *b) {
                (*a, *b)
            } else {
                (*b, *a)
            };
            let pair = PairCosines {
                a,
                b,
                here,
                builtin,
                nested: qa_dim(&sh, a) < qa_dim(&sh, b) && smallest >= NESTED_COS,
            };
            match (here >= EQUIVALENT_COS, builtin >= EQUIVALENT_COS) {
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
