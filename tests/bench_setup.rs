//! What the throughput figures rest on: the disk case has the particle
//! count it claims, the timed steps are steps in contact, and timing a GPU
//! stage alone leaves the solver's state as it was.

mod common;
use common::*;

use sphcontact::bench::{lattice_radius, CpuBench, DiskCase};
use sphcontact::gpu::GpuSolver;

/// The count `lattice_radius` predicts is the count placed, and it is the
/// achievable count nearest the request (within 5 % from 1,000 up).
#[test]
fn disk_case_has_the_predicted_count() {
    for n in [100, 257, 1_000, 4_000, 10_000, 33_333] {
        let case = DiskCase::new(n).expect("a valid size");
        let (r, predicted) = lattice_radius(n);
        assert_eq!(case.particles(), predicted, "n = {n}, R/Δx = {r}");
        assert_eq!(case.r_over_dx, r);
        if n >= 1_000 {
            assert!(
                (predicted as f64 / n as f64 - 1.0).abs() < 0.05,
                "n = {n}: {predicted}"
            );
        }
        // No slightly smaller or larger radius lands nearer the request.
        for f in [0.98, 0.99, 1.01, 1.02] {
            let scene = sphcontact::validation::disk_scene("square", r * f);
            let (m, _) = sphcontact::model::Model::new(&scene);
            assert!(
                m.len().abs_diff(n) >= predicted.abs_diff(n),
                "n = {n}: R/Δx = {} gives {} particles, nearer than {predicted}",
                r * f,
                m.len()
            );
        }
    }
    assert!(DiskCase::new(99).is_err());
    assert!(DiskCase::new(0).is_err());
}

/// The square-lattice disks start a lattice sagitta apart: no contact
/// force at t = 0 at 10,000 particles, so the bench must step into contact
/// before timing (it does, and stays there).
#[test]
fn cpu_bench_times_steps_in_contact() {
    let case = DiskCase::new(10_000).unwrap();
    let mut solver = sphcontact::cpu::CpuSolver::new(case.model.clone(), case.state.clone());
    let f0 = solver.diagnostics().contact.pair(0, 1).0;
    assert_eq!(
        f0, 0.0,
        "the lattice disks start apart by the facet sagitta"
    );
    let mut b = CpuBench::new(&case).unwrap();
    assert!(b.onset > 0, "some steps of approach");
    assert!(b.in_contact());
    for _ in 0..5 {
        b.time_steps(4).unwrap();
        assert!(b.in_contact(), "in contact after the timed steps");
    }
}

/// Every stage timed alone, then stepping on: the same states as a solver
/// that was never timed, to the bit (the device run is deterministic). The
/// reordering permutes the particles, which changes the order of the sums
/// in the steps after it; timed just before a step that reorders anyway,
/// it must leave that step's permutation, and so every bit, unchanged.
/// With round supports and with supports that adapt (whose advance also
/// carries the ellipses).
#[test]
fn time_stage_leaves_the_state_as_it_was() {
    for support in [
        sphcontact::scene::Support::Fixed,
        sphcontact::scene::Support::Adaptive,
    ] {
        time_stage_leaves_the_state_with(support);
    }
}

fn time_stage_leaves_the_state_with(support: sphcontact::scene::Support) {
    let Some(ctx) = gpu() else {
        return;
    };
    let case = DiskCase::new(1_000).unwrap().with_support(support);
    let make = || {
        GpuSolver::new(
            ctx.clone(),
            case.model.clone(),
            &case.state,
            &case.probes,
            1.0,
        )
        .expect("the case fits")
    };
    let (mut timed, mut plain) = (make(), make());
    let names = timed.stage_names();
    assert!(names.contains(&"contact") && names.contains(&"advance"));
    assert!(timed.time_stage("no_such_stage", 1).is_err());
    assert!(timed.time_stage("kinematics", 0).is_err());
    // Steps 0..40, then the stages other than the reordering at step 40
    // (not a reordering step: a multiple of 16 is).
    assert_eq!(timed.run_batch(40).states, plain.run_batch(40).states);
    for name in names.iter().filter(|&&n| n != "reorder") {
        let t = timed.time_stage(name, 3).expect("a known stage");
        assert!(t.as_nanos() > 0, "{name}");
    }
    assert_eq!(
        timed.run_batch(40).states,
        plain.run_batch(40).states,
        "the observations after timing"
    );
    // Step 80 reorders anyway.
    timed.time_stage("reorder", 3).expect("a known stage");
    assert_eq!(
        timed.run_batch(40).states,
        plain.run_batch(40).states,
        "the observations after timing the reordering"
    );
    let (sa, ca) = timed.download_with_control();
    let (sb, cb) = plain.download_with_control();
    assert_eq!(sa, sb, "the state after timing");
    assert_eq!(
        bytemuck::bytes_of(&ca),
        bytemuck::bytes_of(&cb),
        "the control block after timing"
    );
}

/// The size check the benches skip sizes with: a size it accepts builds,
/// and the first size whose widest per-particle array is over the adapter's
/// binding limit is refused (the solver's own refusal of such a size is
/// `too_large_for_the_adapter_is_a_clear_error` in tests/gpu_stages/).
#[test]
fn fits_agrees_with_the_solver() {
    let Some(ctx) = gpu() else { return };
    let case = DiskCase::new(1_000).expect("a valid size");
    assert!(sphcontact::gpu::fits(&ctx, case.particles()));
    assert!(GpuSolver::new(ctx.clone(), case.model.clone(), &case.state, &[], 1e-6).is_ok());
    let too_many = (ctx.limits.max_storage_buffer_binding_size / 16 + 1) as usize;
    assert!(!sphcontact::gpu::fits(&ctx, too_many));
}
