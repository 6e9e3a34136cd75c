//! 2-D Hertz line contact of two identical disks (the paper's case 3),
//! and a disk on a rigid wall.

use crate::physics::material::MaterialModel;
use std::f64::consts::{FRAC_PI_2, LN_2, PI};

use super::tanh_sinh;

// ---------------------------------------------------------------------------
// 2-D quasi-static Hertz line contact of two identical disks (docs/method.md §10,
// case 3)
// ---------------------------------------------------------------------------

/// Approach constant `C` of Johnson (1985) for a disk in diametral
/// compression (docs/method.md §10, case 3): the softer end of the bracket.
pub const HERTZ_C_JOHNSON: f64 = 1.0;

/// Approach constant `C = 1 + 2 ln 2 − (3 − 4ν)/(4(1 − ν))` for a free disk
/// loaded at the contact and held by its own inertia (docs/method.md §10, case 3):
/// the stiffer end of the bracket, ≈ 1.742 for steel.
pub fn hertz_c_inertia(nu: f64) -> f64 {
    1.0 + 2.0 * LN_2 - (3.0 - 4.0 * nu) / (4.0 * (1.0 - nu))
}

/// Plane-strain modulus `E' = E/(1 − ν²)` (docs/method.md §10, case 3).
pub fn plane_strain_modulus(mat: &MaterialModel) -> f64 {
    mat.e / (1.0 - mat.nu * mat.nu)
}

/// Contact half-width `a = sqrt(4 P R/(π E'))` of two identical disks of
/// radius `radius` pressed with force `force` per unit thickness (N/m).
pub fn hertz_half_width(mat: &MaterialModel, radius: f64, force: f64) -> f64 {
    (4.0 * force.max(0.0) * radius / (PI * plane_strain_modulus(mat))).sqrt()
}

/// Result of the quasi-static Hertz impact of two identical disks (docs/method.md
/// §10, case 3), per unit thickness.
#[derive(Debug, Clone, PartialEq)]
pub struct HertzImpact {
    /// Peak contact force per unit thickness, N/m.
    pub peak_force: f64,
    /// Contact duration, s.
    pub contact_time: f64,
    /// Peak approach of the two centres `δ = 2 δ1`, m.
    pub max_approach: f64,
    /// Force history `(t, P)` over the contact (s, N/m), from `(0, 0)` to
    /// `(contact_time, 0)`, symmetric about the peak (elastic, so unloading
    /// retraces loading); denser near the start and end of contact.
    pub curve: Vec<(f64, f64)>,
}

impl HertzImpact {
    /// Contact force at time `t` by linear interpolation of
    /// [`curve`](Self::curve) (relative error ~1e-5 near the peak); 0
    /// outside the contact.
    pub fn force_at(&self, t: f64) -> f64 {
        let c = &self.curve;
        if c.len() < 2 || !(t > c[0].0 && t < c[c.len() - 1].0) {
            return 0.0;
        }
        let i = c.partition_point(|p| p.0 <= t).clamp(1, c.len() - 1);
        let (t0, p0) = c[i - 1];
        let (t1, p1) = c[i];
        if t1 > t0 {
            p0 + (p1 - p0) * (t - t0) / (t1 - t0)
        } else {
            p1
        }
    }
}

/// The line-contact law of two identical disks, in the dimensionless force
/// `p = P/(π E' R)`: `a/R = 2 sqrt(p)`, hence `ln(4R/a) = ln 2 − ½ ln p` and
/// the approach of the centres `δ = 2 δ1 = 2 R p (A − ln p)` with
/// `A = 2 ln 2 − C`. Monotone for `p < exp(A − 1)` (far beyond any elastic
/// load), which bounds the valid range.
#[derive(Debug, Clone, Copy)]
struct HertzLine {
    e_prime: f64,
    radius: f64,
    a: f64,
}

