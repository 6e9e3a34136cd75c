//! The dispersion correction (docs/method.md §4, "The dispersion
//! correction"): the strain rate takes each pair's velocity jump less the
//! part the two particles' velocity gradients explain, and the forces are
//! that map's adjoint applied to the stresses, so that the semi-discrete
//! energy is kept to round-off.
//!
//! With `a_ij = L_i ∇_i W_ij V_j` the weight of the corrected gradient
//! (`∇v_i = Σ_j (v_j − v_i) ⊗ a_ij`, [`super::kinematics`]) and `d_ij =
//! x_j − x_i`:
//!
//! * the strain rate the stress and the density see is `∇v_i + C_i`,
//!   `C_i = −½θ Σ_j ((∇v_j − ∇v_i) d_ij) ⊗ a_ij` ([`strain_correction`]);
//! * its power `Σ_i V_i σ_i : C_i` equals `Σ_k V_k S_k : ∇v_k` with
//!   `S_k = ½θ/V_k Σ_j (V_j σ_j a_jk + V_k σ_k a_kj) ⊗ d_kj`
//!   ([`stress_adjoint`], a general 2×2 matrix), so the correction's forces
//!   are those of the extra stress `S` ([`add_forces`]) and its work, booked
//!   as internal energy, is `S_k : ∇v_k / ρ_k` ([`add_work`]).
//!
//! In a body of revolution `V` is the ring's volume `m/ρ`
//! ([`energy_weights`]), the gradient and the forces weigh their pairs by
//! mass and `C` and `S` by area ([`Weigh`]).
//!
//! No kernel of its own: the kinematic walk keeps each pair's kernel
//! gradient ([`Kept`]) and every sum (`C`, `S`, the forces and the
//! leapfrog's gradient of `v_{n+1}` for the work, [`gradient`]) replays
//! them, only where a scene sets `dispersion_correction`; across symmetry
//! planes each also takes the pairs with the neighbours' images
//! ([`image_pairs`]), as the kinematic sums do.

use std::borrow::Cow;

use glam::DVec2;
use rayon::prelude::*;

use super::kinematics::StressPoint;
use super::kinematics::{gradient_weight, hoop_rate, stress_rate, volumes, with_hoop, Kinematics};
use super::neighbours::Neighbours;
use crate::math::{Mat2, Mirror, Sym};
use crate::model::{Model, State};
use crate::physics::strength;

/// Each visited candidate's kernel gradient `∇_i W_ij` (zero outside the
/// support), kept by the step's kinematic walk
/// ([`super::sweep::kinematics_keeping`]) in its slots
/// ([`Neighbours::sweep_store`]). Every sum of the correction replays them
/// ([`Neighbours::replay`]): within a step the positions and the supports
/// do not move, only the volumes the weights take, which the replays read
/// at their own state.
#[derive(Debug, Clone, Default)]
pub struct Kept(Vec<DVec2>);

impl Kept {
    /// Bytes held.
    pub fn bytes(&self) -> usize {
        size_of_val(&self.0[..])
    }

    /// The store for a walk of `n` slots.
    pub(super) fn slots(&mut self, n: usize) -> &mut [DVec2] {
        self.0.resize(n, DVec2::ZERO);
        &mut self.0
    }
}

/// The pair's gradients `(L_i ∇_i W_ij, L_j ∇_j W_ji)` (`∇_j W_ji = −∇_i W_ij`).
#[inline]
fn pair_gradients(l: &[Mat2], (i, j): (usize, usize), gw: DVec2) -> [DVec2; 2] {
    [l[i].mul_vec(gw), l[j].mul_vec(-gw)]
}

/// The pair's weights `(a_ij, a_ji)` from its gradients `k`
/// ([`pair_gradients`]).
#[inline]
fn weights(
    model: &Model,
    st: &State,
    vol: &[f64],
    (i, j): (usize, usize),
    k: [DVec2; 2],
    by: Weigh,
) -> (DVec2, DVec2) {
    let (wj, wi) = weigh(model, st, vol, (i, j), by);
    (k[0] * wj, k[1] * wi)
}

