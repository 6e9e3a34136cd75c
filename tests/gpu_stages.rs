//! The device against its CPU twins, stage by stage, on identical inputs:
//! a state taken from a CPU run in the middle of a contact (so boundaries,
//! contact forces and stresses are all live). Neighbour sets must agree
//! exactly; floats within 1e-4 of the field's largest magnitude (f32 on the
//! device, f64 on the CPU). No GPU needed for the shader checks.

mod common;
use common::*;
use glam::DVec2;
use sphcontact::cpu::{self, contact, forces, kinematics, neighbours, CpuSolver};
use sphcontact::gpu::{layout, shaders, GpuSolver};
use sphcontact::math::Sym;
use sphcontact::model::{Model, State};
use sphcontact::scene::Integrator;
use sphcontact::stage::{self, Stage};

/// Every shader parses and validates with naga, and every struct shared
/// with the host has the host's layout.
#[test]
fn shaders_validate_and_layouts_match() {
    let mut checked = std::collections::BTreeSet::new();
    for (stage, _) in shaders::STAGES {
        let r = shaders::reflect(stage, &shaders::sample_prelude(stage))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(!r.entry_points().is_empty(), "{stage} has entry points");
        checked.extend(layout::check_layouts(&r.module).unwrap_or_else(|e| panic!("{stage}: {e}")));
    }
    // Every host struct was met in some stage.
    for (name, _, _) in layout::host_layouts() {
        assert!(checked.contains(name), "{name} is in no stage");
    }
}

/// A field of a stage's output, as a failure names it: the stage, its
/// shader and its CPU twin (the stage table, `sphcontact::stage`).
fn at(stage: Stage, field: &str) -> String {
    let s = stage::info(stage);
    format!(
        "stage {} ({} against src/{}): {field}",
        s.name,
        s.shaders[0],
        s.cpu.unwrap_or("-")
    )
}

/// `gpu` within `tol` of the largest |cpu|; on failure, the worst index and
/// both values.
fn assert_field(name: &str, gpu: &[f64], cpu: &[f64], tol: f64, skip: &dyn Fn(usize) -> bool) {
    let scale = cpu.iter().map(|x| x.abs()).fold(0.0, f64::max);
    assert_scaled(name, gpu, cpu, tol, scale, skip);
}

/// As [`assert_field`] with an explicit scale: a sum of parts is only as
/// exact as its largest part.
fn assert_scaled(
    name: &str,
    gpu: &[f64],
    cpu: &[f64],
    tol: f64,
    scale: f64,
    skip: &dyn Fn(usize) -> bool,
) {
    assert_eq!(gpu.len(), cpu.len());
    let scale = scale.max(1e-300);
    let mut worst = (0.0, 0);
    for i in 0..cpu.len() {
        if skip(i) {
            continue;
        }
        let e = (gpu[i] - cpu[i]).abs() / scale;
        if e > worst.0 {
            worst = (e, i);
        }
    }
    let i = worst.1;
    println!(
        "{name}: worst relative error {:.2e} at {i} (scale {scale:.3e})",
        worst.0
    );
    assert!(
        worst.0 <= tol,
        "{name}: particle {i}: gpu {} vs cpu {} (error {:.2e} of max |cpu| {scale:.3e})",
        gpu[i],
        cpu[i],
        worst.0
    );
}

fn state_during_contact(path: &str, t: f64) -> (Model, State) {
    let scene = load(path);
    let (model, state) = Model::new(&scene);
    let mut cpu = CpuSolver::new(model, state);
    while cpu.state.t < t {
        cpu.step(t - cpu.state.t).expect("a stable CPU run");
    }
    (cpu.model.clone(), cpu.state.clone())
}

fn check_stages(path: &str, t: f64) {
    if gpu().is_none() {
        return;
    }
    let (model, st) = state_during_contact(path, t);
    check_state(model, st, true);
}

