//! The strength laws on a homogeneous block: the CPU path's kinematic
//! stage (corrected velocity gradient, stress rate, equivalent strain rate)
//! and its stress update (`physics::strength::update`), driven by an
//! imposed uniform velocity gradient, against each law's exact
//! stress–strain curve (Johnson–Cook, its multiplicative rate form,
//! Zerilli–Armstrong).
//!
//! Under a constant velocity gradient without spin the loading is
//! proportional: the trial stress grows by `3G Δε_eq` a step and the
//! return keeps `q + 3G ε_p = 3G ε_eq` and `q = σ_y(ε_p)` exactly, at any
//! step size. The exact curve is then `q(ε_eq)`, the root of
//! `q = σ_y(ε_eq − q/3G; ε̇, T)` (for Johnson–Cook
//! `(A + B (ε_eq − q/3G)ⁿ)(1 + C ln ε̇*)(1 − T*ᵐ)`), and the block must
//! follow it to round-off (1e-6 relative, f64).

#![allow(clippy::needless_range_loop)] // the particle loops index several arrays

mod common;

use common::parse;
use sphcontact::cpu::{kinematics, neighbours};
use sphcontact::math::Mat2;
use sphcontact::model::Model;
use sphcontact::physics::laws::StrengthLaw;
use sphcontact::physics::strength::{self, History};

/// The 4340 steel strength of Johnson & Cook (1983) with rate coefficient
/// `c`, as a scene's keys.
fn jc_keys(c: f64) -> String {
    format!(
        "strength = {{ kind = \"johnson_cook\", a = 792e6, b = 510e6, n = 0.26, c = {c}, m = 1.03, reference_strain_rate = 1.0, room_temperature = 294.0, melt_temperature = 1793.0 }}"
    )
}

/// A 2-D steel block with the strength law `strength` (a scene's
/// `strength = …` line), Taylor–Quinney fraction `tq`.
fn block(strength: &str, tq: f64) -> (Model, sphcontact::model::State) {
    let scene = parse(&format!(
        r#"
[simulation]
dimension = 2
end_time = 1e-6
[materials.steel]
density = 7830.0
shear_modulus = 77.5e9
eos = {{ kind = "linear", c0 = 4578.0 }}
{strength}
specific_heat = 477.0
taylor_quinney = {tq}
[[bodies]]
name = "block"
material = "steel"
spacing = 1e-4
shape = {{ kind = "rectangle", min = [0.0, 0.0], max = [1.2e-3, 1.2e-3] }}
"#
    ));
    Model::new(&scene)
}