impl HertzLine {
    fn new(mat: &MaterialModel, radius: f64, c: f64) -> Option<Self> {
        let e_prime = plane_strain_modulus(mat);
        let ok = e_prime.is_finite()
            && e_prime > 0.0
            && radius.is_finite()
            && radius > 0.0
            && c.is_finite();
        ok.then_some(Self {
            e_prime,
            radius,
            a: 2.0 * LN_2 - c,
        })
    }

    fn force_scale(&self) -> f64 {
        PI * self.e_prime * self.radius
    }

    /// `δ(p)`, m.
    fn approach_of_p(&self, p: f64) -> f64 {
        if p > 0.0 {
            2.0 * self.radius * p * (self.a - p.ln())
        } else {
            0.0
        }
    }

    /// Inverse of [`approach_of_p`](Self::approach_of_p): solve
    /// `q + ln(A − q) = ln(δ/2R)` for `q = ln p` (the log form stays well
    /// conditioned as `p → 0`, where δ → 0 like `p ln(1/p)`).
    fn p_of_approach(&self, delta: f64) -> Option<f64> {
        if delta <= 0.0 {
            return Some(0.0);
        }
        solve_log_equation(1.0, self.a, (delta / (2.0 * self.radius)).ln()).map(f64::exp)
    }

    /// The dimensionless stored energy is `W(p) = p² (A − ½ − ln p)`, the
    /// exact integral `U = ∫ P dδ = π E' R² W(p)`; this inverts it by solving
    /// `2q + ln(A − ½ − q) = ln W` for `q = ln p`.
    fn p_of_w(&self, w: f64) -> Option<f64> {
        if w.is_nan() || w <= 0.0 {
            return None;
        }
        solve_log_equation(2.0, self.a - 0.5, w.ln()).map(f64::exp)
    }
}

/// Solve `k q + ln(β − q) = target` on the increasing branch
/// `q < q_max = β − 1/k` (safeguarded Newton). None when `target` is at or
/// above the branch maximum (no monotone solution: the load is beyond the
/// range of the line-contact law) or not finite.
fn solve_log_equation(k: f64, beta: f64, target: f64) -> Option<f64> {
    let q_max = beta - 1.0 / k;
    let h = |q: f64| k * q + (beta - q).ln();
    if !target.is_finite() || target >= h(q_max) {
        return None;
    }
    // Lower bracket: h(q) < target.
    let mut step = 1.0;
    let mut lo = (target / k).min(q_max) - step;
    let mut guard = 0;
    while h(lo) >= target {
        step *= 2.0;
        lo -= step;
        guard += 1;
        if guard > 200 {
            return None;
        }
    }
    let mut hi = q_max;
    // Fixed-point estimate as the start, clamped into the bracket.
    let mut q = ((target - (beta - lo).ln()) / k).clamp(lo, hi);
    for _ in 0..200 {
        let f = h(q) - target;
        if f < 0.0 {
            lo = q;
        } else {
            hi = q;
        }
        let d = k - 1.0 / (beta - q);
        let mut qn = q - f / d;
        if !(qn > lo && qn < hi) {
            qn = 0.5 * (lo + hi);
        }
        if (qn - q).abs() <= 1e-15 * (1.0 + q.abs()) || hi - lo <= 1e-15 * (1.0 + q.abs()) {
            return Some(qn);
        }
        q = qn;
    }
    Some(q)
}

/// Approach of the two centres `δ = 2 δ1` (m) of identical disks under the
/// contact force `force` (N/m), `δ1 = (P/(π E'))[2 ln(4R/a) − C]` (docs/method.md
/// §10, case 3). None outside the monotone range of the law or for invalid
/// input.
pub fn hertz_approach(mat: &MaterialModel, radius: f64, c: f64, force: f64) -> Option<f64> {
    let line = HertzLine::new(mat, radius, c)?;
    if force.is_nan() || force < 0.0 {
        return None;
    }
    let p = force / line.force_scale();
    (p < (line.a - 1.0).exp()).then(|| line.approach_of_p(p))
}

