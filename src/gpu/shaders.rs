//! The WGSL sources, assembled (shared declarations + one stage file) and
//! reflected with naga: which buffers each entry point binds, and how.

use std::collections::BTreeMap;

const COMMON: &str = include_str!("../../shaders/common.wgsl");

/// The neighbour walk every stage shares (shaders/walk.wgsl).
const WALK: &str = include_str!("../../shaders/walk.wgsl");

/// One pass of the penalty law (shaders/penalty.wgsl), part of the contact
/// stage.
const PENALTY: &str = include_str!("../../shaders/penalty.wgsl");

/// The contact's spread (shaders/spread.wgsl), part of the stages that run
/// it: the contact's own pass and the midpoint rule's advance passes.
const SPREAD: &str = include_str!("../../shaders/spread.wgsl");

/// The stress update with a plastic history (shaders/strength.wgsl), part
/// of the stages that run it: the kinematics pass (the leapfrog's step) and
/// the midpoint rule's advance passes.
const STRENGTH: &str = include_str!("../../shaders/strength.wgsl");

/// Every stage file: `(name, source)`.
pub const STAGES: &[(&str, &str)] = &[
    ("neighbours", include_str!("../../shaders/neighbours.wgsl")),
    ("kinematics", include_str!("../../shaders/kinematics.wgsl")),
    ("forces", include_str!("../../shaders/forces.wgsl")),
    ("contact", include_str!("../../shaders/contact.wgsl")),
    ("reduce", include_str!("../../shaders/reduce.wgsl")),
    ("advance", include_str!("../../shaders/advance.wgsl")),
    ("reorder", include_str!("../../shaders/reorder.wgsl")),
    ("debug", include_str!("../../shaders/debug.wgsl")),
];

/// The full source of a stage: the shared declarations, the constants the
/// host generates for this scene (`prelude`: the observation slots of
/// `reduce`, [`super::ProbePlan::wgsl`]; empty for the other stages), then
/// the stage.
pub fn source(stage: &str, prelude: &str) -> String {
    let body = STAGES
        .iter()
        .find(|s| s.0 == stage)
        .unwrap_or_else(|| panic!("no shader stage '{stage}'"))
        .1;
    let spread = if matches!(stage, "contact" | "advance") {
        SPREAD
    } else {
        ""
    };
    let strength = if matches!(stage, "kinematics" | "advance") {
        STRENGTH
    } else {
        ""
    };
    let penalty = if stage == "contact" { PENALTY } else { "" };
    format!("{COMMON}\n{WALK}\n{prelude}\n{spread}\n{strength}\n{penalty}\n// ---- {stage}.wgsl ----\n{body}")
}

/// A prelude to check a stage alone with (tests): for `reduce`, one
/// observation slot of every code.
pub fn sample_prelude(stage: &str) -> String {
    if stage == "reduce" {
        super::ProbePlan::sample().wgsl()
    } else {
        String::new()
    }
}

/// How an entry point uses one binding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BindingUse {
    pub binding: u32,
    /// The global's name: the host binds the buffer of that name.
    pub name: String,
    pub uniform: bool,
    pub read_only: bool,
}

/// A parsed and validated stage.
pub struct Reflected {
    pub module: naga::Module,
    pub info: naga::valid::ModuleInfo,
}

/// Parse and validate a stage with naga; the error names the stage and
/// carries naga's full report.
pub fn reflect(stage: &str, prelude: &str) -> Result<Reflected, String> {
    let src = source(stage, prelude);
    let module = naga::front::wgsl::parse_str(&src)
        .map_err(|e| format!("{stage}.wgsl: {}", e.emit_to_string(&src)))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| format!("{stage}.wgsl: {}", e.emit_to_string(&src)))?;
    Ok(Reflected { module, info })
}

impl Reflected {
    /// Entry point names.
    pub fn entry_points(&self) -> Vec<String> {
        self.module
            .entry_points
            .iter()
            .map(|e| e.name.clone())
            .collect()
    }

    /// The bindings an entry point uses, by binding number.
    pub fn bindings(&self, entry: &str) -> Vec<BindingUse> {
        let idx = self
            .module
            .entry_points
            .iter()
            .position(|e| e.name == entry)
            .unwrap_or_else(|| panic!("no entry point '{entry}'"));
        let fi = self.info.get_entry_point(idx);
        let mut out = BTreeMap::new();
        for (h, var) in self.module.global_variables.iter() {
            let Some(rb) = &var.binding else { continue };
            if fi[h].is_empty() {
                continue;
            }
            let (uniform, read_only) = match var.space {
                naga::AddressSpace::Uniform => (true, true),
                naga::AddressSpace::Storage { access } => {
                    (false, !access.contains(naga::StorageAccess::STORE))
                }
                _ => continue,
            };
            out.insert(
                rb.binding,
                BindingUse {
                    binding: rb.binding,
                    name: var.name.clone().unwrap_or_default(),
                    uniform,
                    read_only,
                },
            );
        }
        out.into_values().collect()
    }
}
