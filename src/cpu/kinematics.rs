//! Kinematic passes: the correction matrix and colour gradient (pass A), then
//! the boundary set and area, the velocity gradient, continuity and the
//! deviatoric stress rate (pass B).

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

/// Output of pass A.
#[derive(Debug, Clone, Default)]
pub struct PassA {
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
}

/// Pass A: `L_i = [Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)]⁻¹` and `(∇ψ)_i`.
pub fn correction_and_colour(model: &Model, st: &State, nb: &Neighbours) -> PassA {
    let corrected = model.correction == Correction::Gradient;
    let per: Vec<(Mat2, bool, DVec2)> = (0..model.len())
        .into_par_iter()
        .map(|i| {
            let mut m = Mat2::ZERO;
            let mut gpsi = DVec2::ZERO;
            for b in nb.of(i) {
                let j = b.j as usize;
                let vj = model.mass[j] / st.rho[j];
                m += Mat2::outer(b.gw * vj, st.x[j] - st.x[i]);
                gpsi -= b.gw * vj;
            }
            if !corrected {
                return (Mat2::IDENTITY, true, gpsi);
            }
            if model.dim == 1 {
                // 1-D: L is the scalar 1/M_xx; keep the unused yy entry neutral.
                m.yy = 1.0;
            }
            match m.inverse(CORRECTION_MIN_DET) {
                Some(l) => (l, true, gpsi),
                None => (Mat2::IDENTITY, false, gpsi),
            }
        })
        .collect();
    let mut out = PassA {
        l: Vec::with_capacity(per.len()),
        fallback: Vec::new(),
        grad_psi: Vec::with_capacity(per.len()),
        surface: Vec::with_capacity(per.len()),
    };
    for (i, (l, ok, g)) in per.into_iter().enumerate() {
        out.l.push(l);
        out.surface
            .push(model.h[i] * g.length() > model.boundary_threshold);
        out.grad_psi.push(g);
        if !ok {
            out.fallback.push(i as u32);
        }
    }
    out
}

/// Boundary particles, outward normals and the contact area each represents.
#[derive(Debug, Clone, Default)]
pub struct Boundary {
    pub normal: Vec<DVec2>,
    pub is_boundary: Vec<bool>,
    /// Contact area `A_i` (1 in 1-D; a kernel measure of the boundary line in 2-D).
    pub area: Vec<f64>,
}

/// `n_i = ∇ψ/|∇ψ|` for the boundary set of pass A ([`PassA::surface`]), and
/// `A_i = (15/(7π h)) / Σ_j W_ij` over the body's boundary particles, self
/// included (METHOD.md §8.4, "Contact area").
pub fn boundary(
    model: &Model,
    nb: &Neighbours,
    grad_psi: &[DVec2],
    is_boundary: Vec<bool>,
) -> Boundary {
    let n = model.len();
    let normal: Vec<DVec2> = grad_psi.iter().map(|g| g.normalize_or_zero()).collect();
    let area = (0..n)
        .into_par_iter()
        .map(|i| {
            if !is_boundary[i] {
                return 0.0;
            }
            if model.dim == 1 {
                return 1.0;
            }
            let h = model.h[i];
            let mut sw = kernel::w(2, 0.0, h);
            for b in nb.of(i) {
                if is_boundary[b.j as usize] {
                    sw += b.w;
                }
            }
            kernel::line_integral_2d(h) / sw
        })
        .collect();
    Boundary {
        normal,
        is_boundary,
        area,
    }
}

/// Velocity gradient `∇v_i = Σ_j V_j (v_j − v_i) ⊗ ∇̃_i W_ij` (METHOD.md §6).
#[inline]
pub fn velocity_gradient(model: &Model, st: &State, nb: &Neighbours, l: &Mat2, i: usize) -> Mat2 {
    let mut g = Mat2::ZERO;
    for b in nb.of(i) {
        let j = b.j as usize;
        let vj = model.mass[j] / st.rho[j];
        g += Mat2::outer((st.v[j] - st.v[i]) * vj, l.mul_vec(b.gw));
    }
    g
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

/// Pass B: continuity `dρ/dt = −ρ tr(∇v)` (the difference form of METHOD.md
/// §4 with the corrected gradient), the stress rate, and the velocity
/// gradient itself when pass C reconstructs velocities with it (empty
/// otherwise).
pub struct PassB {
    pub drho: Vec<f64>,
    pub ds: Vec<Sym>,
    pub gv: Vec<Mat2>,
}

pub fn density_and_stress_rates(model: &Model, st: &State, nb: &Neighbours, l: &[Mat2]) -> PassB {
    let per: Vec<(f64, Sym, Mat2)> = (0..model.len())
        .into_par_iter()
        .map(|i| {
            if model.rigid(i) {
                return (0.0, Sym::default(), Mat2::default());
            }
            let gv = velocity_gradient(model, st, nb, &l[i], i);
            let drho = -st.rho[i] * gv.trace();
            (drho, stress_rate(model.material(i).g, &st.s[i], &gv), gv)
        })
        .collect();
    let keep_gv = model.av_reconstruct;
    let mut out = PassB {
        drho: Vec::with_capacity(per.len()),
        ds: Vec::with_capacity(per.len()),
        gv: Vec::with_capacity(if keep_gv { per.len() } else { 0 }),
    };
    for (d, s, g) in per {
        out.drho.push(d);
        out.ds.push(s);
        if keep_gv {
            out.gv.push(g);
        }
    }
    out
}
