//! Whole steps against the CPU: the leapfrog, the strength update.

use super::*;

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
    leapfrog_steps("scenes/paper/disks_polar.toml", 3e-6, 0.0);
}

/// [`leapfrog_steps_match_cpu`] with the hourglass control, which in a
/// leapfrog step sees v_{n+½} and its own gradient where the viscosity sees
/// the predicted velocity (docs/method.md, "Hourglass control"), on a
/// stirred field. (The Hertz spheres of revolution are no test of a step:
/// their position changes in a step, 3e-9 m, are at the f32 resolution of
/// their positions.)
#[test]
fn leapfrog_steps_match_cpu_with_hourglass_control() {
    leapfrog_steps("scenes/paper/disks_polar.toml", 3e-6, 1.0);
}

/// [`leapfrog_steps_match_cpu`] with the Riemann form of the viscosity
/// reconstructed at surfaces too, on a stirred field: in a leapfrog step
/// its sign guard reads the predicted velocities the momentum sees.
#[test]
fn leapfrog_steps_match_cpu_with_riemann_viscosity() {
    if gpu().is_none() {
        return;
    }
    let mut scene = load("scenes/paper/disks_polar.toml");
    let av = scene
        .artificial_viscosity
        .get_or_insert_with(Default::default);
    av.form = sphcontact::scene::ViscosityForm::Riemann;
    av.reconstruct_surfaces = true;
    let (model, mut st) = state_of(&scene, 3e-6);
    stir(&mut st);
    leapfrog_steps_from(model, st, 0.0);
}

/// [`leapfrog_steps_match_cpu`] with Coulomb friction (contact.wgsl, RUB):
/// the oblique disk of scenes/friction/disk_wall_oblique.toml 3 µs into its
/// contact, sliding (μ = 0.1 at 45°) and sticking (μ = 1 at 20°): the rub
/// passes at n+1 looking half a step ahead, the booking's rates at
/// v_{n+1}, and the slips moved and returned.
#[test]
fn leapfrog_steps_match_cpu_with_friction() {
    if gpu().is_none() {
        return;
    }
    for (mu, degrees) in [(0.1, 45.0), (1.0, 20.0)] {
        let (model, st) = oblique_disk_at_3_us(mu, degrees);
        leapfrog_steps_from(model, st, 0.0);
    }
}

/// The coarse penetration (Δx = 0.2 mm) 5 µs into the plate, both bodies
/// in plastic flow, on the leapfrog: its Mie–Grüneisen pressure reads the
/// predicted energy, so this holds the device's predicted energy (the
/// first kick's compatible term taken back, docs/method.md §9) to the
/// CPU's, which the disks' linear EOS cannot.
#[test]
fn leapfrog_steps_match_cpu_in_plastic_flow() {
    if gpu().is_none() {
        return;
    }
    let (model, st) = coarse_penetration_at_5_us();
    leapfrog_steps_from(model, st, 0.0);
}

/// The penetration scene at a spacing of 0.2 mm, 5 µs into the plate on
/// the CPU path.
fn coarse_penetration_at_5_us() -> (Model, State) {
    let mut scene = load("scenes/penetration/tungsten_rod_steel_plate.toml");
    for b in &mut scene.bodies {
        b.spacing = 2.0e-4;
    }
    // Round supports: the plastic update's parity is what is held here;
    // the supports that adapt on this shot, in `adaptive_parity`.
    scene.simulation.support = Some(sphcontact::scene::Support::Fixed);
    state_of(&scene, 5e-6)
}

fn leapfrog_steps(path: &str, t: f64, hourglass: f64) {
    if gpu().is_none() {
        return;
    }
    let (model, mut st) = state_during_contact(path, t);
    if hourglass > 0.0 {
        stir(&mut st);
    }
    leapfrog_steps_from(model, st, hourglass);
}

