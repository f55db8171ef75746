//! The part program (issue 19, step 2): the finishing flank pass of both walls of the S-shape,
//! as the CAM and the NC program a lab needs before the test, made by the same models the
//! analysis uses afterwards.
//!
//! Pipeline position: part geometry → tool path (eq. 2) → machine kinematics (eq. 9-10) →
//! **program** → (machining, CMM) → identify. Surface A, then B, each in increasing `u`
//! (effects.md's machining order), the tool tip on `T_tool(u)` and its axis on `R(u)`
//! ([`crate::toolpath::flank`]), a flat end mill of radius 10 mm. Roughing (the stock removal
//! before this pass) is not included, and every output says so.
//! - [`sampling`]: positions placed so that the scallop between positions, the chord of the
//!   tip path and the controller's linear interpolation in machine axes all stay within the
//!   tolerance; axis values by the analysis's inverse kinematics and B branch, through the
//!   singular zone as the analysis assumes.
//! - [`motion`]: the moves around the cut (retract to a safe machine height, rotary axes,
//!   X Y, down, along the tool axis into and out of each pass), placed with a clearance.
//! - The CL file ([`cl`]): APT `GOTO/x,y,z,i,j,k` with `RAPID` before each positioning move
//!   and `FEDRAT` for the moves along the axis and the pass: the format `budget --cl` reads.
//! - The program in a controller's dialect ([`dialect`], [`gcode`]), read back by [`read`].
//! - [`clearance`]: the replay of the moves with the tool and holder against the part.
//!
//! Units: mm, rad inside; degrees in the G-code; feed mm/min.

pub mod cl;
pub mod clearance;
pub mod dialect;
mod error;
pub mod gcode;
pub mod motion;
pub mod read;
pub mod sampling;

use serde::{Deserialize, Serialize};

pub use dialect::Dialect;
pub use error::ProgramError;
pub use gcode::{write_gcode, GcodeSettings};
pub use motion::{motion, Motion, Step, StepKind};
pub use read::{read_program, ReadBlock};
pub use sampling::{max_step, sample_surface};

use crate::budget::ToolPath;
use crate::machine::chain::PAPER000_L0;
use crate::machine::{AxisValues, Branch, Chain};
use crate::part::{SShape, Surface};
use crate::settings::MachineChoice;
use crate::toolpath::{tool_pose, TOOL_RADIUS};

/// Settings of a program; `Default`: paper 000's machine, L0 = 499.889 mm, signed B, 1 µm
/// tolerance, 1000 mm/min.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ProgramOptions {
    pub machine: MachineChoice,
    /// Pivot-to-tip length (mm; not used by the tilting table).
    pub l0: f64,
    pub branch: Branch,
    /// Largest chord error (mm) of the rules of [`sampling`].
    pub tolerance: f64,
    /// Feed (mm/min) of the finishing pass.
    pub feed: f64,
    /// The controller's dialect of the G-code.
    pub dialect: Dialect,
    /// Tool-centre-point mode (TRAORI, FUNCTION TCPM, G43.4) instead of machine axes.
    pub tcp: bool,
    /// Spindle speed (1/min).
    pub spindle: f64,
    /// Tool number (and its length-offset register).
    pub tool: u32,
}

impl Default for ProgramOptions {
    fn default() -> Self {
        ProgramOptions {
            machine: MachineChoice::Paper000,
            l0: PAPER000_L0,
            branch: Branch::Signed,
            tolerance: 0.001,
            feed: crate::settings::feed::PROGRAMME_FEED,
            dialect: Dialect::Iso,
            tcp: false,
            spindle: 6000.0,
            tool: 1,
        }
    }
}

/// One tool position: path parameter, tip and unit axis (mm, part frame), machine axes (mm,
/// rad), whether it lies in the singular (vertical) zone.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Position {
    pub u: f64,
    pub tip: [f64; 3],
    pub axis: [f64; 3],
    pub axes: AxisValues,
    pub singular: bool,
}

/// The pass of one surface.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProgramPass {
    pub surface: Surface,
    pub positions: Vec<Position>,
    /// Largest error between consecutive positions (mm, rules 1-3 of [`sampling`]).
    pub max_interval_error: f64,
    /// Largest tip step (mm) and the largest scallop (mm, rule 1).
    pub max_step: f64,
    pub max_scallop: f64,
}

/// A part program: both passes and what they guarantee.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Program {
    pub version: &'static str,
    pub settings: ProgramOptions,
    /// The machine's description (axes, chain code).
    pub machine: &'static str,
    pub passes: Vec<ProgramPass>,
    /// The moves around the cut and the heights they were placed with.
    pub motion: Motion,
    pub notes: Vec<String>,
}

