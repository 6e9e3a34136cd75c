//! Snapshots (docs/scenes.md, "Snapshots"): the `.vtu` files are read back with a
//! small reader of the VTK XML appended-raw layout and checked against the
//! run's own state, the `.pvd` collection against the snapshot times.

mod common;
use common::vtu::{attr, read_vtu, Vtu};
use common::*;

use std::path::Path;

use sphcontact::run::{run_scene, RunOptions};
use sphcontact::scene::Backend;
use sphcontact::{RunError, Scene};

/// Two steel disks (R/Δx = 10) touching at the origin, closing at 10 m/s,
/// with a particle probe whose position the snapshots must repeat.
fn disks(end: f64, snapshot_interval: f64, interaction: &str) -> Scene {
    parse(&format!(
        r#"
        [simulation]
        dimension = 2
        end_time = {end:e}
        interaction = "{interaction}"
        [materials.steel]
        density = 7850.0
        shear_modulus = 77.0e9
        eos = {{ kind = "mie_gruneisen", c0 = 4580.0, s = 1.49, gamma0 = 2.02 }}
        [[bodies]]
        name = "left"
        material = "steel"
        spacing = 5.0e-4
        velocity = [5.0, 0.0]
        shape = {{ kind = "disk", center = [-0.005, 0.0], radius = 0.005 }}
        [[bodies]]
        name = "right"
        material = "steel"
        spacing = 5.0e-4
        velocity = [-5.0, 0.0]
        shape = {{ kind = "disk", center = [0.005, 0.0], radius = 0.005 }}
        [[probes]]
        name = "x_edge"
        kind = "particle"
        body = "left"
        at = [-0.0098, 0.001]
        quantity = "position_x"
        [output]
        history_interval = 1.0e-7
        snapshot_interval = {snapshot_interval:e}
        "#
    ))
}

/// `(timestep, file)` of every entry of the collection.
fn read_pvd(out: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(out.join("snapshots.pvd")).expect("snapshots.pvd");
    assert!(text.contains("type=\"Collection\""));
    text.split("<DataSet")
        .skip(1)
        .map(|d| {
            (
                attr(d, "timestep").unwrap().parse().unwrap(),
                attr(d, "file").unwrap().to_string(),
            )
        })
        .collect()
}

