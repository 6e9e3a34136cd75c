//! Checkpoints: round trips, size checks, damaged files.

use super::*;
use crate::model::ContactStats;

fn scenes() -> Vec<Scene> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    [
        "scenes/paper",
        "scenes/large",
        "scenes/hard",
        "scenes/penetration",
        "scenes/shapes",
        "scenes/axisymmetric",
    ]
    .iter()
    .flat_map(|d| std::fs::read_dir(root.join(d)).expect("scene folder"))
    .map(|e| e.expect("entry").path())
    .filter(|p| p.extension().is_some_and(|x| x == "toml"))
    .map(|p| Scene::from_file(&p).expect("a valid scene"))
    .collect()
}

/// The scene travels as TOML text: every shipped scene comes back equal.
#[test]
fn scenes_survive_their_toml_round_trip() {
    for s in scenes() {
        let text = toml::to_string(&s).expect("serialises");
        let back = Scene::from_toml_str(&text, "round trip").expect("parses");
        assert_eq!(back, s, "{text}");
    }
}

fn small() -> Checkpoint {
    let scene = Scene::from_toml_str(
        r#"
        [simulation]
        dimension = 1
        end_time = 1.0e-7
        [materials.steel]
        density = 7850.0
        eos = { kind = "linear", c0 = 4580.0 }
        [[bodies]]
        name = "a"
        material = "steel"
        spacing = 1.0e-3
        velocity = [1.0]
        shape = { kind = "segment", from = 0.0, to = 0.002 }
        [[probes]]
        name = "ke"
        kind = "energy"
        quantity = "kinetic"
        "#,
        "small",
    )
    .expect("valid");
    let (_, state) = crate::model::Model::new(&scene);
    Checkpoint {
        scene_label: "small.toml".into(),
        scene,
        backend: Backend::Cpu,
        adapter: None,
        ledger: Ledger {
            base_energy: 1.5,
            momentum: DVec2::new(2.0, -0.0),
            stored0: 0.0,
            max_fallback: 3,
            wall_seconds: 0.25,
            warnings: vec!["w".into()],
        },
        recorder: RecorderState {
            times: vec![0.0, 1e-8],
            rows: vec![vec![1.0], vec![f64::MIN_POSITIVE]],
            prev: Some((1.2e-8, vec![0.1 + 0.2])),
            snapshots: vec![(0.0, "snapshots/snapshot_000000.vtu".into())],
            checkpoint_every: 1e-8,
            next_checkpoint: 2e-8,
        },
        solver: SolverState::Cpu(Box::new(CpuState {
            lists: Neighbours {
                start: vec![0, 1, 2],
                list: vec![1, 0],
                cross_start: vec![0, 0, 0],
                cross: vec![],
                skin: 1e-4,
                x_ref: state.x.clone(),
                ..Default::default()
            },
            carried: Some((
                Rates {
                    dv: vec![DVec2::new(1.0, -2.0); state.x.len()],
                    de: vec![0.5; state.x.len()],
                    heat_rate: 0.25,
                    spring_rate: -0.125,
                    friction_rate: 0.0625,
                    friction: vec![(
                        1,
                        crate::cpu::contact::Friction {
                            stiffness: 2.0,
                            cap: 1e-6,
                            rate: -0.5,
                            sliding: true,
                        },
                    )],
                    ..Default::default()
                },
                Diagnostics {
                    cfl_dt: 1e-9,
                    contact: ContactStats {
                        pairs: vec![(0, 1, 2.5, 3.5)],
                        stored: 4.0,
                        heat_rate: 0.25,
                        spring_rate: -0.125,
                        friction_rate: 0.0625,
                        tangential: vec![(0, 1, [0.5, 0.25, 2.0])],
                    },
                    correction_fallback: 1,
                    boundary_count: 2,
                    held_force: vec![DVec2::new(0.5, -1.5)],
                },
            )),
            state,
            initial_dt: Some(3e-9),
            energy_limit: Some(f64::INFINITY),
        })),
    }
}

