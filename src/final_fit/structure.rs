//! Structure that no candidate explains, as a correlated error: its covariance along the tool
//! path, estimated by restricted maximum likelihood (REML).
//!
//! When the verdict is `unexplained` the residual carries a structured deviation of unknown
//! shape. The location errors fitted by ordinary least squares then carry whatever part of that
//! structure their signatures can absorb, and a std computed as if the residual were white
//! noise understates how far they can be off. We model the structure as a zero-mean Gaussian
//! process along the tool-tip path length `s` (effects.md: the order in which the part is
//! machined), with the squared-exponential covariance
//!
//! `Cov(e_i, e_j) = σ² δ_ij + τ² exp(−(s_i − s_j)² / (2 ℓ²))`,
//!
//! σ the white measurement noise of the diagnosis (given or estimated), `τ` the structure's
//! amplitude and `ℓ` its correlation length. Points at the same `s` (the Z11 and Z25 points of
//! one ruling, machined by the same tool pose) share the structure; points far apart along the
//! path do not. `τ` and `ℓ` are estimated by REML (Patterson and Thompson 1971): the likelihood of
//! the residual contrasts, which does not depend on the location errors and does not shrink the
//! estimate of `τ` by what the design absorbs. With `Σ = QΛQᵀ`-type eigen-decomposition of the
//! correlation matrix `K_ℓ` for each `ℓ` of a geometric grid, the restricted log-likelihood in
//! `τ²` is cheap (`d_i = σ² + τ² λ_i`, `B̃ = Qᵀ B` with `B` an orthonormal basis of the design's
//! column space):
//!
//! `−2 ℓ_R = Σ ln d_i + ln det(B̃ᵀ D⁻¹ B̃) + ỹᵀD⁻¹ỹ − (B̃ᵀD⁻¹ỹ)ᵀ (B̃ᵀD⁻¹B̃)⁻¹ (B̃ᵀD⁻¹ỹ)`
//!
//! (up to a constant), maximised over `ln τ²` by golden-section search for every `ℓ`.
//!
//! The generalised least squares of [`crate::identify::correlated`] with this `Σ` gives the
//! location errors whose std includes the structure: a structure of the estimated amplitude and
//! length could move them by that much. It is a model of the structure's statistics, not of its
//! shape: a structure whose shape happens to equal a location error's signature exactly cannot
//! be told from that error by any method, and the std then says how large such a confusion can be.

use std::sync::{Arc, Mutex, PoisonError};

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::effects::data::PointMeta;
use crate::identify::solve::Factor;
use crate::numerics::memo::Memo;
use crate::numerics::parallel::{map, Threads};

/// Number of correlation lengths tried, geometric between the point spacing and the path.
pub const LENGTH_GRID: usize = 14;

/// The estimated covariance of the structure (mm, mm of tool path).
#[derive(Debug, Clone, Serialize)]
pub struct StructureCovariance {
    /// `squared_exponential_along_path`.
    pub kernel: &'static str,
    /// White noise σ (mm), as the diagnosis used it.
    pub white_sigma: f64,
    /// Structure amplitude τ (mm).
    pub amplitude: f64,
    /// Correlation length ℓ along the tool-tip path (mm).
    pub length: f64,
    /// Restricted log-likelihood at the estimate (up to a constant).
    pub restricted_log_likelihood: f64,
    /// Above [`DENSE_MAX_POINTS`] points: the number of groups along the path the structure
    /// was taken constant on, and their width (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grouped: Option<Grouping>,
    /// The covariance `σ² I + τ² K_ℓ` (mm², not serialised).
    #[serde(skip)]
    pub form: CovarianceForm,
}

/// How a large part's structure was grouped along the path.
#[derive(Debug, Clone, Serialize)]
pub struct Grouping {
    pub groups: usize,
    /// Width of a group along the tool-tip path (mm): structure shorter than this is white.
    pub width: f64,
}

