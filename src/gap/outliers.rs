//! Single-point faults (a chip or dirt on the part, a probing error): points whose deviation no
//! smooth structure and no candidate effect explains, named, sized, and left out of the
//! identification and the diagnosis.
//!
//! **The rule** (externally studentised residuals against a robust σ, Bonferroni bound; Cook &
//! Weisberg, *Residuals and Influence in Regression*, 1982, §2.2.2; Belsley, Kuh & Welsch,
//! *Regression Diagnostics*, 1980, §2.1; robust scale: Rousseeuw & Croux, JASA 88, 1993, MAD).
//! On the kept points, the deviations `y` are fitted by the baseline design augmented with the
//! per-curve smooth basis of [`super::smooth_noise`]: `X = [A | P]` (location errors and
//! Legendre polynomials of degree [`SMOOTH_DEGREE`] along each curve, so that every effect that
//! varies smoothly along the curves is fitted and not taken for an outlier). With `e = (I − H) y`,
//! `h_ii` the leverage (the squared row norm of the orthonormal basis of `X`):
//! - the **deleted residual** `d_i = e_i / (1 − h_ii)` is the deviation of point `i` from the
//!   prediction of a fit without it: its size (mm);
//! - the **statistic** `t_i = e_i / (σ̂ √(1 − h_ii))` (`= d_i √(1 − h_ii) / σ̂`), with `σ̂` the
//!   CMM repeatability when given, else a robust scale of `u_j = e_j / √(1 − h_jj)` over the kept
//!   points: the MAD `1.4826 · median |u_j|`, then the RMS of the `u_j` within 2.5 MAD scales,
//!   corrected for the truncation (see `robust_sigma`; a single spike does not move it, the
//!   plain RMS would be inflated by it and hide it);
//! - the **bound**: `|t_i| > t_crit` with `t_crit` the two-sided Student-t quantile at `α / n`
//!   (Bonferroni over the `n` points tested, family-wise α = [`super::verdict::ALPHA`] = 0.05) on
//!   `n − rank(X)` degrees of freedom (≈ 3.65 for the 100 built-in points).
//!
//! `X` also holds the signature of the one candidate effect that leaves the smallest robust σ
//! (none unless it lowers σ̂ below [`CANDIDATE_GAIN`] = 0.8 of the σ̂ without it): an effect's structure that the smooth basis cannot follow
//! (a backlash step) would otherwise inflate σ̂ and hide a spike.
//!
//! **Guards against structure.** A point over the bound is named only when it is a single
//! isolated fault:
//! - *isolated*: in the fit without it, neither neighbour along its curve (the previous and the
//!   next point in `u`) shares the excursion (same sign and more than [`ISOLATION`] of its size):
//!   a step (an axis reversal) or a bump moves several neighbouring points;
//! - *no candidate explains it*: with each candidate effect's signature added to `X`, the point
//!   stays over the bound (a backlash step that falls on the last point of a curve leaves one
//!   large point, but the backlash signature fits it).
//!
//! At most [`MAX_OUTLIERS`] points are named, one per round (the largest `|t|` that passes the
//! guards), each round refitting without the points already named (so that one fault does not
//! mask another). Curves with fewer than [`MIN_CURVE_POINTS`] kept points are not tested (the
//! smooth basis would fit them exactly).
//!
//! Units: deviations, sizes and σ in mm; the statistic is dimensionless.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::data::GapInput;
use super::location::curve_sequences;
use super::lsq::Factor;
use super::smooth_noise::{smooth_basis, SMOOTH_DEGREE};
use super::stats;

/// Family-wise false-alarm rate of the outlier test (Bonferroni over the points).
pub const OUTLIER_ALPHA: f64 = 0.05;
/// Most points named as outliers on one part (one per round).
pub const MAX_OUTLIERS: usize = 3;
/// A neighbour along the curve that shares more than this fraction of a point's excursion (same
/// sign) makes it part of a structure, not a single-point fault.
pub const ISOLATION: f64 = 0.5;
/// A candidate's signature joins the fit when it lowers the robust σ below this fraction of the
/// σ without it (a clean part then keeps the plain fit: picking the best of many candidates
/// would otherwise lower σ̂ by chance).
pub const CANDIDATE_GAIN: f64 = 0.8;
/// Rejection point of the robust σ (in units of the MAD scale).
pub const REJECT_AT: f64 = 2.5;
/// Fewest points a curve needs for its points to be tested (more than the smooth basis's
/// `SMOOTH_DEGREE + 1` columns).
pub const MIN_CURVE_POINTS: usize = 2 * (SMOOTH_DEGREE + 1);