fn check_state(model: Model, st: State, expect_contact: bool) {
    let Some(ctx) = gpu() else { return };
    let n = model.len();
    let mut g = GpuSolver::new(ctx, model.clone(), &st, &[], 1.0).expect("fits the adapter");
    let out = g.stage_outputs();

    // Cell list: the same neighbour set for every particle. A pair may only
    // differ if it sits at the cut-off 2 h_ij to f32 precision.
    let nb = neighbours::find(&model, &st.x);
    let mut pairs = 0;
    for i in 0..n {
        let mut cpu_set: Vec<u32> = nb.of(&model, &st.x, i).map(|b| b.j).collect();
        cpu_set.extend_from_slice(nb.cross_of(i));
        cpu_set.sort_unstable();
        pairs += cpu_set.len();
        if cpu_set != out.neighbours[i] {
            for &j in cpu_set
                .iter()
                .filter(|j| !out.neighbours[i].contains(j))
                .chain(out.neighbours[i].iter().filter(|j| !cpu_set.contains(j)))
            {
                let j = j as usize;
                let hij = 0.5 * (model.h[i] + model.h[j]);
                let r = (st.x[i] - st.x[j]).length();
                assert!(
                    (r / (2.0 * hij) - 1.0).abs() < 1e-5,
                    "{}: particle {i}: neighbour {j} at r = {r:e} (2h = {:e}) found by only one side",
                    at(Stage::Neighbours, "neighbour sets"),
                    2.0 * hij
                );
            }
        }
    }
    let per = if model.dim == 1 { 3 } else { 10 };
    assert!(
        pairs > per * n,
        "{}: {pairs} pairs",
        at(Stage::Neighbours, "a real neighbourhood")
    );

    // The kinematics pass against its twins.
    let a = kinematics::kinematics(&model, &st, &nb);
    let none = |_: usize| false;
    for (k, name) in ["L.xx", "L.xy", "L.yx", "L.yy"].iter().enumerate() {
        let cpu_l: Vec<f64> = a.l.iter().map(|m| [m.xx, m.xy, m.yx, m.yy][k]).collect();
        let gpu_l: Vec<f64> = out.l.iter().map(|m| m[k]).collect();
        assert_field(&at(Stage::Kinematics, name), &gpu_l, &cpu_l, 1e-4, &none);
    }
    let bd = kinematics::boundary(&model, &st.x, &nb, a.surface.clone());
    for i in 0..n {
        if bd.is_boundary[i] != out.boundary[i] {
            let x = model.h[i] * a.grad_psi[i].length();
            assert!(
                (x / model.boundary_threshold - 1.0).abs() < 1e-4,
                "{}: particle {i}: boundary cpu {} gpu {} (h|∇ψ| = {x})",
                at(Stage::Kinematics, "boundary set"),
                bd.is_boundary[i],
                out.boundary[i]
            );
        }
    }
    // With contact, the contact's normals (reference volumes); without,
    // the kinematics pass's colour gradient.
    let mut worst_angle: f64 = 0.0;
    for i in 0..n {
        if bd.is_boundary[i] {
            let cpu_n = if model.contact {
                bd.normal[i]
            } else {
                a.grad_psi[i].normalize()
            };
            worst_angle = worst_angle.max(cpu_n.angle_to(out.normal[i]).abs());
        }
    }
    println!("normals: worst angle {worst_angle:.2e} rad");
    assert!(
        worst_angle < 1e-3,
        "{}: normals differ by {worst_angle} rad",
        at(Stage::Kinematics, "boundary normals")
    );

    let pts = cpu::eos_and_stress(&model, &st);
    for (k, name) in ["σ/ρ².xx", "σ/ρ².yy", "σ/ρ².xy"].iter().enumerate() {
        let c: Vec<f64> = pts
            .iter()
            .map(|p| [p.sr2.xx, p.sr2.yy, p.sr2.xy][k])
            .collect();
        let gg: Vec<f64> = out.sr2.iter().map(|p| p[k]).collect();
        assert_field(&at(Stage::Kinematics, name), &gg, &c, 1e-4, &none);
    }
    let c: Vec<f64> = pts.iter().map(|p| p.c).collect();
    assert_field(
        &at(Stage::Kinematics, "sound speed"),
        &out.c,
        &c,
        1e-5,
        &none,
    );

    assert_field(
        &at(Stage::Kinematics, "dρ/dt"),
        &out.drho,
        &a.drho,
        1e-4,
        &none,
    );
    for (k, name) in ["ds.xx", "ds.yy", "ds.xy", "ds.zz"].iter().enumerate() {
        let c: Vec<f64> = a.ds.iter().map(|s| [s.xx, s.yy, s.xy, s.zz][k]).collect();
        let gg: Vec<f64> = out.ds.iter().map(|s| [s.xx, s.yy, s.xy, s.zz][k]).collect();
        assert_field(&at(Stage::Kinematics, name), &gg, &c, 1e-4, &none);
    }

    // The forces pass: momentum and energy before contact.
    let (dv, de) = forces::momentum_energy(&model, &st, &nb, &a.l, &a.gv, &a.surface, &pts);
    let xs = |v: &[DVec2]| v.iter().map(|p| p.x).collect::<Vec<_>>();
    let ys = |v: &[DVec2]| v.iter().map(|p| p.y).collect::<Vec<_>>();
    assert_field(
        &at(Stage::Forces, "dv/dt.x"),
        &xs(&out.dv_sph),
        &xs(&dv),
        1e-4,
        &none,
    );
    assert_field(
        &at(Stage::Forces, "dv/dt.y"),
        &ys(&out.dv_sph),
        &ys(&dv),
        1e-4,
        &none,
    );
    assert_field(&at(Stage::Forces, "de/dt"), &out.de_sph, &de, 1e-4, &none);

    // Contact: area, force on each particle, and the full rates.
    if model.contact {
        assert_field(
            &at(Stage::Forces, "contact area"),
            &out.area,
            &bd.area,
            1e-4,
            &none,
        );
        let cf = contact::penalty(&model, &st, &nb, &bd);
        // The CPU gives the force on the boundary particles and the spread
        // onto their neighbours; every other particle's is zero.
        let mut force = vec![DVec2::ZERO; n];
        for (&i, f) in bd.list.iter().zip(&cf.force) {
            force[i as usize] = *f;
        }
        for &(i, f) in &cf.spread {
            force[i as usize] += f;
        }
        let total: f64 = force.iter().map(|f| f.length()).sum();
        assert_eq!(total > 0.0, expect_contact, "contact force {total}");
        let rigid = |i: usize| model.rigid(i);
        assert_field(
            &at(Stage::Contact, "force.x"),
            &xs(&out.contact_force),
            &xs(&force),
            1e-4,
            &rigid,
        );
        assert_field(
            &at(Stage::Contact, "force.y"),
            &ys(&out.contact_force),
            &ys(&force),
            1e-4,
            &rigid,
        );
    }
    // The full rates: at a contact face the SPH and contact parts nearly
    // cancel (both ~1e9 m/s², the sum ~1e6), so the sum is compared on the
    // scale of its parts.
    let (rates, diag) = cpu::evaluate(&model, &st);
    let max = |v: &[f64]| v.iter().map(|x| x.abs()).fold(0.0, f64::max);
    // Largest of the SPH part `a`, the full rate `b` and the contact part `b - a`.
    let part = |a: &[f64], b: &[f64]| {
        let contact: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
        max(a).max(max(b)).max(max(&contact))
    };
    let dvx = xs(&rates.dv);
    let dvy = ys(&rates.dv);
    let sx = part(&xs(&dv), &dvx);
    let sy = part(&ys(&dv), &dvy);
    assert_scaled(
        &at(Stage::Contact, "dv/dt.x with contact"),
        &xs(&out.dv),
        &dvx,
        1e-4,
        sx,
        &none,
    );
    assert_scaled(
        &at(Stage::Contact, "dv/dt.y with contact"),
        &ys(&out.dv),
        &dvy,
        1e-4,
        sy,
        &none,
    );
    let se = part(&de, &rates.de);
    assert_scaled(
        &at(Stage::Contact, "de/dt with contact"),
        &out.de,
        &rates.de,
        1e-4,
        se,
        &none,
    );
    assert!(
        (out.dt / diag.cfl_dt - 1.0).abs() < 1e-5,
        "{}: gpu {} cpu {}",
        at(Stage::Reduce, "CFL step"),
        out.dt,
        diag.cfl_dt
    );
}