/// The covariance of [`StructureCovariance`]: the `n × n` matrix up to [`DENSE_MAX_POINTS`]
/// points; above, the structure taken constant within groups of points along the path, `K_ℓ ≈
/// P K_g Pᵀ` (`P` the points' group, `K_g` the kernel between the groups' mean `s`), kept as
/// its eigen-decomposition `U Λ Uᵀ` with `U = P C^{-½} V` orthonormal (`C` the groups' sizes,
/// `C^{½} K_g C^{½} = V Λ Vᵀ`): `Σ = σ² I + τ² U Λ Uᵀ`, never formed (20,000 points: 3.2 GB).
#[derive(Debug, Clone)]
pub enum CovarianceForm {
    Dense(DMatrix<f64>),
    Grouped {
        /// The group of each point.
        group: Vec<usize>,
        /// `c_g^{-½}` per group.
        scale: Vec<f64>,
        /// `V` (groups × groups).
        v: DMatrix<f64>,
        /// `τ² λ_k` (mm²).
        d: Vec<f64>,
    },
}

/// Up to this many points the structure's covariance is the exact `n × n` matrix (its 14
/// eigen-decompositions cost O(n³): 0.3 s at 400 points natively).
pub const DENSE_MAX_POINTS: usize = 400;

/// Above [`DENSE_MAX_POINTS`], the number of groups of equal width along the path.
pub const GROUPS: usize = 256;

/// The correlation matrix `K_ℓ` of the points' path positions.
pub fn correlation(points: &[PointMeta], length: f64) -> DMatrix<f64> {
    let n = points.len();
    DMatrix::from_fn(n, n, |i, j| {
        let d = (points[i].s - points[j].s) / length;
        libm::exp(-0.5 * d * d)
    })
}

/// The eigen-decomposition of [`correlation`] at one length: eigenvalues clamped at 0, and the
/// eigenvectors (columns).
struct Decomposition {
    lambda: Vec<f64>,
    q: DMatrix<f64>,
}

/// Point sets whose decompositions a [`Decompositions`] keeps: they depend only on the points'
/// path positions `s` (the part design and the settings), not on the deviations, so a
/// re-analysis of the same points (or another part at them) reuses them.
const KEPT: usize = 2;
/// Larger point sets are not kept (14 matrices of `n²` numbers each: 18 MB at 400 points).
const KEPT_MAX_POINTS: usize = 400;

/// The eigen-decompositions of [`correlation`] at the grid's lengths for the last [`KEPT`] point
/// sets (of at most [`KEPT_MAX_POINTS`] points) that [`estimate`] was given with it: a value its
/// caller holds, one per measured point set (`crate::analysis::PointsModel`), so that the
/// analyses of several deviations at the same points decompose once. The estimate is the same,
/// bit for bit, with a fresh one (the test below).
pub struct Decompositions {
    kept: Mutex<Memo<Vec<u64>, Vec<Decomposition>>>,
}

impl Default for Decompositions {
    fn default() -> Self {
        Self {
            kept: Mutex::new(Memo::new(KEPT)),
        }
    }
}

impl Decompositions {
    /// The memo, locked (threads sharing a points model, `validate --threads`, take turns; the
    /// lock is held to look up or insert, never while decomposing). A thread that panicked
    /// holding it left the memo whole (a lookup or an insert does not panic half-way), so its
    /// poison is ignored.
    fn memo(&self) -> std::sync::MutexGuard<'_, Memo<Vec<u64>, Vec<Decomposition>>> {
        self.kept.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

impl std::fmt::Debug for Decompositions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Decompositions({} point sets)", self.memo().len())
    }
}

