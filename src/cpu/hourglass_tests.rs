//! The hourglass control (`forces::hourglass`, docs/method.md "Hourglass
//! control"): no net force or torque, its work all heat and that heat
//! never negative on any particle, nothing on a linear velocity field, and
//! the solver's pair sweep equal to the plain gather.

use glam::DVec2;

use super::forces::momentum_energy;
use super::kinematics::kinematics;
use super::neighbours;
use super::{eos_and_stress, evaluate};
use crate::bench::{CpuBench, DiskCase};
use crate::model::{Model, State};

/// The paper's square-lattice disks in contact with a stirred velocity
/// field, the viscosity's reconstruction off (it reads the stored
/// gradient, which the control changes where the correction falls back).
fn disks(stir: impl Fn(usize, DVec2) -> DVec2) -> (Model, State) {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (mut model, mut st) = (bench.model().clone(), bench.state().clone());
    model.av_reconstruct = false;
    for i in 0..st.v.len() {
        st.v[i] = stir(i, st.x[i]);
    }
    (model, st)
}

/// The control's own part of the rates: the rates with it less those
/// without, from the solver's sweep and from the plain gather.
fn control_part(model: &Model, st: &State, alpha: f64) -> [(Vec<DVec2>, Vec<f64>); 2] {
    control_part_of(model, st, [alpha; 2])
}

/// [`control_part`] with each disk's families at its own coefficient.
fn control_part_of(model: &Model, st: &State, alpha: [f64; 2]) -> [(Vec<DVec2>, Vec<f64>); 2] {
    let mut on = model.clone();
    on.set_hourglass(alpha[0].max(alpha[1]));
    for (b, a) in on.bodies.iter_mut().zip(alpha) {
        b.hourglass = a;
    }
    let (with, _) = evaluate(&on, st);
    let (without, _) = evaluate(model, st);
    let sweep = (
        with.dv
            .iter()
            .zip(&without.dv)
            .map(|(a, b)| *a - *b)
            .collect(),
        with.de
            .iter()
            .zip(&without.de)
            .map(|(a, b)| a - b)
            .collect(),
    );
    let gather = |m: &Model| {
        let nb = neighbours::find(m, st.frame());
        let k = kinematics(m, st, &nb);
        momentum_energy(m, st, &nb, &k, &eos_and_stress(m, st))
    };
    let (gw, gn) = (gather(&on), gather(model));
    let plain = (
        gw.0.iter().zip(&gn.0).map(|(a, b)| *a - *b).collect(),
        gw.1.iter().zip(&gn.1).map(|(a, b)| a - b).collect(),
    );
    [sweep, plain]
}

#[test]
fn hourglass_control_conserves_and_only_heats() {
    let (model, st) = disks(|i, _| {
        let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
        let b = (i as f64 * 0.414_213_562_3).fract();
        DVec2::new(a.cos(), a.sin()) * (0.5 + b)
    });
    let m = &model.mass;
    // Both disks' families, then the first's alone (a body that takes the
    // control in place of the artificial stress beside one that does not).
    let one = model.bodies[1].range.clone();
    for alpha in [[1.0, 1.0], [1.0, 0.0]] {
        for (dv, de) in control_part_of(&model, &st, alpha) {
            if alpha[1] == 0.0 {
                // The disks share no pair (contact couples them): the second
                // feels nothing.
                assert!(one.clone().all(|i| dv[i] == DVec2::ZERO && de[i] == 0.0));
            }
            // Scales: the control's force and power on the particles.
            let f: f64 = (0..m.len()).map(|i| m[i] * dv[i].length()).sum();
            let p: f64 = (0..m.len()).map(|i| m[i] * de[i].abs()).sum();
            assert!(f > 0.0 && p > 0.0, "the control acts: {f} {p}");
            let force: DVec2 = (0..m.len()).map(|i| dv[i] * m[i]).sum();
            let torque: f64 = (0..m.len()).map(|i| m[i] * st.x[i].perp_dot(dv[i])).sum();
            let r = st.x.iter().map(|x| x.length()).fold(0.0, f64::max);
            assert!(force.length() < 1e-12 * f, "net force {force} of {f}");
            assert!(
                torque.abs() < 1e-12 * f * r,
                "net torque {torque} of {}",
                f * r
            );
            // Its work on the velocities is the heat it books, to round-off.
            let work: f64 = (0..m.len()).map(|i| m[i] * st.v[i].dot(dv[i])).sum();
            let heat: f64 = (0..m.len()).map(|i| m[i] * de[i]).sum();
            assert!(
                heat > 0.0 && (work + heat).abs() < 1e-10 * p,
                "work {work}, heat {heat}"
            );
            // Every particle's heat is its own neighbourhood's, never negative.
            for i in 0..m.len() {
                assert!(m[i] * de[i] > -1e-12 * p, "heat {} at {i}", m[i] * de[i]);
            }
        }
    }
    // The sweep and the gather agree to round-off.
    let [s, g] = control_part(&model, &st, 1.0);
    let f = s.0.iter().map(|a| a.length()).fold(0.0, f64::max);
    for i in 0..m.len() {
        assert!((s.0[i] - g.0[i]).length() < 1e-9 * f, "dv of {i}");
    }
}

/// A linear velocity field (a rotation, a shear and a stretch on a
/// translation) is fitted exactly by every particle's neighbourhood, faces
/// and corners included: the control does nothing.
#[test]
fn hourglass_control_leaves_a_linear_field_alone() {
    let (model, st) = disks(|_, x| {
        DVec2::new(
            3.0 + 40.0 * x.x + 70.0 * x.y,
            -1.0 - 90.0 * x.x - 25.0 * x.y,
        )
    });
    // The scale: the control's force on a stirred field of the same size.
    let (_, stirred) = disks(|i, x| {
        let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
        DVec2::new(40.0 * x.x + 70.0 * x.y, -90.0 * x.x) + DVec2::new(a.cos(), a.sin()) * 0.1
    });
    let scale = |dv: &[DVec2]| dv.iter().map(|a| a.length()).fold(0.0, f64::max);
    let [(dv_s, de_s), _] = control_part(&model, &stirred, 1.0);
    let [(dv, de), _] = control_part(&model, &st, 1.0);
    let (fs, fl) = (scale(&dv_s), scale(&dv));
    assert!(
        fs > 0.0 && fl < 1e-6 * fs,
        "linear field: {fl} against {fs}"
    );
    let hs = de_s.iter().map(|e| e.abs()).fold(0.0, f64::max);
    assert!(
        hs > 0.0 && de.iter().all(|e| e.abs() < 1e-6 * hs),
        "heat on a linear field"
    );
}
