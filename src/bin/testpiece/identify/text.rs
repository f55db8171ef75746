//! `testpiece identify FILE` without --json: the plain-text report, section by section.

use testpiece::analysis::Analysis;
use testpiece::compensation::Compensation;
use testpiece::final_fit::correct::Basis;
use testpiece::identify::monte_carlo::MonteCarloReport;
use testpiece::identify::{Identification, Status};

/// The whole report, in order: the fit, the parameters, the groups, the residual, the final
/// answer, the excluded points and outliers, the noise, the compensation and the Monte Carlo.
pub fn print(
    mode: &str,
    branch: &str,
    id: &Identification,
    analysis: &Analysis,
    compensation: Option<&Compensation>,
    mc: Option<&MonteCarloReport>,
) {
    println!(
        "mode {mode}, branch {branch}: {} points used, {} excluded",
        id.points_used,
        id.points_excluded.len()
    );
    println!(
        "rank {} (solved {}), condition {:.4}",
        id.rank, id.rank_used, id.condition
    );
    parameters(id);
    groups(id);
    residual(id);
    if let Some(r) = &analysis.refinement {
        println!("exact model: {}", r.reason);
    }
    final_answer(analysis);
    for x in &id.points_excluded {
        println!("excluded {}: {}", x.id, x.reason);
    }
    outliers(analysis);
    println!("{}", analysis.noise.summary);
    if let Some(c) = compensation {
        super::compensation::print(c);
    }
    if let Some(mc) = mc {
        monte_carlo(mc);
    }
}

/// `name value std unit status`, one line per parameter.
fn parameters(id: &Identification) {
    println!(
        "{:<6} {:>14} {:>12} {:<4} status",
        "name", "value", "std", "unit"
    );
    for p in &id.parameters.0 {
        let std = p.std.map_or("-".to_string(), |s| format!("{s:.3e}"));
        let status = match p.status {
            Status::Identified => "identified",
            Status::Weak => "weak",
            Status::NotSeparable => "not separable",
        };
        println!(
            "{:<6} {:>14.6e} {:>12} {:<4} {status}",
            p.name(),
            p.value,
            std,
            p.unit()
        );
    }
}

/// Each group and the combinations of it that are estimable.
fn groups(id: &Identification) {
    for g in &id.groups {
        println!("group: {}", g.explanation);
        for e in &g.estimable {
            println!(
                "  {} = {:.6e} ± {}",
                e.combination.text,
                e.value,
                e.std.map_or("-".into(), |s| format!("{s:.3e}"))
            );
        }
    }
}

/// The residual, in all and per curve.
fn residual(id: &Identification) {
    println!(
        "residual: rms {:.6} mm, max |r| {:.6} mm, MAD {:.6} mm, RMSE {:.6} mm",
        id.residual.rms, id.residual.max_abs, id.residual.mad, id.residual.rmse
    );
    for c in &id.per_curve {
        println!(
            "  {}: rms {:.6} mm, max |r| {:.6} mm",
            c.curve, c.stats.rms, c.stats.max_abs
        );
    }
}

/// What the final answer was fitted with and, unless it is the baseline, its shift from it.
fn final_answer(analysis: &Analysis) {
    println!("final answer: {}", analysis.correction.summary);
    let shifts: Vec<String> = analysis
        .correction
        .shift
        .0
        .iter()
        .filter_map(|s| s.std.map(|v| format!("{} {v:+.1}", s.parameter)))
        .collect();
    if analysis.correction.basis != Basis::Baseline && !shifts.is_empty() {
        println!("shift from the baseline (std): {}", shifts.join(", "));
    }
}

/// The outlier test's summary and, when points were left out, the verdict with every point.
fn outliers(analysis: &Analysis) {
    if analysis.outliers.summary.is_empty() {
        return;
    }
    println!("Outliers: {}", analysis.outliers.summary);
    if let Some(v) = analysis
        .outliers
        .verdict_all_points
        .filter(|_| analysis.outliers.excluded)
    {
        println!("With every point, outliers included, the verdict would be `{v}`.");
    }
}

/// The Monte Carlo's std beside the predicted ones.
fn monte_carlo(mc: &MonteCarloReport) {
    println!(
        "Monte Carlo ({} runs, seed {}, σ {:.2e}..{:.2e} mm):",
        mc.runs, mc.seed, mc.sigma_min, mc.sigma_max
    );
    for p in &mc.parameters {
        println!(
            "  {:<6} std MC {:.3e}, predicted {:.3e}",
            p.name, p.std_mc, p.std_predicted
        );
    }
}