/// [`weights`] of particle i and the mirror image of j across `m` (`gw =
/// ∇_i W` at `x_i − m(x_j)`): `(a_ij', a_j'i)`, the image's `L` being
/// `L_j` mirrored.
#[inline]
fn image_weights(
    model: &Model,
    st: &State,
    vol: &[f64],
    l: &[Mat2],
    (i, j, m): (usize, usize, &Mirror),
    gw: DVec2,
    by: Weigh,
) -> (DVec2, DVec2) {
    let k = [l[i].mul_vec(gw), m.mat(&l[j]).mul_vec(-gw)];
    weights(model, st, vol, (i, j), k, by)
}

/// What a pair's neighbour is weighed by: in the velocity gradient (and
/// so in the forces, its adjoint), the kinematic sums' weight
/// ([`gradient_weight`]: a body of revolution's `m_j/η_i`); in `C` (and
/// so in `S`), its area `V_j` everywhere. Weights that grow with the
/// radius give the pair sums an odd moment `Σ_j d ⊗ d ⊗ a_ij` of order
/// `h²/r`, and `C` a term in the first derivative of `∇v` that the
/// correction is not (two steel spheres' Hertz peak force +4.8 %); with
/// the areas the images across the axis keep the sums even.
#[derive(Clone, Copy)]
enum Weigh {
    Gradient,
    Area,
}

/// The scalars `(w_j, w_i)` that turn a pair's gradients into its weights.
#[inline]
fn weigh(model: &Model, st: &State, vol: &[f64], (i, j): (usize, usize), by: Weigh) -> (f64, f64) {
    match by {
        Weigh::Gradient => (
            gradient_weight(model, st, vol, i, j),
            gradient_weight(model, st, vol, j, i),
        ),
        Weigh::Area => (vol[j], vol[i]),
    }
}

/// Adds to each particle's `acc` its pairs with the mirror images of its
/// neighbours (and of itself) across the symmetry planes, i's side only:
/// `pair(i, j, m, gw, d, acc_i)` with `gw = ∇_i W` and `d = m(x_j) − x_i`.
/// The image's side of the pair is the mirror of j's pair with i's image,
/// which j's row takes. Nothing without a plane.
fn image_pairs<T, P>(model: &Model, st: &State, nb: &Neighbours, acc: &mut [T], pair: P)
where
    T: Send,
    P: Fn(usize, usize, &Mirror, DVec2, DVec2, &mut T) + Sync,
{
    if model.images.is_empty() {
        return;
    }
    acc.par_iter_mut().enumerate().for_each(|(i, a)| {
        for (b, _, m) in nb.images_of(model, st.frame(), i) {
            let j = b.j as usize;
            pair(i, j, &m, b.gw, m.point(st.x[j]) - st.x[i], a);
        }
    });
}

/// Each particle's energy weight `W_i`, the volume its stress power is
/// weighed by: `m_i/ρ_i`, its area in the plane and, in a body of
/// revolution, its ring's volume `2π r_i m_i/η_i` (the sums' `m/η` is the
/// area in the r–z plane; docs/method.md §12).
fn energy_weights<'a>(model: &Model, st: &State, vol: &'a [f64]) -> Cow<'a, [f64]> {
    if !model.axisymmetric {
        return Cow::Borrowed(vol);
    }
    (0..model.len())
        .into_par_iter()
        .map(|i| vol[i] * (std::f64::consts::TAU * st.x[i].x))
        .collect::<Vec<_>>()
        .into()
}

/// The correction's work per unit mass from its power density `S : ∇v`:
/// over `ρ`, in a body of revolution over `η / 2πr`.
#[inline]
fn per_mass(model: &Model, st: &State, i: usize, power: f64) -> f64 {
    if model.axisymmetric {
        power * (std::f64::consts::TAU * st.x[i].x) / st.rho[i]
    } else {
        power / st.rho[i]
    }
}

