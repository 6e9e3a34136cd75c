//! Tests of the forces stage (`forces.rs`).

use super::forces::*;
use crate::bench::{CpuBench, DiskCase};
use crate::cpu::{eos_and_stress, kinematics, neighbours, SKIN_FRACTION};
use crate::math::Sym;
use crate::model::{Model, State};
use crate::physics::kernel;
use crate::physics::tension::{art_weight, artificial_stress, close_gate, CLOSE_FULL};
use crate::scene::ArtPairs;
use glam::DVec2;

/// The lane code gives the one-pair code's sums bit for bit, on the
/// disks in contact with a velocity field stirred so that every branch
/// is taken both ways in many pairs (receding and approaching pairs,
/// the limiter on and off): with the reconstructed viscosity and
/// without, on candidate lists with a skin (candidates beyond the
/// support in the rows), and in kernel mode (SPH sums across the
/// bodies) with the second disk's `h` changed, so that pairs across
/// the contact take `h_ij` of two different lengths.
#[test]
fn lanes_match_one_pair_code_bit_for_bit() {
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
    let tensile = |m: &Model, st: &State| {
        let pts = eos_and_stress(m, st);
        pts.iter().filter(|p| p.r != Sym::default()).count()
    };
    // Every seventh particle failed: it takes no part in the artificial
    // stress, and no tension.
    let mut failed = st.clone();
    failed.damage = (0..st.x.len())
        .map(|i| if i % 7 == 3 { 1.0 } else { 0.4 })
        .collect();
    for (reconstruct, h_ratio, art, damaged) in [
        (true, 1.0, None, false),
        (false, 1.0, None, false),
        (true, 1.15, None, false),
        (true, 1.0, Some((0.3, 4.0, ArtPairs::All)), false),
        (false, 1.15, Some((0.2, 3.5, ArtPairs::All)), false),
        (true, 1.0, Some((0.3, 4.0, ArtPairs::Close)), false),
        (false, 1.15, Some((0.2, 3.5, ArtPairs::Close)), false),
        (true, 1.0, Some((0.3, 4.0, ArtPairs::All)), true),
        (false, 1.0, Some((0.3, 4.0, ArtPairs::Close)), true),
    ] {
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
        model.av_reconstruct = reconstruct;
        model.contact = h_ratio == 1.0;
        for i in 0..model.len() {
            if model.body[i] == 1 {
                model.h[i] *= h_ratio;
            }
        }
        let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
        let nb = neighbours::find_with_skin(&model, &st.x, skin);
        let k = kinematics::kinematics(&model, st, &nb);
        let pts = eos_and_stress(&model, st);
        let args = (&model, &st, &nb, &k.l, &k.gv, &k.surface, &pts);
        let one = sums(
            args.0, args.1, args.2, args.3, args.4, args.5, args.6, false, None,
        );
        let four = sums(
            args.0, args.1, args.2, args.3, args.4, args.5, args.6, true, None,
        );
        let bits = |v: &DVec2| (v.x.to_bits(), v.y.to_bits());
        for i in 0..model.len() {
            assert_eq!(bits(&one.0[i]), bits(&four.0[i]), "dv of {i}");
            assert_eq!(one.1[i].to_bits(), four.1[i].to_bits(), "de of {i}");
        }
        // The sums are not trivially equal: the pass does work.
        assert!(one.0.iter().filter(|a| a.length() > 0.0).count() > model.len() / 2);
    }
}