#[test]
fn stages_match_cpu_disks_square() {
    check_stages("scenes/paper/disks_square.toml", 3e-6);
}

#[test]
fn stages_match_cpu_disks_polar() {
    check_stages("scenes/paper/disks_polar.toml", 3e-6);
}

/// The entry overlaps (`State::entry`) on both sides of the rule: body
/// 0's particles joined the surface with a small overlap (their springs
/// push against less, or nothing), body 1's were off the surface at the
/// last step (they join now: no spring of their own).
#[test]
fn stages_match_cpu_with_entry_overlaps() {
    if gpu().is_none() {
        return;
    }
    let (model, mut st) = state_during_contact("scenes/paper/disks_square.toml", 3e-6);
    let dx = model.bodies[0].spacing;
    for i in 0..model.len() {
        st.entry[i] = if model.body[i] == 0 { 2e-3 * dx } else { -1.0 };
    }
    check_state(model, st, true);
}

/// Disks pushed half a spacing further into each other than the run
/// had them: the deepest springs yield (`cpu::contact::yield_overlap`).
#[test]
fn stages_match_cpu_with_yielded_springs() {
    if gpu().is_none() {
        return;
    }
    let (model, mut st) = state_during_contact("scenes/paper/disks_square.toml", 3e-6);
    let dx = model.bodies[1].spacing;
    let shift = DVec2::new(-0.5 * dx, 0.0);
    for i in 0..model.len() {
        if model.body[i] == 1 {
            st.x[i] += shift;
        }
    }
    let nb = neighbours::find(&model, &st.x);
    let surface = kinematics::kinematics(&model, &st, &nb).surface;
    let bd = kinematics::boundary(&model, &st.x, &nb, surface);
    let c = contact::penalty(&model, &st, &nb, &bd);
    assert!(c.entry.iter().any(|e| e.1 > 0.0), "some spring yields");
    check_state(model, st, true);
}

