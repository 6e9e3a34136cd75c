//! The WGSL sources, assembled (shared declarations + one stage file) and
//! reflected with naga: which buffers each entry point binds, and how.

use std::collections::BTreeMap;

/// What every module starts with: the shared declarations, the kernel
/// and the supports, the material laws.
const COMMON: &str = concat!(
    include_str!("../../shaders/common.wgsl"),
    "\n",
    include_str!("../../shaders/kernel.wgsl"),
    "\n",
    include_str!("../../shaders/material.wgsl"),
);

/// The files of [`COMMON`].
#[cfg(test)]
const COMMON_FILES: [&str; 3] = ["common.wgsl", "kernel.wgsl", "material.wgsl"];

/// The neighbour walk every stage shares (shaders/walk.wgsl).
const WALK: &str = include_str!("../../shaders/walk.wgsl");

/// Every WGSL file besides the two every module starts with: the stages'
/// files and the parts some of them share, as the stage table lists them
/// ([`crate::stage::STAGES`], `shaders`), and the test kernels'.
const FILES: &[(&str, &str)] = &[
    ("reorder.wgsl", include_str!("../../shaders/reorder.wgsl")),
    (
        "neighbours.wgsl",
        include_str!("../../shaders/neighbours.wgsl"),
    ),
    (
        "kinematics.wgsl",
        include_str!("../../shaders/kinematics.wgsl"),
    ),
    (
        "kinematics_point.wgsl",
        include_str!("../../shaders/kinematics_point.wgsl"),
    ),
    ("forces.wgsl", include_str!("../../shaders/forces.wgsl")),
    (
        "forces_pair.wgsl",
        include_str!("../../shaders/forces_pair.wgsl"),
    ),
    ("contact.wgsl", include_str!("../../shaders/contact.wgsl")),
    ("reduce.wgsl", include_str!("../../shaders/reduce.wgsl")),
    ("advance.wgsl", include_str!("../../shaders/advance.wgsl")),
    // One pass of the penalty law, part of the contact stage.
    ("penalty.wgsl", include_str!("../../shaders/penalty.wgsl")),
    // The contact's spread: the contact's own pass and the midpoint
    // rule's advance passes.
    ("spread.wgsl", include_str!("../../shaders/spread.wgsl")),
    // The stress update with a plastic history: the kinematics pass (the
    // leapfrog's step) and the midpoint rule's advance passes.
    ("strength.wgsl", include_str!("../../shaders/strength.wgsl")),
    // The dispersion correction's walks, compiled with the kinematics
    // stage (those of its force and work run in the forces stage's
    // entries).
    (
        "dispersion.wgsl",
        include_str!("../../shaders/dispersion.wgsl"),
    ),
    ("debug.wgsl", include_str!("../../shaders/debug.wgsl")),
];

/// The parts more than one module includes (the rest of a stage's parts
/// are its own).
const SHARED_PARTS: [&str; 3] = ["spread.wgsl", "strength.wgsl", "penalty.wgsl"];

/// The test kernels' module (debug.wgsl): compiled as a stage is, but no
/// stage of the step.
pub const TEST_KERNELS: &str = "debug";

/// Every module: each stage of the stage table, then the test kernels.
pub fn modules() -> impl Iterator<Item = &'static str> {
    crate::stage::STAGES
        .iter()
        .map(|s| s.name)
        .chain([TEST_KERNELS])
}

fn file(name: &str) -> &'static str {
    FILES
        .iter()
        .find(|f| f.0 == name)
        .unwrap_or_else(|| panic!("no shader file '{name}'"))
        .1
}

/// The full source of a stage: the shared declarations, the constants the
/// host generates for this scene (`prelude`: the observation slots of
/// `reduce`, [`super::ProbePlan::wgsl`]; empty for the other stages), the
/// shared parts the stage table lists for it, then the stage's own file.
pub fn source(stage: &str, prelude: &str) -> String {
    let (body, parts): (&str, &[&str]) = if stage == TEST_KERNELS {
        (file("debug.wgsl"), &["strength.wgsl"])
    } else {
        let info = crate::stage::Stage::named(stage)
            .map(crate::stage::info)
            .unwrap_or_else(|| panic!("no shader stage '{stage}'"));
        (file(info.shaders[0]), &info.shaders[1..])
    };
    // The shared parts in one order, whatever order the table lists them.
    let part = |f: &str| if parts.contains(&f) { file(f) } else { "" };
    let (spread, penalty) = (part("spread.wgsl"), part("penalty.wgsl"));
    let strength = if parts.contains(&"strength.wgsl") {
        format!("{}\n{}", file("strength.wgsl"), laws())
    } else {
        String::new()
    };
    // Then the stage's own parts, in the table's order.
    let own: String = parts
        .iter()
        .filter(|f| !SHARED_PARTS.contains(f))
        .map(|f| format!("// ---- {f} ----\n{}\n", file(f)))
        .collect();
    let eos = eos_laws();
    format!("{COMMON}\n{eos}\n{WALK}\n{prelude}\n{spread}\n{strength}\n{penalty}\n{own}// ---- {stage}.wgsl ----\n{body}")
}

