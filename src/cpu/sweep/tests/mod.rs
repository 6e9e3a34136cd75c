//! Tests of the pair-once sweeps: the same sums as the plain gathers,
//! the lane code's bits equal to the one-pair code's, the same bits on
//! any thread count.

mod artificial;
mod lanes;

use super::forces::sums;
use super::forces_lanes::lanes_serve;
use super::forces_lanes::SumsOut;
use super::*;
use crate::bench::{CpuBench, DiskCase};
use crate::cpu::neighbours::{find_with_skin, Neighbours};
use crate::cpu::neighbours_tests::two_bodies;
use crate::cpu::{eos_and_stress, SKIN_FRACTION};
use crate::math::Sym;
use crate::model::{Frame, Model, State};
use crate::scene::ArtPairs;
use glam::DVec2;

/// The pair sweep sums what a gather over every particle's own partners
/// sums, with small chunks (so that far pairs and both phases occur) as
/// with the default, and the same bits on one thread as on three.
#[test]
fn sweep_equals_gather() {
    let (model, state) = two_bodies();
    let x = &state.x;
    let n = x.len();
    // Σ W_ij, Σ ∇_i W_ij and Σ j W_ij: symmetric, antisymmetric and
    // neither, so a term added to the wrong side shows.
    type Acc = (f64, DVec2, f64);
    let gather: Vec<Acc> = {
        let nb = find_with_skin(&model, Frame::round(x), 0.05);
        (0..n)
            .map(|i| {
                nb.of(&model, Frame::round(x), i)
                    .fold((0.0, DVec2::ZERO, 0.0), |a, b| {
                        (a.0 + b.w, a.1 + b.gw, a.2 + b.j as f64 * b.w)
                    })
            })
            .collect()
    };
    let sweep = |nb: &Neighbours| {
        let mut acc = vec![(0.0, DVec2::ZERO, 0.0); n];
        nb.sweep(
            &model,
            Frame::round(x),
            &mut acc,
            |i, b, ai: &mut Acc, aj: Option<&mut Acc>| {
                ai.0 += b.w;
                ai.1 += b.gw;
                ai.2 += b.j as f64 * b.w;
                if let Some(aj) = aj {
                    aj.0 += b.w;
                    aj.1 -= b.gw;
                    aj.2 += i as f64 * b.w;
                }
            },
        );
        acc
    };
    for chunk in [Some(8), Some(64), None] {
        let mut nb = find_with_skin(&model, Frame::round(x), 0.05);
        let plain = nb.clone();
        // The lists come indexed with the default chunk.
        let far = |nb: &Neighbours| -> usize {
            (0..n)
                .map(|i| (nb.far_end[i] - nb.fwd_end[i]) as usize)
                .sum()
        };
        // 1 % of the pairs, each in both of its rows: 2 % of the entries.
        assert!(
            far(&nb) * 50 < nb.list.len(),
            "the default leaves under 2 % of the row entries far"
        );
        if let Some(c) = chunk {
            nb.index_rows_in(c);
            assert!(far(&nb) > 0, "far pairs with chunks of {c}");
        }
        let chunk = nb.chunk;
        for i in 0..n {
            // Each row is a permutation of the unindexed one, and
            // indexing again changes nothing.
            let (mut a, mut b) = (nb.candidates(i).to_vec(), plain.candidates(i).to_vec());
            a.sort();
            b.sort();
            assert_eq!(a, b, "row {i}");
        }
        let again = {
            let mut c = nb.clone();
            c.index_rows_in(chunk);
            c
        };
        assert_eq!(again.list, nb.list);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let three = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let s1 = one.install(|| sweep(&nb));
        let s3 = three.install(|| sweep(&nb));
        for i in 0..n {
            let (g, s) = (gather[i], s1[i]);
            let scale = g.0.abs() + g.1.length() * model.h[i];
            assert!((g.0 - s.0).abs() < 1e-12 * scale, "ΣW at {i}: {g:?} {s:?}");
            assert!(
                (g.1 - s.1).length() * model.h[i] < 1e-12 * scale,
                "Σ∇W at {i}"
            );
            assert!((g.2 - s.2).abs() < 1e-12 * n as f64 * scale, "Σ jW at {i}");
            assert_eq!(s1[i].0.to_bits(), s3[i].0.to_bits(), "thread count, {i}");
            assert_eq!(s1[i].1, s3[i].1, "thread count, {i}");
        }
    }
}

