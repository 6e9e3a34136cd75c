//! The time step's stages: one table for both backends.
//!
//! A stage is one piece of the step that both backends run: the GPU as a
//! shader, `shaders/<stage>.wgsl`, the CPU oracle as a plain gather of the
//! same name, `src/cpu/<stage>.rs` (or `src/cpu/<stage>/`). Where the CPU solver runs the stage's
//! sums pair by pair instead (kinematics and forces, [`crate::cpu::sweep`]),
//! the row names that file too. [`STAGES`] lists each stage with its
//! files, the tests that hold the two to each other, and what it reads and
//! writes; [`MIDPOINT`] and [`LEAPFROG`] are the two integrators' steps as
//! sequences of stages. The GPU encodes its step from these schedules
//! (`gpu::GpuSolver`), the CPU's step runs its stages in the same order
//! (checked in its tests), and the benchmarks time the stages by these
//! names (`sphcontact bench --stages`).
//!
//! | stage | shader | CPU twin | what |
//! |---|---|---|---|
//! | reorder | `reorder.wgsl` | — | particles permuted by cell, every 16 steps |
//! | neighbours | `neighbours.wgsl` | [`crate::cpu::neighbours`] | the cell list (the CPU: and the candidate lists) |
//! | kinematics | `kinematics.wgsl` | [`crate::cpu::kinematics`] | correction, the boundary set, EOS, `∇v`, `dρ/dt`, `ds/dt` |
//! | forces | `forces.wgsl` | [`crate::cpu::forces`] | momentum, energy, contact normals and areas |
//! | contact | `contact.wgsl` | [`crate::cpu::contact`] | the penalty contact |
//! | reduce | `reduce.wgsl` | [`crate::cpu::reduce`] | the CFL step and the observations |
//! | advance | `advance.wgsl` | [`crate::cpu::advance`] | time integration, strength update, state check |
//!
//! Some shader files are not stages but parts of them: `strength.wgsl`
//! (the stress update with a plastic history, [`crate::physics::strength`])
//! in the kinematics and advance stages, `spread.wgsl` (the contact
//! spring's pull through the normals) in the contact and advance stages,
//! `kinematics_point.wgsl` (the per-particle part) in the kinematics stage,
//! `dispersion.wgsl` (the dispersion correction's walks,
//! [`crate::cpu::dispersion`]) compiled with the kinematics stage, its
//! force and work walks run in the forces stage's entries, and
//! `forces_pair.wgsl` (the pair terms) in the forces stage.
//! `common.wgsl` holds the declarations every stage shares, `kernel.wgsl`
//! the kernel and the supports, `material.wgsl` the material laws, and
//! `walk.wgsl` the neighbour walk; `penalty.wgsl` is the contact stage's pass of the
//! penalty law ([`crate::physics::penalty`]).

use crate::scene::Integrator;

/// A stage of the time step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stage {
    Reorder,
    Neighbours,
    Kinematics,
    Forces,
    Contact,
    Reduce,
    Advance,
}

/// One row of the stage table.
#[derive(Debug, Clone, Copy)]
pub struct StageInfo {
    pub stage: Stage,
    /// The stage's name: its shader's and its CPU twin's file stem, and
    /// what `bench --stages` and the step profiles call it.
    pub name: &'static str,
    /// Its shader and the shader parts it includes, under `shaders/`.
    pub shaders: &'static [&'static str],
    /// Its CPU twin, under `src/`; `None` where the CPU has no such stage.
    pub cpu: Option<&'static str>,
    /// What the CPU solver runs in the twin's place, under `src/`, where it
    /// runs something else: the same sums pair by pair
    /// ([`crate::cpu::sweep`]), tested against the twin.
    pub solver: Option<&'static str>,
    /// Tests of the stage: `file::function`, the file under the crate root.
    /// The first checks the shader against the CPU twin.
    pub tests: &'static [&'static str],
    /// What it reads and what it writes, per particle unless it says
    /// otherwise.
    pub reads: &'static str,
    pub writes: &'static str,
    /// What it does, in a line.
    pub what: &'static str,
}