/// The lane code gives the one-pair code's sums bit for bit in 1-D too
/// (rows of two to five candidates, so most chunks are partial), with
/// the artificial stress on a stirred state in tension and compression.
#[test]
fn lanes_match_one_pair_code_in_1d() {
    let scene = crate::scene::Scene::from_toml_str(
        r#"
        [simulation]
        dimension = 1
        end_time = 1.0e-6
        interaction = "penalty"
        [materials.steel]
        density = 7850.0
        shear_modulus = 77.0e9
        eos = { kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }
        [[bodies]]
        name = "flyer"
        material = "steel"
        spacing = 1.0e-5
        velocity = [200.0]
        shape = { kind = "segment", from = -0.001, to = 0.0 }
        [[bodies]]
        name = "target"
        material = "steel"
        spacing = 1.0e-5
        velocity = [0.0]
        shape = { kind = "segment", from = 0.0, to = 0.002 }
        "#,
        "the 1-D test scene",
    )
    .expect("a valid scene");
    let (mut model, mut st) = Model::new(&scene);
    for i in 0..st.rho.len() {
        let a = (i as f64 * 0.414_213_562_3).fract() - 0.5;
        st.rho[i] *= 1.0 + 2e-3 * a;
        st.v[i].x += 30.0 * ((i as f64 * 0.618_033_988_7).fract() - 0.5);
        st.s[i].xx = 1e8 * ((i as f64 * 0.732_050_807_6).fract() - 0.5);
        st.s[i].yy = -0.5 * st.s[i].xx;
        st.s[i].zz = -0.5 * st.s[i].xx;
    }
    let mut seen = Vec::new();
    for art in [
        None,
        Some((0.3, 4.0, ArtPairs::All)),
        Some((0.2, 3.5, ArtPairs::All)),
        Some((0.3, 4.0, ArtPairs::Close)),
    ] {
        model.artificial_stress = art.map(as_of);
        let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
        let nb = neighbours::find_with_skin(&model, &st.x, skin);
        let k = kinematics::kinematics(&model, &st, &nb);
        let pts = eos_and_stress(&model, &st);
        let a = (&model, &st, &nb, &k.l, &k.gv, &k.surface, &pts);
        let one = sums(a.0, a.1, a.2, a.3, a.4, a.5, a.6, false, None);
        let four = sums(a.0, a.1, a.2, a.3, a.4, a.5, a.6, true, None);
        for i in 0..model.len() {
            assert_eq!(
                one.0[i].x.to_bits(),
                four.0[i].x.to_bits(),
                "dv of {i}, {art:?}"
            );
            assert_eq!(
                one.1[i].to_bits(),
                four.1[i].to_bits(),
                "de of {i}, {art:?}"
            );
        }
        seen.push(one.0);
    }
    // Each form does work of its own: the close-pair form acts (the
    // stirred densities open its gate on some pairs) and differs from
    // the classic one.
    let differ = |a: &[DVec2], b: &[DVec2]| a.iter().zip(b).filter(|(p, q)| p != q).count();
    assert!(differ(&seen[0], &seen[1]) > model.len() / 2);
    let close = differ(&seen[0], &seen[3]);
    assert!(
        close > 10 && close < differ(&seen[0], &seen[1]),
        "{close} changed"
    );
}

fn as_of((epsilon, n, pairs): (f64, f64, ArtPairs)) -> crate::scene::ArtificialStress {
    crate::scene::ArtificialStress { epsilon, n, pairs }
}

/// The close-pair gate: shut at and beyond the local spacing `V̄^(1/d)`,
/// open fully from `CLOSE_FULL` of it in, linear in `(r/s)²` between,
/// in 1-D (`s = V̄`) and 2-D (`s = √V̄`).
#[test]
fn close_gate_opens_inside_the_local_spacing() {
    for (dim, vol, s) in [(1, 2.0e-5, 2.0e-5), (2, 4.0e-10, 2.0e-5)] {
        let g = |r: f64| close_gate(r * r, vol, 1.0, dim);
        assert_eq!(g(s), 0.0);
        assert_eq!(g(1.5 * s), 0.0);
        assert_eq!(g(CLOSE_FULL * s * (1.0 - 1e-12)), 1.0);
        assert_eq!(g(0.5 * s), 1.0);
        let r = 0.975 * s;
        let want = (1.0 - 0.975f64.powi(2)) / (1.0 - CLOSE_FULL * CLOSE_FULL);
        assert!((g(r) - want).abs() < 1e-12, "{} against {want}", g(r));
        assert!(g(0.99 * s) > 0.0 && g(0.99 * s) < g(0.98 * s));
        // κ² scales the spacing: shut beyond κ s.
        assert_eq!(close_gate((0.91 * s).powi(2), vol, 0.81, dim), 0.0);
        assert_eq!(close_gate((0.85 * s).powi(2), vol, 0.81, dim), 1.0);
    }
}

