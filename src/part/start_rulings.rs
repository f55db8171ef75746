//! The start of a closest-point projection ([`super::projection`]): the ruling nearest to a point
//! among a surface's sampled rulings `C0ᵢ + v·Dᵢ` at `u = i/400`, `i = 0..=400` (mm), searched
//! coarse to fine with a bound that makes it the very ruling the scan of all 401 finds.
//!
//! The rulings are grouped in blocks of [`BLOCK`] consecutive ones, each with a reference ruling
//! `m` (its middle), the largest distance `r = max |C0ᵢ − C0ₘ|` of its rulings' base points from
//! the reference's, and the largest sine `σ = max sin∠(Dᵢ, Dₘ)` of their directions' angles to the
//! reference's. With `Pᵢ = I − eᵢeᵢᵀ` (`eᵢ = Dᵢ/|Dᵢ|`) the distance of `p` from ruling `i`'s line is
//! `|Pᵢ(p − C0ᵢ)|`, and `‖Pᵢ − Pₘ‖₂ = sin∠(eᵢ, eₘ)`, so
//!
//! `dist(p, Lᵢ) ≥ dist(p, Lₘ) − σ·|p − C0ₘ| − r`
//!
//! for every ruling of the block. The search evaluates the references, then the blocks from the
//! one of lowest bound on, skipping a block whose bound (less a rounding allowance, [`SLACK`]) is
//! above the nearest ruling found so far. Equal distances go to the lowest index, as in the scan
//! (which keeps the first of the nearest), and each ruling's distance is computed by the scan's
//! arithmetic: the result is the scan's, bit for bit (test `blocks_find_the_rulings_scan_finds`).
//! Issue 31: 802 rulings a point were 8.5 % of `diagnose` on a 20,000-point scan.

use nalgebra::Vector3;

use super::projection::MARGIN_V;
use super::{RuledPart, Surface};

/// Steps of the start rulings over `u ∈ [0, 1]` (401 rulings).
pub const START_SAMPLES: usize = 400;

/// Rulings a block of the coarse search (the last one shorter).
pub const BLOCK: usize = 16;

/// The rounding allowance of a block's bound, relative to the lengths in it (mm per mm): the
/// distances are computed to ~1e-15 of `|p − C0|`, the bound's terms to a few ulps; 1e-9 is far
/// above both and far below any margin by which a block is skipped.
pub const SLACK: f64 = 1e-9;

/// A ruling `C0 + v·D` of the start search (mm).
pub type Ruling = (Vector3<f64>, Vector3<f64>);

/// A block of consecutive rulings `first..end` with its reference ruling and bounds (module doc).
#[derive(Debug, Clone, Copy)]
struct Block {
    first: usize,
    end: usize,
    reference: usize,
    /// `max |C0ᵢ − C0ₘ|` over the block (mm).
    radius: f64,
    /// `max sin∠(Dᵢ, Dₘ)` over the block.
    sine: f64,
    /// The largest of the block's rulings' [`StartRulings::margins`] (mm).
    step: f64,
}

/// A surface's start rulings with their blocks, computed once for all the points of a file.
#[derive(Debug, Clone)]
pub struct StartRulings {
    rulings: Vec<Ruling>,
    blocks: Vec<Block>,
    /// Per ruling, twice the larger of its steps `|ΔC0| + V·|ΔD|` (`V` = [`MARGIN_V`]) to its
    /// neighbours (mm): a point `C0(u) + v·D(u)` (`|v| ≤ V`) between two start rulings lies
    /// within `|C0(u) − C0ᵢ| + |v|·|D(u) − Dᵢ|` of the nearer one's line, at most this (the
    /// factor 2 holds the curves' sag between samples; [`StartRulings::beyond`]).
    margins: Vec<f64>,
}

impl StartRulings {
    /// Samples the start rulings of surface `s` of `part` and groups them in blocks.
    pub fn new<P: RuledPart + ?Sized>(part: &P, s: Surface) -> Self {
        let rulings: Vec<Ruling> = (0..=START_SAMPLES)
            .map(|i| {
                let sec = part.section_at(s, i as f64 / START_SAMPLES as f64);
                (sec.c0.point, sec.d.point)
            })
            .collect();
        Self::of(rulings)
    }

