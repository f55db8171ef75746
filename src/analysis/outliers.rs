//! The single-point outliers of a diagnosis, named by the file's point ids.

use crate::identify::Identification;
use crate::measurement::outliers::outlier_sentence;

use super::diagnosis::Modelled;
use super::report::Outliers;

/// The outliers of a diagnosis, named by the file's point ids.
pub(super) fn outliers_of(m: &Modelled, ids: &[String], kept: bool) -> Outliers {
    let test = m.outliers.clone().map(|mut t| {
        for o in &mut t.points {
            o.id = ids[o.index].clone();
        }
        // `structured` holds the metadata ids (1-based rows): the file's ids instead.
        t.structured = t
            .structured
            .iter()
            .filter_map(|s| s.parse::<usize>().ok())
            .filter_map(|k| ids.get(k.wrapping_sub(1)).cloned())
            .collect();
        t
    });
    let summary = test
        .as_ref()
        .map_or(String::new(), |t| outlier_sentence(t, kept));
    Outliers {
        tested: test.is_some(),
        excluded: !kept && test.as_ref().is_some_and(|t| !t.points.is_empty()),
        verdict_all_points: m
            .verdict_all_points
            .or(m.diagnosis.report().map(|r| r.verdict.id())),
        test,
        summary,
    }
}

/// The reason an outlier left out of `id` is listed under `points_excluded`.
pub(super) fn name_outliers(id: &mut Identification, outliers: &Outliers) {
    if !outliers.excluded {
        return;
    }
    let Some(t) = &outliers.test else { return };
    for x in &mut id.points_excluded {
        if let Some(o) = t.points.iter().find(|o| o.id == x.id) {
            x.reason = format!(
                "outlier: {:+.1} µm from the fit without it, |t| = {:.1} > {:.2} (Bonferroni α = {} over the points; a chip, dirt or a probing error)",
                o.size * 1e3,
                o.statistic.abs(),
                t.threshold,
                t.alpha
            );
        }
    }
}
