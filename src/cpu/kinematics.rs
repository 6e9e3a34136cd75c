//! Kinematic pass: the correction matrix, the colour gradient, the velocity
//! gradient, continuity and the deviatoric stress rate in one walk over the
//! neighbours (METHOD.md §5, §6, §8.1); then the boundary set and area.

use glam::DVec2;
use rayon::prelude::*;

use super::neighbours::Neighbours;
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::kernel;
use crate::scene::Correction;

/// Smallest `|det M|` accepted for the correction matrix; `M` is
/// dimensionless and ≈ I inside a body, ≈ ½ at a face, ≈ ¼ at a corner.
pub const CORRECTION_MIN_DET: f64 = 1e-3;

/// Output of the kinematic pass.
#[derive(Debug, Clone, Default)]
pub struct Kinematics {
    /// Correction matrix `L_i` (METHOD.md §5); identity without correction.
    pub l: Vec<Mat2>,
    /// Particles whose `M_i` could not be inverted and fell back to `L = I`.
    pub fallback: Vec<u32>,
    /// Colour gradient `(∇ψ)_i = −Σ_j V_j ∇_i W_ij` (METHOD.md §8.1, eq. 26).
    pub grad_psi: Vec<DVec2>,
    /// Surface particles, `h_i |∇ψ|_i` above the boundary threshold (METHOD.md
    /// §8.1): the contact's boundary set, and where the viscosity keeps the
    /// plain velocity jump.
    pub surface: Vec<bool>,
    /// Corrected velocity gradient `∇v_i` (zero on rigid particles), kept
    /// only when the viscosity reconstructs velocities with it
    /// (`Model::av_reconstruct`); empty otherwise.
    pub gv: Vec<Mat2>,
    /// Continuity `dρ/dt = −ρ tr(∇v)` (the difference form of METHOD.md §4
    /// with the corrected gradient).
    pub drho: Vec<f64>,
    /// Deviatoric stress rate ([`stress_rate`]).
    pub ds: Vec<Sym>,
}

/// One particle's sums of the kinematic walk.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    /// `M_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)`.
    m: Mat2,
    /// `Σ_j V_j (v_j − v_i) ⊗ ∇_i W_ij`.
    gsum: Mat2,
    /// `(∇ψ)_i`.
    gpsi: DVec2,
}

/// One particle's result of the kinematic pass.
struct Point {
    l: Mat2,
    ok: bool,
    gpsi: DVec2,
    gv: Mat2,
}