/// The artificial stress without the principal angle is the angle
/// form's (rotate to principal axes, keep `−ε σ̄/ρ²` of the tensile
/// values, rotate back) on stresses with no, one and two tensile
/// principal values, and where the two principal values meet.
#[test]
fn artificial_stress_is_the_principal_axes_form() {
    let angle_form = |eps: f64, s: &Sym, rho: f64| {
        let (a, b, th) = s.principal();
        let k = |v: f64| if v > 0.0 { -eps * v / (rho * rho) } else { 0.0 };
        Sym::from_principal(k(a), k(b), th)
    };
    let mut seen = [0usize; 3];
    for i in 0..400 {
        let u = |m: f64| ((i as f64 * m).fract() - 0.5) * 2.0e9;
        let mut s = Sym {
            xx: u(0.618_033_988_7),
            yy: u(0.414_213_562_3),
            xy: u(0.732_050_807_6) * 0.5,
            zz: u(0.236_067_977_5),
        };
        if i % 50 == 0 {
            (s.yy, s.xy) = (s.xx, 0.0);
        }
        let (a, b, _) = s.principal();
        seen[(a > 0.0) as usize + (b > 0.0) as usize] += 1;
        let (got, want) = (
            artificial_stress(0.3, &s, 7850.0),
            angle_form(0.3, &s, 7850.0),
        );
        let scale = 0.3 * 2.0e9 / (7850.0f64 * 7850.0);
        for (g, w) in [(got.xx, want.xx), (got.yy, want.yy), (got.xy, want.xy)] {
            assert!(
                (g - w).abs() <= 1e-12 * scale,
                "{s:?}: {got:?} against {want:?}"
            );
        }
        assert_eq!(got.zz, 0.0);
    }
    assert!(seen.iter().all(|&n| n > 50), "sign patterns {seen:?}");
}

/// The pair weight is `(W(r)/W(Δp))^n` from the kernel itself, inside
/// and outside `q = 1`, with `n = 4` by squarings and other `n` by
/// powers.
#[test]
fn art_weight_is_the_kernel_ratio() {
    let (dp, h) = (1.0e-5, 1.2e-5);
    for r in [0.0, 0.3e-5, 1.0e-5, 1.3e-5, 2.2e-5, 2.39e-5] {
        for n in [4.0, 3.5, 1.0] {
            let want = (kernel::w(2, r, h) / kernel::w(2, dp, h)).powf(n);
            let got = art_weight(r * r, dp, h, n);
            assert!((got - want).abs() <= 1e-13 * want.max(1.0), "r {r} n {n}");
        }
    }
    assert!((art_weight(dp * dp, dp, h, 4.0) - 1.0).abs() < 1e-14);
}

