//! The physics benchmark's figures: per group of parts, per kind, and the done-when summary of
//! issue 29, as a serialisable report and a plain-text table.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::gap::verdict::VerdictId;
use crate::numerics::stats::median;
use crate::validate::physics::noise::NoiseSpec;
use crate::validate::physics::{Kind, Physics};

use super::expected::Catalogue;
use super::score::Judged;

/// One case of the run.
#[derive(Debug, Clone, Serialize)]
pub struct PhysicsCase {
    pub case: usize,
    pub kind: Kind,
    pub physics: Physics,
    #[serde(flatten)]
    pub catalogue: Catalogue,
    pub noise: NoiseSpec,
    /// True σ of one analysed deviation (mm).
    pub sigma: f64,
    /// Visible structure: RMS of the noise-free deviation the location errors cannot absorb (mm).
    pub visible: f64,
    /// The detection limit with the true σ, `k σ` (mm).
    pub limit: f64,
    /// `visible / limit`.
    pub ratio: f64,
    /// The ratio the effect's amplitude was aimed at (0: a clean part; the physics is not
    /// linear in every amplitude, and amplitudes stop at their physical bound).
    pub target_ratio: f64,
    /// The location errors (rad, mm; the baseline's order).
    pub xi: Vec<f64>,
    #[serde(flatten)]
    pub judged: Judged,
}

impl PhysicsCase {
    fn is_none(&self) -> bool {
        self.judged.verdict == VerdictId::Noise
    }
}

/// The figures of one group of cases.
#[derive(Debug, Clone, Serialize, Default)]
pub struct GroupRow {
    pub group: String,
    pub cases: usize,
    /// Verdict `none`, `unexplained`, an effect named; the verdict right.
    pub none: usize,
    pub unexplained: usize,
    pub named: usize,
    pub right: usize,
    /// Location errors within 2 std of the truth over all of them: final answer and baseline.
    pub coverage: f64,
    pub coverage_baseline: f64,
    /// Median of the final std over the true model's std.
    pub median_std_ratio: f64,
    /// Median visible structure over the limit.
    pub median_ratio: f64,
}

impl GroupRow {
    fn of<'a>(group: &str, cases: impl Iterator<Item = &'a PhysicsCase>) -> Self {
        let mut r = GroupRow {
            group: group.to_string(),
            ..Default::default()
        };
        let (mut cov, mut covb, mut params) = (0, 0, 0);
        let mut ratios = Vec::new();
        let mut visible = Vec::new();
        for c in cases {
            r.cases += 1;
            match c.judged.verdict {
                VerdictId::Noise => r.none += 1,
                VerdictId::Unexplained => r.unexplained += 1,
                VerdictId::Effect(_) => r.named += 1,
            }
            r.right += usize::from(c.judged.right);
            cov += c.judged.final_error.covered;
            covb += c.judged.baseline_error.covered;
            params += c.judged.final_error.parameters;
            ratios.extend(c.judged.std_ratio.iter().copied().filter(|x| x.is_finite()));
            visible.push(c.ratio);
        }
        let share = |k: usize| {
            if params > 0 {
                k as f64 / params as f64
            } else {
                f64::NAN
            }
        };
        r.coverage = share(cov);
        r.coverage_baseline = share(covb);
        r.median_std_ratio = median(&mut ratios);
        r.median_ratio = median(&mut visible);
        r
    }
}

/// The done-when figures of issue 29 on this run.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Parts whose visible structure exceeds twice the limit, and those of them called `none`.
    pub above_twice: usize,
    pub none_above_twice: usize,
    /// `none` on clean parts, on clean scattered parts, on the repeats of a scattered part.
    pub clean_none: f64,
    pub clean_scatter_none: f64,
    pub repeats_none: f64,
    /// The smallest coverage of the final answer over the groups (clean, clean + scatter,
    /// repeats, below the limit, in and out of the catalogue above 2×, wrong verdict; verdict
    /// named, unexplained, none), and that group.
    pub min_coverage: f64,
    pub min_coverage_group: String,
    /// Verdict right on parts in the catalogue above the limit (candidates the product has; all),
    /// and out of it.
    pub in_catalogue_right: f64,
    pub in_catalogue_product_right: f64,
    pub out_of_catalogue_right: f64,
    /// Named families whose fitted shape lies within its 95 % interval, per kind of shape
    /// (`backlash lag`, `warm-up`, `servo lag`): (within, scored).
    pub shape_within: BTreeMap<String, (usize, usize)>,
}

