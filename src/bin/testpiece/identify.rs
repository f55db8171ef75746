//! `testpiece identify FILE`: identify the machine's errors from a measured part.

use crate::args::Args;
use nalgebra::DMatrix;
use testpiece::identify::monte_carlo::{monte_carlo, CmmMpe, MonteCarloOptions, Noise};
use testpiece::identify::refine::{refine, ExactModel, RefineOptions};
use testpiece::identify::{
    export, identify, Design, ExcludedPoint, IdentifyOptions, Observations, Status,
};
use testpiece::part::{builtin_points, SShape};
use testpiece::simulate::ExactBuiltinModel;

const HELP: &str = "\
testpiece identify FILE [--mode physical|paper] [--branch signed|positive] [--tool-radius]
                        [--json | --export csv|json] [--sigma MM] [--no-refine]
                        [--monte-carlo RUNS] [--seed S]

Identifies the 8 ISO 230-1 location errors (EC0Y EA0Z EB0Z EA0C EB0C EX0B EA0B EC0B; rad, EX0B
in mm) and, with --tool-radius, the tool-radius error dR (mm, + = a larger tool) from the
measured deviations of FILE (canonical CSV `id,curve,x,y,z,nx,ny,nz,deviation`, mm).
Weighted least squares on the linearised defect (paper 000 eq. 14), SVD of the unit-scaled
design: rank, condition number, and the groups of parameters the part cannot separate
(condition index >= 30) or sees only weakly (std above 1/4 of a typical error, 1e-4 rad or
0.01 mm). Points are matched to the built-in points by their coordinates (within 0.01 mm).

--json            {parameters, groups, rank, condition, residual, points_used, points_excluded, ...}
--export csv|json the compensation table: name, iso_230_1, value, unit, std, status
--sigma MM        a priori σ of the deviations instead of the residual's
--no-refine       skips the exact-model check: by default the exact eq. 12 is evaluated at the
                  linear solution and Levenberg-Marquardt refines it when the linearisation error
                  exceeds 0.1 σ (reported under \"refinement\")
--monte-carlo N   adds a Monte Carlo check (N runs, --seed, default 7) with the noise of the
                  paper's CMM: MPE_E = ±(3 + L/75) µm, R0 = 3 µm, σ = max(MPE/√3, R0/1.693)
";

/// A measured part as read from a file: one entry per data row.
pub struct Measured {
    pub ids: Vec<String>,
    pub curves: Vec<String>,
    pub points: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub deviation: Vec<f64>,
}

/// Reads a canonical CSV `id,curve,x,y,z,nx,ny,nz,deviation`. This minimal reader is replaced
/// by the CMM reader of the cmm stage (all formats of cmm-csv.md); keep it behind this function.
pub fn read_measured(path: &str) -> Result<Measured, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines.next().ok_or_else(|| format!("{path}: empty file"))?;
    let cols: Vec<String> = header
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    let want = ["id", "curve", "x", "y", "z", "nx", "ny", "nz", "deviation"];
    let idx: Vec<usize> = want
        .iter()
        .map(|w| {
            cols.iter().position(|c| c == w).ok_or_else(|| {
                format!(
                    "{path}: line 1: no column `{w}` in header `{header}`; expected {}",
                    want.join(",")
                )
            })
        })
        .collect::<Result<_, _>>()?;
    let mut m = Measured {
        ids: vec![],
        curves: vec![],
        points: vec![],
        normals: vec![],
        deviation: vec![],
    };
    for (ln, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() < cols.len() {
            return Err(format!(
                "{path}: line {}: {} columns, expected {}",
                ln + 1,
                f.len(),
                cols.len()
            ));
        }
        let num = |k: usize| -> Result<f64, String> {
            let t = f[idx[k]];
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    format!(
                        "{path}: line {}, column `{}`: `{t}` is not a number",
                        ln + 1,
                        want[k]
                    )
                })
        };
        m.ids.push(f[idx[0]].to_string());
        m.curves.push(f[idx[1]].to_string());
        m.points.push([num(2)?, num(3)?, num(4)?]);
        m.normals.push([num(5)?, num(6)?, num(7)?]);
        m.deviation.push(num(8)?);
    }
    if m.deviation.is_empty() {
        return Err(format!("{path}: no data row after the header"));
    }
    Ok(m)
}

