//! Pairs of effects (effects.md: the diagnosis "adds candidates one at a time (and may try
//! pairs)"). A real part often carries two unmodelled effects at once, e.g. a worn tool and the
//! lost motion of an axis. One at a time, each candidate then leaves the other effect in its
//! residual: its σ is inflated, its visible part falls under 2.5 σ, and the single-candidate rule
//! of [`crate::gap::verdict`] says `unexplained` (or even `none`, when the estimated noise absorbs the
//! second effect).
//!
//! This step runs when the single-candidate verdict names no effect, and when it names one (a
//! second effect on top of it: the single rule measures the structure left against the
//! smooth-basis σ, which a smooth second effect inflates; the pair then has to keep the named
//! effect or an equivalent). The candidates that are significant on their own (F-test with
//! Bonferroni), at most [`POOL`] of them by p-value (not by `cv_score`: with a second effect
//! unmodelled, a step-like signature such as a backlash predicts withheld curves badly although
//! it fits well), are paired, and the [`ANCHORS`] most significant are also paired with every
//! other candidate (forward selection: the second effect of a part is often not significant on
//! its own, its F-test's denominator holding the first effect, or is crowded out of the pool by
//! look-alikes of the first); pairs that the part cannot tell apart from one candidate (cosine ≥
//! [`EQUIVALENT_COS`] between their unabsorbed spans) are skipped. Each pair `{c₁, c₂}` is
//! refitted jointly with the baseline ([`fit_in_sample`] on the stacked signature `[S₁ | S₂]`),
//! and accepted when, with `RSS₁`, `RSS₂`, `RSS₁₂` the residual sums of squares of `c₁` alone,
//! `c₂` alone and the pair, `p` the baseline rank and `q₁₂` the pair's added rank:
//! - (a) each member adds significantly to the other:
//!   `F = ((RSS_other − RSS₁₂)/Δq) / (RSS₁₂/(n − p − q₁₂))` against `F(Δq, n − p − q₁₂)`,
//!   Bonferroni over the pairs tried, family-wise α;
//! - (b) each member is visible: `√((RSS_other − RSS₁₂)/n)`, which by Frisch–Waugh–Lovell is the
//!   RMS of the part of its fitted effect that neither the baseline nor the other member can
//!   absorb, is above 2.5 σ (σ of the pair's fit, or the given repeatability);
//! - (c) the pair predicts withheld points better than the baseline and than each member alone
//!   (lower `cv_score`, which charges `ln n` per extra parameter);
//! - (d) the pair explains the gap: the structure left is at most 2.5 σ.
//!
//! Among accepted pairs the lowest `cv_score` wins. The verdict names the member with the larger
//! visible part first. A candidate the part cannot tell apart from a member is one that, in that
//! member's place, fits not significantly worse (`(RSS' − RSS₁₂)/σ̂² < χ²₁(0.95)`), as for single
//! candidates, or whose unabsorbed span reproduces the member's (cosine ≥ [`EQUIVALENT_COS`]).
//!
//! **A second effect below the limit** (issue 29: σ that structure cannot inflate). A single
//! candidate's σ is its own residual's, so a part with one effect above the limit and a second,
//! weaker one, e.g. all axes' common servo rounding and one axis's mismatch at the limit, gets
//! `unexplained`: the first's σ holds the second, and the second is under the limit against the
//! pair's σ. When no single candidate is named and no pair meets (a)-(d), a pair meeting (a),
//! (c) and (d) whose larger member is visible against the pair's σ and whose smaller member is
//! not (`second_below_limit`) names the larger one alone ([`crate::gap::verdict::pair_verdict`]),
//! the smaller one among the effects possible below the detection limit. A pair of two visible
//! members is preferred to such a pair.

use crate::numerics::parallel::{map, Threads};
use nalgebra::DMatrix;
use serde::Serialize;

use crate::effects::data::{Candidate, NamedColumns};
use crate::gap::beside::{Beside, Members};
use crate::gap::equivalence::{cos_to_span, EQUIVALENT_COS};
use crate::gap::shape::Unabsorbed;
use crate::gap::which::{fit_in_sample, CandidateFit, Context, InSample};
use crate::numerics::order::sort_by_key_f64;
use crate::numerics::stats;
use crate::numerics::stats::CHI2_1_95;
use crate::parameter::Effect;

