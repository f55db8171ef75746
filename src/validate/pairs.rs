//! The withheld-effect benchmark for two effects at once (`testpiece validate --pairs`): simulated
//! parts `y = A ξ + S₁ θ₁ + S₂ θ₂ + ε` for every pair of candidates the part can tell apart (not
//! near-equivalent on it, [`crate::gap::equivalence::EQUIVALENT_COS`]), diagnosed with both withheld
//! from the baseline. Machine errors and noise as in [`super::single`]; each effect's magnitude
//! is set so that the RMS of the part the baseline cannot absorb is `ρ · 2.5σ`, `ρ` log-uniform
//! in [[`RATIO_MIN`], [`RATIO_MAX`]] (each effect detectable on its own).
//!
//! A case counts as **both named** when each id is among the verdict's effect, its `with` and
//! their equivalents, or near-equivalent on this part to one of them (as in [`super::single`]); **one named** when only one is (a single verdict, or a pair
//! with a wrong partner); otherwise by the verdict (`unexplained`, `none`).

use serde::Serialize;

use super::single::{effect_parameters, machine_errors, ValidateOptions, ValidationModel};
use super::ValidateError;
use crate::effects::data::GapInput;
use crate::gap::diagnose::diagnose_with;
use crate::gap::verdict::VerdictId;
use crate::identify::solve::{hstack, Factor};
use crate::numerics::random::Sampler;
use crate::parameter::Effect;

/// Smallest simulated `ρ` of each effect of a pair.
pub const RATIO_MIN: f64 = 1.5;
/// Largest simulated `ρ` of each effect of a pair.
pub const RATIO_MAX: f64 = 6.0;

/// The outcome of the pair benchmark.
#[derive(Debug, Clone, Serialize)]
pub struct PairValidation {
    pub cases: usize,
    pub seed: u64,
    pub both_named: usize,
    pub one_named: usize,
    pub unexplained: usize,
    pub none: usize,
    /// `both_named / cases`.
    pub rate: f64,
    /// Cases where each effect is visible beyond the baseline AND the other effect (joint ratio
    /// above 1): only there can any rule name both.
    pub jointly_visible: usize,
    /// Of those, both named.
    pub jointly_visible_both_named: usize,
    /// Per pair: `(first, second, both named?, verdict text)`.
    pub results: Vec<PairCase>,
}

/// One simulated two-effect part.
#[derive(Debug, Clone, Serialize)]
pub struct PairCase {
    pub effects: [Effect; 2],
    pub ratios: [f64; 2],
    /// RMS of each effect's part that neither the baseline nor the other effect absorbs, over
    /// k σ (Frisch–Waugh–Lovell: what a joint fit can see of it).
    pub joint_ratios: [f64; 2],
    pub verdict: VerdictId,
    /// The pair's second effect when the verdict names a pair.
    pub with: Option<Effect>,
    pub both_named: bool,
}

