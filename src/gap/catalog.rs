//! The candidate effects of `shared/spec/effects.md`: ids, parameters, units and plain names.
//! Ids are fixed (files, the CLI's JSON and the page use them as written).

/// One candidate of effects.md.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EffectInfo {
    pub id: &'static str,
    /// Parameter names and units, in the order of the signature columns.
    pub parameters: &'static [(&'static str, &'static str)],
    pub plain_name: &'static str,
}

/// Every candidate, in the order of effects.md.
pub const EFFECTS: &[EffectInfo] = &[
    EffectInfo {
        id: "tool_radius",
        parameters: &[("dR", "mm")],
        plain_name: "tool radius error",
    },
    EffectInfo {
        id: "tool_taper",
        parameters: &[("dR0", "mm"), ("g", "mm/mm")],
        plain_name: "tool radius varying along the tool axis (taper)",
    },
    EffectInfo {
        id: "overcut",
        parameters: &[("k", "1")],
        plain_name: "flank-milling overcut of the ruled surface",
    },
    EffectInfo {
        id: "backlash_x",
        parameters: &[("b", "mm")],
        plain_name: "backlash of the X axis",
    },
    EffectInfo {
        id: "backlash_y",
        parameters: &[("b", "mm")],
        plain_name: "backlash of the Y axis",
    },
    EffectInfo {
        id: "backlash_z",
        parameters: &[("b", "mm")],
        plain_name: "backlash of the Z axis",
    },
    EffectInfo {
        id: "backlash_b",
        parameters: &[("b", "rad")],
        plain_name: "backlash of the B axis",
    },
    EffectInfo {
        id: "backlash_c",
        parameters: &[("b", "rad")],
        plain_name: "backlash of the C axis",
    },
    EffectInfo {
        id: "thermal_drift",
        parameters: &[("g", "mm")],
        plain_name: "thermal growth of the head along Z",
    },
    EffectInfo {
        id: "setup_error",
        parameters: &[("thetaz", "rad"), ("tx", "mm"), ("ty", "mm")],
        plain_name: "part set-up (datum alignment) error",
    },
    EffectInfo {
        id: "scale_x",
        parameters: &[("k", "mm/mm")],
        plain_name: "linear scale error of the X axis",
    },
    EffectInfo {
        id: "scale_y",
        parameters: &[("k", "mm/mm")],
        plain_name: "linear scale error of the Y axis",
    },
    EffectInfo {
        id: "scale_z",
        parameters: &[("k", "mm/mm")],
        plain_name: "linear scale error of the Z axis",
    },
    EffectInfo {
        id: "c_index",
        parameters: &[("dC", "rad")],
        plain_name: "zero offset of the C axis",
    },
    EffectInfo {
        id: "pivot_length",
        parameters: &[("dL0", "mm")],
        plain_name: "pivot-to-tip length error",
    },
];

/// The verdict when the residual is noise.
pub const NONE: &str = "none";
/// The verdict when the residual is structured and no candidate explains it.
pub const UNEXPLAINED: &str = "unexplained";

/// The catalog entry of `id`.
pub fn effect_info(id: &str) -> Option<&'static EffectInfo> {
    EFFECTS.iter().find(|e| e.id == id)
}

/// A plain-language name for a verdict or candidate id (the id itself if unknown).
pub fn plain_name(id: &str) -> &str {
    match id {
        NONE => "no unmodelled effect (the residual is measurement noise)",
        UNEXPLAINED => "unexplained structured residual",
        _ => effect_info(id).map_or(id, |e| e.plain_name),
    }
}