/// The accepted pair and its evidence.
#[derive(Debug, Clone, Serialize)]
pub struct PairFit {
    /// The member with the larger visible part (the verdict's effect).
    pub first: Effect,
    /// The other member.
    pub second: Effect,
    /// Candidates this part cannot tell apart from `first` (in the pair with `second`).
    pub first_equivalent: Vec<Effect>,
    /// Candidates this part cannot tell apart from `second` (in the pair with `first`).
    pub second_equivalent: Vec<Effect>,
    /// `second` is significant on top of `first` but its visible part is at most the detection
    /// limit (module doc): the verdict names `first` alone.
    pub second_below_limit: bool,
    /// F-test of `second` on top of `first`, Bonferroni-corrected p-value.
    pub f: f64,
    pub p_bonferroni: f64,
    /// RMS of what `second` adds beyond baseline + `first` (mm).
    pub added_rms: f64,
    /// RMS of what `first` adds beyond baseline + `second` (mm).
    pub first_added_rms: f64,
    /// The joint fit (`effect` = `first`, `with` = `second`, parameters named
    /// `<effect>.<parameter>`).
    pub fit: CandidateFit,
    /// The grid indices of the members' shapes fitted jointly (a family's lag or warm-up found
    /// with the other member in the model, [`joint_shapes`]; `None` for one shape).
    #[serde(skip)]
    pub shapes: [Option<usize>; 2],
}

/// The members' shapes fitted jointly: each family member's shape chosen with the other member
/// in the model (variable projection over its grid, the other at its shape), in turn, twice: a
/// shape that the single fit bent towards the other effect's structure is found again once that
/// structure is fitted. Returns the members at those shapes and the grid indices. `kept`: the
/// families' members already projected off the baseline by an earlier search of the same
/// diagnosis ([`KeptMembers`]).
fn joint_shapes(
    ctx: &Context,
    a: &Candidate,
    b: &Candidate,
    start: [Option<usize>; 2],
    kept: &KeptMembers,
) -> (Candidate, Candidate, [Option<usize>; 2]) {
    let mut idx = start;
    if a.family.is_none() && b.family.is_none() {
        return (a.at_shape(None), b.at_shape(None), [None, None]);
    }
    let factor = &ctx.baseline.factor;
    for _ in 0..2 {
        for which in 0..2 {
            let (me, other) = if which == 0 { (a, b) } else { (b, a) };
            let Some(family) = &me.family else { continue };
            let fixed = other.at_shape(idx[1 - which]);
            // the other member's part outside the baseline once for the whole grid
            let fixed = Unabsorbed::of(factor, &fixed.signature.matrix);
            // the member of least RSS beside the other, the first of equal ones: each screened
            // in one pass, the closest fitted exactly (the member of the exact fit of each,
            // side by side on the threads given, [`Beside`]: a backlash's 54 members searched
            // four times a pair had been a third of a named backlash's diagnosis on a scan)
            let beside = Beside::new(&fixed, &ctx.baseline.residual);
            let make = |k: usize| family.member(k);
            let members = match kept.get(me.effect) {
                Some(un) => Members::Kept(un),
                None => Members::Made {
                    len: family.len(),
                    columns: &make,
                    baseline: factor,
                },
            };
            idx[which] = beside.least(&members, ctx.threads);
        }
    }
    (a.at_shape(idx[0]), b.at_shape(idx[1]), idx)
}

/// The most the members of the families searched in pairs may hold, projected off the baseline,
/// for the next pair with the same family (bytes: every family of a 20,000-point scan, one or
/// two of a 200,000-point one; the others are computed again, the same numbers).
const KEPT_MEMBERS_BYTES: usize = 128 << 20;

/// The families' members projected off the baseline ([`Unabsorbed::of`]) by the pairs' joint
/// searches of one diagnosis, kept within [`KEPT_MEMBERS_BYTES`]: a family is in up to
/// [`POOL`] − 1 + [`ANCHORS`] pairs and searched twice in each.
#[derive(Default)]
struct KeptMembers {
    families: Vec<(Effect, Vec<Unabsorbed>)>,
    bytes: usize,
}

impl KeptMembers {
    /// The members of the families of `a` and `b` (`a`'s first) projected off the baseline,
    /// each family not kept yet kept when it fits in the budget (else [`joint_shapes`] makes
    /// them a block at a time, [`Members`]): what the pair's searches read, the families kept in
    /// the order the pairs need them.
    fn keep_for(&mut self, ctx: &Context, a: &Candidate, b: &Candidate) {
        for me in [a, b] {
            let Some(family) = &me.family else { continue };
            let bytes = family.len() * ctx.y.len() * me.signature.ncols() * 8;
            if self.get(me.effect).is_none() && self.bytes + bytes <= KEPT_MEMBERS_BYTES {
                let members: Vec<usize> = (0..family.len()).collect();
                let factor = &ctx.baseline.factor;
                let un = map(ctx.threads, &members, |&k| {
                    Unabsorbed::of(factor, &family.member(k))
                });
                self.bytes += bytes;
                self.families.push((me.effect, un));
            }
        }
    }

