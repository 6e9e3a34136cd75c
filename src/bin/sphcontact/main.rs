//! The `sphcontact` command line (docs/scenes.md, "Command line").

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use sphcontact::run::{run_scene, RunOptions};
use sphcontact::scene::{Backend, Integrator, Scene};

mod check;
mod validate;

use check::check;
use validate::{validate_cmd, ValidateArgs};

#[derive(Parser)]
#[command(
    name = "sphcontact",
    version,
    about = "SPH for impacts between elastic and elasto-plastic solids, with the Seo & Min penalty contact",
    after_help = "Scene files, their keys and every output: docs/scenes.md. The method: docs/method.md."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    Auto,
    Gpu,
    Cpu,
}

#[derive(Clone, Copy, ValueEnum)]
enum IntegratorArg {
    Midpoint,
    Leapfrog,
}

#[derive(Clone, Copy, ValueEnum)]
enum SupportArg {
    Fixed,
    Adaptive,
}

fn integrator_of(i: IntegratorArg) -> Integrator {
    match i {
        IntegratorArg::Midpoint => Integrator::Midpoint,
        IntegratorArg::Leapfrog => Integrator::Leapfrog,
    }
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write history.csv, history.png and summary.json.
    Run {
        /// The scene file (TOML); not with --resume, which takes the scene
        /// from the checkpoint.
        #[arg(required_unless_present = "resume", conflicts_with = "resume")]
        scene: Option<PathBuf>,
        /// Output directory (default: the scene's output.dir, else out/<scene stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Which backend runs the scene (overrides the scene's simulation.backend).
        #[arg(long, value_enum)]
        backend: Option<BackendArg>,
        /// Stop at this simulated time, s (overrides simulation.end_time).
        #[arg(long, allow_negative_numbers = true)]
        end_time: Option<f64>,
        /// Time integration (overrides simulation.integrator): midpoint
        /// (two evaluations a step) or leapfrog (one).
        #[arg(long, value_enum)]
        integrator: Option<IntegratorArg>,
        /// No progress: only warnings and the closing line (without a
        /// terminal, and without --quiet, a plain progress line every 5 %
        /// of the end time or 10 s).
        #[arg(long)]
        quiet: bool,
        /// Write the run's whole state to OUT/checkpoint.bin at the first
        /// step at or after every multiple of this simulated time, s (the
        /// steps themselves are not changed).
        #[arg(long, value_name = "T", allow_negative_numbers = true)]
        checkpoint_every: Option<f64>,
        /// Write a snapshot every T of simulated time, s (overrides
        /// output.snapshot_interval; 0 writes none). Snapshots end the
        /// steps that would cross them, so the interval moves the steps.
        #[arg(long, value_name = "T", allow_negative_numbers = true)]
        snapshot_every: Option<f64>,
        /// Continue the run whose checkpoint is in DIR (its output
        /// directory), on the backend that wrote it; the history comes out
        /// as the uninterrupted run's. Outputs go to DIR unless --out says
        /// otherwise.
        #[arg(long, value_name = "DIR")]
        resume: Option<PathBuf>,
    },
    /// Parse and validate a scene, print the derived set-up, run nothing.
    Check {
        /// The scene file (TOML).
        scene: PathBuf,
    },
    /// Run the paper's cases against their exact answers: table, figures
    /// (PNG), the CSV behind every curve and validation.json.
    Validate(ValidateArgs),
    /// Particle throughput: the two-disk impact (square lattice) timed in
    /// contact at each particle count, on each backend.
    Bench(BenchArgs),
    /// The ballistic limit of a projectile against a target, by bisection
    /// over whole runs of the scene; each shot's residual velocity.
    Ballistic(BallisticArgs),
    /// Which GPU the solver can see, and what to install where it sees none.
    ///
    /// The graphics loader, driver manifests and adapters found, the limits
    /// the solver needs, whether `run` takes the GPU path and why not.
    /// Exit status 0 with a usable hardware adapter, 1 without
    /// (docs/usage.md, "When the GPU is not found").
    Doctor,
    /// Draw a finished run's snapshots as pictures of one particle field.
    ///
    /// Each snapshot in OUT/snapshots/ becomes OUT/frames/FIELD_NNNNNN.png:
    /// the particles as filled cells of their spacing, coloured by the
    /// field on one scale for every frame, with its colour bar and unit
    /// and the snapshot's time (docs/usage.md, "Particle pictures").
    Render {
        /// The run's output directory (it needs output.snapshot_interval).
        out: PathBuf,
        /// The field: density, pressure, stress_xx, stress_yy, stress_xy,
        /// von_mises, internal_energy, plastic_strain, temperature, damage,
        /// failure_time, velocity_x, velocity_y, speed, body, boundary.
        #[arg(long, default_value = "von_mises")]
        field: String,
        /// The colour scale's ends (default: the field's least and
        /// greatest over every snapshot).
        #[arg(long, num_args = 2, value_names = ["LOW", "HIGH"], allow_negative_numbers = true)]
        range: Option<Vec<f64>>,
        /// Also join the frames into OUT/frames/FIELD.gif (10 frames a second).
        #[arg(long)]
        gif: bool,
        /// Mark the contact boundary's particles with black dots.
        #[arg(long)]
        boundary: bool,
        /// Leave the bodies' names (read from OUT/summary.json) off.
        #[arg(long)]
        no_names: bool,
        /// Show only this part of the plane, m (default: every particle).
        #[arg(long, num_args = 4, value_names = ["XMIN", "XMAX", "YMIN", "YMAX"], allow_negative_numbers = true)]
        window: Option<Vec<f64>>,
    },
}