/// The sweeps sum what the plain gathers sum (kinematics and forces, to
/// round-off; with one disk rigid too), and the lane code gives the
/// one-pair code's sums bit for bit, on the disks in contact with a velocity field stirred so that every branch
/// is taken both ways in many pairs (receding and approaching pairs,
/// the limiter on and off): with the reconstructed viscosity and
/// without, on candidate lists with a skin (candidates beyond the
/// support in the rows), and in kernel mode (SPH sums across the
/// bodies) with the second disk's `h` changed, so that pairs across
/// the contact take `h_ij` of two different lengths.
#[test]
fn sweeps_match_gathers_and_lanes_one_pair_code() {
    let (base, st) = stirred_disks_3000();
    let failed = with_failures(&st);
    // The leapfrog's kinematics (hourglass, "seen"): the viscosity's
    // gradient of other velocities, the control's of the state's.
    let seen_v: Vec<DVec2> =
        st.v.iter()
            .enumerate()
            .map(|(i, v)| *v + DVec2::new(0.1, -0.2) * (i as f64 * 0.271_828).fract())
            .collect();
    let (without_control, with_control) = sweep_cases();
    // Each case with Monaghan's viscosity and with the Riemann form
    // reconstructed at surfaces too.
    for ((reconstruct, h_ratio, art, damaged, (hourglass, seen, keyed)), riemann) in without_control
        .into_iter()
        .chain(with_control)
        .flat_map(|c| [(c, false), (c, true)])
    {
        let st = if damaged { &failed } else { &st };
        let mut model = base.clone();
        model.artificial_stress = art.map(as_of);
        if art.is_some_and(|a| a.1 == 3.5 && a.2 == ArtPairs::Close) {
            // Placement scales below 1, as jitter leaves them.
            model.close_scale = (0..model.len())
                .map(|i| 1.0 - 0.03 * (i as f64 * 0.377_964_473_0).fract())
                .collect();
        }
        if art.is_some() {
            let n = tensile(&model, st);
            assert!(n > model.len() / 4 && n < model.len(), "{n} in tension");
        }
        if art.is_some_and(|a| a.1 == 3.0) {
            yield_at_median(&mut model, st);
            let n = (0..model.len()).filter(|&i| model.flowing(st, i)).count();
            assert!(n > model.len() / 4 && n < model.len() * 3 / 4, "{n} flow");
        }
        model.av_reconstruct = reconstruct;
        model.av_release = riemann;
        model.av_recon_surface = riemann;
        model.set_hourglass(hourglass);
        if keyed {
            model.bodies[0].art = false;
            model.bodies[1].hourglass = 0.0;
        }
        model.contact = h_ratio == 1.0;
        for i in 0..model.len() {
            if model.body[i] == 1 {
                model.h[i] *= h_ratio;
            }
        }
        let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
        let nb = find_with_skin(&model, st.frame(), skin);
        let k = if seen {
            let k = kinematics_seen(&model, st, &nb, &seen_v);
            assert!(!k.hv.is_empty() && !k.hgrad.is_empty());
            k
        } else {
            kinematics(&model, st, &nb)
        };
        let pts = eos_and_stress(&model, st);
        if keyed {
            // The first disk carries no artificial stress, the second does.
            let tension = |b: usize| {
                model.bodies[b]
                    .range
                    .clone()
                    .filter(|&i| pts[i].r.xx + pts[i].r.yy < 0.0)
                    .count()
            };
            assert_eq!(tension(0), 0);
            assert!(tension(1) > model.bodies[1].range.len() / 4);
        }
        let args = (&model, st, &nb, &k, &pts[..]);
        let one = sums(args, false, None);
        let four = sums(args, true, None);
        let bits = |v: &DVec2| (v.x.to_bits(), v.y.to_bits());
        for i in 0..model.len() {
            assert_eq!(bits(&one.0[i]), bits(&four.0[i]), "dv of {i}");
            assert_eq!(one.1[i].to_bits(), four.1[i].to_bits(), "de of {i}");
        }
        assert_eq!(one.2.to_bits(), four.2.to_bits(), "dissipation");
        // The sums are not trivially equal: the pass does work.
        assert!(one.0.iter().filter(|a| a.length() > 0.0).count() > model.len() / 2);
        if riemann {
            // ... and the form acts: on receding pairs, and at surfaces.
            let mut plain = model.clone();
            plain.av_release = false;
            plain.av_recon_surface = false;
            let m = sums((&plain, st, &nb, &k, &pts[..]), true, None);
            let moved = (0..model.len()).filter(|&i| m.0[i] != four.0[i]).count();
            assert!(moved > model.len() / 2, "the Riemann form moved {moved}");
        }
        if hourglass > 0.0 {
            // ... and the control's part of it.
            let mut off = model.clone();
            off.set_hourglass(0.0);
            let none = sums((&off, st, &nb, &k, &pts[..]), true, None);
            let moved = (0..model.len()).filter(|&i| none.0[i] != four.0[i]).count();
            // Keyed, the first disk's families alone.
            let with = if keyed {
                model.bodies[0].range.len()
            } else {
                model.len()
            };
            assert!(moved > with / 2, "the control moved {moved}");
        }
        if seen {
            // The gather below takes the state's own kinematics.
            continue;
        }
        gathers_match(&model, st, &nb, &one);
        dissipation_is_the_artificial_terms_work(&model, st, &nb, &one);
        if art.is_none() && !damaged && hourglass == 0.0 {
            rigid_disk_matches(&model, st, &nb, &pts);
        }
    }
}

