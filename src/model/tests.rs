use super::*;

fn scene(lattice: &str, jitter: f64) -> Scene {
    Scene::from_toml_str(
        &format!(
            r#"
            [simulation]
            dimension = 2
            end_time = 1.0e-6
            interaction = "penalty"
            [materials.steel]
            density = 7850.0
            shear_modulus = 77.0e9
            eos = {{ kind = "linear", c0 = 4580.0 }}
            [[bodies]]
            name = "a"
            material = "steel"
            spacing = 1.0e-4
            jitter = {jitter}
            seed = 7
            shape = {{ kind = "disk", center = [0.0, 0.0], radius = 2.0e-3, lattice = "{lattice}" }}
            [[bodies]]
            name = "b"
            material = "steel"
            spacing = 1.0e-4
            shape = {{ kind = "rectangle", min = [3.0e-3, -2.0e-3], max = [5.0e-3, 2.0e-3] }}
            "#
        ),
        "the test scene",
    )
    .expect("a valid scene")
}

/// The model keeps the contact's step limit over its pairs of bodies
/// (two steel bodies of one spacing: `Δx / (√2 c_L)`), infinite
/// without contact; the CPU solver's step is the shorter of it and the
/// CFL step, and a fixed step is left as the scene gives it.
#[test]
fn contact_step_limit_holds_the_solvers_step() {
    let mut sc = scene("square", 0.0);
    let (m, _) = Model::new(&sc);
    let c = m.bodies[0].material.c_l;
    let limit = 1.0e-4 / (2f64.sqrt() * c);
    assert!(
        (m.contact_dt / limit - 1.0).abs() < 1e-14,
        "{}",
        m.contact_dt
    );
    let next_dt = |sc: &Scene| {
        let (m, st) = Model::new(sc);
        crate::cpu::CpuSolver::new(m, st).next_dt()
    };
    sc.simulation.cfl = 0.9;
    assert_eq!(next_dt(&sc), m.contact_dt);
    sc.simulation.cfl = 0.3;
    assert!(next_dt(&sc) < 0.6 * m.contact_dt);
    sc.simulation.cfl = 0.9;
    sc.simulation.dt = Some(1.2 * m.contact_dt);
    assert_eq!(next_dt(&sc), 1.2 * m.contact_dt);
    sc.simulation.interaction = Interaction::Kernel;
    assert_eq!(Model::new(&sc).0.contact_dt, f64::INFINITY);
}

/// Each particle's surface offset as placed, the model and state the
/// scene builds, and which particles the solver's test puts on the
/// boundary.
fn placed_offsets(sc: &Scene) -> (Vec<f64>, Model, State, Vec<bool>) {
    let placed = place_bodies(sc)
        .iter()
        .flat_map(|p| p.offsets.iter().copied())
        .collect();
    let (m, st) = Model::new(sc);
    let (_, boundary) = crate::cpu::surface(&m, &st);
    (placed, m, st, boundary)
}

/// Every particle the solver finds on the boundary as placed keeps the
/// surface offset its placement gave it, on the square and polar
/// lattices, jittered or not: the fresh surfaces' half spacing goes
/// only to particles deeper than any outer layer, and to some of them
/// in each body.
#[test]
fn boundary_particles_keep_their_placed_offsets() {
    for (lattice, jitter) in [
        ("square", 0.0),
        ("polar", 0.0),
        ("square", 0.3),
        ("square", 0.45),
    ] {
        let (placed, m, _, boundary) = placed_offsets(&scene(lattice, jitter));
        let mut fresh = vec![0; m.bodies.len()];
        for i in 0..m.len() {
            if boundary[i] {
                assert_eq!(
                    m.offset[i],
                    placed[i],
                    "{lattice} {jitter}: particle {i} placed {}",
                    placed[i] / m.spacing_of(i)
                );
            } else if m.offset[i] != placed[i] {
                assert_eq!(m.offset[i], 0.5 * m.spacing_of(i));
                fresh[m.body[i] as usize] += 1;
            }
        }
        assert!(
            fresh.iter().all(|&n| n > 100),
            "{lattice} {jitter}: {fresh:?}"
        );
    }
}