/// The exact von Mises stress at equivalent strain `eps_eq` from the virgin
/// state, the law's rate and temperature factor held at `factor`: the root
/// of `q = σ_y(ε_eq − q/3G)`, by bisection to round-off.
fn exact_q(law: &StrengthLaw, g: f64, eps_eq: f64, factor: f64) -> f64 {
    let f = |q: f64| {
        let ep = (eps_eq - q / (3.0 * g)).max(0.0);
        q - law.curve(factor, ep).0
    };
    let q_el = 3.0 * g * eps_eq;
    if f(q_el) <= 0.0 {
        return q_el;
    }
    let (mut lo, mut hi) = (0.0, q_el);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// What a driven block run records: per step the equivalent strain and each
/// particle's von Mises stress.
struct Driven {
    eps_eq: Vec<f64>,
    q: Vec<Vec<f64>>,
    /// The equivalent strain rate the kinematic stage saw (max over the
    /// particles, max over the steps).
    rate: (f64, f64),
}

/// Drive the block with the uniform velocity gradient `l` for `steps` steps
/// of `dt`: the velocities set to `l x` at the current positions, the
/// kinematic stage's stress rate and strain rate, the stress update, and
/// the positions moved with the velocities. Every particle starts at
/// temperature `t0`.
fn drive(strength: &str, tq: f64, t0: f64, l: Mat2, dt: f64, steps: usize) -> Driven {
    let (model, mut st) = block(strength, tq);
    let n = model.len();
    let mat = *model.material(0);
    let mut hist = vec![
        History {
            eps_p: 0.0,
            temperature: t0,
            damage: 0.0,
        };
        n
    ];
    let mut out = Driven {
        eps_eq: Vec::new(),
        q: Vec::new(),
        rate: (f64::INFINITY, 0.0),
    };
    let mut eps_eq = 0.0;
    for _ in 0..steps {
        for i in 0..n {
            st.v[i] = l.mul_vec(st.x[i]);
        }
        let nb = neighbours::find(&model, st.frame());
        let k = kinematics::kinematics(&model, &st, &nb);
        let mut qs = Vec::with_capacity(n);
        for i in 0..n {
            let trial = st.s[i].add_scaled(&k.ds[i], dt);
            let rate = k.rate[i];
            out.rate = (out.rate.0.min(rate), out.rate.1.max(rate));
            let (s, h) = strength::update(&mat, trial, rate, st.rho[i], || 0.0, hist[i]);
            st.s[i] = s;
            hist[i] = h;
            st.rho[i] += k.drho[i] * dt;
            qs.push(s.von_mises());
        }
        for i in 0..n {
            st.x[i] += st.v[i] * dt;
        }
        eps_eq += strength::equivalent_strain_rate(&l) * dt;
        out.eps_eq.push(eps_eq);
        out.q.push(qs);
    }
    out
}

/// The largest relative distance of the block's stresses from the exact
/// curve, over every particle and step.
fn worst(d: &Driven, law: &StrengthLaw, g: f64, factor: f64) -> f64 {
    d.eps_eq
        .iter()
        .zip(&d.q)
        .flat_map(|(&e, qs)| {
            let want = exact_q(law, g, e, factor);
            qs.iter().map(move |q| (q / want - 1.0).abs())
        })
        .fold(0.0, f64::max)
}

/// Uniaxial strain: `∇v = diag(ε̇, 0)`, `ε̇_eq = ⅔|ε̇|`.
fn uniaxial(rate: f64) -> Mat2 {
    Mat2 {
        xx: rate,
        ..Mat2::ZERO
    }
}

/// Shear without spin: `∇v` symmetric with `d_xy = γ̇/2`, `ε̇_eq = γ̇/√3`
/// (simple shear's rate of deformation; simple shear adds the spin `γ̇/2`,
/// which only rotates the stress, see `jaumann_simple_shear_rotates`).
fn shear(gamma_rate: f64) -> Mat2 {
    Mat2 {
        xy: 0.5 * gamma_rate,
        yx: 0.5 * gamma_rate,
        ..Mat2::ZERO
    }
}

fn steel() -> (StrengthLaw, f64) {
    let (model, _) = block(&jc_keys(0.014), 0.0);
    (model.material(0).strength.unwrap(), model.material(0).g)
}

/// Compression and shear to an equivalent strain of 5 %, in 400 steps: the
/// static curve (rate below the reference, room temperature), the rate
/// term alone (ε̇ far above the reference, no heating), the temperature
/// term alone (the block at 800 K, no heating).
#[test]
fn a_block_follows_the_exact_johnson_cook_curve() {
    let (jc, g) = steel();
    let steps = 400;
    let strain = 0.05;
    for (what, l_of) in [
        ("uniaxial strain", uniaxial as fn(f64) -> Mat2),
        ("shear", shear),
    ] {
        // Static: a rate of 0.5/s is below the reference 1/s.
        let slow = l_of(1.0);
        let per = strength::equivalent_strain_rate(&slow);
        let scale_slow = 0.5 / per;
        let l = Mat2 {
            xx: slow.xx * scale_slow,
            xy: slow.xy * scale_slow,
            yx: slow.yx * scale_slow,
            yy: slow.yy * scale_slow,
        };
        let dt = strain / 0.5 / steps as f64;
        let d = drive(&jc_keys(0.014), 0.0, 294.0, l, dt, steps);
        let e = worst(&d, &jc, g, 1.0);
        println!("{what}, static: worst {e:.2e}");
        assert!(e < 1e-6, "{what}, static: {e:e}");

        // The rate term alone: ε̇_eq = 1e3/s.
        let fast = l_of(1e3 / per);
        let dt = strain / 1e3 / steps as f64;
        let d = drive(&jc_keys(0.014), 0.0, 294.0, fast, dt, steps);
        assert!(d.rate.0 > 0.999e3 && d.rate.1 < 1.001e3, "{:?}", d.rate);
        let scale = jc.factor(1e3, 294.0);
        let e = worst(&d, &jc, g, scale);
        println!("{what}, rate term (×{scale:.4}): worst {e:.2e}");
        assert!(e < 1e-6, "{what}, rate: {e:e}");
        // The test can tell: the static curve is 9.7 % away.
        assert!(worst(&d, &jc, g, 1.0) > 0.05);

        // The temperature term alone: 800 K, no heating.
        let d = drive(
            &jc_keys(0.014),
            0.0,
            800.0,
            l,
            strain / 0.5 / steps as f64,
            steps,
        );
        let scale = jc.factor(0.5, 800.0);
        let e = worst(&d, &jc, g, scale);
        println!("{what}, temperature term (×{scale:.4}): worst {e:.2e}");
        assert!(e < 1e-6, "{what}, temperature: {e:e}");
        assert!(worst(&d, &jc, g, 1.0) > 0.2);
    }
}

/// The other laws of the registry on the same block: Zerilli–Armstrong
/// (copper's FCC constants, and a BCC form) and the multiplicative rate
/// form of Johnson–Cook (Weldox 460 E), each in compression at a slow and
/// a fast rate and hot, against its exact curve at the rate the kinematic
/// stage measured. Each case also differs from the same law's curve at
/// another rate or temperature, so the check can tell.
#[test]
fn the_other_laws_follow_their_exact_curves() {
    let za_cu = "strength = { kind = \"zerilli_armstrong\", c0 = 65e6, c2 = 890e6, c3 = 0.0028, c4 = 0.000115, room_temperature = 294.0 }";
    let za_bcc = "strength = { kind = \"zerilli_armstrong\", c0 = 70e6, c1 = 1033e6, c3 = 0.00698, c4 = 0.000415, c5 = 266e6, n = 0.289, room_temperature = 294.0 }";
    let mjc = "strength = { kind = \"modified_johnson_cook\", a = 490e6, b = 807e6, n = 0.73, c = 0.0114, m = 0.94, reference_strain_rate = 5e-4, room_temperature = 293.0, melt_temperature = 1800.0 }";
    let steps = 400;
    let strain = 0.05;
    for (name, law_keys) in [
        ("ZA copper", za_cu),
        ("ZA BCC", za_bcc),
        ("modified JC", mjc),
    ] {
        let (model, _) = block(law_keys, 0.0);
        let (law, g) = (model.material(0).strength.unwrap(), model.material(0).g);
        let per = strength::equivalent_strain_rate(&uniaxial(1.0));
        for (rate, t0) in [(0.5, 294.0), (2e3, 294.0), (0.5, 700.0)] {
            let dt = strain / rate / steps as f64;
            let d = drive(law_keys, 0.0, t0, uniaxial(-rate / per), dt, steps);
            // The block's rate is uniform and steady to round-off.
            assert!((d.rate.1 / d.rate.0 - 1.0) < 1e-9, "{name}: {:?}", d.rate);
            let f = law.factor(d.rate.1, t0);
            let e = worst(&d, &law, g, f);
            let other = law.factor(
                if rate > 1.0 { 0.5 } else { 2e3 },
                if t0 > 300.0 { 294.0 } else { 700.0 },
            );
            let apart = worst(&d, &law, g, other);
            println!("{name} at {rate}/s, {t0} K: worst {e:.2e} (another rate or temperature: {apart:.2e})");
            assert!(e < 1e-6, "{name} at {rate}/s, {t0} K: {e:e}");
            assert!(
                apart > 0.01,
                "{name} at {rate}/s, {t0} K: the check cannot tell ({apart:e})"
            );
        }
    }
}

/// With the Taylor–Quinney heating on, the temperature follows
/// `ρ c_p dT = χ σ_y dε_p`; the update takes the softening at the step's
/// start, so the block meets the exact curve (a root of the ODE, here
/// integrated with 100 times finer steps) to first order in the step:
/// halving the step halves the error.
#[test]
fn adiabatic_heating_converges_to_first_order() {
    let (jc, g) = steel();
    let strain = 0.2;
    let l = uniaxial(-0.75); // ε̇_eq = 0.5/s, below the reference
    let run = |steps: usize| {
        let d = drive(
            &jc_keys(0.014),
            0.9,
            294.0,
            l,
            strain / 0.5 / steps as f64,
            steps,
        );
        *d.q.last()
            .unwrap()
            .iter()
            .max_by(|a, b| a.total_cmp(b))
            .unwrap()
    };
    // Reference: the same update on one particle with 100x the steps.
    let reference = {
        let (model, _) = block(&jc_keys(0.014), 0.9);
        let mat = *model.material(0);
        let steps = 40_000;
        let de = strain / steps as f64;
        let mut h = History {
            eps_p: 0.0,
            temperature: 294.0,
            damage: 0.0,
        };
        let mut s = sphcontact::math::Sym::default();
        let mut rho = mat.rho0;
        let dir = sphcontact::math::Sym {
            xx: 2.0 / 3.0,
            yy: -1.0 / 3.0,
            xy: 0.0,
            zz: -1.0 / 3.0,
        };
        for _ in 0..steps {
            // ε̇_eq = ⅔|ε̇_xx|: a compression of 1.5 de in x.
            let trial = s.add_scaled(&dir, -3.0 * g * de);
            let (s2, h2) = strength::update(&mat, trial, 0.5, rho, || 0.0, h);
            s = s2;
            h = h2;
            rho *= (1.5 * de).exp();
        }
        s.von_mises()
    };
    let (e1, e2) = (
        (run(200) / reference - 1.0).abs(),
        (run(400) / reference - 1.0).abs(),
    );
    let cold = exact_q(&jc, g, strain, 1.0);
    println!(
        "heated q {reference:.6e} (cold {cold:.6e}); error at 200 steps {e1:.2e}, at 400 {e2:.2e}"
    );
    assert!(reference < 0.99 * cold, "heating softens");
    assert!(e1 < 1e-3 && e2 < 0.6 * e1 && e2 > 0.4 * e1);
}

/// Simple shear of an elastic block, spin included: the Jaumann rate
/// rotates the stress, `s_xy = G sin γ` and `s_xx = −s_yy = G (1 − cos γ)`
/// (the classic hypoelastic answer), to second order in the step.
#[test]
fn jaumann_simple_shear_rotates() {
    let (model, mut st) = block(&jc_keys(0.0), 0.0);
    let g = model.material(0).g;
    let n = model.len();
    let gamma_rate = 1.0;
    let steps = 2000;
    let gamma_end = 0.5;
    let dt = gamma_end / gamma_rate / steps as f64;
    let l = Mat2 {
        xy: gamma_rate,
        ..Mat2::ZERO
    };
    for _ in 0..steps {
        // Midpoint in the stress: the rate at the half-step stress.
        for i in 0..n {
            st.v[i] = l.mul_vec(st.x[i]);
        }
        let nb = neighbours::find(&model, st.frame());
        let k = kinematics::kinematics(&model, &st, &nb);
        let s0 = st.s.clone();
        for i in 0..n {
            st.s[i] = s0[i].add_scaled(&k.ds[i], 0.5 * dt);
        }
        let k2 = kinematics::kinematics(&model, &st, &nb);
        for i in 0..n {
            st.s[i] = s0[i].add_scaled(&k2.ds[i], dt);
        }
    }
    let (want_xy, want_xx) = (g * gamma_end.sin(), g * (1.0 - gamma_end.cos()));
    let worst =
        st.s.iter()
            .map(|s| ((s.xy - want_xy).abs() + (s.xx - want_xx).abs() + (s.yy + want_xx).abs()) / g)
            .fold(0.0, f64::max);
    println!("Jaumann simple shear to γ = {gamma_end}: worst {worst:.2e} G");
    assert!(worst < 1e-6, "{worst:e}");
}

/// The leapfrog carries each adaptive support over a step by `F = I + Δt
/// L` (`Metric::carried`), which is the step's motion `x_{n+1} = x_n + Δt
/// v_{n+½}` exactly when `L` is the velocity gradient with respect to
/// `x_n`; its kinematic walk differentiates at `x_{n+1}`, and the step
/// maps that gradient back (`Mat2::gradient_behind`, docs/method.md §9).
/// A block in an affine velocity field `v = A x`, unstressed (so that the
/// first half kick leaves the interior's velocities affine), one step:
/// every interior particle's carried support is `Bᵀ Q B`, `B = (I +
/// ΔtA)⁻¹`, to round-off (measured 1e-18 of `Q`). The end-configuration
/// gradient misses it by about `(Δt|A|)²` of `Q` a step (here 2.3e-6), a
/// first-order error over a run.
#[test]
fn the_leapfrog_carries_supports_with_the_steps_motion() {
    use sphcontact::cpu::CpuSolver;
    let (model, mut st) = block(&jc_keys(0.0), 0.0);
    assert!(model.adaptive, "the block's supports adapt");
    let a = Mat2 {
        xx: -2.0e5,
        xy: 1.5e5,
        yx: -0.5e5,
        yy: 1.0e5,
    };
    for i in 0..model.len() {
        st.v[i] = a.mul_vec(st.x[i]);
    }
    let (x0, q0) = (st.x.clone(), st.metric.clone());
    let mut solver = CpuSolver::new(model, st);
    let dt = solver.step(f64::INFINITY).expect("one step");
    let (model, st) = (&solver.model, &solver.state);
    let carried = if st.carried.is_empty() {
        &st.metric
    } else {
        &st.carried
    };
    // B = (I + ΔtA)⁻¹.
    let f = Mat2 {
        xx: 1.0 + dt * a.xx,
        xy: dt * a.xy,
        yx: dt * a.yx,
        yy: 1.0 + dt * a.yy,
    };
    let b = f.inverse(1e-12).expect("F invertible");
    let (lo, hi) = (0.4e-3, 0.8e-3);
    let mut worst = 0.0f64;
    let mut interior = 0;
    for i in 0..model.len() {
        let x = x0[i];
        if x.x < lo || x.x > hi || x.y < lo || x.y > hi {
            continue;
        }
        interior += 1;
        // An empty metric: every support round (Metric::round).
        let q = &q0
            .get(i)
            .copied()
            .unwrap_or(sphcontact::physics::support::Metric::round(model.h[i]));
        // Q B, then Bᵀ (Q B).
        let (qb11, qb21) = (q.xx * b.xx + q.xy * b.yx, q.xy * b.xx + q.yy * b.yx);
        let (qb12, qb22) = (q.xx * b.xy + q.xy * b.yy, q.xy * b.xy + q.yy * b.yy);
        let exact = [
            b.xx * qb11 + b.yx * qb21,
            b.xx * qb12 + b.yx * qb22,
            b.xy * qb12 + b.yy * qb22,
        ];
        let c = &carried[i];
        let err = [c.xx - exact[0], c.xy - exact[1], c.yy - exact[2]]
            .iter()
            .map(|e| e.abs())
            .fold(0.0, f64::max);
        worst = worst.max(err / q.xx.abs().max(q.yy.abs()));
    }
    let norm = (a.xx * a.xx + a.xy * a.xy + a.yx * a.yx + a.yy * a.yy).sqrt();
    println!(
        "Δt|A| = {:.2e}; {interior} interior supports, worst {worst:.2e} of Q",
        dt * norm
    );
    assert!(interior >= 9, "{interior} interior particles");
    assert!(worst < 1e-9, "carried supports off by {worst:e} of Q");
}