/// How many particles of `st` carry an artificial stress.
fn tensile(m: &Model, st: &State) -> usize {
    let pts = eos_and_stress(m, st);
    pts.iter().filter(|p| p.r != Sym::default()).count()
}

/// The 3,000-particle disks in contact, velocities, densities and
/// deviators stirred.
fn stirred_disks_3000() -> (Model, State) {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (base, mut st) = (bench.model().clone(), bench.state().clone());
    for (i, v) in st.v.iter_mut().enumerate() {
        let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
        *v += DVec2::new(a.cos(), a.sin()) * 0.3;
    }
    // Densities and deviators stirred too, so that the principal
    // stresses take every sign pattern and the artificial stress acts.
    let rho0 = st.rho[0];
    for i in 0..st.rho.len() {
        let a = (i as f64 * 0.414_213_562_3).fract() - 0.5;
        let b = (i as f64 * 0.732_050_807_6).fract() - 0.5;
        st.rho[i] *= 1.0 + 2e-3 * a;
        st.s[i] = Sym {
            xx: 2e-3 * rho0 * b,
            yy: -1e-3 * rho0 * a,
            xy: 1.5e-3 * rho0 * (a + b),
            zz: 1e-3 * rho0 * (b - a),
        };
    }
    (base, st)
}

/// `st` with every seventh particle failed, and every eleventh intact with
/// a void open (State::damage_of): it takes no part in the artificial
/// stress, and no tension.
fn with_failures(st: &State) -> State {
    let mut failed = st.clone();
    failed.damage = (0..st.x.len())
        .map(|i| if i % 7 == 3 { 1.0 } else { 0.4 })
        .collect();
    failed.failed_at = (0..st.x.len())
        .map(|i| {
            if i % 11 == 5 && i % 7 != 3 {
                crate::physics::strength::VOID_OPEN
            } else {
                crate::physics::strength::INTACT
            }
        })
        .collect();
    failed
}

/// One case of the sweep tests: the reconstruction, the second disk's
/// smoothing ratio, the artificial stress `(ε, n, pairs)`, damaged, and
/// the hourglass control `(α_hg, seen, keyed)`.
type SweepCase = (
    bool,
    f64,
    Option<(f64, f64, ArtPairs)>,
    bool,
    (f64, bool, bool),
);

