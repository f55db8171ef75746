//! The stages of one analysis as they begin, reported to a sink the caller passes as a value
//! (issue 31 item 3): the page's worker posts them to the page's progress bar, the CLI writes
//! them on a terminal's stderr. The core knows nothing of either: a sink is any
//! `FnMut(Progress)`; [`silent`] reports nothing. No stage changes any result.

use serde::Serialize;

/// A stage of one analysis ([`super::analyse_parts_with`]), in the order they run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Reading the file(s) and matching every point to the nominal surfaces.
    Read,
    /// The points' axis values and part model (a scan's lines, the path positions).
    Model,
    /// The design of the location errors at the points.
    Design,
    /// The outlier test and the gap diagnosis (every candidate effect).
    Diagnose,
    /// The baseline identification and its exact-model refinement.
    Identify,
    /// The final answer: the location errors fitted with what the diagnosis found.
    FinalFit,
}

impl Stage {
    /// Every stage, in order.
    pub const ALL: [Stage; 6] = [
        Stage::Read,
        Stage::Model,
        Stage::Design,
        Stage::Diagnose,
        Stage::Identify,
        Stage::FinalFit,
    ];

    /// What the stage does, in words for a progress line.
    pub fn words(self) -> &'static str {
        match self {
            Stage::Read => "reading and matching the points",
            Stage::Model => "solving the axis values and the part model",
            Stage::Design => "the design of the location errors",
            Stage::Diagnose => "diagnosing the gap (outliers, every candidate effect)",
            Stage::Identify => "identifying the location errors",
            Stage::FinalFit => "fitting the final answer",
        }
    }
}

/// One report: stage `step` (1-based) of `steps` begins. Serialised as `{stage, step, steps,
/// fraction, text}` (`fraction` = the share of the stages done, 0 to 1; `text` the stage's
/// words).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    pub stage: Stage,
    pub step: usize,
    pub steps: usize,
}

impl Progress {
    /// The report that `stage` begins.
    pub fn of(stage: Stage) -> Self {
        let step = Stage::ALL.iter().position(|&s| s == stage).unwrap_or(0) + 1;
        Self {
            stage,
            step,
            steps: Stage::ALL.len(),
        }
    }

    /// Share of the stages done when this one begins (0 to 1).
    pub fn fraction(&self) -> f64 {
        (self.step - 1) as f64 / self.steps as f64
    }

    /// `stage 4 of 6: diagnosing the gap (…)`.
    pub fn text(&self) -> String {
        format!(
            "stage {} of {}: {}",
            self.step,
            self.steps,
            self.stage.words()
        )
    }
}

impl Serialize for Progress {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut m = s.serialize_struct("Progress", 5)?;
        m.serialize_field("stage", &self.stage)?;
        m.serialize_field("step", &self.step)?;
        m.serialize_field("steps", &self.steps)?;
        m.serialize_field("fraction", &self.fraction())?;
        m.serialize_field("text", &self.text())?;
        m.end()
    }
}

/// Where the stages go: any function of a [`Progress`], passed by the caller.
pub type Sink<'a> = &'a mut dyn FnMut(Progress);

/// A sink that reports nothing.
pub fn silent(_: Progress) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stages_are_numbered_in_order_and_their_fractions_rise_from_0() {
        let steps: Vec<Progress> = Stage::ALL.iter().map(|&s| Progress::of(s)).collect();
        for (k, p) in steps.iter().enumerate() {
            assert_eq!((p.step, p.steps), (k + 1, 6));
        }
        assert_eq!(steps[0].fraction(), 0.0);
        assert!(steps.windows(2).all(|w| w[0].fraction() < w[1].fraction()));
        assert_eq!(
            steps[3].text(),
            "stage 4 of 6: diagnosing the gap (outliers, every candidate effect)"
        );
    }
}
