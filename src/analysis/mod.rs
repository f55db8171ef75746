//! One measured part through the whole pipeline, as one call: the page's "analyse" action, the
//! CLI's `identify`, and the tests share it (DESIGN.md: file bytes → cmm → part projection →
//! sensitivity → identify → gap → one report).
//!
//! 1. [`crate::cmm::read_and_match`]: every row read (or reported), every point matched to the
//!    nominal S-shape by projection of its own coordinates, deviation `(measured − nominal)·N`
//!    (mm, + = material left, − = overcut).
//! 2. Each matched point becomes a [`MeasurementPoint`] at its own `(surface, u, v)`, labelled with
//!    the nearer measurement curve (Z = 11 or 25 mm) for grouping; its contact height `h` follows
//!    from `v` (s-shape.md).
//! 3. [`crate::sensitivity::sensitivity_matrix`] at those points: the defect per unit of each
//!    location error of the configured machine (paper 000 eq. 14, mode and branch as set),
//!    optionally with the tool-radius column `−1` (`dR`, mm, + = a larger tool).
//! 4. [`crate::identify::identify`]: weighted least squares, rank, groups, uncertainty; then
//!    [`crate::identify::refine::refine`] with the exact eq. 12 at the same points
//!    ([`crate::simulate::ExactDefectModel`]) where the linearisation error exceeds 0.1 σ.
//!    The machine is a setting ([`MachineChoice`]): paper 000's B head / C table (default),
//!    paper 001's A-B head or paper 002's B-C tilting table; each has its own set of location
//!    errors, derived from what the part sees ([`crate::sensitivity::error_set`]; the design's
//!    columns).
//! 5. [`crate::gap::diagnose`] on the same points ([`diagnose_on_machine`]): the baseline of
//!    effects.md (the chosen machine's location errors, `physical` mode, the chosen branch) and
//!    every candidate effect whose physics the machine has ([`Effect::on_chain`]: paper 001's A-B
//!    head has `backlash_a` and `a_index`, no `backlash_c` or `c_index`; paper 002's tilting table
//!    has no `pivot_length`), whatever the identification's own mode; where the residual lies,
//!    which effect, how far it shrinks.
//!
//! Edge cases (tests/edge_*.rs): non-finite or non-positive `l0` and `noise_sigma` are refused
//! with the value; a refinement whose linear and exact models disagree by more than
//! [`crate::identify::refine::NONLINEAR_WARN_FRACTION`] adds a `WARNING:` note to the
//! identification (with `refine: false` that check is not made).

mod diagnosis;
mod error;
mod final_answer;
mod fit;
mod known;
mod noise;
mod options;
mod outliers;
mod points;
mod progress;
mod report;
mod session;

use crate::numerics::parallel::join;
pub use diagnosis::{diagnose_on_machine, diagnose_points, Diagnosis};
pub use error::AnalysisError;
pub use fit::{fit_points, fit_points_with, PointsFit};
pub use options::{AnalysisOptions, KnownDeviation};
pub use points::{
    columns_of, design_at, effects_on_machine, measurement_points, measurement_points_on,
    nearest_curve, sensitivity_options,
};
pub use progress::{silent, Progress, Sink, Stage};
use report::diagnosis_summary;
pub use report::{
    Analysis, BaselineFit, DesignColumns, Fitted, NoiseSource, Outliers, RepeatReport,
};
pub use session::{prepare, PointsModel, Session, KEPT_MAX_POINTS, KEPT_POINT_SETS};

use crate::cmm::{read_and_match, MatchedPart, ReadOptions};
use crate::measurement::repeat::{self, Measurement, PureError};
use crate::settings::{NoiseError, NoiseKind};

use known::{known_note, minus_known};
use noise::noise_source;
use outliers::name_outliers;

/// [`analyse`] of one file on settings prepared for it alone: the plain function from the file
/// and its settings to the analysis. A caller analysing several files (or the same file again)
/// with the same machine, L0, branch and mode holds one [`Session`] instead.
pub fn analyse_once(
    bytes: &[u8],
    name: &str,
    opts: &AnalysisOptions,
) -> Result<Analysis, AnalysisError> {
    analyse_parts_once_with(&[(bytes, name)], opts, &mut silent).map(|(a, _)| a)
}

