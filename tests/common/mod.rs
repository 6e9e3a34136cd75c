//! Shared helpers of the integration tests: run a scene through the library
//! and read observables off its history.
#![allow(dead_code)]

pub mod vtu;

use std::path::Path;

use sphcontact::physics::material::MaterialModel;
use sphcontact::run::{run_scene, RunOptions, RunOutput};
use sphcontact::scene::{Backend, Integrator};
use sphcontact::validation::exact::HertzImpact;
use sphcontact::Scene;

pub fn load(path: &str) -> Scene {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    Scene::from_file(&root.join(path)).expect("a valid scene")
}

/// The oblique disk of scenes/friction/disk_wall_oblique.toml at friction
/// `mu`, its speed as shipped turned to `degrees` from the wall's normal
/// (as shipped: 0.1, 45°). Returns the scene and the disk's velocity.
pub fn oblique_disk(mu: f64, degrees: f64) -> (Scene, glam::DVec2) {
    let mut scene = load("scenes/friction/disk_wall_oblique.toml");
    scene.contact.as_mut().unwrap().friction = mu;
    let speed = glam::DVec2::from_slice(scene.bodies[0].velocity.as_deref().unwrap()).length();
    let v0 = glam::DVec2::from_angle(degrees.to_radians()) * speed;
    scene.bodies[0].velocity = Some(vec![v0.x, v0.y]);
    (scene, v0)
}

/// `scene` with the hourglass control at `alpha` in place of the
/// artificial stress (docs/method.md, "Hourglass control").
pub fn with_hourglass_control(scene: &mut Scene, alpha: f64) {
    scene.artificial_stress = Some(sphcontact::scene::ArtificialStress {
        epsilon: 0.0,
        ..sphcontact::scene::ArtificialStress::DEFAULT
    });
    scene
        .artificial_viscosity
        .get_or_insert_with(Default::default)
        .hourglass = alpha;
}

/// `scene` with the dispersion correction at `theta` and the viscosity's
/// linear coefficient at `alpha` (docs/method.md §4, "The dispersion
/// correction").
#[allow(dead_code)]
pub fn with_dispersion_correction(scene: &mut Scene, theta: f64, alpha: f64) {
    scene.simulation.dispersion_correction = theta;
    scene
        .artificial_viscosity
        .get_or_insert_with(Default::default)
        .alpha = alpha;
}

pub fn parse(text: &str) -> Scene {
    Scene::from_toml_str(text, "test scene").expect("a valid scene")
}

