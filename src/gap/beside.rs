//! A family's members searched beside fixed columns (a pair's other member, [`super::pairs`]):
//! the member of least residual sum of squares found by a screen of one pass a member, then
//! the exact fit of the few members the screen cannot rank.
//!
//! The exact fit of a member `u` (one column, off the baseline) beside the fixed columns `F`
//! ([`Unabsorbed::beside`] then [`Unabsorbed::rss`]) factorises the `n × (1 + q)` matrix
//! `[u | F]` anew for every member: a Householder QR, its `Q`, `Q·U_R` and a solve, some thirty
//! passes over `n`-vectors (a named backlash's 54 members, searched twice or four times a pair
//! in the ~40 pairs of each of its diagnoses: a third of a 20,000-point scan's, issue 31). By Frisch–Waugh–Lovell the same
//! sum is, with `Q_F` an orthonormal basis of `F`'s span, `r_F = r₀ − Q_F Q_Fᵀ r₀` and
//! `c = Q_Fᵀ u`, `w = u − Q_F c` (`u`'s part outside `F`):
//!
//! `RSS(u) = ‖r_F‖² − (wᵀ r_F)² / ‖w‖²,  ‖w‖² = ‖u‖² − ‖c‖²,  wᵀr_F = uᵀr_F − cᵀ(Q_Fᵀ r_F)`,
//!
//! three dot products a member once `Q_F` and `r_F` are made for the search.
//!
//! **The same member, to the bit.** The screen is used only where both computations are well
//! conditioned, and only to rule members out; the least is always an exact fit:
//! - `[u | F]`, each column scaled by its norm before the baseline's projection (as the exact
//!   fit's rank is judged, [`crate::identify::solve`]), has full rank by a margin: with `σ_F` the
//!   smallest singular value of the scaled `F` and `‖w‖/‖s‖` the scaled part of `u` outside it,
//!   the scaled `[u | F]`'s smallest singular value is at least `σ_F·min(1, ‖w‖/‖s‖)/2` (split a
//!   unit vector `(a, b)` at `|a| = σ_F/2`); both at least [`SCREEN_MIN_SCALED`] put it above
//!   5·10⁻⁷, five times [`RANK_TOL`]: the exact fit keeps every column too;
//! - `‖w‖² ≥` [`SCREEN_MIN_OUTSIDE`]`·‖u‖²`: the subtraction `‖u‖² − ‖c‖²` loses at most three
//!   digits. A dot product of `n` terms in two partial sums (the page's wasm,
//!   [`products::tr_mul_into`]; nalgebra's eight natively) errs by at most `(n/2)·ε` of
//!   `‖x‖‖y‖` (1.1·10⁻¹² at 20,000 points, 1.1·10⁻¹¹ at 200,000), so the
//!   screened sum errs by at most ~2·10⁻⁸ of `‖r₀‖²` at 200,000 points, and the exact fit
//!   (backward stable, condition below 3·10⁶ by the bound above) by less than 10⁻⁹ of it;
//! - the members within `2δ` of the least screened sum, `δ =` [`SCREEN_MARGIN`]`·‖r₀‖²`, and
//!   those the screen does not take, are fitted exactly; every other member's exact sum exceeds
//!   the least screened one's exact sum, so the least exact sum (the first of equal ones, in the
//!   members' order) is that of the search of every member by the exact fit.

use std::borrow::Cow;

use nalgebra::{DMatrix, DVector};

use super::shape::Unabsorbed;
use crate::identify::solve::{usable_scale, Factor, RANK_TOL};
use crate::numerics::parallel::{map, Threads};
use crate::numerics::products;

/// The least scaled smallest singular value of `F`, and scaled part of a member outside it, for
/// the screen (module doc: with both, `[u | F]` is of full rank five times above [`RANK_TOL`]).
pub const SCREEN_MIN_SCALED: f64 = 1e-3;
/// The least share `‖w‖²/‖u‖²` of a member's squared norm outside `F` for the screen.
pub const SCREEN_MIN_OUTSIDE: f64 = 1e-3;
/// `δ/‖r₀‖²`: the screen's error bound with a margin (module doc: ~2·10⁻⁸ at 200,000 points).
pub const SCREEN_MARGIN: f64 = 1e-7;

// the bound of the module doc
const _: () = assert!(SCREEN_MIN_SCALED * SCREEN_MIN_SCALED / 2.0 >= 5.0 * RANK_TOL);