fn vtu_files(out: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(out.join("snapshots"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Boundary flags and normals of a snapshot: some boundary particles, unit
/// (to `unit_tol`) outward normals on them (pointing away from their disk's centre), zero
/// normals elsewhere.
fn check_boundary(v: &Vtu, centres: [[f64; 2]; 2], unit_tol: f64) -> usize {
    let x = v.xy("Points");
    let n = v.xy("normal");
    let body = v.ints("body");
    let boundary = v.ints("boundary");
    let mut count = 0;
    for i in 0..v.points {
        let len = n[i][0].hypot(n[i][1]);
        if boundary[i] == 1 {
            count += 1;
            assert!((len - 1.0).abs() < unit_tol, "particle {i}: |n| = {len}");
            let c = centres[body[i] as usize];
            let out = n[i][0] * (x[i][0] - c[0]) + n[i][1] * (x[i][1] - c[1]);
            assert!(out > 0.0, "particle {i}: the normal points inward");
        } else {
            assert_eq!(boundary[i], 0);
            assert_eq!(len, 0.0, "particle {i}: a normal off the boundary");
        }
    }
    assert!(count > 0, "no boundary particle");
    count
}

/// Mass-weighted centre of each body (the disks have equal masses per
/// particle, so the plain mean).
fn centres(v: &Vtu) -> [[f64; 2]; 2] {
    let x = v.xy("Points");
    let body = v.ints("body");
    let mut c = [[0.0; 2]; 2];
    let mut k = [0.0; 2];
    for i in 0..v.points {
        let b = body[i] as usize;
        c[b][0] += x[i][0];
        c[b][1] += x[i][1];
        k[b] += 1.0;
    }
    [0, 1].map(|b| [c[b][0] / k[b], c[b][1] / k[b]])
}

#[test]
fn cpu_snapshots_hold_the_state_at_their_times() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    // 0.5 µs does not divide 2.2 µs: the end gets a snapshot of its own.
    let scene = disks(2.2e-6, 5.0e-7, "penalty");
    let out = run_on(&scene, Backend::Cpu, Some(&out_dir));
    let expected = [0.0, 5e-7, 1e-6, 1.5e-6, 2e-6, 2.2e-6];

    let pvd = read_pvd(&out_dir);
    assert_eq!(pvd.len(), expected.len(), "{pvd:?}");
    for ((t, file), want) in pvd.iter().zip(expected) {
        assert!((t - want).abs() <= 1e-12 * want, "{t} vs {want}");
        assert!(file.starts_with("snapshots/") && file.ends_with(".vtu"));
        assert!(out_dir.join(file).is_file(), "{file} listed but missing");
    }
    assert!(pvd.windows(2).all(|w| w[1].0 > w[0].0));
    assert_eq!(vtu_files(&out_dir).len(), expected.len());
    assert_eq!(out.summary.snapshots, expected.len());
    assert!(out.summary.snapshot_bytes > 0);

    let model = &out.model;
    let n = model.len();
    let probe_x = column(&out, "x_edge");
    let probe_i = {
        let v0 = read_vtu(&out_dir.join(&pvd[0].1));
        let x = v0.xy("Points");
        (0..n)
            .min_by(|&a, &b| {
                let d = |p: [f64; 2]| (p[0] + 0.0098).hypot(p[1] - 0.001);
                d(x[a]).total_cmp(&d(x[b]))
            })
            .unwrap()
    };
    for (k, (t, file)) in pvd.iter().enumerate() {
        let v = read_vtu(&out_dir.join(file));
        assert_eq!(v.points, n);
        assert_eq!(v.time, *t);
        assert_eq!(v.field_ints["body:left"], 0);
        assert_eq!(v.field_ints["body:right"], 1);
        let body: Vec<i64> = model.body.iter().map(|&b| b as i64).collect();
        assert_eq!(v.ints("body"), body);
        assert_eq!(v.ints("connectivity"), (0..n as i64).collect::<Vec<_>>());
        assert_eq!(v.ints("offsets"), (1..=n as i64).collect::<Vec<_>>());
        assert!(v.ints("types").iter().all(|&c| c == 1), "VTK_VERTEX cells");
        let b = check_boundary(&v, centres(&v), 1e-12);
        println!("snapshot {k} at t = {t:e}: {b} boundary particles of {n}");
        // The state is the one at the snapshot's time: the history row
        // there (taken from the same state) repeats its position.
        let row = out
            .history
            .times
            .iter()
            .position(|h| (h - t).abs() <= 1e-12 * t.max(1e-300))
            .expect("a history row at each snapshot time");
        let x = v.xy("Points")[probe_i][0];
        assert!(
            (x - probe_x[row]).abs() <= 1e-15,
            "t = {t}: snapshot x {x} vs history {}",
            probe_x[row]
        );
    }

    // The size `check` announces: the arrays, plus a header of a few kB.
    let bytes = std::fs::metadata(out_dir.join(&pvd[0].1)).unwrap().len();
    let arrays = sphcontact::output::vtk::BYTES_PER_PARTICLE * n as u64;
    assert!(
        bytes >= arrays && bytes < arrays + 8192,
        "{bytes} bytes for {n} particles"
    );

    // The last snapshot is the final state, bit for bit.
    let last = read_vtu(&out_dir.join(&pvd.last().unwrap().1));
    let st = &out.state;
    let x = last.xy("Points");
    let vel = last.xy("velocity");
    let rho = last.f64s("density", 1);
    let e = last.f64s("internal_energy", 1);
    let p = last.f64s("pressure", 1);
    let sxx = last.f64s("stress_xx", 1);
    let vm = last.f64s("von_mises", 1);
    for i in 0..n {
        assert_eq!(x[i], [st.x[i].x, st.x[i].y]);
        assert_eq!(vel[i], [st.v[i].x, st.v[i].y]);
        assert_eq!(rho[i], st.rho[i]);
        assert_eq!(e[i], st.e[i]);
        let pi = model.material(i).pressure(st.rho[i], st.e[i]);
        assert_eq!(p[i], pi);
        assert_eq!(sxx[i], st.s[i].xx - pi);
        assert_eq!(vm[i], st.s[i].von_mises());
    }
    assert!(vm.iter().any(|&s| s > 0.0), "the impact stresses the disks");
    // The final state has the very boundary set the CPU solver computes.
    let (_, boundary) = sphcontact::cpu::surface(model, st);
    let flags: Vec<i64> = boundary.iter().map(|&b| b as i64).collect();
    assert_eq!(last.ints("boundary"), flags);
}

#[test]
fn no_interval_no_snapshots_and_a_rerun_replaces_them() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    run_on(
        &disks(1.0e-6, 2.5e-7, "penalty"),
        Backend::Cpu,
        Some(&out_dir),
    );
    assert_eq!(vtu_files(&out_dir).len(), 5);
    // Fewer snapshots into the same folder: no file of the first run is left.
    let out = run_on(
        &disks(1.0e-6, 5.0e-7, "penalty"),
        Backend::Cpu,
        Some(&out_dir),
    );
    assert_eq!(out.summary.snapshots, 3);
    assert_eq!(vtu_files(&out_dir).len(), 3);
    assert_eq!(read_pvd(&out_dir).len(), 3);

    let mut scene = disks(2.0e-7, 1.0e-7, "penalty");
    scene.output.snapshot_interval = None;
    let other = dir.path().join("none");
    let out = run_on(&scene, Backend::Cpu, Some(&other));
    assert_eq!(out.summary.snapshots, 0);
    assert!(!other.join("snapshots").exists() && !other.join("snapshots.pvd").exists());
}

/// `--snapshot-every` (`RunOptions::snapshot_every`) overrides the
/// scene's interval: 0 writes none and runs the steps of the scene without
/// an interval, to the byte; another value writes its own count. A
/// negative or non-finite one, or one with `--resume`, is refused (exit 2).
#[test]
fn snapshot_every_overrides_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = disks(1.0e-6, 2.5e-7, "penalty");
    scene.output.snapshot_png = true;
    let opts = |out: &Path, every: Option<f64>| RunOptions {
        out_dir: Some(out.to_path_buf()),
        backend: Some(Backend::Cpu),
        silent: true,
        write: true,
        snapshot_every: every,
        ..Default::default()
    };
    let none = dir.path().join("none");
    let out = run_scene(&scene, None, &opts(&none, Some(0.0))).expect("runs");
    assert_eq!(out.summary.snapshots, 0);
    assert!(!none.join("snapshots").exists() && !none.join("snapshots.pvd").exists());
    let mut plain = scene.clone();
    (plain.output.snapshot_interval, plain.output.snapshot_png) = (None, false);
    let without = dir.path().join("without");
    run_scene(&plain, None, &opts(&without, None)).expect("runs");
    let history = |d: &Path| std::fs::read(d.join("history.csv")).expect("a history");
    assert_eq!(history(&none), history(&without));
    // The scene's interval moves the steps: the histories differ.
    let scene_own = dir.path().join("own");
    run_scene(&scene, None, &opts(&scene_own, None)).expect("runs");
    assert_ne!(history(&scene_own), history(&without));

    let fewer = dir.path().join("fewer");
    let out = run_scene(&scene, None, &opts(&fewer, Some(5.0e-7))).expect("runs");
    assert_eq!(out.summary.snapshots, 3);
    assert_eq!(read_pvd(&fewer).len(), 3);

    for bad in [-1.0e-7, f64::NAN, f64::INFINITY] {
        let err = run_scene(&scene, None, &opts(&dir.path().join("bad"), Some(bad)))
            .expect_err("refused");
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("--snapshot-every"), "{err}");
    }
    let ck = dir.path().join("ck");
    let write = RunOptions {
        checkpoint_every: Some(5.0e-7),
        ..opts(&ck, None)
    };
    run_scene(&scene, None, &write).expect("runs");
    let resume = RunOptions {
        silent: true,
        snapshot_every: Some(1.0e-7),
        ..Default::default()
    };
    let err = sphcontact::run::resume_run(&ck, &resume).expect_err("refused");
    assert_eq!(err.exit_code(), 2);
    assert!(err.to_string().contains("--snapshot-every"), "{err}");
}