/// The decompositions of `K_ℓ` at every length of the grid over `(lo, hi)`, from `kept` when it
/// has them (the lengths follow from the `s`, so the `s` bits are the key).
fn decompositions(
    points: &[PointMeta],
    (lo, hi): (f64, f64),
    kept: &Decompositions,
    threads: Threads,
) -> Arc<Vec<Decomposition>> {
    let key: Vec<u64> = points.iter().map(|p| p.s.to_bits()).collect();
    if let Some(d) = kept.memo().find(|k| *k == key) {
        return d;
    }
    // (each length's on its own, side by side on the threads: the same matrices)
    let lengths: Vec<usize> = (0..LENGTH_GRID).collect();
    let d: Arc<Vec<Decomposition>> = Arc::new(map(threads, &lengths, |&k| {
        let eig = nalgebra::SymmetricEigen::new(correlation(points, grid_length(lo, hi, k)));
        Decomposition {
            lambda: eig.eigenvalues.iter().map(|l| l.max(0.0)).collect(),
            q: eig.eigenvectors,
        }
    }));
    if points.len() <= KEPT_MAX_POINTS {
        kept.memo().insert(key, Arc::clone(&d));
    }
    d
}

/// The `k`-th length of the geometric grid of [`LENGTH_GRID`] lengths from `lo` to `hi` (mm).
fn grid_length(lo: f64, hi: f64, k: usize) -> f64 {
    lo * (hi / lo).powf(k as f64 / (LENGTH_GRID - 1) as f64)
}

/// The REML estimate of the structure's covariance for the residual of `design` on `y`, the
/// white σ (mm) being fixed, with the decompositions `kept` for these points (a fresh
/// [`Decompositions`] computes them). `None` without a positive σ or with fewer points than two
/// more than the design's rank. The lengths of the grid are tried side by side on `threads`
/// threads (the same estimate whatever the threads: each length's likelihood is its own, the
/// best taken in the grid's order).
pub fn estimate(
    points: &[PointMeta],
    design: &DMatrix<f64>,
    y: &[f64],
    white_sigma: f64,
    kept: &Decompositions,
    threads: Threads,
) -> Option<StructureCovariance> {
    let n = points.len();
    if !(white_sigma > 0.0 && white_sigma.is_finite()) || y.len() != n || design.nrows() != n {
        return None;
    }
    let basis = Factor::of_on(design.clone(), None, threads).basis;
    if n < basis.ncols() + 2 {
        return None;
    }
    if n > DENSE_MAX_POINTS {
        return estimate_grouped(points, &basis, y, white_sigma, threads);
    }
    let y = DVector::from_column_slice(y);
    let (lo, hi) = length_range(points);
    let s2 = white_sigma * white_sigma;
    let mut best: Option<(f64, f64, f64)> = None; // (loglik, tau2, length)
    let decompositions = decompositions(points, (lo, hi), kept, threads);
    for (k, Decomposition { lambda, q }) in decompositions.iter().enumerate() {
        let length = grid_length(lo, hi, k);
        let bt = q.transpose() * &basis;
        let yt = q.transpose() * &y;
        let loglik = |tau2: f64| restricted_log_likelihood(lambda, &bt, &yt, s2, tau2);
        let (t, f) = golden_ln_tau2(s2, loglik);
        if f.is_finite() && best.is_none_or(|(bf, _, _)| f > bf) {
            best = Some((f, libm::exp(t), length));
        }
    }
    let (loglik, tau2, length) = best?;
    let mut matrix = correlation(points, length) * tau2;
    for i in 0..n {
        matrix[(i, i)] += s2;
    }
    Some(StructureCovariance {
        kernel: "squared_exponential_along_path",
        white_sigma,
        amplitude: tau2.sqrt(),
        length,
        restricted_log_likelihood: loglik,
        grouped: None,
        form: CovarianceForm::Dense(matrix),
    })
}

/// Golden section of `f` over `ln τ²` in `[ln 1e-4 σ², ln 1e4 σ²]` (40 steps), then `ln τ²`
/// rounded to 1e-4 (0.01 % of τ²: the optimum of a flat likelihood is located only to about
/// √ε; `exp` and `ln` are libm's, pure Rust, so the native and wasm builds agree bit for bit):
/// `(ln τ², f)`.
fn golden_ln_tau2(s2: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let (mut a, mut b) = (libm::log(1e-4 * s2), libm::log(1e4 * s2));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(libm::exp(c)), f(libm::exp(d)));
    for _ in 0..40 {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(libm::exp(c));
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(libm::exp(d));
        }
    }
    let t = if fc > fd { c } else { d };
    let t = (t * 1e4).round() / 1e4;
    (t, f(libm::exp(t)))
}

