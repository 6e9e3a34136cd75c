//! Device memory and the work of a step.

use super::*;

/// The device memory of the benchmark's whole 2-D disk impact (contact and
/// the reconstructed viscosity on, every buffer a step uses) at four million
/// particles, with round supports (`support = "fixed"`) and either
/// integrator: at most 200 bytes a particle (docs/performance.md lists the
/// buffers); with the default supports (carried ellipses) at most 220 in
/// either. Built, not stepped.
#[test]
fn device_memory_per_particle_at_four_million() {
    let Some(ctx) = gpu() else { return };
    // The benchmark's nearest case to 4e6 holds 3,999,968: ask for the
    // first one at or above it.
    let want = (4_000_000..)
        .step_by(10_000)
        .find(|&k| sphcontact::bench::lattice_radius(k).1 >= 4_000_000)
        .expect("a case");
    let adaptive = sphcontact::bench::DiskCase::new(want).expect("the benchmark case");
    let case = adaptive
        .clone()
        .with_support(sphcontact::scene::Support::Fixed);
    let n = case.particles();
    assert!(n >= 4_000_000, "{n} particles");
    assert!(case.model.contact && case.model.av_reconstruct);
    let mut model = midpoint(case.model.clone());
    let solver = GpuSolver::new(ctx.clone(), model.clone(), &case.state, &case.probes, 1e-5)
        .expect("four million particles fit the adapter");
    let per = solver.device_bytes() as f64 / n as f64;
    println!("{n} particles: {per:.2} device bytes a particle");
    assert!(per <= 200.0, "{per:.2} device bytes a particle");
    drop(solver);
    model.integrator = Integrator::Leapfrog;
    let solver = GpuSolver::new(ctx.clone(), model, &case.state, &case.probes, 1e-5)
        .expect("four million particles fit the adapter");
    let per = solver.device_bytes() as f64 / n as f64;
    println!("{n} particles, leapfrog: {per:.2} device bytes a particle");
    assert!(per <= 200.0, "{per:.2} device bytes a particle");
    drop(solver);
    // Supports that follow the deformation carry a metric a particle; in
    // the midpoint rule they are carried with the viscosity's gradient, in
    // the leapfrog with a copy of the step's in f16: at most 220 bytes a
    // particle either way.
    let case = adaptive;
    let mut model = midpoint(case.model.clone());
    assert!(model.adaptive && model.kept_gradient_is_the_steps());
    let solver = GpuSolver::new(ctx.clone(), model.clone(), &case.state, &case.probes, 1e-5)
        .expect("four million particles fit the adapter");
    let per = solver.device_bytes() as f64 / n as f64;
    println!("{n} particles, adaptive supports: {per:.2} device bytes a particle");
    assert!(per <= 220.0, "{per:.2} device bytes a particle");
    drop(solver);
    model.integrator = Integrator::Leapfrog;
    assert!(!model.kept_gradient_is_the_steps());
    let solver = GpuSolver::new(ctx, model, &case.state, &case.probes, 1e-5)
        .expect("four million particles fit the adapter");
    let per = solver.device_bytes() as f64 / n as f64;
    println!("{n} particles, leapfrog, adaptive supports: {per:.2} device bytes a particle");
    assert!(per <= 220.0, "{per:.2} device bytes a particle");
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
    let mut g = GpuSolver::new(
        ctx,
        midpoint(case.model.clone()),
        &case.state,
        &case.probes,
        1.0,
    )
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
    // The carried ellipses of the default supports among them (16 bytes
    // on round supports' 205): 221.74 measured at this size.
    assert!(work.device_bytes_per_particle <= 222.0);

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

/// Constraints cost only the scenes that hold a region: on the benchmark's
/// disks (about 2e4 particles) a clamp over part of one disk adds 20 bytes
/// a particle (each particle's region and its impulse) and, in the
/// midpoint rule with contact, one dispatch a step (the base evaluation's
/// spread as a pass of its own, before the reductions read the region's
/// force); the leapfrog's step keeps its dispatches.
#[test]
fn constraints_cost_only_where_held() {
    let Some(ctx) = gpu() else { return };
    let case = sphcontact::bench::DiskCase::new(20_000).expect("the benchmark case");
    let n = case.particles();
    let clamped = |mut model: Model, state: &mut State| {
        let particles: Vec<usize> = model.bodies[0].range.clone().take(40).collect();
        model.held_of = vec![0; n];
        for &i in &particles {
            model.held_of[i] = 1;
            state.v[i] = DVec2::ZERO;
        }
        model.held.push(sphcontact::model::Held {
            name: "clamp".into(),
            mask: DVec2::ONE,
            velocity: DVec2::ZERO,
            particles,
        });
        state.held_impulse = vec![DVec2::ZERO];
        model
    };
    for integrator in [Integrator::Midpoint, Integrator::Leapfrog] {
        let mut model = case.model.clone();
        model.integrator = integrator;
        let free = GpuSolver::new(ctx.clone(), model.clone(), &case.state, &case.probes, 1.0)
            .expect("fits")
            .step_work();
        let mut state = case.state.clone();
        let model = clamped(model, &mut state);
        let held = GpuSolver::new(ctx.clone(), model, &state, &case.probes, 1.0)
            .expect("fits")
            .step_work();
        let extra = held.device_bytes_per_particle - free.device_bytes_per_particle;
        println!(
            "{integrator:?}: {} then {} dispatches, {extra:.4} bytes a particle more",
            free.dispatches, held.dispatches
        );
        assert!((extra - 20.0).abs() < 0.01, "{extra} bytes a particle");
        let spread = (integrator == Integrator::Midpoint) as u32;
        assert_eq!(held.dispatches, free.dispatches + spread, "{integrator:?}");
        assert_eq!(held.walks, free.walks, "{integrator:?}");
    }
}

/// Coulomb friction costs only where a scene rubs: on the paper's disks
/// (about 2e4 particles) with μ = 0.1, 48 bytes a particle (its slip, its
/// friction in an evaluation and what its rub hands on, by original index)
/// and two 16-byte entries a place on the list of boundary particles
/// (under 2 bytes a particle here); the midpoint rule's evaluations each add two contact
/// walks (the rub pass and its gather), the leapfrog's step those two and
/// its booking's rub pass; the other walks stay as they were.
#[test]
fn friction_costs_only_where_it_rubs() {
    let Some(ctx) = gpu() else { return };
    let case = sphcontact::bench::DiskCase::new(20_000).expect("the benchmark case");
    let n = case.particles();
    for (integrator, passes) in [(Integrator::Midpoint, 4), (Integrator::Leapfrog, 3)] {
        let mut model = case.model.clone();
        model.integrator = integrator;
        let free = GpuSolver::new(ctx.clone(), model.clone(), &case.state, &case.probes, 1.0)
            .expect("fits")
            .step_work();
        model.friction = sphcontact::model::Coulomb {
            sliding: 0.1,
            sticking: 0.1,
        };
        model.rubs = true;
        let mut state = case.state.clone();
        state.slip = vec![0.0; n];
        state.slip_stiffness = vec![0.0; n];
        state.sliding = vec![false; n];
        let rubbing = GpuSolver::new(ctx.clone(), model, &state, &case.probes, 1.0)
            .expect("fits")
            .step_work();
        let extra = rubbing.device_bytes_per_particle - free.device_bytes_per_particle;
        println!(
            "{integrator:?}: {} then {} dispatches, {extra:.4} bytes a particle more",
            free.dispatches, rubbing.dispatches
        );
        assert!(extra > 48.0 && extra < 50.0, "{extra} bytes a particle");
        assert_eq!(
            rubbing.dispatches,
            free.dispatches + passes,
            "{integrator:?}"
        );
        assert_eq!(
            rubbing.contact_walks,
            free.contact_walks + passes,
            "{integrator:?}"
        );
        assert_eq!(rubbing.walks, free.walks, "{integrator:?}");
    }
}