thread_local! {
    /// The backend `run` uses on this test's thread.
    static BACKEND: std::cell::Cell<Backend> = const { std::cell::Cell::new(Backend::Cpu) };
    /// The integrator `run` imposes on this test's thread (`None`: the scene's).
    static INTEGRATOR: std::cell::Cell<Option<Integrator>> = const { std::cell::Cell::new(None) };
    /// Whether `run` gives round supports to scenes that name none.
    static ROUND: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Run a test body with round supports (`support = "fixed"`) in every
/// scene that does not name its supports: for tests of something else
/// whose scenes squeeze material, where adaptive supports (the default)
/// take up to twice the steps. Their own tests hold them.
pub fn on_round_supports(test: impl FnOnce()) {
    ROUND.with(|r| r.set(true));
    test();
    ROUND.with(|r| r.set(false));
}

/// Run a test body with every `run` stepped by the leapfrog.
pub fn on_leapfrog(test: impl FnOnce()) {
    INTEGRATOR.with(|i| i.set(Some(Integrator::Leapfrog)));
    test();
    INTEGRATOR.with(|i| i.set(None));
}

/// Run a test body with every `run` stepped by the midpoint rule (the
/// default is the leapfrog).
pub fn on_midpoint(test: impl FnOnce()) {
    INTEGRATOR.with(|i| i.set(Some(Integrator::Midpoint)));
    test();
    INTEGRATOR.with(|i| i.set(None));
}

/// The backend of this test thread's runs.
pub fn backend() -> Backend {
    BACKEND.with(|b| b.get())
}

/// Run a test body with every `run` on the GPU backend (skipped visibly, or
/// failed under `SPHCONTACT_REQUIRE_GPU`, without an adapter).
pub fn on_gpu(test: impl FnOnce()) {
    if gpu().is_none() {
        return;
    }
    BACKEND.with(|b| b.set(Backend::Gpu));
    test();
    BACKEND.with(|b| b.set(Backend::Cpu));
}

/// Run silently, in memory, on this thread's backend.
pub fn run(scene: &Scene) -> RunOutput {
    run_on(scene, backend(), None)
}

/// Run silently on `backend`, writing the outputs into `out_dir` if given.
pub fn run_on(scene: &Scene, backend: Backend, out_dir: Option<&Path>) -> RunOutput {
    let round;
    let scene = if ROUND.with(|r| r.get()) && scene.simulation.support.is_none() {
        let mut s = scene.clone();
        s.simulation.support = Some(sphcontact::scene::Support::Fixed);
        round = s;
        &round
    } else {
        scene
    };
    run_scene(
        scene,
        None,
        &RunOptions {
            silent: true,
            backend: Some(backend),
            integrator: INTEGRATOR.with(|i| i.get()),
            write: out_dir.is_some(),
            out_dir: out_dir.map(Path::to_path_buf),
            ..Default::default()
        },
    )
    .expect("the run completes")
}

pub fn material(scene: &Scene, name: &str) -> MaterialModel {
    MaterialModel::new(&scene.materials[name])
}

pub fn column(out: &RunOutput, name: &str) -> Vec<f64> {
    out.history
        .column(name)
        .unwrap_or_else(|| panic!("no probe '{name}'"))
}

#[allow(unused_imports)]
pub use sphcontact::output::contact_window;

/// The values of `column` over the middle of a contact, 10–90 % of
/// `t_sep` (away from the loading and unloading transients): the contact
/// plateau.
pub fn plateau(times: &[f64], column: &[f64], t_sep: f64) -> Vec<f64> {
    times
        .iter()
        .zip(column)
        .filter(|(&tk, _)| tk > 0.1 * t_sep && tk < 0.9 * t_sep)
        .map(|(_, &x)| x)
        .collect()
}

/// Momentum to round-off (relative to Σ m |v0|: 1e-12 in f64 on the CPU,
/// 1e-6 for f32 on the GPU) and the ledger closed: the total energy
/// (kinetic + internal + stored penalty, with what the spring lost; the
/// dashpot's and the artificial terms' heat are inside the internal
/// energy) within 1e-10 of the initial on the CPU and 1e-5 on the GPU.
/// Measured over the default suite's 72 calls: at most 2.4e-13 on the
/// CPU, 7.4e-7 on the GPU (the steel bars in f32).
pub fn assert_conserved(scene: &Scene, out: &RunOutput) {
    let s = &out.summary;
    let scale: f64 = s
        .bodies
        .iter()
        .zip(&scene.bodies)
        .map(|(b, sb)| {
            let v = sb.velocity.clone().unwrap_or_default();
            b.mass * v.iter().map(|x| x * x).sum::<f64>().sqrt()
        })
        .sum::<f64>()
        .max(1e-300);
    let round_off = if backend() == Backend::Gpu {
        1e-6
    } else {
        1e-12
    };
    for (a, b) in s.momentum_initial.iter().zip(&s.momentum_final) {
        assert!(
            (a - b).abs() <= round_off * scale,
            "momentum drifted: {a} -> {b} (scale {scale})"
        );
    }
    // The ledger closes: what the bodies hold plus what the discrete
    // penalty spring lost (reported, and bounded by the tests that make
    // contact) is what they started with, up to the time integration.
    let l = &s.energy;
    let held = l.kinetic + l.internal + l.spring + l.potential.unwrap_or(0.0);
    assert!(
        (held - s.energy_final).abs() <= 1e-12 * s.energy_final.abs().max(1e-300)
            && l.initial == s.energy_initial
            && l.spring_loss == s.energy_spring_loss
            && (l.residual - s.energy_balance() * s.energy_initial).abs()
                <= 1e-9 * s.energy_initial.abs().max(1e-300),
        "the ledger's terms do not add up: {l:?} against {s:?}"
    );
    assert!(
        l.dashpot_heat >= 0.0,
        "the dashpot made energy: {:e}",
        l.dashpot_heat
    );
    if s.energy_initial > 0.0 {
        let drift = s.energy_balance().abs();
        println!(
            "{} energy drift {drift:.2e}",
            std::thread::current().name().unwrap_or("-")
        );
        let bound = if out.summary.backend == "gpu" {
            1e-5
        } else {
            1e-10
        };
        assert!(drift < bound, "energy drift {drift:e} (bound {bound:e})");
        assert!(
            s.energy_spring_loss >= -1e-3 * s.energy_initial,
            "the penalty spring made energy: {:e}",
            s.energy_spring_loss
        );
    }
}

/// The contact never pulls body `body` (its mean velocity along the
/// direction to its partner in column `velocity`): the largest pull
/// ([`sphcontact::output::pull_and_push`], read from the body's momentum,
/// not from a probe clamped at zero) stays at round-off. On the CPU that
/// is 1e-11 of the largest push (measured 5e-14 to 1.3e-12 on the bars,
/// disks, impedance and jitter cases). In f32 a mean velocity rounds at
/// about 1e-7 of the largest, so two rows Δt apart differ by that much
/// over Δt: the bound is ten times it, `1e-6 m max|v| / Δt` (measured
/// 0.05–0.15 of it).
pub fn assert_never_pulls(out: &RunOutput, body: usize, velocity: &str) {
    let t = &out.history.times;
    let v = column(out, velocity);
    let mass = out.summary.bodies[body].mass;
    let (pull, push) = sphcontact::output::pull_and_push(t, &v, mass);
    assert!(push > 0.0, "no contact: largest push {push:e}");
    let bound = if out.summary.backend == "gpu" {
        let v_max = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let dt = t
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        1e-6 * mass * v_max / dt
    } else {
        1e-11 * push
    };
    println!(
        "largest pull {pull:e}, {:.2e} of the bound, {:.2e} of the largest push",
        pull / bound,
        pull / push
    );
    assert!(
        pull <= bound,
        "the contact pulled: {pull:e} against a largest push of {push:e} (bound {bound:e})"
    );
}

/// The GPU context shared by a test binary, or `None` with a visible skip
/// line. With `SPHCONTACT_REQUIRE_GPU` set (CI), a missing adapter fails
/// the test instead.
pub fn gpu() -> Option<std::sync::Arc<sphcontact::gpu::GpuContext>> {
    match sphcontact::gpu::shared_context() {
        Ok(c) => Some(c),
        Err(e) => {
            if std::env::var_os("SPHCONTACT_REQUIRE_GPU").is_some() {
                panic!("SPHCONTACT_REQUIRE_GPU is set but there is no GPU adapter: {e}");
            }
            eprintln!("SKIP: no GPU adapter ({e}); this GPU test did not run");
            None
        }
    }
}

/// `history.csv` as written: the header and the rows (perhaps none yet).
/// Every row is whole and numeric, the rows start at t = 0 and their times
/// increase (else a panic).
pub fn read_history(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let csv = std::fs::read_to_string(path).expect("history.csv");
    assert!(csv.ends_with('\n'), "the last row is whole");
    let mut lines = csv.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    assert_eq!(header[0], "time");
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let row: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or_else(|_| panic!("row {l:?}")))
                .collect();
            assert_eq!(row.len(), header.len(), "row {l:?}");
            row
        })
        .collect();
    assert!(rows.first().is_none_or(|r| r[0] == 0.0), "rows from t = 0");
    for w in rows.windows(2) {
        assert!(w[1][0] > w[0][0], "times increase");
    }
    (header, rows)
}

