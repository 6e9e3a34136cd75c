//! Kinematic pass: the correction matrix, the colour gradient, the velocity
//! gradient, continuity and the deviatoric stress rate in one walk over the
//! neighbours (docs/method.md §5, §6, §8.1); the EOS and the stress the momentum
//! pass reads; then the boundary set and area.

use glam::DVec2;
use rayon::prelude::*;
use std::borrow::Cow;

use super::axis;
use super::forces::StressPoint;
use super::neighbours::Neighbours;
use crate::math::{Mat2, Sym};
use crate::model::{Model, State};
use crate::physics::kernel;
use crate::physics::{material, strength, tension};
use crate::scene::Correction;

/// Output of the kinematic pass.
#[derive(Debug, Clone, Default)]
pub struct Kinematics {
    /// Correction matrix `L_i` (docs/method.md §5); identity without correction.
    pub l: Vec<Mat2>,
    /// Particles whose `M_i` could not be inverted and fell back to `L = I`.
    pub fallback: Vec<u32>,
    /// Colour gradient `(∇ψ)_i = −Σ_j V_j ∇_i W_ij` (docs/method.md §8.1, eq. 26).
    pub grad_psi: Vec<DVec2>,
    /// Surface particles, [`surface_measure`] above the boundary threshold
    /// (docs/method.md §8.1): the contact's boundary set, and where the
    /// viscosity keeps the plain velocity jump.
    pub surface: Vec<bool>,
    /// The colour function `ψ_i = Σ_j V_j W_ij`, i included, in a body of
    /// revolution ([`surface_measure`]); empty in plane strain.
    pub psi: Vec<f64>,
    /// Corrected velocity gradient `∇v_i` (zero on rigid particles) of the
    /// velocities the viscosity sees (the state's, or the leapfrog's
    /// predicted ones, [`super::sweep::kinematics_seen`]), kept only when the viscosity
    /// reconstructs velocities with it (`Model::av_reconstruct`) or the
    /// hourglass control is on (`Model::hourglass`); empty otherwise.
    /// Where the correction falls back and the hourglass control is on,
    /// the least-squares fit instead (`kernel::fit_inverse`).
    pub gv: Vec<Mat2>,
    /// The velocities the hourglass control sees and their gradient (the
    /// least-squares fit where the correction falls back), when they are
    /// not those of [`Kinematics::gv`]: in the leapfrog's step the state's
    /// `v_{n+½}` of the kinematic walk, where the viscosity sees the
    /// predicted velocities (docs/method.md, "Hourglass control"). Empty
    /// otherwise: the control then sees the state's velocities and `gv`.
    pub hv: Vec<DVec2>,
    pub hgrad: Vec<Mat2>,
    /// The state's velocity gradient, where supports adapt (they are
    /// carried with it, [`super::advance::carry_supports`]); empty
    /// otherwise.
    pub lv: Vec<Mat2>,
    /// The state's corrected velocity gradient (zero on rigid particles)
    /// when the dispersion correction is on ([`super::dispersion`]);
    /// empty otherwise.
    pub g: Vec<Mat2>,
    /// Continuity `dρ/dt = −ρ tr(∇v)` (the difference form of docs/method.md §4
    /// with the corrected gradient).
    pub drho: Vec<f64>,
    /// Deviatoric stress rate ([`stress_rate`]).
    pub ds: Vec<Sym>,
    /// Equivalent strain rate ([`strength::equivalent_strain_rate`]) when a
    /// material's laws depend on it (`Model::strain_rate`); empty otherwise.
    pub rate: Vec<f64>,
}

/// One particle's sums of the kinematic walk; `S` the sum of the velocity
/// gradient the viscosity sees, when it sees other velocities than the
/// state's ([`Seen`]).
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::cpu) struct Sums<S> {
    /// `M_i = Σ_j V_j ∇_i W_ij ⊗ (x_j − x_i)`.
    pub(in crate::cpu) m: Mat2,
    /// `Σ_j V_j (v_j − v_i) ⊗ ∇_i W_ij`.
    pub(in crate::cpu) gsum: Mat2,
    /// `(∇ψ)_i`.
    pub(in crate::cpu) gpsi: DVec2,
    /// `Σ_j V_j W_ij` over the colour gradient's pairs, the particle itself
    /// left out (bodies of revolution only: [`surface_measure`]).
    pub(in crate::cpu) psi: f64,
    pub(in crate::cpu) seen: S,
    /// Same-body partners in the gradient sums, images included (the
    /// debris floor, [`Model::debris_neighbours`]).
    pub(in crate::cpu) n: u32,
}

