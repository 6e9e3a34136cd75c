//! The reduce stage (twin of `shaders/reduce.wgsl`): the CFL step over
//! the particles. (The observations the GPU reduces alongside it are the
//! CPU's probes, [`crate::probe`].)

use rayon::prelude::*;

use super::kinematics::StressPoint;
use crate::model::{Model, State};
use crate::physics::material;
use crate::physics::support::Metric;

/// The CFL step (docs/method.md §9): `C min_i h_i / (c_i + |v_i|)` over deformable
/// particles, with the sound speeds of `pts`.
pub fn cfl_step(model: &Model, st: &State, pts: &[StressPoint]) -> f64 {
    (0..model.len())
        .into_par_iter()
        .filter(|&i| !model.rigid(i))
        .map(|i| {
            let h = support_h(model, &st.metric, i);
            material::cfl_step(model.cfl, h, pts[i].c, st.v[i].length())
        })
        .reduce(|| f64::INFINITY, f64::min)
}

/// The smoothing length the CFL step takes for particle i: its `h`, or,
/// where supports adapt, its support's minor semi-axis.
#[inline]
pub(super) fn support_h(model: &Model, metric: &[Metric], i: usize) -> f64 {
    match metric.get(i) {
        Some(q) => q.axes().0,
        None => model.h[i],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// The paper's bars at three particles each, the right bar made rigid
    /// and thrown at 1e5 m/s: `C h / (c + |v|)` worked out by hand for the
    /// left bar's three particles, the smallest taken; the rigid bar's,
    /// far smaller, is not.
    #[test]
    fn cfl_step_by_hand() {
        let mut scene = crate::validation::bar_scene(crate::validation::BARS, 3, 1e-8);
        scene.bodies[1].rigid = true;
        let (model, mut st) = Model::new(&scene);
        assert_eq!(model.len(), 6);
        st.v = [0.0, -500.0, 100.0, 1e5, 1e5, 1e5]
            .map(|v| DVec2::new(v, 0.0))
            .to_vec();
        let pts: Vec<StressPoint> = (0..6)
            .map(|_| StressPoint {
                c: 2000.0,
                ..Default::default()
            })
            .collect();
        let (c, h) = (model.cfl, model.h[0]);
        // C h / 2000, C h / 2500, C h / 2100: the second.
        assert_eq!(cfl_step(&model, &st, &pts), c * h / 2500.0);
    }
}