/// Reads, matches, identifies and diagnoses one CMM file, on the session of its settings
/// ([`Session::new`] with the same `opts`, or any session whose machine, L0, branch and mode
/// are those of `opts`).
pub fn analyse(
    session: &Session,
    bytes: &[u8],
    name: &str,
    opts: &AnalysisOptions,
) -> Result<Analysis, AnalysisError> {
    analyse_fitted(session, bytes, name, opts).map(|(a, _)| a)
}

/// [`analyse`] of the mean of several measurements of one part (the first file, then its
/// repeats: the same point ids measured again). The CMM's share of the noise is the pure error
/// of their differences ([`crate::measurement::repeat`]), so neither σ nor an MPE may be given
/// with them; it is a floor, and the part's own scatter (which re-probing does not resample) is
/// added from the data by the diagnosis. The points, their order and the excluded rows are the
/// first file's.
pub fn analyse_repeats(
    session: &Session,
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
) -> Result<Analysis, AnalysisError> {
    analyse_parts(session, files, opts).map(|(a, _)| a)
}

/// [`analyse`], and what it fitted.
pub fn analyse_fitted(
    session: &Session,
    bytes: &[u8],
    name: &str,
    opts: &AnalysisOptions,
) -> Result<(Analysis, Fitted), AnalysisError> {
    analyse_parts(session, &[(bytes, name)], opts)
}

/// The files read, matched and combined: the first file, its deviations replaced by the mean of
/// the repeats when there are some, and their pure error.
pub(super) fn read_parts(
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
) -> Result<(MatchedPart, Option<PureError>), AnalysisError> {
    let ropts = ReadOptions::default()
        .with_exclude_bad_rows(opts.exclude_bad_rows)
        .with_threads(opts.threads);
    let mut parts = files
        .iter()
        .map(|(bytes, name)| read_and_match(bytes, name, &ropts))
        .collect::<Result<Vec<_>, _>>()?;
    if parts.len() < 2 {
        return Ok((parts.remove(0), None));
    }
    if opts.noise_sigma.is_some() || opts.noise_mpe.is_some() {
        return Err(AnalysisError::SigmaAndRepeats {
            given: match (opts.noise_sigma, &opts.noise_mpe) {
                (Some(s), _) => format!("σ = {s} mm"),
                (None, Some(m)) => format!("MPE = {} + L/{} µm", m.a_um, m.k_mm),
                (None, None) => unreachable!("checked above"),
            },
            repeats: parts.len(),
        });
    }
    let ids: Vec<Vec<String>> = parts
        .iter()
        .map(|p| p.points.iter().map(|q| q.file.id.clone()).collect())
        .collect();
    let feet: Vec<Vec<[f64; 3]>> = parts
        .iter()
        .map(|p| p.points.iter().map(|q| q.foot).collect())
        .collect();
    let deviations: Vec<Vec<f64>> = parts.iter().map(MatchedPart::deviations).collect();
    let measurements: Vec<Measurement> = (0..parts.len())
        .map(|k| Measurement {
            name: &parts[k].name,
            ids: &ids[k],
            positions: &feet[k],
            deviations: &deviations[k],
        })
        .collect();
    let pe = repeat::pure_error(&measurements)?;
    let mut first = parts.remove(0);
    for (q, m) in first.points.iter_mut().zip(&pe.mean) {
        q.deviation = *m;
    }
    Ok((first, Some(pe)))
}

/// [`analyse_repeats`], and what it fitted: one file (`files.len() == 1`) is [`analyse_fitted`].
pub fn analyse_parts(
    session: &Session,
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
) -> Result<(Analysis, Fitted), AnalysisError> {
    analyse_parts_with(session, files, opts, &mut silent)
}

