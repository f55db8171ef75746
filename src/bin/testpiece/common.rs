//! What several commands share: the parsers of their option values (the machine, mode, branch,
//! the CMM's noise, numbers), the checks that join two options, reading the measured files and
//! printing JSON. Command modules import this one, never each other.
//!
//! A value parser's message says what was expected; `main` prefixes the option and the value
//! (``--machine `paper9`: expected paper000, paper001 or paper002``).

use std::io::IsTerminal;

use testpiece::analysis::{
    analyse_parts_once_with, silent, Analysis, AnalysisOptions, Fitted, Progress,
};
use testpiece::identify::monte_carlo::CmmMpe;
use testpiece::machine::Branch;
use testpiece::numerics::parallel::Threads;
use testpiece::part::ConeFrustum;
use testpiece::sensitivity::Mode;
use testpiece::settings::MachineChoice;

/// `--machine paper000|paper001|paper002`: the chain.
pub fn machine(s: &str) -> Result<MachineChoice, String> {
    match s {
        "paper000" => Ok(MachineChoice::Paper000),
        "paper001" => Ok(MachineChoice::Paper001),
        "paper002" => Ok(MachineChoice::Paper002),
        _ => Err("expected paper000, paper001 or paper002".into()),
    }
}

/// `--mode physical|paper`.
pub fn mode(s: &str) -> Result<Mode, String> {
    Mode::parse(s).map_err(|_| "expected physical or paper".into())
}

/// `--branch signed|positive`.
pub fn branch(s: &str) -> Result<Branch, String> {
    Branch::parse(s).ok_or_else(|| "expected signed or positive".into())
}

/// The `--branch` word of a branch (the library's string-keyed calls and the JSON take it).
pub fn branch_name(b: Branch) -> &'static str {
    match b {
        Branch::Signed => "signed",
        Branch::Positive => "positive",
    }
}

/// A number of mm (`--sigma`, `--l0`, `--radius`, ...).
pub fn mm(s: &str) -> Result<f64, String> {
    s.parse().map_err(|_| "expected a number of mm".into())
}

/// A plain number (`--rho`, `--phi`, `--tolerance`, `--feed`, ...).
pub fn number(s: &str) -> Result<f64, String> {
    s.parse().map_err(|_| "expected a number".into())
}

/// A count (`--cases`, `--layers`, `--points`, `--monte-carlo`, ...).
pub fn whole(s: &str) -> Result<usize, String> {
    s.parse().map_err(|_| "expected a whole number".into())
}

/// `--seed S`: the seed of a ChaCha8 stream.
pub fn seed(s: &str) -> Result<u64, String> {
    s.parse()
        .map_err(|_| "expected a non-negative integer".into())
}

/// `--mpe A,K[,R0]` as written, and the CMM's MPE it gives.
#[derive(Debug, Clone)]
pub struct Mpe {
    pub text: String,
    pub mpe: CmmMpe,
}

/// `--mpe A,K[,R0]` (µm, mm, µm): MPE_E = A + L/K µm and the repeatability range R0.
pub fn mpe(s: &str) -> Result<Mpe, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| "expected A,K or A,K,R0 (numbers: µm, mm, µm)".to_string())?;
    let (a, k, r0) = match v.as_slice() {
        [a, k] => (*a, *k, 0.0),
        [a, k, r0] => (*a, *k, *r0),
        _ => return Err("expected A,K or A,K,R0 (MPE_E = A + L/K µm, R0 in µm)".into()),
    };
    let mpe = CmmMpe::try_new(a, k, r0).map_err(|e| e.to_string())?;
    Ok(Mpe {
        text: s.to_string(),
        mpe,
    })
}

/// The CMM's noise from `--sigma` and `--mpe`: at most one of them.
pub fn cmm_noise(sigma: Option<f64>, mpe: Option<&Mpe>) -> Result<Option<CmmMpe>, String> {
    match (sigma, mpe) {
        (Some(s), Some(m)) => Err(format!(
            "--sigma {s} and --mpe {} both give the CMM noise: give one of them \
             (--sigma the σ in mm, --mpe the MPE A + L/K in µm)",
            m.text
        )),
        (_, m) => Ok(m.map(|m| m.mpe)),
    }
}

/// `--l0`: the pivot-to-tip length must be a positive length.
pub fn positive_l0(l0: f64) -> Result<f64, String> {
    if l0.is_finite() && l0 > 0.0 {
        Ok(l0)
    } else {
        Err(format!("--l0 {l0}: expected a positive length in mm"))
    }
}

/// The file name of a path (for messages and part names).
pub fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map_or(path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// The bytes of a file; the error names it.
pub fn read(path: &str) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("{path}: {e}"))
}

