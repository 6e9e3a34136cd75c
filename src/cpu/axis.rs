//! Bodies of revolution on the CPU (docs/method.md §12): the axis as a
//! mirror and the hoop terms; the same mirror serves a symmetry plane
//! (docs/method.md §13), without the hoop.
//!
//! The kernel sums run in the r–z plane with each particle's area
//! `V = m / η` (`η = 2π r ρ`, [`crate::model::State::rho`]). Near the axis
//! a particle's support reaches across it; what lies there is the mirror
//! image of the body, `(r, z) → (−r, z)`, with the radial velocity and the
//! `rz` shear reversed. Each particle within reach of the axis adds the
//! terms of the mirror images of its neighbours (and of itself) to its
//! sums (the lists' image rows, [`Neighbours::images_of`]), so the axis is neither a free surface nor a hole in the kernel's
//! support, and no particle sits on it.

use glam::DVec2;
use rayon::prelude::*;

use super::forces::{pair_terms_of, vectors_of, Side};
use super::kinematics::{gradient_weight, Kinematics, Seen, StressPoint, Sums};
use super::neighbours::{image_entry, Neighbours};
use crate::math::Mat2;
use crate::model::{Model, State};

/// The mirror partners' energy vectors, one per slot of the lists' image
/// rows ([`Neighbours::images`]; zero where the image lies beyond reach):
/// pair (i, j̄)'s `X_i` ([`crate::cpu::sweep::PairVectors`]), so that its
/// energy rate at velocities `w` is `−m_j (w_i − w̄_j)·X_i`. Kept by
/// [`add_momentum`] for the velocities the leapfrog books its work at:
/// each mirror pair's energy vector `X_i` and its artificial part `a +
/// X_i^hg` ([`super::forces::PairTerms::a`]).
pub(super) struct KeptMirrors(Vec<[DVec2; 2]>);

/// Adds the mirror partners' and the hoop's accelerations to `dv` and
/// keeps what their energy rates need ([`KeptMirrors::add_energy`]): the
/// hoop acceleration `−σ_θθ / (r ρ)` along r, whose work the hoop heat
/// `σ_θθ v_r / (r ρ)` books, so that they exchange no energy with the
/// total.
pub(super) fn add_momentum(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    kin: &Kinematics,
    pts: &[StressPoint],
    dv: &mut [DVec2],
) -> KeptMirrors {
    let side = |k| Side::of(st, kin, pts, k);
    // One slice of the kept vectors for each row, filled in parallel.
    let mut kept = vec![[DVec2::ZERO; 2]; nb.images.len()];
    let mut rows = Vec::new();
    let mut rest: &mut [[DVec2; 2]] = &mut kept;
    for i in nb.image_rows() {
        let (row, tail) = rest.split_at_mut(nb.image_candidates(i).len());
        rows.push((i, row));
        rest = tail;
    }
    let terms: Vec<(usize, DVec2)> = rows
        .into_par_iter()
        .filter(|(i, _)| !model.rigid(*i))
        .map(|(i, row)| {
            let a = side(i);
            let mut dvi = DVec2::ZERO;
            for (b, slot, m) in nb.images_of(model, st.frame(), i) {
                let j = b.j as usize;
                let im = side(j).mirrored(&m);
                let p = pair_terms_of(model, st, &kin.surface, (i, &a), (j, &im), &b);
                dvi += p.tg * model.mass[j];
                row[slot] = [vectors_of(&p)[0], p.a + p.hg[0]];
            }
            (i, dvi)
        })
        .collect();
    for (i, dvi) in terms {
        dv[i] += dvi;
    }
    if model.axisymmetric {
        dv.par_iter_mut().enumerate().for_each(|(i, dv)| {
            if !model.rigid(i) {
                dv.x -= pts[i].hoop;
            }
        });
    }
    KeptMirrors(kept)
}

/// [`add_momentum`] and its energy rates at the state's own velocities: a
/// body of revolution's terms of an evaluation's rates (the leapfrog books
/// the energy at other velocities). Returns the mirror pairs' artificial
/// dissipation rate ([`KeptMirrors::add_energy`]).
pub(super) fn add_rates(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    kin: &Kinematics,
    pts: &[StressPoint],
    (dv, de): (&mut [DVec2], &mut [f64]),
) -> f64 {
    add_momentum(model, st, nb, kin, pts, dv).add_energy(model, nb, pts, &st.v, de)
}

impl KeptMirrors {
    /// Adds the mirror partners' and the hoop's energy rates at the
    /// velocities `w` to `de`; returns the artificial dissipation rate of
    /// the mirror pairs (the hoop's work is the stress's own).
    pub(super) fn add_energy(
        &self,
        model: &Model,
        nb: &Neighbours,
        pts: &[StressPoint],
        w: &[DVec2],
        de: &mut [f64],
    ) -> f64 {
        let mut diss = 0.0;
        for i in nb.image_rows().filter(|&i| !model.rigid(i)) {
            let base = nb.image_start[i] as usize;
            let (mut sum, mut art) = (0.0, 0.0);
            for (k, &e) in nb.image_candidates(i).iter().enumerate() {
                let [x, a] = self.0[base + k];
                if x != DVec2::ZERO {
                    let (j, kind) = image_entry(e);
                    let j = j as usize;
                    let wij = w[i] - model.images[kind].vector(w[j]);
                    sum -= model.mass[j] * wij.dot(x);
                    art -= model.mass[j] * wij.dot(a);
                }
            }
            de[i] += sum;
            diss += model.mass[i] * art;
        }
        if model.axisymmetric {
            de.par_iter_mut().enumerate().for_each(|(i, de)| {
                if !model.rigid(i) {
                    *de += pts[i].hoop * w[i].x;
                }
            });
        }
        diss
    }
}

/// Adds the mirror partners' terms to each particle's kinematic sums
/// ([`super::kinematics::Sums`]): the images' masses, offsets and
/// velocities (`vel`, as the walk reads them), and their areas `vol` in
/// the colour gradient.
pub(super) fn add_kinematics<S: Seen>(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    vol: &[f64],
    vel: &[S::Vel],
    sums: &mut [Sums<S>],
) {
    let axi = model.axisymmetric;
    for i in nb.image_rows() {
        let sum = &mut sums[i];
        for (b, _, m) in nb.images_of(model, st.frame(), i) {
            let j = b.j as usize;
            let vj = S::mirror(vel[j], &m);
            let gi = b.gw * gradient_weight(model, st, vol, i, j);
            sum.m += Mat2::outer(gi, m.point(st.x[j]) - st.x[i]);
            sum.gsum += Mat2::outer(S::v(vj) - S::v(vel[i]), gi);
            sum.n += u32::from(b.q2 > 0.0);
            if st.round_supports() {
                sum.add_colour(b.gw, b.w, vol[j], axi);
            }
            sum.seen.add(vj, vel[i], gi);
        }
        if !st.round_supports() {
            // The colour gradient keeps the round supports
            // (kinematics::round_colour).
            for (b, _, _) in nb.images_of(model, crate::model::Frame::round(&st.x), i) {
                sum.add_colour(b.gw, b.w, vol[b.j as usize], axi);
            }
        }
    }
}