/// A point named as an outlier.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outlier {
    /// Row of the point in the input (0-based).
    #[serde(skip)]
    pub index: usize,
    /// Point id (as in the file when the caller sets it; else the point's metadata id).
    pub id: String,
    /// Curve label.
    pub curve: String,
    /// Deleted residual `d_i` (mm): the point's deviation from the fit without it.
    pub size: f64,
    /// Studentised residual `t_i` (dimensionless).
    pub statistic: f64,
}

/// What the outlier test did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutlierTest {
    /// The points named, in the order found.
    pub points: Vec<Outlier>,
    /// The rule, in words.
    pub rule: String,
    /// Family-wise α.
    pub alpha: f64,
    /// `t_crit` of the first round (over all points).
    pub threshold: f64,
    /// σ̂ of the first round (mm).
    pub sigma: f64,
    /// Where σ̂ came from: `given` or `robust`.
    pub sigma_source: String,
    /// Points over the bound that the guards kept as structure (ids).
    pub structured: Vec<String>,
}

impl OutlierTest {
    /// Rows of the points named.
    pub fn indices(&self) -> Vec<usize> {
        self.points.iter().map(|o| o.index).collect()
    }
}

/// Two-sided Student-t quantile: `t` with `P(|T_ν| > t) = p` (bisection on `F(1, ν)`; the
/// normal quantile when `ν` is infinite).
pub fn t_two_sided_quantile(p: f64, nu: f64) -> f64 {
    let tail = |t: f64| {
        if nu.is_finite() {
            stats::f_sf(t * t, 1.0, nu)
        } else {
            stats::normal_two_sided(t)
        }
    };
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while tail(hi) > p && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

fn hstack(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols() + b.ncols(), |i, j| {
        if j < a.ncols() {
            a[(i, j)]
        } else {
            b[(i, j - a.ncols())]
        }
    })
}

/// Residual, leverage and rank of the fit of `y` by `x` restricted to the rows `keep`
/// (the other rows get residual and leverage 0).
fn fit(x: &DMatrix<f64>, y: &DVector<f64>, keep: &[usize]) -> (Vec<f64>, Vec<f64>, usize) {
    let xs = x.select_rows(keep);
    let ys = DVector::from_iterator(keep.len(), keep.iter().map(|&i| y[i]));
    let f = Factor::new(&xs, None);
    let e = f.unabsorbed_vec(&ys);
    let n = x.nrows();
    let (mut r, mut h) = (vec![0.0; n], vec![0.0; n]);
    for (k, &i) in keep.iter().enumerate() {
        r[i] = e[k];
        h[i] = f.basis.row(k).norm_squared();
    }
    (r, h, f.rank)
}

/// `t_i` of every kept row (0 where the leverage is 1).
fn statistics(r: &[f64], h: &[f64], keep: &[usize], sigma: f64) -> Vec<f64> {
    let mut t = vec![0.0; r.len()];
    for &i in keep {
        let s = (1.0 - h[i]).max(0.0).sqrt();
        t[i] = if s > 1e-8 && sigma > 0.0 {
            r[i] / (sigma * s)
        } else {
            0.0
        };
    }
    t
}

/// The robust scale over the kept rows (mm): with `u_j = e_j / √(1 − h_jj)` (variance σ² for
/// white noise), `s₀ = 1.4826 · median |u_j|`, then the one-step rejection estimate
/// `σ̂² = mean(u_j² : |u_j| ≤ c s₀) / κ(c)`, `c` = [`REJECT_AT`], `κ(c) = 1 − 2cφ(c)/(2Φ(c) − 1)`
/// the variance of a standard normal truncated at ±c (Huber, *Robust Statistics*, 1981, §5.3:
/// the median alone has 37 % efficiency, the rejection step brings it near 90 %).
fn robust_sigma(r: &[f64], h: &[f64], keep: &[usize]) -> f64 {
    let u: Vec<f64> = keep
        .iter()
        .filter(|&&i| h[i] < 1.0 - 1e-8)
        .map(|&i| r[i] / (1.0 - h[i]).sqrt())
        .collect();
    let s0 = mad_sigma(&u);
    if s0 <= 0.0 {
        return s0;
    }
    let c = REJECT_AT;
    let inside: Vec<f64> = u.iter().copied().filter(|v| v.abs() <= c * s0).collect();
    if inside.is_empty() {
        return s0;
    }
    let phi = (-0.5 * c * c).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let mass = 1.0 - stats::normal_two_sided(c);
    let kappa = 1.0 - 2.0 * c * phi / mass;
    (inside.iter().map(|v| v * v).sum::<f64>() / inside.len() as f64 / kappa).sqrt()
}