/// Every field comes back bit for bit.
#[test]
fn round_trip_is_exact() {
    let c = small();
    let bytes = c.to_bytes().expect("encodes");
    let back = Checkpoint::from_bytes(&bytes, "t").expect("decodes");
    assert_eq!(back.to_bytes().expect("encodes"), bytes);
    assert_eq!(back.recorder, c.recorder);
    assert_eq!(back.ledger, c.ledger);
    assert_eq!(back.scene, c.scene);
}

/// A state of another particle count than the scene's model is refused
/// before anything is restored; the scene's own is accepted.
#[test]
fn sizes_are_checked_against_the_model() {
    let c = small();
    let (model, _) = crate::model::Model::new(&c.scene);
    c.check_sizes(&model, "ck").expect("its own scene");
    let mut other = c.scene.clone();
    other.bodies[0].spacing = 5.0e-4;
    let (model, _) = crate::model::Model::new(&other);
    let e = c.check_sizes(&model, "ck").expect_err("4 particles, not 2");
    assert!(e.to_string().contains("do not match the scene's 4"), "{e}");
}

/// A flipped bit, a truncation or a foreign file is refused with a
/// message naming the file; no decode panics or allocates from a
/// damaged count.
#[test]
fn damage_is_refused() {
    let bytes = small().to_bytes().expect("encodes");
    for k in (0..bytes.len()).step_by(7) {
        let mut b = bytes.clone();
        b[k] ^= 0x10;
        let e = Checkpoint::from_bytes(&b, "ck.bin").expect_err("damaged");
        assert!(e.to_string().starts_with("ck.bin: "), "{e}");
    }
    for len in [0, 5, 20, bytes.len() / 2, bytes.len() - 1] {
        let e = Checkpoint::from_bytes(&bytes[..len], "ck.bin").expect_err("short");
        assert!(e.to_string().starts_with("ck.bin: "), "{e}");
    }
    let e = Checkpoint::from_bytes(b"time,a\n0,1\n.......", "h.csv").expect_err("foreign");
    assert!(e.to_string().contains("not a sphcontact checkpoint"), "{e}");
}

/// The records' bytes are the file format's, worked out by hand: a list
/// is its length as a u64 then its items, a u32 is four bytes, an option
/// is 0 or 1 then its value, a text its length then UTF-8; and each comes
/// back as written.
#[test]
fn records_are_the_documented_bytes() {
    use codec::Record;
    let put = |f: &dyn Fn(&mut Writer)| {
        let mut w = Writer(Vec::new());
        f(&mut w);
        w.0
    };
    let le = |v: u64| v.to_le_bytes().to_vec();
    assert_eq!(
        put(&|w| vec![7u32, 9].put(w)),
        [le(2), vec![7, 0, 0, 0, 9, 0, 0, 0]].concat()
    );
    assert_eq!(
        put(&|w| Some((0.5f64, "ab".to_string())).put(w)),
        [le(1), le(0.5f64.to_bits()), le(2), b"ab".to_vec()].concat()
    );
    assert_eq!(put(&|w| None::<f64>.put(w)), le(0));
    let rec = RecorderState {
        times: vec![1.0, 2.0],
        rows: vec![vec![3.0], vec![4.0]],
        prev: Some((2.0, vec![4.0])),
        snapshots: vec![(1.5, "snap_000001.vtu".into())],
        checkpoint_every: 1e-6,
        next_checkpoint: 3e-6,
    };
    let bytes = put(&|w| rec.put(w));
    let f = |v: f64| le(v.to_bits());
    let want = [
        le(2),
        f(1.0),
        f(2.0),
        le(2),
        le(1),
        f(3.0),
        le(1),
        f(4.0),
        le(1),
        f(2.0),
        le(1),
        f(4.0),
        le(1),
        f(1.5),
        le(15),
        b"snap_000001.vtu".to_vec(),
        f(1e-6),
        f(3e-6),
    ]
    .concat();
    assert_eq!(bytes, want);
    let mut r = Reader { b: &bytes, at: 0 };
    assert_eq!(RecorderState::get(&mut r), Ok(rec));
    assert_eq!(r.at, bytes.len());
    // A count larger than what is left is refused before allocating.
    let mut r = Reader {
        b: &[255, 255, 255, 255, 0, 0, 0, 0],
        at: 0,
    };
    assert!(Vec::<f64>::get(&mut r).is_err());
}