/// `A : B` of two general matrices.
#[inline]
fn ddot2(a: &Mat2, b: &Mat2) -> f64 {
    a.xx * b.xx + a.xy * b.xy + a.yx * b.yx + a.yy * b.yy
}

/// The corrected gradient `Σ_j (v_j − v_i) ⊗ a_ij` of the velocities `v`
/// at `st`'s positions with the correction matrices `l` (zero on rigid
/// particles), replayed from the step's pairs `kept`: the same sums as the
/// kinematic pass's.
pub fn gradient(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    (l, kept): (&[Mat2], &Kept),
    v: &[DVec2],
) -> Vec<Mat2> {
    let vol = volumes(model, st);
    let mut g = vec![Mat2::ZERO; model.len()];
    nb.replay(&mut g, &kept.0, |i, j, &gw, gi, gj| {
        let k = pair_gradients(l, (i, j), gw);
        let (ai, aj) = weights(model, st, &vol, (i, j), k, Weigh::Gradient);
        let dv = v[j] - v[i];
        *gi += Mat2::outer(dv, ai);
        if let Some(gj) = gj {
            *gj += Mat2::outer(-dv, aj);
        }
    });
    image_pairs(model, st, nb, &mut g, |i, j, m, gw, _, gi| {
        let (ai, _) = image_weights(model, st, &vol, l, (i, j, m), gw, Weigh::Gradient);
        *gi += Mat2::outer(m.vector(v[j]) - v[i], ai);
    });
    for (i, g) in g.iter_mut().enumerate() {
        if model.rigid(i) {
            *g = Mat2::ZERO;
        }
    }
    g
}

/// `C_i = −½θ Σ_j ((∇v_j − ∇v_i) d_ij) ⊗ a_ij` from the kinematic pass's
/// `∇v` (`k.g`), `L` (zero on rigid particles) and pairs (`kept`).
pub fn strain_correction(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    k: &Kinematics,
    kept: &Kept,
) -> Vec<Mat2> {
    pair_sums(model, st, nb, (&k.l, kept), Some(&k.g), None).0
}

/// [`strain_correction`] and [`stress_adjoint`] in one replay, where the
/// stresses do not wait for the corrected rates (the midpoint rule's
/// evaluations take them from the state).
pub fn strain_and_stress(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    k: &Kinematics,
    pts: &[StressPoint],
    kept: &Kept,
) -> (Vec<Mat2>, Vec<Mat2>) {
    pair_sums(model, st, nb, (&k.l, kept), Some(&k.g), Some(pts))
}

/// `W σ` of each particle: the stress point keeps `σ/ρ²` (`σ/(ηρ)` in a
/// body of revolution, where `V η²` is then the ring's volume times `ρ`).
fn weighed_stresses(model: &Model, st: &State, vol: &[f64], pts: &[StressPoint]) -> Vec<Sym> {
    (0..model.len())
        .into_par_iter()
        .map(|i| pts[i].sr2.scale(vol[i] * st.rho[i] * st.rho[i]))
        .collect()
}

/// `S`'s pair term `(W_i σ_i a_ij + W_j σ_j a_ji) ⊗ d_ij`.
#[inline]
fn stress_term(vs: (&Sym, &Sym), (ai, aj): (DVec2, DVec2), d: DVec2) -> Mat2 {
    Mat2::outer(vs.0.mul_vec(ai) + vs.1.mul_vec(aj), d)
}

/// `S`'s pairs with the neighbours' images.
fn stress_images(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    (vol, l, vs): (&[f64], &[Mat2], &[Sym]),
    acc: &mut [Mat2],
) {
    image_pairs(model, st, nb, acc, |i, j, m, gw, d, qi| {
        let a = image_weights(model, st, vol, l, (i, j, m), gw, Weigh::Area);
        *qi += stress_term((&vs[i], &m.sym(&vs[j])), a, d);
    });
}

