//! Debris (docs/method.md, "Debris"): a particle whose correction falls
//! back carries no deviatoric stress and no tension while it is so.

use glam::DVec2;

use super::kinematics::kinematics;
use super::{eos_and_stress, eos_and_stress_with, evaluate, neighbours};
use crate::bench::{CpuBench, DiskCase};
use crate::math::Sym;

/// The first particles of the first disk moved to `at` (offsets in Δx
/// from a point ten spacings above the bodies' top), moving together at
/// (3, −2) m/s, 1 % below their density and with a deviatoric stress:
/// torn off, in tension. Their indices.
fn tear_off(
    model: &crate::model::Model,
    st: &mut crate::model::State,
    at: &[(f64, f64)],
) -> Vec<usize> {
    let dx = model.bodies[0].spacing;
    let top = st.x.iter().map(|x| x.y).fold(f64::MIN, f64::max);
    let torn: Vec<usize> = model.bodies[0].range.clone().take(at.len()).collect();
    for (&i, &(a, b)) in torn.iter().zip(at) {
        st.x[i] = DVec2::new(a * dx, top + (10.0 + b) * dx);
        st.v[i] = DVec2::new(3.0, -2.0);
        st.rho[i] *= 0.99;
        st.s[i] = Sym {
            xx: 1e8,
            yy: -1e8,
            xy: 5e7,
            zz: 0.0,
        };
    }
    torn
}

/// Three particles of a disk torn off into a straight chain, in tension
/// and with a deviatoric stress, moving together: they are debris, have
/// no stress, and fly on ballistically (no acceleration, no heating),
/// where without the rule the chain would pull itself together. Their
/// deviatoric stress is kept, frozen, for when they rejoin.
#[test]
fn a_torn_off_chain_flies_ballistically() {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (model, mut st) = (bench.model().clone(), bench.state().clone());
    let chain = tear_off(&model, &mut st, &[(-1.0, 0.0), (0.0, 0.0), (1.0, 0.0)]);
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics(&model, &st, &nb);
    let plain = eos_and_stress(&model, &st);
    let pts = eos_and_stress_with(&model, &st, &k.fallback);
    let (rates, _) = evaluate(&model, &st);
    for &i in &chain {
        assert!(k.fallback.contains(&(i as u32)), "{i} is debris");
        // Without the rule: tension and shear.
        assert!(plain[i].sr2.xx > 0.0 && plain[i].sr2.xy != 0.0);
        assert_eq!(pts[i].sr2, Sym::default());
        assert_eq!(k.ds[i], Sym::default(), "frozen deviatoric stress");
        assert_eq!(rates.dv[i], DVec2::ZERO, "ballistic");
        assert_eq!(rates.de[i], 0.0, "no work");
    }
}

/// Five particles torn off together into a compact cross (a centre and
/// four arms at 0.8 Δx), in tension and with a deviatoric stress: every
/// one has four neighbours, a matrix `M` the conditioning test accepts,
/// and too few neighbours to be a continuum. They are debris and fly on
/// ballistically; with the floor off (`debris_neighbours = 0`) the same
/// cluster keeps its correction.
#[test]
fn a_compact_cluster_is_debris() {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (mut model, mut st) = (bench.model().clone(), bench.state().clone());
    assert_eq!(model.bodies[0].debris_neighbours, 5);
    let at = [(0.0, 0.0), (0.8, 0.0), (-0.8, 0.0), (0.0, 0.8), (0.0, -0.8)];
    let cluster = tear_off(&model, &mut st, &at);
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics(&model, &st, &nb);
    let (rates, _) = evaluate(&model, &st);
    for &i in &cluster {
        assert!(k.fallback.contains(&(i as u32)), "{i} is debris");
        assert_eq!(rates.dv[i], DVec2::ZERO, "ballistic");
        assert_eq!(rates.de[i], 0.0, "no work");
    }
    model.bodies[0].debris_neighbours = 0;
    let k = kinematics(&model, &st, &nb);
    for &i in &cluster {
        assert!(!k.fallback.contains(&(i as u32)), "{i} passes M's test");
    }
}

/// Bodies as placed keep their correction everywhere: the faces and
/// corners of a square-lattice block, a strip two particles thick, the
/// staircase of a square-lattice disk, a polar disk and the 90° corners
/// of a polygon on the boundary-following lattice have at least the
/// floor's neighbours; a triangle with 45° corners gets its floor lowered
/// to what they have (where their matrix alone may fall back).
#[test]
fn placed_bodies_keep_their_correction() {
    let (model, st) = super::neighbours_tests::model_of(
        r#"
[[bodies]]
name = "block"
material = "m"
spacing = 0.1
shape = { kind = "rectangle", min = [0.0, 0.0], max = [1.0, 0.6] }
[[bodies]]
name = "strip"
material = "m"
spacing = 0.1
shape = { kind = "rectangle", min = [2.0, 0.0], max = [3.0, 0.2] }
[[bodies]]
name = "disk"
material = "m"
spacing = 0.1
shape = { kind = "disk", center = [0.6, 2.0], radius = 0.6 }
[[bodies]]
name = "polar"
material = "m"
spacing = 0.1
shape = { kind = "disk", center = [2.5, 2.0], radius = 0.6, lattice = "polar" }
[[bodies]]
name = "diamond"
material = "m"
spacing = 0.1
[bodies.shape]
kind = "polygon"
lattice = "boundary"
vertices = [[4.5, 0.0], [5.5, 1.0], [4.5, 2.0], [3.5, 1.0]]
[[bodies]]
name = "wedge"
material = "m"
spacing = 0.1
[bodies.shape]
kind = "polygon"
lattice = "boundary"
vertices = [[7.0, 0.0], [8.0, 1.0], [6.0, 1.0]]
"#,
    );
    let floors: Vec<u32> = model.bodies.iter().map(|b| b.debris_neighbours).collect();
    // The wedge's 45° corners have three neighbours as placed.
    assert_eq!(floors, [5, 5, 5, 5, 5, 3]);
    let nb = neighbours::find(&model, st.frame());
    let k = kinematics(&model, &st, &nb);
    // What falls back is a 45° corner's particle, by its matrix alone.
    for &i in &k.fallback {
        let x = st.x[i as usize];
        let corner = [DVec2::new(8.0, 1.0), DVec2::new(6.0, 1.0)]
            .iter()
            .any(|c| (x - *c).length() < 0.2);
        assert!(model.body[i as usize] == 5 && corner, "{i} at {x}");
    }
}