/// `1.4826 · median |u|`.
fn mad_sigma(u: &[f64]) -> f64 {
    let mut a: Vec<f64> = u.iter().map(|v| v.abs()).collect();
    if a.is_empty() {
        return 0.0;
    }
    a.sort_by(f64::total_cmp);
    let m = a.len();
    let med = if m % 2 == 1 {
        a[m / 2]
    } else {
        0.5 * (a[m / 2 - 1] + a[m / 2])
    };
    1.482_6 * med
}

/// The neighbours of each row along its curve (previous and next in `u`, among all rows).
fn neighbours(input: &GapInput) -> Vec<Vec<usize>> {
    let mut nb = vec![Vec::new(); input.points.len()];
    for (_, idx) in curve_sequences(&input.points) {
        for (k, &i) in idx.iter().enumerate() {
            if k > 0 {
                nb[i].push(idx[k - 1]);
            }
            if k + 1 < idx.len() {
                nb[i].push(idx[k + 1]);
            }
        }
    }
    nb
}

/// Finds the single-point outliers of a measured part by the rule of the module doc (α =
/// [`OUTLIER_ALPHA`]); σ̂ is `input.noise_sigma` when given, else robust.
pub fn find_outliers(input: &GapInput) -> OutlierTest {
    let n = input.deviations.len();
    let y = DVector::from_column_slice(&input.deviations);
    let x0 = hstack(
        &input.baseline.matrix,
        &smooth_basis(&input.points, SMOOTH_DEGREE),
    );
    let nb = neighbours(input);
    let testable: Vec<bool> = {
        let mut t = vec![false; n];
        for (_, idx) in curve_sequences(&input.points) {
            if idx.len() >= MIN_CURVE_POINTS {
                for i in idx {
                    t[i] = true;
                }
            }
        }
        t
    };
    let mut named: Vec<Outlier> = Vec::new();
    let mut structured: Vec<String> = Vec::new();
    let mut first: Option<(f64, f64)> = None;
    for _round in 0..MAX_OUTLIERS {
        let keep: Vec<usize> = (0..n)
            .filter(|i| !named.iter().any(|o| o.index == *i))
            .collect();
        let x = with_best_candidate(input, &x0, &y, &keep);
        let (r, h, rank) = fit(&x, &y, &keep);
        let dof = keep.len().saturating_sub(rank);
        if dof < 2 {
            break;
        }
        let sigma = input
            .noise_sigma
            .unwrap_or_else(|| robust_sigma(&r, &h, &keep));
        let tested = keep.iter().filter(|&&i| testable[i]).count().max(1);
        let crit = t_two_sided_quantile(OUTLIER_ALPHA / tested as f64, dof as f64);
        first.get_or_insert((crit, sigma));
        if sigma <= 0.0 {
            break;
        }
        let t = statistics(&r, &h, &keep, sigma);
        let mut over: Vec<usize> = keep
            .iter()
            .copied()
            .filter(|&i| testable[i] && t[i].abs() > crit)
            .collect();
        over.sort_by(|&a, &b| t[b].abs().total_cmp(&t[a].abs()));
        let found = over.into_iter().find(|&i| {
            let ok = isolated(&x, &y, &keep, i, &nb[i], r[i] / (1.0 - h[i]).max(1e-12))
                && !explained(input, &x, &y, &keep, i, sigma, crit);
            if !ok {
                let id = input.points[i].id.to_string();
                if !structured.contains(&id) {
                    structured.push(id);
                }
            }
            ok
        });
        let Some(i) = found else { break };
        named.push(Outlier {
            index: i,
            id: input.points[i].id.to_string(),
            curve: input.points[i].curve.clone(),
            size: r[i] / (1.0 - h[i]).max(1e-12),
            statistic: t[i],
        });
    }
    let (threshold, sigma) = first.unwrap_or((f64::NAN, 0.0));
    OutlierTest {
        points: named,
        rule: format!(
            "externally studentised residual of the fit of the baseline plus a degree-{SMOOTH_DEGREE} \
             smooth basis per curve, |t| = |e|/(σ·√(1−h)) against the Student-t quantile at \
             α/n (Bonferroni, α = {OUTLIER_ALPHA}); σ {}; only isolated points (no neighbour \
             along the curve shares over {:.0} % of the excursion) that no candidate effect \
             explains; at most {MAX_OUTLIERS}, one per round",
            if input.noise_sigma.is_some() {
                "given"
            } else {
                "robust (MAD of e/√(1−h), then the RMS within 2.5 MAD scales)"
            },
            100.0 * ISOLATION
        ),
        alpha: OUTLIER_ALPHA,
        threshold,
        sigma,
        sigma_source: if input.noise_sigma.is_some() {
            "given".into()
        } else {
            "robust".into()
        },
        structured,
    }
}