impl ProgramOptions {
    /// The chain of the chosen machine with its L0.
    pub fn chain(&self) -> Chain {
        self.machine.chain(self.l0)
    }

    fn validate(&self) -> Result<(), ProgramError> {
        if !(self.tolerance.is_finite() && (1e-5..=1.0).contains(&self.tolerance)) {
            return Err(ProgramError::BadTolerance(self.tolerance));
        }
        if !(self.feed.is_finite() && self.feed > 0.0) {
            return Err(ProgramError::BadFeed(self.feed));
        }
        if !(self.l0.is_finite() && self.l0 > 0.0) {
            return Err(ProgramError::BadL0(self.l0));
        }
        if !(self.spindle.is_finite() && (1.0..=100_000.0).contains(&self.spindle)) {
            return Err(ProgramError::BadSpindle(self.spindle));
        }
        if !(1..=99).contains(&self.tool) {
            return Err(ProgramError::BadTool(self.tool));
        }
        if self.tcp && !self.dialect.offers_tcp() {
            return Err(ProgramError::NoTcp(self.dialect.id()));
        }
        Ok(())
    }
}

/// The finishing flank pass of surfaces A and B for `opts`.
pub fn program(opts: &ProgramOptions) -> Result<Program, ProgramError> {
    opts.validate()?;
    let part = SShape::iso();
    let chain = opts.chain();
    let mut passes = Vec::new();
    for s in Surface::BOTH {
        let (path, err, max_scallop) =
            sample_surface(&part, &chain, opts.branch, s, opts.tolerance)?;
        let positions: Vec<Position> = path
            .iter()
            .map(|p| {
                let t = tool_pose(&part, s, p.u);
                Position {
                    u: p.u,
                    tip: [t.tip.x, t.tip.y, t.tip.z],
                    axis: [t.axis.x, t.axis.y, t.axis.z],
                    axes: p.values,
                    singular: p.singular,
                }
            })
            .collect();
        let step = positions
            .windows(2)
            .map(|w| {
                let d = [0, 1, 2].map(|k| w[1].tip[k] - w[0].tip[k]);
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
            })
            .fold(0.0, f64::max);
        passes.push(ProgramPass {
            surface: s,
            positions,
            max_interval_error: err,
            max_step: step,
            max_scallop,
        });
    }
    let notes = vec![
        "Finishing flank pass only: roughing (stock removal before this pass) is not included."
            .to_string(),
        format!(
            "Positions: tip steps of {:.4} mm (scallop {} mm on a flat wall, paper 000 eq. 7), \
             then halved where the scallop on the curved wall, the tip chord or the controller's \
             linear interpolation of the axes (tip and top of flank, h = 35 mm) left the \
             tolerance.",
            max_step(opts.tolerance, TOOL_RADIUS),
            opts.tolerance
        ),
        if opts.tcp {
            format!(
                "G-code ({}): tool-centre-point mode, the tip in the part frame and the rotary \
                 angles, feed per minute at the tip.",
                opts.dialect.describe()
            )
        } else {
            format!(
                "G-code ({}): machine axes of the chain without tool-centre-point management; \
                 part origin at the chain's machine zero (where the analysis sets it); the pass \
                 in {}.",
                opts.dialect.describe(),
                if opts.dialect.inverse_time() {
                    "inverse-time feed (G93)"
                } else {
                    "per-block feeds for the programmed tip speed"
                }
            )
        },
    ];
    let chain = opts.chain();
    let motion = motion::motion(
        &chain,
        &passes
            .iter()
            .map(|p| (p.surface, p.positions.as_slice()))
            .collect::<Vec<_>>(),
    )?;
    let mut notes = notes;
    notes.push(format!(
        "Moves outside the cut: Z to the machine's home, then per surface the rotary axes alone \
         at the safe height Z = {:.3} mm, X Y, Z down to {} mm clear of the part, feed along the \
         tool axis into the pass and out of it; the tool leaves each cut at feed along its axis.",
        motion.z_safe,
        motion::DESIGN_CLEARANCE
    ));
    Ok(Program {
        version: crate::VERSION,
        machine: opts.machine.describe(),
        settings: opts.clone(),
        passes,
        motion,
        notes,
    })
}

/// What a program guarantees, without its positions (for the page).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassSummary {
    pub surface: Surface,
    pub positions: usize,
    pub singular_positions: usize,
    pub max_interval_error: f64,
    pub max_step: f64,
    pub max_scallop: f64,
}