/// [`estimate`] above [`DENSE_MAX_POINTS`] points, on [`GROUPS`] groups of equal width along
/// the path ([`CovarianceForm::Grouped`]); the lengths tried start at the group width.
fn estimate_grouped(
    points: &[PointMeta],
    basis: &DMatrix<f64>,
    y: &[f64],
    white_sigma: f64,
    threads: Threads,
) -> Option<StructureCovariance> {
    let n = points.len();
    let (s_lo, s_hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.s), b.max(p.s))
        });
    let width = ((s_hi - s_lo) / GROUPS as f64).max(1e-6);
    let raw: Vec<usize> = points
        .iter()
        .map(|p| (((p.s - s_lo) / width) as usize).min(GROUPS - 1))
        .collect();
    // Number the non-empty groups in path order: each group's size and the sum of its members'
    // `s` in one pass over the points, in the points' order (a pass a group had been 256 passes,
    // 51 million tests at 200,000 points; each sum in the same order from `-0.0`, as `Sum`)
    let mut members = vec![0usize; GROUPS];
    let mut s_sum = vec![-0.0f64; GROUPS];
    for (&k, p) in raw.iter().zip(points) {
        members[k] += 1;
        s_sum[k] += p.s;
    }
    let mut index = vec![usize::MAX; GROUPS];
    let mut count: Vec<f64> = Vec::new();
    let mut centre: Vec<f64> = Vec::new();
    for (k, slot) in index.iter_mut().enumerate() {
        if members[k] > 0 {
            *slot = count.len();
            count.push(members[k] as f64);
            centre.push(s_sum[k] / members[k] as f64);
        }
    }
    let group: Vec<usize> = raw.iter().map(|&k| index[k]).collect();
    let g = count.len();
    let scale: Vec<f64> = count.iter().map(|c| 1.0 / c.sqrt()).collect();
    let s2 = white_sigma * white_sigma;
    let yv = DVector::from_column_slice(y);
    // `diag(scale) Gᵀ x`, the scaled group sums of a column (`Uᵀx = Vᵀ` of them): once for `y`
    // and each basis column, what the lengths' `V` multiply (they had been summed again at each
    // length)
    let group_sums = |x: &[f64]| -> DVector<f64> {
        let mut sums = DVector::zeros(g);
        for (i, &b) in group.iter().enumerate() {
            sums[b] += x[i];
        }
        for b in 0..g {
            sums[b] *= scale[b];
        }
        sums
    };
    let y_sums = group_sums(y);
    let basis_sums: Vec<DVector<f64>> = basis
        .column_iter()
        .map(|c| group_sums(c.as_slice()))
        .collect();
    let yy = yv.norm_squared();
    let by = basis.transpose() * &yv;
    let (lo, hi) = length_range(points);
    let (lo, hi) = (lo.max(width), hi.max(width));
    // each length's (log-likelihood, τ², length, V, λ), side by side on the threads (a 256 × 256
    // eigen-decomposition each: the fourteen had been 0.2 s of one thread on a 20,000-point scan,
    // issue 31); the best taken in the grid's order, as one length after the other
    type Best = (f64, f64, f64, DMatrix<f64>, Vec<f64>);
    let lengths: Vec<usize> = (0..LENGTH_GRID).collect();
    let tried: Vec<Best> = map(threads, &lengths, |&k| {
        let length = grid_length(lo, hi, k);
        let kg = DMatrix::from_fn(g, g, |a, b| {
            let d = (centre[a] - centre[b]) / length;
            libm::exp(-0.5 * d * d) * (count[a] * count[b]).sqrt()
        });
        let eig = nalgebra::SymmetricEigen::new(kg);
        let lambda: Vec<f64> = eig.eigenvalues.iter().map(|l| l.max(0.0)).collect();
        let v = eig.eigenvectors;
        let vt = v.transpose();
        let yt = &vt * &y_sums;
        let bt = DMatrix::from_columns(&basis_sums.iter().map(|c| &vt * c).collect::<Vec<_>>());
        let f = |tau2: f64| grouped_log_likelihood(&lambda, &bt, &yt, s2, tau2, n, yy, &by);
        let (t, fv) = golden_ln_tau2(s2, f);
        (fv, libm::exp(t), length, v, lambda)
    });
    let mut best: Option<Best> = None;
    for b in tried {
        if b.0.is_finite() && best.as_ref().is_none_or(|x| b.0 > x.0) {
            best = Some(b);
        }
    }
    let (loglik, tau2, length, v, lambda) = best?;
    Some(StructureCovariance {
        kernel: "squared_exponential_along_path",
        white_sigma,
        amplitude: tau2.sqrt(),
        length,
        restricted_log_likelihood: loglik,
        grouped: Some(Grouping { groups: g, width }),
        form: CovarianceForm::Grouped {
            group,
            scale,
            v,
            d: lambda.iter().map(|l| tau2 * l).collect(),
        },
    })
}

