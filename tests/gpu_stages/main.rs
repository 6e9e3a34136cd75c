//! The device against its CPU twins, stage by stage, on identical inputs:
//! a state taken from a CPU run in the middle of a contact (so boundaries,
//! contact forces and stresses are all live). Neighbour sets must agree
//! exactly; floats within 1e-4 of the field's largest magnitude (f32 on the
//! device, f64 on the CPU). No GPU needed for the shader checks.

#[path = "../common/mod.rs"]
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
    for stage in shaders::modules() {
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
    state_of(&load(path), t)
}

/// Every particle's velocity stirred by 5 % of its speed (at least
/// 0.05 m/s) in a direction of its own: a field whose non-affine part,
/// which the hourglass control acts on, is a large part of the forces.
fn stir(st: &mut State) {
    for (i, v) in st.v.iter_mut().enumerate() {
        let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
        *v += DVec2::new(a.cos(), a.sin()) * 0.05 * v.length().max(1.0);
    }
}

/// A state of `scene` at time `t` of a CPU run.
fn state_of(scene: &sphcontact::Scene, t: f64) -> (Model, State) {
    let (model, state) = Model::new(scene);
    let mut cpu = CpuSolver::new(model, state);
    while cpu.state.t < t {
        cpu.step(t - cpu.state.t).expect("a stable CPU run");
    }
    (cpu.model.clone(), cpu.state.clone())
}

/// The disk of scenes/friction/disk_wall_oblique.toml striking its wall
/// at 5 m/s, `degrees` from the wall's normal with friction `mu`, 3 µs
/// into the contact on the CPU path.
fn oblique_disk_at_3_us(mu: f64, degrees: f64) -> (Model, State) {
    state_of(&oblique_disk(mu, degrees).0, 3e-6)
}

fn check_stages(path: &str, t: f64) {
    if gpu().is_none() {
        return;
    }
    let (model, st) = state_during_contact(path, t);
    check_state(model, st, true);
}

/// The stage tests read one evaluation, the midpoint rule's
/// ([`GpuSolver::stage_outputs`]); the leapfrog's steps are held in
/// `steps.rs`.
fn midpoint(mut model: Model) -> Model {
    model.integrator = Integrator::Midpoint;
    model
}

fn check_state(model: Model, st: State, expect_contact: bool) {
    let model = midpoint(model);
    let Some(ctx) = gpu() else { return };
    let n = model.len();
    let mut g = GpuSolver::new(ctx, model.clone(), &st, &[], 1.0).expect("fits the adapter");
    let out = g.stage_outputs();

    // Cell list: the same neighbour set for every particle. A pair may only
    // differ if it sits at the cut-off 2 h_ij to f32 precision. (The
    // device's set is the round supports' whatever the scene's.)
    let nb = neighbours::find(&model, st.frame());
    let round = sphcontact::model::Frame::round(&st.x);
    let mut pairs = 0;
    for i in 0..n {
        let mut cpu_set: Vec<u32> = nb.of(&model, round, i).map(|b| b.j).collect();
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
    let bd = forces::boundary_of(&model, &st.x, &nb, &a);
    for i in 0..n {
        if bd.is_boundary[i] != out.boundary[i] {
            let x = kinematics::surface_measure(&model, i, a.grad_psi[i], a.psi.get(i).copied());
            assert!(
                (x / model.boundary_threshold - 1.0).abs() < 1e-4,
                "{}: particle {i}: boundary cpu {} gpu {} (measure {x})",
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

    let pts = cpu::eos_and_stress_with(&model, &st, &a.fallback);
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
    // Who takes only the artificial stress's heat (a body that can
    // yield, or a particle that flows): the same particles, but for one
    // whose von Mises stress sits at the threshold to f32 precision.
    let keyed = model.art_keyed_on_flow();
    for i in 0..n {
        let cpu_flows = keyed && model.art_heats(&st, i);
        if cpu_flows != out.flows[i] {
            let y0 = model.material(i).y0;
            let at_threshold = !model.history
                && (st.s[i].von_mises() / y0 - (1.0 - sphcontact::model::YIELD_TOL)).abs() < 1e-6;
            assert!(
                at_threshold,
                "{}: particle {i}: cpu {cpu_flows} gpu {}",
                at(Stage::Kinematics, "flows plastically"),
                out.flows[i]
            );
        }
    }

    // The device's density rate is of ρ itself; a body of revolution's
    // CPU state keeps η = 2π r ρ: dρ/dt = (dη/dt)/2πr − ρ v_r/r.
    let drho: Vec<f64> = if model.axisymmetric {
        (0..n)
            .map(|i| {
                let (r, vr) = (st.x[i].x, st.v[i].x);
                let ring = 2.0 * std::f64::consts::PI * r;
                let rate = a.drho[i] / ring;
                if model.rigid(i) {
                    rate
                } else {
                    rate - st.rho[i] / ring * vr / r
                }
            })
            .collect()
    } else {
        a.drho.clone()
    };
    assert_field(
        &at(Stage::Kinematics, "dρ/dt"),
        &out.drho,
        &drho,
        1e-4,
        &none,
    );
    for (k, name) in ["ds.xx", "ds.yy", "ds.xy", "ds.zz"].iter().enumerate() {
        let c: Vec<f64> = a.ds.iter().map(|s| [s.xx, s.yy, s.xy, s.zz][k]).collect();
        let gg: Vec<f64> = out.ds.iter().map(|s| [s.xx, s.yy, s.xy, s.zz][k]).collect();
        assert_field(&at(Stage::Kinematics, name), &gg, &c, 1e-4, &none);
    }

    // The forces pass: momentum and energy before contact. Held tighter
    // than the other fields, so that an error of 1e-4 in the pass fails:
    // measured at most 1.7e-5 (dv/dt) and 2.1e-6 (de/dt) of the largest
    // value over every parity case on lavapipe.
    let (dv, de) = forces::momentum_energy(&model, &st, &nb, &a, &pts);
    let xs = |v: &[DVec2]| v.iter().map(|p| p.x).collect::<Vec<_>>();
    let ys = |v: &[DVec2]| v.iter().map(|p| p.y).collect::<Vec<_>>();
    assert_field(
        &at(Stage::Forces, "dv/dt.x"),
        &xs(&out.dv_sph),
        &xs(&dv),
        5e-5,
        &none,
    );
    assert_field(
        &at(Stage::Forces, "dv/dt.y"),
        &ys(&out.dv_sph),
        &ys(&dv),
        5e-5,
        &none,
    );
    assert_field(&at(Stage::Forces, "de/dt"), &out.de_sph, &de, 2e-5, &none);

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

mod batches;
mod eos;
mod laws;
mod parity;
mod steps;
mod work;