#[derive(Args)]
struct BallisticArgs {
    /// The scene file (TOML): the projectile's velocity gives the impact
    /// direction.
    scene: PathBuf,
    /// The projectile body.
    #[arg(long)]
    projectile: String,
    /// The target body.
    #[arg(long)]
    target: String,
    /// An impact speed that does not perforate, m/s.
    #[arg(long, allow_negative_numbers = true)]
    low: f64,
    /// An impact speed that perforates, m/s.
    #[arg(long, allow_negative_numbers = true)]
    high: f64,
    /// Stop when the bracket is this narrow, m/s.
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true)]
    tolerance: f64,
    /// Every body's particle spacing for the search, m (default: the
    /// scene's); the result is reported with it.
    #[arg(long, allow_negative_numbers = true)]
    spacing: Option<f64>,
    /// The shots' end time, s (default: the scene's).
    #[arg(long, allow_negative_numbers = true)]
    end_time: Option<f64>,
    /// More impact speeds to shoot after the search, for the residual
    /// velocity curve, m/s.
    #[arg(long, num_args = 1.., allow_negative_numbers = true)]
    speeds: Vec<f64>,
    /// Which backend runs the shots.
    #[arg(long, value_enum)]
    backend: Option<BackendArg>,
    /// Output directory: ballistic.json, residual.csv, residual.png, and
    /// each shot's outputs in v<speed>/.
    #[arg(long, default_value = "out/ballistic")]
    out: PathBuf,
}