#[test]
fn kernel_mode_snapshots_have_normals_too() {
    // No contact: the boundary set is still computed for the snapshot (the
    // SPH sums run across bodies, so the touching faces are not boundary).
    let dir = tempfile::tempdir().unwrap();
    let out = run_on(
        &disks(2.0e-7, 2.0e-7, "kernel"),
        Backend::Cpu,
        Some(dir.path()),
    );
    assert_eq!(out.summary.snapshots, 2);
    let v = read_vtu(&dir.path().join("snapshots/snapshot_000001.vtu"));
    check_boundary(&v, centres(&v), 1e-12);
}

#[test]
fn one_dimensional_snapshots() {
    let scene = parse(
        r#"
        [simulation]
        dimension = 1
        end_time = 1.0e-7
        [materials.steel]
        density = 7850.0
        shear_modulus = 77.0e9
        eos = { kind = "linear", c0 = 4580.0 }
        [[bodies]]
        name = "left"
        material = "steel"
        spacing = 1.0e-4
        velocity = [10.0]
        shape = { kind = "segment", from = -0.002, to = 0.0 }
        [[bodies]]
        name = "right"
        material = "steel"
        spacing = 1.0e-4
        velocity = [-10.0]
        shape = { kind = "segment", from = 0.0, to = 0.002 }
        [output]
        snapshot_interval = 1.0e-7
        "#,
    );
    let dir = tempfile::tempdir().unwrap();
    let out = run_on(&scene, Backend::Cpu, Some(dir.path()));
    let v = read_vtu(&dir.path().join("snapshots/snapshot_000001.vtu"));
    assert_eq!(v.points, 40);
    let x = v.xy("Points");
    assert!(x.iter().all(|p| p[1] == 0.0));
    let vel = v.xy("velocity");
    for (vi, si) in vel.iter().zip(&out.state.v) {
        assert_eq!(*vi, [si.x, 0.0]);
    }
    // Each bar's two ends are its boundary, normals ±x outward.
    check_boundary(&v, centres(&v), 1e-12);
}