/// The sweep tests' cases without the hourglass control and with it.
fn sweep_cases() -> ([SweepCase; 11], [SweepCase; 6]) {
    let without_control = [
        (true, 1.0, None, false),
        (false, 1.0, None, false),
        (true, 1.15, None, false),
        (true, 1.0, Some((0.3, 4.0, ArtPairs::All)), false),
        (false, 1.15, Some((0.2, 3.5, ArtPairs::All)), false),
        (true, 1.0, Some((0.3, 4.0, ArtPairs::Close)), false),
        (false, 1.15, Some((0.2, 3.5, ArtPairs::Close)), false),
        (true, 1.0, Some((0.3, 4.0, ArtPairs::All)), true),
        (false, 1.0, Some((0.3, 4.0, ArtPairs::Close)), true),
        (false, 1.15, Some((0.2, 3.0, ArtPairs::All)), false),
        (true, 1.0, Some((0.3, 3.0, ArtPairs::Close)), true),
    ]
    .map(|(r, h, a, d)| (r, h, a, d, (0.0, false, false)));
    // The hourglass control: (α_hg, the leapfrog's kinematics, keyed:
    // the first disk takes it in place of the artificial stress and the
    // second the term without it, `plastic = "hourglass"`).
    let with_control = [
        (true, 1.0, None, false, (0.7, false, false)),
        (false, 1.15, None, false, (1.0, false, false)),
        (
            true,
            1.0,
            Some((0.3, 4.0, ArtPairs::Close)),
            true,
            (0.7, false, false),
        ),
        (true, 1.0, None, false, (0.7, true, false)),
        (
            false,
            1.15,
            Some((0.3, 4.0, ArtPairs::All)),
            false,
            (0.5, false, true),
        ),
        (
            true,
            1.0,
            Some((0.3, 4.0, ArtPairs::Close)),
            true,
            (0.5, true, true),
        ),
    ];
    (without_control, with_control)
}

/// One disk rigid: the one-pair code's zero rates against the gather's;
/// kept for a later booking (the leapfrog's), its artificial work at these
/// velocities is the same.
fn rigid_disk_matches(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    pts: &[crate::cpu::kinematics::StressPoint],
) {
    let mut rigid = model.clone();
    rigid.bodies[1].rigid = true;
    rigid.any_rigid = true;
    let k = kinematics(&rigid, st, nb);
    let out = sums((&rigid, st, nb, &k, pts), false, None);
    gathers_match(&rigid, st, nb, &out);
    dissipation_is_the_artificial_terms_work(&rigid, st, nb, &out);
    // Kept for a later booking (the leapfrog's), the one-pair
    // code's artificial work at these velocities is the same.
    let mut kept = vec![[DVec2::ZERO; 2]; nb.store_len()];
    let (_, _, fixed, c) = sums((&rigid, st, nb, &k, pts), false, Some(&mut kept));
    let at = fixed - (0..rigid.len()).map(|i| c[i].dot(st.v[i])).sum::<f64>();
    assert!(
        (at - out.2).abs() <= 1e-12 * out.2.abs(),
        "kept {at:e} against {:e}",
        out.2
    );
}