/// The leapfrog's momentum pass gives `momentum_energy`'s `dv/dt` bit
/// for bit, keeps the same pair vectors in the lane code and in the
/// one-pair code, and the energy replayed from them at the pass's own
/// velocities is its `de/dt` up to round-off (the same terms, grouped
/// `w·(S_i G − ½ΠG)` instead of `w·S_i G − ½Π w·G`). With velocities
/// that differ, the replay differs: it does book the work on them.
#[test]
fn kept_pair_vectors_replay_the_energy_sums() {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (model, mut st) = (bench.model().clone(), bench.state().clone());
    for (i, v) in st.v.iter_mut().enumerate() {
        let a = (i as f64 * 0.618_033_988_7).fract() * std::f64::consts::TAU;
        *v += DVec2::new(a.cos(), a.sin()) * 0.3;
    }
    let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
    let nb = neighbours::find_with_skin(&model, &st.x, skin);
    let k = kinematics::kinematics(&model, &st, &nb);
    let pts = eos_and_stress(&model, &st);
    let args = (&model, &st, &nb, &k.l, &k.gv, &k.surface, &pts);
    let (dv, de) = momentum_energy(args.0, args.1, args.2, args.3, args.4, args.5, args.6);
    let mut kept = [Vec::new(), Vec::new()];
    for (lanes, kept) in [true, false].into_iter().zip(&mut kept) {
        kept.resize(nb.store_len(), [DVec2::ZERO; 2]);
        let (kdv, _) = sums(
            args.0,
            args.1,
            args.2,
            args.3,
            args.4,
            args.5,
            args.6,
            lanes,
            Some(kept),
        );
        for i in 0..model.len() {
            assert_eq!(kdv[i].x.to_bits(), dv[i].x.to_bits(), "dv.x of {i}");
            assert_eq!(kdv[i].y.to_bits(), dv[i].y.to_bits(), "dv.y of {i}");
        }
    }
    let bits = |x: &PairVectors| x.map(|v| [v.x.to_bits(), v.y.to_bits()]);
    assert!(kept[0].iter().map(bits).eq(kept[1].iter().map(bits)));
    let pairs = kept[0].iter().filter(|x| x[0] != DVec2::ZERO).count();
    assert!(pairs > 5 * model.len(), "{pairs} kept pairs");

    let scale = de.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let replay = energy_replay(&model, &nb, &kept[0], &st.v);
    for i in 0..model.len() {
        assert!(
            (replay[i] - de[i]).abs() <= 1e-12 * scale,
            "de of {i}: {} against {}",
            replay[i],
            de[i]
        );
    }
    // At other velocities the replay moves with them.
    let w: Vec<DVec2> = st.v.iter().map(|v| *v * 1.5 + DVec2::X).collect();
    let other = energy_replay(&model, &nb, &kept[0], &w);
    let moved = (0..model.len()).filter(|&i| (other[i] - de[i]).abs() > 1e-6 * scale);
    assert!(moved.count() > model.len() / 2);
    // Energy is conserved pair by pair: Σ m_i de_i = Σ_pairs m_i m_j
    // w_ij·t G_ij = −Σ m_i w_i·dv_i (the work of the forces on w).
    let heat: f64 = (0..model.len()).map(|i| model.mass[i] * other[i]).sum();
    let work: f64 = (0..model.len())
        .map(|i| model.mass[i] * w[i].dot(dv[i]))
        .sum();
    let size: f64 = (0..model.len())
        .map(|i| model.mass[i] * (w[i].dot(dv[i])).abs())
        .sum();
    assert!(
        (heat + work).abs() <= 1e-10 * size,
        "internal {heat:e} against work {work:e}"
    );
}

/// The lane code's sums do not depend on the thread count: the chunks
/// of the sweep fix every sum's order (one thread against three).
#[test]
fn lanes_are_the_same_on_any_thread_count() {
    let bench = CpuBench::new(&DiskCase::new(3_000).expect("the case")).expect("in contact");
    let (model, st) = (bench.model(), bench.state());
    let skin = SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max);
    let nb = neighbours::find_with_skin(model, &st.x, skin);
    let k = kinematics::kinematics(model, st, &nb);
    let pts = eos_and_stress(model, st);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| sums(model, st, &nb, &k.l, &k.gv, &k.surface, &pts, true, None))
    };
    let (one, three) = (on(1), on(3));
    for i in 0..model.len() {
        assert_eq!(one.0[i].x.to_bits(), three.0[i].x.to_bits(), "dv.x of {i}");
        assert_eq!(one.0[i].y.to_bits(), three.0[i].y.to_bits(), "dv.y of {i}");
        assert_eq!(one.1[i].to_bits(), three.1[i].to_bits(), "de of {i}");
    }
}