#[test]
fn an_unwritable_snapshot_folder_is_a_run_error() {
    let dir = tempfile::tempdir().unwrap();
    // A file where the snapshot folder must go.
    std::fs::write(dir.path().join("snapshots"), b"in the way").unwrap();
    let err = run_scene(
        &disks(1.0e-7, 1.0e-7, "penalty"),
        None,
        &RunOptions {
            silent: true,
            backend: Some(Backend::Cpu),
            write: true,
            out_dir: Some(dir.path().to_path_buf()),
            ..Default::default()
        },
    )
    .expect_err("the snapshot folder cannot be made");
    assert!(matches!(err, RunError::Io { .. }), "{err}");
    assert_eq!(err.exit_code(), 1);
    assert!(err.to_string().contains("snapshots"), "{err}");
}

#[test]
fn gpu_snapshots_match_the_cpu_ones_at_the_start() {
    if gpu().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (cpu_dir, gpu_dir) = (dir.path().join("cpu"), dir.path().join("gpu"));
    let scene = disks(3.0e-7, 1.0e-7, "penalty");
    let cpu = run_on(&scene, Backend::Cpu, Some(&cpu_dir));
    let gpu_out = run_on(&scene, Backend::Gpu, Some(&gpu_dir));
    let (pc, pg) = (read_pvd(&cpu_dir), read_pvd(&gpu_dir));
    assert_eq!(pg.len(), 4);
    for (a, b) in pc.iter().zip(&pg) {
        assert_eq!(a.0, b.0, "the same snapshot times");
    }
    assert_eq!(gpu_out.summary.snapshots, 4);
    for k in [0, pg.len() - 1] {
        let c = read_vtu(&cpu_dir.join(&pc[k].1));
        let g = read_vtu(&gpu_dir.join(&pg[k].1));
        assert_eq!(g.points, c.points);
        assert_eq!(g.ints("body"), c.ints("body"));
        // f32 on the device: positions to its round-off over the 2 cm scene.
        for (p, q) in g.xy("Points").iter().zip(c.xy("Points")) {
            assert!(
                (p[0] - q[0]).abs() < 1e-8 && (p[1] - q[1]).abs() < 1e-8,
                "{p:?} vs {q:?}"
            );
        }
        let bg = check_boundary(&g, centres(&g), 1e-6);
        if k == 0 {
            // At t = 0 (the same state) the boundary sets agree.
            assert_eq!(g.ints("boundary"), c.ints("boundary"));
            for (a, b) in g.xy("normal").iter().zip(c.xy("normal")) {
                assert!((a[0] - b[0]).abs() < 1e-4 && (a[1] - b[1]).abs() < 1e-4);
            }
        }
        println!("gpu snapshot {k}: {bg} boundary particles");
    }
    // The last GPU snapshot is the state the run hands back.
    let last = read_vtu(&gpu_dir.join(&pg.last().unwrap().1));
    for (p, q) in last.xy("Points").iter().zip(&gpu_out.state.x) {
        assert_eq!(*p, [q.x, q.y]);
    }
    assert_eq!(cpu.summary.snapshots, 4);
}

/// A run that writes its outputs draws `history.png` beside `history.csv`:
/// one 300-pixel panel a probe, 1000 pixels wide (or, without a font, a
/// warning in the summary and no picture; CI requires the font).
#[test]
fn run_draws_its_history() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = load("scenes/paper/disks_polar.toml");
    let out = run_on(&scene, Backend::Cpu, Some(tmp.path()));
    let png = tmp.path().join("history.png");
    if !sphcontact::plot::font_available() {
        assert!(
            std::env::var_os("SPHCONTACT_REQUIRE_FONT").is_none(),
            "SPHCONTACT_REQUIRE_FONT is set but no TrueType font was found"
        );
        assert!(!png.exists());
        assert!(out
            .summary
            .warnings
            .iter()
            .any(|w| w.contains("history.png")));
        return;
    }
    let bytes = std::fs::read(&png).expect("history.png written");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "a PNG");
    let be = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().unwrap());
    assert_eq!(
        (be(16), be(20)),
        (1000, 300 * scene.probes.len() as u32),
        "width and height"
    );
    assert!(scene.probes.len() >= 5, "a panel a probe");
}

