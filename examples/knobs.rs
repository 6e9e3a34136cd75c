//! Study of the knobs that set the 1-D rebound and the disks' contact force.
//!
//!     cargo run --release --example knobs -- bars N ALPHA BETA
//!     cargo run --release --example knobs -- disks LATTICE R_OVER_DX ALPHA BETA

use sphcontact::output::contact_window;
use sphcontact::run::{run_scene, RunOptions};
use sphcontact::Scene;

fn knobs(scene: &mut Scene) {
    if let Ok(h) = std::env::var("KNOB_H") {
        scene.simulation.smoothing_ratio = h.parse().unwrap();
    }
    if let Ok(c) = std::env::var("KNOB_CFL") {
        scene.simulation.cfl = c.parse().unwrap();
    }
    if std::env::var("KNOB_NOCORR").is_ok() {
        scene.simulation.correction = sphcontact::scene::Correction::None;
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let opts = RunOptions {
        silent: true,
        backend: std::env::var("KNOB_GPU")
            .ok()
            .map(|_| sphcontact::scene::Backend::Gpu)
            .or(Some(sphcontact::scene::Backend::Cpu)),
        ..Default::default()
    };
    match args[0].as_str() {
        "bars" => {
            let n: f64 = args[1].parse()?;
            let a: f64 = args[2].parse()?;
            let b: f64 = args[3].parse()?;
            let mut scene = Scene::from_file(std::path::Path::new("scenes/paper/bars_steel.toml"))?;
            for body in &mut scene.bodies {
                body.spacing = 0.005 / n;
            }
            scene.artificial_viscosity = Some(sphcontact::scene::ArtificialViscosity {
                alpha: a,
                beta: b,
                reconstruct: std::env::var("KNOB_NORECON").is_err(),
            });
            scene.output.history_interval = Some(1e-9);
            knobs(&mut scene);
            let out = run_scene(&scene, None, &opts)?;
            let t = &out.history.times;
            let p = out.history.column("contact_pressure").unwrap();
            let (_, ts) = contact_window(t, &p);
            let k = t.iter().position(|&x| x > 0.5 * ts).unwrap_or(0);
            let v = out.history.column("velocity_left").unwrap();
            println!(
                "bars N={n} a={a} b={b}: plateau {:.4} MPa sep {:.4} us rebound {:.4} wall {:.2}",
                p[k] / 1e6,
                ts * 1e6,
                -v.last().unwrap() / 10.0,
                out.summary.wall_seconds
            );
        }
        "disks" => {
            let lattice = &args[1];
            let r: f64 = args[2].parse()?;
            let a: f64 = args[3].parse()?;
            let b: f64 = args[4].parse()?;
            let mut scene = Scene::from_file(std::path::Path::new(&format!(
                "scenes/paper/disks_{lattice}.toml"
            )))?;
            for body in &mut scene.bodies {
                body.spacing = 0.005 / r;
            }
            scene.artificial_viscosity = Some(sphcontact::scene::ArtificialViscosity {
                alpha: a,
                beta: b,
                reconstruct: std::env::var("KNOB_NORECON").is_err(),
            });
            scene.output.history_interval = Some(2e-9);
            knobs(&mut scene);
            let out = run_scene(&scene, None, &opts)?;
            let t = &out.history.times;
            let f = out.history.column("contact_force").unwrap();
            let (t0, t1) = contact_window(t, &f);
            let peak = f.iter().cloned().fold(0.0, f64::max);
            let vl = out.history.column("velocity_left").unwrap();
            println!(
                "disks {lattice} R/dx={r} a={a} b={b}: peak {:.4} MN/m ({:+.2} % vs 1.198) contact {:.3} us ({:+.2} % vs 8.39) restitution {:.4} particles {} wall {:.1}",
                peak / 1e6,
                100.0 * (peak / 1.198e6 - 1.0),
                (t1 - t0) * 1e6,
                100.0 * ((t1 - t0) / 8.39e-6 - 1.0),
                -vl.last().unwrap() / 5.0,
                out.summary.particles,
                out.summary.wall_seconds
            );
        }
        _ => return Err("bars|disks".into()),
    }
    Ok(())
}