/// Contact force (N/m) of identical disks at centre approach `approach` (m):
/// the numerical inverse of [`hertz_approach`]; 0 for no overlap. None beyond
/// the monotone range of the law or for invalid input.
pub fn hertz_force(mat: &MaterialModel, radius: f64, c: f64, approach: f64) -> Option<f64> {
    let line = HertzLine::new(mat, radius, c)?;
    if approach.is_nan() {
        return None;
    }
    Some(line.p_of_approach(approach)? * line.force_scale())
}

/// Number of curve intervals on each half (loading, unloading).
const HERTZ_HALF_SAMPLES: usize = 400;

/// Quasi-static Hertz impact of two identical elastic disks in plane strain
/// (docs/method.md §10, case 3): radius `radius` (m), closing speed
/// `closing_speed` (m/s, i.e. each disk at half of it), approach constant `c`
/// ([`HERTZ_C_JOHNSON`] or [`hertz_c_inertia`]).
///
/// Model: `m* δ̈ = −P(δ)`, `δ(0) = 0`, `δ̇(0) = V`, `m* = ρ π R²/2`, with
/// `P(δ)` the inverse of `δ = 2 (P/(π E'))[2 ln(4R/a) − C]`. The peak follows
/// from energy, `½ m* V² = ∫0^δmax P dδ`, whose integral is closed-form in
/// `p = P/(πE'R)`; the contact time `2 ∫ dδ/δ̇` is integrated in
/// `p = p_max sin²φ`, which removes the inverse-square-root singularity at the
/// turning point (and the logarithmic one at `p → 0`), by tanh–sinh
/// quadrature to ~1e-12.
///
/// Returns NaN fields and an empty curve for invalid input (non-positive
/// radius, speed or density) or a load beyond the range of the law; see
/// [`try_hertz_disks`].
pub fn hertz_disks(mat: &MaterialModel, radius: f64, closing_speed: f64, c: f64) -> HertzImpact {
    try_hertz_disks(mat, radius, closing_speed, c).unwrap_or(HertzImpact {
        peak_force: f64::NAN,
        contact_time: f64::NAN,
        max_approach: f64::NAN,
        curve: Vec::new(),
    })
}

/// [`hertz_disks`], with `None` for invalid input.
pub fn try_hertz_disks(
    mat: &MaterialModel,
    radius: f64,
    closing_speed: f64,
    c: f64,
) -> Option<HertzImpact> {
    let line = HertzLine::new(mat, radius, c)?;
    let v = closing_speed;
    if !(v.is_finite() && v > 0.0 && mat.rho0.is_finite() && mat.rho0 > 0.0) {
        return None;
    }
    let m_star = 0.5 * mat.rho0 * PI * radius * radius;
    // ½ m* V² = π E' R² W(p_max).
    let w_max = m_star * v * v / (2.0 * line.force_scale() * radius);
    let p_max = line.p_of_w(w_max)?;
    let a = line.a;
    let b_minus_lnpm = a - 0.5 - p_max.ln();
    // dt/dφ = [4 R p_max sqrt(B − ln p_max)/V] · sinφ (A − 1 − ln p)/sqrt(Q),
    // Q = (W_max − W)/(p_max² cos²φ), written to stay accurate at both ends.
    let prefactor = 4.0 * radius * p_max * b_minus_lnpm.sqrt() / v;
    let integrand = |phi: f64| -> f64 {
        let sin = phi.sin();
        if sin <= 0.0 {
            return 0.0;
        }
        let s = sin * sin;
        let c2 = {
            let cos = (FRAC_PI_2 - phi).sin();
            cos * cos
        };
        let ln_s = 2.0 * sin.ln();
        // s² ln(s)/cos²φ, with ln(s) = ln(1 − cos²φ) near φ = π/2.
        let tail = if c2 <= 0.0 {
            -s * s
        } else if s < 0.5 {
            s * s * ln_s / c2
        } else {
            s * s * (-c2).ln_1p() / c2
        };
        let q = b_minus_lnpm * (1.0 + s) + tail;
        let ln_p = p_max.ln() + ln_s;
        prefactor * sin * (a - 1.0 - ln_p) / q.sqrt()
    };
    let n = HERTZ_HALF_SAMPLES;
    let mut half = Vec::with_capacity(n + 1);
    half.push((0.0, 0.0));
    let mut t_acc = 0.0;
    for i in 1..=n {
        let phi0 = FRAC_PI_2 * (i - 1) as f64 / n as f64;
        let phi1 = FRAC_PI_2 * i as f64 / n as f64;
        t_acc += tanh_sinh(&integrand, phi0, phi1, 1e-13);
        let sin = phi1.sin();
        half.push((t_acc, line.force_scale() * p_max * sin * sin));
    }
    let t_half = t_acc;
    let contact_time = 2.0 * t_half;
    let peak_force = line.force_scale() * p_max;
    if !(contact_time.is_finite() && contact_time > 0.0) {
        return None;
    }
    // Exact symmetry: the last point of the loading half is the peak.
    if let Some(last) = half.last_mut() {
        *last = (t_half, peak_force);
    }
    let mut curve = half.clone();
    curve.extend(
        half.iter()
            .rev()
            .skip(1)
            .map(|&(t, p)| (contact_time - t, p)),
    );
    if let Some(last) = curve.last_mut() {
        *last = (contact_time, 0.0);
    }
    Some(HertzImpact {
        peak_force,
        contact_time,
        max_approach: line.approach_of_p(p_max),
        curve,
    })
}