/// Every stage, in the order a midpoint step first runs them.
pub const STAGES: [StageInfo; 7] = [
    StageInfo {
        stage: Stage::Reorder,
        name: "reorder",
        shaders: &["reorder.wgsl"],
        cpu: None,
        solver: None,
        tests: &[
            "tests/gpu_runs/main.rs::disks_polar_gpu_matches_cpu",
            "tests/gpu_runs/repeat.rs::gpu_histories_are_bitwise_repeatable",
        ],
        reads: "the cell list; every per-particle array",
        writes: "every per-particle array, permuted by cell",
        what: "particles sorted by cell every 16 steps, for memory locality \
               (the CPU keeps the scene's order; the GPU un-permutes what it reports)",
    },
    StageInfo {
        stage: Stage::Neighbours,
        name: "neighbours",
        shaders: &["neighbours.wgsl"],
        cpu: Some("cpu/neighbours.rs"),
        solver: None,
        tests: &[
            "tests/gpu_stages/parity.rs::stages_match_cpu_disks_square",
            "src/cpu/neighbours_tests.rs::cell_list_equals_brute_force",
            "src/math/cells.rs::cells_of_four_particles_by_hand",
        ],
        reads: "x",
        writes: "the cell list: counts, offsets, particles sorted by cell \
                 (the CPU: and each particle's candidate list)",
        what: "the cell list the neighbour walks visit",
    },
    StageInfo {
        stage: Stage::Kinematics,
        name: "kinematics",
        shaders: &[
            "kinematics.wgsl",
            "kinematics_point.wgsl",
            "strength.wgsl",
            "dispersion.wgsl",
        ],
        cpu: Some("cpu/kinematics/mod.rs"),
        solver: Some("cpu/sweep/kinematics.rs"),
        tests: &[
            "tests/gpu_stages/parity.rs::stages_match_cpu_disks_polar",
            "tests/stages.rs::corrected_gradient_reproduces_linear_fields",
            "src/cpu/sweep/tests/mod.rs::sweeps_match_gathers_and_lanes_one_pair_code",
        ],
        reads: "x, v, ρ, e, s, damage; the cell list",
        writes: "L (the gradient correction), ∇ψ and the boundary set, σ/ρ² and c (EOS), \
                 ∇v, dρ/dt, ds/dt, the equivalent strain rate",
        what:
            "correction, colour gradient and the boundary set, EOS, velocity gradient, density and \
             stress rates",
    },
    StageInfo {
        stage: Stage::Forces,
        name: "forces",
        shaders: &["forces.wgsl", "forces_pair.wgsl"],
        cpu: Some("cpu/forces/mod.rs"),
        solver: Some("cpu/sweep/forces.rs"),
        tests: &[
            "tests/gpu_stages/parity.rs::stages_match_cpu_bars_steel_aluminium",
            "src/cpu/sweep/tests/mod.rs::sweeps_match_gathers_and_lanes_one_pair_code",
            "tests/stages.rs::outward_normals",
            "src/cpu/forces/tests.rs::square_corner_normal_by_hand",
            "src/physics/tension.rs::artificial_stress_is_the_principal_axes_form",
        ],
        reads: "x, v, σ/ρ², c, L, ∇v, the boundary set; the cell list",
        writes: "dv/dt and de/dt of the SPH sums; the boundary list, each boundary particle's \
                 outward normal and contact area",
        what: "momentum and energy (artificial viscosity and stress), contact normals and areas",
    },
    StageInfo {
        stage: Stage::Contact,
        name: "contact",
        shaders: &["contact.wgsl", "penalty.wgsl", "spread.wgsl"],
        cpu: Some("cpu/contact/mod.rs"),
        solver: None,
        tests: &[
            "tests/gpu_stages/parity.rs::stages_match_cpu_with_entry_overlaps",
            "src/cpu/contact_tests.rs::two_particles_gap_and_force_by_hand",
            "src/cpu/contact_tests.rs::spring_force_is_the_stored_energys_gradient",
        ],
        reads: "x, v, normals, contact area, the boundary list, entry overlaps",
        writes: "penalty forces (and their spread onto neighbours), dashpot heat, \
                 spring energy, entry overlaps",
        what: "the penalty contact between bodies, both gathers",
    },
    StageInfo {
        stage: Stage::Reduce,
        name: "reduce",
        shaders: &["reduce.wgsl"],
        cpu: Some("cpu/reduce.rs"),
        solver: None,
        tests: &[
            "tests/gpu_stages/parity.rs::stages_match_cpu_disks_square",
            "src/cpu/reduce.rs::cfl_step_by_hand",
        ],
        reads: "c, v, h; the probes' quantities",
        writes: "the step Δt (one number); the step's observations",
        what: "the CFL step and the recorded observations",
    },
    StageInfo {
        stage: Stage::Advance,
        name: "advance",
        shaders: &["advance.wgsl", "strength.wgsl", "spread.wgsl"],
        cpu: Some("cpu/advance.rs"),
        solver: None,
        tests: &[
            "tests/gpu_stages/steps.rs::stages_match_cpu_penetration",
            "tests/gpu_stages/steps.rs::leapfrog_steps_match_cpu",
            "tests/strength.rs::a_block_follows_the_exact_johnson_cook_curve",
        ],
        reads: "the state and the rates",
        writes: "the next state (x, v, ρ, e, s, plastic history), time and step counters",
        what: "time integration, the strength update, the state check",
    },
];

