//! Tests of the contact stage (`contact.rs`).

use super::contact::*;
use crate::cpu::{forces, kinematics, neighbours};
use crate::model::{Model, State};
use crate::physics::penalty::{spring_stiffness, yield_overlap};
use crate::validation::disk_scene;
use glam::DVec2;

/// Two disks of the paper pressed `overlap` spacings into each other, at
/// rest.
fn pressed(lattice: &str, overlap: f64) -> (Model, State) {
    let scene = disk_scene(lattice, 8.0);
    let (model, mut st) = Model::new(&scene);
    let centre = |b: u32| {
        let (mut c, mut n) = (DVec2::ZERO, 0.0);
        for i in (0..model.len()).filter(|&i| model.body[i] == b) {
            c += st.x[i];
            n += 1.0;
        }
        c / n
    };
    let axis = (centre(1) - centre(0)).normalize();
    let shift = -axis * overlap * model.bodies[1].spacing;
    for i in 0..model.len() {
        if model.body[i] == 1 {
            st.x[i] += shift;
        }
        st.v[i] = DVec2::ZERO;
    }
    (model, st)
}

/// The stored energy at `x`, with the boundary set and areas held.
fn stored(model: &Model, st: &State, surface: &[bool], area: &[f64]) -> f64 {
    let nb = neighbours::find(model, st.frame());
    let mut bd = forces::boundary(model, &st.x, &nb, surface.to_vec(), Vec::new());
    bd.area = area.to_vec();
    penalty(model, st, &nb, &bd).stats.stored
}

/// The paper's two steel bars at four particles each (1-D, Δx = 1.25 mm),
/// the right one pushed `δ = 0.01 Δx` into the left, at rest, entries
/// zero: the gap, the stiffness, the force and the stored energy worked
/// out by hand.
#[test]
fn two_particles_gap_and_force_by_hand() {
    let dx = 1.25e-3;
    let scene = crate::validation::bar_scene(crate::validation::BARS, 4, 1e-8);
    let (model, mut st) = Model::new(&scene);
    assert_eq!(model.bodies[0].spacing, dx);
    let delta = 0.01 * dx;
    for i in 0..8 {
        st.v[i] = DVec2::ZERO;
        if model.body[i] == 1 {
            st.x[i].x -= delta;
        }
    }
    assert_eq!(st.entry, vec![0.0; 8]);
    // P, the left bar's last particle, at −Δx/2; Q, the right bar's
    // first, at Δx/2 − δ; their surfaces Δx/2 beyond them: gap −δ.
    let (p, q) = (3, 4);
    assert!((model.offset[p] / (0.5 * dx) - 1.0).abs() < 1e-12);
    assert!((model.offset[q] / (0.5 * dx) - 1.0).abs() < 1e-12);
    // Constrained modulus at the reference state M = ρ0 c0² + 4G/3 (steel
    // of the paper's Table 1); two layers Δx/2 thick in
    // series: k = M/Δx.
    let m = 7850.0 * 4580.0 * 4580.0 + 4.0 / 3.0 * 77.0e9;
    assert!((model.bodies[0].material.m / m - 1.0).abs() < 1e-15);
    let k = m / dx;
    assert!((spring_stiffness(0.5 * dx, dx, m, 0.5 * dx, dx, m) / k - 1.0).abs() < 1e-15);

    let nb = neighbours::find(&model, st.frame());
    let kin = kinematics::kinematics(&model, &st, &nb);
    let bd = forces::boundary_of(&model, &st.x, &nb, &kin);
    // The four ends are the boundary; in 1-D the area is 1.
    assert_eq!(bd.list, vec![0, 3, 4, 7]);
    assert!(bd.list.iter().all(|&i| bd.area[i as usize] == 1.0));
    let c = penalty(&model, &st, &nb, &bd);
    // Two passes (P against Q, Q against P), each Φ = ¼ k δ² A: the
    // total ½ k δ², its gradient k δ on each particle, apart.
    let force = |i: usize| {
        let k = bd.list.iter().position(|&j| j as usize == i).unwrap();
        c.force[k]
            + c.spread
                .iter()
                .filter(|s| s.0 as usize == i)
                .map(|s| s.1)
                .sum::<DVec2>()
    };
    let want = k * delta;
    let tol = 1e-9 * want;
    assert!(
        (force(p).x + want).abs() < tol,
        "P: {} against {}",
        force(p).x,
        -want
    );
    assert!(
        (force(q).x - want).abs() < tol,
        "Q: {} against {want}",
        force(q).x
    );
    assert_eq!(force(0), DVec2::ZERO);
    assert_eq!(force(7), DVec2::ZERO);
    let stored = 0.5 * k * delta * delta;
    assert!(
        (c.stats.stored / stored - 1.0).abs() < 1e-9,
        "stored {} against {stored}",
        c.stats.stored
    );
    // At rest there is no dashpot and nothing to heat.
    assert!(c.heat.iter().all(|&h| h == 0.0));
}