    /// Groups `rulings` (at `u = i/`[`START_SAMPLES`]) in blocks of [`BLOCK`].
    fn of(rulings: Vec<Ruling>) -> Self {
        let steps: Vec<f64> = rulings
            .windows(2)
            .map(|w| (w[1].0 - w[0].0).norm() + MARGIN_V * (w[1].1 - w[0].1).norm())
            .collect();
        let margins: Vec<f64> = (0..rulings.len())
            .map(|i| {
                let before = if i > 0 { steps[i - 1] } else { 0.0 };
                2.0 * before.max(steps.get(i).copied().unwrap_or(0.0))
            })
            .collect();
        let blocks = (0..rulings.len())
            .step_by(BLOCK)
            .map(|first| {
                let end = (first + BLOCK).min(rulings.len());
                let reference = (first + end) / 2;
                let (cm, dm) = rulings[reference];
                let em = dm.normalize();
                let (radius, sine) =
                    rulings[first..end]
                        .iter()
                        .fold((0.0f64, 0.0f64), |(r, s), (c, d)| {
                            let sin = d.normalize().cross(&em).norm().min(1.0);
                            (r.max((c - cm).norm()), s.max(sin))
                        });
                Block {
                    first,
                    end,
                    reference,
                    radius,
                    sine,
                    step: margins[first..end].iter().copied().fold(0.0, f64::max),
                }
            })
            .collect();
        Self {
            rulings,
            blocks,
            margins,
        }
    }

    /// The surface-wide margin: twice the largest step between neighbouring start rulings,
    /// `2·max(|ΔC0| + V·|ΔD|)` for feet of `|v| ≤ V =` [`MARGIN_V`] (the largest of
    /// [`StartRulings::margins`]), so the foot on the surface is at least its nearest ruling's
    /// distance less this.
    pub fn margin(&self) -> f64 {
        self.margins.iter().copied().fold(0.0, f64::max)
    }

    /// Whether every point `C0(u) + v·D(u)` of the surface with `|v| ≤` [`MARGIN_V`] is farther
    /// than `d` (mm) from `p`: its distance is at least that of the nearer of the two start
    /// rulings around it less that ruling's [`StartRulings::margins`], so every ruling's distance
    /// less its margin above `d` is enough; a block whose bound on its rulings' distances
    /// (module doc) less its largest margin is above `d` is passed whole, the others ruling by
    /// ruling. The surface-wide margin ([`StartRulings::margin`]) takes the largest step of the
    /// whole surface (12-16 mm on the S-shape, more than the 9-10 mm between its two sides): a
    /// scan's point on A had been projected onto B too (issue 31: a Newton a point, ~2 % of a
    /// 20,000-point scan's instructions). Conservative by [`SLACK`]; `false` for `d` infinite.
    pub fn beyond(&self, p: &Vector3<f64>, d: f64) -> bool {
        let clear = |dist: f64, margin: f64, scale: f64| dist - margin - SLACK * scale > d;
        d.is_finite()
            && self.blocks.iter().all(|b| {
                let (_, f) = on_ruling(&self.rulings[b.reference], p);
                let reach = (p - self.rulings[b.reference].0).norm();
                let bound = f.sqrt() - b.sine * reach - b.radius;
                clear(bound, b.step, 1.0 + reach + b.radius + b.step)
                    || (b.first..b.end).all(|i| {
                        let (_, f) = on_ruling(&self.rulings[i], p);
                        let reach = (p - self.rulings[i].0).norm();
                        clear(f.sqrt(), self.margins[i], 1.0 + reach + self.margins[i])
                    })
            })
    }

    /// The rulings in `u` order.
    pub fn rulings(&self) -> &[Ruling] {
        &self.rulings
    }

    /// `(u, v)` on the ruling nearest to `p` and the squared distance from `p` to that ruling's
    /// line (mm²): of equally near rulings the first (module doc; the same as [`scan`]).
    pub fn nearest(&self, p: &Vector3<f64>) -> (f64, f64, f64) {
        // the references: their distances and each block's bound
        let refs: Vec<(f64, f64, f64)> = self
            .blocks
            .iter()
            .map(|b| {
                let (v, f) = on_ruling(&self.rulings[b.reference], p);
                let reach = (p - self.rulings[b.reference].0).norm();
                let bound = f.sqrt() - b.sine * reach - b.radius;
                (v, f, bound - SLACK * (1.0 + reach + b.radius))
            })
            .collect();
        let first = (0..refs.len())
            .min_by(|&a, &b| refs[a].2.total_cmp(&refs[b].2))
            .unwrap_or(0);
        // (squared distance, index, v) of the nearest so far, lowest index among equals
        let mut best = (f64::INFINITY, usize::MAX, 0.0);
        for k in std::iter::once(first).chain((0..refs.len()).filter(|&k| k != first)) {
            if refs[k].2 > best.0.sqrt() {
                continue;
            }
            let b = &self.blocks[k];
            for i in b.first..b.end {
                let (v, f) = if i == b.reference {
                    (refs[k].0, refs[k].1)
                } else {
                    on_ruling(&self.rulings[i], p)
                };
                if f < best.0 || (f == best.0 && i < best.1) {
                    best = (f, i, v);
                }
            }
        }
        (best.1 as f64 / START_SAMPLES as f64, best.2, best.0)
    }
}