impl<S> Sums<S> {
    /// Adds neighbour j's colour terms, of kernel gradient `gw` (`∇_i W`)
    /// and value `w`, volume `vol`: `∇ψ` always, `ψ` in a body of
    /// revolution (`axi`) only.
    #[inline]
    pub(in crate::cpu) fn add_colour(&mut self, gw: DVec2, w: f64, vol: f64, axi: bool) {
        self.gpsi -= gw * vol;
        if axi {
            self.psi += w * vol;
        }
    }
}

/// The kinematic walk's velocities and sum for the velocity gradient of the
/// velocities the viscosity sees: none (`()`, they are the state's; the
/// walk reads the state's velocities `v`), or (`Mat2`) `Σ_j V_j (v*_j −
/// v*_i) ⊗ ∇_i W_ij`, the walk reading `[v, v*]` of a particle together.
pub(in crate::cpu) trait Seen: Copy + Default + Send + Sync {
    type Vel: Copy + Send + Sync;
    /// Each particle's velocities for the walk, from the state's `v` and
    /// the `seen` ones.
    fn vel<'a>(v: &'a [DVec2], seen: &[DVec2]) -> Cow<'a, [Self::Vel]>;
    fn v(vel: Self::Vel) -> DVec2;
    /// The velocities of a particle's mirror image across the axis.
    fn mirror(vel: Self::Vel) -> Self::Vel;
    fn add(&mut self, vj: Self::Vel, vi: Self::Vel, g: DVec2);
    fn sum(self) -> Option<Mat2>;
}

impl Seen for () {
    type Vel = DVec2;
    fn vel<'a>(v: &'a [DVec2], _: &[DVec2]) -> Cow<'a, [DVec2]> {
        Cow::Borrowed(v)
    }
    #[inline]
    fn v(vel: DVec2) -> DVec2 {
        vel
    }
    #[inline]
    fn mirror(vel: DVec2) -> DVec2 {
        axis::mirror(vel)
    }
    #[inline]
    fn add(&mut self, _: DVec2, _: DVec2, _: DVec2) {}
    fn sum(self) -> Option<Mat2> {
        None
    }
}

impl Seen for Mat2 {
    type Vel = [DVec2; 2];
    fn vel<'a>(v: &'a [DVec2], seen: &[DVec2]) -> Cow<'a, [[DVec2; 2]]> {
        Cow::Owned(v.par_iter().zip(seen).map(|(&v, &s)| [v, s]).collect())
    }
    #[inline]
    fn v(vel: [DVec2; 2]) -> DVec2 {
        vel[0]
    }
    #[inline]
    fn mirror(vel: [DVec2; 2]) -> [DVec2; 2] {
        vel.map(axis::mirror)
    }
    #[inline]
    fn add(&mut self, vj: [DVec2; 2], vi: [DVec2; 2], g: DVec2) {
        *self += Mat2::outer(vj[1] - vi[1], g);
    }
    fn sum(self) -> Option<Mat2> {
        Some(self)
    }
}

/// One particle's result of the kinematic pass.
struct Point {
    l: Mat2,
    ok: bool,
    /// The colour function, i included, in a body of revolution.
    psi: Option<f64>,
    gpsi: DVec2,
    gv: Mat2,
    /// `∇v` of the velocities the viscosity sees, when not the state's.
    gv_seen: Option<Mat2>,
    /// The least-squares `∇v` (of the seen velocities) where the
    /// correction fell back and the hourglass control is on.
    fit: Option<Mat2>,
    /// The hourglass control's `∇v` of the state's velocities, where the
    /// viscosity sees others (the leapfrog).
    hgrad: Option<Mat2>,
}

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

