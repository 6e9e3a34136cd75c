//! The contact's boundary: each boundary particle's outward normal and
//! contact area, measured in the forces stage as on the GPU (forces.wgsl).

use super::*;
use crate::cpu::kinematics::surface_measure;
use crate::physics::kernel;
use rayon::prelude::*;

/// Boundary particles, outward normals and the contact area each represents.
#[derive(Debug, Clone, Default)]
pub struct Boundary {
    /// Outward unit normal on the boundary particles, zero elsewhere.
    pub normal: Vec<DVec2>,
    /// `|∇ψ|` on the boundary particles, zero elsewhere: how fast the
    /// normal turns as the colour gradient changes.
    pub grad_norm: Vec<f64>,
    pub is_boundary: Vec<bool>,
    /// Contact area `A_i` (1 in 1-D; a kernel measure of the boundary line
    /// in 2-D) on the boundary particles, zero elsewhere.
    pub area: Vec<f64>,
    /// The boundary particles in ascending order: the contact's work goes
    /// over these alone (some hundreds in a body of 1e5 particles).
    pub list: Vec<u32>,
    /// In a body of revolution, each particle's [`surface_measure`] from
    /// the kinematic pass, which the contact's surface ramp reads
    /// ([`contact::surface_ramp`](super::contact::surface_ramp)); empty in
    /// plane strain and 1-D, where the ramp reads `h |∇ψ⁰|`.
    pub measure: Vec<f64>,
}

/// What the contact's surface ramp reads in a body of revolution: each
/// particle's [`surface_measure`] of the kinematic pass `k`, the measure
/// the boundary set was chosen by; empty elsewhere and without contact.
/// Unnormalised, `h |∇ψ⁰|` of the face's axis particle of a spread Taylor
/// bar fell to the threshold while `h |∇ψ| / ψ` stayed at 0.66: the ramp
/// let go of a particle that was still a boundary particle pressed on the
/// wall, and it sank into it.
pub fn contact_measure(model: &Model, k: &Kinematics) -> Vec<f64> {
    if !model.axisymmetric || !model.contact {
        return Vec::new();
    }
    (0..model.len())
        .into_par_iter()
        .map(|i| surface_measure(model, i, k.grad_psi[i], k.psi.get(i).copied()))
        .collect()
}

/// [`boundary`] of the kinematics pass `k`: its surface set and, in a body
/// of revolution, its [`contact_measure`]. For callers outside the step,
/// which keeps `k`'s surface set by moving it.
pub fn boundary_of(model: &Model, x: &[DVec2], nb: &Neighbours, k: &Kinematics) -> Boundary {
    boundary(model, x, nb, k.surface.clone(), contact_measure(model, k))
}

/// The boundary set of the kinematics pass ([`Kinematics::surface`]), with
/// each boundary particle's outward normal `n_i = g_i/|g_i|` and contact
/// area `A_i = (15/(7π h)) / Σ_j W_ij` over the body's boundary particles,
/// self included (docs/method.md §8.4, "Contact area"), at positions `x`.
///
/// `g_i = −Σ_j V⁰_j ∇_i W_ij` is the colour gradient with the reference
/// volumes `V⁰ = m/ρ₀` where the kinematics pass has the current ones: the
/// normals, and with them the penalty spring's stored energy, are then
/// functions of the positions alone, so the spring's force (their
/// gradient) does all the work the stored energy gains or loses. With the
/// current volumes the energy also moves with the densities, work that no
/// force does: 0.7 % of the total at the height of two steel disks'
/// contact at R/Δx 20.
pub fn boundary(
    model: &Model,
    x: &[DVec2],
    nb: &Neighbours,
    is_boundary: Vec<bool>,
    measure: Vec<f64>,
) -> Boundary {
    let n = model.len();
    let list: Vec<u32> = (0..n as u32)
        .into_par_iter()
        .filter(|&i| is_boundary[i as usize])
        .collect();
    let mut normal = vec![DVec2::ZERO; n];
    let mut grad_norm = vec![0.0; n];
    let mut area = vec![0.0; n];
    // In a body of revolution the images across the axis are neighbours
    // too, and a particle's area is its ring's.
    let per: Vec<(DVec2, f64)> = list
        .par_iter()
        .map(|&i| {
            let i = i as usize;
            let h = model.h[i];
            // A particle on a symmetry plane counts for its share here, its
            // image for the rest, and represents its share of the area.
            let mut sw = model.share(i) * kernel::w(2, 0.0, h);
            let mut g = DVec2::ZERO;
            for (b, _) in nb.round_with_images(model, x, i) {
                let j = b.j as usize;
                g -= b.gw * model.reference_volume(j);
                if is_boundary[j] {
                    sw += model.share(j) * b.w;
                }
            }
            let a = if model.dim == 1 {
                1.0
            } else if model.axisymmetric {
                kernel::line_integral_2d(h) / sw * crate::math::circumference(x[i].x)
            } else {
                kernel::line_integral_2d(h) / sw
            } * model.share(i);
            (g, a)
        })
        .collect();
    for (&i, (g, a_i)) in list.iter().zip(per) {
        normal[i as usize] = g.normalize_or_zero();
        grad_norm[i as usize] = g.length();
        area[i as usize] = a_i;
    }
    Boundary {
        normal,
        grad_norm,
        is_boundary,
        area,
        list,
        measure,
    }
}