/// The fixed columns `F` of a search, with what the screen of a member needs of them.
pub struct Beside<'a> {
    fixed: &'a Unabsorbed,
    r0: &'a DVector<f64>,
    /// `Q_F`, `r_F`, `‖r_F‖²` and `Q_Fᵀ r_F`; `None` when `F` is not safely of full rank (every
    /// member is then fitted exactly).
    screen: Option<Screen>,
    /// `δ` of the module doc.
    delta: f64,
}

struct Screen {
    basis: DMatrix<f64>,
    rf: DVector<f64>,
    rrf: f64,
    grf: DVector<f64>,
}

impl<'a> Beside<'a> {
    /// The search beside `fixed` on the baseline residual `r0`.
    pub fn new(fixed: &'a Unabsorbed, r0: &'a DVector<f64>) -> Self {
        let q = fixed.u.ncols();
        let factor = Factor::new(&fixed.u, Some(&fixed.norms));
        // the scaled F's smallest singular value, from below: its largest is at least its
        // longest scaled column
        let longest = (0..q)
            .map(|j| fixed.u.column(j).norm() / usable_scale(fixed.norms[j]))
            .fold(0.0, f64::max);
        let safe = q > 0 && factor.rank == q && longest / factor.condition >= SCREEN_MIN_SCALED;
        let screen = safe.then(|| {
            let rf = factor.unabsorbed_vec(r0);
            Screen {
                rrf: rf.norm_squared(),
                grf: factor.basis.tr_mul(&rf),
                basis: factor.basis,
                rf,
            }
        });
        Self {
            fixed,
            r0,
            screen,
            delta: SCREEN_MARGIN * r0.norm_squared(),
        }
    }

    /// The exact residual sum of squares of the baseline, `u` and the fixed columns.
    pub fn exact(&self, u: &Unabsorbed) -> f64 {
        u.beside(self.fixed).rss(self.r0).0
    }

    /// The screened sum of `u` (module doc), `None` where the screen does not take `u`.
    fn screened(&self, u: &Unabsorbed) -> Option<f64> {
        let s = self.screen.as_ref()?;
        if u.u.ncols() != 1 {
            return None;
        }
        // `uᵀu`, `uᵀr_F` and `Q_Fᵀu`: nalgebra's dot products natively, one product in 128-bit
        // lanes in the page's wasm (where nalgebra's are scalar: half of the screen's time)
        let col = u.u.as_slice();
        let dots: Vec<f64> = if cfg!(target_arch = "wasm32") {
            let mut against = vec![col, s.rf.as_slice()];
            against.extend(products::columns(&s.basis));
            let mut out = vec![0.0; against.len()];
            products::tr_mul_into(&[col], &against, &mut out, 1, None);
            out
        } else {
            let v = u.u.column(0);
            [v.norm_squared(), v.dot(&s.rf)]
                .into_iter()
                .chain(s.basis.tr_mul(&v).iter().copied())
                .collect()
        };
        let (uu, urf, c) = (dots[0], dots[1], &dots[2..]);
        let ww = uu - c.iter().map(|x| x * x).sum::<f64>();
        if !(ww >= SCREEN_MIN_OUTSIDE * uu
            && ww.sqrt() / usable_scale(u.norms[0]) >= SCREEN_MIN_SCALED)
        {
            return None;
        }
        let d = urf - c.iter().zip(s.grf.iter()).map(|(x, g)| x * g).sum::<f64>();
        let v = s.rrf - d * d / ww;
        v.is_finite().then_some(v)
    }

    /// The index of the member of least exact residual sum of squares (the first of equal
    /// ones), of the `members`: the same index as the exact fit of every member (module doc),
    /// on `threads` threads.
    pub fn least(&self, members: &Members, threads: Threads) -> Option<usize> {
        let len = members.len();
        // the screen, or the exact fit where the screen does not take the member; members made
        // a block at a time
        let mut first: Vec<(f64, bool)> = Vec::with_capacity(len);
        let all: Vec<usize> = (0..len).collect();
        for block in all.chunks(members.block()) {
            let made = members.get(block, threads);
            first.extend(map(threads, &made, |u| match self.screened(u) {
                Some(v) => (v, false),
                None => (self.exact(u), true),
            }));
        }
        let least_screened = first
            .iter()
            .filter(|(_, exact)| !exact)
            .map(|(v, _)| *v)
            .fold(f64::INFINITY, f64::min);
        let bound = least_screened + 2.0 * self.delta;
        let close: Vec<usize> = all
            .iter()
            .copied()
            .filter(|&k| !first[k].1 && first[k].0 <= bound)
            .collect();
        let mut value: Vec<f64> = first
            .iter()
            .map(|&(v, exact)| if exact { v } else { f64::INFINITY })
            .collect();
        // (a block at a time: the members of a family the part does not have are all close)
        for block in close.chunks(members.block()) {
            let made = members.get(block, threads);
            let exact = map(threads, &made, |u| self.exact(u));
            for (&k, v) in block.iter().zip(exact) {
                value[k] = v;
            }
        }
        (0..len).min_by(|&a, &b| value[a].total_cmp(&value[b]))
    }
}