/// The images of a GIF file, walking its blocks (GIF89a: the screen
/// descriptor and its colour table, then extensions and images, each
/// image a descriptor, its colour table and its data sub-blocks).
fn gif_images(b: &[u8]) -> usize {
    let table = |flags: u8| {
        if flags & 0x80 != 0 {
            3 << ((flags & 7) + 1)
        } else {
            0
        }
    };
    let sub_blocks = |mut i: usize| {
        while b[i] != 0 {
            i += 1 + b[i] as usize;
        }
        i + 1
    };
    let (mut i, mut images) = (13 + table(b[10]), 0);
    loop {
        match b[i] {
            0x21 => i = sub_blocks(i + 2),
            0x2c => {
                images += 1;
                i = sub_blocks(i + 10 + table(b[i + 9]) + 1);
            }
            0x3b => return images,
            x => panic!("not a GIF block at byte {i}: {x:#x}"),
        }
    }
}

/// `sphcontact render` (docs/usage.md, "Particle pictures"): its reader
/// gives back the last snapshot's time, positions and velocities as the
/// run ended, to the bit; it draws one frame a snapshot; an unknown field
/// and a range upside down are refused with the reason.
#[test]
fn render_reads_each_snapshot_back_and_draws_it() {
    use sphcontact::output::render;
    let scene = disks(2e-6, 1e-6, "penalty");
    let tmp = tempfile::tempdir().unwrap();
    let out = run_on(&scene, Backend::Cpu, Some(tmp.path()));
    let files = render::snapshot_files(tmp.path()).unwrap();
    assert_eq!(files.len(), 3);
    let last = render::read_vtu(files.last().unwrap()).unwrap();
    assert_eq!(last.time, out.state.t);
    assert_eq!(last.x, out.state.x);
    let vx: Vec<f64> = out.state.v.iter().map(|v| v.x).collect();
    assert_eq!(last.field("velocity_x").unwrap(), vx);
    let speed: Vec<f64> = out.state.v.iter().map(|v| v.length()).collect();
    assert_eq!(last.field("speed").unwrap(), speed);
    // The bodies' names come from the run's summary.json.
    let names = render::Drawing::names_of_run(tmp.path());
    let want: Vec<String> = scene.bodies.iter().map(|b| b.name.clone()).collect();
    assert_eq!(names.as_ref(), Some(&want));
    let drawing = render::Drawing {
        names,
        boundary: true,
        window: None,
    };
    let mut frames = render::render(tmp.path(), "speed", None, true, &drawing).unwrap();
    assert_eq!(frames.len(), 4);
    let gif = frames.pop().unwrap();
    let b = std::fs::read(&gif).unwrap();
    assert_eq!(&b[..6], b"GIF89a", "{}", gif.display());
    let le = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
    assert_eq!((le(6), le(8)), (1000, 800));
    assert_eq!(gif_images(&b), 3, "one image a snapshot");
    for f in &frames {
        let b = std::fs::read(f).unwrap();
        assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n");
        let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        assert_eq!((be(16), be(20)), (1000, 800));
    }
    // `output.snapshot_png` draws the von Mises frames at the run's end.
    let mut drawn = scene.clone();
    drawn.output.snapshot_png = true;
    let tmp2 = tempfile::tempdir().unwrap();
    run_on(&drawn, Backend::Cpu, Some(tmp2.path()));
    for k in 0..3 {
        assert!(tmp2
            .path()
            .join(format!("frames/von_mises_{k:06}.png"))
            .exists());
    }
    let unknown =
        render::render(tmp.path(), "spead", None, false, &Default::default()).unwrap_err();
    assert!(unknown.contains("unknown field 'spead'") && unknown.contains("speed"));
    let upside = render::render(
        tmp.path(),
        "speed",
        Some((1.0, 0.0)),
        false,
        &Default::default(),
    )
    .unwrap_err();
    assert!(upside.contains("--range"), "{upside}");
    let window = render::Drawing {
        window: Some([0.0, 1.0, 1.0, 0.0]),
        ..Default::default()
    };
    let e = render::render(tmp.path(), "speed", None, false, &window).unwrap_err();
    assert!(e.contains("--window 0 1 1 0"), "{e}");
}