/// The entry rule: a particle that joins the surface in overlap stores
/// nothing and takes its overlap as its entry; the entry only shrinks;
/// with the entries the evaluation returns the evaluation is the same
/// (the rule is idempotent); entries of zero push every overlap out.
#[test]
fn entry_overlaps_store_nothing_and_only_shrink() {
    let (model, mut st) = pressed("square", 0.2);
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics::kinematics(&model, &st, &nb);
    let bd = forces::boundary_of(&model, &st.x, &nb, &k);
    let full = penalty(&model, &st, &nb, &bd);
    assert!(full.stats.stored > 0.0);
    assert!(full.entry.iter().all(|&(_, e)| e == 0.0));
    st.entry.iter_mut().for_each(|e| *e = -1.0);
    let joined = penalty(&model, &st, &nb, &bd);
    assert_eq!(joined.stats.stored, 0.0);
    assert!(joined.force.iter().all(|f| *f == DVec2::ZERO));
    assert!(joined.spread.iter().all(|f| f.1 == DVec2::ZERO));
    let deepest = joined.entry.iter().map(|e| e.1).fold(0.0, f64::max);
    let dx = model.bodies[0].spacing;
    assert!(
        deepest > 0.1 * dx && deepest < yield_overlap(dx),
        "{deepest:e}"
    );
    // Entries half the overlaps: a quarter of each pass's energy.
    write_entries(&joined.entry, &mut st.entry);
    st.entry.iter_mut().for_each(|e| *e *= 0.5);
    let half = penalty(&model, &st, &nb, &bd);
    assert!(
        (half.stats.stored / full.stats.stored - 0.25).abs() < 1e-12,
        "{}",
        half.stats.stored / full.stats.stored
    );
    for &(i, e) in &half.entry {
        assert_eq!(e, st.entry[i as usize]);
    }
    // A large entry shrinks to the overlap, and stores nothing.
    st.entry.iter_mut().for_each(|e| *e = 1e3);
    let big = penalty(&model, &st, &nb, &bd);
    assert_eq!(big.stats.stored, 0.0);
    assert_eq!(big.entry, joined.entry);
}

/// The yield: an overlap more than a quarter spacing beyond the entry
/// moves the entry along, so no pass pushes harder than its spring at
/// the cap; the entries it returns give the same evaluation again.
#[test]
fn a_deep_overlap_yields() {
    let (model, st) = pressed("square", 0.7);
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics::kinematics(&model, &st, &nb);
    let bd = forces::boundary_of(&model, &st.x, &nb, &k);
    let c = penalty(&model, &st, &nb, &bd);
    let dx = model.bodies[0].spacing;
    let cap = yield_overlap(dx);
    let yielded = c.entry.iter().filter(|e| e.1 > 0.0).count();
    assert!(yielded > 4, "{yielded} particles yielded");
    let mut again = st.clone();
    write_entries(&c.entry, &mut again.entry);
    let d = penalty(&model, &again, &nb, &bd);
    assert_eq!(d.entry, c.entry);
    assert_eq!(d.stats.stored, c.stats.stored);
    assert_eq!(d.force, c.force);
    // At rest the pressure is the spring's, k δ: no higher than the
    // stiffest spring there is (both layers at their floor, 2 M/Δx) at
    // the cap, M/2. Without the yield the deepest pass (0.7 Δx, k at
    // least M/Δx) would push at 0.7 M.
    let most = spring_stiffness(0.0, dx, 1.0, 0.0, dx, 1.0) * cap * model.bodies[0].material.m;
    let (_, largest) = c.stats.pair(0, 1);
    assert!(largest > 0.0 && largest <= most, "{largest:e} vs {most:e}");
}