/// [`analyse_parts`], each [`Stage`] reported to `progress` as it begins (the results are the
/// same whatever the sink).
pub fn analyse_parts_with(
    session: &Session,
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
    progress: Sink,
) -> Result<(Analysis, Fitted), AnalysisError> {
    check_sigma(opts)?;
    progress(Progress::of(Stage::Read));
    let read = read_parts(files, opts)?;
    analyse_read(session, read, opts, progress)
}

/// [`analyse_parts_with`] on a session made for `opts` alone ([`Session::new`]), prepared while
/// the files are read and matched (on another thread when there is one: the two depend on
/// nothing of each other's, and a process that analyses one file, as the CLI does, had prepared
/// its settings first, ~30 ms with one of two threads idle half the time, issue 31). The same
/// results; an error of the settings is reported before one of the files.
pub fn analyse_parts_once_with(
    files: &[(&[u8], &str)],
    opts: &AnalysisOptions,
    progress: Sink,
) -> Result<(Analysis, Fitted), AnalysisError> {
    check_sigma(opts)?;
    progress(Progress::of(Stage::Read));
    let (session, read) = join(
        opts.threads,
        || Session::new(opts),
        || read_parts(files, opts),
    );
    analyse_read(&session?, read?, opts, progress)
}

/// A given σ must be finite and positive.
fn check_sigma(opts: &AnalysisOptions) -> Result<(), AnalysisError> {
    match opts.noise_sigma {
        Some(s) if !(s.is_finite() && s > 0.0) => Err(NoiseError::BadSigma(s).into()),
        _ => Ok(()),
    }
}

