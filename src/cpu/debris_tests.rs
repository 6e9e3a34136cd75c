//! Debris (docs/method.md, "Debris"): a particle whose correction falls
//! back carries no deviatoric stress and no tension while it is so.

use glam::DVec2;

use super::kinematics::kinematics;
use super::{eos_and_stress, eos_and_stress_with, evaluate, neighbours};
use crate::bench::{CpuBench, DiskCase};
use crate::math::Sym;

/// Three particles of a disk torn off into a straight chain, in tension
/// and with a deviatoric stress, moving together: they are debris, have
/// no stress, and fly on ballistically (no acceleration, no heating),
/// where without the rule the chain would pull itself together. Their
/// deviatoric stress is kept, frozen, for when they rejoin.
#[test]
fn a_torn_off_chain_flies_ballistically() {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (model, mut st) = (bench.model().clone(), bench.state().clone());
    let dx = model.bodies[0].spacing;
    let top = st.x.iter().map(|x| x.y).fold(f64::MIN, f64::max);
    let chain: Vec<usize> = (0..model.len())
        .filter(|&i| model.body[i] == 0)
        .take(3)
        .collect();
    let s = Sym {
        xx: 1e8,
        yy: -1e8,
        xy: 5e7,
        zz: 0.0,
    };
    for (k, &i) in chain.iter().enumerate() {
        st.x[i] = DVec2::new((k as f64 - 1.0) * dx, top + 10.0 * dx);
        st.v[i] = DVec2::new(3.0, -2.0);
        st.rho[i] *= 0.99;
        st.s[i] = s;
    }
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
