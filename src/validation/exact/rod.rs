//! 1-D elastic–plastic rod onto a rigid wall: the elastic precursor and
//! the plastic wave behind it.

use crate::physics::material::MaterialModel;

// ---------------------------------------------------------------------------
// 1-D elastic–plastic rod on a rigid wall: elastic precursor and plastic wave
// ---------------------------------------------------------------------------

/// A uniform state of a rod in uniaxial strain (docs/method.md §6), behind one of
/// the waves of [`rod_on_wall`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodState {
    /// Axial stress `σ_xx`, Pa, tension positive (docs/method.md §2).
    pub stress: f64,
    /// Particle velocity towards the wall, m/s.
    pub velocity: f64,
    /// Density, kg/m³.
    pub density: f64,
    /// Specific internal energy, J/kg (all of it: the EOS's energy is the
    /// total work of the stress, deviatoric part included, as in the
    /// solver's energy equation, docs/method.md §4).
    pub energy: f64,
    /// Pressure `p(ρ, e)` of the material's EOS, Pa.
    pub pressure: f64,
}

/// The two-wave answer of an elastic–perfectly-plastic rod striking a rigid
/// wall ([`rod_on_wall`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoWaveImpact {
    /// Behind the elastic precursor: the Hugoniot elastic limit (HEL).
    pub hel: RodState,
    /// Lagrangian speed of the precursor (relative to the undeformed rod),
    /// m/s: it reaches the material at distance `D` from the struck end
    /// (measured at t = 0) at `D / elastic_speed`. Equals `c_L` to first
    /// order.
    pub elastic_speed: f64,
    /// Behind the plastic wave: at rest against the wall, deviator held at
    /// yield.
    pub plastic: RodState,
    /// Lagrangian speed of the plastic wave, m/s (the bulk speed
    /// `sqrt(K/ρ0)` to first order, more as the EOS stiffens).
    pub plastic_speed: f64,
}

/// The acoustic (small-strain) Hugoniot elastic limit in uniaxial strain,
/// `σ_HEL = (K + 4G/3) Y0/(2G)` (docs/method.md §6: the deviator reaches the von
/// Mises limit `|s_xx| = 2Y0/3` at the strain `Y0/(2G)`), Pa, as a positive
/// magnitude. ≈ 1.04 GPa for the steel of Table 1 with Y0 = 600 MPa.
pub fn acoustic_hel(mat: &MaterialModel) -> f64 {
    mat.m * mat.y0 / (2.0 * mat.g)
}

/// Stress and energy of the state at density `rho` reached from state `a`
/// (stress `sigma_a`, engineering strain `eps_a`, energy `e_a`) through a
/// single jump, with deviatoric stress `s_xx`: the Rankine–Hugoniot energy
/// jump `e − e_a = (σ + σ_a)(ε − ε_a)/(2ρ0)` together with
/// `σ = −p(ρ, e) + s_xx`. The EOS is linear in `e` where `e ≥ 0`
/// (`p = p(ρ, 0) + Γ0 ρ e`, docs/method.md §6), which a compressive jump
/// from rest keeps, so the pair solves in closed form.
fn jump_state(
    mat: &MaterialModel,
    rho: f64,
    s_xx: f64,
    sigma_a: f64,
    eps_a: f64,
    e_a: f64,
) -> (f64, f64) {
    let eps = mat.rho0 / rho - 1.0;
    let w = (eps - eps_a) / (2.0 * mat.rho0);
    let g = mat.eos.gruneisen() * rho;
    let p0 = mat.pressure(rho, 0.0);
    let sigma = (-p0 - g * e_a - g * sigma_a * w + s_xx) / (1.0 + g * w);
    let e = e_a + (sigma + sigma_a) * w;
    (sigma, e)
}