/// The report of a physics run.
#[derive(Debug, Clone, Serialize)]
pub struct PhysicsReport {
    pub seed: u64,
    pub cases: usize,
    /// Whether the CMM's σ was given to the analysis (else estimated).
    pub cmm_sigma_given: bool,
    pub detect_factor: f64,
    pub summary: Summary,
    /// By the truth, then by the verdict.
    pub groups: Vec<GroupRow>,
    pub by_verdict: Vec<GroupRow>,
    pub per_kind: Vec<GroupRow>,
    /// `confusion[expected][verdict]`.
    pub confusion: BTreeMap<String, BTreeMap<String, usize>>,
    pub results: Vec<PhysicsCase>,
}

fn rate(num: usize, den: usize) -> f64 {
    if den > 0 {
        num as f64 / den as f64
    } else {
        f64::NAN
    }
}

impl PhysicsReport {
    /// The report of `results`.
    pub fn of(
        seed: u64,
        cmm_sigma_given: bool,
        detect_factor: f64,
        results: Vec<PhysicsCase>,
    ) -> Self {
        let r = &results;
        let kind = |k: Kind| move |c: &&PhysicsCase| c.kind == k;
        let effect = |c: &&PhysicsCase| !c.kind.is_clean();
        let in_cat = |c: &&PhysicsCase| matches!(c.catalogue, Catalogue::In { .. });
        let out_cat = |c: &&PhysicsCase| c.catalogue == Catalogue::Out;
        let groups =
            vec![
            GroupRow::of("clean", r.iter().filter(kind(Kind::Clean))),
            GroupRow::of("clean + scatter", r.iter().filter(kind(Kind::CleanScatter))),
            GroupRow::of("repeats (scattered)", r.iter().filter(kind(Kind::Repeats))),
            GroupRow::of(
                "effect below the limit",
                r.iter().filter(effect).filter(|c| c.ratio <= 1.0),
            ),
            GroupRow::of(
                "effect 1-2x the limit",
                r.iter().filter(effect).filter(|c| c.ratio > 1.0 && c.ratio <= 2.0),
            ),
            GroupRow::of(
                "in-catalogue > 2x",
                r.iter().filter(in_cat).filter(|c| c.ratio > 2.0),
            ),
            GroupRow::of(
                "  of them product ids",
                r.iter().filter(in_cat).filter(|c| c.ratio > 2.0).filter(|c| {
                    matches!(&c.catalogue, Catalogue::In { id, .. } if id.effect().is_some())
                }),
            ),
            GroupRow::of(
                "out-of-catalogue > 2x",
                r.iter().filter(out_cat).filter(|c| c.ratio > 2.0),
            ),
            GroupRow::of("wrong verdict", r.iter().filter(|c| !c.judged.right)),
        ];
        let by_verdict = vec![
            GroupRow::of("verdict none", r.iter().filter(|c| c.is_none())),
            GroupRow::of(
                "verdict named",
                r.iter()
                    .filter(|c| matches!(c.judged.verdict, VerdictId::Effect(_))),
            ),
            GroupRow::of(
                "verdict unexplained",
                r.iter()
                    .filter(|c| c.judged.verdict == VerdictId::Unexplained),
            ),
        ];
        let mut kinds: Vec<Kind> = r.iter().map(|c| c.kind).collect();
        kinds.sort();
        kinds.dedup();
        let per_kind = kinds
            .into_iter()
            .map(|k| GroupRow::of(k.as_str(), r.iter().filter(kind(k))))
            .collect();
        let mut confusion: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
        for c in r {
            *confusion
                .entry(c.judged.expected.as_string())
                .or_default()
                .entry(c.judged.verdict.to_string())
                .or_default() += 1;
        }
        let above: Vec<&PhysicsCase> = r.iter().filter(|c| c.ratio > 2.0).collect();
        let none_rate = |k: Kind| {
            let g: Vec<_> = r.iter().filter(kind(k)).collect();
            rate(g.iter().filter(|c| c.is_none()).count(), g.len())
        };
        let right_rate = |keep: &dyn Fn(&&PhysicsCase) -> bool| {
            let g: Vec<_> = r.iter().filter(|c| c.ratio > 1.0).filter(keep).collect();
            rate(g.iter().filter(|c| c.judged.right).count(), g.len())
        };
        let (min_coverage, min_coverage_group) = groups
            .iter()
            .chain(&by_verdict)
            .filter(|g| g.cases > 0 && !g.group.starts_with("  ") && !g.group.contains("1-2x"))
            .map(|g| (g.coverage, g.group.clone()))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap_or((f64::NAN, String::new()));
        let summary = Summary {
            above_twice: above.len(),
            none_above_twice: above.iter().filter(|c| c.is_none()).count(),
            clean_none: none_rate(Kind::Clean),
            clean_scatter_none: none_rate(Kind::CleanScatter),
            repeats_none: none_rate(Kind::Repeats),
            min_coverage,
            min_coverage_group,
            in_catalogue_right: right_rate(&in_cat),
            in_catalogue_product_right: right_rate(
                &|c: &&PhysicsCase| matches!(&c.catalogue, Catalogue::In { id, .. } if id.effect().is_some()),
            ),
            out_of_catalogue_right: right_rate(&out_cat),
            shape_within: r.iter().filter_map(|c| c.judged.shape).fold(
                BTreeMap::new(),
                |mut m, sc| {
                    let e: &mut (usize, usize) = m.entry(sc.what.to_string()).or_default();
                    e.0 += usize::from(sc.within);
                    e.1 += 1;
                    m
                },
            ),
        };
        PhysicsReport {
            seed,
            cases: results.len(),
            cmm_sigma_given,
            detect_factor,
            summary,
            groups,
            by_verdict,
            per_kind,
            confusion,
            results,
        }
    }
}