#[test]
fn stages_match_cpu_bars_steel_aluminium() {
    check_stages("scenes/paper/bars_steel_aluminium.toml", 0.5e-6);
}

#[test]
fn stages_match_cpu_kernel_mode() {
    check_stages("scenes/paper/disks_square_kernel.toml", 2e-6);
}

/// Dispatches wrap into a second dimension past the adapter's workgroup
/// limit: with the limit forced down to 3, every kernel runs as a 2-D grid
/// and the step is bitwise the same as with 1-D dispatches.
#[test]
fn wrapped_dispatches_give_the_same_step() {
    let Some(ctx) = gpu() else { return };
    let (mut model, st) = state_during_contact("scenes/paper/disks_polar.toml", 1e-6);
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        model.integrator = integrator;
        let run = |opts: sphcontact::gpu::GpuOptions| {
            let mut g = GpuSolver::with_options(ctx.clone(), model.clone(), &st, &[], 1.0, opts)
                .expect("fits the adapter");
            let b = g.run_batch(20);
            assert!(b.failure.is_none());
            g.download()
        };
        let plain = run(Default::default());
        let wrapped = run(sphcontact::gpu::GpuOptions {
            max_workgroups_per_dimension: Some(3),
            ..Default::default()
        });
        assert_eq!(plain.step, 20);
        assert!(
            plain == wrapped,
            "{integrator}: wrapped dispatches changed the state"
        );
    }
}

/// Profiling real steps with timestamp queries changes nothing in them
/// (bitwise the same state and observations), and its profile accounts for
/// every dispatch of the step once a step and for the periodic reorder.
/// Adapters without timestamp queries inside passes say so instead.
#[test]
fn a_profiled_batch_is_the_same_run() {
    let Some(ctx) = gpu() else { return };
    let (mut model, st) = state_during_contact("scenes/paper/disks_polar.toml", 1e-6);
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        model.integrator = integrator;
        let new = || GpuSolver::new(ctx.clone(), model.clone(), &st, &[], 1.0).expect("fits");
        let mut plain = new();
        let b = plain.run_batch(32);
        assert!(b.failure.is_none() && b.states.len() == 32);
        let mut timed = new();
        let (tb, profile) = match timed.run_batch_profiled(32) {
            Ok(x) => x,
            Err(e) => {
                assert!(!ctx.timestamps, "{e}");
                println!("no profile on this adapter: {e}");
                return;
            }
        };
        assert_eq!(profile.steps, 32, "{integrator:?}");
        assert_eq!(tb.states, b.states, "{integrator:?}: observations");
        assert!(
            timed.download() == plain.download(),
            "{integrator:?}: state"
        );
        let work = timed.step_work();
        let per_step: f64 = profile
            .dispatches
            .iter()
            .filter(|d| d.stage != "reorder")
            .map(|d| d.calls_per_step)
            .sum();
        assert_eq!(per_step, work.dispatches as f64, "{integrator:?}");
        let reorder = profile.dispatches.iter().find(|d| d.stage == "reorder");
        assert_eq!(reorder.map(|d| d.calls_per_step), Some(2.0 / 32.0));
        assert!(profile.seconds_per_step > 0.0);
    }
}