/// `// ---- <dir>/<kind>.wgsl ----` and the file, for every law of a
/// registry.
fn law_sources(dir: &str, laws: &[crate::physics::DeviceLaw]) -> String {
    laws.iter()
        .map(|l| format!("// ---- {dir}/{}.wgsl ----\n{}\n", l.kind, l.wgsl))
        .collect()
}

/// The dispatch `head` (a WGSL function's signature) on the law number
/// `field` of a registry: each law's `<kind>_<call>` behind its bit of the
/// override `gate`, else `none`.
fn dispatch(
    laws: &[crate::physics::DeviceLaw],
    (gate, field): (&str, &str),
    head: &str,
    call: &str,
    none: &str,
) -> String {
    let mut f = format!("{head} {{\n");
    for l in laws {
        f += &format!(
            "    if (({gate} & {}u) != 0u && {field} == {}u) {{\n        return {}_{call};\n    }}\n",
            1u32 << l.id,
            l.id,
            l.kind
        );
    }
    f + &format!("    return {none};\n}}\n")
}

/// Every strength law's WGSL (shaders/laws/) and damage law's
/// (shaders/failure/), and the dispatch on a body's law, written from the
/// registries ([`crate::physics::laws::DEVICE`],
/// [`crate::physics::failure::DEVICE`]). A law that no body of the scene
/// uses is compiled out: the override `STRENGTH_LAWS` (`FAILURE_LAWS`) has
/// its bit (`1 << id`) clear.
fn laws() -> String {
    use crate::physics::{failure, laws};
    let strength = ("STRENGTH_LAWS", "p.law");
    let mut out = law_sources("laws", laws::DEVICE) + &law_sources("failure", failure::DEVICE);
    out += "// The laws' dispatch (gpu::shaders::laws).\n";
    out += &dispatch(
        laws::DEVICE,
        strength,
        "fn law_factor(p: Plastic, rate: f32, rise: f32) -> f32",
        "factor(p, rate, rise)",
        "1.0",
    );
    out += &dispatch(
        laws::DEVICE,
        strength,
        "fn law_curve(p: Plastic, f: f32, eps: f32) -> vec2<f32>",
        "curve(p, f, eps)",
        "vec2<f32>(0.0)",
    );
    // The damage laws' (a particle with none never asks).
    out += &dispatch(
        failure::DEVICE,
        ("FAILURE_LAWS", "p.damage"),
        "fn failure_strain(p: Plastic, triax: f32, rate_star: f32, t_star: f32) -> f32",
        "failure_strain(p, triax, rate_star, t_star)",
        "BIG",
    );
    out
}

/// Every equation of state's WGSL (shaders/eos/) and the dispatch on a
/// body's law, written from the registry ([`crate::physics::eos::DEVICE`]):
/// `eos_pressure`, `eos_dpdrho` and `eos_zero_mu`. A law that no body of the
/// scene uses is compiled out: the override `EOS_LAWS` has its bit
/// (`1 << id`) clear.
fn eos_laws() -> String {
    use crate::physics::eos::DEVICE;
    let gate = ("EOS_LAWS", "b.eos");
    let mut out = law_sources("eos", DEVICE);
    out += "// The equations of state's dispatch (gpu::shaders::eos_laws).\n";
    out += &dispatch(
        DEVICE,
        gate,
        "fn eos_pressure(b: Body, mu: f32, e: f32) -> f32",
        "pressure(b, mu, e)",
        "0.0",
    );
    out += &dispatch(
        DEVICE,
        gate,
        "fn eos_dpdrho(b: Body, mu: f32, e: f32) -> f32",
        "dpdrho(b, mu, e)",
        "0.0",
    );
    out += &dispatch(
        DEVICE,
        gate,
        "fn eos_zero_mu(b: Body, e: f32) -> f32",
        "zero_mu(b, e)",
        "0.0",
    );
    out
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

#[cfg(test)]
mod tests {
    /// Every file in shaders/ is a module's part, and every file the
    /// stage table names is one of them.
    #[test]
    fn every_shader_file_is_listed() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|f| {
                f.ends_with(".wgsl")
                    && !super::COMMON_FILES.contains(&f.as_str())
                    && f != "walk.wgsl"
            })
            .collect();
        on_disk.sort();
        let mut listed: Vec<String> = super::FILES.iter().map(|f| f.0.to_string()).collect();
        listed.sort();
        assert_eq!(on_disk, listed);
        for s in &crate::stage::STAGES {
            for f in s.shaders {
                super::file(f);
            }
        }
    }
}