/// At rest (no dashpot) the contact force on every particle it touches
/// is minus the derivative of the stored energy, by central
/// differences: through the gap, the weights, the stiffness and the
/// normals. Momentum and angular momentum are exact.
#[test]
fn spring_force_is_the_stored_energys_gradient() {
    // The square lattice again with entry overlaps of half the
    // overlaps: the spring measured from them is a gradient too.
    for (lattice, entries) in [("polar", false), ("square", false), ("square", true)] {
        let (model, mut st) = pressed(lattice, 0.2);
        let nb = neighbours::find(&model, st.frame());
        let k = kinematics::kinematics(&model, &st, &nb);
        let surface = k.surface.clone();
        let bd = forces::boundary_of(&model, &st.x, &nb, &k);
        if entries {
            st.entry.iter_mut().for_each(|e| *e = -1.0);
            let joined = penalty(&model, &st, &nb, &bd);
            write_entries(&joined.entry, &mut st.entry);
            st.entry.iter_mut().for_each(|e| *e *= 0.5);
        }
        let c = penalty(&model, &st, &nb, &bd);
        assert!(c.stats.stored > 0.0, "{lattice}: the disks overlap");
        let mut f = vec![DVec2::ZERO; model.len()];
        for (k, &i) in bd.list.iter().enumerate() {
            f[i as usize] += c.force[k];
        }
        for &(i, g) in &c.spread {
            f[i as usize] += g;
        }
        let total: DVec2 = f.iter().copied().sum();
        let torque: f64 = f.iter().zip(&st.x).map(|(f, x)| x.perp_dot(*f)).sum();
        let scale = f.iter().map(|f| f.length()).fold(0.0, f64::max);
        assert!(
            total.length() < 1e-12 * scale * model.len() as f64,
            "{lattice}: Σf = {total}"
        );
        assert!(
            torque.abs() < 1e-12 * scale * model.len() as f64,
            "{lattice}: torque {torque}"
        );
        // The particles with the largest forces, boundary and interior.
        let mut order: Vec<usize> = (0..model.len()).filter(|&i| f[i] != DVec2::ZERO).collect();
        order.sort_by(|&a, &b| f[b].length().total_cmp(&f[a].length()));
        let interior = order
            .iter()
            .copied()
            .filter(|&i| !bd.is_boundary[i])
            .take(4);
        let picked: Vec<usize> = order.iter().copied().take(6).chain(interior).collect();
        assert!(
            picked.iter().any(|&i| !bd.is_boundary[i]),
            "{lattice}: no interior force"
        );
        let eps = 1e-6 * model.bodies[0].spacing;
        for &i in &picked {
            for e in [DVec2::X, DVec2::Y] {
                let at = |s: f64| {
                    let mut moved = st.clone();
                    moved.x[i] += e * (s * eps);
                    stored(&model, &moved, &surface, &bd.area)
                };
                let fd = (at(1.0) - at(-1.0)) / (2.0 * eps);
                let exact = -f[i].dot(e);
                assert!(
                    (fd - exact).abs() < 1e-5 * scale,
                    "{lattice}: particle {i} along {e}: dΦ/dx {fd:e} vs −f {exact:e} (scale {scale:e})"
                );
            }
        }
    }
}
