//! Bodies far from the origin: the same answers as at the origin.

use super::*;

/// The scene with every coordinate (shapes and probe points, both axes in
/// 2-D) moved by `-delta`.
fn shifted(scene: &Scene, delta: f64) -> Scene {
    use sphcontact::scene::Shape;
    let mut s = scene.clone();
    let dim = s.dim();
    let shift = |v: &mut Vec<f64>| v.iter_mut().take(dim).for_each(|x| *x -= delta);
    for b in &mut s.bodies {
        match &mut b.shape {
            Shape::Segment { from, to } => {
                *from -= delta;
                *to -= delta;
            }
            Shape::Rectangle { min, max } => {
                shift(min);
                shift(max);
            }
            Shape::Disk { center, .. } | Shape::Ring { center, .. } => shift(center),
            Shape::Polygon {
                vertices, holes, ..
            } => {
                vertices.iter_mut().for_each(shift);
                holes.iter_mut().flatten().for_each(shift);
            }
            Shape::Particles { .. } => panic!("the far-field scenes are built-in shapes"),
        }
    }
    for p in &mut s.probes {
        if let Probe::Particle { at, .. } = p {
            shift(at);
        }
    }
    s
}

/// How far the runs at 1 m and 100 m stray from the run at the origin:
/// the largest difference of the contact force over the history (relative
/// to its peak), of the contact window's end (relative), of the final body
/// velocities (relative to the impact speed `v_scale`) and of the
/// position probes less the shift (m).
struct Stray {
    force: f64,
    window: f64,
    velocity: f64,
    position: f64,
}

/// Tolerances for a run at `offset` (m) against the origin run, as
/// [`Stray`]'s fields. CPU (f64): a coordinate near X is rounded to
/// `ε X` (ε = 2.2e-16), and the penalty spring (stiffness `M/Δx` over two
/// half-spacing layers) turns a gap error `ε X` into a pressure error
/// `M ε X/Δx`, that is `(c_L/v) (ε X/Δx)` of the contact stress `Z v`: with
/// four roundings in a gap (two coordinates, their shift, the difference)
/// and a factor 2 of margin, `8 (c_L/v) ε X/Δx` for the force history, the
/// contact end and the velocities; a mean position sums `n` coordinates, so
/// `n ε X`. GPU (f32): positions are relative to a grid origin held in f64
/// on the host, so the offset changes only the rounding of each particle's
/// f32 offset inside its cell (1e-7 Δx, 1 unit in the last place); one
/// flipped rounding on a contact face moves the pressure by
/// `(c_L/v)·1e-7·(a few)` ≈ 1e-4 of it (measured 4e-5 at 100 m): force
/// history and contact end within 1e-3, velocities within 1e-5 of the
/// impact speed, positions within 1e-8 m (f32 resolution of a
/// centimetre-size body, 2e-4 Δx; an absolute f32 coordinate near 100 m
/// would be off by up to 3.8e-6 m).
fn tolerances(offset: f64, c_over_v: f64, spacing: f64, n: usize) -> Stray {
    if backend() == sphcontact::scene::Backend::Gpu {
        return Stray {
            force: 1e-3,
            window: 1e-3,
            velocity: 1e-5,
            position: 1e-8,
        };
    }
    let round = f64::EPSILON * offset.max(0.01);
    let rel = 8.0 * c_over_v * round / spacing;
    Stray {
        force: rel,
        window: rel,
        velocity: rel,
        position: n as f64 * round,
    }
}

/// `far` (placed near 100 m) run moved to the origin, to 1 m and as it is.
fn runs_at_offsets(far: &Scene) -> Vec<(f64, RunOutput)> {
    [0.0, 1.0, 100.0]
        .iter()
        .map(|&o| (o, run(&shifted(far, 100.0 - o))))
        .collect()
}

/// The runs of [`runs_at_offsets`] away from the origin conserve and give
/// the origin run's answers within [`tolerances`] (impact speed 10 m/s,
/// `n` particles in a mean position).
fn assert_offsets_match(
    what: &str,
    far: &Scene,
    runs: &[(f64, RunOutput)],
    spacing: f64,
    n: usize,
) {
    let steel = material(far, "steel");
    let origin = &runs[0].1;
    for (o, out) in &runs[1..] {
        assert_conserved(far, out);
        let s = stray(origin, out, *o, 10.0);
        // The contact stress is Z v0 with v0 = 10 m/s per body.
        let tol = tolerances(*o, steel.c_l / 10.0, spacing, n);
        println!(
            "{what} at {o} m: force {:.2e} (tolerance {:.1e}), contact end {:.2e}, velocity {:.2e}, position {:.2e} m (tolerance {:.1e})",
            s.force, tol.force, s.window, s.velocity, s.position, tol.position
        );
        assert!(
            s.force < tol.force,
            "{o} m: force history off by {:e} of the peak",
            s.force
        );
        assert!(
            s.window < tol.window,
            "{o} m: end of contact off by {:e}",
            s.window
        );
        assert!(
            s.velocity < tol.velocity,
            "{o} m: rebound off by {:e} of v0",
            s.velocity
        );
        assert!(
            s.position < tol.position,
            "{o} m: positions off by {:e} m",
            s.position
        );
    }
}