/// A single disk at speed `speed` on a rigid frictionless wall (docs/method.md
/// §8.5): the same force history as two identical disks at closing speed
/// `2 speed`; `max_approach` is then the approach of the disk centre to the
/// wall, `δ1 = δ/2`.
pub fn hertz_disk_on_wall(mat: &MaterialModel, radius: f64, speed: f64, c: f64) -> HertzImpact {
    let mut h = hertz_disks(mat, radius, 2.0 * speed, c);
    h.max_approach *= 0.5;
    h
}

// ---------------------------------------------------------------------------
// 3-D Hertz impact of two elastic spheres (docs/method.md §12)
// ---------------------------------------------------------------------------

/// One body of a Hertz sphere impact: its radius, mass and contact modulus
/// `E/(1 − ν²)`; a rigid flat wall has all three infinite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzBody {
    pub radius: f64,
    pub mass: f64,
    pub modulus: f64,
}

impl HertzBody {
    /// A sphere of radius `radius` of the material `mat`.
    pub fn sphere(mat: &MaterialModel, radius: f64) -> HertzBody {
        HertzBody {
            radius,
            mass: mat.rho0 * 4.0 / 3.0 * PI * radius.powi(3),
            modulus: plane_strain_modulus(mat),
        }
    }

    /// A rigid flat wall.
    pub const WALL: HertzBody = HertzBody {
        radius: f64::INFINITY,
        mass: f64::INFINITY,
        modulus: f64::INFINITY,
    };
}

/// Peak force, contact time and peak approach of a Hertz sphere impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzSpheres {
    /// N.
    pub peak_force: f64,
    /// s.
    pub contact_time: f64,
    /// m.
    pub max_approach: f64,
}