fn pct(x: f64) -> String {
    if x.is_finite() {
        format!("{:5.1} %", 100.0 * x)
    } else {
        "    —  ".into()
    }
}

fn rows(title: &str, groups: &[GroupRow]) -> String {
    let mut s = format!(
        "{title:26} cases   none  unexpl  named   right   coverage (base)    std/true  ρ med\n"
    );
    for g in groups {
        s += &format!(
            "{:26} {:>5}  {:>5}  {:>6}  {:>5}  {}  {} ({})  {:>8.2}  {:>5.2}\n",
            g.group,
            g.cases,
            g.none,
            g.unexplained,
            g.named,
            pct(rate(g.right, g.cases)),
            pct(g.coverage),
            pct(g.coverage_baseline).trim(),
            g.median_std_ratio,
            g.median_ratio,
        );
    }
    s
}

/// A plain-text table of a physics report.
pub fn physics_table(r: &PhysicsReport) -> String {
    let s_ = &r.summary;
    let mut s = format!(
        "validate --generator physics: {} parts, seed {} ({}), σ {}; limit = {} σ_true\n",
        r.cases,
        r.seed,
        match r.seed {
            1..=3 => "development seed",
            101..=103 => "HELD-OUT seed",
            _ => "other seed",
        },
        if r.cmm_sigma_given {
            "of the CMM given to the analysis"
        } else {
            "estimated by the analysis"
        },
        r.detect_factor
    );
    s += "done when (issue 29, on held-out seeds):\n";
    s += &format!(
        "  none with visible structure > 2x limit: {}/{} (target 0)\n",
        s_.none_above_twice, s_.above_twice
    );
    s += &format!(
        "  none on clean parts: {} (target >= 95 %); clean + scatter: {}; repeats of a scattered part: {} (target >= 95 %)\n",
        pct(s_.clean_none).trim(),
        pct(s_.clean_scatter_none).trim(),
        pct(s_.repeats_none).trim()
    );
    s += &format!(
        "  min coverage over groups: {} ({}) (target >= 90 %)\n",
        pct(s_.min_coverage).trim(),
        s_.min_coverage_group
    );
    s += &format!(
        "  verdict right above the limit: in-catalogue {} (of ids the product has: {}), out-of-catalogue {}\n",
        pct(s_.in_catalogue_right).trim(),
        pct(s_.in_catalogue_product_right).trim(),
        pct(s_.out_of_catalogue_right).trim()
    );
    if !s_.shape_within.is_empty() {
        let (w, n) = s_
            .shape_within
            .values()
            .fold((0, 0), |(a, b), (w, n)| (a + w, b + n));
        let each: Vec<String> = s_
            .shape_within
            .iter()
            .map(|(k, (w, n))| format!("{k} {w}/{n}"))
            .collect();
        s += &format!(
            "done when (issue 30): fitted shape within its 95 % interval, named families: {w}/{n} ({}) (target >= 90 %)\n",
            each.join(", ")
        );
    }
    s += "coverage: location errors of the final answer (baseline) within 2 std of the truth; \
          std/true: median final std over the true model's fit's; ρ: visible structure / limit\n";
    s += &rows("group (by truth)", &r.groups);
    s += &rows("group (by verdict)", &r.by_verdict);
    s += &rows("kind", &r.per_kind);
    s += "confusion (expected -> verdict: count)\n";
    for (exp, row) in &r.confusion {
        let cells: Vec<String> = row.iter().map(|(v, c)| format!("{v}:{c}")).collect();
        s += &format!("  {exp:15} -> {}\n", cells.join(" "));
    }
    s
}