/// `x` with the signature of the candidate that leaves the smallest robust σ on the rows `keep`
/// (or `x` alone when none does better): the structure of an effect (a backlash step) would
/// otherwise inflate σ̂ and hide a spike.
fn with_best_candidate(
    input: &GapInput,
    x: &DMatrix<f64>,
    y: &DVector<f64>,
    keep: &[usize],
) -> DMatrix<f64> {
    let scale = |m: &DMatrix<f64>| {
        let (r, h, _) = fit(m, y, keep);
        robust_sigma(&r, &h, keep)
    };
    let plain = scale(x);
    let mut best = (CANDIDATE_GAIN * plain, x.clone());
    for c in &input.candidates {
        let xc = hstack(x, &c.signature.matrix);
        let s = scale(&xc);
        if s < best.0 {
            best = (s, xc);
        }
    }
    best.1
}

/// Whether no neighbour of row `i` shares its excursion `d` in the fit without `i`.
fn isolated(
    x: &DMatrix<f64>,
    y: &DVector<f64>,
    keep: &[usize],
    i: usize,
    nb: &[usize],
    d: f64,
) -> bool {
    let without: Vec<usize> = keep.iter().copied().filter(|&k| k != i).collect();
    let (r, _, _) = fit(x, y, &without);
    nb.iter()
        .filter(|j| without.contains(j))
        .all(|&j| !(r[j].signum() == d.signum() && r[j].abs() > ISOLATION * d.abs()))
}

/// Whether some candidate's signature, added to `x`, brings row `i` under the bound.
fn explained(
    input: &GapInput,
    x: &DMatrix<f64>,
    y: &DVector<f64>,
    keep: &[usize],
    i: usize,
    sigma: f64,
    crit: f64,
) -> bool {
    input.candidates.iter().any(|c| {
        let xc = hstack(x, &c.signature.matrix);
        let (r, h, _) = fit(&xc, y, keep);
        let t = statistics(&r, &h, keep, sigma);
        t[i].abs() <= crit
    })
}

/// The input without the rows `drop` (deviations, points, designs; σ and reversals kept).
pub fn without_rows(input: &GapInput, drop: &[usize]) -> GapInput {
    let keep: Vec<usize> = (0..input.deviations.len())
        .filter(|i| !drop.contains(i))
        .collect();
    GapInput {
        deviations: keep.iter().map(|&i| input.deviations[i]).collect(),
        points: keep.iter().map(|&i| input.points[i].clone()).collect(),
        baseline: input.baseline.select_rows(&keep),
        candidates: input
            .candidates
            .iter()
            .map(|c| super::Candidate {
                effect: c.effect,
                signature: c.signature.select_rows(&keep),
            })
            .collect(),
        noise_sigma: input.noise_sigma,
        reversals: input.reversals.clone(),
    }
}

/// The sentence a report carries about the outliers (empty when none).
pub fn outlier_sentence(test: &OutlierTest, kept: bool) -> String {
    if test.points.is_empty() {
        return String::new();
    }
    let list: Vec<String> = test
        .points
        .iter()
        .map(|o| {
            format!(
                "point {} ({}, {:+.1} µm, |t| = {:.1})",
                o.id,
                o.curve,
                o.size * 1e3,
                o.statistic.abs()
            )
        })
        .collect();
    let what = if test.points.len() == 1 {
        "is a single-point outlier"
    } else {
        "are single-point outliers"
    };
    format!(
        "{} {what} (a chip, dirt or a probing error: |t| > {:.2}, Bonferroni α = {} over the points){}",
        list.join(", "),
        test.threshold,
        test.alpha,
        if kept {
            ": kept in the fit as asked (--keep-outliers)."
        } else {
            ": left out of the identification and the diagnosis."
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantile_matches_tables() {
        // t_{0.975, 10} = 2.228, z_{0.975} = 1.960, t_{0.99975, 70} ≈ 3.65 (Bonferroni 0.05/100; Cornish-Fisher z + (z³ + z)/(4ν)).
        assert!((t_two_sided_quantile(0.05, 10.0) - 2.228).abs() < 1e-3);
        assert!((t_two_sided_quantile(0.05, f64::INFINITY) - 1.960).abs() < 1e-3);
        let t = t_two_sided_quantile(0.0005, 70.0);
        assert!((t - 3.65).abs() < 0.01, "{t}");
    }
}
