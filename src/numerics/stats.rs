//! Distribution functions for the tests of the diagnosis: F, χ² and normal tail probabilities.
//!
//! `ln Γ` by the Lanczos approximation (g = 7, 9 terms; relative error < 1e-13), the regularized
//! incomplete beta `I_x(a, b)` by Lentz's continued fraction, the regularized incomplete gamma by
//! its series / continued fraction, `erfc` from `I_x`-free Chebyshev fit (|error| < 1.2e-7).
//! Sources: Abramowitz & Stegun 26.5.8 (beta continued fraction), 6.5.29/6.5.31 (gamma).

/// χ²₁ quantile at 0.95: fits closer than this (in σ² units) are not told apart.
pub const CHI2_1_95: f64 = 3.841_459;

/// The median (mean of the two middle values for an even count), reordering `x` in place (by a
/// selection, O(n): a full sort of a dense scan's 200,000 residuals was a tenth of a second of
/// the outlier rounds, issue 31; the middle values are the sorted order's, so the same number);
/// NaN when empty.
pub fn median(x: &mut [f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let m = x.len();
    let (left, mid, _) = x.select_nth_unstable_by(m / 2, f64::total_cmp);
    let mid = *mid;
    if m % 2 == 1 {
        mid
    } else {
        // the largest of the lower half: the sorted order's `x[m/2 − 1]`
        let below = left.iter().copied().max_by(f64::total_cmp).unwrap_or(mid);
        0.5 * (below + mid)
    }
}

/// `ln Γ(x)`, `x > 0`.
pub fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..400 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        if d.abs() < TINY {
            d = TINY;
        }
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        if d.abs() < TINY {
            d = TINY;
        }
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// Regularized incomplete beta function `I_x(a, b)`.
pub fn beta_inc(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_bt = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    let bt = ln_bt.exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        bt * beta_cf(a, b, x) / a
    } else {
        1.0 - bt * beta_cf(b, a, 1.0 - x) / b
    }
}

/// Upper tail `P(F > f)` of the F distribution with `(d1, d2)` degrees of freedom.
pub fn f_sf(f: f64, d1: f64, d2: f64) -> f64 {
    if f.is_nan() || f <= 0.0 {
        return 1.0;
    }
    beta_inc(d2 / 2.0, d1 / 2.0, d2 / (d2 + d1 * f))
}

/// Regularized lower incomplete gamma `P(a, x)`.
pub fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let gln = ln_gamma(a);
    if x < a + 1.0 {
        let (mut ap, mut sum) = (a, 1.0 / a);
        let mut del = sum;
        for _ in 0..1000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        sum * (-x + a * x.ln() - gln).exp()
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        1.0 - (-x + a * x.ln() - gln).exp() * h
    }
}

/// Upper tail `P(χ²_k > x)`.
pub fn chi2_sf(x: f64, k: f64) -> f64 {
    1.0 - gamma_p(k / 2.0, x / 2.0)
}

/// The `x` in `[0, hi]` where the decreasing survival function `sf` falls to `tail`, by
/// bisection (200 halvings: to the last bit of `hi`).
pub fn sf_inverse(sf: impl Fn(f64) -> f64, tail: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, hi);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if sf(mid) > tail {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The upper-`tail` quantile of `χ²_k`: `x` with `P(χ²_k > x) = tail`.
pub fn chi2_isf(tail: f64, k: f64) -> f64 {
    sf_inverse(|x| chi2_sf(x, k), tail, k + 40.0 * (2.0 * k).sqrt() + 100.0)
}

/// Complementary error function (Numerical Recipes `erfcc`, |relative error| < 1.2e-7).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let ans = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        ans
    } else {
        2.0 - ans
    }
}

/// Two-sided normal tail probability `P(|Z| > |z|)`.
pub fn normal_two_sided(z: f64) -> f64 {
    erfc(z.abs() / std::f64::consts::SQRT_2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn closed_forms() {
        // Γ(5) = 24, Γ(1/2) = √π.
        assert_near!(ln_gamma(5.0), 24f64.ln(), 1e-12);
        assert_near!(ln_gamma(0.5), std::f64::consts::PI.sqrt().ln(), 1e-12);
        // χ²₂ tail is exp(−x/2).
        assert_near!(chi2_sf(3.0, 2.0), (-1.5f64).exp(), 1e-12);
        // F(1, ∞)-like: F(1, d2) with x = t² is the two-sided t tail; for d1 = 2, d2 = 2:
        // P(F > f) = 1/(1+f).
        assert_near!(f_sf(3.0, 2.0, 2.0), 0.25, 1e-12);
        // Standard normal: P(|Z| > 1.959964) = 0.05.
        assert_near!(normal_two_sided(1.959_964), 0.05, 1e-6);
        // χ²₁ tail at 3.841459 = 0.05 (table value).
        assert_near!(chi2_sf(3.841_459, 1.0), 0.05, 1e-6);
        // F(1, 90) critical value at 5 %: 3.9469 (table).
        assert_near!(f_sf(3.946_9, 1.0, 90.0), 0.05, 1e-4);
        // χ² quantiles (tables: χ²₀.₉₅(1) = 3.841459, χ²₀.₉₇₅(10) = 20.483177).
        assert_near!(chi2_isf(0.05, 1.0), 3.841_459, 1e-6);
        assert_near!(chi2_isf(0.025, 10.0), 20.483_177, 1e-6);
    }

    /// The selection's median is the sorted order's, bit for bit: odd and even counts, ties,
    /// signed zeros and a run of equal values (the definition: the middle of the sorted values).
    #[test]
    fn the_median_is_the_sorted_middle() {
        let sorted_median = |x: &[f64]| {
            let mut s = x.to_vec();
            s.sort_by(f64::total_cmp);
            let m = s.len();
            if m % 2 == 1 {
                s[m / 2]
            } else {
                0.5 * (s[m / 2 - 1] + s[m / 2])
            }
        };
        for n in [1, 2, 3, 4, 7, 10, 101, 1000] {
            let x: Vec<f64> = (0..n)
                .map(|i| ((i * 7919 % 97) as f64 - 48.0) * 0.37 + (i as f64 * 1.3).sin())
                .collect();
            assert_eq!(
                median(&mut x.clone()).to_bits(),
                sorted_median(&x).to_bits(),
                "{n}"
            );
        }
        for x in [
            vec![0.0, -0.0],
            vec![2.0, 2.0, 1.0, 2.0],
            vec![-0.0, 0.0, 0.0, 5.0],
        ] {
            assert_eq!(
                median(&mut x.clone()).to_bits(),
                sorted_median(&x).to_bits(),
                "{x:?}"
            );
        }
        assert!(median(&mut []).is_nan());
    }
}