/// The exact model at the matched rows of the built-in points.
struct Rows<'a> {
    model: &'a ExactBuiltinModel,
    rows: &'a [usize],
}

impl ExactModel for Rows<'_> {
    fn deviation(&self, x: &[f64]) -> Result<Vec<f64>, String> {
        let f = self.model.deviation(x)?;
        Ok(self.rows.iter().map(|&r| f[r]).collect())
    }
    fn jacobian(&self, x: &[f64]) -> Result<DMatrix<f64>, String> {
        Ok(self.model.jacobian(x)?.select_rows(self.rows.iter()))
    }
}

/// Design rows, observations, point distances from the origin (mm), exclusions, and the
/// built-in row of each used point.
type Matched = (
    Design,
    Observations,
    Vec<f64>,
    Vec<ExcludedPoint>,
    Vec<usize>,
);

/// Matches each measured point to the built-in point within 0.01 mm (and normal within 5°).
fn match_points(m: &Measured, full: &Design) -> Result<Matched, String> {
    let pts = builtin_points(&SShape::iso());
    let mut rows = Vec::new();
    let mut keep = Vec::new();
    let mut excluded = Vec::new();
    for (i, p) in m.points.iter().enumerate() {
        let (k, dist) = pts
            .iter()
            .enumerate()
            .map(|(k, q)| {
                (
                    k,
                    ((p[0] - q.point.x).powi(2)
                        + (p[1] - q.point.y).powi(2)
                        + (p[2] - q.point.z).powi(2))
                    .sqrt(),
                )
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::INFINITY));
        if dist > 0.01 {
            excluded.push(ExcludedPoint {
                id: m.ids[i].clone(),
                reason: format!(
                    "not at a built-in point: nearest is id {} at {dist:.4} mm (> 0.01 mm); projection of arbitrary points comes with the CMM reader",
                    k + 1
                ),
            });
            continue;
        }
        let n = m.normals[i];
        let q = pts[k].normal;
        let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let cos = (n[0] * q.x + n[1] * q.y + n[2] * q.z) / norm;
        if norm.is_nan() || norm <= 0.0 || cos < 5f64.to_radians().cos() {
            excluded.push(ExcludedPoint {
                id: m.ids[i].clone(),
                reason: format!(
                    "its normal differs from the model's by {:.2}° (> 5°)",
                    cos.clamp(-1.0, 1.0).acos().to_degrees()
                ),
            });
            continue;
        }
        rows.push(k);
        keep.push(i);
    }
    if rows.is_empty() {
        return Err(format!(
            "no point of the file matches a built-in point ({} excluded)",
            excluded.len()
        ));
    }
    let a = full.matrix().select_rows(rows.iter());
    let design = Design::try_new(full.parameters().to_vec(), a).map_err(|e| e.to_string())?;
    let obs = Observations::new(
        keep.iter().map(|&i| m.ids[i].clone()).collect(),
        keep.iter().map(|&i| m.curves[i].clone()).collect(),
        keep.iter().map(|&i| m.deviation[i]).collect(),
    );
    let lengths = keep
        .iter()
        .map(|&i| {
            let p = m.points[i];
            (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
        })
        .collect();
    Ok((design, obs, lengths, excluded, rows))
}

pub fn run(rest: &[String]) -> Result<(), String> {
    if crate::wants_help(rest, HELP) {
        return Ok(());
    }
    let args = Args::parse(
        rest,
        &["mode", "branch", "export", "sigma", "monte-carlo", "seed"],
    )?;
    let (mode, branch) = crate::simulate::mode_and_branch(&args)?;
    let tool_radius = args.flag("tool-radius");
    let json = args.flag("json");
    let no_refine = args.flag("no-refine");
    let export_fmt = args.value("export").map(str::to_string);
    let sigma = match args.value("sigma") {
        Some(t) => Some(
            t.parse::<f64>()
                .map_err(|_| format!("--sigma `{t}`: expected a number of mm"))?,
        ),
        None => None,
    };
    let runs = match args.value("monte-carlo") {
        Some(t) => Some(
            t.parse::<usize>()
                .map_err(|_| format!("--monte-carlo `{t}`: expected a number of runs"))?,
        ),
        None => None,
    };
    let seed: u64 = match args.value("seed") {
        Some(t) => t
            .parse()
            .map_err(|_| format!("--seed `{t}`: expected a non-negative integer"))?,
        None => 7,
    };
    args.reject_unknown("identify")?;
    let [file] = args.positional.as_slice() else {
        return Err("`testpiece identify` needs exactly one FILE (see --help)".to_string());
    };
    if let Some(f) = &export_fmt {
        if f != "csv" && f != "json" {
            return Err(format!("--export `{f}`: expected csv or json"));
        }
    }
    let measured = read_measured(file)?;
    let full = crate::simulate::design_for(&mode, &branch, tool_radius)?;
    let (design, obs, lengths, excluded, rows) = match_points(&measured, &full)?;
    let mut opts = IdentifyOptions::default();
    if let Some(s) = sigma {
        opts = opts.with_sigma(s);
    }
    let mut id = identify(&design, &obs, &opts).map_err(|e| e.to_string())?;
    id.points_excluded.extend(excluded);
    // Exact eq. 12 where it matters (identify::refine module docs).
    let refinement = if no_refine {
        None
    } else {
        let exact = ExactBuiltinModel::new(&full, &mode, &branch).map_err(|e| e.to_string())?;
        let model = Rows {
            model: &exact,
            rows: &rows,
        };
        let r = refine(&design, &obs, &id, model, &RefineOptions::default(), &opts)
            .map_err(|e| e.to_string())?;
        if r.performed && r.success {
            for (j, p) in id.parameters.0.iter_mut().enumerate() {
                p.value = r.values[j];
                if p.status != Status::NotSeparable {
                    p.std = r.std[j];
                }
            }
            id.notes.push(format!(
                "values refined with the exact eq. 12: {}",
                r.reason
            ));
        }
        Some(r)
    };
    if let Some(f) = export_fmt {
        if f == "csv" {
            print!("{}", export::compensation_csv(&id));
        } else {
            println!("{}", export::compensation_json(&id));
        }
        return Ok(());
    }
    let mc = match runs {
        Some(r) => {
            let noise = Noise::from_mpe(&CmmMpe::paper000(), &lengths);
            let o = MonteCarloOptions::default().with_runs(r).with_seed(seed);
            Some(
                monte_carlo(&design, &obs, &id.values(), &noise, &o, &opts)
                    .map_err(|e| e.to_string())?,
            )
        }
        None => None,
    };
    if json {
        let mut v = serde_json::to_value(&id).map_err(|e| e.to_string())?;
        v["mode"] = serde_json::json!(mode);
        v["branch"] = serde_json::json!(branch);
        if let Some(r) = &refinement {
            v["refinement"] = serde_json::to_value(r).map_err(|e| e.to_string())?;
        }
        if let Some(mc) = mc {
            v["monte_carlo"] = serde_json::to_value(mc).map_err(|e| e.to_string())?;
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!(
        "mode {mode}, branch {branch}: {} points used, {} excluded",
        id.points_used,
        id.points_excluded.len()
    );
    println!(
        "rank {} (solved {}), condition {:.4}",
        id.rank, id.rank_used, id.condition
    );
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
            p.name, p.value, std, p.unit
        );
    }
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
    if let Some(r) = &refinement {
        println!("exact model: {}", r.reason);
    }
    for x in &id.points_excluded {
        println!("excluded {}: {}", x.id, x.reason);
    }
    if let Some(mc) = mc {
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
    Ok(())
}