/// In a body of revolution the axis is no surface: a rod's and a
/// sphere's particles along it, placed as deep as their distance to
/// the face or the pole, are off the solver's boundary (which counts
/// the images across the axis) and carry a fresh surface's half
/// spacing, while every boundary particle keeps its placed offset.
/// Kept at their depth, the axis particles of a Taylor rod entered the
/// contact with surface points spacings in front of them as the face
/// spread (the face's centre pressed through the wall).
#[test]
fn the_axis_of_a_body_of_revolution_is_no_surface() {
    let sc = Scene::from_toml_str(
        r#"
        [simulation]
        dimension = 2
        geometry = "axisymmetric"
        end_time = 1.0e-6
        interaction = "penalty"
        [materials.steel]
        density = 7850.0
        shear_modulus = 77.0e9
        eos = { kind = "linear", c0 = 4580.0 }
        [[bodies]]
        name = "rod"
        material = "steel"
        spacing = 1.0e-4
        shape = { kind = "rectangle", min = [0.0, 0.0], max = [1.6e-3, 3.0e-3] }
        [[bodies]]
        name = "ball"
        material = "steel"
        spacing = 1.0e-4
        shape = { kind = "disk", center = [0.0, 5.0e-3], radius = 1.5e-3, lattice = "polar" }
        "#,
        "the test scene",
    )
    .expect("a valid scene");
    let (placed, m, st, boundary) = placed_offsets(&sc);
    let mut fresh_on_axis = vec![0; m.bodies.len()];
    for i in 0..m.len() {
        let dx = m.spacing_of(i);
        if boundary[i] {
            assert_eq!(m.offset[i], placed[i], "particle {i}");
        } else if placed[i] > crate::physics::penalty::FRESH_DEPTH * dx {
            assert_eq!(m.offset[i], 0.5 * dx, "particle {i} at {}", st.x[i]);
            fresh_on_axis[m.body[i] as usize] += usize::from(st.x[i].x < dx);
        }
    }
    // The rod's axis column below its top's outer layers, the ball's
    // inside its poles'.
    assert!(fresh_on_axis.iter().all(|&n| n >= 10), "{fresh_on_axis:?}");
}

/// The close-pair scales: 1 on the square lattice; on a jittered one
/// the brute-force nearest neighbour of the particle's own body over
/// its volume's side, capped at 1; the default form computes them and
/// a scene that switches the term off carries none.
#[test]
fn close_scales_are_the_placed_nearest_neighbour() {
    let (m, st) = Model::new(&scene("square", 0.0));
    assert!(m.close_scales(&st.x).iter().all(|&k| k == 1.0));
    assert!(m.close_scale.is_empty(), "all 1: none kept");

    let (m, st2) = Model::new(&scene("square", 0.1));
    let mut below = 0;
    for i in 0..m.len() {
        let d2 = (0..m.len())
            .filter(|&j| j != i && m.body[j] == m.body[i])
            .map(|j| (st2.x[j] - st2.x[i]).length_squared())
            .fold(f64::INFINITY, f64::min);
        let want = (d2 / (m.mass[i] / 7850.0)).min(1.0);
        assert_eq!(m.close_scale.len(), m.len());
        assert!((m.close_scale[i] - want).abs() < 1e-12, "particle {i}");
        below += (want < 0.99) as usize;
    }
    assert!(below > m.bodies[0].range.len() / 2, "{below} below 0.99");
    // The rectangle is not jittered: its scales stay 1.
    let b = m.bodies[1].range.clone();
    assert!(m.close_scale[b].iter().all(|&k| k == 1.0));

    let mut off = scene("square", 0.0);
    off.artificial_stress = Some(ArtificialStress {
        epsilon: 0.0,
        ..ArtificialStress::DEFAULT
    });
    let (m, _) = Model::new(&off);
    assert!(m.artificial_stress.is_none() && m.close_scale.is_empty());
}