/// The [`StressPoint`] of pressure `p`, sound speed `c` and deviatoric
/// stress `s` at `η`, `x` and density `rho`, with its artificial stress if
/// `art`.
#[inline]
fn point_of(
    model: &Model,
    art: bool,
    (eta, x): (f64, DVec2),
    rho: f64,
    (p, c): (f64, f64),
    s: &Sym,
) -> StressPoint {
    let sigma = material::cauchy(p, s);
    let r = match model.artificial_stress.filter(|_| art) {
        Some(a) if model.axisymmetric => {
            tension::artificial_stress(a.epsilon, &sigma, rho).scale(rho / eta)
        }
        Some(a) => tension::artificial_stress(a.epsilon, &sigma, rho),
        None => Sym::default(),
    };
    StressPoint {
        sr2: sigma.scale(1.0 / (eta * rho)),
        r,
        c,
        hoop: if model.axisymmetric {
            sigma.zz / (x.x * rho)
        } else {
            0.0
        },
    }
}

impl Kinematics {
    /// Whether each particle is debris ([`debris_point`]): on the
    /// fallback list and not rigid; empty when none is.
    pub fn debris_flags(&self, model: &Model) -> Vec<bool> {
        let mut flags = Vec::new();
        if let Some(&last) = self.fallback.iter().max() {
            flags.resize(last as usize + 1, false);
            for &i in &self.fallback {
                flags[i as usize] = !model.rigid(i as usize);
            }
        }
        flags
    }
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
///
/// Each particle's sums are gathered over its own neighbours, as the
/// shader does; the solver runs the same sums pair by pair
/// ([`super::sweep::kinematics()`], equal to round-off).
pub fn kinematics(model: &Model, st: &State, nb: &Neighbours) -> Kinematics {
    let vol = volumes(model, st);
    let mut sums: Vec<Sums<()>> = (0..model.len())
        .map(|i| {
            let mut sum = Sums::<()>::default();
            for b in nb.of(model, st.frame(), i) {
                let j = b.j as usize;
                let gm = b.gw * gradient_weight(model, st, &vol, i, j);
                sum.m += Mat2::outer(gm, st.x[j] - st.x[i]);
                sum.gsum += Mat2::outer(st.v[j] - st.v[i], gm);
                sum.add_colour(b.gw, b.w, vol[j], model.axisymmetric);
                sum.n += u32::from(b.q2 > 0.0);
            }
            sum
        })
        .collect();
    if model.axisymmetric {
        axis::add_kinematics(model, st, nb, &vol, &st.v, &mut sums);
    }
    round_colour(model, st, nb, &vol, &mut sums);
    finish(model, st, sums)
}

/// Where supports adapt, each particle's colour gradient with the round
/// supports of the bodies' `h` instead of its own, images included: the
/// surface set it decides is then a function of the positions alone, as
/// the contact's normals are, and does not switch as the supports turn
/// (docs/method.md, "Supports that follow the deformation"). Nothing with
/// round supports.
pub(in crate::cpu) fn round_colour<S: Seen>(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    vol: &[f64],
    sums: &mut [Sums<S>],
) {
    if st.round_supports() {
        return;
    }
    sums.par_iter_mut().enumerate().for_each(|(i, sum)| {
        (sum.gpsi, sum.psi) = (DVec2::ZERO, 0.0);
        for (b, _) in nb.round_with_images(model, &st.x, i) {
            sum.add_colour(b.gw, b.w, vol[b.j as usize], model.axisymmetric);
        }
    });
}

/// Neighbour j's weight in particle i's gradient sums (`M_i`, `∇v_i`):
/// its volume `vol[j]`, in a body of revolution its mass over `η_i`
/// (docs/method.md §12; the colour gradient keeps the volumes).
#[inline]
pub(in crate::cpu) fn gradient_weight(
    model: &Model,
    st: &State,
    vol: &[f64],
    i: usize,
    j: usize,
) -> f64 {
    if model.axisymmetric {
        model.mass[j] / st.rho[i]
    } else {
        vol[j]
    }
}

/// What the boundary threshold is held against (docs/method.md §8.1):
/// `h |∇ψ|`, in a body of revolution `h |∇ψ| / ψ` with `ψ` the colour
/// function itself ([`Kinematics::psi`]). The areas `m/(2π r ρ)` of the
/// particles nearest the axis do not tile the r–z plane once it spreads
/// (ψ from 0.4 to 1.5 in a Taylor bar's face): unnormalised, the face's
/// axis particle left the surface set while pressed on a wall, and
/// interior particles by the axis joined it.
#[inline]
pub fn surface_measure(model: &Model, i: usize, gpsi: DVec2, psi: Option<f64>) -> f64 {
    model.h[i] * gpsi.length() / psi.unwrap_or(1.0)
}

/// Each particle's volume `V_j = m_j / ρ_j`.
pub(in crate::cpu) fn volumes(model: &Model, st: &State) -> Vec<f64> {
    (0..model.len())
        .into_par_iter()
        .map(|j| model.mass[j] / st.rho[j])
        .collect()
}

/// The kinematic pass's results from each particle's sums: `L_i`, `∇v_i`,
/// continuity, the stress rate, the surface set.
pub(in crate::cpu) fn finish<S: Seen>(model: &Model, st: &State, sums: Vec<Sums<S>>) -> Kinematics {
    let corrected = model.correction == Correction::Gradient;
    let per: Vec<Point> = sums
        .into_par_iter()
        .enumerate()
        .map(
            |(
                i,
                Sums {
                    mut m,
                    gsum,
                    gpsi,
                    psi,
                    seen,
                    n,
                },
            )| {
                let (l, ok) = if !corrected {
                    (Mat2::IDENTITY, true)
                } else {
                    if model.dim == 1 {
                        // 1-D: L is the scalar 1/M_xx; keep the unused yy entry neutral.
                        m.yy = 1.0;
                    }
                    // Too few neighbours is debris however well M looks: a
                    // compact cluster of a few particles passes the
                    // conditioning test (docs/method.md, "Debris").
                    match kernel::correction_inverse(&m) {
                        Some(l) if n >= model.bodies[model.body[i] as usize].debris_neighbours => {
                            (l, true)
                        }
                        _ => (Mat2::IDENTITY, false),
                    }
                };
                let (gv, gv_seen) = if model.rigid(i) {
                    (Mat2::ZERO, seen.sum().map(|_| Mat2::ZERO))
                } else {
                    (
                        gsum.mul_transpose(&l),
                        seen.sum().map(|g| g.mul_transpose(&l)),
                    )
                };
                // Where the correction falls back, the hourglass control
                // still needs the least-squares fit (kernel::fit_inverse).
                // It sees the state's velocities; with others seen (the
                // leapfrog) the viscosity keeps their plain gradient.
                let hg = model.hourglass > 0.0;
                let fit_of = |g: Mat2| {
                    (!ok && !model.rigid(i)).then(|| g.mul_transpose(&kernel::fit_inverse(&m)))
                };
                let (fit, hgrad) = match seen.sum() {
                    Some(_) if hg => (None, Some(fit_of(gsum).unwrap_or(gv))),
                    None if hg => (fit_of(gsum), None),
                    _ => (None, None),
                };
                Point {
                    l,
                    ok,
                    psi: model
                        .axisymmetric
                        .then(|| psi + model.mass[i] / st.rho[i] * kernel::w(2, 0.0, model.h[i])),
                    gpsi,
                    gv,
                    gv_seen,
                    fit,
                    hgrad,
                }
            },
        )
        .collect();
    let n = per.len();
    let mut out = Kinematics {
        l: Vec::with_capacity(n),
        fallback: Vec::new(),
        grad_psi: Vec::with_capacity(n),
        surface: Vec::with_capacity(n),
        psi: Vec::with_capacity(if model.axisymmetric { n } else { 0 }),
        gv: Vec::with_capacity(if model.keeps_gradient() { n } else { 0 }),
        hv: Vec::new(),
        hgrad: Vec::new(),
        lv: Vec::with_capacity(if model.adaptive { n } else { 0 }),
        g: Vec::with_capacity(if model.dispersion > 0.0 { n } else { 0 }),
        drho: Vec::with_capacity(n),
        ds: Vec::with_capacity(n),
        rate: Vec::with_capacity(if model.strain_rate { n } else { 0 }),
    };
    for (i, p) in per.into_iter().enumerate() {
        out.l.push(p.l);
        out.surface
            .push(surface_measure(model, i, p.gpsi, p.psi) > model.boundary_threshold);
        if let Some(psi) = p.psi {
            out.psi.push(psi);
        }
        out.grad_psi.push(p.gpsi);
        if !p.ok {
            out.fallback.push(i as u32);
        }
        if model.rigid(i) {
            out.drho.push(0.0);
            out.ds.push(Sym::default());
        } else {
            // η = 2π r ρ obeys the plane's continuity equation: the hoop
            // strain rate is in ρ alone (docs/method.md §12).
            out.drho.push(-st.rho[i] * p.gv.trace());
            // Debris keeps its deviatoric stress, frozen (docs/method.md,
            // "Debris").
            let g = if p.ok { model.material(i).g } else { 0.0 };
            let ds = stress_rate(g, &st.s[i], &p.gv);
            out.ds.push(if model.axisymmetric {
                axis::with_hoop(g, ds, axis::hoop_rate(st, i))
            } else {
                ds
            });
        }
        if model.keeps_gradient() {
            out.gv.push(p.fit.or(p.gv_seen).unwrap_or(p.gv));
        }
        if let Some(g) = p.hgrad {
            out.hgrad.push(g);
        }
        if model.adaptive {
            out.lv.push(p.gv);
        }
        if model.dispersion > 0.0 {
            out.g.push(p.gv);
        }
        if model.strain_rate {
            out.rate.push(if model.axisymmetric && !model.rigid(i) {
                strength::equivalent_strain_rate_3(&p.gv, axis::hoop_rate(st, i))
            } else {
                strength::equivalent_strain_rate(&p.gv)
            });
        }
    }
    if !out.hgrad.is_empty() {
        out.hv.clone_from(&st.v);
    }
    out
}

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
            let mut sw = kernel::w(2, 0.0, h);
            let mut g = DVec2::ZERO;
            for (b, _) in nb.round_with_images(model, x, i) {
                let j = b.j as usize;
                g -= b.gw * model.reference_volume(j);
                if is_boundary[j] {
                    sw += b.w;
                }
            }
            let a = if model.dim == 1 {
                1.0
            } else if model.axisymmetric {
                kernel::line_integral_2d(h) / sw * crate::math::circumference(x[i].x)
            } else {
                kernel::line_integral_2d(h) / sw
            };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::neighbours;
    use crate::scene::Scene;

