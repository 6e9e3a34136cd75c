//! Dispatch sizes, profiled batches, the contact list grown, adapter limits.

use super::*;

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
    // A vec4 a particle: 4096 bytes hold 256 (and the bucket starts of
    // 256 buckets, 1028 bytes).
    assert!(err.contains("max_storage_buffer_binding_size"), "{err}");
    assert!(err.contains("at most 256 particles fit"), "{err}");
}

/// A scene larger than the device memory the solver may take is refused
/// before anything is allocated past it, with what it needs and how many
/// particles fit; at exactly what it needs it is built.
#[test]
fn past_the_memory_limit_is_a_clear_error() {
    let Some(ctx) = gpu() else { return };
    let (model, st) = state_during_contact("scenes/paper/disks_polar.toml", 0.0);
    let n = model.len();
    let build = |limit: Option<u64>| {
        GpuSolver::with_options(
            ctx.clone(),
            model.clone(),
            &st,
            &[],
            1.0,
            sphcontact::gpu::GpuOptions {
                max_device_bytes: limit,
                ..Default::default()
            },
        )
    };
    let need = build(None).expect("fits").device_bytes();
    build(Some(need)).expect("fits in exactly what it needs");
    let err = build(Some(need - 1)).err().expect("refused");
    println!("{err}");
    assert!(
        err.contains(&format!("its {n} particles need {need} bytes")),
        "{err}"
    );
    assert!(err.contains(&format!("allows {}", need - 1)), "{err}");
    assert!(
        err.contains(&format!("about {} particles fit", n - 1)),
        "{err}"
    );
    let err = build(Some(need / 2)).err().expect("refused");
    let fit = (need / 2) as f64 / (need as f64 / n as f64);
    assert!(
        err.contains(&format!("about {} particles fit", fit.floor())),
        "{err}"
    );
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
