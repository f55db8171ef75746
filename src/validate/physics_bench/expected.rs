//! What the diagnosis should say of a physics part: in the catalogue of effects.md (which id, and
//! which ids count as the same), outside it, or clean; and whether a verdict is right.
//!
//! The families of effects.md's "Shapes are families" (`tool_wear`, `servo_lag_<axis>`,
//! `servo_common`) are candidates of the product since issue 30; their ids keep variants of their
//! own here because the generator's physics names them, not the product's signatures.
//!
//! A verdict is **right** (the rule of [`super::super::single`]):
//! - `none` when the part is clean or its visible structure is at most the detection limit;
//! - above the limit, an effect of the catalogue: the verdict names it (as the effect or the second
//!   of a pair), an id listed with it, an id the verdict lists as equivalent, or one the part
//!   cannot tell from it ([`crate::validate::ValidationModel::near_equivalence`]);
//! - above the limit, outside the catalogue: `unexplained`;
//! - and in both, a named verdict whose effects absorb the part's effect to below the limit
//!   (with the location errors; no test on these points can tell the two apart).

use serde::Serialize;

use crate::machine::AxisName;
use crate::parameter::Effect;
use crate::validate::physics::Physics;

/// An effect id of effects.md: a candidate of the product, or one it does not have yet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CatalogueId {
    Product(Effect),
    /// `tool_wear`.
    ToolWear,
    /// `servo_lag_<axis>`.
    ServoLag(AxisName),
    /// `servo_common`.
    ServoCommon,
}

impl CatalogueId {
    /// The id as effects.md writes it.
    pub fn id(&self) -> String {
        match self {
            CatalogueId::Product(e) => e.id().to_string(),
            CatalogueId::ToolWear => "tool_wear".into(),
            CatalogueId::ServoLag(a) => format!("servo_lag_{}", a.to_string().to_lowercase()),
            CatalogueId::ServoCommon => "servo_common".into(),
        }
    }
    /// The product's candidate (every id of the catalogue has one since issue 30).
    pub fn effect(&self) -> Option<Effect> {
        Some(match self {
            CatalogueId::Product(e) => *e,
            CatalogueId::ToolWear => Effect::ToolWear,
            CatalogueId::ServoLag(a) => Effect::ServoLag(*a),
            CatalogueId::ServoCommon => Effect::ServoCommon,
        })
    }
}

impl Serialize for CatalogueId {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.id())
    }
}

/// Where a part's effect stands against the catalogue (JSON: `catalogue` = `clean`, `in`,
/// `out`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "catalogue", rename_all = "snake_case")]
pub enum Catalogue {
    /// No effect.
    Clean,
    /// One effect of effects.md: `id`, and `also` the ids that come with it (the common rounding
    /// of a loop whose gain differs) or contain it.
    In {
        id: CatalogueId,
        also: Vec<CatalogueId>,
    },
    /// Several effects at once, or none of the list.
    Out,
}

impl Catalogue {
    /// The catalogue's view of `physics`; `mismatch_ratio`: for loops whose gains differ, the
    /// visible structure of what the difference adds to their common rounding, over the limit
    /// (at most 1: the gains' difference is invisible, the part is `servo_common`).
    pub fn of(physics: &Physics, mismatch_ratio: Option<f64>) -> Self {
        let product = |e| CatalogueId::Product(e);
        let one = |id| Catalogue::In { id, also: vec![] };
        match physics {
            Physics::None => Catalogue::Clean,
            Physics::Backlash { axis, .. } => one(product(Effect::Backlash(*axis))),
            Physics::Servo { spread, .. } => {
                let odd: Vec<usize> = (0..5).filter(|&i| spread[i] != 0.0).collect();
                match odd.as_slice() {
                    _ if mismatch_ratio.is_none_or(|r| r <= 1.0) => one(CatalogueId::ServoCommon),
                    [i] => Catalogue::In {
                        id: CatalogueId::ServoLag(crate::validate::physics::machining::AXES[*i]),
                        also: vec![CatalogueId::ServoCommon],
                    },
                    _ => Catalogue::Out,
                }
            }
            Physics::Warmup { .. } => one(product(Effect::ThermalDrift)),
            Physics::Wear { .. } => one(CatalogueId::ToolWear),
            Physics::ToolRadius { .. } => Catalogue::In {
                id: product(Effect::ToolRadius),
                also: vec![product(Effect::ToolTaper)],
            },
            Physics::ToolTaper { .. } => one(product(Effect::ToolTaper)),
            Physics::Scale { axis, .. } => one(product(Effect::Scale(*axis))),
            Physics::CIndex { .. } => one(product(Effect::CIndex)),
            Physics::PivotLength { .. } => one(product(Effect::PivotLength)),
            Physics::Setup { .. } => one(product(Effect::SetupError)),
            Physics::Overcut => one(product(Effect::Overcut)),
            Physics::Straightness { .. }
            | Physics::Cyclic { .. }
            | Physics::Pitch { .. }
            | Physics::ProbeLobing { .. }
            | Physics::PartDrift { .. } => Catalogue::Out,
        }
    }

    /// `in` or `out` (clean parts: `clean`).
    pub fn name(&self) -> &'static str {
        match self {
            Catalogue::Clean => "clean",
            Catalogue::In { .. } => "in",
            Catalogue::Out => "out",
        }
    }
}

/// The verdict a part should get (JSON: `none`, `unexplained` or the id).
#[derive(Debug, Clone, PartialEq)]
pub enum Expected {
    None,
    Named(CatalogueId),
    Unexplained,
}

impl Expected {
    /// The expected verdict of a part of `catalogue` whose visible structure is `ratio` times
    /// the detection limit.
    pub fn of(catalogue: &Catalogue, ratio: f64) -> Self {
        match catalogue {
            _ if ratio <= 1.0 => Expected::None,
            Catalogue::Clean => Expected::None,
            Catalogue::In { id, .. } => Expected::Named(*id),
            Catalogue::Out => Expected::Unexplained,
        }
    }
    pub fn as_string(&self) -> String {
        match self {
            Expected::None => "none".into(),
            Expected::Named(id) => id.id(),
            Expected::Unexplained => "unexplained".into(),
        }
    }
}

impl Serialize for Expected {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.as_string())
    }
}