/// `ℓ_R` of [`restricted_log_likelihood`] for `Σ = σ² I + τ² U Λ Uᵀ` with `U` (n × g)
/// orthonormal: the `g` components in `U`'s span as there, the `n − g` others of variance `σ²`
/// from the totals (`yy = yᵀy`, `by = Bᵀy`, `BᵀB = I`).
#[allow(clippy::too_many_arguments)]
fn grouped_log_likelihood(
    lambda: &[f64],
    bt: &DMatrix<f64>,
    yt: &DVector<f64>,
    s2: f64,
    tau2: f64,
    n: usize,
    yy: f64,
    by: &DVector<f64>,
) -> f64 {
    let r = bt.ncols();
    let g = lambda.len();
    let dinv: Vec<f64> = lambda.iter().map(|l| 1.0 / (s2 + tau2 * l)).collect();
    let logdet_sigma: f64 =
        dinv.iter().map(|d| -libm::log(*d)).sum::<f64>() + (n - g) as f64 * libm::log(s2);
    // Inside U's span with their own variances, outside with σ².
    let btb = bt.transpose() * bt;
    let bty = bt.transpose() * yt;
    let mut m = (DMatrix::identity(r, r) - &btb) / s2;
    let mut b_y = (by - &bty) / s2;
    let mut q = (yy - yt.norm_squared()) / s2;
    for (i, di) in dinv.iter().enumerate() {
        q += di * yt[i] * yt[i];
        for a in 0..r {
            let ba = bt[(i, a)] * di;
            b_y[a] += ba * yt[i];
            for b in 0..r {
                m[(a, b)] += ba * bt[(i, b)];
            }
        }
    }
    finish(m, &b_y, q, logdet_sigma)
}

/// The range of correlation lengths tried (mm): from the median spacing of neighbouring points
/// along the path to the whole path.
fn length_range(points: &[PointMeta]) -> (f64, f64) {
    let mut s: Vec<f64> = points.iter().map(|p| p.s).collect();
    s.sort_by(f64::total_cmp);
    let span = (s.last().copied().unwrap_or(0.0) - s.first().copied().unwrap_or(0.0)).max(1.0);
    let mut gaps: Vec<f64> = s
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|g| *g > 1e-6)
        .collect();
    gaps.sort_by(f64::total_cmp);
    let spacing = gaps.get(gaps.len() / 2).copied().unwrap_or(span / 10.0);
    (spacing.clamp(1e-3, span), span)
}