/// Where supports adapt (docs/method.md, "Supports that follow the
/// deformation"), the sweeps sum what the plain gathers sum and the lane
/// code gives the one-pair code's sums bit for bit, on the stirred disks
/// with every particle's support an ellipse of its own (semi-axes from
/// 0.6 h to 2.5 h, turned every way), with and without the artificial
/// stress in both forms.
#[test]
fn adaptive_sweeps_match_gathers_and_lanes_one_pair_code() {
    use crate::physics::support::Metric;
    let (mut model, mut st) = stirred_disks();
    for i in 0..st.x.len() {
        let (a, b) = stir(i);
        let h = model.h[i];
        let e = DVec2::new(
            (b * std::f64::consts::TAU).cos(),
            (b * std::f64::consts::TAU).sin(),
        );
        st.metric.push(Metric::with_axes(
            h * (0.6 + 0.4 * a),
            h * (1.0 + 1.5 * b),
            e,
        ));
    }
    model.adaptive = true;
    let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
    let nb = find_with_skin(&model, st.frame(), skin);
    assert_eq!(nb.support_ref.len(), model.len());
    for (reconstruct, art) in [
        (true, None),
        (false, Some((0.3, 4.0, ArtPairs::All))),
        (true, Some((0.3, 4.0, ArtPairs::Close))),
    ] {
        model.av_reconstruct = reconstruct;
        model.artificial_stress = art.map(as_of);
        let k = kinematics(&model, &st, &nb);
        let pts = eos_and_stress(&model, &st);
        let args = (&model, &st, &nb, &k, &pts[..]);
        let one = sums(args, false, None);
        let four = sums(args, true, None);
        for i in 0..model.len() {
            assert_eq!(one.0[i].x.to_bits(), four.0[i].x.to_bits(), "dv of {i}");
            assert_eq!(one.0[i].y.to_bits(), four.0[i].y.to_bits(), "dv of {i}");
            assert_eq!(one.1[i].to_bits(), four.1[i].to_bits(), "de of {i}");
        }
        assert_eq!(one.2.to_bits(), four.2.to_bits(), "dissipation");
        gathers_match(&model, &st, &nb, &one);
        dissipation_is_the_artificial_terms_work(&model, &st, &nb, &one);
        // The supports change the sums: the same state with round ones
        // gives other forces.
        let (mut round, mut flat) = (model.clone(), st.clone());
        (round.adaptive, flat.metric) = (false, Vec::new());
        let nbr = find_with_skin(&round, flat.frame(), skin);
        let kr = kinematics(&round, &flat, &nbr);
        let r = sums((&round, &flat, &nbr, &kr, &pts[..]), true, None);
        let moved =
            (0..model.len()).filter(|&i| (r.0[i] - one.0[i]).length() > 1e-3 * one.0[i].length());
        assert!(moved.count() > model.len() / 2);
    }
}

/// The plain gathers ([`crate::cpu::kinematics::kinematics`],
/// [`crate::cpu::forces::momentum_energy`]) sum what the sweeps sum,
/// `sums` the sweep's forces, to round-off: each field within 1e-12 of its
/// largest value (the sums differ only in the order of their terms).
fn gathers_match(model: &Model, st: &State, nb: &Neighbours, sums: &SumsOut) {
    let k = kinematics(model, st, nb);
    let plain = crate::cpu::kinematics::kinematics(model, st, nb);
    let close = |what: &str, a: &[f64], b: &[f64]| {
        let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(scale > 0.0, "{what} is zero");
        for i in 0..a.len() {
            assert!(
                (a[i] - b[i]).abs() <= 1e-12 * scale,
                "{what} of {i}: {} against {}",
                a[i],
                b[i]
            );
        }
    };
    let flat = |m: &[crate::math::Mat2]| -> Vec<f64> {
        m.iter().flat_map(|m| [m.xx, m.xy, m.yx, m.yy]).collect()
    };
    let syms =
        |s: &[Sym]| -> Vec<f64> { s.iter().flat_map(|s| [s.xx, s.yy, s.xy, s.zz]).collect() };
    let xy = |v: &[DVec2]| -> Vec<f64> { v.iter().flat_map(|v| [v.x, v.y]).collect() };
    close("L", &flat(&k.l), &flat(&plain.l));
    close("∇ψ", &xy(&k.grad_psi), &xy(&plain.grad_psi));
    close("dρ/dt", &k.drho, &plain.drho);
    close("ds/dt", &syms(&k.ds), &syms(&plain.ds));
    assert_eq!(k.surface, plain.surface, "surface set");
    assert_eq!(k.fallback, plain.fallback, "fallbacks");
    if model.av_reconstruct {
        close("∇v", &flat(&k.gv), &flat(&plain.gv));
    }
    let pts = eos_and_stress(model, st);
    let (dv, de, d) = crate::cpu::forces::rates_and_dissipation(model, st, nb, &k, &pts);
    close("dv/dt", &xy(&sums.0), &xy(&dv));
    close("de/dt", &sums.1, &de);
    let power: f64 = (0..model.len()).map(|i| model.mass[i] * de[i].abs()).sum();
    assert!(
        (sums.2 - d).abs() <= 1e-12 * power,
        "dissipation {} against the gather's {d}",
        sums.2
    );
    if model.any_rigid {
        let rigid = (0..model.len()).filter(|&i| model.rigid(i));
        assert!(rigid.clone().count() > 0);
        for i in rigid {
            assert_eq!((dv[i], de[i]), (DVec2::ZERO, 0.0), "rigid {i}");
        }
    }
}