/// The replay behind [`strain_correction`] (with `g`, the velocity
/// gradients), [`stress_adjoint`] (with `pts`, the stresses) and
/// [`strain_and_stress`] (both): `(C, S)`, each zero where not asked for
/// and on rigid particles.
fn pair_sums(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    (l, kept): (&[Mat2], &Kept),
    g: Option<&[Mat2]>,
    pts: Option<&[StressPoint]>,
) -> (Vec<Mat2>, Vec<Mat2>) {
    let vol = volumes(model, st);
    let vs = pts.map(|pts| weighed_stresses(model, st, &vol, pts));
    let mut acc = vec![(Mat2::ZERO, Mat2::ZERO); model.len()];
    nb.replay(&mut acc, &kept.0, |i, j, &gw, (ci, qi), cj| {
        let a = weights(
            model,
            st,
            &vol,
            (i, j),
            pair_gradients(l, (i, j), gw),
            Weigh::Area,
        );
        let d = st.x[j] - st.x[i];
        // (∇v_j − ∇v_i) d_ij, the same from j's side (d_ji = −d_ij).
        let u = g.map(|g| g[j].mul_vec(d) - g[i].mul_vec(d));
        let q = vs.as_ref().map(|vs| stress_term((&vs[i], &vs[j]), a, d));
        if let Some(u) = u {
            *ci += Mat2::outer(u, a.0);
        }
        if let Some(q) = q {
            *qi += q;
        }
        if let Some((cj, qj)) = cj {
            if let Some(u) = u {
                *cj += Mat2::outer(u, a.1);
            }
            if let Some(q) = q {
                *qj -= q;
            }
        }
    });
    image_pairs(model, st, nb, &mut acc, |i, j, m, gw, d, (ci, _)| {
        if let Some(g) = g {
            let (ai, _) = image_weights(model, st, &vol, l, (i, j, m), gw, Weigh::Area);
            *ci += Mat2::outer(m.mat(&g[j]).mul_vec(d) - g[i].mul_vec(d), ai);
        }
    });
    let (c, mut q): (Vec<Mat2>, Vec<Mat2>) = acc.into_par_iter().unzip();
    if let Some(vs) = &vs {
        stress_images(model, st, nb, (&vol, l, vs), &mut q);
    }
    let w = energy_weights(model, st, &vol);
    let theta = model.dispersion;
    c.into_par_iter()
        .zip(q)
        .enumerate()
        .map(|(i, (c, q))| {
            if model.rigid(i) {
                (Mat2::ZERO, Mat2::ZERO)
            } else {
                (c.scale(-0.5 * theta), q.scale(0.5 * theta / w[i]))
            }
        })
        .unzip()
}

/// The kinematic pass's density and stress rates (and equivalent strain
/// rate) taken at `∇v + C` instead of `∇v` ([`strain_correction`]).
pub fn correct_rates(model: &Model, st: &State, k: &mut Kinematics, c: &[Mat2]) {
    let debris = k.debris_flags(model);
    let (g, drho, ds) = (&k.g, &mut k.drho, &mut k.ds);
    drho.par_iter_mut()
        .zip(ds.par_iter_mut())
        .enumerate()
        .for_each(|(i, (drho, ds))| {
            if model.rigid(i) {
                return;
            }
            let gc = g[i] + c[i];
            *drho = -st.rho[i] * gc.trace();
            let shear = if debris.get(i).copied().unwrap_or(false) {
                0.0
            } else {
                model.material(i).g
            };
            let rate = stress_rate(shear, &st.s[i], &gc);
            // The hoop rate v_r/r takes no correction (kinematics::finish).
            *ds = if model.axisymmetric {
                with_hoop(shear, rate, hoop_rate(st, i))
            } else {
                rate
            };
        });
    if model.strain_rate {
        k.rate.par_iter_mut().enumerate().for_each(|(i, r)| {
            if !model.rigid(i) {
                let gc = g[i] + c[i];
                *r = if model.axisymmetric {
                    strength::equivalent_strain_rate_3(&gc, hoop_rate(st, i))
                } else {
                    strength::equivalent_strain_rate(&gc)
                };
            }
        });
    }
}