/// The row of `stage`.
pub fn info(stage: Stage) -> &'static StageInfo {
    &STAGES[stage as usize]
}

impl Stage {
    /// The stage's name ([`StageInfo::name`]).
    pub fn name(self) -> &'static str {
        info(self).name
    }

    /// The stage called `name`.
    pub fn named(name: &str) -> Option<Stage> {
        STAGES.iter().find(|s| s.name == name).map(|s| s.stage)
    }
}

/// Where in a step a stage runs: on which state, or which of its passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// Every 16 steps, before the step.
    Periodic,
    /// An evaluation at the step's base state `n`.
    Base,
    /// An evaluation at the midpoint `n+½`.
    Mid,
    /// Once a step.
    Step,
    /// The midpoint rule's half step `n → n+½`, with the strength update.
    HalfStep,
    /// The midpoint rule's full step `n → n+1` from the midpoint's rates.
    FullStep,
    /// The leapfrog's half kick and drift; its cell counts.
    KickDrift,
    /// The leapfrog's cell list at `x_{n+1}`, from the counts the drift took.
    Drifted,
    /// An evaluation at the leapfrog's `n+1`.
    Next,
    /// The leapfrog's energy sums at the kicked velocities.
    Energy,
    /// The leapfrog's booking of the contact's rates.
    Book,
    /// The leapfrog's second half kick.
    Finish,
}

/// One entry of a step's schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Scheduled {
    pub stage: Stage,
    pub role: Role,
}

const fn at(stage: Stage, role: Role) -> Scheduled {
    Scheduled { stage, role }
}

/// The explicit midpoint rule: two evaluations a step.
pub const MIDPOINT: &[Scheduled] = &[
    at(Stage::Reorder, Role::Periodic),
    at(Stage::Neighbours, Role::Base),
    at(Stage::Kinematics, Role::Base),
    at(Stage::Forces, Role::Base),
    at(Stage::Contact, Role::Base),
    at(Stage::Reduce, Role::Step),
    at(Stage::Advance, Role::HalfStep),
    at(Stage::Neighbours, Role::Mid),
    at(Stage::Kinematics, Role::Mid),
    at(Stage::Forces, Role::Mid),
    at(Stage::Contact, Role::Mid),
    at(Stage::Advance, Role::FullStep),
];

/// The kick–drift–kick leapfrog: one evaluation a step, the rates at `n`
/// carried over from the step before.
pub const LEAPFROG: &[Scheduled] = &[
    at(Stage::Reorder, Role::Periodic),
    at(Stage::Reduce, Role::Step),
    at(Stage::Advance, Role::KickDrift),
    at(Stage::Neighbours, Role::Drifted),
    at(Stage::Kinematics, Role::Next),
    at(Stage::Forces, Role::Next),
    at(Stage::Contact, Role::Next),
    at(Stage::Forces, Role::Energy),
    at(Stage::Contact, Role::Book),
    at(Stage::Advance, Role::Finish),
];

/// The step of an integrator.
pub fn schedule(integrator: Integrator) -> &'static [Scheduled] {
    match integrator {
        Integrator::Midpoint => MIDPOINT,
        Integrator::Leapfrog => LEAPFROG,
    }
}

/// The entries of `stage` in `schedule` that run at the step's own state:
/// all but the evaluation at the midpoint, which runs the same dispatches
/// again. What timing a stage alone runs.
pub fn at_base(schedule: &[Scheduled], stage: Stage) -> impl Iterator<Item = Scheduled> + '_ {
    schedule
        .iter()
        .copied()
        .filter(move |e| e.stage == stage && e.role != Role::Mid)
}