/// Exact plane-wave answer of a 1-D elastic–plastic rod (uniaxial
/// strain, docs/method.md §6) striking a rigid wall (docs/method.md §8.5) at speed
/// `v0` > 0: a two-wave structure running from the wall into the rod.
///
/// * **Elastic precursor.** The rod is compressed elastically until the von
///   Mises stress reaches `Y0`. With the solver's hypoelastic law in 1-D,
///   `ṡ_xx = (4/3) G ε̇_xx` and `ε̇_xx = −ρ̇/ρ`, so
///   `s_xx = −(4/3) G ln(ρ/ρ0)`; yield (`J = (3/2)|s_xx| = Y0`) is at
///   `ρ_H = ρ0 exp(Y0/(2G))`. The HEL stress is `σ_H = −p(ρ_H, e_H) − 2Y0/3`
///   with the Rankine–Hugoniot energy from rest. Jump conditions in
///   Lagrangian form for a wave running away from the wall (speed `W`
///   relative to the undeformed rod, engineering strain `ε = ρ0/ρ − 1`,
///   Δ = behind − ahead): `Δσ = ρ0 W Δv` and `Δv = W Δε`, so
///   `W_e = sqrt(σ_H/(ρ0 ε_H))` and `v_H = v0 + W_e ε_H`. To first order
///   this is [`acoustic_hel`], `c_L` and `u_HEL = σ_HEL/(ρ0 c_L)` (≈ 22.7 m/s
///   for the steel of Table 1).
/// * **Plastic wave.** Behind it the rod is at rest against the wall and the
///   deviator stays at yield, `σ = −p(ρ, e) − 2Y0/3` (the radial return
///   holds `s_xx = −2Y0/3` while compression grows). With a Johnson–Cook
///   strength without rate term or heating (`C = 0`, Taylor–Quinney 0),
///   `Y0 = A` and the deviator behind is `−⅔ q(ρ)` with `q` the hardened
///   flow stress at the compression ρ: under monotonic uniaxial compression
///   `q + 3G ε_p = 2G ln(ρ/ρ0)` and `q = A + B ε_pⁿ`. The wave is still a
///   shock when this `σ(ε)` is convex (linear hardening with a linear EOS
///   is). From the HEL state the
///   jump conditions give `(σ_H − σ_F)(ε_H − ε_F) = ρ0 v_H²`, with `σ_F`
///   from the EOS and the energy jump (`jump_state`); this one equation in
///   `ε_F` is solved by bisection, then `W_p = v_H/(ε_H − ε_F)`. For a weak
///   plastic wave `W_p` tends to the bulk speed `sqrt(K/ρ0)` (divided by
///   `1 + ε_H`); the Mie–Grüneisen EOS stiffens with compression, so it is a
///   little faster.
///
/// `None` when there is no two-wave structure: an elastic material (no
/// yield stress or no shear modulus), a strength with a rate term or
/// heating, `v0` not above the HEL particle
/// velocity (the rod stays elastic), or a plastic wave at least as fast as
/// the precursor (an overdriven single shock).
pub fn rod_on_wall(mat: &MaterialModel, v0: f64) -> Option<TwoWaveImpact> {
    let (rho0, y0, g) = (mat.rho0, mat.y0, mat.g);
    if !(y0.is_finite() && y0 > 0.0 && g > 0.0 && v0.is_finite() && v0 > 0.0) {
        return None;
    }
    if let Some(law) = &mat.strength {
        // The answer is exact for a strength that depends on the plastic
        // strain alone: no rate term, no heating.
        if law.rate_dependent() || mat.taylor_quinney != 0.0 {
            return None;
        }
    }
    let s_yield = -2.0 * y0 / 3.0;
    // The deviator on the yield surface at density ρ: constant for perfect
    // plasticity; with hardening the return from the virgin state at the
    // equivalent strain ⅔ ln(ρ/ρ0), path-independent under monotonic
    // compression (docs/method.md, "Strength and failure").
    let deviator = |rho: f64| match &mat.strength {
        None => s_yield,
        Some(law) => {
            let q_trial = 2.0 * g * (rho / rho0).ln();
            let f = law.factor(law.reference_strain_rate(), law.room_temperature());
            let d = crate::physics::laws::return_increment(|e| law.curve(f, e), q_trial, g, 0.0);
            -2.0 / 3.0 * (q_trial - 3.0 * g * d)
        }
    };

    // Elastic precursor from rest.
    let rho_h = rho0 * (y0 / (2.0 * g)).exp();
    let eps_h = rho0 / rho_h - 1.0;
    let (sig_h, e_h) = jump_state(mat, rho_h, s_yield, 0.0, 0.0, 0.0);
    let w_e = (sig_h / (rho0 * eps_h)).sqrt();
    let v_h = v0 + w_e * eps_h;
    if !(w_e.is_finite() && v_h > 0.0) {
        return None;
    }
    let hel = RodState {
        stress: sig_h,
        velocity: v_h,
        density: rho_h,
        energy: e_h,
        pressure: mat.pressure(rho_h, e_h),
    };

    // Plastic wave: bring the HEL state to rest.
    let target = rho0 * v_h * v_h;
    let excess = |eps: f64| {
        let rho = rho0 / (1.0 + eps);
        let (sig, _) = jump_state(mat, rho, deviator(rho), sig_h, eps_h, e_h);
        (sig_h - sig) * (eps_h - eps) - target
    };
    // Bracket from the acoustic estimate Δε ≈ v_H/c0, widened until the
    // Rayleigh line carries enough momentum (ε > −1 always: ρ finite).
    let mut step = v_h / mat.c0;
    let mut lo = eps_h - step;
    while excess(lo) < 0.0 {
        step *= 2.0;
        lo = eps_h - step;
        if lo <= -0.99 {
            return None;
        }
    }
    let mut hi = eps_h;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if excess(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let eps_f = 0.5 * (lo + hi);
    let rho_f = rho0 / (1.0 + eps_f);
    let (sig_f, e_f) = jump_state(mat, rho_f, deviator(rho_f), sig_h, eps_h, e_h);
    let w_p = v_h / (eps_h - eps_f);
    if !(w_p.is_finite() && w_p > 0.0 && w_p < w_e) {
        return None;
    }
    Some(TwoWaveImpact {
        hel,
        elastic_speed: w_e,
        plastic: RodState {
            stress: sig_f,
            velocity: 0.0,
            density: rho_f,
            energy: e_f,
            pressure: mat.pressure(rho_f, e_f),
        },
        plastic_speed: w_p,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validation::exact::test_support::*;

    /// The steel of docs/method.md §6 Table 1 with its Mie–Grüneisen EOS and
    /// Y0 = 600 MPa, as the scenes write it.
    fn steel_mg_plastic() -> MaterialModel {
        MaterialModel::new(&crate::scene::Material {
            shear_modulus: Some(77e9),
            yield_stress: Some(600e6),
            ..crate::scene::Material::basic(
                7850.0,
                crate::scene::Eos::mie_gruneisen(4580.0, 1.49, 2.02),
            )
        })
    }

    /// Steel at 100 m/s on a rigid wall: the HEL is the acoustic
    /// `(K + 4G/3) Y0/(2G)` ≈ 1.04 GPa, with `u_HEL` ≈ 22.7 m/s and the
    /// precursor at `c_L`, to first order in the strain at yield (3.9e-3):
    /// the EOS's curvature and Grüneisen term put the exact HEL 0.8 % above
    /// the acoustic one (1.049 GPa), the precursor 0.5 % above `c_L`;
    /// the plastic wave runs a little faster than the bulk speed (the EOS
    /// stiffens) and slower than the precursor.
    #[test]
    fn rod_on_wall_steel_at_100() {
        let m = steel_mg_plastic();
        let r = rod_on_wall(&m, 100.0).expect("two waves");
        println!("steel rod on a wall at 100 m/s: {r:?}");
        let hel = acoustic_hel(&m);
        assert!(near(hel / 1e9, 1.04, 0.005), "{hel:e}");
        assert!(close(-r.hel.stress, hel, 1e-2));
        assert!(close(100.0 - r.hel.velocity, hel / m.z, 1e-2));
        assert!(near(100.0 - r.hel.velocity, 22.7, 0.2));
        assert!(close(r.elastic_speed, m.c_l, 1e-2));
        let bulk = (m.k / m.rho0).sqrt();
        assert!(r.plastic_speed > bulk && r.plastic_speed < 1.05 * bulk);
        assert!(r.plastic_speed < r.elastic_speed);
        // Roughly σ_H − ρ0 W_p v_H: about −3.9 GPa.
        assert!(r.plastic.stress < -3.5e9 && r.plastic.stress > -4.5e9);
        assert!(r.plastic.density > r.hel.density && r.plastic.energy > r.hel.energy);
    }

    /// The solution satisfies what it was solved from, independently
    /// re-evaluated: the EOS with the deviator at yield, and the
    /// Rankine–Hugoniot mass, momentum and energy jumps across both waves
    /// (Lagrangian form).
    #[test]
    fn rod_on_wall_jump_conditions() {
        let m = steel_mg_plastic();
        for v0 in [30.0, 100.0, 300.0] {
            let r = rod_on_wall(&m, v0).expect("two waves");
            let eps = |s: &RodState| m.rho0 / s.density - 1.0;
            let (h, f) = (r.hel, r.plastic);
            let y = 2.0 * m.y0 / 3.0;
            for s in [&h, &f] {
                assert!(close(s.stress, -m.pressure(s.density, s.energy) - y, 1e-12));
                assert!(close(s.pressure, m.pressure(s.density, s.energy), 1e-15));
            }
            // Precursor, from rest at v0.
            let (we, wp) = (r.elastic_speed, r.plastic_speed);
            assert!(close(h.stress, m.rho0 * we * (h.velocity - v0), 1e-12));
            assert!(close(h.velocity - v0, we * eps(&h), 1e-12));
            assert!(close(h.energy, 0.5 * h.stress * eps(&h) / m.rho0, 1e-12));
            // Plastic wave, to rest.
            assert_eq!(f.velocity, 0.0);
            assert!(close(f.stress - h.stress, -m.rho0 * wp * h.velocity, 1e-9));
            assert!(close(-h.velocity, wp * (eps(&f) - eps(&h)), 1e-9));
            let de = 0.5 * (f.stress + h.stress) * (eps(&f) - eps(&h)) / m.rho0;
            assert!(close(f.energy - h.energy, de, 1e-9));
            // The yield point from the hypoelastic law: (4/3) G ln(ρ_H/ρ0) = 2Y0/3.
            assert!(close(4.0 / 3.0 * m.g * (h.density / m.rho0).ln(), y, 1e-12));
        }
    }

    /// A linear EOS without Grüneisen term makes the stress a function of
    /// strain only, `σ(ε) = K ε/(1 + ε) − 2Y0/3`, and the plastic jump a
    /// quadratic: with `x = ε_F − ε_H`, `b = 1 + ε_H`, `a = ρ0 v_H²/K`,
    /// `x = b (a − sqrt(a² + 4a))/2`. The bisection meets the closed form;
    /// a weak plastic wave runs at the local plastic wave speed
    /// `sqrt(σ'(ε_H)/ρ0) = c0/(1 + ε_H)`.
    #[test]
    fn rod_on_wall_linear_closed_form() {
        let mut m = material(7850.0, 4580.0, 77e9);
        m.y0 = 600e6;
        let mu_h = (m.y0 / (2.0 * m.g)).exp() - 1.0;
        let eps_h = 1.0 / (1.0 + mu_h) - 1.0;
        let sig_h = -m.k * mu_h - 2.0 * m.y0 / 3.0;
        let w_e = (sig_h / (m.rho0 * eps_h)).sqrt();
        for v0 in [25.0, 100.0, 400.0] {
            let r = rod_on_wall(&m, v0).expect("two waves");
            assert!(close(r.hel.stress, sig_h, 1e-12));
            assert!(close(r.elastic_speed, w_e, 1e-12));
            let v_h = v0 + w_e * eps_h;
            assert!(close(r.hel.velocity, v_h, 1e-10));
            let (a, b) = (m.rho0 * v_h * v_h / m.k, 1.0 + eps_h);
            let x = b * (a - (a * a + 4.0 * a).sqrt()) / 2.0;
            let eps_f = m.rho0 / r.plastic.density - 1.0;
            assert!(
                close(eps_f - eps_h, x, 1e-10),
                "{v0}: {} vs {x}",
                eps_f - eps_h
            );
            assert!(close(r.plastic_speed, -v_h / x, 1e-10));
        }
        let u_hel = -w_e * eps_h;
        let weak = rod_on_wall(&m, u_hel * (1.0 + 1e-5)).expect("two waves");
        let local = m.c0 / (1.0 + eps_h);
        assert!(
            close(weak.plastic_speed, local, 1e-6),
            "{}",
            weak.plastic_speed
        );
    }

    /// No two-wave structure: elastic materials, impacts below the HEL,
    /// an overdriven plastic shock, bad speeds.
    #[test]
    fn rod_on_wall_outside_its_range() {
        let m = steel_mg_plastic();
        assert!(rod_on_wall(&steel(), 100.0).is_none(), "no yield stress");
        assert!(rod_on_wall(&m, 20.0).is_none(), "below u_HEL");
        assert!(rod_on_wall(&m, 23.0).is_some(), "just above u_HEL");
        assert!(rod_on_wall(&m, 5000.0).is_none(), "overdriven");
        assert!(rod_on_wall(&m, -100.0).is_none());
        assert!(rod_on_wall(&m, f64::NAN).is_none());
    }
}