/// Two leapfrog steps from `st` (see [`leapfrog_steps_match_cpu`]) with
/// the hourglass control at `hourglass`.
fn leapfrog_steps_from(mut model: Model, st: State, hourglass: f64) {
    let Some(ctx) = gpu() else { return };
    model.integrator = Integrator::Leapfrog;
    model.set_hourglass(hourglass);
    let mut cpu = CpuSolver::new(model.clone(), st.clone());
    let mut g = GpuSolver::new(ctx, model.clone(), &st, &[], 1.0).expect("fits the adapter");
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics::kinematics(&model, &st, &nb);
    let bd = forces::boundary_of(&model, &st.x, &nb, &k);
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
        // The density's change is a small difference of f32 sums: on the
        // stirred disks with the Riemann viscosity its worst particle (at
        // the contact face) agrees to 8.7e-4 with the predictor weight 1
        // and to 1.0e-3 with the damping-weighted one
        // (physics::viscosity::predictor_weight); every other field to
        // 3e-4 or better.
        let fields: [(&str, &Field, f64); 6] = [
            ("x", &|s, i| s.x[i].x, 1e-3),
            ("rho", &|s, i| s.rho[i], 2e-3),
            ("e", &|s, i| s.e[i], 1e-3),
            ("sxx", &|s, i| s.s[i].xx, 1e-3),
            ("syy", &|s, i| s.s[i].yy, 1e-3),
            ("sxy", &|s, i| s.s[i].xy, 1e-3),
        ];
        for (name, f, tol) in fields {
            let (dg, dc) = change(f);
            assert_field(
                &format!("step {step}: change of {name}"),
                &dg,
                &dc,
                tol,
                &none,
            );
        }
        if model.rubs {
            // The slips themselves: a sliding particle's stays where the
            // return put it (its change is the f32 rounding of its value).
            let n = model.len();
            let (g, c): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (gs.slip[i], c.slip[i])).unzip();
            assert!(c.iter().any(|&u| u != 0.0), "step {step}: slips carried");
            assert_field(&format!("step {step}: slip"), &g, &c, 1e-3, &none);
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
    stages_match_cpu_penetration_with(None);
}

/// The same with both materials' cavitation pressure at 0.5 GPa, where
/// the plate's release opens voids: the half step's voids (the failure
/// time's −2), stresses and densities (docs/method.md, "Cavitation")
/// against physics::strength::void_state, particles within f32 of the
/// cavitation pressure skipped.
#[test]
fn stages_match_cpu_penetration_with_voids() {
    stages_match_cpu_penetration_with(Some(0.5e9));
}

fn stages_match_cpu_penetration_with(cavitation: Option<f64>) {
    use sphcontact::physics::strength;
    if gpu().is_none() {
        return;
    }
    let (model, st) = coarse_penetration_at_5_us();
    let mut model = midpoint(model);
    if let Some(pc) = cavitation {
        for b in &mut model.bodies {
            b.material.cavitation = pc;
        }
    }
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
    let mut at = st.failed_at.clone();
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
        // Within f32 of failing or of the cavitation pressure: either
        // side may call it.
        let p = mat.pressure(r, e);
        near_failure[i] = !strength::failed(st.damage[i])
            && (h.damage > 0.998
                || (p + mat.spall).abs() < 1e-3 * mat.spall
                || (p + mat.cavitation).abs() < 1e-3 * mat.cavitation
                || (p - strength::VOID_CLOSES * mat.cavitation).abs() < 1e-3 * mat.cavitation);
        at[i] = if strength::failed(h.damage) || !mat.cavitation.is_finite() {
            st.failed_at[i]
        } else {
            strength::void_state(mat, p, st.failed_at[i])
        };
        let void = at[i] == strength::VOID_OPEN;
        s[i] = if void { Sym::default() } else { sn };
        rho[i] = if strength::failed(h.damage) || void {
            r.max(mat.failed_density_floor(e))
        } else {
            r
        };
        hist[i] = h;
    }
    let voids = (0..n).filter(|&i| at[i] == strength::VOID_OPEN).count();
    println!("{voids} voids open after the half step");
    if cavitation.is_some() {
        assert!(voids > 20, "voids open");
    }
    let void_mismatch: Vec<usize> = (0..n)
        .filter(|&i| !model.rigid(i) && !near_failure[i])
        .filter(|&i| (at[i] == strength::VOID_OPEN) != (out.mid_hist[i][3] == strength::VOID_OPEN))
        .collect();
    assert!(
        void_mismatch.is_empty(),
        "a void on one side only: {void_mismatch:?}"
    );
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
        // The device stores the history itself in f32, not its increment:
        // an increment read back is the difference of two stored values,
        // good to one f32 step of the value (6.1e-5 K at 903 K). Within
        // that the two agree; what is beyond it is held to the tolerance.
        let ulp = |x: f64| {
            let v = x.abs() as f32;
            f64::from(f32::from_bits(v.to_bits() + 1) - v)
        };
        let gg: Vec<f64> = (0..n)
            .map(|i| {
                let d = gg[i] - c[i];
                c[i] + d.signum() * (d.abs() - ulp(out.mid_hist[i][col])).max(0.0)
            })
            .collect();
        assert_field(name, &gg, &c, 1e-4, &skip);
    }
}
