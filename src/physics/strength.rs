//! The stress update of a particle after the trial step: radial return onto
//! the yield surface of its material's strength law, the plastic work's
//! heating, damage and failure (docs/method.md, "Strength and failure").
//!
//! Perfect plasticity (`yield_stress`) needs nothing but the trial stress.
//! A Johnson–Cook strength law and the failure models need a history per
//! particle ([`History`]): the equivalent plastic strain, the temperature
//! and the damage, carried by the solvers only when a scene's materials ask
//! for them.

use crate::math::{Mat2, Sym};
use crate::physics::laws;
use crate::physics::material::MaterialModel;
pub use crate::physics::material::{failed, FAILED};

/// What a particle remembers of its plastic past.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct History {
    /// Equivalent plastic strain `ε_p`.
    pub eps_p: f64,
    /// Temperature, K.
    pub temperature: f64,
    /// Damage `D` in [0, 1]; 1: failed.
    pub damage: f64,
}

pub use crate::physics::failure::TRIAXIALITY_BOUND;

/// The default cavitation pressure of a material with a strength law, as
/// a fraction of Young's modulus: the theoretical strength of a solid,
/// about E/10 (Orowan 1949).
pub const THEORETICAL_STRENGTH: f64 = 0.1;

/// A particle's failure time (`State::failed_at`) while it is intact.
pub const INTACT: f64 = -1.0;

/// A particle's failure time while it is intact with a void open
/// (docs/method.md, "Cavitation"): it carries no tension and no deviatoric
/// stress, as a failed particle, until compression closes the void.
pub const VOID_OPEN: f64 = -2.0;

/// The pressure, as a fraction of the cavitation pressure, past which a
/// void closes: a compression clearly above the round-off of the
/// pressure at the density floor, which is zero only to it (in f32 on the
/// GPU, to about 1e-7 of the bulk modulus).
pub const VOID_CLOSES: f64 = 1e-3;

/// The failure time an intact particle's `at` becomes at EOS pressure
/// `p`: a void opens past the material's cavitation pressure and closes
/// once the particle is compressed again ([`VOID_CLOSES`]).
#[inline]
pub fn void_state(mat: &MaterialModel, p: f64, at: f64) -> f64 {
    if p < -mat.cavitation {
        VOID_OPEN
    } else if at == VOID_OPEN && p > VOID_CLOSES * mat.cavitation {
        INTACT
    } else {
        at
    }
}

/// The equivalent strain rate `sqrt(⅔ d′:d′)` of a velocity gradient, `d′`
/// the deviatoric rate of deformation in plane strain (`d_zz = 0`): the
/// rate of the Johnson–Cook rate terms.
#[inline]
pub fn equivalent_strain_rate(gv: &Mat2) -> f64 {
    let dxy = 0.5 * (gv.xy + gv.yx);
    let tr3 = (gv.xx + gv.yy) / 3.0;
    let (a, b, c) = (gv.xx - tr3, gv.yy - tr3, -tr3);
    ((2.0 / 3.0) * (a * a + b * b + c * c + 2.0 * dxy * dxy)).sqrt()
}

/// [`equivalent_strain_rate`] with the third normal rate `d_zz` (the hoop
/// rate `v_r / r` of a body of revolution) instead of 0.
#[inline]
pub fn equivalent_strain_rate_3(gv: &Mat2, d_zz: f64) -> f64 {
    let dxy = 0.5 * (gv.xy + gv.yx);
    let tr3 = (gv.xx + gv.yy + d_zz) / 3.0;
    let (a, b, c) = (gv.xx - tr3, gv.yy - tr3, d_zz - tr3);
    ((2.0 / 3.0) * (a * a + b * b + c * c + 2.0 * dxy * dxy)).sqrt()
}

