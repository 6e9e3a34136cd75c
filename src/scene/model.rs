//! A scene's material as the solvers' material model: the derived
//! constants of physics::material::MaterialModel from the scene's keys.

use super::Material;
use crate::physics::material::MaterialModel;

impl MaterialModel {
    /// The model of a scene's material: its EOS, elastic constants, sound
    /// speeds and impedance, and its strength and failure laws.
    pub fn new(mat: &Material) -> Self {
        let rho0 = mat.density;
        let c0 = mat.eos.c0();
        let g = mat.shear_modulus.unwrap_or(0.0);
        let strength = mat.strength;
        let failure = mat.failure;
        let y0 = match &strength {
            Some(law) => law.initial_yield(),
            None => mat.yield_stress.unwrap_or(f64::INFINITY),
        };
        let k = rho0 * c0 * c0;
        let (e, nu) = if g > 0.0 {
            (
                9.0 * k * g / (3.0 * k + g),
                (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g)),
            )
        } else {
            (k, 0.5)
        };
        let m = k + 4.0 * g / 3.0;
        let c_l = (m / rho0).sqrt();
        Self {
            rho0,
            c0,
            eos: mat.eos,
            g,
            y0,
            k,
            e,
            nu,
            c_l,
            z: rho0 * c_l,
            m,
            strength,
            failure,
            spall: mat.spall_pressure.unwrap_or(f64::INFINITY),
            cavitation: mat.cavitation_pressure.unwrap_or(if strength.is_some() {
                crate::physics::strength::THEORETICAL_STRENGTH * e
            } else {
                f64::INFINITY
            }),
            specific_heat: mat.specific_heat.unwrap_or(0.0),
            taylor_quinney: mat.taylor_quinney(),
        }
    }
}
