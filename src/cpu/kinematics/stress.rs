//! Each particle's stress point of an evaluation: the equation of state,
//! the stress over ρ², the artificial stress and the hoop stress; and the
//! stress rate.

use super::*;

/// Per-particle inputs of the momentum pass: `σ/ρ²`, artificial stress and
/// sound speed, from the EOS.
pub fn eos_and_stress(model: &Model, st: &State) -> Vec<StressPoint> {
    (0..model.len())
        .into_par_iter()
        .map(|i| {
            stress_point(
                model,
                i,
                (st.rho[i], st.x[i]),
                st.e[i],
                &st.s[i],
                st.damage_of(i),
            )
        })
        .collect()
}

/// [`eos_and_stress`] with the particles of `debris` (a kinematics pass's
/// [`Kinematics::fallback`]) as debris ([`debris_point`]).
pub fn eos_and_stress_with(model: &Model, st: &State, debris: &[u32]) -> Vec<StressPoint> {
    let mut pts = eos_and_stress(model, st);
    for i in debris.iter().map(|&i| i as usize) {
        if !model.rigid(i) {
            pts[i] = debris_point(model, i, (st.rho[i], st.x[i]), st.e[i]);
        }
    }
    pts
}

/// The [`StressPoint`] of a debris particle (docs/method.md, "Debris"):
/// one whose neighbourhood cannot support a corrected gradient (the
/// correction fell back) carries, while it is so, no deviatoric stress
/// and no tension, as a failed particle does; its pressure in
/// compression stays, so it still cannot pass through its neighbours.
#[inline]
pub(crate) fn debris_point(model: &Model, i: usize, at: (f64, DVec2), e: f64) -> StressPoint {
    stress_point(model, i, at, e, &Sym::default(), strength::FAILED)
}

/// Particle i's [`StressPoint`] at density `rho` (a state's
/// [`State::rho`]) and position `x`, energy `e`, deviatoric stress `s`
/// and damage `damage` (a failed particle carries no tension).
///
/// In a body of revolution `rho` is `η = 2π r ρ` (docs/method.md §12): the
/// EOS takes `ρ = η / 2π r`, the momentum sums `σ/(η ρ)` (the divergence
/// of `2π r σ` per unit `η`) and the artificial stress in the same
/// measure, and the hoop acceleration is `σ_θθ / (r ρ)`; in plane strain
/// `η = ρ` and there is no hoop term.
#[inline]
pub(crate) fn stress_point(
    model: &Model,
    i: usize,
    (eta, x): (f64, DVec2),
    e: f64,
    s: &Sym,
    damage: f64,
) -> StressPoint {
    let mat = model.material(i);
    let rho = model.density(eta, x);
    let p = mat.pressure_of(rho, e, damage);
    let c = mat.sound_speed_of(rho, e, damage);
    point_of(model, model.takes_art(i), (eta, x), rho, (p, c), s)
}

/// Jaumann-rate hypoelastic deviatoric stress rate (docs/method.md §6):
/// `ṡ = 2G(ε̇ − ⅓ tr ε̇ I) + s Ωᵀ + Ω s`, plane strain with `s_zz` carried
/// (1-D uniaxial strain is the same formula with zero y-gradients).
#[inline]
pub fn stress_rate(g_mod: f64, s: &Sym, gv: &Mat2) -> Sym {
    let exy = 0.5 * (gv.xy + gv.yx);
    let w = 0.5 * (gv.xy - gv.yx);
    let tr3 = (gv.xx + gv.yy) / 3.0;
    Sym {
        xx: 2.0 * g_mod * (gv.xx - tr3) + 2.0 * w * s.xy,
        yy: 2.0 * g_mod * (gv.yy - tr3) - 2.0 * w * s.xy,
        xy: 2.0 * g_mod * exy + w * (s.yy - s.xx),
        zz: -2.0 * g_mod * tr3,
    }
}

/// The hoop rate of strain `v_r / r` of particle i.
#[inline]
pub fn hoop_rate(st: &State, i: usize) -> f64 {
    st.v[i].x / st.x[i].x
}

/// The deviatoric stress rate with the hoop strain rate `d_θθ` added to
/// the plane's ([`stress_rate`] with `d_θθ = 0`): the
/// trace takes it, and `s_θθ` (kept as `zz`) follows it.
#[inline]
pub fn with_hoop(g_mod: f64, ds: Sym, d_tt: f64) -> Sym {
    let third = d_tt / 3.0;
    Sym {
        xx: ds.xx - 2.0 * g_mod * third,
        yy: ds.yy - 2.0 * g_mod * third,
        xy: ds.xy,
        zz: ds.zz + 4.0 * g_mod * third,
    }
}

/// Per-particle inputs of the momentum pass, computed once per evaluation.
#[derive(Debug, Clone, Copy, Default)]
pub struct StressPoint {
    /// `σ_i / ρ_i²`, in plane (tension positive).
    pub sr2: Sym,
    /// Artificial stress `R_i` (zero when off).
    pub r: Sym,
    /// Sound speed for the viscosity.
    pub c: f64,
    /// The hoop stress's acceleration `σ_θθ / (r ρ)` of a body of
    /// revolution (docs/method.md §12); 0 in plane strain.
    pub hoop: f64,
}
