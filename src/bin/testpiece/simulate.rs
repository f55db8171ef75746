//! `testpiece simulate`: a synthetic measured part in the canonical CSV format.

use testpiece::cmm::write::{canonical_csv, scan_csv, Precision};
use testpiece::effects::prepared::Prepared;
use testpiece::machine::chain::PAPER000_L0;
use testpiece::machine::location_errors::minimal_set;
use testpiece::machine::{Branch, ErrorParam};
use testpiece::parameter::{Effect, ParamId};
use testpiece::part::{builtin_points, SShape, ScanLayout};
use testpiece::sensitivity::error_set::full_list;
use testpiece::sensitivity::{Mode, SensitivityOptions};
use testpiece::settings::MachineChoice;
use testpiece::simulate::{
    builtin_design, parse_errors, simulate_at, simulate_deviation, simulate_exact, simulate_on,
};

use crate::common::{branch, machine, mm, mode, positive_l0, seed};

/// a synthetic measured part for given errors: id,curve,x,y,z,nx,ny,nz,deviation
///
/// Prints a synthetic measured part at the 100 built-in points in the canonical format
/// `id,curve,x,y,z,nx,ny,nz,deviation` (mm; deviation = (machined - nominal)·N, + = material left).
/// The deviation is the exact machined defect of paper 000 eq. 12 (--linear: its linearisation,
/// eq. 14; they differ by < 0.3 µm at 3e-4 rad) for the given errors
/// (EC0Y EA0Z EB0Z EA0C EB0C EA0B EC0B in rad, EX0B in mm; others 0), plus dR (mm, a tool larger by
/// dR overcuts by dR) if given in --errors, plus Gaussian noise of σ = --noise mm (default 0) drawn
/// from a ChaCha8 stream seeded by --seed (default 7): the same seed gives the same part.
///
/// --machine paper000|paper001|paper002 (default paper000) and --l0: the chain. With another
/// machine than paper000, or an error outside the eight above, the part is the exact eq. 12 defect
/// on that chain for any of its ISO 230-1 location errors (`testpiece machine --machine M` lists
/// them: e.g. EY0C=0.02,EX0C=-0.015 for a C axis off the part origin on the tilting table), and
/// --effect uses that machine's signatures.
///
/// --scan HEIGHTSxRULINGS (e.g. 40x250: 20,000 points) writes a scanning CMM's file instead:
/// each surface scanned on HEIGHTS lines of constant height, evenly from 3 to 27 mm, each line
/// RULINGS points at equal arc length (5 %-95 % of the curve), surface A's lines then B's, in
/// scan order, as `x,y,z,nx,ny,nz,deviation` with no id and no curve label; the deviation is
/// always the exact eq. 12 defect on the chain (not --linear).
///
/// --effect adds unmodelled effects of shared/spec/effects.md, each as ID=VALUE for a one-parameter
/// effect (backlash_c=1e-4: rad for B and C, mm for X, Y, Z) or ID.PARAMETER=VALUE (tool_taper.g=2e-4,
/// setup_error.thetaz=1e-4), in the parameter's unit: the deviation gains VALUE times the effect's
/// signature at the points (paper 000's machine, physical mode, the --branch given), the signature
/// `testpiece diagnose` fits. Ids: tool_radius, tool_taper, overcut, backlash_x|y|z|b|c,
/// thermal_drift, setup_error, scale_x|y|z, c_index, pivot_length.
#[derive(clap::Args)]
#[command(verbatim_doc_comment)]
pub struct Args {
    /// the machine's errors, NAME=VALUE separated by commas (rad; mm for offsets and dR)
    #[arg(long, value_name = "EX0B=0.03,EA0B=3e-4", value_parser = errors)]
    errors: Option<Errors>,
    /// unmodelled effects of effects.md: ID=VALUE or ID.PARAMETER=VALUE, separated by commas
    #[arg(long, value_name = "backlash_c=1e-4,tool_taper.g=2e-4", value_parser = effects)]
    effect: Option<EffectValues>,
    /// σ of the Gaussian noise (mm)
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = mm, allow_negative_numbers = true)]
    noise: f64,
    /// the seed of the noise's ChaCha8 stream
    #[arg(long, value_name = "S", default_value_t = 7, value_parser = seed)]
    seed: u64,
    /// the defect's displaced point, normal and reference (as `testpiece sensitivity`)
    #[arg(long, value_name = "physical|paper", default_value = "physical", value_parser = mode)]
    mode: Mode,
    /// the B-axis branch of the inverse kinematics
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    branch: Branch,
    /// the linearised defect (eq. 14) instead of the exact one; paper000's eight errors only
    #[arg(long)]
    linear: bool,
    /// the chain: paper000 (B head / C table), paper001 (A-B head), paper002 (B-C tilting table)
    #[arg(long, value_name = "paper000|paper001|paper002", default_value = "paper000", value_parser = machine)]
    machine: MachineChoice,
    /// the pivot-to-tip length (mm)
    #[arg(long, value_name = "MM", default_value_t = PAPER000_L0, value_parser = mm, allow_negative_numbers = true)]
    l0: f64,
    /// a scan: lines of constant height on each surface x points per line, e.g. 40x250
    #[arg(long, value_name = "HEIGHTSxRULINGS", value_parser = scan_layout)]
    scan: Option<ScanLayout>,
}