    fn get(&self, e: Effect) -> Option<&[Unabsorbed]> {
        self.families
            .iter()
            .find(|(f, _)| *f == e)
            .map(|(_, u)| u.as_slice())
    }
}

/// The candidate `first + second`: stacked signatures, parameters named `<effect>.<name>`; it
/// carries `first`'s effect (the fit's `with` names `second`).
fn stacked(first: &Candidate, second: &Candidate) -> Candidate {
    let (a, b) = (&first.signature, &second.signature);
    let n = a.matrix.nrows();
    let mut m = DMatrix::zeros(n, a.matrix.ncols() + b.matrix.ncols());
    m.columns_mut(0, a.matrix.ncols()).copy_from(&a.matrix);
    m.columns_mut(a.matrix.ncols(), b.matrix.ncols())
        .copy_from(&b.matrix);
    let params = a.params.iter().chain(&b.params).cloned().collect();
    Candidate::new(first.effect, NamedColumns { params, matrix: m })
}

/// Most candidates paired with each other (the most significant ones, by their F-test p-value):
/// 15 pairs.
pub const POOL: usize = 6;

/// The most significant candidates also paired with every other candidate (forward selection).
pub const ANCHORS: usize = 2;

/// `(RSS_other − RSS_pair)`: F-test p-value (uncorrected) and the visible RMS of the member.
fn added(rss_other: f64, rss_pair: f64, dq: usize, dof: f64, n: f64) -> (f64, f64, f64) {
    let f = ((rss_other - rss_pair).max(0.0) / dq as f64) / (rss_pair / dof);
    let p = stats::f_sf(f, dq as f64, dof);
    (f, p, ((rss_other - rss_pair).max(0.0) / n).sqrt())
}

