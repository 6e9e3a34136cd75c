//! The lanes' sums: in 1-D, on any thread count, and the kept pair
//! vectors they replay the energy sums with.

use super::*;

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
        let nb = find_with_skin(&model, st.frame(), skin);
        let k = kinematics(&model, &st, &nb);
        let pts = eos_and_stress(&model, &st);
        let a = (&model, &st, &nb, &k, &pts[..]);
        let one = sums(a, false, None);
        let four = sums(a, true, None);
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
    let nb = find_with_skin(&model, st.frame(), skin);
    let k = kinematics(&model, &st, &nb);
    let pts = eos_and_stress(&model, &st);
    let args = (&model, &st, &nb, &k, &pts[..]);
    let (dv, de) = momentum_energy(args.0, args.1, args.2, args.3, args.4);
    let mut kept = [Vec::new(), Vec::new()];
    for (lanes, kept) in [true, false].into_iter().zip(&mut kept) {
        kept.resize(nb.store_len(), [DVec2::ZERO; 2]);
        let (kdv, _, fixed, c) = sums(args, lanes, Some(kept));
        // The kept artificial work at the pass's own velocities is its
        // dissipation.
        let at = fixed - (0..model.len()).map(|i| c[i].dot(st.v[i])).sum::<f64>();
        let (.., d, _) = sums(args, lanes, None);
        let power: f64 = (0..model.len()).map(|i| model.mass[i] * de[i].abs()).sum();
        assert!(
            (at - d).abs() <= 1e-12 * power && d.abs() > 1e-6 * power,
            "kept dissipation {at:e} against {d:e}"
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
    let nb = find_with_skin(model, st.frame(), skin);
    let k = kinematics(model, st, &nb);
    let pts = eos_and_stress(model, st);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| sums((model, st, &nb, &k, &pts), true, None))
    };
    let (one, three) = (on(1), on(3));
    for i in 0..model.len() {
        assert_eq!(one.0[i].x.to_bits(), three.0[i].x.to_bits(), "dv.x of {i}");
        assert_eq!(one.0[i].y.to_bits(), three.0[i].y.to_bits(), "dv.y of {i}");
        assert_eq!(one.1[i].to_bits(), three.1[i].to_bits(), "de of {i}");
    }
}
