//! `sphcontact validate`: the paper's cases scored against their exact
//! answers, or the speed-against-error sweep.

use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

use sphcontact::scene::Backend;

use crate::{backend_of, failed, integrator_of, BackendArg, IntegratorArg};

#[derive(Args)]
pub(crate) struct ValidateArgs {
    /// Cases to run: bars, steel_aluminium, disks (default: all).
    cases: Vec<String>,
    /// Which backend runs the cases (default: the scenes' auto).
    #[arg(long, value_enum)]
    backend: Option<BackendArg>,
    /// Time integration of the cases (default: the scenes' leapfrog).
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// The dispersion correction's theta in every scene (docs/method.md
    /// §4; default: the scenes' 0, off), in [0, 1.5].
    #[arg(long)]
    dispersion_correction: Option<f64>,
    /// The artificial viscosity's alpha in every scene (default: the
    /// scenes' 0.75), >= 0.
    #[arg(long)]
    alpha: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "out/validate")]
    out: PathBuf,
    /// Particles per bar (cases bars, steel_aluminium).
    #[arg(long, default_value_t = 100)]
    bar_particles: usize,
    /// Disk radius over particle spacing (case disks).
    #[arg(long, default_value_t = 50.0)]
    disk_resolution: f64,
    /// Instead of the cases: the speed-against-error sweep over
    /// resolution, on every available backend (or the one --backend names).
    #[arg(long)]
    sweep: bool,
    /// Largest R/Δx of the sweep's disks.
    #[arg(long, default_value_t = 50.0)]
    sweep_max_disk_resolution: f64,
}

pub(crate) fn validate_cmd(args: ValidateArgs) -> ExitCode {
    use sphcontact::validation as v;
    let ValidateArgs {
        cases,
        backend,
        integrator,
        dispersion_correction,
        alpha,
        out,
        bar_particles,
        disk_resolution,
        sweep,
        sweep_max_disk_resolution: sweep_max,
    } = args;
    let bad = |msg: String| {
        eprintln!("error: {msg}");
        ExitCode::from(2)
    };
    if bar_particles < 10 {
        return bad(format!(
            "--bar-particles must be at least 10 (got {bar_particles})"
        ));
    }
    if !(disk_resolution.is_finite() && disk_resolution >= 5.0) {
        return bad(format!(
            "--disk-resolution must be at least 5 (got {disk_resolution})"
        ));
    }
    if let Some(t) = dispersion_correction {
        if let Err(e) = sphcontact::scene::validate::dispersion_correction_in_range(t) {
            return bad(format!("--dispersion-correction {e}"));
        }
    }
    if let Some(a) = alpha {
        if !(a.is_finite() && a >= 0.0) {
            return bad(format!("--alpha must be >= 0 (got {a})"));
        }
    }
    let tuning = v::Tuning {
        dispersion_correction,
        alpha,
    };
    if !tuning.label().is_empty() {
        eprintln!("validate: every scene with {}", tuning.label());
    }
    let mut chosen = Vec::new();
    for c in &cases {
        match v::Case::parse(c) {
            Some(k) => chosen.push(k),
            None => {
                return bad(format!(
                    "unknown case '{c}' (known: bars, steel_aluminium, disks)"
                ))
            }
        }
    }
    if chosen.is_empty() {
        chosen = v::Case::ALL.to_vec();
    }
    if sweep {
        let sw = SweepRequest {
            backend,
            integrator,
            sweep_max,
        };
        return sweep_cmd(sw, tuning, out);
    }
    let opts = v::Options {
        cases: chosen,
        backend: backend.map(backend_of),
        integrator: integrator.map(integrator_of),
        tuning,
        out: out.clone(),
        resolution: v::Resolution {
            bar_particles,
            disk_r_over_dx: disk_resolution,
        },
        verbose: true,
    };
    match v::validate(&opts) {
        Ok(rep) => {
            print!("{}", rep.table());
            for w in &rep.warnings {
                eprintln!("warning: {w}");
            }
            let failed = rep.records.iter().filter(|r| !r.pass).count();
            eprintln!(
                "{} observables, {} outside their target; figures, CSV and validation.json in {}",
                rep.records.len(),
                failed,
                out.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => failed(e),
    }
}

/// What `validate --sweep` was asked for.
struct SweepRequest {
    backend: Option<BackendArg>,
    integrator: Option<IntegratorArg>,
    sweep_max: f64,
}

/// `validate --sweep`: the speed-against-error sweep on the backends asked
/// for (or every one available), its table printed.
fn sweep_cmd(req: SweepRequest, tuning: sphcontact::validation::Tuning, out: PathBuf) -> ExitCode {
    use sphcontact::validation as v;
    let SweepRequest {
        backend,
        integrator,
        sweep_max,
    } = req;
    let backends = match backend.map(backend_of) {
        Some(Backend::Auto) | None => {
            let mut b = vec![Backend::Cpu];
            match sphcontact::gpu::shared_context() {
                Ok(ctx) => {
                    eprintln!("sweep: GPU adapter {}", ctx.adapter_name());
                    b.push(Backend::Gpu);
                }
                Err(e) => eprintln!("sweep: no GPU adapter ({e}); CPU only"),
            }
            b
        }
        Some(b) => vec![b],
    };
    let mut opts = v::SweepOptions::new(backends, out.clone());
    opts.disk_r_over_dx.retain(|&r| r <= sweep_max);
    if let Some(i) = integrator {
        opts.integrator = integrator_of(i);
    }
    opts.tuning = tuning;
    opts.verbose = true;
    match v::sweep(&opts) {
        Ok((points, warnings)) => {
            println!("| case | lattice | backend | resolution | particles | wall (s) | observable | relative error |");
            println!("|---|---|---|---|---|---|---|---|");
            for p in &points {
                println!(
                    "| {} | {} | {} | {} | {} | {:.2} | {} | {:+.3} % |",
                    p.case,
                    p.lattice,
                    p.backend,
                    p.resolution,
                    p.particles,
                    p.wall_seconds,
                    p.observable,
                    100.0 * p.relative_error
                );
            }
            for w in warnings {
                eprintln!("warning: {w}");
            }
            eprintln!("sweep written to {}", out.display());
            ExitCode::SUCCESS
        }
        Err(e) => failed(e),
    }
}
