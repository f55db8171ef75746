//! `testpiece plan`: the measurement plan (issue 19, step 1): points, predicted std, groups,
//! detection limits; DMIS and CSV programs for the CMM.

use testpiece::machine::chain::PAPER000_L0;
use testpiece::plan::{nominal_csv, plan, split_total, Plan, PlanOptions};
use testpiece::settings::MachineChoice;

use crate::common::{cmm_noise, machine, mm, mpe, print_json, whole, ModeBranch, Mpe};

/// the measurement plan: points, predicted std, groups, detection limits; DMIS, CSV
///
/// The measurement plan of the S-shape, before any part exists: the points to measure and what an
/// identification on them will be able to tell.
///   points            N per curve at equal arc length from 5 % to 95 % (the built-in layout with
///                     25 replaced by N), ids 1.. in the order A_Z11, A_Z25, B_Z11, B_Z25
///   parameters        the predicted std of every location error (same names and units as
///                     `identify`: rad, EX0B in mm) and its status (identified, weak,
///                     not_separable): exactly what `identify FILE --sigma σ --effects none` reports
///                     on a part measured at these points
///   groups            the combinations the part cannot separate (and the weak ones)
///   detection_limits  per effect of effects.md and parameter, the smallest size whose part the
///                     location errors cannot absorb reaches 2.5 σ RMS over the points (the
///                     diagnosis's rule); null when the location errors absorb it entirely
///
/// Without --json: one line per parameter (name, predicted std, unit, status), the groups, then
/// one line per effect parameter with its detection limit.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// N points in all, spread over the 4 curves (remainder to the first ones)
    #[arg(long, value_name = "N", value_parser = whole)]
    points: Option<usize>,
    /// N points per curve (default 25: the 100 built-in points)
    #[arg(long, value_name = "N", value_parser = whole)]
    per_curve: Option<usize>,
    /// the CMM's standard uncertainty of one deviation (mm)
    #[arg(long, value_name = "MM", value_parser = mm, allow_negative_numbers = true)]
    sigma: Option<f64>,
    /// or its MPE_E = A + L/K µm: σ = median of max(MPE_E(L)/√3, R0/1.693) over the points
    /// (default: paper 000's CMM, 3 + L/75 µm, R0 = 3 µm)
    #[arg(long, value_name = "A,K[,R0]", value_parser = mpe, verbatim_doc_comment)]
    mpe: Option<Mpe>,
    /// the chain: paper000 (B head / C table), paper001 (A-B head), paper002 (B-C tilting table)
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine)]
    machine: MachineChoice,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    #[command(flatten)]
    model: ModeBranch,
    /// include the tool-radius term dR (mm) in the predicted identification
    #[arg(long)]
    tool_radius: bool,
    /// {points, parameters: {NAME: {std, status, unit}}, groups, rank, condition,
    /// detection_limits: {effect: {parameter: size}}, detection_detail, noise, notes}
    #[arg(long, verbatim_doc_comment)]
    json: bool,
    /// writes the plan as a DMIS program (ISO 22093) a CMM runs: the probe (tip 4 mm,
    /// SNSDEF/SNSLCT), the alignment on the fixture plate's top and edge faces (DATDEF/DATSET,
    /// TRANS to the part origin), per point a point feature with its nominal position and
    /// outward normal and its measurement (PTMEAS), GOTOs over the part wherever the straight
    /// move between touches would come within 2 mm of it, OUTPUT of the measured points; ASCII,
    /// lines of at most 80 characters ($ continues); coordinates in the part frame (mm)
    #[arg(long, value_name = "FILE", verbatim_doc_comment)]
    dmis: Option<String>,
    /// writes the nominal table id,curve,x,y,z,nx,ny,nz (mm)
    #[arg(long, value_name = "FILE")]
    csv: Option<String>,
}

pub fn run(a: Args) -> Result<(), String> {
    let opts = a.options()?;
    let prepared = opts.prepare().map_err(|e| e.to_string())?;
    let p = plan(&prepared, &opts).map_err(|e| e.to_string())?;
    if let Some(path) = &a.dmis {
        let d = p.dmis().map_err(|e| e.to_string())?;
        std::fs::write(path, &d.text).map_err(|e| format!("{path}: {e}"))?;
        let r = &d.replay;
        eprintln!(
            "{path}: DMIS program, probe tip {} mm; moves between touches keep {:.3} mm from \
             the part (replayed, {:.3} mm sampled less the {:.3} mm sampling bound; {} of {} \
             moves cleared by {} GOTOs)",
            r.tip_diameter,
            r.min_distance_certain,
            r.min_distance,
            r.sampling_bound,
            r.cleared_moves,
            r.cleared_moves + r.straight_moves,
            r.gotos
        );
    }
    if let Some(path) = &a.csv {
        std::fs::write(path, nominal_csv(&p.points)).map_err(|e| format!("{path}: {e}"))?;
    }
    if a.json {
        return print_json(&p);
    }
    print_text(&p);
    Ok(())
}

impl Args {
    /// The plan's settings; --points and --per-curve, --sigma and --mpe exclude each other.
    fn options(&self) -> Result<PlanOptions, String> {
        let per_curve = match (self.points, self.per_curve) {
            (Some(_), Some(_)) => {
                return Err(
                    "--points and --per-curve both set the number of points: give one".into(),
                )
            }
            (Some(n), None) => split_total(n).map_err(|e| e.to_string())?,
            (None, Some(n)) => [n; 4],
            (None, None) => [25; 4],
        };
        Ok(PlanOptions {
            per_curve,
            sigma: self.sigma,
            mpe: cmm_noise(self.sigma, self.mpe.as_ref())?,
            machine: self.machine,
            l0: self.l0,
            mode: self.model.mode,
            branch: self.model.branch,
            tool_radius: self.tool_radius,
        })
    }
}

fn print_text(p: &Plan) {
    println!("{} points; {}", p.points.len(), p.noise.summary);
    println!("parameter  predicted std  unit  status");
    for (name, q) in &p.parameters.0 {
        let std = q.std.map_or("-".to_string(), |s| format!("{s:.3e}"));
        let status = serde_json::to_value(q.status).unwrap_or_default();
        println!(
            "{name:<8} {std:>14} {:>5}  {}",
            q.id.unit(),
            status.as_str().unwrap_or("")
        );
    }
    for g in &p.groups {
        println!("group: {}", g.explanation);
    }
    println!("effect.parameter  detection limit  unit");
    for d in &p.detection_detail {
        for q in &d.parameters {
            let size = q
                .size
                .map_or("never visible".to_string(), |s| format!("{s:.3e}"));
            let name = format!("{}.{}", d.effect.id(), q.name);
            println!("{name:<20} {size:>14} {}", q.unit);
        }
    }
    for n in &p.notes {
        println!("note: {n}");
    }
}
