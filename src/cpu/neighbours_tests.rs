//! Tests of the neighbours stage (`neighbours.rs`).

use super::neighbours::*;
use crate::model::{Frame, Model};
use crate::scene::Scene;
use glam::DVec2;

/// The model of a 2-D scene of one linear-EOS material `m` and the
/// bodies given as TOML.
pub(in crate::cpu) fn model_of(bodies: &str) -> (Model, crate::model::State) {
    let text = format!(
        r#"
[simulation]
dimension = 2
end_time = 1e-6
[materials.m]
density = 1000.0
eos = {{ kind = "linear", c0 = 1000.0 }}
{bodies}"#
    );
    let scene = Scene::from_toml_str(&text, "test").unwrap();
    Model::new(&scene)
}

/// A polar-lattice disk and a coarser rectangle beside it: two bodies of
/// different spacing, many cells, and particle orders that put some
/// neighbours far apart in index.
pub(in crate::cpu) fn two_bodies() -> (Model, crate::model::State) {
    model_of(
        r#"
[[bodies]]
name = "a"
material = "m"
spacing = 0.1
shape = { kind = "disk", center = [0.0, 0.0], radius = 1.0, lattice = "polar" }
[[bodies]]
name = "b"
material = "m"
spacing = 0.13
shape = { kind = "rectangle", min = [1.01, -0.5], max = [2.0, 0.7] }
"#,
    )
}

/// The cell list finds exactly the pairs an O(N²) search finds, in a
/// scattered 2-D cloud spanning many cells and two bodies.
#[test]
fn cell_list_equals_brute_force() {
    let (model, mut state) = two_bodies();
    // Jitter positions deterministically so no pair sits on a lattice.
    let mut seed = 12345u64;
    for p in state.x.iter_mut() {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let a = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let b = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        *p += DVec2::new(a, b) * 0.08;
    }
    let nb = find(&model, state.frame());
    let n = state.x.len();
    let mut pairs_found = 0;
    for i in 0..n {
        let mut fast: Vec<u32> = nb.of(&model, state.frame(), i).map(|b| b.j).collect();
        fast.extend_from_slice(nb.cross_of(i));
        fast.sort();
        let mut slow = Vec::new();
        for j in 0..n {
            let hij = 0.5 * (model.h[i] + model.h[j]);
            if j != i && (state.x[i] - state.x[j]).length() < 2.0 * hij {
                slow.push(j as u32);
            }
        }
        assert_eq!(fast, slow, "particle {i}");
        pairs_found += slow.len();
    }
    assert!(pairs_found > 10 * n, "a real neighbourhood: {pairs_found}");
    // Cross-body candidates exist and are symmetric.
    assert!(!nb.cross.is_empty());
    for i in 0..n {
        for &j in nb.cross_of(i) {
            assert!(nb.cross_of(j as usize).contains(&(i as u32)));
        }
    }
    // With a skin: the candidates are a superset, and the true pairs
    // filtered from them are the same pairs with the same kernel values
    // (in another order: the cells are larger).
    let skinned = find_with_skin(&model, state.frame(), 0.3 * model.h[0]);
    assert!(skinned.list.len() > nb.list.len());
    for i in 0..n {
        let mut a: Vec<Nbr> = nb.of(&model, state.frame(), i).collect();
        let mut b: Vec<Nbr> = skinned.of(&model, state.frame(), i).collect();
        a.sort_by_key(|p| p.j);
        b.sort_by_key(|p| p.j);
        assert_eq!(a, b, "particle {i}");
    }
}

/// Lists built with a skin stay valid until some particle has moved half
/// the skin, and then say so.
#[test]
fn skin_validity() {
    let (model, state) = model_of(
        r#"
[[bodies]]
name = "a"
material = "m"
spacing = 0.1
shape = { kind = "rectangle", min = [0.0, 0.0], max = [1.0, 1.0] }
"#,
    );
    let skin = 0.04;
    let nb = find_with_skin(&model, state.frame(), skin);
    let mut x = state.x.clone();
    x[7].x += 0.49 * skin;
    assert!(nb.still_valid(Frame::round(&x)));
    x[7].x += 0.02 * skin;
    assert!(!nb.still_valid(Frame::round(&x)));
    // Without a skin the lists hold only at the build positions.
    let exact = find(&model, state.frame());
    assert!(exact.still_valid(state.frame()));
    assert!(!exact.still_valid(Frame::round(&x)));
}

/// Where supports adapt, the lists found by scanning each particle's
/// rings of round-reach cells are those the wide cells give, row for row
/// and in the same order: two bodies, jittered, their supports drawn out
/// up to 4 h along turning directions and squeezed to h/2, a few round.
#[test]
fn adaptive_rings_give_the_wide_cells_lists() {
    use crate::physics::support::Metric;
    let (model, mut state) = two_bodies();
    let mut seed = 777u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for p in state.x.iter_mut() {
        *p += DVec2::new(next() - 0.5, next() - 0.5) * 0.06;
    }
    let metric: Vec<Metric> = (0..state.x.len())
        .map(|i| {
            let h = model.h[i];
            let turn = DVec2::from_angle(6.0 * next());
            match i % 7 {
                0 => Metric::with_axes(0.5 * h, 4.0 * h, turn),
                1 | 2 => Metric::with_axes(0.7 * h, 1.8 * h, turn),
                3 => Metric::with_axes(0.5 * h, 0.9 * h, turn),
                _ => Metric::with_axes(h, h, turn),
            }
        })
        .collect();
    let f = Frame {
        x: &state.x,
        metric: &metric,
    };
    let skin = 0.3 * model.h[0];
    assert!(rings_pay(&model, f, skin), "the rings are scanned");
    let rings = find_scanning(&model, f, skin, true);
    let wide = find_scanning(&model, f, skin, false);
    assert!(
        rings.list.len() > 20 * state.x.len(),
        "{}",
        rings.list.len()
    );
    assert!(!rings.cross.is_empty());
    assert_eq!(rings.start, wide.start);
    assert_eq!(rings.list, wide.list);
    assert_eq!(rings.cross_start, wide.cross_start);
    assert_eq!(rings.cross, wide.cross);
    assert_eq!(rings.fwd_end, wide.fwd_end);
    assert_eq!(rings.far_end, wide.far_end);
}