/// Reads FILE and its repeats (the same points measured again) and analyses their mean
/// ([`analyse_parts_once_with`]) on the settings prepared once for the command, while the files
/// are read; errors name the file.
/// When stderr is a terminal, the analysis's stages are written there on one line, overwritten
/// as each begins and cleared at the end ([`stage_line`]); piped or redirected, nothing is
/// written (the outputs stay byte for byte what they were).
pub fn analyse_files(
    file: &str,
    repeats: &[String],
    settings: &AnalysisOptions,
) -> Result<(Analysis, Fitted), String> {
    let mut contents = Vec::new();
    for f in std::iter::once(file).chain(repeats.iter().map(String::as_str)) {
        contents.push((read(f)?, file_name(f)));
    }
    let files: Vec<(&[u8], &str)> = contents
        .iter()
        .map(|(b, n)| (b.as_slice(), n.as_str()))
        .collect();
    // the settings prepared while the files are read (`analyse_parts_once_with`)
    let result = if std::io::stderr().is_terminal() {
        let name = file_name(file);
        let mut show = |p: Progress| eprint!("\r\x1b[K{}", stage_line(&name, &p));
        let r = analyse_parts_once_with(&files, settings, &mut show);
        eprint!("\r\x1b[K");
        r
    } else {
        analyse_parts_once_with(&files, settings, &mut silent)
    };
    result.map_err(|e| format!("{file}: {e}"))
}

/// Leaves `value` to the end of the process instead of freeing it: the system takes the
/// process's memory back whole, where freeing a dense scan's analysis piece by piece is tens of
/// milliseconds of one thread (200,000 points: 36 ms, issue 31). For what a command holds until
/// it returns, once its output is written.
pub fn leave_to_exit<T>(value: T) {
    std::mem::forget(value);
}

/// `--threads N`, or the machine's cores when not given.
pub fn threads(given: Option<u16>) -> Threads {
    Threads::new(given.map_or_else(
        || std::thread::available_parallelism().map_or(1, usize::from),
        usize::from,
    ))
}

/// One stage on the terminal's progress line: `part.csv: stage 4 of 6: diagnosing … [###...]`.
pub fn stage_line(name: &str, p: &Progress) -> String {
    const WIDTH: usize = 12;
    let done = (p.fraction() * WIDTH as f64).round() as usize;
    format!(
        "{name}: {} [{}{}]",
        p.text(),
        "#".repeat(done),
        ".".repeat(WIDTH - done)
    )
}

/// Prints a value as pretty JSON.
pub fn print_json<T: serde::Serialize + ?Sized>(v: &T) -> Result<(), String> {
    println!(
        "{}",
        serde_json::to_string_pretty(v).map_err(|e| e.to_string())?
    );
    Ok(())
}

/// A value as JSON (for the fields a command adds to a report).
pub fn to_json<T: serde::Serialize + ?Sized>(v: &T) -> Result<serde_json::Value, String> {
    serde_json::to_value(v).map_err(|e| e.to_string())
}

/// `--part`: the built-in S-shape or a cone frustum of paper 002 Table 3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    SShape,
    /// M3_15: half apex angle 15°.
    Cone15,
    /// M3_45: half apex angle 45°.
    Cone45,
}

/// `--part s-shape|M3_15|M3_45` (any case; `s_shape` and `sshape` for the S-shape).
pub fn part(s: &str) -> Result<Part, String> {
    match s.to_ascii_uppercase().as_str() {
        "S-SHAPE" | "S_SHAPE" | "SSHAPE" => Ok(Part::SShape),
        "M3_15" => Ok(Part::Cone15),
        "M3_45" => Ok(Part::Cone45),
        _ => Err("expected s-shape, M3_15 or M3_45".into()),
    }
}

impl Part {
    /// The cone frustum (placed with the paper's offsets if `offsets`), `None` for the S-shape.
    pub fn cone(self, offsets: bool) -> Option<ConeFrustum> {
        match self {
            Part::SShape => None,
            Part::Cone15 => Some(ConeFrustum::m3_15(offsets)),
            Part::Cone45 => Some(ConeFrustum::m3_45(offsets)),
        }
    }
}

/// The defect model's `--mode` and `--branch`, as the commands that build a design of the
/// location errors take them (`compare`, `identify`, `plan`).
#[derive(clap::Args)]
pub struct ModeBranch {
    /// the defect's displaced point, normal and reference (as `testpiece sensitivity`)
    #[arg(long, value_name = "physical|paper", default_value = "physical", value_parser = mode)]
    pub mode: Mode,
    /// the B-axis branch of the inverse kinematics
    #[arg(long, value_name = "signed|positive", default_value = "signed", value_parser = branch)]
    pub branch: Branch,
}
