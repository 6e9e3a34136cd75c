//! The artificial viscosity (docs/method.md §4): Monaghan's `Π_ij` on the
//! velocity jump, reconstructed to the pair's midpoint where the field is
//! smooth.

use glam::DVec2;

use crate::math::Mat2;

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

/// Monaghan's `Π_ij` (docs/method.md §4), zero for receding pairs.
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
