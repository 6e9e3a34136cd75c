//! Pass C: momentum and energy sums (METHOD.md §4) with Monaghan artificial
//! viscosity and, when the scene asks for it, Gray–Monaghan–Swift artificial
//! stress. The pair-antisymmetric `G_ij = ½ (L_i + L_j) ∇_i W_ij` conserves
//! momentum and energy exactly in semi-discrete form.

use glam::DVec2;
use rayon::prelude::*;

use super::neighbours::Neighbours;
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::kernel;

/// Per-particle inputs of the momentum pass, computed once per evaluation.
#[derive(Debug, Clone, Copy, Default)]
pub struct StressPoint {
    /// `σ_i / ρ_i²`, in plane (tension positive).
    pub sr2: Sym,
    /// Artificial stress `R_i` (zero when off).
    pub r: Sym,
    /// Sound speed for the viscosity.
    pub c: f64,
}

/// The Cauchy stress `σ = −p I + s` (in plane; `zz` = `−p + s_zz`).
#[inline]
pub fn cauchy(p: f64, s: &Sym) -> Sym {
    Sym {
        xx: s.xx - p,
        yy: s.yy - p,
        xy: s.xy,
        zz: s.zz - p,
    }
}

/// Artificial stress of METHOD.md §4: rotate σ/ρ² to principal axes, take
/// `−ε σ̄/ρ²` of each tensile principal value, rotate back.
#[inline]
pub fn artificial_stress(eps: f64, sigma: &Sym, rho: f64) -> Sym {
    let (a, b, th) = sigma.principal();
    let r2 = rho * rho;
    let ra = if a > 0.0 { -eps * a / r2 } else { 0.0 };
    let rb = if b > 0.0 { -eps * b / r2 } else { 0.0 };
    Sym::from_principal(ra, rb, th)
}

/// The velocity jump the viscosity sees: `v_ij` less the linear
/// reconstruction of each side to the pair's midpoint, limited (van Leer).
///
/// Plain Monaghan viscosity acts on every approaching pair, so it also damps
/// smooth compression and smears every wave; what survives of a step after
/// one transit is then lost at a contact that cannot pull (the release front
/// reaches the face spread out, and the face opens on its first part). With
/// each side extrapolated to the midpoint by its own velocity gradient
/// `∇v` (pass B), the jump is `O(Δx²)` where the field is smooth and stays
/// whole at a front, where the two sides' slopes disagree and the limiter
/// `φ = 4r/(1+r)²` (`r` the ratio of the projected slopes, 0 when they
/// differ in sign) turns the reconstruction off. The same idea is used for
/// the viscosity of CRKSPH (Frontiere, Raskin & Owen 2017). `x_ij = x_i − x_j`.
#[inline]
pub fn reconstructed_jump(vij: DVec2, xij: DVec2, gv_i: &Mat2, gv_j: &Mat2) -> DVec2 {
    let di = gv_i.mul_vec(xij);
    let dj = gv_j.mul_vec(xij);
    let (si, sj) = (xij.dot(di), xij.dot(dj));
    if si * sj <= 0.0 {
        return vij;
    }
    // 4r/(1+r)² with r = si/sj, in one division.
    let phi = (4.0 * si * sj / ((si + sj) * (si + sj))).min(1.0);
    vij - (di + dj) * (0.5 * phi)
}

/// Monaghan's `Π_ij` (METHOD.md §4), zero for receding pairs.
#[inline]
pub fn viscosity_pi(
    alpha: f64,
    beta: f64,
    hij: f64,
    xij: DVec2,
    vij: DVec2,
    c_mean: f64,
    rho_mean: f64,
) -> f64 {
    let vx = vij.dot(xij);
    if vx >= 0.0 {
        return 0.0;
    }
    // μ = h v·x / D, Π = (−α c̄ μ + β μ²)/ρ̄, in one division.
    let d = xij.length_squared() + 0.01 * hij * hij;
    let hv = hij * vx;
    hv * (-alpha * c_mean * d + beta * hv) / (d * d * rho_mean)
}

/// Pass C: `dv_i/dt` and `de_i/dt` from the SPH sums.
pub fn momentum_energy(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>) {
    let dim = model.dim;
    (0..model.len())
        .into_par_iter()
        .map(|i| {
            if model.rigid(i) {
                return (DVec2::ZERO, 0.0);
            }
            let pi_ = &pts[i];
            let mut dv = DVec2::ZERO;
            let mut de = 0.0;
            for b in nb.of(model, &st.x, i) {
                let j = b.j as usize;
                let pj = &pts[j];
                let hij = 0.5 * (model.h[i] + model.h[j]);
                let xij = st.x[i] - st.x[j];
                let vij = st.v[i] - st.v[j];
                let g = (l[i] + l[j]).scale(0.5).mul_vec(b.gw);
                // The viscosity sees the reconstructed jump; the energy
                // equation below keeps the true v_ij, so the viscous work
                // is still exactly the heat booked (energy conserved).
                // Not at a surface: there ∇v is extrapolated from one side
                // only, and the face is where a contact loads the body
                // impulsively; full viscosity damps that start-up ringing.
                let vis = if model.av_reconstruct && !surface[i] && !surface[j] {
                    reconstructed_jump(vij, xij, &gv[i], &gv[j])
                } else {
                    vij
                };
                let pi = viscosity_pi(
                    model.alpha,
                    model.beta,
                    hij,
                    xij,
                    vis,
                    0.5 * (pi_.c + pj.c),
                    0.5 * (st.rho[i] + st.rho[j]),
                );
                let mut t = pi_.sr2.add_scaled(&pj.sr2, 1.0);
                t.xx -= pi;
                t.yy -= pi;
                // The artificial stress's work on the pair, half to each
                // particle, is booked as heat: ½ (R_i + R_j) f^n : (v_ij ⊗
                // G_ij). METHOD.md §4 puts R in the momentum bracket only,
                // which leaves its work in no energy (the rubber rings'
                // total swung by 8 %); booked, the ledger closes as for
                // the viscosity.
                let mut art_work = 0.0;
                if let Some((_, n)) = model.artificial_stress {
                    let dp = 0.5
                        * (model.bodies[model.body[i] as usize].spacing
                            + model.bodies[model.body[j] as usize].spacing);
                    let f = b.w / kernel::w(dim, dp, hij);
                    let rf = pi_.r.add_scaled(&pj.r, 1.0).scale(f.powf(n));
                    t = t.add_scaled(&rf, 1.0);
                    art_work = 0.5 * vij.dot(rf.mul_vec(g));
                }
                let mj = model.mass[j];
                dv += t.mul_vec(g) * mj;
                // −(σ_i/ρ_i² − ½Π I + ½ (R_i + R_j) f^n) : (v_ij ⊗ G_ij)
                de -= mj * (vij.dot(pi_.sr2.mul_vec(g)) - 0.5 * pi * vij.dot(g) + art_work);
            }
            (dv, de)
        })
        .unzip()
}
