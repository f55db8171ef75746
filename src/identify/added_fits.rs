//! Least squares of one `y` on `[A | S]` for many `S` beside the same `A` (a model and its
//! alternatives: [`crate::final_fit::model_spread`]), on a tall design: `A` factorised once.
//!
//! [`super::solve::Factor`] of `[A | S]` on more than [`QR_FIRST_ROWS`] rows is the Householder
//! QR of the column-scaled design, the SVD of its `R` (`R = U_R Σ Vᵀ`) and the basis
//! `U = Q·U_R` (`n × p`). Here the QR of `[A | S]` is that of `A` with `S`'s columns reflected
//! by `A`'s reflections, then by their own ([`HouseholderQr::added`]: the same `R` to the last
//! bit, so the same singular values, rank and `V Σ⁻¹`), and the fit needs no basis:
//! with `z = Qᵀy` (the whole `n × n` `Q`, its reflections applied to `y`; `A`'s once for all
//! the `S`), `z₁` its first `p` entries and `z₂` the others,
//!
//! `β = V Σ⁻¹ U_Kᵀ z₁` and `RSS = ‖z₂‖² + ‖z₁ − U_K U_Kᵀ z₁‖²`
//!
//! (`U_K` the kept columns of `U_R`; `Uᵀy = U_Kᵀ Qᵀy`, and `Q` keeps norms) — Golub & Van Loan,
//! *Matrix Computations*, 4th ed., §5.3.3 (least squares by QR) and §5.5.4 (by the SVD of `R`).
//! A model of 9 columns at 20,000 points had been a QR of all 9 (4.3 ms), its `Q` and
//! `Q·U_R` (issue 31); the same `β` and RSS to rounding (test).

use nalgebra::{DMatrix, DVector};

use super::householder::HouseholderQr;
use super::solve::{column_scales, jacobi_svd, kept, Kept, QR_FIRST_RATIO, QR_FIRST_ROWS};

/// A least-squares fit: every coefficient, the residual sum of squares and the numerical rank of
/// the scaled design (as [`super::solve::Factor`] decides it).
#[derive(Debug, Clone)]
pub struct AddedFit {
    pub beta: DVector<f64>,
    pub rss: f64,
    pub rank: usize,
}

/// `A` factorised with its columns scaled, and `Qᵀy` of its reflections.
#[derive(Debug, Clone)]
pub struct AddedFits {
    qr: HouseholderQr,
    /// The norms `A`'s columns are measured against ([`super::solve::Factor::new`]'s `scale`).
    d: Vec<f64>,
    /// `y` after `A`'s reflections.
    qty: Vec<f64>,
}

impl AddedFits {
    /// `A` (its columns measured against `scale`, as [`super::solve::Factor::new`]'s) and `y`;
    /// `None` when `A` has no column or its rows are not more than [`QR_FIRST_ROWS`] (the
    /// factorisation there is another: [`super::solve::Factor`]).
    pub fn new(a: &DMatrix<f64>, scale: &[f64], y: &DVector<f64>) -> Option<Self> {
        let (n, p) = a.shape();
        assert_eq!(y.len(), n, "y of {} entries for {n} rows", y.len());
        if p == 0 || n <= QR_FIRST_ROWS {
            return None;
        }
        let d = column_scales(a, Some(scale));
        let qr = HouseholderQr::new(scaled(a.clone(), &d));
        let mut qty = y.as_slice().to_vec();
        qr.q_tr_mul(&mut qty);
        Some(Self { qr, d, qty })
    }

    /// Whether `[A | S]` with `q` columns in `S` is factorised by a QR (at least
    /// [`QR_FIRST_RATIO`] rows a column), so that [`AddedFits::fit`] can take it.
    pub fn takes(&self, q: usize) -> bool {
        let (n, p) = self.qr_shape();
        q > 0 && n >= QR_FIRST_RATIO * (p + q)
    }