/// The contact keeps what boundary particles carry between its passes on a
/// list of them that the kinematics pass makes; a list too short for the
/// boundary (16 places for the disks' hundreds of boundary particles) is
/// lengthened before the first step, and one that fills past three
/// quarters during the run pauses the steps and is lengthened: either
/// way, bitwise the same steps as with a list long enough from the start,
/// with either integrator.
#[test]
fn a_contact_list_too_short_grows_and_gives_the_same_steps() {
    let Some(ctx) = gpu() else { return };
    let (mut model, st) = state_during_contact("scenes/paper/disks_polar.toml", 1e-6);
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        model.integrator = integrator;
        let run = |opts: sphcontact::gpu::GpuOptions, steps: u64| {
            let mut g = GpuSolver::with_options(ctx.clone(), model.clone(), &st, &[], 1.0, opts)
                .expect("fits the adapter");
            let mut states = Vec::new();
            let mut batches = 0;
            while (states.len() as u64) < steps {
                let b = g.run_batch((steps - states.len() as u64) as u32);
                assert!(b.failure.is_none(), "{:?}", b.failure);
                states.extend(b.states);
                batches += 1;
            }
            (g.download(), states, batches)
        };
        let walkers = GpuSolver::new(ctx.clone(), model.clone(), &st, &[], 1.0)
            .expect("fits the adapter")
            .step_work()
            .per_walk
            .iter()
            .find(|w| w.name == "contact_pass1")
            .expect("a contact walk")
            .walkers;
        assert!(walkers > 64, "{walkers} boundary particles");
        let (long, obs, batches) = run(Default::default(), 20);
        assert_eq!((long.step, batches), (20, 1));
        // Too short from the start: lengthened before the first step.
        let (short, short_obs, _) = run(
            sphcontact::gpu::GpuOptions {
                surf_capacity: Some(16),
                ..Default::default()
            },
            20,
        );
        assert!(
            long == short,
            "{integrator}: the lengthened list changed the state"
        );
        assert_eq!(obs, short_obs, "{integrator}: observations");
        // Long enough, but without a quarter to spare, and not checked
        // before the first step: the run pauses, lengthens the list and
        // goes on.
        let (grown, grown_obs, batches) = run(
            sphcontact::gpu::GpuOptions {
                surf_capacity: Some(walkers as u32 + walkers as u32 / 8),
                unchecked_list: true,
                ..Default::default()
            },
            20,
        );
        assert!(batches > 1, "{integrator}: the run paused");
        assert!(
            long == grown,
            "{integrator}: the list grown in a run changed the state"
        );
        assert_eq!(obs, grown_obs, "{integrator}: observations");
        println!("{integrator}: {batches} batches with a list grown during the run");
    }
}

/// A scene larger than the adapter's binding size is refused with a clear
/// error, before anything runs.
#[test]
fn too_large_for_the_adapter_is_a_clear_error() {
    let Some(ctx) = gpu() else { return };
    let (model, st) = state_during_contact("scenes/paper/disks_polar.toml", 0.0);
    let err = GpuSolver::with_options(
        ctx,
        model,
        &st,
        &[],
        1.0,
        sphcontact::gpu::GpuOptions {
            max_binding_size: Some(4096),
            ..Default::default()
        },
    )
    .err()
    .expect("refused");
    assert!(err.contains("does not fit this adapter"), "{err}");
    assert!(err.contains("4096"), "{err}");
}

/// Bodies far apart (half a metre, a thousand cells) cost no large grid: the
/// hashed cell list finds exactly the CPU's neighbours, and nothing touches.
#[test]
fn bodies_far_apart() {
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/paper/disks_polar.toml");
    if let sphcontact::scene::Shape::Disk { center, .. } = &mut scene.bodies[1].shape {
        center[0] += 0.5;
        center[1] -= 0.2;
    } else {
        panic!("the paper's disks are disks");
    }
    let (model, st) = Model::new(&scene);
    check_state(model, st, false);
}

/// The device memory of the benchmark's whole 2-D disk impact (contact and
/// the reconstructed viscosity on, every buffer a step uses) at four million
/// particles, with either integrator: at most 200 bytes a particle
/// (docs/performance.md lists the buffers). Built, not stepped.
#[test]
fn device_memory_per_particle_at_four_million() {
    let Some(ctx) = gpu() else { return };
    // The benchmark's nearest case to 4e6 holds 3,999,968: ask for the
    // first one at or above it.
    let want = (4_000_000..)
        .step_by(10_000)
        .find(|&k| sphcontact::bench::lattice_radius(k).1 >= 4_000_000)
        .expect("a case");
    let case = sphcontact::bench::DiskCase::new(want).expect("the benchmark case");
    let n = case.particles();
    assert!(n >= 4_000_000, "{n} particles");
    assert!(case.model.contact && case.model.av_reconstruct);
    let mut model = case.model;
    let solver = GpuSolver::new(ctx.clone(), model.clone(), &case.state, &case.probes, 1e-5)
        .expect("four million particles fit the adapter");
    let per = solver.device_bytes() as f64 / n as f64;
    println!("{n} particles: {per:.2} device bytes a particle");
    assert!(per <= 200.0, "{per:.2} device bytes a particle");
    drop(solver);
    model.integrator = Integrator::Leapfrog;
    let solver = GpuSolver::new(ctx, model, &case.state, &case.probes, 1e-5)
        .expect("four million particles fit the adapter");
    let per = solver.device_bytes() as f64 / n as f64;
    println!("{n} particles, leapfrog: {per:.2} device bytes a particle");
    assert!(per <= 200.0, "{per:.2} device bytes a particle");
}