/// How many times one step runs the entries [`at_base`] gives: the
/// evaluation stages of the midpoint rule twice, every other once, the
/// reordering once every `reorder_every` steps.
pub fn per_step(schedule: &[Scheduled], stage: Stage, reorder_every: u64) -> f64 {
    if stage == Stage::Reorder {
        return 1.0 / reorder_every as f64;
    }
    let all = schedule.iter().filter(|e| e.stage == stage).count();
    let base = at_base(schedule, stage).count();
    all as f64 / base as f64
}

/// Records the stages the CPU's step runs, in its tests; nothing otherwise.
#[cfg(test)]
pub(crate) mod trace {
    use super::Scheduled;
    use std::cell::RefCell;

    thread_local! {
        static RAN: RefCell<Option<Vec<Scheduled>>> = const { RefCell::new(None) };
    }

    pub fn enter(s: Scheduled) {
        RAN.with(|r| {
            if let Some(v) = r.borrow_mut().as_mut() {
                v.push(s);
            }
        });
    }

    /// The stages `f` runs on this thread.
    pub fn record(f: impl FnOnce()) -> Vec<Scheduled> {
        RAN.with(|r| *r.borrow_mut() = Some(Vec::new()));
        f();
        RAN.with(|r| r.borrow_mut().take().unwrap_or_default())
    }
}

/// Marks the start of a stage of the CPU's step (recorded in tests).
#[inline(always)]
pub(crate) fn enter(_stage: Stage, _role: Role) {
    #[cfg(test)]
    trace::enter(at(_stage, _role));
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Every file and test the table names exists: the table cannot drift
    /// from the tree.
    #[test]
    fn the_table_names_what_is_there() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        for (k, s) in STAGES.iter().enumerate() {
            assert_eq!(s.stage as usize, k, "{} out of order", s.name);
            assert_eq!(s.shaders[0], format!("{}.wgsl", s.name), "twins by name");
            for f in s.shaders {
                assert!(root.join("shaders").join(f).is_file(), "shaders/{f}");
            }
            if let Some(c) = s.cpu {
                let (file, folder) = (
                    format!("cpu/{}.rs", s.name),
                    format!("cpu/{}/mod.rs", s.name),
                );
                assert!(c == file || c == folder, "twins by name: {c}");
                assert!(root.join("src").join(c).is_file(), "src/{c}");
            }
            if let Some(c) = s.solver {
                assert!(root.join("src").join(c).is_file(), "src/{c}");
            }
            for t in s.tests {
                let (file, func) = t.split_once("::").expect("file::function");
                let text = std::fs::read_to_string(root.join(file))
                    .unwrap_or_else(|e| panic!("{file} of {}: {e}", s.name));
                assert!(
                    text.contains(&format!("fn {func}()")),
                    "{}: no test {func} in {file}",
                    s.name
                );
            }
        }
    }

    #[test]
    fn names_round_trip() {
        for s in &STAGES {
            assert_eq!(Stage::named(s.name), Some(s.stage));
            assert_eq!(s.stage.name(), s.name);
        }
        assert_eq!(Stage::named("pass_b"), None);
    }

    /// Each schedule runs every stage and one full step: the midpoint two
    /// evaluations, the leapfrog one.
    #[test]
    fn schedules_evaluate_as_their_integrators_do() {
        let count = |s: &[Scheduled], st: Stage| s.iter().filter(|e| e.stage == st).count();
        for (st, leap) in [
            (Stage::Neighbours, 1),
            (Stage::Kinematics, 1),
            (Stage::Forces, 2),
            (Stage::Contact, 2),
        ] {
            assert_eq!(count(MIDPOINT, st), 2, "{st:?}");
            assert_eq!(count(LEAPFROG, st), leap, "{st:?}");
        }
        for s in &STAGES {
            assert!(count(MIDPOINT, s.stage) > 0 && count(LEAPFROG, s.stage) > 0);
        }
        assert_eq!(per_step(MIDPOINT, Stage::Reorder, 16), 1.0 / 16.0);
        assert_eq!(per_step(MIDPOINT, Stage::Neighbours, 16), 2.0);
        assert_eq!(per_step(MIDPOINT, Stage::Advance, 16), 1.0);
        assert_eq!(per_step(LEAPFROG, Stage::Forces, 16), 1.0);
    }
}