/// The quasi-static Hertz impact of bodies `a` and `b` closing at
/// `closing_speed` (Johnson 1985, §11.4): `F = (4/3) E* √R* δ^{3/2}` with
/// `1/E* = 1/E'_a + 1/E'_b`, `1/R* = 1/R_a + 1/R_b`, `1/m* = 1/m_a +
/// 1/m_b`. Energy gives the peak approach `δ_max = (15 m* V² / (16 E*
/// √R*))^{2/5}` and the peak force; the contact time is `2 (δ_max/V)
/// ∫₀¹ (1 − x^{5/2})^{−1/2} dx` (the integral 1.471638), computed by
/// tanh–sinh quadrature.
pub fn hertz_spheres(a: HertzBody, b: HertzBody, closing_speed: f64) -> HertzSpheres {
    let inv = |x: f64, y: f64| 1.0 / (1.0 / x + 1.0 / y);
    let (m, r, e) = (
        inv(a.mass, b.mass),
        inv(a.radius, b.radius),
        inv(a.modulus, b.modulus),
    );
    let v = closing_speed;
    let d = (15.0 * m * v * v / (16.0 * e * r.sqrt())).powf(0.4);
    // x^{5/2} = sin²φ: dx/√(1 − x^{5/2}) = (4/5) sin^{−1/5}φ dφ, whose
    // end-point singularity at φ = 0 tanh–sinh integrates.
    let i = tanh_sinh(
        &|phi: f64| 0.8 * phi.sin().powf(-0.2),
        0.0,
        FRAC_PI_2,
        1e-13,
    );
    HertzSpheres {
        peak_force: 4.0 / 3.0 * e * r.sqrt() * d.powf(1.5),
        contact_time: 2.0 * d / v * i,
        max_approach: d,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validation::exact::test_support::*;

    /// docs/method.md §6 derived constants and the §10 case-3 inputs.
    #[test]
    fn steel_constants() {
        let s = steel();
        assert!(close(s.e, 199.8e9, 5e-4));
        assert!(near(s.nu, 0.298, 5e-4));
        assert!(close(plane_strain_modulus(&s), 219.3e9, 5e-4));
        let c = hertz_c_inertia(s.nu);
        println!("C_inertia(steel) = {c}");
        assert!(near(c, 1.742, 5e-4));
    }

    /// docs/method.md §10 case 3: peak 1.161 (C = 1) to 1.224 MN/m (C ≈ 1.742),
    /// contact time 8.71 to 8.30 µs.
    #[test]
    fn hertz_bracket() {
        let s = steel();
        let r = 5e-3;
        let soft = hertz_disks(&s, r, 10.0, HERTZ_C_JOHNSON);
        let stiff = hertz_disks(&s, r, 10.0, hertz_c_inertia(s.nu));
        println!(
            "Hertz C=1: peak {:.6} MN/m, t_c {:.6} us, delta_max {:.6e} m",
            soft.peak_force / 1e6,
            soft.contact_time * 1e6,
            soft.max_approach
        );
        println!(
            "Hertz C=C_inertia: peak {:.6} MN/m, t_c {:.6} us, delta_max {:.6e} m",
            stiff.peak_force / 1e6,
            stiff.contact_time * 1e6,
            stiff.max_approach
        );
        assert!(close(soft.peak_force, 1.161e6, 2e-3));
        assert!(close(soft.contact_time, 8.71e-6, 2e-3));
        assert!(close(stiff.peak_force, 1.224e6, 2e-3));
        assert!(close(stiff.contact_time, 8.30e-6, 2e-3));
        // And to the printed digits.
        assert!(near(soft.peak_force / 1e6, 1.161, 0.0005));
        assert!(near(stiff.peak_force / 1e6, 1.224, 0.0005));
        assert!(near(soft.contact_time * 1e6, 8.71, 0.005));
        assert!(near(stiff.contact_time * 1e6, 8.30, 0.005));
    }

    /// Curve shape: ≥ 200 points, from (0, 0) to (t_c, 0), monotone times,
    /// symmetric about the peak, and its impulse `∫P dt = 2 m* V` (the
    /// relative velocity reverses).
    #[test]
    fn hertz_curve() {
        let s = steel();
        let (r, v) = (5e-3, 10.0);
        let h = hertz_disks(&s, r, v, hertz_c_inertia(s.nu));
        let c = &h.curve;
        assert!(c.len() >= 200);
        assert_eq!(c[0], (0.0, 0.0));
        assert_eq!(c[c.len() - 1], (h.contact_time, 0.0));
        assert!(c.windows(2).all(|w| w[1].0 > w[0].0));
        let n = c.len();
        for i in 0..n {
            let (t, p) = c[i];
            let (tm, pm) = c[n - 1 - i];
            assert!(near(t + tm, h.contact_time, 1e-15));
            assert_eq!(p, pm);
        }
        let peak = c.iter().map(|p| p.1).fold(0.0, f64::max);
        assert_eq!(peak, h.peak_force);
        assert!(near(c[n / 2].0, 0.5 * h.contact_time, 1e-18));
        let impulse: f64 = c
            .windows(2)
            .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
            .sum();
        let m_star = 0.5 * s.rho0 * PI * r * r;
        assert!(close(impulse, 2.0 * m_star * v, 1e-4), "{impulse}");
        assert!(close(h.force_at(0.5 * h.contact_time), h.peak_force, 1e-12));
        assert_eq!(h.force_at(-1.0), 0.0);
        assert_eq!(h.force_at(2.0 * h.contact_time), 0.0);
    }

    /// Energy: ½ m* V² = ∫0^δmax P(δ) dδ with P(δ) from the numerical
    /// inversion (independent of the closed form), and the inversion is
    /// consistent with the forward law.
    #[test]
    fn hertz_energy_and_inversion() {
        let s = steel();
        let (r, v) = (5e-3, 10.0);
        for c in [HERTZ_C_JOHNSON, hertz_c_inertia(s.nu)] {
            let h = hertz_disks(&s, r, v, c);
            let dmax = h.max_approach;
            let back = hertz_approach(&s, r, c, h.peak_force).expect("in range");
            assert!(close(back, dmax, 1e-14));
            for &f in &[1e-6, 1.0, 1e3, 1e6, 2e6] {
                let d = hertz_approach(&s, r, c, f).expect("in range");
                let p = hertz_force(&s, r, c, d).expect("in range");
                assert!(close(p, f, 1e-12), "{f}: {p}");
            }
            assert_eq!(hertz_force(&s, r, c, 0.0), Some(0.0));
            assert_eq!(hertz_force(&s, r, c, -1e-9), Some(0.0));
            // Simpson on δ ∈ [0, δmax]; refine near 0 with δ = δmax u².
            let n = 40000;
            let g = |u: f64| {
                let d = dmax * u * u;
                hertz_force(&s, r, c, d).unwrap_or(f64::NAN) * 2.0 * dmax * u
            };
            let hstep = 1.0 / n as f64;
            let mut sum = g(0.0) + g(1.0);
            for i in 1..n {
                let w = if i % 2 == 1 { 4.0 } else { 2.0 };
                sum += w * g(i as f64 * hstep);
            }
            let work = sum * hstep / 3.0;
            let m_star = 0.5 * s.rho0 * PI * r * r;
            let kinetic = 0.5 * m_star * v * v;
            println!("C = {c}: work {work} J/m, kinetic {kinetic} J/m");
            assert!(close(work, kinetic, 1e-8), "{work} vs {kinetic}");
        }
    }

    /// Independent check of the quadrature: integrate m* δ̈ = −P(δ) with RK4
    /// and locate the return to δ = 0 by interpolation.
    #[test]
    fn hertz_ode_cross_check() {
        let s = steel();
        let (r, v) = (5e-3, 10.0);
        let m_star = 0.5 * s.rho0 * PI * r * r;
        for c in [HERTZ_C_JOHNSON, hertz_c_inertia(s.nu)] {
            let h = hertz_disks(&s, r, v, c);
            let acc = |d: f64| -hertz_force(&s, r, c, d).unwrap_or(f64::NAN) / m_star;
            let dt = h.contact_time / 20_000.0;
            let (mut t, mut d, mut u) = (0.0, 0.0, v);
            let mut p_peak: f64 = 0.0;
            loop {
                let (k1d, k1u) = (u, acc(d));
                let (k2d, k2u) = (u + 0.5 * dt * k1u, acc(d + 0.5 * dt * k1d));
                let (k3d, k3u) = (u + 0.5 * dt * k2u, acc(d + 0.5 * dt * k2d));
                let (k4d, k4u) = (u + dt * k3u, acc(d + dt * k3d));
                let dn = d + dt / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
                let un = u + dt / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
                if dn <= 0.0 && t > 0.0 {
                    let tc = t + dt * d / (d - dn);
                    println!("C = {c}: ODE t_c {tc:e}, quadrature {:e}", h.contact_time);
                    assert!(close(tc, h.contact_time, 1e-4));
                    assert!(near(un, -v, 1e-3 * v));
                    break;
                }
                t += dt;
                d = dn;
                u = un;
                p_peak = p_peak.max(-acc(d) * m_star);
                assert!(t < 2.0 * h.contact_time);
            }
            assert!(close(p_peak, h.peak_force, 1e-6));
        }
    }

    /// docs/method.md §8.5: a disk at V on a rigid wall equals two disks at 2V.
    #[test]
    fn hertz_wall() {
        let s = steel();
        let w = hertz_disk_on_wall(&s, 5e-3, 5.0, HERTZ_C_JOHNSON);
        let d = hertz_disks(&s, 5e-3, 10.0, HERTZ_C_JOHNSON);
        assert_eq!(w.peak_force, d.peak_force);
        assert_eq!(w.contact_time, d.contact_time);
        assert_eq!(w.max_approach, 0.5 * d.max_approach);
    }

    #[test]
    fn hertz_invalid_input() {
        let s = steel();
        assert!(try_hertz_disks(&s, 5e-3, 0.0, 1.0).is_none());
        assert!(try_hertz_disks(&s, -5e-3, 10.0, 1.0).is_none());
        assert!(try_hertz_disks(&s, 5e-3, 1e12, 1.0).is_none());
        assert!(hertz_disks(&s, 5e-3, f64::NAN, 1.0).peak_force.is_nan());
    }

    /// The contact time's integral is `(2/5) B(2/5, 1/2)` = 1.471638...
    /// (Γ(2/5) = 2.2181595437577, Γ(9/10) = 1.0686287021193), and two
    /// identical spheres give Johnson's `t = 2.868 (m*²/(R* E*² V))^{1/5}`.
    #[test]
    fn hertz_spheres_by_hand() {
        let integral = 0.4 * 2.218_159_543_757_688 * PI.sqrt() / 1.068_628_702_119_319;
        let ball = HertzBody {
            radius: 0.005,
            mass: 0.004,
            modulus: 2.2e11,
        };
        let h = hertz_spheres(ball, ball, 10.0);
        let d = (15.0 * 0.002 * 100.0 / (16.0 * 1.1e11 * 0.0025f64.sqrt())).powf(0.4);
        assert!((h.max_approach / d - 1.0).abs() < 1e-14);
        assert!((h.contact_time / (2.0 * d / 10.0 * integral) - 1.0).abs() < 1e-10);
        let scale = (0.002f64.powi(2) / (0.0025 * 1.1e11f64.powi(2) * 10.0)).powf(0.2);
        assert!((h.contact_time / scale / 2.868_266 - 1.0).abs() < 1e-6);
        let f = 4.0 / 3.0 * 1.1e11 * 0.0025f64.sqrt() * d.powf(1.5);
        assert!((h.peak_force / f - 1.0).abs() < 1e-14);
        // A sphere on a rigid wall at V is one of two spheres closing at 2V.
        let wall = hertz_spheres(ball, HertzBody::WALL, 5.0);
        let pair = hertz_spheres(ball, ball, 10.0);
        assert!((wall.peak_force / pair.peak_force - 1.0).abs() < 1e-12);
        assert!((wall.contact_time / pair.contact_time - 1.0).abs() < 1e-12);
    }
}