/// The kinematic pass at `st`.
///
/// `L_i = [Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)]⁻¹`, `(∇ψ)_i`, and the velocity
/// gradient `∇v_i = Σ_j V_j (v_j − v_i) ⊗ ∇̃_i W_ij` with `∇̃ = L_i ∇`.
/// Because `L_i` is particle i's own, `∇v_i = [Σ_j V_j (v_j − v_i) ⊗
/// ∇_i W_ij] L_iᵀ`: the uncorrected sum is gathered in the same walk as
/// `M_i` and corrected once at the end, so one pass over the neighbours
/// serves what would otherwise take two.
///
/// The walk visits each pair once ([`Neighbours::sweep`]): with
/// `∇_j W_ji = −∇_i W_ij`, particle j's terms are i's outer products
/// `∇_i W_ij ⊗ (x_j − x_i)` and `(v_j − v_i) ⊗ ∇_i W_ij` weighted by `V_i`
/// instead of `V_j`, and its colour-gradient term changes sign.
pub fn kinematics(model: &Model, st: &State, nb: &Neighbours) -> Kinematics {
    let corrected = model.correction == Correction::Gradient;
    let vol: Vec<f64> = (0..model.len())
        .into_par_iter()
        .map(|j| model.mass[j] / st.rho[j])
        .collect();
    let mut sums = vec![Sums::default(); model.len()];
    nb.sweep(model, &st.x, &mut sums, |i, b, si, sj| {
        let j = b.j as usize;
        let (dx, dv) = (st.x[j] - st.x[i], st.v[j] - st.v[i]);
        let gi = b.gw * vol[j];
        si.m += Mat2::outer(gi, dx);
        si.gsum += Mat2::outer(dv, gi);
        si.gpsi -= gi;
        if let Some(sj) = sj {
            let gj = b.gw * vol[i];
            sj.m += Mat2::outer(gj, dx);
            sj.gsum += Mat2::outer(dv, gj);
            sj.gpsi += gj;
        }
    });
    let per: Vec<Point> = sums
        .into_par_iter()
        .enumerate()
        .map(|(i, Sums { mut m, gsum, gpsi })| {
            let (l, ok) = if !corrected {
                (Mat2::IDENTITY, true)
            } else {
                if model.dim == 1 {
                    // 1-D: L is the scalar 1/M_xx; keep the unused yy entry neutral.
                    m.yy = 1.0;
                }
                match m.inverse(CORRECTION_MIN_DET) {
                    Some(l) => (l, true),
                    None => (Mat2::IDENTITY, false),
                }
            };
            let gv = if model.rigid(i) {
                Mat2::ZERO
            } else {
                gsum.mul_transpose(&l)
            };
            Point { l, ok, gpsi, gv }
        })
        .collect();
    let n = per.len();
    let mut out = Kinematics {
        l: Vec::with_capacity(n),
        fallback: Vec::new(),
        grad_psi: Vec::with_capacity(n),
        surface: Vec::with_capacity(n),
        gv: Vec::with_capacity(if model.av_reconstruct { n } else { 0 }),
        drho: Vec::with_capacity(n),
        ds: Vec::with_capacity(n),
    };
    for (i, p) in per.into_iter().enumerate() {
        out.l.push(p.l);
        out.surface
            .push(model.h[i] * p.gpsi.length() > model.boundary_threshold);
        out.grad_psi.push(p.gpsi);
        if !p.ok {
            out.fallback.push(i as u32);
        }
        if model.rigid(i) {
            out.drho.push(0.0);
            out.ds.push(Sym::default());
        } else {
            out.drho.push(-st.rho[i] * p.gv.trace());
            out.ds
                .push(stress_rate(model.material(i).g, &st.s[i], &p.gv));
        }
        if model.av_reconstruct {
            out.gv.push(p.gv);
        }
    }
    out
}

/// Boundary particles, outward normals and the contact area each represents.
#[derive(Debug, Clone, Default)]
pub struct Boundary {
    /// Outward unit normal on the boundary particles, zero elsewhere.
    pub normal: Vec<DVec2>,
    pub is_boundary: Vec<bool>,
    /// Contact area `A_i` (1 in 1-D; a kernel measure of the boundary line
    /// in 2-D) on the boundary particles, zero elsewhere.
    pub area: Vec<f64>,
    /// The boundary particles in ascending order: the contact's work goes
    /// over these alone (some hundreds in a body of 1e5 particles).
    pub list: Vec<u32>,
}

/// `n_i = ∇ψ/|∇ψ|` for the boundary set of pass A ([`PassA::surface`]), and
/// `A_i = (15/(7π h)) / Σ_j W_ij` over the body's boundary particles, self
/// included (METHOD.md §8.4, "Contact area"), at positions `x`.
pub fn boundary(
    model: &Model,
    x: &[DVec2],
    nb: &Neighbours,
    grad_psi: &[DVec2],
    is_boundary: Vec<bool>,
) -> Boundary {
    let n = model.len();
    let list: Vec<u32> = (0..n as u32)
        .into_par_iter()
        .filter(|&i| is_boundary[i as usize])
        .collect();
    let mut normal = vec![DVec2::ZERO; n];
    let mut area = vec![0.0; n];
    let per: Vec<(DVec2, f64)> = list
        .par_iter()
        .map(|&i| {
            let i = i as usize;
            let a = if model.dim == 1 {
                1.0
            } else {
                let h = model.h[i];
                let mut sw = kernel::w(2, 0.0, h);
                for b in nb.of(model, x, i) {
                    if is_boundary[b.j as usize] {
                        sw += b.w;
                    }
                }
                kernel::line_integral_2d(h) / sw
            };
            (grad_psi[i].normalize_or_zero(), a)
        })
        .collect();
    for (&i, (n_i, a_i)) in list.iter().zip(per) {
        normal[i as usize] = n_i;
        area[i as usize] = a_i;
    }
    Boundary {
        normal,
        is_boundary,
        area,
        list,
    }
}

/// Jaumann-rate hypoelastic deviatoric stress rate (METHOD.md §6):
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
