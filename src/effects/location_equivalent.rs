//! Candidates that are a location error of the machine under another name (issue 20: "a
//! candidate that equals a location error of the machine is not offered under another name").
//!
//! A candidate whose every signature column is absorbed by the machine's baseline (its location
//! errors, [`crate::sensitivity::error_set`]) to less than
//! [`crate::sensitivity::error_set::VISIBLE_FRACTION`] of its RMS at the part's 100 built-in
//! points is that location error on this part: it is not offered, and the reports say which
//! error it is. The rule is the error set's own (the identification's condition index 30), and
//! like the set it is decided once per machine on the built-in design, whatever the file's
//! points (by the prepared settings, [`crate::effects::prepared::Prepared`]). Columns that are exactly zero (an effect invisible on the machine, e.g. `backlash_z` on
//! the tilting table) are not "absorbed": the diagnosis reports them as invisible.
//!
//! On the three machines (signed branch) only one candidate is left out this way: `c_index` on
//! paper 002's tilting table, whose C axis rides on B: at B = 0 an index of C is a rotation of
//! the B line about z (EC0B), and on this part it is `0.98 EC0B` to 1.7 % of its RMS. On paper
//! 000 the smallest share left by the baseline is `backlash_c`'s 49 %.

use nalgebra::DVector;

use crate::effects::data::{Candidate, NamedColumns};
use crate::parameter::Effect;
use crate::sensitivity::error_set::VISIBLE_FRACTION;

/// The candidates of a part model that are location errors of the machine, each with why
/// (computed on the built-in design's baseline and candidates; `typical`: the typical size of
/// each baseline parameter, in its unit, for the words).
pub fn location_equivalents(
    baseline: &NamedColumns,
    typical: &[f64],
    candidates: &[Candidate],
) -> Vec<(Effect, String)> {
    let a = &baseline.matrix;
    if a.ncols() == 0 {
        return Vec::new();
    }
    let svd = a.clone().svd(true, true);
    let mut out = Vec::new();
    for c in candidates {
        let s = &c.signature.matrix;
        if s.iter().all(|v| *v == 0.0) {
            continue;
        }
        let mut worst = 0.0_f64;
        let mut coef: Option<DVector<f64>> = None;
        for j in 0..s.ncols() {
            let col = s.column(j).into_owned();
            let Ok(x) = svd.solve(&col, 1e-14) else {
                worst = f64::INFINITY;
                break;
            };
            let left = (&col - a * &x).norm() / col.norm().max(f64::MIN_POSITIVE);
            if left > worst || coef.is_none() {
                coef = Some(x);
            }
            worst = worst.max(left);
        }
        if worst < VISIBLE_FRACTION {
            let like = coef.map_or(String::new(), |x| like_text(&baseline.names(), typical, &x));
            out.push((
                c.effect,
                format!(
                    "on this machine it is a location error of the baseline: one unit of it is \
                     {like} on the part's 100 built-in points, to {:.1} % of its RMS (a \
                     candidate is offered from {:.1} %); the identification reports it there",
                    100.0 * worst,
                    100.0 * VISIBLE_FRACTION
                ),
            ));
        }
    }
    out
}

/// `0.98 EC0B - 0.25 EZ0B`: the terms carrying 99 % of the fit's energy in typical sizes.
fn like_text(names: &[String], typical: &[f64], x: &DVector<f64>) -> String {
    let scaled: Vec<f64> = x.iter().zip(typical).map(|(v, t)| v / t).collect();
    let mut text = String::new();
    for (k, j) in crate::numerics::terms::dominant(&scaled, 0.99)
        .into_iter()
        .enumerate()
    {
        let v = x[j];
        let sign = match (k, v < 0.0) {
            (0, true) => "-",
            (0, false) => "",
            (_, true) => " - ",
            (_, false) => " + ",
        };
        text.push_str(&format!("{sign}{:.3e} {}", v.abs(), names[j]));
    }
    text
}