impl Program {
    /// Per pass: positions (in the singular zone too), largest interval error, step, scallop.
    pub fn summary(&self) -> Vec<PassSummary> {
        self.passes
            .iter()
            .map(|p| PassSummary {
                surface: p.surface,
                positions: p.positions.len(),
                singular_positions: p.positions.iter().filter(|q| q.singular).count(),
                max_interval_error: p.max_interval_error,
                max_step: p.max_step,
                max_scallop: p.max_scallop,
            })
            .collect()
    }

    /// The header comment lines every output carries: software version, machine, L0, tool,
    /// branch, tolerance, feed, and that roughing is not included.
    pub fn header(&self) -> String {
        let o = &self.settings;
        let l0 = if o.machine.uses_l0() {
            format!("L0 = {} mm (pivot to tool tip)", o.l0)
        } else {
            "L0 not used by this chain".to_string()
        };
        let branch = match o.branch {
            Branch::Signed => {
                "signed (tilt angle may be negative; outer rotary angle interpolated across the vertical zone)"
            }
            Branch::Positive => "positive (tilt angle >= 0; outer rotary angle unwrapped modulo 2 pi)",
        };
        format!(
            "testpiece {} part program: ISO 10791-7 S-shape, finishing flank pass of surface A then B (increasing u)\n\
             ROUGHING NOT INCLUDED: remove the stock before this pass\n\
             machine: {}\n\
             {l0}\n\
             tool: flat end mill, diameter {} mm, programmed point = tool tip, axis = ruling R(u) (paper 000 eq. 2)\n\
             branch: {branch}\n\
             chord tolerance: {} mm; feed {} mm/min; {} + {} positions\n\
             units: mm, degrees; part frame of paper 000 Table 1 (Z = 0 at the base, Z up)",
            self.version,
            self.machine,
            2.0 * TOOL_RADIUS,
            o.tolerance,
            o.feed,
            self.passes.first().map_or(0, |p| p.positions.len()),
            self.passes.get(1).map_or(0, |p| p.positions.len()),
        )
    }

    /// Every position as a [`ToolPath`] (tips and axes in the part frame), surface A then B.
    pub fn tool_path(&self, name: &str) -> ToolPath {
        let all = self.passes.iter().flat_map(|p| &p.positions);
        let tips: Vec<[f64; 3]> = all.clone().map(|q| q.tip).collect();
        ToolPath {
            name: name.to_string(),
            format: "testpiece program".to_string(),
            lines: (1..=tips.len()).collect(),
            axes: all.map(|q| q.axis).collect(),
            tips,
            times: None,
            cutter_diameter: Some(2.0 * TOOL_RADIUS),
            notes: Vec::new(),
        }
    }

    /// The CL file ([`cl`]).
    pub fn cl_apt(&self) -> String {
        cl::write_cl(self)
    }

    /// The G-code settings of this program.
    pub fn gcode_settings(&self) -> GcodeSettings {
        let o = &self.settings;
        GcodeSettings {
            dialect: o.dialect,
            tcp: o.tcp,
            feed: o.feed,
            spindle: o.spindle,
            tool: o.tool,
        }
    }

    /// The largest move of a tool point (tip to the top of the flank) that the rounding of the
    /// G-code's axis words gives (mm): [`gcode::rounding_bound`] over the pass.
    pub fn rounding_bound(&self) -> f64 {
        let qs: Vec<AxisValues> = self
            .passes
            .iter()
            .flat_map(|p| p.positions.iter().map(|q| q.axes))
            .collect();
        gcode::rounding_bound(
            &self.settings.chain(),
            &qs,
            self.settings.dialect.decimals(),
            crate::part::ruled::TIP_OFFSET,
        )
    }

    /// The program in the chosen dialect ([`gcode`]).
    pub fn gcode(&self) -> String {
        let s = self.gcode_settings();
        let mut header = self.header();
        header.push_str(&format!(
            "\ndialect: {}{}; tool T{} length offset {}, spindle S{} clockwise, flood coolant\n\
             axis words rounded to {} decimals: tool path read back within {:.2e} mm\n\
             safe height Z {:.3} mm (machine), {} mm clearance; machine Z home assumed above it",
            s.dialect.describe(),
            if s.tcp {
                ", tool-centre-point mode"
            } else {
                ""
            },
            s.tool,
            s.tool,
            s.spindle,
            s.dialect.decimals(),
            self.rounding_bound(),
            self.motion.z_safe,
            motion::DESIGN_CLEARANCE,
        ));
        write_gcode(&self.settings.chain(), &header, &self.motion, &s)
    }
}