/// The stress update of one particle of material `mat`: the trial
/// deviatoric stress `trial` returned onto the yield surface at the strain
/// rate `rate` (1/s), from the history `h` at the start of the step; `rho`
/// is the density the step ends at, `pressure` gives its pressure (asked
/// only by the failure laws, [`MaterialModel::can_fail`]). Returns
/// the deviatoric stress and the history at the end.
///
/// * Perfect plasticity: `s` scaled onto `Y0`; `Δε_p = (q − Y0)/3G`.
/// * A strength law ([`crate::physics::laws`]): `Δε_p` from the return
///   onto its curve at the rate and temperature of the step's start
///   ([`laws::return_increment`]), and `ΔT = χ σ_y Δε_p / (ρ c_p)`.
/// * Damage: `ΔD = Δε_p / ε_f(σ*, ε̇*, T*)` with the triaxiality
///   `σ* = −p/σ_y` of the returned state; a particle whose damage reaches
///   1, or whose pressure falls below `−p_spall`, fails.
/// * A failed particle carries no deviatoric stress (and, in the EOS, no
///   tension: [`MaterialModel::pressure_of`]).
#[inline]
pub fn update(
    mat: &MaterialModel,
    trial: Sym,
    rate: f64,
    rho: f64,
    pressure: impl FnOnce() -> f64,
    h: History,
) -> (Sym, History) {
    let mut h = h;
    if failed(h.damage) {
        return (Sym::default(), h);
    }
    let q = trial.von_mises();
    let (mut s, mut d_eps, mut flow) = (trial, 0.0, q);
    if let Some(law) = &mat.strength {
        let f = law.factor(rate, h.temperature);
        d_eps = laws::return_increment(|e| law.curve(f, e), q, mat.g, h.eps_p);
        if d_eps > 0.0 {
            flow = q - 3.0 * mat.g * d_eps;
            s = trial.scale(flow / q);
            h.temperature += mat.taylor_quinney * flow * d_eps / (rho * mat.specific_heat);
        }
    } else if q > mat.y0 {
        d_eps = (q - mat.y0) / (3.0 * mat.g);
        flow = mat.y0;
        s = trial.scale(mat.y0 / q);
    }
    h.eps_p += d_eps;
    if !mat.can_fail() {
        return (s, h);
    }
    let p = pressure();
    if let Some(f) = &mat.failure {
        if d_eps > 0.0 {
            let triax = if flow > 0.0 {
                -p / flow
            } else {
                -p.signum() * f64::INFINITY
            };
            let (rate_star, t_star) = match &mat.strength {
                Some(law) => (
                    rate / law.reference_strain_rate(),
                    laws::homologous(
                        law.room_temperature(),
                        law.melt_temperature(),
                        h.temperature,
                    ),
                ),
                None => (rate, 0.0),
            };
            let eps_f = f.failure_strain(
                triax.clamp(-TRIAXIALITY_BOUND, TRIAXIALITY_BOUND),
                rate_star,
                t_star,
            );
            h.damage = (h.damage + d_eps / eps_f).min(FAILED);
        }
    }
    if p < -mat.spall {
        h.damage = FAILED;
    }
    if failed(h.damage) {
        s = Sym::default();
    }
    (s, h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::failure::DamageLaw;
    use crate::scene::Material;

    /// 4340 steel of the library; without `strength`, perfectly plastic at
    /// its A (792 MPa); with or without its damage law; spall pressure
    /// `spall`.
    fn steel(strength: bool, failure: bool, spall: Option<f64>) -> MaterialModel {
        let lib = crate::scene::library::entry("steel_4340").unwrap();
        MaterialModel::new(&Material {
            yield_stress: (!strength).then_some(792e6),
            strength: lib.strength.filter(|_| strength),
            failure: lib.failure.filter(|_| failure),
            spall_pressure: spall,
            ..lib
        })
    }

    fn fresh() -> History {
        History {
            eps_p: 0.0,
            temperature: 294.0,
            damage: 0.0,
        }
    }

    /// Uniaxial stretch `s = q·diag(⅔, −⅓, −⅓)` with von Mises `q`.
    fn uniaxial(q: f64) -> Sym {
        Sym {
            xx: 2.0 * q / 3.0,
            yy: -q / 3.0,
            xy: 0.0,
            zz: -q / 3.0,
        }
    }

    #[test]
    fn equivalent_rate_of_uniaxial_strain_and_shear() {
        // Uniaxial strain rate ε̇: ε̇_eq = ⅔ ε̇.
        let gv = Mat2 {
            xx: 3.0,
            ..Mat2::ZERO
        };
        assert!((equivalent_strain_rate(&gv) - 2.0).abs() < 1e-15);
        // Simple shear γ̇: ε̇_eq = γ̇/√3.
        let gv = Mat2 {
            xy: 3.0,
            ..Mat2::ZERO
        };
        assert!((equivalent_strain_rate(&gv) - 3.0 / 3f64.sqrt()).abs() < 1e-15);
    }

    /// The returned stress lies on the surface, the heating is the
    /// Taylor–Quinney share of the plastic work, and a purely elastic trial
    /// changes nothing.
    #[test]
    fn johnson_cook_return_heats_by_the_plastic_work() {
        let m = steel(true, false, None);
        let g = m.g;
        let (s, h) = update(&m, uniaxial(1.2e9), 1.0, 7830.0, || 0.0, fresh());
        let y = m.strength.unwrap().flow_stress(h.eps_p, 1.0, 294.0);
        assert!((s.von_mises() - y).abs() <= 1e-12 * y);
        assert!((h.eps_p - (1.2e9 - y) / (3.0 * g)).abs() <= 1e-12 * h.eps_p);
        let heat = 0.9 * y * h.eps_p / (7830.0 * 477.0);
        assert!((h.temperature - 294.0 - heat).abs() <= 1e-12 * heat);
        let (s, h) = update(&m, uniaxial(700e6), 1.0, 7830.0, || 0.0, fresh());
        assert_eq!((s, h), (uniaxial(700e6), fresh()));
    }

    /// Damage grows by Δε_p/ε_f; at 1 the particle fails and keeps no
    /// deviator; spall fails it at once; a failed particle stays failed.
    #[test]
    fn damage_and_spall() {
        let m = steel(false, true, Some(2e9));
        let g = m.g;
        let q = 792e6 + 3.0 * g * 0.01;
        // Uniaxial tension, σ* = ⅓: ε_f of 4340 at σ* = ⅓.
        let p = -792e6 / 3.0;
        let (s, h) = update(&m, uniaxial(q), 1.0, 7830.0, || p, fresh());
        let eps_f = 0.05 + 3.44 * (-2.12f64 / 3.0).exp();
        assert!((h.damage - 0.01 / eps_f).abs() < 1e-12);
        assert!((s.von_mises() - 792e6).abs() < 1e-3);
        let near = History {
            damage: 0.995,
            ..fresh()
        };
        let (s, h) = update(&m, uniaxial(q), 1.0, 7830.0, || p, near);
        assert_eq!((s, h.damage), (Sym::default(), FAILED));
        // Spall: elastic, but the pressure below −p_spall.
        let (s, h) = update(&m, uniaxial(100e6), 1.0, 7830.0, || -2.1e9, fresh());
        assert_eq!((s, h.damage, h.eps_p), (Sym::default(), FAILED, 0.0));
        let (s, h2) = update(&m, uniaxial(1e9), 1.0, 7830.0, || 1e9, h);
        assert_eq!((s, h2), (Sym::default(), h));
    }

    /// The default cavitation pressure is E/10 for a material with a
    /// strength law and none without one; a void opens past it, stays
    /// open while the particle is not compressed, and closes once it is.
    #[test]
    fn a_void_opens_past_the_cavitation_pressure_and_closes_under_compression() {
        let m = steel(true, false, None);
        assert_eq!(m.cavitation, 0.1 * m.e);
        assert_eq!(steel(false, false, None).cavitation, f64::INFINITY);
        let pc = m.cavitation;
        assert_eq!(void_state(&m, -0.99 * pc, INTACT), INTACT);
        assert_eq!(void_state(&m, -1.01 * pc, INTACT), VOID_OPEN);
        // Held at the zero-pressure density, or still drawn: open.
        assert_eq!(void_state(&m, 0.0, VOID_OPEN), VOID_OPEN);
        assert_eq!(void_state(&m, -0.5 * pc, VOID_OPEN), VOID_OPEN);
        assert_eq!(void_state(&m, 0.9e-3 * pc, VOID_OPEN), VOID_OPEN);
        assert_eq!(void_state(&m, 1.1e-3 * pc, VOID_OPEN), INTACT);
        // A failed particle's time is no business of the void's.
        assert_eq!(void_state(&m, 1.1e-3 * pc, 3e-6), 3e-6);
    }

    /// At a triaxiality past the bound, Armco iron's failure strain (D1 < 0)
    /// would be negative; the update takes it at the bound, so damage grows
    /// by Δε_p/ε_f(1.5) and stays positive.
    #[test]
    fn the_triaxiality_bound_keeps_armco_iron_positive() {
        let f = crate::physics::failure::johnson_cook::Failure {
            d1: -2.20,
            d2: 5.43,
            d3: -0.47,
            d4: 0.016,
            d5: 0.63,
        };
        assert!(f.failure_strain(3.0, 1.0, 0.0) < 0.0);
        let m = MaterialModel::new(&Material {
            failure: Some(crate::scene::FailureLaw::JohnsonCook(f)),
            ..crate::scene::library::entry("steel_4340").unwrap()
        });
        let m = MaterialModel {
            strength: None,
            y0: 175e6,
            ..m
        };
        let q = 175e6 + 3.0 * m.g * 0.001;
        // σ* = −p/σ_y = 3, twice the bound.
        let (_, h) = update(&m, uniaxial(q), 1.0, 7830.0, || -3.0 * 175e6, fresh());
        let eps_f = f.failure_strain(TRIAXIALITY_BOUND, 1.0, 0.0);
        assert!(eps_f > 0.4);
        assert!((h.damage - 0.001 / eps_f).abs() < 1e-12, "{}", h.damage);
    }
}
