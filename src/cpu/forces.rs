//! Pass C: momentum and energy sums (METHOD.md §4) with Monaghan artificial
//! viscosity and, when the scene asks for it, Gray–Monaghan–Swift artificial
//! stress. The pair-antisymmetric `G_ij = ½ (L_i + L_j) ∇_i W_ij` conserves
//! momentum and energy exactly in semi-discrete form.

use glam::DVec2;

use super::neighbours::{Nbr, Neighbours};
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

/// What a pair contributes to both of its particles' momentum and energy
/// sums, from particle i's side.
struct PairTerms {
    /// `t G_ij`, `t = σ_i/ρ_i² + σ_j/ρ_j² − Π_ij I (+ artificial stress)`.
    tg: DVec2,
    /// `G_ij = ½ (L_i + L_j) ∇_i W_ij`.
    g: DVec2,
    /// `v_ij = v_i − v_j`.
    vij: DVec2,
    /// `½ Π_ij v_ij·G_ij − ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij)`, the part of
    /// either particle's energy term that is the pair's own.
    shared: f64,
}

/// The momentum and energy terms of the pair `(i, b.j)`.
///
/// Swapping the particles flips `G`, `v_ij`, `x_ij` and the reconstructed
/// jump and keeps `Π_ij`, `t` and `f`, so particle j's terms are
/// `dv_j −= m_i t G_ij` and `de_j −= m_i (v_ij·(σ_j/ρ_j² G_ij) − shared)`:
/// one evaluation of a pair serves both of its particles.
#[inline]
#[allow(clippy::too_many_arguments)]
fn pair_terms(
    model: &Model,
    st: &State,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
    i: usize,
    b: &Nbr,
) -> PairTerms {
    let j = b.j as usize;
    let (pi_, pj) = (&pts[i], &pts[j]);
    let hij = 0.5 * (model.h[i] + model.h[j]);
    let xij = st.x[i] - st.x[j];
    let vij = st.v[i] - st.v[j];
    let g = (l[i] + l[j]).scale(0.5).mul_vec(b.gw);
    // The viscosity sees the reconstructed jump; the energy equation keeps
    // the true v_ij, so the viscous work is still exactly the heat booked
    // (energy conserved). Not at a surface: there ∇v is extrapolated from
    // one side only, and the face is where a contact loads the body
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
    // The artificial stress's work on the pair, half to each particle, is
    // booked as heat: ½ (R_i + R_j) f^n : (v_ij ⊗ G_ij). METHOD.md §4 puts
    // R in the momentum bracket only, which leaves its work in no energy
    // (the rubber rings' total swung by 8 %); booked, the ledger closes as
    // for the viscosity.
    let mut art_work = 0.0;
    if let Some((_, n)) = model.artificial_stress {
        let dp = 0.5
            * (model.bodies[model.body[i] as usize].spacing
                + model.bodies[model.body[j] as usize].spacing);
        let f = b.w / kernel::w(model.dim, dp, hij);
        let rf = pi_.r.add_scaled(&pj.r, 1.0).scale(f.powf(n));
        t = t.add_scaled(&rf, 1.0);
        art_work = 0.5 * vij.dot(rf.mul_vec(g));
    }
    PairTerms {
        tg: t.mul_vec(g),
        g,
        vij,
        shared: 0.5 * pi * vij.dot(g) - art_work,
    }
}

/// Pass C: `dv_i/dt` and `de_i/dt` from the SPH sums, each pair evaluated
/// once ([`Neighbours::sweep`]); rigid particles get zero rates.
///
/// `dv_i/dt = Σ_j m_j t G_ij` and `de_i/dt = −Σ_j m_j (σ_i/ρ_i² − ½Π I +
/// ½ (R_i + R_j) f^n) : (v_ij ⊗ G_ij)` (METHOD.md §4).
pub fn momentum_energy(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    l: &[Mat2],
    gv: &[Mat2],
    surface: &[bool],
    pts: &[StressPoint],
) -> (Vec<DVec2>, Vec<f64>) {
    let terms = |i, b: &Nbr| pair_terms(model, st, l, gv, surface, pts, i, b);
    let mut acc = vec![(DVec2::ZERO, 0.0); model.len()];
    nb.sweep(model, &st.x, &mut acc, |i, b, ai, aj| {
        let j = b.j as usize;
        // Rigid particles keep zero rates; a far pair has no j side here.
        let aj = aj.filter(|_| !model.rigid(j));
        let ri = model.rigid(i);
        if ri && aj.is_none() {
            return;
        }
        let p = terms(i, b);
        if !ri {
            let mj = model.mass[j];
            ai.0 += p.tg * mj;
            ai.1 -= mj * (p.vij.dot(pts[i].sr2.mul_vec(p.g)) - p.shared);
        }
        if let Some(aj) = aj {
            let mi = model.mass[i];
            aj.0 -= p.tg * mi;
            aj.1 -= mi * (p.vij.dot(pts[j].sr2.mul_vec(p.g)) - p.shared);
        }
    });
    acc.into_iter().unzip()
}