/// The artificial dissipation rate of the sweep's `sums` is exactly what
/// the artificial terms add to the energy sums: `Σ m_i de_i/dt` less the
/// same sums with the viscosity, the artificial stress and the hourglass
/// control off, at the same state (the stress's own work does not depend
/// on them), to round-off.
fn dissipation_is_the_artificial_terms_work(
    model: &Model,
    st: &State,
    nb: &Neighbours,
    with: &SumsOut,
) {
    let k = kinematics(model, st, nb);
    let pts = eos_and_stress(model, st);
    let mut off = model.clone();
    (off.alpha, off.beta, off.artificial_stress) = (0.0, 0.0, None);
    off.set_hourglass(0.0);
    let bare = sums((&off, st, nb, &k, &pts[..]), lanes_serve(model), None);
    assert_eq!(bare.2, 0.0, "no artificial term, no dissipation");
    let total = |de: &[f64]| -> f64 { (0..model.len()).map(|i| model.mass[i] * de[i]).sum() };
    let power: f64 = (0..model.len())
        .map(|i| model.mass[i] * with.1[i].abs())
        .sum();
    let moved = total(&with.1) - total(&bare.1);
    assert!(
        (moved - with.2).abs() <= 1e-11 * power,
        "dissipation {:e} against the energy sums' change {moved:e}",
        with.2
    );
    assert!(with.2.abs() > 1e-6 * power, "the state dissipates");
}

/// The artificial stress of a case; those with `n = 3.5` may only heat,
/// those with `n = 3` only where they flow.
fn as_of((epsilon, n, pairs): (f64, f64, ArtPairs)) -> crate::scene::ArtificialStress {
    use crate::scene::ArtWork;
    crate::scene::ArtificialStress {
        epsilon,
        n,
        pairs,
        work: match n {
            3.5 => ArtWork::Heat,
            3.0 => ArtWork::Plastic,
            _ => ArtWork::Either,
        },
        ..crate::scene::ArtificialStress::DEFAULT
    }
}

/// Every body given a yield stress at the median von Mises stress of
/// `st`, so that about half the particles flow ([`Model::flowing`]).
fn yield_at_median(model: &mut Model, st: &State) {
    let mut vm: Vec<f64> = st.s.iter().map(|s| s.von_mises()).collect();
    vm.sort_by(f64::total_cmp);
    for b in &mut model.bodies {
        b.material.y0 = vm[vm.len() / 2];
    }
    model.plastic = true;
}

/// Particle i's two stirring fractions.
fn stir(i: usize) -> (f64, f64) {
    (
        (i as f64 * 0.618_033_988_7).fract(),
        (i as f64 * 0.414_213_562_3).fract(),
    )
}

/// The paper's disks in contact (3,000 particles) with velocities,
/// densities and deviators stirred so that pairs approach and recede and
/// the principal stresses take every sign pattern.
fn stirred_disks() -> (Model, State) {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (model, mut st) = (bench.model().clone(), bench.state().clone());
    let rho0 = st.rho[0];
    for i in 0..st.x.len() {
        let (a, b) = stir(i);
        st.v[i] += DVec2::new(
            (a * std::f64::consts::TAU).cos(),
            (a * std::f64::consts::TAU).sin(),
        ) * 0.3;
        st.rho[i] *= 1.0 + 2e-3 * (b - 0.5);
        st.s[i] = Sym {
            xx: 2e-3 * rho0 * (a - 0.5),
            yy: -1e-3 * rho0 * (b - 0.5),
            xy: 1.5e-3 * rho0 * (a + b - 1.0),
            zz: 1e-3 * rho0 * (b - a),
        };
    }
    (model, st)
}
