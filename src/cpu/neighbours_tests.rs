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

/// Lists built with a skin stay valid while no two particles that can
/// meet have moved apart or together by more than the skin, and then say
/// so: one particle may move almost the whole skin, the body as a whole
/// up to half the lists' reach.
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
    let moved = |k: usize, by: f64| {
        let mut x = state.x.clone();
        x[k].x += by;
        x
    };
    let shifted =
        |by: f64| -> Vec<DVec2> { state.x.iter().map(|&p| p + DVec2::new(by, -by)).collect() };
    let valid = |nb: &Neighbours, x: &[DVec2]| nb.still_valid(&model, Frame::round(x));
    assert!(valid(&nb, &moved(7, 0.49 * skin)));
    assert!(valid(&nb, &moved(7, 0.99 * skin)));
    assert!(!valid(&nb, &moved(7, 1.01 * skin)));
    // Half the reach, `2 h + skin` (0.28), along the diagonal.
    let reach = 2.0 * model.h[0] + skin;
    assert!(valid(&nb, &shifted(0.49 * reach / 2f64.sqrt())));
    assert!(!valid(&nb, &shifted(0.51 * reach / 2f64.sqrt())));
    // Without a skin the lists hold only at the build positions.
    let exact = find(&model, state.frame());
    assert!(valid(&exact, &state.x));
    assert!(!valid(&exact, &moved(7, 1e-9)));
}

/// Whenever the lists call themselves valid, they hold every pair and
/// every contact candidate the exact lists at those positions hold: two
/// bodies a hundredth apart, each moved as a whole and its particles
/// jittered, in many combinations. Some are valid only by the relative
/// test (a particle moved more than half the skin), some are not valid;
/// and the test can fail: the bodies closing by twice the skin miss pairs.
#[test]
fn valid_lists_hold_every_pair() {
    let (model, state) = two_bodies();
    let h_max = model.h.iter().cloned().fold(0.0, f64::max);
    let skin = 0.3 * h_max;
    let nb = find_with_skin(&model, state.frame(), skin);
    let body_b = model.bodies[1].range.clone();
    let field = |ta: DVec2, tb: DVec2, jitter: f64| -> Vec<DVec2> {
        state
            .x
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let r = |m: f64| ((i as f64 * m).fract() - 0.5) * 2.0 * jitter;
                let t = if body_b.contains(&i) { tb } else { ta };
                p + t + DVec2::new(r(0.618_033_988_7), r(0.414_213_562_3))
            })
            .collect()
    };
    let holds = |x: &[DVec2]| {
        let exact = find(&model, Frame::round(x));
        (0..x.len()).all(|i| {
            let own: std::collections::HashSet<u32> = nb.candidates(i).iter().copied().collect();
            let cross: std::collections::HashSet<u32> = nb.cross_of(i).iter().copied().collect();
            exact.candidates(i).iter().all(|j| own.contains(j))
                && exact.cross_of(i).iter().all(|j| cross.contains(j))
        })
    };
    let (mut valid, mut beyond_half, mut invalid) = (0, 0, 0);
    let shifts = [0.0, 0.4, 0.9, 3.0, 20.0];
    for &a in &shifts {
        for &b in &shifts {
            for &(jitter, dir) in &[(0.0, 1.0), (0.2, -1.0), (0.45, 1.0)] {
                let (ta, tb) = (
                    DVec2::new(0.0, dir * a * skin),
                    DVec2::new(0.0, dir * b * skin),
                );
                let x = field(ta, tb, jitter * skin);
                if nb.still_valid(&model, Frame::round(&x)) {
                    assert!(
                        holds(&x),
                        "a {a} b {b} jitter {jitter}: valid lists miss a pair"
                    );
                    valid += 1;
                    let far = x
                        .iter()
                        .zip(&state.x)
                        .any(|(p, q)| p.distance(*q) > 0.5 * skin);
                    beyond_half += usize::from(far);
                } else {
                    invalid += 1;
                }
            }
        }
    }
    assert!(
        beyond_half > 5 && invalid > 5,
        "valid {valid} ({beyond_half} beyond half the skin), invalid {invalid}"
    );
    // Body b closing on a by twice the skin: not valid, and rightly so.
    let x = field(DVec2::ZERO, DVec2::new(-2.0 * skin, 0.0), 0.0);
    assert!(!nb.still_valid(&model, Frame::round(&x)));
    assert!(!holds(&x), "the closing bodies meet new candidates");
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