    /// The fit of `y` on `[A | s]`, `s`'s columns measured against `scale` ([`AddedFits::takes`]
    /// must hold).
    pub fn fit(&self, s: &DMatrix<f64>, scale: &[f64]) -> AddedFit {
        let (n, p) = self.qr_shape();
        let q = s.ncols();
        assert!(
            self.takes(q),
            "{q} columns added to {n} × {p}: not a tall design"
        );
        let ds = column_scales(s, Some(scale));
        let added = self.qr.added(scaled(s.clone(), &ds));
        let (u, sv, vt) = jacobi_svd(self.qr.r_with(&added));
        let d: Vec<f64> = self.d.iter().chain(&ds).copied().collect();
        let Kept { keep, vsi, .. } = kept(&sv, &vt, &d);
        let mut z = self.qty.clone();
        self.qr.added_q_tr_mul(&added, &mut z);
        let m = p + q;
        let z1 = DVector::from_column_slice(&z[..m]);
        let uk = u.select_columns(&keep);
        let c = uk.tr_mul(&z1);
        let inside = &z1 - &uk * &c;
        let rss = z[m..].iter().map(|x| x * x).sum::<f64>() + inside.norm_squared();
        AddedFit {
            beta: &vsi * c,
            rss,
            rank: keep.len(),
        }
    }

    fn qr_shape(&self) -> (usize, usize) {
        (self.qty.len(), self.d.len())
    }
}

/// `a`'s columns divided by `d` ([`super::solve::Factor`]'s scaling: times `1/d`).
fn scaled(mut a: DMatrix<f64>, d: &[f64]) -> DMatrix<f64> {
    for (j, dj) in d.iter().enumerate() {
        a.column_mut(j).scale_mut(1.0 / dj);
    }
    a
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::identify::solve::{hstack, Factor};
    use crate::numerics::random::Sampler;

    fn norms(x: &DMatrix<f64>) -> Vec<f64> {
        x.column_iter().map(|c| c.norm()).collect()
    }

    /// Against [`Factor`] of the whole `[A | S]`: the same rank, `β` and RSS to 1e-12 of their
    /// sizes (`Factor` forms `U = Q·U_R`, here `Qᵀy`: the roundings differ), on 2,500 rows with a
    /// column of `S` in `A`'s span (rank one short) and without; the factorisation itself is
    /// the whole one's bit for bit (`householder`'s tests).
    #[test]
    fn fits_are_the_factors_of_the_whole_design() {
        let mut rng = Sampler::new(5);
        let n = 2500;
        let a = DMatrix::from_fn(n, 8, |_, _| rng.normal());
        let y = DVector::from_fn(n, |_, _| rng.normal());
        let fits = AddedFits::new(&a, &norms(&a), &y).expect("tall");
        let free = DMatrix::from_fn(n, 2, |_, _| rng.normal());
        let mut inside = DMatrix::from_fn(n, 1, |_, _| rng.normal());
        inside.set_column(0, &(a.column(1) * 2.0 - a.column(4)));
        for (s, rank) in [(free, 10), (inside, 8)] {
            let whole = hstack(&a, &s);
            let f = Factor::new(&whole, Some(&norms(&whole)));
            let want_beta = f.solve(&y);
            let want_rss = f.unabsorbed_vec(&y).norm_squared();
            let got = fits.fit(&s, &norms(&s));
            assert_eq!(got.rank, rank);
            assert_eq!(f.rank, rank);
            let scale = want_beta.amax();
            for (g, w) in got.beta.iter().zip(want_beta.iter()) {
                assert!((g - w).abs() <= 1e-12 * scale, "β {g} against {w}");
            }
            assert!(
                (got.rss - want_rss).abs() <= 1e-12 * want_rss,
                "RSS {} against {want_rss}",
                got.rss
            );
        }
    }

    /// Not a tall design: no fits (the caller factorises the whole).
    #[test]
    fn short_designs_are_left_to_the_factor() {
        let a = DMatrix::from_element(QR_FIRST_ROWS, 2, 1.0);
        let y = DVector::zeros(QR_FIRST_ROWS);
        assert!(AddedFits::new(&a, &[1.0, 1.0], &y).is_none());
        let a = DMatrix::from_fn(QR_FIRST_ROWS + 1, 2, |i, j| ((i + j) % 7) as f64);
        let y = DVector::zeros(QR_FIRST_ROWS + 1);
        let fits = AddedFits::new(&a, &norms(&a), &y).expect("tall");
        assert!(fits.takes(1));
        assert!(!fits.takes(QR_FIRST_ROWS));
        assert!(!fits.takes(0));
    }
}
