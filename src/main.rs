//! The `sphcontact` command line (SCENES.md, "Command line").

use clap::{Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use sphcontact::model::Model;
use sphcontact::physics::material::series;
use sphcontact::run::{history_times, output_dir, run_scene, RunOptions};
use sphcontact::scene::{validate::cfl_step_at_start, Backend, Scene};

#[derive(Parser)]
#[command(
    name = "sphcontact",
    version,
    about = "SPH for impacts between elastic and elasto-plastic solids, with the Seo & Min penalty contact"
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

#[derive(Subcommand)]
enum Command {
    /// Run a scene and write history.csv and summary.json.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Output directory (default: the scene's output.dir, else out/<scene stem>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Which backend runs the scene (overrides the scene's simulation.backend).
        #[arg(long, value_enum)]
        backend: Option<BackendArg>,
        /// Stop at this simulated time, s (overrides simulation.end_time).
        #[arg(long, allow_negative_numbers = true)]
        end_time: Option<f64>,
        /// Occasional plain progress lines instead of a progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Parse and validate a scene, print the derived set-up, run nothing.
    Check {
        /// The scene file (TOML).
        scene: PathBuf,
    },
}

fn load(path: &Path) -> Result<Scene, ExitCode> {
    Scene::from_file(path).map_err(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}

fn check(path: &Path, scene: &Scene) {
    let (model, _) = Model::new(scene);
    let sim = &scene.simulation;
    println!("scene       {}", path.display());
    if let Some(t) = &scene.title {
        println!("title       {t}");
    }
    println!(
        "set-up      {}-D, interaction {:?}, correction {:?}, smoothing ratio {}",
        sim.dimension, sim.interaction, sim.correction, sim.smoothing_ratio
    );
    let av = scene.viscosity();
    println!("viscosity   alpha {}, beta {}", av.alpha, av.beta);
    println!("particles   {}", model.len());
    for b in &model.bodies {
        let m = &b.material;
        let mass: f64 = b.range.clone().map(|i| model.mass[i]).sum();
        println!(
            "body        {:<12} {:>8} particles, spacing {:.4e} m, h {:.4e} m, mass {:.6e}, velocity ({}, {}){}",
            b.name,
            b.range.len(),
            b.spacing,
            model.h[b.range.start],
            mass,
            b.velocity0.x,
            b.velocity0.y,
            if b.rigid { ", rigid" } else { "" }
        );
        println!(
            "            rho0 {} kg/m3, K {:.4e} Pa, G {:.4e} Pa, E {:.4e} Pa, nu {:.4}, c_L {:.2} m/s, Z {:.4e} Pa s/m{}",
            m.rho0,
            m.k,
            m.g,
            m.e,
            m.nu,
            m.c_l,
            m.z,
            if m.y0.is_finite() { format!(", Y0 {:.4e} Pa", m.y0) } else { String::new() }
        );
    }
    if model.contact {
        let inf = |b: &sphcontact::model::BodyInfo, v: f64| if b.rigid { f64::INFINITY } else { v };
        for (i, a) in model.bodies.iter().enumerate() {
            for b in &model.bodies[i + 1..] {
                let z = series(inf(a, a.material.z), inf(b, b.material.z));
                let e = series(inf(a, a.material.e), inf(b, b.material.e));
                let spring = format!(
                    "E* {:.4e} Pa, spring E*/h0 {:.4e} Pa/m",
                    e,
                    e / (0.5 * (a.spacing + b.spacing))
                );
                println!(
                    "contact     {} | {}: Z* {:.4e} Pa s/m, {}",
                    a.name, b.name, z, spring
                );
            }
        }
    }
    let placed = sphcontact::scene::place_bodies(scene);
    let dt = cfl_step_at_start(scene, &placed);
    let used = sim.dt.unwrap_or(dt);
    println!(
        "time        end {:.4e} s, step {:.4e} s ({}), about {} steps",
        sim.end_time,
        used,
        if sim.dt.is_some() {
            "fixed"
        } else {
            "CFL at t = 0"
        },
        (sim.end_time / used).ceil()
    );
    println!(
        "output      {} ({} history rows, {} probes)",
        output_dir(scene, Some(path), &RunOptions::default()).display(),
        history_times(sim.end_time, scene.history_interval()).len(),
        scene.probes.len()
    );
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
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
            quiet,
        } => {
            let s = match load(&scene) {
                Ok(s) => s,
                Err(code) => return code,
            };
            let opts = RunOptions {
                out_dir: out,
                backend: backend.map(|b| match b {
                    BackendArg::Auto => Backend::Auto,
                    BackendArg::Gpu => Backend::Gpu,
                    BackendArg::Cpu => Backend::Cpu,
                }),
                end_time,
                quiet,
                silent: false,
                write: true,
            };
            match run_scene(&s, Some(&scene), &opts) {
                Ok(out) => {
                    let sm = &out.summary;
                    eprintln!(
                        "done: {} particles, {} steps, {:.2} s wall, {:.3e} particle-steps/s; outputs in {}",
                        sm.particles,
                        sm.steps,
                        sm.wall_seconds,
                        sm.particle_steps_per_second,
                        out.out_dir.as_deref().unwrap_or(Path::new(".")).display()
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(e.exit_code() as u8)
                }
            }
        }
    }
}
