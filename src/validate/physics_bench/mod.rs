//! `testpiece validate --generator physics`: parts made by the physics generator
//! ([`super::physics`], not the fitter), each analysed by the shipped analysis and judged against
//! its truth (issue 29 item 4).
//!
//! For every case: the generator makes a part of the kind [`Kind::of_case`] from its own stream
//! (seed and case number), the location errors of paper 000's machine drawn at random; its
//! **visible structure** is the RMS of its noise-free deviation that the location errors cannot
//! absorb (the baseline design at the points, [`score::Scorer::visible`]); **the limit** is the
//! detection limit with the generator's true σ, the product's own rule `k σ`
//! ([`crate::gap::diagnose::DiagnoseOptions::detect_factor`], effects.md's 2.5), σ the true σ of one
//! analysed deviation (CMM and surface scatter; of the mean for repeats). The part then goes
//! through the analysis a user's file goes through ([`score`]) and is judged ([`expected`]); the
//! report ([`report`]) gives the groups of issue 29 and its done-when figures.
//!
//! The figures are an upper bound on real parts: the generator knows the machine's structure
//! (its chain, its path, its points), and real parts carry effects no one has modelled.
//!
//! Seeds: 1-3 develop, 101-103 are held out ([`super::physics`]).

pub mod expected;
pub mod report;
pub mod score;
pub mod shape_check;

pub use report::{physics_table, PhysicsCase, PhysicsReport};

use crate::gap::diagnose::DiagnoseOptions;
use crate::machine::chain::PAPER000_L0;
use crate::machine::ErrorParam;
use crate::numerics::random::Sampler;
use crate::part::{builtin_points, SShape};
use crate::validate::physics::{Generator, Kind, Workshop};
use crate::validate::{ValidateError, ValidationModel};

use expected::Catalogue;
use score::Scorer;

/// Sample spacing of the generator's passes (mm of tool-tip path): 13,400 poses a pass; the loops
/// are integrated every 1.5-3 ms at 1000-2000 mm/min.
pub const STEP_MM: f64 = 0.05;

/// Options of a physics run.
#[derive(Debug, Clone, Copy)]
pub struct PhysicsOptions {
    pub cases: usize,
    pub seed: u64,
    /// Give the CMM's σ (never the part's scatter) to the analysis of a single measurement.
    pub cmm_sigma: bool,
    /// Worker threads the cases are shared between (each case has its own random stream and
    /// its own analysis, so the report does not depend on it: tested); at least 1.
    pub threads: usize,
}

impl Default for PhysicsOptions {
    fn default() -> Self {
        Self {
            cases: 300,
            seed: 1,
            cmm_sigma: false,
            threads: default_threads(),
        }
    }
}

/// The machine's available parallelism (1 when it cannot be known).
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// The settings-only model of a run: the workshop, the scoring model and the location errors.
pub struct PhysicsBench {
    pub workshop: Workshop,
    pub model: ValidationModel,
    pub location: Vec<ErrorParam>,
    pub detect_factor: f64,
}

impl PhysicsBench {
    /// The built-in S-shape and points on paper 000's machine.
    pub fn builtin() -> Result<Self, ValidateError> {
        let part = SShape::iso();
        let points = builtin_points(&part);
        let model = ValidationModel::at(&part, &points)?.without_shapes();
        // the baseline's columns are the machine's location errors
        let location: Vec<ErrorParam> = model
            .baseline
            .params
            .iter()
            .filter_map(|p| match p {
                crate::parameter::ParamId::Machine(e) => Some(*e),
                _ => None,
            })
            .collect();
        Ok(Self {
            workshop: Workshop::new(&part, &points, PAPER000_L0, STEP_MM)?,
            model,
            location,
            detect_factor: DiagnoseOptions::default().detect_factor,
        })
    }

    /// The stream of case `case` of seed `seed` (each case its own, so one case can be made
    /// again alone).
    pub fn stream(seed: u64, case: usize) -> Sampler {
        Sampler::new(seed.wrapping_mul(1_000_000).wrapping_add(case as u64))
    }

    /// Runs `opts.cases` cases, shared between `opts.threads` threads (case `i` on thread
    /// `i mod threads`: the kinds cycle with the case number, so each thread gets a mix), the
    /// results in case order.
    pub fn run(&self, opts: &PhysicsOptions) -> Result<PhysicsReport, ValidateError> {
        let threads = opts.threads.clamp(1, opts.cases.max(1));
        let cases = |t: usize| (t..opts.cases).step_by(threads);
        let mut results: Vec<PhysicsCase> = if threads == 1 {
            self.cases(opts, cases(0))?
        } else {
            std::thread::scope(|scope| {
                let workers: Vec<_> = (0..threads)
                    .map(|t| scope.spawn(move || self.cases(opts, cases(t))))
                    .collect();
                workers
                    .into_iter()
                    .map(|w| w.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                    .collect::<Result<Vec<_>, _>>()
            })?
            .into_iter()
            .flatten()
            .collect()
        };
        crate::numerics::order::sort_by_index(&mut results, |c| c.case);
        Ok(PhysicsReport::of(
            opts.seed,
            opts.cmm_sigma,
            self.detect_factor,
            results,
        ))
    }

    /// The cases `cases` on this thread: the generator's part, its analysis and its judgement.
    fn cases(
        &self,
        opts: &PhysicsOptions,
        cases: impl Iterator<Item = usize>,
    ) -> Result<Vec<PhysicsCase>, ValidateError> {
        let scorer = Scorer::new(&self.model)?;
        let visible = |d: &[f64]| scorer.visible(d);
        let generator = Generator::new(
            &self.workshop,
            self.location.clone(),
            &visible,
            self.detect_factor,
        );
        let mut results = Vec::new();
        for case in cases {
            let kind = Kind::of_case(case);
            let part = generator.part(kind, &mut Self::stream(opts.seed, case))?;
            let visible = scorer.visible(&part.noise_free);
            let limit = self.detect_factor * part.sigma;
            let mismatch = part.common.as_ref().map(|c| {
                let d: Vec<f64> = part.noise_free.iter().zip(c).map(|(a, b)| a - b).collect();
                scorer.visible(&d) / limit
            });
            let catalogue = Catalogue::of(&part.physics, mismatch);
            let ratio = visible / limit;
            let analysed = scorer.analyse(case, &part, opts.cmm_sigma)?;
            let judged = scorer.judge(&part, &catalogue, ratio, limit, &analysed);
            results.push(PhysicsCase {
                case,
                kind,
                physics: part.physics.clone(),
                catalogue,
                noise: part.noise,
                sigma: part.sigma,
                visible,
                limit,
                ratio,
                target_ratio: part.target_ratio,
                xi: part.xi.clone(),
                judged,
            });
        }
        Ok(results)
    }
}