/// Runs `opts.cases` two-effect parts, cycling through the distinguishable pairs.
pub fn validate_pairs(
    model: &ValidationModel,
    opts: &ValidateOptions,
) -> Result<PairValidation, ValidateError> {
    let a = &model.baseline.matrix;
    let base = Factor::new(a, None);
    let alike = model.near_equivalence();
    let mut pairs = Vec::new();
    for (i, c1) in model.candidates.iter().enumerate() {
        for c2 in &model.candidates[i + 1..] {
            if !alike(c1.effect, c2.effect) {
                pairs.push((c1, c2));
            }
        }
    }
    if pairs.is_empty() {
        return Err(ValidateError::NoPairs);
    }
    let limit = opts.detect_factor * opts.noise_sigma;
    let mut rng = Sampler::new(opts.seed);
    let mut results = Vec::with_capacity(opts.cases);
    for case in 0..opts.cases {
        let (c1, c2) = pairs[case % pairs.len()];
        let xi = machine_errors(&model.baseline.params, opts, &mut rng);
        let mut y = a * xi;
        let mut ratios = [0.0; 2];
        let mut parts = Vec::with_capacity(2);
        for (k, c) in [c1, c2].iter().enumerate() {
            ratios[k] = rng.log_uniform(RATIO_MIN, RATIO_MAX);
            let theta = effect_parameters(c, &base, ratios[k] * limit, &mut rng);
            let part = &c.signature.matrix * theta;
            y += &part;
            parts.push(part);
        }
        let n = a.nrows() as f64;
        let joint_ratios = [(0, c2), (1, c1)].map(|(k, other)| {
            let f = Factor::new(&hstack(a, &other.signature.matrix), None);
            f.unabsorbed_vec(&parts[k]).norm() / n.sqrt() / limit
        });
        for v in y.iter_mut() {
            *v += opts.noise_sigma * rng.normal();
        }
        let report = diagnose_with(
            &GapInput {
                deviations: y.iter().copied().collect(),
                points: std::borrow::Cow::Borrowed(&model.points),
                baseline: std::borrow::Cow::Borrowed(&model.baseline),
                candidates: std::borrow::Cow::Borrowed(&model.candidates),
                noise_sigma: opts.known_sigma.then_some(opts.noise_sigma),
                reversals: Vec::new(),
            },
            opts.diagnose_options(),
        )?;
        let f = &report.verdict.finding;
        let named: Vec<Effect> = f
            .effects()
            .into_iter()
            .chain(f.equivalent().iter().copied())
            .chain(
                f.with()
                    .into_iter()
                    .flat_map(|w| w.equivalent.iter().copied()),
            )
            .collect();
        let has = |e: Effect| named.iter().any(|&m| m == e || alike(m, e));
        results.push(PairCase {
            effects: [c1.effect, c2.effect],
            ratios,
            joint_ratios,
            verdict: f.id(),
            with: f.with().map(|w| w.effect),
            both_named: has(c1.effect) && has(c2.effect),
        });
    }
    let count = |f: &dyn Fn(&PairCase) -> bool| results.iter().filter(|r| f(r)).count();
    let both_named = count(&|r| r.both_named);
    let none = count(&|r| r.verdict == VerdictId::Noise);
    let unexplained = count(&|r| r.verdict == VerdictId::Unexplained);
    let visible = |r: &PairCase| r.joint_ratios.iter().all(|&j| j > 1.0);
    Ok(PairValidation {
        jointly_visible: count(&visible),
        jointly_visible_both_named: count(&|r| visible(r) && r.both_named),
        cases: results.len(),
        seed: opts.seed,
        both_named,
        one_named: results.len() - both_named - none - unexplained,
        unexplained,
        none,
        rate: both_named as f64 / results.len().max(1) as f64,
        results,
    })
}

/// A plain-text summary of the pair benchmark.
pub fn pairs_table(r: &PairValidation) -> String {
    let mut s = format!(
        "validate --pairs: {} two-effect parts, seed {}, each effect at {RATIO_MIN}..{RATIO_MAX} x the detection limit\n",
        r.cases, r.seed
    );
    s += &format!(
        "both named: {}/{} = {:.1} %; one named: {}; unexplained: {}; none: {}\n",
        r.both_named,
        r.cases,
        100.0 * r.rate,
        r.one_named,
        r.unexplained,
        r.none
    );
    s += &format!(
        "both visible jointly (each beyond the baseline and the other effect, > k σ): {}/{}; both named there: {}/{} = {:.1} %\n",
        r.jointly_visible,
        r.cases,
        r.jointly_visible_both_named,
        r.jointly_visible,
        100.0 * r.jointly_visible_both_named as f64 / r.jointly_visible.max(1) as f64
    );
    let missed: Vec<&PairCase> = r.results.iter().filter(|c| !c.both_named).collect();
    if missed.len() > 20 {
        s += &format!("first 20 of {} misses:\n", missed.len());
    }
    for c in missed.into_iter().take(20) {
        s += &format!(
            "  missed {} ({:.1}x, jointly {:.1}x) + {} ({:.1}x, jointly {:.1}x): verdict {}{}\n",
            c.effects[0],
            c.ratios[0],
            c.joint_ratios[0],
            c.effects[1],
            c.ratios[1],
            c.joint_ratios[1],
            c.verdict,
            c.with.map(|w| format!(" with {w}")).unwrap_or_default()
        );
    }
    s
}
