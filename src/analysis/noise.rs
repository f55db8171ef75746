//! The σ an analysis uses, from the CMM-noise setting, with its sentence for the reports.

use crate::settings::CmmNoise;

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::report::NoiseSource;

/// The σ an analysis uses (checked) and where it came from.
pub(super) fn noise_source(
    opts: &AnalysisOptions,
    lengths: &[f64],
) -> Result<NoiseSource, AnalysisError> {
    let noise = CmmNoise::try_new(opts.noise_sigma, opts.noise_mpe.as_ref())?.resolve(lengths);
    let summary = match (noise.sigma, noise.mpe) {
        (Some(med), Some(r)) => format!(
            "Noise: σ = {:.2} µm from the CMM's MPE_E = {} + L/{} µm (R0 = {} µm): \
             σ_i = max(MPE_E(L_i)/√3, R0/1.693) = {:.2}..{:.2} µm over the points \
             (L = distance from the part origin), median used.",
            med * 1e3,
            r.mpe.a_um,
            r.mpe.k_mm,
            r.mpe.r0_um,
            r.lo * 1e3,
            r.hi * 1e3
        ),
        (Some(sigma), None) => format!("Noise: σ = {:.2} µm, as given.", sigma * 1e3),
        (None, _) => "Noise: σ estimated from the residual (no CMM figure given).".to_string(),
    };
    Ok(NoiseSource {
        source: noise.kind,
        sigma: noise.sigma,
        mpe_range: noise.mpe.map(|r| (r.lo, r.hi)),
        summary,
    })
}
