use super::*;
use crate::cpu::kinematics::kinematics;
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