/// An instability message, parsed.
#[derive(Debug)]
pub struct Message {
    pub step: u64,
    pub time: f64,
    pub body: String,
    pub particle: usize,
    pub quantity: String,
}

/// `unstable at step N (t = T s): body 'B', particle K: Q = V`, parsed
/// (`None` for any other text).
fn parse_instability(line: &str) -> Option<Message> {
    let rest = line.strip_prefix("unstable at step ")?;
    let (step, rest) = rest.split_once(" (t = ")?;
    let (time, rest) = rest.split_once(" s): body '")?;
    let (body, rest) = rest.split_once("', particle ")?;
    let (particle, rest) = rest.split_once(": ")?;
    let (quantity, value) = rest.rsplit_once(" = ")?;
    if !(value == "NaN" || value.contains("inf") || value.parse::<f64>().is_ok()) {
        return None;
    }
    Some(Message {
        step: step.parse().ok()?,
        time: time.parse().ok()?,
        body: body.to_string(),
        particle: particle.parse().ok()?,
        quantity: quantity.to_string(),
    })
}

/// What a run that went unstable left, checked as docs/scenes.md and the
/// instability contract ask: `stderr` holds exactly one instability
/// message (the adapter may add lines of its own), naming a known
/// quantity; `summary.json` in `out_dir` parses, is marked failed and
/// carries that message and the failing state's time (to the message's six
/// digits); `history.csv` holds whole numeric rows up to the failure.
/// Returns the message (its line and parsed) and the history rows.
pub fn failed_run(out_dir: &Path, stderr: &str) -> (String, Message, Vec<Vec<f64>>) {
    let ours: Vec<&str> = stderr
        .lines()
        .filter_map(|l| l.strip_prefix("error: "))
        .filter(|l| l.starts_with("unstable"))
        .collect();
    assert_eq!(ours.len(), 1, "one instability message:\n{stderr}");
    let msg = parse_instability(ours[0])
        .unwrap_or_else(|| panic!("not an instability message: {:?}", ours[0]));
    assert!(
        [
            "position",
            "velocity",
            "internal energy",
            "density",
            "time step",
            "total energy"
        ]
        .iter()
        .any(|q| msg.quantity.starts_with(q)),
        "quantity {:?}",
        msg.quantity
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .expect("summary.json parses");
    assert_eq!(summary["status"], "failed");
    assert_eq!(summary["error"], ours[0]);
    let reached = summary["time_reached"].as_f64().unwrap();
    assert!(
        (reached - msg.time).abs() <= 1e-6 * msg.time,
        "time reached {reached:e}, failure at {:e}",
        msg.time
    );
    let (_, rows) = read_history(&out_dir.join("history.csv"));
    assert!(!rows.is_empty(), "no history rows");
    assert!(rows.last().unwrap()[0] <= msg.time, "rows past the failure");
    (ours[0].to_string(), msg, rows)
}

/// Assert that a contact's peak force and duration lie within `margin` (a
/// fraction) of the quasi-static Hertz bracket: the peak between the soft
/// bound's and the stiff bound's, the duration between the stiff bound's
/// (shorter) and the soft bound's.
pub fn assert_in_hertz_bracket(
    peak: f64,
    duration: f64,
    soft: &HertzImpact,
    stiff: &HertzImpact,
    margin: f64,
) {
    let pct = 100.0 * margin;
    assert!(
        peak > (1.0 - margin) * soft.peak_force && peak < (1.0 + margin) * stiff.peak_force,
        "peak force {peak:e} N/m outside ±{pct} % of the Hertz bracket"
    );
    assert!(
        duration > (1.0 - margin) * stiff.contact_time
            && duration < (1.0 + margin) * soft.contact_time,
        "contact time {duration:e} s outside ±{pct} % of the Hertz bracket"
    );
}