/// The closest `v` on ruling `(c0, d)` to `p` and the squared distance there (mm²).
fn on_ruling((c0, d): &Ruling, p: &Vector3<f64>) -> (f64, f64) {
    let v = (p - c0).dot(d) / d.norm_squared();
    (v, (c0 + d * v - p).norm_squared())
}

/// The direct method [`StartRulings::nearest`] replaces: every ruling in turn, the first of the
/// nearest kept.
#[cfg(all(test, not(target_arch = "wasm32")))]
fn scan(rulings: &[Ruling], p: &Vector3<f64>) -> (f64, f64, f64) {
    let (mut u, mut v, mut best) = (0.0, 0.0, f64::INFINITY);
    for (i, r) in rulings.iter().enumerate() {
        let (vi, f) = on_ruling(r, p);
        if f < best {
            (u, v, best) = (i as f64 / START_SAMPLES as f64, vi, f);
        }
    }
    (u, v, best)
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::part::{ConeFrustum, SShape};
    use proptest::prelude::*;

    fn both(part: &SShape) -> [StartRulings; 2] {
        Surface::BOTH.map(|s| StartRulings::new(part, s))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Anywhere in and around the part's box: the blocks give the scan's ruling, `v` and
        /// distance bit for bit (tolerance: none).
        #[test]
        fn blocks_find_the_rulings_scan_finds(
            x in -80.0f64..180.0, y in -80.0f64..180.0, z in -40.0f64..70.0
        ) {
            let part = SShape::iso();
            let p = Vector3::new(x, y, z);
            for r in both(&part) {
                prop_assert_eq!(r.nearest(&p), scan(r.rulings(), &p));
            }
        }

        /// Points near the surfaces (within 3 mm of either, above and below the part too), at
        /// their ends (`u` within 0.01 of 0 or 1, and beyond them along the tangent) and in the
        /// S's middle (`u` 0.4-0.6): the scan's result bit for bit.
        #[test]
        fn blocks_find_the_scans_ruling_near_the_surface(
            on_a in any::<bool>(), zone in 0usize..4, t in 0.0f64..1.0, v in -0.3f64..1.3,
            d in -3.0f64..3.0, along in -3.0f64..3.0
        ) {
            let part = SShape::iso();
            let s = if on_a { Surface::A } else { Surface::B };
            let u = match zone {
                0 => 0.01 * t,
                1 => 1.0 - 0.01 * t,
                2 => 0.4 + 0.2 * t,
                _ => t,
            };
            let f = part.frame_at(s, u, v);
            let p = f.point + f.n * d + f.t * along;
            for r in both(&part) {
                prop_assert_eq!(r.nearest(&p), scan(r.rulings(), &p));
            }
        }
    }

    /// Exact ties: a point on the axis of a cone frustum is equally far from all its rulings'
    /// lines up to rounding; whatever the distances, the first of the nearest is the scan's.
    #[test]
    fn ties_go_to_the_first_ruling_as_in_the_scan() {
        let cone = ConeFrustum::m3_15(false);
        let r = StartRulings::new(&cone, Surface::A);
        for z in [-5.0, 0.0, 7.5, 30.0] {
            let p = Vector3::new(0.0, 0.0, z);
            assert_eq!(r.nearest(&p), scan(r.rulings(), &p), "z = {z}");
        }
        // identical rulings: every distance equal, the first wins
        let same = StartRulings::of(vec![
            (
                Vector3::new(1.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, 1.0)
            );
            START_SAMPLES + 1
        ]);
        let p = Vector3::new(3.0, 4.0, 0.5);
        assert_eq!(same.nearest(&p), (0.0, 0.5, 4.0 + 16.0));
    }
}
