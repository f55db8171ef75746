//! The machine a part is identified on: one of the three five-axis chains of the papers, with
//! its pivot length where it has one (the page's "Kinematic chain" setting, the CLI's `--machine`).

use serde::Serialize;

use crate::machine::Chain;

/// The machine whose location errors are identified (the page's "Kinematic chain" setting).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MachineChoice {
    /// Paper 000: B head on Z on X, C table on Y (`w C Y' b X Z B t`), tip `L0` below the B axis.
    #[default]
    Paper000,
    /// Paper 001 Appendix 2: X table, A-B head (`w X' b Y Z B A t`), tip `L0 = ls + lt` below A.
    Paper001,
    /// Paper 002 eq. 1: B-C tilting table (`w C' B' b X Y Z t`), tip at the machine point (no L0).
    Paper002,
}

impl MachineChoice {
    /// The chain with the pivot length `l0` (mm; unused by the tilting table).
    pub fn chain(self, l0: f64) -> Chain {
        match self {
            MachineChoice::Paper000 => Chain::paper000(l0),
            // Only ls + lt enters the tool tip (T_12p raises Z by ls + lt, the tip is ls + lt below A).
            MachineChoice::Paper001 => Chain::paper001(l0, 0.0),
            MachineChoice::Paper002 => Chain::paper002(),
        }
    }
    /// The three chains, in the page's order.
    pub const ALL: [MachineChoice; 3] = [
        MachineChoice::Paper000,
        MachineChoice::Paper002,
        MachineChoice::Paper001,
    ];
    /// Whether the pivot length L0 enters the chain (not on the tilting table).
    pub fn uses_l0(self) -> bool {
        self != MachineChoice::Paper002
    }
    /// What a page or report shows of the machine.
    pub fn info(self) -> MachineInfo {
        MachineInfo {
            id: self,
            name: self.describe(),
            uses_l0: self.uses_l0(),
        }
    }
    /// A plain description for reports.
    pub fn describe(self) -> &'static str {
        match self {
            MachineChoice::Paper000 => "B head / C table (paper 000, w C Y' b X Z B t)",
            MachineChoice::Paper001 => "A-B head, X table (paper 001, w X' b Y Z B A t)",
            MachineChoice::Paper002 => "B-C tilting table (paper 002, w C' B' b X Y Z t)",
        }
    }
}

/// A machine as the page lists it (JSON `{id, name, uses_l0}`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MachineInfo {
    pub id: MachineChoice,
    pub name: &'static str,
    pub uses_l0: bool,
}