/// The extra stress `S_k` whose forces are the correction's adjoint, from
/// the stresses of `pts`, the kinematic pass's `L` and the step's pairs
/// `kept` (replayed).
pub fn stress_adjoint(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    pairs: (&[Mat2], &Kept),
    pts: &[StressPoint],
) -> Vec<Mat2> {
    pair_sums(model, st, nb, pairs, None, Some(pts)).1
}

/// The forces of the extra stress `s` ([`stress_adjoint`]), added to the
/// accelerations `dv`: `m_i a_i += Σ_j (V_i S_i a_ij − V_j S_j a_ji)`,
/// minus the gradient of `Σ_k V_k S_k : ∇v_k` in the velocities; the
/// step's pairs `kept` replayed.
pub fn add_forces(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    (l, kept): (&[Mat2], &Kept),
    s: &[Mat2],
    dv: &mut [DVec2],
) {
    let vol = volumes(model, st);
    let w = energy_weights(model, st, &vol);
    let mut f = vec![DVec2::ZERO; model.len()];
    nb.replay(&mut f, &kept.0, |i, j, &gw, fi, fj| {
        let k = pair_gradients(l, (i, j), gw);
        let (ai, aj) = weights(model, st, &vol, (i, j), k, Weigh::Gradient);
        let p = s[i].mul_vec(ai) * w[i] - s[j].mul_vec(aj) * w[j];
        *fi += p;
        if let Some(fj) = fj {
            *fj -= p;
        }
    });
    image_pairs(model, st, nb, &mut f, |i, j, m, gw, _, fi| {
        let (ai, aj) = image_weights(model, st, &vol, l, (i, j, m), gw, Weigh::Gradient);
        *fi += s[i].mul_vec(ai) * w[i] - m.mat(&s[j]).mul_vec(aj) * w[j];
    });
    dv.par_iter_mut().enumerate().for_each(|(i, a)| {
        if !model.rigid(i) {
            *a += f[i] / model.mass[i];
        }
    });
}

