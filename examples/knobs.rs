//! The study behind the defaults of docs/method.md: the 1-D rebound and the
//! disks' contact force under one knob at a time.
//!
//!     cargo run --release --example knobs -- bars N ALPHA BETA
//!     cargo run --release --example knobs -- disks square|polar R_OVER_DX ALPHA BETA
//!
//! Environment: KNOB_H (smoothing ratio), KNOB_CFL, KNOB_NOCORR (no gradient
//! correction), KNOB_NORECON (plain Monaghan viscosity), KNOB_FORM
//! (`monaghan` or `riemann`), KNOB_RECON_SURFACES (1: the reconstructed
//! jump at surfaces too, 0: plain there), KNOB_GPU (GPU
//! backend; default CPU).

use sphcontact::scene::{ArtificialViscosity, Backend, Correction, ViscosityForm};
use sphcontact::validation::{
    bar_observables_of, bar_scene, disk_observables_of, disk_scene, Observed, BARS,
};
use sphcontact::Scene;

fn arg<T: std::str::FromStr>(args: &[String], k: usize) -> Result<T, String> {
    args.get(k)
        .and_then(|a| a.parse().ok())
        .ok_or_else(|| format!("argument {k} missing or malformed"))
}

/// The viscosity and the environment's knobs applied to a scene.
fn apply(scene: &mut Scene, alpha: f64, beta: f64) -> Result<(), String> {
    let var = |k: &str| std::env::var(k).ok();
    let defaults = ArtificialViscosity::default();
    scene.artificial_viscosity = Some(ArtificialViscosity {
        alpha,
        beta,
        reconstruct: var("KNOB_NORECON").is_none(),
        form: match var("KNOB_FORM").as_deref() {
            None => defaults.form,
            Some("monaghan") => ViscosityForm::Monaghan,
            Some("riemann") => ViscosityForm::Riemann,
            Some(_) => return Err("KNOB_FORM: monaghan or riemann".into()),
        },
        reconstruct_surfaces: match var("KNOB_RECON_SURFACES").as_deref() {
            None => defaults.reconstruct_surfaces,
            Some(v) => v == "1",
        },
        ..defaults
    });
    if let Some(h) = var("KNOB_H") {
        scene.simulation.smoothing_ratio = h.parse().map_err(|_| "KNOB_H")?;
    }
    if let Some(c) = var("KNOB_CFL") {
        scene.simulation.cfl = c.parse().map_err(|_| "KNOB_CFL")?;
    }
    if var("KNOB_NOCORR").is_some() {
        scene.simulation.correction = Correction::None;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let backend = Some(if std::env::var_os("KNOB_GPU").is_some() {
        Backend::Gpu
    } else {
        Backend::Cpu
    });
    let (label, run, obs) = match args.first().map(String::as_str) {
        Some("bars") => {
            let n: usize = arg(&args, 1)?;
            let mut scene = bar_scene(BARS, n, 1e-9);
            apply(&mut scene, arg(&args, 2)?, arg(&args, 3)?)?;
            let (run, obs) = bar_observables_of(&scene, backend)?;
            (format!("bars N = {n}"), run, obs)
        }
        Some("disks") => {
            let lattice: String = arg(&args, 1)?;
            let r: f64 = arg(&args, 2)?;
            let mut scene = disk_scene(&lattice, r);
            scene.output.history_interval = Some(2e-9);
            apply(&mut scene, arg(&args, 3)?, arg(&args, 4)?)?;
            let (run, obs) = disk_observables_of(&scene, backend)?;
            (format!("disks {lattice} R/dx = {r}"), run, obs)
        }
        _ => {
            return Err("usage: knobs bars N ALPHA BETA | knobs disks LATTICE R ALPHA BETA".into())
        }
    };
    let parts: Vec<String> = obs
        .iter()
        .map(|o: &Observed| {
            format!(
                "{} {:.6e} ({:+.2} %)",
                o.name,
                o.measured,
                100.0 * o.error()
            )
        })
        .collect();
    println!(
        "{label}: {}; {} particles, {:.1} s wall",
        parts.join(", "),
        run.out.summary.particles,
        run.out.summary.wall_seconds
    );
    Ok(())
}