/// The work of a GPU step on the benchmark's disks (the square lattice,
/// about 2e4 particles), counted on the host from the device's cell list
/// (`GpuSolver::step_work`): the count is checked against the device's own
/// walk (the candidates the test kernel visits, summed), and held to the
/// budget of the row stencil: at most 40 candidates a particle for the
/// ~20 neighbours each has, every neighbour among them. The leapfrog's
/// step: at most 3 neighbour walks besides the contact's gathers and 16
/// dispatches (the periodic reorder aside); the midpoint rule's: two
/// pass-A and two pass-C walks, 25 dispatches.
#[test]
fn step_work_on_the_bench_lattice() {
    let Some(ctx) = gpu() else { return };
    let case = sphcontact::bench::DiskCase::new(20_000).expect("the benchmark case");
    let n = case.particles();
    let mut g = GpuSolver::new(ctx, case.model.clone(), &case.state, &case.probes, 1.0)
        .expect("fits the adapter");
    let out = g.stage_outputs();
    let work = g.step_work();
    println!("{work:#?}");

    let visits: u64 = out.visits.iter().map(|&v| v as u64).sum();
    let walk = |name: &str| {
        work.per_walk
            .iter()
            .find(|w| w.name == name)
            .unwrap_or_else(|| panic!("a {name} walk"))
    };
    let a = walk("kinematics");
    assert_eq!(a.walkers, n);
    assert_eq!(
        (a.candidates * n as f64).round() as u64,
        visits,
        "the host's count of the walk against the device's own"
    );
    let neighbours: usize = out.neighbours.iter().map(Vec::len).sum();
    let mean_nb = neighbours as f64 / n as f64;
    assert!(
        (18.0..22.0).contains(&mean_nb),
        "the lattice's {mean_nb:.2} neighbours a particle"
    );
    assert!(
        a.candidates >= mean_nb + 1.0 && a.candidates <= 40.0,
        "{:.2} candidates a particle for {mean_nb:.2} neighbours",
        a.candidates
    );
    // A group runs its rows as long as its longest lane: more trips than
    // the mean candidates, but within 1.5 of them on a reordered lattice.
    assert!(
        a.group_trips >= a.candidates && a.group_trips <= 1.5 * a.candidates,
        "{:.2} trips of a group for {:.2} candidates",
        a.group_trips,
        a.candidates
    );
    assert_eq!((a.per_step, walk("forces").per_step), (2, 2));
    assert_eq!(work.walks, 4, "neighbour walks a step");
    assert_eq!(work.contact_walks, 4, "contact gathers a step");
    let c = walk("contact_pass1");
    assert!(
        c.walkers > 0 && c.walkers < n / 10,
        "{} boundary walkers",
        c.walkers
    );
    assert!(
        work.dispatches <= 25,
        "{} dispatches a step",
        work.dispatches
    );
    assert!(work.device_bytes_per_particle <= 205.0);

    let mut model = case.model.clone();
    model.integrator = Integrator::Leapfrog;
    let ctx = gpu().expect("an adapter, as above");
    let mut g = GpuSolver::new(ctx, model, &case.state, &case.probes, 1.0).expect("fits");
    let leap = g.step_work();
    println!("{leap:#?}");
    assert!(leap.walks <= 3, "{} neighbour walks a step", leap.walks);
    assert!(
        leap.dispatches <= 16,
        "{} dispatches a step",
        leap.dispatches
    );
    // The force passes' two gathers and the booking's first: without a
    // rigid body the booking's second has no heat to hand over.
    assert_eq!(leap.contact_walks, 3, "contact gathers a step");
    let lw = |name: &str| {
        leap.per_walk
            .iter()
            .find(|w| w.name == name)
            .unwrap_or_else(|| panic!("a leapfrog {name} walk"))
    };
    // The leapfrog's contact walks its list of the boundary particles: a
    // group is 32 of them, where the midpoint rule's groups are the 32
    // slots around each.
    let (mc, lc) = (walk("contact_pass1"), lw("contact_pass1"));
    assert_eq!(lc.walkers, mc.walkers, "the same boundary particles");
    assert!(
        lc.lane_use >= 0.4 && lc.lane_use >= 3.0 * mc.lane_use,
        "lanes used: {:.2} listed, {:.2} in place",
        lc.lane_use,
        mc.lane_use
    );
    let ka = lw("kinematics_leap");
    assert_eq!(ka.candidates, a.candidates, "the same cell list");
    // The momentum and energy walks visit the pairs of the kinematic
    // walk's masks: every neighbour of the particle's own body (contact
    // takes the others), and nothing else.
    let body = &case.model.body;
    let own_body: usize = out
        .neighbours
        .iter()
        .enumerate()
        .map(|(i, nb)| nb.iter().filter(|&&j| body[j as usize] == body[i]).count())
        .sum();
    let c = lw("forces");
    assert_eq!(c.per_step, 2);
    assert_eq!(
        (c.candidates * n as f64).round() as usize,
        own_body,
        "the masks hold every pair of one body"
    );
    assert!(
        c.group_trips <= 0.8 * ka.group_trips,
        "{:.2} trips of a masked group against {:.2} of the full walk",
        c.group_trips,
        ka.group_trips
    );
    for w in leap.per_walk.iter().filter(|w| w.walkers == n) {
        assert!(
            w.candidates <= 40.0,
            "{}: {:.2} candidates",
            w.name,
            w.candidates
        );
    }
}