/// The correction's work on each particle, `S_k : ∇v_k / ρ_k` per unit
/// mass, added to `de`: its sum over the particles is minus the power of
/// [`add_forces`]'s forces at the velocities `∇v` is taken of.
pub fn add_work(model: &Model, st: &State, s: &[Mat2], g: &[Mat2], de: &mut [f64]) {
    de.par_iter_mut().enumerate().for_each(|(i, e)| {
        if !model.rigid(i) {
            *e += per_mass(model, st, i, ddot2(&s[i], &g[i]));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::kinematics::eos_and_stress;
    use crate::cpu::{neighbours, sweep};
    use crate::scene::Scene;

    /// `σ : A` of an in-plane stress and a general matrix.
    fn ddot(s: &Sym, a: &Mat2) -> f64 {
        s.xx * a.xx + s.xy * (a.xy + a.yx) + s.yy * a.yy
    }

    /// `Σ_i V_i σ_i : C_i`, the correction's power through the strain rate,
    /// which [`add_work`] books in its adjoint form.
    pub fn strain_power(model: &Model, st: &State, pts: &[StressPoint], c: &[Mat2]) -> f64 {
        (0..model.len())
            .map(|i| model.mass[i] * st.rho[i] * ddot(&pts[i].sr2, &c[i]))
            .sum()
    }

    /// A block of `dim` dimensions, the correction at `theta`, `support`
    /// the scene's key; with `stir`, its lattice, velocities, densities and
    /// deviatoric stresses stirred by a fixed pseudo-random sequence.
    fn stirred(dim: u32, support: &str, theta: f64, stir: bool) -> (Model, State) {
        stirred_cut(dim, support, theta, stir, None)
    }

    /// The cut of [`stirred_cut`]: a symmetry plane normal to x at the
    /// abscissa, or the block a body of revolution whose axis is its edge
    /// `x = 0`.
    #[derive(Debug, Clone, Copy)]
    enum Cut {
        Plane(f64),
        Axis,
    }

    /// [`stirred`], the 2-D block cut by the symmetry plane normal to x
    /// (the half beyond it kept; a particle on the plane keeps its place
    /// and no velocity across it), or turned about its edge on the axis.
    fn stirred_cut(
        dim: u32,
        support: &str,
        theta: f64,
        stir: bool,
        cut: Option<Cut>,
    ) -> (Model, State) {
        let plane = match cut {
            Some(Cut::Plane(p)) => Some(p),
            _ => None,
        };
        let (cut, geometry) = match cut {
            Some(Cut::Plane(p)) => (
                format!("[[symmetry]]\nnormal = [1.0, 0.0]\npoint = [{p}, 0.0]\n"),
                "",
            ),
            Some(Cut::Axis) => (String::new(), "geometry = \"axisymmetric\"\n"),
            None => (String::new(), ""),
        };
        let (shape, v) = if dim == 1 {
            (r#"{ kind = "segment", from = 0.0, to = 0.004 }"#, "[3.0]")
        } else {
            (
                r#"{ kind = "rectangle", min = [0.0, 0.0], max = [0.003, 0.0025] }"#,
                "[3.0, -1.0]",
            )
        };
        let scene = Scene::from_toml_str(
            &format!(
                r#"
[simulation]
dimension = {dim}
end_time = 1.0e-6
support = "{support}"
dispersion_correction = {theta}
{geometry}[materials.m]
density = 7850.0
shear_modulus = 77.0e9
eos = {{ kind = "linear", c0 = 4580.0 }}
[[bodies]]
name = "block"
material = "m"
spacing = 1.0e-4
velocity = {v}
shape = {shape}
{cut}"#
            ),
            "block",
        )
        .expect("the scene");
        let (model, mut st) = Model::new(&scene);
        if !stir {
            return (model, st);
        }
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut r = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let y = if dim == 1 { 0.0 } else { 1.0 };
        for i in 0..model.len() {
            let on = plane.is_some_and(|p| st.x[i].x == p);
            let (dx, dv) = (
                DVec2::new(r(), r() * y) * 2.0e-5,
                DVec2::new(r(), r() * y) * 4.0,
            );
            st.x[i] += if on { DVec2::new(0.0, dx.y) } else { dx };
            let vx = st.v[i].x;
            st.v[i] += if on { DVec2::new(-vx, dv.y) } else { dv };
            st.rho[i] *= 1.0 + 0.01 * r();
            st.s[i] = Sym {
                xx: 1e8 * r(),
                yy: 1e8 * r() * y,
                xy: 1e8 * r() * y,
                zz: 0.0,
            };
        }
        (model, st)
    }

    /// The correction's two halves are each other's adjoints on a stirred
    /// block: `Σ V σ : C = Σ V S : ∇v` (the stress power the strain rate
    /// gains is the extra stress's), and the extra stress's forces do
    /// minus that work at the velocities, so the ledger closes.
    #[test]
    fn the_forces_are_the_strain_rates_adjoint() {
        // Across a symmetry plane between two rows of particles, and on
        // one (its particles with half their volume); a body of revolution
        // (its power weighed by the rings' volumes, the axis's images).
        let cases = [
            (1, "fixed", None),
            (2, "fixed", None),
            (2, "adaptive", None),
            (2, "fixed", Some(Cut::Plane(0.0015))),
            (2, "fixed", Some(Cut::Plane(0.00155))),
            (2, "adaptive", Some(Cut::Plane(0.00155))),
            (2, "fixed", Some(Cut::Axis)),
            (2, "adaptive", Some(Cut::Axis)),
        ];
        for (dim, support, cut) in cases {
            let (model, st) = stirred_cut(dim, support, 0.7, true, cut);
            if cut.is_some() {
                assert!(!model.images.is_empty());
            }
            assert_eq!(model.axisymmetric, matches!(cut, Some(Cut::Axis)));
            let support = &format!("{support}, {cut:?}");
            let nb = neighbours::find(&model, st.frame());
            let mut kept = Kept::default();
            let k = sweep::kinematics_keeping(&model, &st, &nb, None, &mut kept);
            assert_eq!(k.g.len(), model.len());
            // Keeping the pairs changes nothing of the kinematic pass.
            let plain = sweep::kinematics(&model, &st, &nb);
            assert!(plain.g == k.g && plain.l == k.l && plain.drho == k.drho);
            let c = strain_correction(&model, &st, &nb, &k, &kept);
            let pts = eos_and_stress(&model, &st);
            let s = stress_adjoint(&model, &st, &nb, (&k.l, &kept), &pts);
            let through_strain = strain_power(&model, &st, &pts, &c);
            let mut de = vec![0.0; model.len()];
            add_work(&model, &st, &s, &k.g, &mut de);
            let booked: f64 = (0..model.len()).map(|i| model.mass[i] * de[i]).sum();
            let mut dv = vec![DVec2::ZERO; model.len()];
            add_forces(&model, &st, &nb, (&k.l, &kept), &s, &mut dv);
            let kinetic: f64 = (0..model.len())
                .map(|i| model.mass[i] * st.v[i].dot(dv[i]))
                .sum();
            let scale: f64 = (0..model.len()).map(|i| model.mass[i] * de[i].abs()).sum();
            assert!(scale > 0.0, "{dim}-D {support}: no correction at all");
            let tol = 1e-10 * scale;
            assert!(
                (through_strain - booked).abs() < tol,
                "{dim}-D {support}: Σ Vσ:C {through_strain} against Σ V S:∇v {booked}"
            );
            assert!(
                (kinetic + booked).abs() < tol,
                "{dim}-D {support}: the forces' power {kinetic} against the work booked {booked}"
            );
            // The midpoint rule's one replay of C and S gives the two
            // replays' sums, bit for bit.
            let (c2, s2) = strain_and_stress(&model, &st, &nb, &k, &pts, &kept);
            assert!(c2 == c && s2 == s, "{dim}-D {support}: the replay of S");
            // The correction's replay of ∇v is the kinematic pass's.
            let g = gradient(&model, &st, &nb, (&k.l, &kept), &st.v);
            for (a, b) in g.iter().zip(&k.g) {
                assert!(ddot2(&(*a - *b), &(*a - *b)).sqrt() < 1e-9 * ddot2(b, b).sqrt().max(1.0));
            }
        }
    }

    /// A velocity field whose gradient is uniform leaves the strain rate
    /// alone everywhere (the corrected gradient is exact for it at the
    /// surfaces too, so the neighbours' gradients agree), and a uniform
    /// stress gives no extra stress inside (the neighbours' `L` agree
    /// there; at the surfaces they do not).
    #[test]
    fn linear_fields_are_left_alone_inside() {
        let (model, mut st) = stirred(2, "fixed", 0.7, false);
        let a = Mat2 {
            xx: 300.0,
            xy: -120.0,
            yx: 80.0,
            yy: -200.0,
        };
        for i in 0..model.len() {
            st.v[i] = a.mul_vec(st.x[i]);
            st.s[i] = Sym {
                xx: 2e8,
                yy: -1e8,
                xy: 5e7,
                zz: -1e8,
            };
        }
        let nb = neighbours::find(&model, st.frame());
        let mut kept = Kept::default();
        let k = sweep::kinematics_keeping(&model, &st, &nb, None, &mut kept);
        let c = strain_correction(&model, &st, &nb, &k, &kept);
        let pts = eos_and_stress(&model, &st);
        let s = stress_adjoint(&model, &st, &nb, (&k.l, &kept), &pts);
        let norm = |m: &Mat2| ddot2(m, m).sqrt();
        // Two supports' reach from every edge: the particle's and its
        // neighbours' sums are whole.
        let reach = 4.0 * model.h[0] + 1e-9;
        let (lo, hi) = (DVec2::splat(0.0), DVec2::new(0.003, 0.0025));
        let inside: Vec<usize> = (0..model.len())
            .filter(|&i| {
                (st.x[i] - lo).min_element() > reach && (hi - st.x[i]).min_element() > reach
            })
            .collect();
        assert!(inside.len() > 20, "{}", inside.len());
        for (g, c) in k.g.iter().zip(&c) {
            assert!(norm(&(*g - a)) < 1e-9 * norm(&a), "∇v {g:?}");
            assert!(norm(c) < 1e-9 * norm(&a), "C {c:?}");
        }
        for &i in &inside {
            assert!(norm(&s[i]) < 1e-9 * 2e8, "S {:?}", s[i]);
        }
        let edge = (0..model.len()).map(|i| norm(&s[i])).fold(0.0, f64::max);
        assert!(edge > 1e-3 * 2e8, "{edge}");
    }

    /// A quadratic field takes no correction inside a plane lattice (its
    /// pair sums are even), and in a body of revolution next to none
    /// clear of the axis: `C` weighs its pairs by area, so the sums stay
    /// even there. Weighed by mass, as the gradient is, they would take up
    /// a term in the first derivative of `∇v` of order `h²/r` (measured:
    /// 32 1/s clear of the axis against 1.3 by area, the first-order
    /// term's size `½θ k h` being 42). The two rows by the axis keep the
    /// mass-weighted gradient's own error there (9.4 1/s; 42 by mass).
    #[test]
    fn a_quadratic_field_takes_no_correction_off_the_axis() {
        let k = 1.0e6;
        let field = |x: DVec2| DVec2::new(k * x.x * x.y, k * (x.x * x.x - 0.5 * x.y * x.y));
        let (mut plane, mut by_axis, mut off_axis) = (0.0f64, 0.0f64, 0.0f64);
        let mut h = 0.0;
        for cut in [None, Some(Cut::Axis)] {
            let (model, mut st) = stirred_cut(2, "fixed", 0.7, false, cut);
            for i in 0..model.len() {
                st.v[i] = field(st.x[i]);
            }
            let nb = neighbours::find(&model, st.frame());
            let mut kept = Kept::default();
            let kin = sweep::kinematics_keeping(&model, &st, &nb, None, &mut kept);
            let c = strain_correction(&model, &st, &nb, &kin, &kept);
            // Two supports' reach from every edge but the axis.
            h = model.h[0];
            let reach = 4.0 * h + 1e-9;
            let lo = DVec2::new(if cut.is_some() { -1.0 } else { 0.0 }, 0.0);
            let hi = DVec2::new(0.003, 0.0025);
            for (&x, c) in st.x.iter().zip(&c) {
                if (x - lo).min_element() <= reach || (hi - x).min_element() <= reach {
                    continue;
                }
                let norm = ddot2(c, c).sqrt();
                match cut {
                    None => plane = plane.max(norm),
                    Some(_) if x.x > 2.0 * h => off_axis = off_axis.max(norm),
                    Some(_) => by_axis = by_axis.max(norm),
                }
            }
        }
        let first_order = 0.5 * 0.7 * k * h;
        println!(
            "largest |C| inside: plane {plane:e}, off the axis {off_axis:e}, by it {by_axis:e} 1/s"
        );
        assert!(plane < 1e-9 * first_order, "{plane}");
        assert!(off_axis < 0.1 * first_order, "{off_axis}");
        assert!(by_axis < 0.5 * first_order, "{by_axis}");
    }
}