/// `--scan 40x250`: heights and rulings, each at least 1.
fn scan_layout(s: &str) -> Result<ScanLayout, String> {
    let bad = || format!("`{s}`: expected HEIGHTSxRULINGS, two whole numbers >= 1, e.g. 40x250");
    let (h, r) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let n = |t: &str| t.trim().parse::<usize>().ok().filter(|n| *n >= 1);
    match (n(h), n(r)) {
        (Some(heights), Some(rulings)) => Ok(ScanLayout { heights, rulings }),
        _ => Err(bad()),
    }
}

/// `--errors`: each error's name and value.
#[derive(Debug, Clone)]
pub struct Errors(Vec<(String, f64)>);

fn errors(s: &str) -> Result<Errors, String> {
    parse_errors(s).map(Errors).map_err(|e| e.to_string())
}

/// `--effect`: each effect parameter (effect, parameter index) and its value.
#[derive(Debug, Clone)]
pub struct EffectValues(Vec<(Effect, usize, f64)>);

fn effects(s: &str) -> Result<EffectValues, String> {
    parse_errors(s)
        .map_err(|e| e.to_string())?
        .into_iter()
        .map(|(key, value)| {
            let (effect, j) = Effect::parse_parameter(&key).map_err(|e| e.to_string())?;
            Ok((effect, j, value))
        })
        .collect::<Result<_, String>>()
        .map(EffectValues)
}

pub fn run(a: Args) -> Result<(), String> {
    let Some(Errors(errs)) = &a.errors else {
        return Err("--errors is required, e.g. --errors EX0B=0.03,EA0B=3e-4".into());
    };
    let l0 = positive_l0(a.l0)?;
    let errs = ids_on(errs, a.machine, l0)?;
    let part = SShape::iso();
    let (pts, dev) = match a.scan {
        Some(layout) => {
            if a.linear {
                return Err("--linear: not with --scan (a scan's part is the exact defect)".into());
            }
            let pts = layout.scan_points(&part);
            let dev = simulate_at(&part, &pts, &a.chain_options(l0), &errs, a.noise, a.seed)
                .map_err(|e| e.to_string())?;
            (pts, dev)
        }
        None => (builtin_points(&part), machine_part(&a, &errs, l0)?),
    };
    let dev: Vec<f64> = match &a.effect {
        Some(EffectValues(values)) => {
            let prepared =
                Prepared::new(part.clone(), a.chain_options(l0)).map_err(|e| e.to_string())?;
            let model = prepared
                .axis_values(&pts)
                .map_err(|e| e.to_string())
                .and_then(|q| prepared.part_model(&pts, &q).map_err(|e| e.to_string()))?;
            let e = model
                .effect_deviation(values)
                .map_err(|e| format!("--effect: {e}"))?;
            dev.iter().zip(e).map(|(d, e)| d + e).collect()
        }
        None => dev,
    };
    if pts.len() != dev.len() {
        return Err(format!(
            "internal: {} built-in points but {} design rows",
            pts.len(),
            dev.len()
        ));
    }
    let rows = pts.iter().zip(dev.iter().copied());
    let out = match a.scan {
        Some(_) => scan_csv(rows, Precision::Shortest, None),
        None => canonical_csv(rows, Precision::Shortest, None),
    };
    print!("{out}");
    Ok(())
}

impl Args {
    /// The chain's sensitivity options with --mode and --branch.
    fn chain_options(&self, l0: f64) -> SensitivityOptions {
        SensitivityOptions::default()
            .with_chain(self.machine.chain(l0))
            .with_branch(self.branch)
            .with_mode(self.mode)
    }
}

/// The errors' names read into ids: each must be one of the chain's ISO 230-1 location errors
/// or dR.
fn ids_on(
    errs: &[(String, f64)],
    machine: MachineChoice,
    l0: f64,
) -> Result<Vec<(ParamId, f64)>, String> {
    let full: Vec<ParamId> = full_list(&machine.chain(l0))
        .iter()
        .map(|(e, _)| ParamId::Machine(ErrorParam::Location(*e)))
        .collect();
    errs.iter()
        .map(|(name, v)| match ParamId::parse(name) {
            Ok(id) if id == ParamId::ToolRadius || full.contains(&id) => Ok((id, *v)),
            _ => Err(format!(
                "--errors: unknown error `{name}` on {}; known: {}, dR",
                machine.describe(),
                full.iter()
                    .map(ParamId::name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        })
        .collect()
}

/// The machine's part: paper 000 with its eight errors keeps the design-based path (its parts
/// bit for bit, exact or --linear); any other machine or error, the exact defect on the chain.
fn machine_part(a: &Args, errs: &[(ParamId, f64)], l0: f64) -> Result<Vec<f64>, String> {
    let eight: Vec<ParamId> = minimal_set(&MachineChoice::Paper000.chain(l0))
        .free()
        .into_iter()
        .map(|e| ParamId::Machine(ErrorParam::Location(e)))
        .collect();
    let on_chain = a.machine != MachineChoice::Paper000
        || errs
            .iter()
            .any(|(id, _)| *id != ParamId::ToolRadius && !eight.contains(id));
    let (mode, branch) = (a.mode, a.branch);
    if on_chain {
        if a.linear {
            return Err("--linear: only on paper000 with its eight errors".to_string());
        }
        simulate_on(&a.chain_options(l0), errs, a.noise, a.seed)
    } else if a.linear {
        let tool_radius = errs.iter().any(|(id, _)| *id == ParamId::ToolRadius);
        let design = builtin_design(mode, branch, tool_radius).map_err(|e| e.to_string())?;
        simulate_deviation(&design, errs, a.noise, a.seed)
    } else {
        simulate_exact(mode, branch, errs, a.noise, a.seed)
    }
    .map_err(|e| e.to_string())
}