/// A family's members off the baseline, for [`Beside::least`]: kept from an earlier search, or
/// made when needed.
pub enum Members<'m> {
    /// Every member's part outside the baseline.
    Kept(&'m [Unabsorbed]),
    /// `len` members, member `k`'s columns `columns(k)`, projected off `baseline`
    /// [`MADE_BLOCK`] at a time together ([`Factor::unabsorbed_each`]: the baseline's basis read
    /// twice a thread and a block instead of twice a member, 61 MB at 200,000 points; the same
    /// numbers as [`Unabsorbed::of`] of each).
    Made {
        len: usize,
        columns: &'m (dyn Fn(usize) -> Cow<'m, DMatrix<f64>> + Sync),
        baseline: &'m Factor,
    },
}

/// Members made together by [`Members::Made`] (at 200,000 points a block's parts outside the
/// baseline are 13 MB; four a thread share each read of the baseline's basis).
pub const MADE_BLOCK: usize = 8;

impl Members<'_> {
    fn len(&self) -> usize {
        match self {
            Members::Kept(u) => u.len(),
            Members::Made { len, .. } => *len,
        }
    }

    /// Members taken at a time.
    fn block(&self) -> usize {
        match self {
            Members::Kept(u) => u.len().max(1),
            Members::Made { .. } => MADE_BLOCK,
        }
    }

    /// Members `ks`, borrowed or made (their columns side by side on `threads` threads).
    fn get(&self, ks: &[usize], threads: Threads) -> Vec<Cow<'_, Unabsorbed>> {
        match self {
            Members::Kept(u) => ks.iter().map(|&k| Cow::Borrowed(&u[k])).collect(),
            Members::Made {
                columns, baseline, ..
            } if cfg!(target_arch = "wasm32") => {
                // the page's wasm, on one thread: a member at a time (the same numbers; the
                // blocks' code kept out of its first module, at its size cap)
                ks.iter()
                    .map(|&k| Cow::Owned(Unabsorbed::of(baseline, &columns(k))))
                    .collect()
            }
            Members::Made {
                columns, baseline, ..
            } => {
                let cols: Vec<Cow<DMatrix<f64>>> = map(threads, ks, |&k| columns(k));
                let refs: Vec<&DMatrix<f64>> = cols.iter().map(|c| c.as_ref()).collect();
                let us = baseline.unabsorbed_each(&refs, threads);
                let norms: Vec<Vec<f64>> = cols
                    .iter()
                    .map(|s| (0..s.ncols()).map(|j| s.column(j).norm()).collect())
                    .collect();
                // (the columns dropped before the members are screened)
                drop(refs);
                drop(cols);
                us.into_iter()
                    .zip(norms)
                    .map(|(u, norms)| Cow::Owned(Unabsorbed { u, norms }))
                    .collect()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::random::Sampler;

    /// A baseline of 6 smooth columns on 3,000 points, its residual, fixed columns of 1 and 2
    /// columns, and 60 members: smooth waves, with near-copies of a fixed column (outside share
    /// 1e-6, 1e-3), a member the baseline all but absorbs, and a repeated member (a tie).
    fn case(q: usize) -> (Factor, DVector<f64>, Unabsorbed, Vec<Unabsorbed>) {
        let n = 3000;
        let mut rng = Sampler::new(5);
        let t = |i: usize| i as f64 / n as f64;
        let a = DMatrix::from_fn(n, 6, |i, j| t(i).powi(j as i32));
        let factor = Factor::new(&a, None);
        let y = DVector::from_fn(n, |i, _| {
            (9.0 * t(i)).sin() + 0.3 * (23.0 * t(i)).cos() + 0.01 * rng.normal()
        });
        let r0 = factor.unabsorbed_vec(&y);
        let fixed_cols = DMatrix::from_fn(n, q, |i, j| (7.0 * (j + 1) as f64 * t(i)).cos());
        let fixed = Unabsorbed::of(&factor, &fixed_cols);
        let mut members: Vec<Unabsorbed> = (0..56)
            .map(|k| {
                let w = 2.0 + 0.4 * k as f64;
                Unabsorbed::of(
                    &factor,
                    &DMatrix::from_fn(n, 1, |i, _| (w * t(i)).sin() + 0.1 * t(i)),
                )
            })
            .collect();
        for share in [1e-6, 1e-3] {
            let s = DMatrix::from_fn(n, 1, |i, _| {
                fixed_cols[(i, 0)] + share * (31.0 * t(i)).sin()
            });
            members.push(Unabsorbed::of(&factor, &s));
        }
        members.push(Unabsorbed::of(
            &factor,
            &DMatrix::from_fn(n, 1, |i, _| t(i).powi(2) + 1e-9 * t(i).powi(7)),
        ));
        members.push(members[20].clone());
        (factor, r0, fixed, members)
    }

    /// The screened sums are within 1e-9 of `‖r₀‖²` of the exact ones (the module's bound is
    /// 3e-8 at 200,000 points; 3,000 here), the near-copies and the absorbed member are left to
    /// the exact fit, and the least is the exact search's on 1 and 2 threads, for one and two
    /// fixed columns.
    #[test]
    fn the_screen_finds_the_exact_searchs_member() {
        for q in [1, 2] {
            let (_, r0, fixed, members) = case(q);
            let beside = Beside::new(&fixed, &r0);
            assert!(beside.screen.is_some(), "F of {q} columns is screened");
            let rr = r0.norm_squared();
            let mut left = 0;
            for u in &members {
                let exact = beside.exact(u);
                match beside.screened(u) {
                    Some(v) => assert!((v - exact).abs() <= 1e-9 * rr, "{v} against {exact}"),
                    None => left += 1,
                }
            }
            assert!(left >= 2, "{left} members left to the exact fit");
            let exact: Vec<f64> = members.iter().map(|u| beside.exact(u)).collect();
            let want = (0..members.len()).min_by(|&a, &b| exact[a].total_cmp(&exact[b]));
            for t in [1, 2] {
                let got = beside.least(&Members::Kept(&members), Threads::new(t));
                assert_eq!(got, want, "{q} fixed columns, {t} threads");
            }
        }
    }

    /// A tie (the same member twice) gives the first, as the exact search does: the least
    /// exact member repeated ahead of itself.
    #[test]
    fn a_tie_gives_the_first_member() {
        let (_, r0, fixed, members) = case(1);
        let beside = Beside::new(&fixed, &r0);
        let exact: Vec<f64> = members.iter().map(|u| beside.exact(u)).collect();
        let best = (0..members.len())
            .min_by(|&a, &b| exact[a].total_cmp(&exact[b]))
            .unwrap();
        let mut twice: Vec<Unabsorbed> = members.clone();
        twice.push(members[best].clone());
        let got = beside.least(&Members::Kept(&twice), Threads::ONE);
        assert_eq!(got, Some(best));
    }

    /// Members made a block at a time off the baseline ([`Members::Made`], 60 members: blocks
    /// of 8 and a last of 4) are those of [`Unabsorbed::of`] of each, bit for bit, and give
    /// the same member as when kept, on 1 and 2 threads.
    #[test]
    fn members_made_in_blocks_are_the_kept_ones() {
        let (factor, r0, fixed, members) = case(2);
        let n = r0.len();
        let t = |i: usize| i as f64 / n as f64;
        let columns: Vec<DMatrix<f64>> = (0..60)
            .map(|k| {
                DMatrix::from_fn(n, 1, |i, _| {
                    ((2.0 + 0.3 * k as f64) * t(i)).sin() + 0.2 * t(i)
                })
            })
            .collect();
        let kept: Vec<Unabsorbed> = columns.iter().map(|c| Unabsorbed::of(&factor, c)).collect();
        let beside = Beside::new(&fixed, &r0);
        let want = beside.least(&Members::Kept(&kept), Threads::ONE);
        let make = |k: usize| Cow::Borrowed(&columns[k]);
        for th in [1, 2] {
            let made = Members::Made {
                len: columns.len(),
                columns: &make,
                baseline: &factor,
            };
            let all: Vec<usize> = (0..columns.len()).collect();
            for (m, k) in made.get(&all, Threads::new(th)).iter().zip(&kept) {
                let bits = |x: &DMatrix<f64>| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&m.u), bits(&k.u));
                assert_eq!(m.norms, k.norms);
            }
            assert_eq!(beside.least(&made, Threads::new(th)), want, "{th} threads");
        }
        let _ = members;
    }
}