/// One per-particle quantity of a state.
type Field = dyn Fn(&State, usize) -> f64;

/// Two leapfrog steps from one state in mid-contact, device against the CPU
/// twin, particle by particle: what each step changed. The first step
/// starts from the first evaluation's rates, the second from the rates the
/// first step carried (the predicted velocity and energy, the extrapolated
/// velocity gradient, the contact booked at v_{n+1}). As in the stage test,
/// the velocity change is compared on the scale of its parts: at a contact
/// face the SPH and contact accelerations nearly cancel, so each particle's
/// change is only as exact as the contact part, dt max |F_c / m|; the rest
/// on the scale of their largest change.
#[test]
fn leapfrog_steps_match_cpu() {
    let Some(ctx) = gpu() else { return };
    let (mut model, st) = state_during_contact("scenes/paper/disks_polar.toml", 3e-6);
    model.integrator = Integrator::Leapfrog;
    let mut cpu = CpuSolver::new(model.clone(), st.clone());
    let mut g = GpuSolver::new(ctx, model.clone(), &st, &[], 1.0).expect("fits the adapter");
    let nb = neighbours::find(&model, &st.x);
    let k = kinematics::kinematics(&model, &st, &nb);
    let bd = kinematics::boundary(&model, &st.x, &nb, k.surface.clone());
    let cf = contact::penalty(&model, &st, &nb, &bd);
    let a_contact = bd
        .list
        .iter()
        .zip(&cf.force)
        .map(|(&i, f)| f.length() / model.mass[i as usize])
        .fold(0.0, f64::max);
    let mut before = st.clone();
    for step in 1..=2 {
        cpu.step(1.0).expect("a stable CPU step");
        let b = g.run_batch(1);
        assert!(b.failure.is_none());
        let gs = g.download();
        let c = &cpu.state;
        // The device counts time from its own start.
        let tc = c.t - st.t;
        assert!(
            (gs.t / tc - 1.0).abs() < 1e-6,
            "step {step}: t {} vs {tc}",
            gs.t
        );
        let n = model.len();
        let change = |f: &Field| -> (Vec<f64>, Vec<f64>) {
            (
                (0..n).map(|i| f(&gs, i) - f(&before, i)).collect(),
                (0..n).map(|i| f(c, i) - f(&before, i)).collect(),
            )
        };
        let none = |_: usize| false;
        let dt = c.t - before.t;
        let velocities: [(&str, &Field); 2] = [("vx", &|s, i| s.v[i].x), ("vy", &|s, i| s.v[i].y)];
        for (name, f) in velocities {
            let (dg, dc) = change(f);
            let what = format!("step {step}: change of {name}");
            assert_scaled(&what, &dg, &dc, 1e-4, dt * a_contact, &none);
        }
        let fields: [(&str, &Field); 6] = [
            ("x", &|s, i| s.x[i].x),
            ("rho", &|s, i| s.rho[i]),
            ("e", &|s, i| s.e[i]),
            ("sxx", &|s, i| s.s[i].xx),
            ("syy", &|s, i| s.s[i].yy),
            ("sxy", &|s, i| s.s[i].xy),
        ];
        for (name, f) in fields {
            let (dg, dc) = change(f);
            assert_field(
                &format!("step {step}: change of {name}"),
                &dg,
                &dc,
                1e-3,
                &none,
            );
        }
        before = c.clone();
    }
}