    /// A 3×3 block of particles: by its mirror symmetries the corner's
    /// normal is the outward diagonal, an edge's middle particle's normal
    /// the outward axis, and the centre's colour gradient vanishes, so it
    /// is inside.
    #[test]
    fn square_corner_normal_by_hand() {
        let scene = Scene::from_toml_str(
            r#"
[simulation]
dimension = 2
end_time = 1.0e-6
[materials.m]
density = 1000.0
shear_modulus = 1.0e9
eos = { kind = "linear", c0 = 2000.0 }
[[bodies]]
name = "block"
material = "m"
spacing = 1.0
shape = { kind = "rectangle", min = [0.0, 0.0], max = [3.0, 3.0] }
"#,
            "block",
        )
        .expect("the scene");
        let (model, st) = Model::new(&scene);
        assert_eq!(model.len(), 9);
        let at = |x: f64, y: f64| {
            (0..9)
                .find(|&i| st.x[i] == DVec2::new(x, y))
                .unwrap_or_else(|| panic!("a particle at ({x}, {y})"))
        };
        let nb = neighbours::find(&model, st.frame());
        let k = kinematics(&model, &st, &nb);
        let bd = boundary_of(&model, &st.x, &nb, &k);
        let close = |a: DVec2, b: DVec2| (a - b).length() < 1e-12;
        let d = std::f64::consts::FRAC_1_SQRT_2;
        assert!(close(bd.normal[at(0.5, 0.5)], DVec2::new(-d, -d)));
        assert!(close(bd.normal[at(2.5, 2.5)], DVec2::new(d, d)));
        assert!(close(bd.normal[at(2.5, 0.5)], DVec2::new(d, -d)));
        assert!(close(bd.normal[at(0.5, 1.5)], DVec2::new(-1.0, 0.0)));
        assert!(close(bd.normal[at(1.5, 2.5)], DVec2::new(0.0, 1.0)));
        let centre = at(1.5, 1.5);
        assert!(k.grad_psi[centre].length() < 1e-12);
        assert!(!bd.is_boundary[centre]);
        assert_eq!(bd.list.len(), 8);
    }
}
