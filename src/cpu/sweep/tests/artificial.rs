//! The artificial stress's work as heat, keyed on the work it does.

use super::*;

/// With `work = "heat"` the artificial stress only heats: on the stirred
/// disks (every sign pattern of principal stress, approaching and
/// receding pairs) no pair's share of its work is below zero, in either
/// form, while with `work = "either"` many are, so the gate has pairs to
/// shut. The viscosity is off, so a pair's energy term is the artificial
/// stress's alone.
#[test]
fn artificial_stress_with_heat_work_only_heats() {
    use crate::scene::ArtWork;
    let (mut model, st, nb) = inviscid_stirred_disks();
    for pairs in [ArtPairs::All, ArtPairs::Close] {
        let mut shares = |work| {
            model.artificial_stress = Some(crate::scene::ArtificialStress {
                epsilon: 0.3,
                n: 4.0,
                pairs,
                work,
                ..crate::scene::ArtificialStress::DEFAULT
            });
            let (mut acted, mut least) = (0, f64::INFINITY);
            for (_, _, t) in every_pair_terms(&model, &st, &nb) {
                if t.shared != 0.0 {
                    acted += 1;
                    least = least.min(t.shared);
                }
            }
            (acted, least)
        };
        let (heat_pairs, heat_least) = shares(ArtWork::Heat);
        let (either_pairs, either_least) = shares(ArtWork::Either);
        assert!(heat_pairs > 100, "{pairs:?}: {heat_pairs} pairs heated");
        assert!(
            heat_least >= 0.0,
            "{pairs:?}: a pair cooled by {heat_least:e}"
        );
        assert!(
            either_least < 0.0 && either_pairs > heat_pairs + 100,
            "{pairs:?}: either {either_pairs} pairs, least {either_least:e}; heat {heat_pairs}"
        );
    }
}

/// With `work = "plastic"` a pair with a particle that flows
/// takes the term as with `work = "heat"` and every other pair as with
/// `"either"`, to the bit: the stirred disks given a yield stress at their
/// median von Mises stress, so that about half the particles flow.
#[test]
fn artificial_stress_keyed_on_plastic_flow() {
    use crate::scene::ArtWork;
    let (mut model, st, nb) = inviscid_stirred_disks();
    yield_at_median(&mut model, &st);
    let mut terms = |work| {
        model.artificial_stress = Some(crate::scene::ArtificialStress {
            work,
            pairs: ArtPairs::All,
            ..crate::scene::ArtificialStress::DEFAULT
        });
        every_pair_terms(&model, &st, &nb)
            .into_iter()
            .map(|(i, j, t)| (i, j, t.tg, t.shared))
            .collect::<Vec<_>>()
    };
    let (plastic, heat, either) = (
        terms(ArtWork::Plastic),
        terms(ArtWork::Heat),
        terms(ArtWork::Either),
    );
    let (mut keyed, mut cooling_kept) = (0, 0);
    for ((p, h), e) in plastic.iter().zip(&heat).zip(&either) {
        let (i, j) = (p.0, p.1);
        let flows = model.flowing(&st, i) || model.flowing(&st, j);
        let want = if flows { h } else { e };
        assert_eq!(
            (p.2.x.to_bits(), p.2.y.to_bits(), p.3.to_bits()),
            (want.2.x.to_bits(), want.2.y.to_bits(), want.3.to_bits()),
            "pair {i} {j} (flows {flows})"
        );
        keyed += (flows && h.3 != e.3) as usize;
        // `shared` is the pair's heat here: one that cools is kept.
        cooling_kept += (!flows && e.3 < 0.0) as usize;
    }
    assert!(
        keyed > 100 && cooling_kept > 100,
        "{keyed} pairs keyed, {cooling_kept} cooling pairs kept"
    );
}

/// [`stirred_disks`] without the viscosity and the hourglass control, so
/// that a pair's energy term is the artificial stress's alone, and their
/// neighbours.
fn inviscid_stirred_disks() -> (Model, State, Neighbours) {
    let (mut model, st) = stirred_disks();
    model.alpha = 0.0;
    model.beta = 0.0;
    model.set_hourglass(0.0);
    let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
    let nb = find_with_skin(&model, st.frame(), skin);
    (model, st, nb)
}

/// Every pair's terms (particle, neighbour, terms), in walk order.
fn every_pair_terms(
    model: &Model,
    st: &State,
    nb: &Neighbours,
) -> Vec<(usize, usize, crate::cpu::forces::PairTerms)> {
    let k = kinematics(model, st, nb);
    let pts = eos_and_stress(model, st);
    let mut out = Vec::new();
    for i in 0..model.len() {
        for b in nb.of(model, st.frame(), i) {
            let t = crate::cpu::forces::pair_terms(model, st, &k, &pts, i, &b);
            out.push((i, b.j as usize, t));
        }
    }
    out
}