/// The analysis of the files [`read_parts`] read and matched, from the points' model on.
fn analyse_read(
    session: &Session,
    (matched, pure): (MatchedPart, Option<PureError>),
    opts: &AnalysisOptions,
    progress: Sink,
) -> Result<(Analysis, Fitted), AnalysisError> {
    let prepared = session.prepared();
    let points = measurement_points_on(prepared.part(), &matched, opts.threads);
    let mut noise = match &pure {
        Some(pe) => NoiseSource {
            source: NoiseKind::Repeat,
            sigma: Some(pe.sigma_mean),
            mpe_range: None,
            // written with the lack of fit, once the baseline is fitted (below)
            summary: String::new(),
        },
        None => noise_source(
            opts,
            &points.iter().map(|p| p.point.norm()).collect::<Vec<_>>(),
        )?,
    };
    // The options the stages see: σ given or from the MPE.
    let opts_in = opts;
    let opts = &AnalysisOptions {
        noise_sigma: noise.sigma,
        noise_mpe: None,
        ..opts.clone()
    };
    let deviations = minus_known(matched.deviations(), opts.known.as_ref())?;
    let ids: Vec<String> = matched.points.iter().map(|p| p.file.id.clone()).collect();
    progress(Progress::of(Stage::Model));
    let model = session.points_model(&points);
    let scan = model.scan().map(|s| s.layout.clone());
    let path_position = model
        .part_model()
        .ok()
        .map(|m| m.points.iter().map(|p| p.s).collect());
    // the fit, and beside it (on another thread when there is one) what a scan's heights tell
    // apart that the built-in points cannot (issue 31 item 2)
    let (fitted, separability) = join(
        opts.threads,
        || fit_points_with(prepared, &model, &deviations, &ids, opts, progress),
        || {
            scan.as_ref()
                .and_then(|_| model.part_model().ok())
                .map(|m| crate::gap::separability::separability(m, prepared.builtin_model()))
        },
    );
    let PointsFit {
        mut diagnosis,
        outliers,
        mut baseline,
        design: final_design,
        identification: mut final_id,
        refinement: final_refinement,
        correction,
        observations: obs,
    } = fitted?;
    let repeat = pure.map(|pe| {
        let baseline = &baseline.identification;
        let used: Vec<f64> = baseline
            .points
            .iter()
            .filter(|p| p.used)
            .map(|p| p.residual)
            .collect();
        let rss: f64 = used.iter().map(|r| r * r).sum();
        let lack_of_fit = repeat::lack_of_fit(&pe, rss, used.len(), baseline.rank_used);
        let summary = repeat::sentence(&pe, &lack_of_fit);
        noise.summary = summary.clone();
        RepeatReport {
            pure_error: pe,
            lack_of_fit,
            summary,
        }
    });
    if let Some(k) = &opts.known {
        let note = known_note(k);
        baseline.identification.notes.push(note.clone());
        final_id.notes.push(note);
    }
    for id in [&mut baseline.identification, &mut final_id] {
        name_outliers(id, &outliers);
        if noise.source.is_derived() {
            id.notes.push(noise.summary.clone());
        }
    }
    if let Diagnosis::Made { report, .. } = &mut diagnosis {
        report.summary = diagnosis_summary(
            report,
            &outliers,
            &points,
            opts.known.as_ref(),
            &noise,
            opts.feed,
            (scan.as_ref(), separability.as_ref()),
        );
    }
    let analysis = Analysis {
        diagnosis,
        version: crate::VERSION,
        settings: opts_in.clone(),
        outliers,
        noise,
        repeat,
        scan,
        separability,
        path_position,
        file: matched,
        points,
        design: columns_of(&final_design),
        identification: final_id,
        refinement: final_refinement,
        correction,
        baseline,
    };
    Ok((
        analysis,
        Fitted {
            design: final_design,
            observations: obs,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::part::SShape;
    use crate::settings::MachineChoice;

    const CLEAN: &str = include_str!("../../tests/data/reference/examples/example_clean.csv");

    #[test]
    fn the_clean_example_matches_the_builtin_points_and_their_design() {
        let a = analyse_once(
            CLEAN.as_bytes(),
            "example_clean.csv",
            &AnalysisOptions::default(),
        )
        .unwrap();
        assert_eq!(a.points.len(), 100);
        let part = SShape::iso();
        let builtin = crate::part::builtin_points(&part);
        // The file's points are the built-in ones written with 6 decimals: the projection finds
        // the same (u, v) to the rounding of the file (5e-7 mm over |dS/du| ≈ 650 mm).
        for (p, q) in a.points.iter().zip(&builtin) {
            assert_eq!(p.curve, q.curve);
            assert!(
                (p.u - q.u).abs() < 1e-8,
                "id {}: u {} vs {}",
                q.id,
                p.u,
                q.u
            );
            assert!((p.h - q.h).abs() < 1e-6);
        }
        assert_eq!(a.design.parameters.len(), 8);
        assert_eq!(a.identification.points_used, 100);
    }

    #[test]
    fn tool_radius_term_adds_a_minus_one_column() {
        let o = AnalysisOptions {
            tool_radius: true,
            ..Default::default()
        };
        let a = analyse_once(CLEAN.as_bytes(), "example_clean.csv", &o).unwrap();
        assert_eq!(
            a.design.parameters.last(),
            Some(&crate::parameter::ParamId::ToolRadius)
        );
        assert!(a.design.columns[8].iter().all(|&v| v == -1.0));
    }

    #[test]
    fn the_examples_get_their_keyed_verdicts_through_the_whole_pipeline() {
        // Keys: tests/data/reference/examples/*.key.json (`accept`).
        for (file, text, accept) in [
            ("example_clean.csv", CLEAN, &["none"][..]),
            (
                "example_tool_radius.csv",
                include_str!("../../tests/data/reference/examples/example_tool_radius.csv"),
                &["tool_radius", "tool_taper"][..],
            ),
            (
                "example_backlash_c.csv",
                include_str!("../../tests/data/reference/examples/example_backlash_c.csv"),
                &["backlash_c"][..],
            ),
        ] {
            let a = analyse_once(text.as_bytes(), file, &AnalysisOptions::default()).unwrap();
            let d = a.diagnosis.report().unwrap();
            assert!(
                accept.contains(&d.verdict.id().as_str()),
                "{file}: {}",
                d.verdict.id()
            );
            assert!(d.summary.starts_with("Verdict: "), "{file}: {}", d.summary);
        }
    }

    #[test]
    fn each_machine_analyses_the_clean_example_with_its_own_error_set() {
        // The three chains of the page; each design has one column per error of the chain's
        // set (sensitivity::error_set) and a finite fit at all 100 points.
        for m in [
            MachineChoice::Paper000,
            MachineChoice::Paper001,
            MachineChoice::Paper002,
        ] {
            let o = AnalysisOptions {
                machine: m,
                ..Default::default()
            };
            let a = analyse_once(CLEAN.as_bytes(), "example_clean.csv", &o).unwrap();
            let set = crate::sensitivity::error_set::error_set(&m.chain(o.l0), o.branch).unwrap();
            assert_eq!(a.design.names(), set.kept, "{m:?}");
            assert_eq!(a.identification.points_used, 100);
            assert!(a.identification.residual.rms.is_finite(), "{m:?}");
        }
    }

    #[test]
    fn a_known_deviation_is_subtracted_before_identification() {
        // Subtracting the measured deviation itself leaves nothing for the machine: every
        // fitted value and residual is 0, and the reports say what was subtracted.
        let base = analyse_once(CLEAN.as_bytes(), "c.csv", &AnalysisOptions::default()).unwrap();
        let o = AnalysisOptions {
            known: Some(KnownDeviation {
                source: "test path".into(),
                values: base.file.deviations(),
            }),
            ..Default::default()
        };
        let a = analyse_once(CLEAN.as_bytes(), "c.csv", &o).unwrap();
        assert!(a
            .identification
            .points
            .iter()
            .all(|p| p.measured.abs() < 1e-15));
        assert!(a.identification.residual.max_abs < 1e-12);
        assert!(a
            .identification
            .notes
            .iter()
            .any(|n| n.contains("test path")));
        // a known shift moves the fit's input by exactly that shift
        let o = AnalysisOptions {
            known: Some(KnownDeviation {
                source: "shift".into(),
                values: vec![0.001; 100],
            }),
            refine: false,
            ..Default::default()
        };
        let b = analyse_once(CLEAN.as_bytes(), "c.csv", &o).unwrap();
        for (p, q) in b
            .identification
            .points
            .iter()
            .zip(&base.identification.points)
        {
            crate::assert_near!(p.measured, q.measured - 0.001, 1e-15);
        }
        let bad = AnalysisOptions {
            known: Some(KnownDeviation {
                source: "short".into(),
                values: vec![0.0; 3],
            }),
            ..Default::default()
        };
        let e = analyse_once(CLEAN.as_bytes(), "c.csv", &bad).unwrap_err();
        assert!(
            e.to_string().contains("3 values for 100 matched points"),
            "{e}"
        );
    }

    #[test]
    fn bad_settings_are_named() {
        let o = AnalysisOptions {
            l0: -1.0,
            ..Default::default()
        };
        let e = analyse_once(CLEAN.as_bytes(), "x.csv", &o).unwrap_err();
        assert_eq!(e.to_string(), "L0 = -1 mm is not a positive finite length");
    }

    #[test]
    fn the_path_position_is_the_tool_tip_length_at_each_point() {
        // Against the tip-length tables of the part (src/toolpath/tip_length.rs, checked there
        // against a chord sum): A's points at s_A(u), B's after the whole of A's pass; to 1e-9 mm.
        use crate::part::Surface;
        use crate::toolpath::tip_length::TipLength;
        let a = analyse_once(
            CLEAN.as_bytes(),
            "example_clean.csv",
            &AnalysisOptions::default(),
        )
        .unwrap();
        let s = a.path_position.as_ref().expect("a diagnosis model");
        assert_eq!(s.len(), a.points.len());
        let part = SShape::iso();
        let (ta, tb) = (
            TipLength::new(&part, Surface::A),
            TipLength::new(&part, Surface::B),
        );
        for (p, &got) in a.points.iter().zip(s) {
            let want = match p.surface {
                Surface::A => ta.at(&part, p.u),
                Surface::B => ta.total() + tb.at(&part, p.u),
            };
            assert!((got - want).abs() < 1e-9, "id {}: {got} vs {want}", p.id);
        }
    }
}