fn ballistic_cmd(args: BallisticArgs) -> ExitCode {
    use sphcontact::ballistic::{search, BallisticOptions};
    let scene = match load(&args.scene) {
        Ok(s) => s,
        Err(code) => return code,
    };
    let opts = BallisticOptions {
        projectile: args.projectile,
        target: args.target,
        low: args.low,
        high: args.high,
        tolerance: args.tolerance,
        spacing: args.spacing,
        end_time: args.end_time,
        speeds: args.speeds,
        backend: args.backend.map(backend_of),
        out_dir: Some(args.out.clone()),
    };
    let label = args.scene.display().to_string();
    let result = search(&scene, &label, &opts, |s| {
        eprintln!(
            "shot {:8.1} m/s: {:<16} residual {:8.1} m/s, {} target particles failed, {} particles, {} steps, {:.1} s",
            s.speed,
            match (s.perforated, s.undecided) {
                (true, _) => "perforates",
                (_, true) => "undecided",
                _ => "stops",
            },
            s.residual_velocity,
            s.target_failed,
            s.particles,
            s.steps,
            s.wall_seconds
        );
    });
    match result.and_then(|b| b.write(&args.out).map(|_| b)) {
        Ok(b) => {
            if let Some(why) = &b.stopped {
                eprintln!("warning: the bisection stopped early: {why}");
            }
            println!(
                "ballistic limit {:.1} m/s (between {:.1} and {:.1} m/s) at a spacing of {:.3e} m; outputs in {}",
                b.ballistic_limit,
                b.limit_bracket[0],
                b.limit_bracket[1],
                b.spacing[0],
                args.out.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => failed(e),
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum BenchBackendArg {
    Cpu,
    Gpu,
    Auto,
    All,
}

#[derive(Args)]
struct BenchArgs {
    /// Backends to time: cpu, gpu (an error without an adapter), auto (the
    /// one `run` would use), all (the CPU, and the GPU when there is one).
    #[arg(long, value_enum, default_value = "all")]
    backend: BenchBackendArg,
    /// Total particle counts (both disks); each is met as closely as the
    /// square lattice allows, and the table gives the actual count.
    #[arg(long, num_args = 1.., default_values_t = [1_000usize, 10_000, 100_000])]
    particles: Vec<usize>,
    /// Timed steps per measurement (default: at least 20, more until it
    /// lasts about 1 s).
    #[arg(long)]
    steps: Option<u64>,
    /// Measurements per backend and size, one after another in the same
    /// run, each of as many steps as the first; the record gives the
    /// median and every rate.
    #[arg(long, default_value_t = 1)]
    repeat: u32,
    /// Also time each GPU stage alone.
    #[arg(long)]
    stages: bool,
    /// Time integration of the timed steps: leapfrog (one evaluation a
    /// step, the default, as in a scene) or midpoint (two).
    #[arg(long, value_enum, default_value = "leapfrog")]
    integrator: IntegratorArg,
    /// The hourglass control's coefficient α_hg in the disks, on top of
    /// their artificial stress, to time what it costs (0, the default: off;
    /// docs/method.md, "Hourglass control").
    #[arg(long, default_value_t = 0.0)]
    hourglass: f64,
    /// The dispersion correction's θ in the disks, to time what its sweeps
    /// cost (0, the default: off; docs/method.md, "The dispersion
    /// correction").
    #[arg(long, default_value_t = 0.0)]
    dispersion_correction: f64,
    /// The disks' kernel supports: adaptive (carried with the
    /// deformation, round while nothing stretches; the default, as in a
    /// scene) or fixed (round), to time what carrying them costs
    /// (docs/method.md, "Supports that follow the deformation").
    #[arg(long, value_enum, default_value = "adaptive")]
    support: SupportArg,
    /// A JSON list of the records on stdout instead of the table.
    #[arg(long)]
    json: bool,
}

fn backend_of(b: BackendArg) -> Backend {
    match b {
        BackendArg::Auto => Backend::Auto,
        BackendArg::Gpu => Backend::Gpu,
        BackendArg::Cpu => Backend::Cpu,
    }
}

/// Exit status and message of a run that failed (docs/scenes.md, "Exit status": 2 bad input,
/// 1 the run itself).
fn failed(e: sphcontact::RunError) -> ExitCode {
    eprintln!("error: {e}");
    ExitCode::from(e.exit_code() as u8)
}

fn bench_cmd(args: BenchArgs) -> ExitCode {
    use sphcontact::bench::{self, BenchBackend, BenchOptions};
    let opts = BenchOptions {
        backend: match args.backend {
            BenchBackendArg::Cpu => BenchBackend::Cpu,
            BenchBackendArg::Gpu => BenchBackend::Gpu,
            BenchBackendArg::Auto => BenchBackend::Auto,
            BenchBackendArg::All => BenchBackend::All,
        },
        particles: args.particles,
        steps: args.steps,
        repeat: args.repeat,
        stages: args.stages,
        integrator: integrator_of(args.integrator),
        hourglass: args.hourglass,
        dispersion: args.dispersion_correction,
        support: match args.support {
            SupportArg::Fixed => sphcontact::scene::Support::Fixed,
            SupportArg::Adaptive => sphcontact::scene::Support::Adaptive,
        },
        verbose: true,
    };
    match bench::bench(&opts) {
        Ok(records) => {
            if args.json {
                match serde_json::to_string_pretty(&records) {
                    Ok(j) => println!("{j}"),
                    Err(e) => {
                        eprintln!("error: writing the records as JSON: {e}");
                        return ExitCode::from(1);
                    }
                }
            } else {
                print!("{}", bench::table(&records));
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}

fn load(path: &Path) -> Result<Scene, ExitCode> {
    Scene::from_file(path).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

/// Large blocks on huge pages (`process::HugePages`).
#[global_allocator]
static ALLOC: sphcontact::process::HugePages = sphcontact::process::HugePages;

/// Mesa's Vulkan drivers look for a display while the adapters are listed,
/// and on a machine without a desktop session (no `XDG_RUNTIME_DIR`) print
/// `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` for
/// each, although a compute solver needs no display. A private directory
/// of this process's user, made at most once, quiets them; nothing is ever
/// written there. Set before any thread starts.
#[cfg(unix)]
fn quiet_display_lookup() {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt};
    let set = std::env::var_os("XDG_RUNTIME_DIR")
        .is_some_and(|d| Path::new(&d).is_absolute() && Path::new(&d).is_dir());
    if set {
        return;
    }
    // SAFETY: getuid only reads the process's credentials; it cannot fail.
    let uid = unsafe { libc::getuid() };
    let dir = std::env::temp_dir().join(format!("sphcontact-runtime-{uid}"));
    let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    // Only a directory this user owns (another user's is left alone).
    let own = std::fs::metadata(&dir).is_ok_and(|m| m.is_dir() && m.uid() == uid);
    if own {
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

#[cfg(not(unix))]
fn quiet_display_lookup() {}

/// Output piped into a reader that stops early (`sphcontact check … | head`)
/// ends the process quietly, as it does any Unix filter, instead of
/// panicking on the closed pipe: Rust ignores SIGPIPE by default.
#[cfg(unix)]
fn quiet_closed_pipe() {
    // SAFETY: restoring the default action of a signal before any thread
    // starts; no handler is installed.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn quiet_closed_pipe() {}

fn main() -> ExitCode {
    quiet_closed_pipe();
    quiet_display_lookup();
    let cli = Cli::parse();
    // The whole command on a pool worker, freed memory kept: the solver's
    // parallel loops then start without waking the main thread each time.
    sphcontact::process::solver_process(move || command(cli))
}

fn command(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Validate(args) => validate_cmd(args),
        Command::Bench(args) => bench_cmd(args),
        Command::Ballistic(args) => ballistic_cmd(args),
        Command::Render {
            out,
            field,
            range,
            gif,
            boundary,
            no_names,
            window,
        } => {
            use sphcontact::output::render::{render, Drawing};
            let range = range.map(|r| (r[0], r[1]));
            let drawing = Drawing {
                names: (!no_names).then(|| Drawing::names_of_run(&out)).flatten(),
                boundary,
                window: window.map(|w| [w[0], w[1], w[2], w[3]]),
            };
            match render(&out, &field, range, gif, &drawing) {
                Ok(files) => {
                    println!(
                        "{} files of {field} in {}",
                        files.len(),
                        out.join("frames").display()
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Command::Doctor => {
            let d = sphcontact::doctor::diagnose();
            for l in &d.lines {
                println!("{l}");
            }
            ExitCode::from(if d.hardware { 0 } else { 1 })
        }
        Command::Check { scene } => match load(&scene) {
            Ok(s) => {
                check(&scene, &s);
                ExitCode::SUCCESS
            }
            Err(code) => code,
        },
        Command::Run {
            scene,
            out,
            backend,
            end_time,
            integrator,
            quiet,
            checkpoint_every,
            snapshot_every,
            resume,
        } => {
            let opts = RunOptions {
                out_dir: out,
                backend: backend.map(backend_of),
                end_time,
                integrator: integrator.map(integrator_of),
                quiet,
                silent: false,
                write: true,
                checkpoint_every,
                snapshot_every,
            };
            let result = match (&resume, &scene) {
                (Some(dir), _) => sphcontact::run::resume_run(dir, &opts),
                (None, Some(scene)) => match load(scene) {
                    Ok(s) => run_scene(&s, Some(scene), &opts),
                    Err(code) => return code,
                },
                (None, None) => unreachable!("clap requires a scene or --resume"),
            };
            match result {
                Ok(out) => {
                    let sm = &out.summary;
                    let snaps = if sm.snapshots > 0 {
                        format!(
                            ", {} snapshots ({:.1} MB, {:.2} s)",
                            sm.snapshots,
                            sm.snapshot_bytes as f64 / 1e6,
                            sm.snapshot_seconds
                        )
                    } else {
                        String::new()
                    };
                    eprintln!(
                        "done: {} particles, {} steps, {:.2} s wall, {:.3e} particle-steps/s{snaps}; outputs in {}",
                        sm.particles,
                        sm.steps,
                        sm.wall_seconds,
                        sm.particle_steps_per_second,
                        out.out_dir.as_deref().unwrap_or(Path::new(".")).display()
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => failed(e),
            }
        }
    }
}