/// Pairs the significant candidates `fits` (see the module doc); `None` when no pair meets
/// (a)-(d), nor, with `below_limit`, (a), (c) and (d) with one member visible.
/// `baseline_cv_score` is the baseline's own score.
pub fn best_pair(
    ctx: &Context,
    candidates: &[Candidate],
    fits: &[CandidateFit],
    baseline_cv_score: f64,
    below_limit: bool,
) -> Option<PairFit> {
    let n = ctx.y.len();
    let nf = n as f64;
    let p = ctx.baseline.factor.rank;
    let mut pool: Vec<&CandidateFit> = fits
        .iter()
        .filter(|f| f.evidence.significant && f.evidence.added_rank > 0)
        .collect();
    sort_by_key_f64(&mut pool, |f| f.evidence.p_value);
    pool.truncate(POOL);
    // Forward selection from the strongest candidates: a second effect that the first one's
    // residual hides (not significant on its own, or crowded out of the pool by look-alikes of
    // the first) is found as the best addition to it.
    let partners: Vec<&CandidateFit> = fits.iter().filter(|f| f.evidence.added_rank > 0).collect();
    let mut pairs: Vec<(&CandidateFit, &CandidateFit)> = Vec::new();
    let candidates_pairs = pool
        .iter()
        .enumerate()
        .flat_map(|(i, a)| pool[i + 1..].iter().map(move |b| (*a, *b)))
        .chain(
            pool.iter()
                .take(ANCHORS)
                .flat_map(|a| partners.iter().map(move |b| (*a, *b))),
        );
    for (a, b) in candidates_pairs {
        if a.effect == b.effect
            || pairs.iter().any(|(x, y)| {
                (x.effect == a.effect && y.effect == b.effect)
                    || (x.effect == b.effect && y.effect == a.effect)
            })
        {
            continue;
        }
        let same = cos_to_span(&b.unabsorbed_effect, &a.unabsorbed_basis) >= EQUIVALENT_COS
            || cos_to_span(&a.unabsorbed_effect, &b.unabsorbed_basis) >= EQUIVALENT_COS;
        if !same {
            pairs.push((a, b));
        }
    }
    let tries = pairs.len().max(1);
    let pair_ctx = Context {
        tries: tries as f64,
        ..*ctx
    };
    let rss = |f: &CandidateFit| f.rms * f.rms * nf;
    // each pair's candidates, and the families' members its searches read, kept in the pairs'
    // order (as the pairs one after the other had kept them on first need)
    let mut kept = KeptMembers::default();
    let mut jobs: Vec<[(&CandidateFit, &Candidate); 2]> = Vec::with_capacity(pairs.len());
    for (a, b) in pairs {
        let (ca, cb) = (
            candidates.iter().find(|c| c.effect == a.effect)?,
            candidates.iter().find(|c| c.effect == b.effect)?,
        );
        kept.keep_for(ctx, ca, cb);
        jobs.push([(a, ca), (b, cb)]);
    }
    // the pairs side by side on the threads, each on one (a pair's joint searches, fits and
    // members had been half of one thread's work beside the other idle on a backlash scan,
    // issue 31): each pair's numbers are its own whatever the threads; tried and accepted in
    // the pairs' order
    let one = Context {
        threads: Threads::ONE,
        ..*ctx
    };
    let pair_one = Context {
        threads: Threads::ONE,
        ..pair_ctx
    };
    let outcomes = map(ctx.threads, &jobs, |&[(a, ca), (b, cb)]| {
        let start = [
            a.shape.as_ref().map(|s| s.grid_index),
            b.shape.as_ref().map(|s| s.grid_index),
        ];
        let (ca, cb, shapes) = joint_shapes(&one, ca, cb, start, &kept);
        let joint = stacked(&ca, &cb);
        // (a) and (b) from the in-sample fit; the withheld points only for a pair that meets
        // them (the same fit: a pair's withheld points were most of its cost on a scan)
        let in_sample = InSample::of(&pair_one, &joint.signature.matrix);
        let q = in_sample.added_rank();
        let rss_ab = {
            let r = in_sample.rms();
            r * r * nf
        };
        let tried = (a.effect, b.effect, rss_ab);
        let (dqa, dqb) = (
            q.saturating_sub(b.evidence.added_rank),
            q.saturating_sub(a.evidence.added_rank),
        );
        if dqa == 0 || dqb == 0 || rss_ab <= 0.0 {
            return (tried, None);
        }
        let dof = (n - p - q).max(1) as f64;
        let (fa, pa, va) = added(rss(b), rss_ab, dqa, dof, nf);
        let (fb, pb, vb) = added(rss(a), rss_ab, dqb, dof, nf);
        let limit = ctx.detect_factor * in_sample.sigma(&pair_one);
        let significant = pa * (tries as f64) < ctx.alpha && pb * (tries as f64) < ctx.alpha;
        // a member visible: both (two visible members) or the larger (`weak` below)
        if !significant || va.max(vb) <= limit {
            return (tried, None);
        }
        let mut fit = fit_in_sample(&pair_one, &joint, in_sample);
        let e = &fit.evidence;
        let explains = significant
            && fit.cv_score < baseline_cv_score
            && fit.cv_score < a.cv_score
            && fit.cv_score < b.cv_score
            && e.structure_after <= ctx.detect_factor * e.sigma_smooth;
        let weak = below_limit && va.max(vb) > limit && va.min(vb) <= limit;
        if !(explains && (va.min(vb) > limit || weak)) {
            return (tried, None);
        }
        // The member with the larger visible part first.
        let (first, second, f, pv, v, v_first) = if va >= vb {
            (a, b, fb, pb, vb, va)
        } else {
            (b, a, fa, pa, va, vb)
        };
        fit.effect = first.effect;
        fit.with = Some(second.effect);
        let accepted = PairFit {
            first: first.effect,
            second: second.effect,
            second_below_limit: va.min(vb) <= limit,
            first_equivalent: Vec::new(),
            second_equivalent: Vec::new(),
            f,
            p_bonferroni: (pv * tries as f64).min(1.0),
            added_rms: v,
            first_added_rms: v_first,
            fit,
            shapes: if first.effect == a.effect {
                shapes
            } else {
                [shapes[1], shapes[0]]
            },
        };
        (tried, Some(accepted))
    });
    drop(kept);
    let mut tried: Vec<(Effect, Effect, f64)> = Vec::with_capacity(outcomes.len());
    let mut accepted: Vec<PairFit> = Vec::new();
    for (t, a) in outcomes {
        tried.push(t);
        accepted.extend(a);
    }
    // a pair of two visible members first
    let mut best = accepted.into_iter().min_by(|a, b| {
        a.second_below_limit
            .cmp(&b.second_below_limit)
            .then(a.fit.cv_score.total_cmp(&b.fit.cv_score))
    })?;
    let rss_best = rss(&best.fit);
    let sigma2 = (best.fit.rms * best.fit.rms)
        .max(best.fit.evidence.sigma * best.fit.evidence.sigma)
        .max(f64::MIN_POSITIVE);
    // Members the part cannot tell apart: another candidate in the place of one member fits
    // not significantly worse than the chosen pair.
    let swap = |keep: Effect, out: Effect| -> Vec<Effect> {
        tried
            .iter()
            .filter_map(|(a, b, r)| {
                let other = if *a == keep {
                    *b
                } else if *b == keep {
                    *a
                } else {
                    return None;
                };
                (other != out && (r - rss_best) / sigma2 < CHI2_1_95).then_some(other)
            })
            .collect()
    };
    best.first_equivalent = swap(best.second, best.first);
    best.second_equivalent = swap(best.first, best.second);
    Some(best)
}