/// `ℓ_R` (up to a constant) for `Σ = Q diag(σ² + τ² λ) Qᵀ`, `bt = QᵀB`, `yt = Qᵀy`.
fn restricted_log_likelihood(
    lambda: &[f64],
    bt: &DMatrix<f64>,
    yt: &DVector<f64>,
    s2: f64,
    tau2: f64,
) -> f64 {
    let dinv: Vec<f64> = lambda.iter().map(|l| 1.0 / (s2 + tau2 * l)).collect();
    let logdet_sigma: f64 = dinv.iter().map(|d| -libm::log(*d)).sum();
    let r = bt.ncols();
    let mut m = DMatrix::zeros(r, r);
    let mut by = DVector::zeros(r);
    let mut yy = 0.0;
    for (i, di) in dinv.iter().enumerate() {
        yy += di * yt[i] * yt[i];
        for a in 0..r {
            let ba = bt[(i, a)] * di;
            by[a] += ba * yt[i];
            for b in 0..=a {
                m[(a, b)] += ba * bt[(i, b)];
            }
        }
    }
    for a in 0..r {
        for b in 0..a {
            m[(b, a)] = m[(a, b)];
        }
    }
    finish(m, &by, yy, logdet_sigma)
}

/// `−½ (ln det Σ + ln det M + q − bᵀM⁻¹b)` of the restricted likelihood from `M = B̃ᵀD⁻¹B̃`,
/// `b = B̃ᵀD⁻¹ỹ`, `q = ỹᵀD⁻¹ỹ` and `ln det Σ`; −∞ when `M` is not positive definite.
fn finish(m: DMatrix<f64>, by: &DVector<f64>, q: f64, logdet_sigma: f64) -> f64 {
    let Some(ch) = m.cholesky() else {
        return f64::NEG_INFINITY;
    };
    let l: DMatrix<f64> = ch.l();
    let logdet_m: f64 = 2.0
        * l.diagonal()
            .iter()
            .map(|v: &f64| libm::log(*v))
            .sum::<f64>();
    let quad = q - by.dot(&ch.solve(by));
    -0.5 * (logdet_sigma + logdet_m + quad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::random::Sampler;
    use crate::part::Surface;

    fn points(n: usize, spacing: f64) -> Vec<PointMeta> {
        (0..n)
            .map(|i| PointMeta {
                id: i as u32 + 1,
                curve: "A_Z11".into(),
                surface: Surface::A,
                u: i as f64 / (n - 1) as f64,
                h: 11.0,
                s: i as f64 * spacing,
                order: i,
                nz: 0.0,
            })
            .collect()
    }

    /// White noise alone: REML puts the structure's amplitude far below σ (seeded sample of
    /// 100 points, σ = 1.5 µm, a constant in the design).
    #[test]
    fn white_noise_has_no_structure() {
        let p = points(100, 25.0);
        let mut rng = Sampler::new(3);
        let y: Vec<f64> = (0..100).map(|_| 0.0015 * rng.normal()).collect();
        let a = DMatrix::from_element(100, 1, 1.0);
        let s = estimate(&p, &a, &y, 0.0015, &Decompositions::default(), Threads::ONE).unwrap();
        assert!(s.amplitude < 0.5 * 0.0015, "τ = {}", s.amplitude);
    }

    /// A waviness of 5 µm amplitude and 400 mm wavelength on 1.5 µm noise: REML finds an
    /// amplitude of the wave's size (its RMS is 3.5 µm; accepted 2-8 µm) and a correlation
    /// length of the order of a quarter wavelength (accepted 30-300 mm).
    #[test]
    fn a_waviness_is_found_with_its_size_and_scale() {
        let p = points(100, 25.0);
        let mut rng = Sampler::new(5);
        let y: Vec<f64> = p
            .iter()
            .map(|q| {
                0.005 * (2.0 * std::f64::consts::PI * q.s / 400.0).sin() + 0.0015 * rng.normal()
            })
            .collect();
        let a = DMatrix::from_element(100, 1, 1.0);
        let s = estimate(&p, &a, &y, 0.0015, &Decompositions::default(), Threads::ONE).unwrap();
        assert!((0.002..0.008).contains(&s.amplitude), "τ = {}", s.amplitude);
        assert!((30.0..300.0).contains(&s.length), "ℓ = {}", s.length);
    }

    /// The decompositions kept for the points give the estimate computed without them, bit for
    /// bit (another deviation vector of the same points reuses them).
    fn dense(c: &StructureCovariance) -> DMatrix<f64> {
        match &c.form {
            CovarianceForm::Dense(m) => m.clone(),
            CovarianceForm::Grouped { .. } => panic!("grouped"),
        }
    }

    /// The estimate on 3 threads is the one on 1, bit for bit, dense (300 points: the length
    /// grid's decompositions side by side) and grouped (3,000 points: the lengths' likelihoods
    /// side by side). Tolerance: none (each length's numbers are its own, the best taken in the
    /// grid's order).
    #[test]
    fn the_estimate_on_threads_is_the_one_on_one_thread() {
        for (n, spacing) in [(300, 1.0), (3000, 0.1)] {
            let p = points(n, spacing);
            let mut rng = Sampler::new(5);
            let y: Vec<f64> = p
                .iter()
                .map(|q| 0.004 * libm::sin(q.s / 9.0) + 0.0015 * rng.normal())
                .collect();
            let a = DMatrix::from_fn(n, 2, |i, j| if j == 0 { 1.0 } else { p[i].s });
            let one = estimate(&p, &a, &y, 0.0015, &Decompositions::default(), Threads::ONE);
            let three = estimate(
                &p,
                &a,
                &y,
                0.0015,
                &Decompositions::default(),
                Threads::new(3),
            );
            let (one, three) = (one.unwrap(), three.unwrap());
            assert_eq!(one.grouped.is_some(), n > DENSE_MAX_POINTS);
            assert_eq!(format!("{one:?}"), format!("{three:?}"), "{n} points");
        }
    }

    /// 400 points at 200 path positions (two per position, as the Z11 and Z25 points of one
    /// ruling), each position in a group of its own: the grouped REML is the dense one, exactly
    /// in theory; measured to 1e-9 relative on τ and equal lengths.
    #[test]
    fn the_grouped_estimate_is_the_dense_one_when_groups_are_positions() {
        let single = points(200, 3.0);
        let p: Vec<PointMeta> = single.iter().chain(&single).cloned().collect();
        let mut rng = Sampler::new(11);
        let y: Vec<f64> = p
            .iter()
            .map(|q| 0.004 * libm::sin(q.s / 40.0) + 0.0015 * rng.normal())
            .collect();
        let a = DMatrix::from_element(p.len(), 1, 1.0);
        let d = estimate(&p, &a, &y, 0.0015, &Decompositions::default(), Threads::ONE).unwrap();
        assert!(d.grouped.is_none());
        let basis = Factor::new(&a, None).basis;
        let g = estimate_grouped(&p, &basis, &y, 0.0015, Threads::ONE).unwrap();
        assert_eq!(g.grouped.as_ref().unwrap().groups, 200);
        assert_eq!(g.length.to_bits(), d.length.to_bits());
        assert!(
            (g.amplitude / d.amplitude - 1.0).abs() < 1e-9,
            "{} {}",
            g.amplitude,
            d.amplitude
        );
        assert!(
            (g.restricted_log_likelihood - d.restricted_log_likelihood).abs() < 1e-6,
            "{} {}",
            g.restricted_log_likelihood,
            d.restricted_log_likelihood
        );
    }

    #[test]
    fn kept_decompositions_give_the_same_estimate() {
        let p = points(60, 20.0);
        let mut rng = Sampler::new(7);
        let a = DMatrix::from_element(60, 1, 1.0);
        let ys: Vec<Vec<f64>> = (0..2)
            .map(|_| (0..60).map(|_| 0.0015 * rng.normal()).collect())
            .collect();
        let mut fresh = Vec::new();
        for y in &ys {
            fresh.push(
                estimate(&p, &a, y, 0.0015, &Decompositions::default(), Threads::ONE).unwrap(),
            );
        }
        let kept_for_p = Decompositions::default();
        for (y, f) in ys.iter().zip(&fresh) {
            let kept = estimate(&p, &a, y, 0.0015, &kept_for_p, Threads::ONE).unwrap();
            assert_eq!(kept.amplitude.to_bits(), f.amplitude.to_bits());
            assert_eq!(kept.length.to_bits(), f.length.to_bits());
            assert_eq!(dense(&kept), dense(f));
        }
    }
}