fn stray(origin: &RunOutput, far: &RunOutput, offset: f64, v_scale: f64) -> Stray {
    let f0 = column(origin, "contact_force");
    let f1 = column(far, "contact_force");
    let peak = f0.iter().cloned().fold(0.0, f64::max);
    let force = f0
        .iter()
        .zip(&f1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / peak;
    let t = &origin.history.times;
    let (_, e0) = contact_window(t, &f0);
    let (_, e1) = contact_window(&far.history.times, &f1);
    let velocity = ["velocity_left", "velocity_right"]
        .iter()
        .map(|n| {
            (column(origin, n).last().unwrap() - column(far, n).last().unwrap()).abs() / v_scale
        })
        .fold(0.0, f64::max);
    let position = origin
        .history
        .names
        .iter()
        .filter(|n| n.starts_with("position"))
        .flat_map(|n| {
            column(origin, n)
                .into_iter()
                .zip(column(far, n))
                .map(|(a, b)| (b - offset - a).abs())
        })
        .fold(0.0, f64::max);
    Stray {
        force,
        window: (e1 / e0 - 1.0).abs(),
        velocity,
        position,
    }
}

/// The paper's bars with the contact face at 100 m (scenes/hard/
/// far_bars_steel.toml), moved back to the origin and to 1 m: the runs at
/// 1 m and 100 m must give the origin run's answers to round-off
/// ([`tolerances`]: at 100 m on the CPU 2e-6 of the contact force and 2e-12 m
/// of position; on the GPU 1e-3 and 1e-8 m). The origin run itself meets
/// the paper's case 1 (plateau and separation within 1 %, rebound within
/// 5 %: tests/paper_bars.rs).
fn far_bars() {
    let far = load("scenes/hard/far_bars_steel.toml");
    let steel = material(&far, "steel");
    let exact = bar_impact(&steel, 0.005, 10.0, &steel, 0.005, -10.0);
    let runs = runs_at_offsets(&far);
    let origin = &runs[0].1;
    assert_conserved(&far, origin);
    let f = column(origin, "contact_force");
    let (_, t_sep) = contact_window(&origin.history.times, &f);
    assert!((t_sep / exact.separation_time - 1.0).abs() < 0.01);
    let k = origin
        .history
        .times
        .iter()
        .position(|&x| x > 0.5 * t_sep)
        .unwrap();
    assert!((f[k] / -exact.contact_stress - 1.0).abs() < 0.01);
    let vl = *column(origin, "velocity_left").last().unwrap();
    assert!((vl / exact.final_velocity_1 - 1.0).abs() < 0.05);

    assert_offsets_match("bars", &far, &runs, 5e-5, 100);
}

#[test]
fn far_from_origin_bars() {
    far_bars();
}

#[test]
fn far_from_origin_bars_gpu() {
    on_gpu(far_bars);
}

/// Two coarse polar-lattice steel disks touching at (100 m, 100 m)
/// (scenes/hard/far_disks_polar.toml), moved back to the origin and to
/// (1 m, 1 m): the runs there and here must give the origin run's answers
/// to round-off ([`tolerances`], the 2-D contact's partner interpolation
/// in the chain). The origin run makes contact and the disks separate
/// (restitution between 0.8 and 1 at this coarse resolution; the converged
/// answer is tests/paper_disks.rs's).
fn far_disks() {
    let far = load("scenes/hard/far_disks_polar.toml");
    let runs = runs_at_offsets(&far);
    let origin = &runs[0].1;
    assert_conserved(&far, origin);
    let (t0, t1) = contact_window(&origin.history.times, &column(origin, "contact_force"));
    assert!(
        t1 > t0 && t1 < far.simulation.end_time,
        "the disks separate"
    );
    let restitution = (column(origin, "velocity_right").last().unwrap()
        - column(origin, "velocity_left").last().unwrap())
        / 10.0;
    assert!(
        restitution > 0.8 && restitution <= 1.0,
        "restitution {restitution}"
    );

    let n = origin.summary.bodies[0].particles;
    assert_offsets_match("disks", &far, &runs, 5e-4, n);
}

#[test]
fn far_from_origin_disks() {
    far_disks();
}

#[test]
fn far_from_origin_disks_gpu() {
    on_gpu(far_disks);
}

// ---------------------------------------------------------------------------
// 4. Long run
// ---------------------------------------------------------------------------