/// A tungsten-alloy rod 5 µs into a 4340 plate at 1,200 m/s (the
/// penetration scene at a spacing of 0.2 mm): both bodies in plastic flow
/// with Johnson–Cook strength and heating, the plate's damage growing and
/// some of its particles failed. The kinematics, forces and contact passes
/// against their twins there (a failed particle's pressure, sound speed and
/// absence from the artificial stress included), then the strength update
/// of the midpoint rule's half step (strength.wgsl in `advance_half`)
/// against physics::strength::update from the CPU's rates: the stress,
/// the density (a failed particle's floor), and the increments of the
/// plastic strain, temperature and damage, each within 1e-4 of its
/// field's largest (f32 against f64; an increment is a small difference
/// of f32 values: measured 1.4e-5 at worst).
#[test]
fn stages_match_cpu_penetration() {
    use sphcontact::physics::strength;
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/penetration/tungsten_rod_steel_plate.toml");
    for b in &mut scene.bodies {
        b.spacing = 2.0e-4;
    }
    let (model, st) = Model::new(&scene);
    let mut cpu = CpuSolver::new(model, st);
    while cpu.state.t < 5e-6 {
        cpu.step(5e-6 - cpu.state.t).expect("a stable CPU run");
    }
    let (model, st) = (cpu.model.clone(), cpu.state.clone());
    let failed = st.damage.iter().filter(|&&d| strength::failed(d)).count();
    let yielded = st.eps_p.iter().filter(|&&e| e > 0.0).count();
    println!("{failed} failed, {yielded} yielded of {}", model.len());
    assert!(
        failed > 20 && yielded > 200,
        "a state in plastic flow with failures"
    );
    check_state(model.clone(), st.clone(), true);

    let Some(ctx) = gpu() else { return };
    let mut g = GpuSolver::new(ctx, model.clone(), &st, &[], 1.0).expect("fits the adapter");
    let out = g.stage_outputs();
    let (rates, _) = cpu::evaluate(&model, &st);
    let k = 0.5 * out.dt;
    let n = model.len();
    let (mut s, mut rho) = (vec![Sym::default(); n], vec![0.0; n]);
    let mut hist = vec![
        strength::History {
            eps_p: 0.0,
            temperature: 0.0,
            damage: 0.0
        };
        n
    ];
    let mut near_failure = vec![false; n];
    for i in 0..n {
        hist[i] = st.history(i);
        (s[i], rho[i]) = (st.s[i], st.rho[i]);
        if model.rigid(i) {
            continue;
        }
        let mat = model.material(i);
        let trial = st.s[i].add_scaled(&rates.ds[i], k);
        let r = st.rho[i] + rates.drho[i] * k;
        let e = st.e[i] + rates.de[i] * k;
        let (sn, h) =
            strength::update(mat, trial, rates.rate[i], r, || mat.pressure(r, e), hist[i]);
        // Within f32 of failing: either side may call it.
        near_failure[i] = !strength::failed(st.damage[i])
            && (h.damage > 0.998 || (mat.pressure(r, e) + mat.spall).abs() < 1e-3 * mat.spall);
        s[i] = sn;
        rho[i] = if strength::failed(h.damage) {
            r.max(mat.failed_density_floor(e))
        } else {
            r
        };
        hist[i] = h;
    }
    let skip = |i: usize| near_failure[i];
    let mismatched: Vec<usize> = (0..n)
        .filter(|&i| strength::failed(hist[i].damage) != (out.mid_hist[i][2] >= 1.0))
        .collect();
    assert!(
        mismatched.iter().all(|&i| near_failure[i]),
        "failed on one side only: {:?}",
        mismatched
            .iter()
            .filter(|&&i| !near_failure[i])
            .collect::<Vec<_>>()
    );
    let newly = (0..n)
        .filter(|&i| strength::failed(hist[i].damage) && !strength::failed(st.damage[i]))
        .count();
    println!("{newly} fail in the half step");
    for (k, name) in ["s.xx", "s.yy", "s.xy", "s.zz"].iter().enumerate() {
        let c: Vec<f64> = s.iter().map(|s| [s.xx, s.yy, s.xy, s.zz][k]).collect();
        let gg: Vec<f64> = out
            .mid_s
            .iter()
            .map(|s| [s.xx, s.yy, s.xy, s.zz][k])
            .collect();
        assert_field(name, &gg, &c, 1e-4, &skip);
    }
    assert_field("ρ", &out.mid_rho, &rho, 1e-5, &skip);
    let increments = |f: &dyn Fn(&strength::History) -> f64, col: usize| {
        let c: Vec<f64> = (0..n).map(|i| f(&hist[i]) - f(&st.history(i))).collect();
        let gg: Vec<f64> = (0..n)
            .map(|i| out.mid_hist[i][col] - f(&st.history(i)))
            .collect();
        (gg, c)
    };
    for (col, name, f) in [
        (
            0,
            "Δε_p",
            &(|h: &strength::History| h.eps_p) as &dyn Fn(&strength::History) -> f64,
        ),
        (1, "ΔT", &|h: &strength::History| h.temperature),
        (2, "ΔD", &|h: &strength::History| h.damage),
    ] {
        let (gg, c) = increments(f, col);
        let max = c.iter().map(|x| x.abs()).fold(0.0, f64::max);
        println!("{name}: largest {max:.3e}");
        assert!(max > 0.0, "{name} grows");
        assert_field(name, &gg, &c, 1e-4, &skip);
    }
}
