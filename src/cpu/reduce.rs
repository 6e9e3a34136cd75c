//! The reduce stage (twin of `shaders/reduce.wgsl`): the CFL step over
//! the particles. (The observations the GPU reduces alongside it are the
//! CPU's probes, [`crate::probe`].)

use rayon::prelude::*;

use super::forces::StressPoint;
use crate::model::{Model, State};
use crate::physics::material;

/// The CFL step (docs/method.md §9): `C min_i h_i / (c_i + |v_i|)` over deformable
/// particles, with the sound speeds of `pts`.
pub fn cfl_step(model: &Model, st: &State, pts: &[StressPoint]) -> f64 {
    (0..model.len())
        .into_par_iter()
        .filter(|&i| !model.rigid(i))
        .map(|i| material::cfl_step(model.cfl, model.h[i], pts[i].c, st.v[i].length()))
        .reduce(|| f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use glam::DVec2;

    /// Three particles of a 1-D bar: `C h / (c + |v|)` worked out by hand
    /// for each, the smallest taken; the rigid wall's is not.
    #[test]
    fn cfl_step_by_hand() {
        let scene = Scene::from_toml_str(
            r#"
[simulation]
dimension = 1
end_time = 1.0e-6
cfl = 0.25
[materials.m]
density = 1000.0
shear_modulus = 1.0e9
eos = { kind = "linear", c0 = 2000.0 }
[[bodies]]
name = "bar"
material = "m"
spacing = 1.0e-3
velocity = [0.0]
shape = { kind = "segment", from = 0.0, to = 3.0e-3 }
"#,
            "cfl",
        )
        .expect("the scene");
        let (model, mut st) = Model::new(&scene);
        assert_eq!(model.len(), 3);
        st.v = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(-500.0, 0.0),
            DVec2::new(100.0, 0.0),
        ];
        let pts: Vec<StressPoint> = (0..3)
            .map(|_| StressPoint {
                c: 2000.0,
                ..Default::default()
            })
            .collect();
        let h = model.h[0];
        // 0.25 h / 2000, 0.25 h / 2500, 0.25 h / 2100: the second.
        assert_eq!(cfl_step(&model, &st, &pts), 0.25 * h / 2500.0);
    }
}
