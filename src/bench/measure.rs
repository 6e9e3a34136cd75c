//! Running the benchmark: choosing the backends, measuring each size and
//! filling in the records.

use std::sync::Arc;
use std::time::Duration;

use crate::cpu::neighbours;
use crate::gpu::GpuContext;
use crate::run::{choose_backend, RunOptions};
use crate::scene::{Backend, Support};
use crate::validation::disk_scene;

use super::case::{check_particles, DiskCase};
use super::cpu_bench::CpuBench;
use super::gpu_bench::GpuBench;
use super::{BenchBackend, BenchError, BenchOptions, Record, DEFAULT_STEPS, TARGET_SECONDS};

/// The processor's model name (from /proc/cpuinfo where there is one).
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// Steps, then the wall time of each of `repeat` measurements: the first
/// of exactly `fixed` steps, or of [`DEFAULT_STEPS`] and then more until
/// it lasts [`TARGET_SECONDS`]; the others of the first's steps.
fn measure(
    fixed: Option<u64>,
    repeat: u32,
    mut time: impl FnMut(u64) -> Result<Duration, BenchError>,
) -> Result<(u64, Vec<f64>), BenchError> {
    let (steps, first) = measure_once(fixed, &mut time)?;
    let mut walls = vec![first];
    for _ in 1..repeat {
        walls.push(time(steps)?.as_secs_f64());
    }
    Ok((steps, walls))
}

/// The first measurement of [`measure`].
fn measure_once(
    fixed: Option<u64>,
    mut time: impl FnMut(u64) -> Result<Duration, BenchError>,
) -> Result<(u64, f64), BenchError> {
    if let Some(k) = fixed {
        return Ok((k, time(k)?.as_secs_f64()));
    }
    let mut steps = DEFAULT_STEPS;
    let mut wall = time(steps)?.as_secs_f64();
    if wall < TARGET_SECONDS {
        let per_step = (wall / steps as f64).max(1e-9);
        let more = (((TARGET_SECONDS - wall) / per_step).ceil() as u64).clamp(1, 1_000_000);
        wall += time(more)?.as_secs_f64();
        steps += more;
    }
    Ok((steps, wall))
}

/// The backends to run: the CPU flag and the GPU context.
fn backends(
    which: BenchBackend,
    verbose: bool,
) -> Result<(bool, Option<Arc<GpuContext>>), BenchError> {
    match which {
        BenchBackend::Cpu => Ok((true, None)),
        BenchBackend::Gpu => match crate::gpu::shared_context() {
            Ok(ctx) => Ok((false, Some(ctx))),
            Err(e) => Err(BenchError::Failed(format!(
                "bench --backend gpu: {e}; use --backend cpu (or all)"
            ))),
        },
        BenchBackend::Auto => {
            // The choice `run --backend auto` makes (it needs a scene only
            // for its own backend key, overridden here).
            let scene = disk_scene("square", 5.0);
            let opts = RunOptions {
                backend: Some(Backend::Auto),
                ..Default::default()
            };
            let choice =
                choose_backend(&scene, &opts).map_err(|e| BenchError::Failed(e.to_string()))?;
            if let (Some(w), true) = (&choice.warning, verbose) {
                eprintln!("warning: {w}");
            }
            Ok((choice.gpu.is_none(), choice.gpu))
        }
        BenchBackend::All => match crate::gpu::shared_context() {
            Ok(ctx) => Ok((true, Some(ctx))),
            Err(e) => {
                if verbose {
                    eprintln!("bench: {e}; CPU only");
                }
                Ok((true, None))
            }
        },
    }
}

/// How a record names the supports.
fn support_name(s: Support) -> &'static str {
    match s {
        Support::Fixed => "fixed",
        Support::Adaptive => "adaptive",
    }
}

/// Run the benchmark: one record per backend and size.
pub fn bench(opts: &BenchOptions) -> Result<Vec<Record>, BenchError> {
    check_options(opts)?;
    let (cpu, gpu) = backends(opts.backend, opts.verbose)?;
    let threads = rayon::current_num_threads();
    let cpu_adapter = format!("cpu: {} ({threads} threads)", cpu_name());
    let mut records = Vec::new();
    for &n in &opts.particles {
        let case = DiskCase::new(n)?
            .with_support(opts.support)
            .with_integrator(opts.integrator)
            .with_hourglass(opts.hourglass)
            .with_dispersion(opts.dispersion);
        let particles = case.particles();
        let record = |backend: &str, adapter: &str, steps: u64, walls: Vec<f64>| {
            record_of(opts, &case, n, (backend, adapter), steps, walls)
        };
        // The GPU solver is built first: a size the adapter cannot hold
        // fails in a moment, before minutes of CPU work.
        let mut gpu_bench = None;
        if let Some(ctx) = &gpu {
            if opts.verbose {
                eprintln!(
                    "bench: gpu, {particles} particles (R/Δx = {:.2})",
                    case.r_over_dx
                );
            }
            match GpuBench::new(ctx.clone(), &case) {
                Ok(b) => {
                    if opts.verbose {
                        eprintln!("bench: gpu, in contact by step {}", b.onset);
                    }
                    gpu_bench = Some(b);
                }
                // With every backend asked for, a size the adapter cannot
                // hold leaves the CPU figures standing.
                Err(BenchError::Input(e)) if opts.backend == BenchBackend::All => {
                    eprintln!("warning: GPU skipped at {particles} particles: {e}");
                }
                Err(e) => return Err(e),
            }
        }
        let mut here = Vec::new();
        if cpu {
            if opts.verbose {
                eprintln!(
                    "bench: cpu, {particles} particles (R/Δx = {:.2})",
                    case.r_over_dx
                );
            }
            let mut b = CpuBench::new(&case)?;
            if opts.verbose {
                eprintln!("bench: cpu, in contact by step {}", b.onset);
            }
            let (steps, walls) = measure(opts.steps, opts.repeat, |k| b.time_steps(k))?;
            let mut r = record("cpu", &cpu_adapter, steps, walls);
            r.threads = Some(threads);
            r.particle_steps_per_second_per_core =
                Some(r.particle_steps_per_second / threads as f64);
            r.bytes_per_particle = b.memory_bytes() as f64 / particles as f64;
            r.memory_kind = "host".into();
            r.in_contact = b.in_contact();
            here.push(r);
        }
        if let (Some(ctx), Some(mut b)) = (&gpu, gpu_bench) {
            let (steps, walls) = measure(opts.steps, opts.repeat, |k| b.time_steps(k))?;
            let mut r = record("gpu", &ctx.adapter_name(), steps, walls);
            r.bytes_per_particle = b.solver.device_bytes() as f64 / particles as f64;
            r.memory_kind = "device".into();
            r.in_contact = b.in_contact();
            if opts.stages {
                r.stages = Some(b.time_stages(0.25)?);
                r.work = Some(b.solver().step_work());
                r.step_profile = b.profile_steps()?;
            }
            here.push(r);
        }
        let mean_nb = neighbours::mean_neighbours(&case.model, &case.state.x);
        for r in &mut here {
            r.mean_neighbours = mean_nb;
        }
        records.extend(here);
    }
    Ok(records)
}

/// Every option checked before anything runs: the sizes, the steps, the
/// repeats, the hourglass coefficient, the correction's θ.
fn check_options(opts: &BenchOptions) -> Result<(), BenchError> {
    if opts.particles.is_empty() {
        return Err(BenchError::Input(
            "--particles needs at least one count".into(),
        ));
    }
    // Every size is checked before anything runs.
    for &n in &opts.particles {
        check_particles(n)?;
    }
    if opts.steps == Some(0) {
        return Err(BenchError::Input(
            "--steps must be at least 1 (got 0)".into(),
        ));
    }
    if opts.repeat == 0 {
        return Err(BenchError::Input(
            "--repeat must be at least 1 (got 0)".into(),
        ));
    }
    if !(opts.hourglass.is_finite() && opts.hourglass >= 0.0) {
        return Err(BenchError::Input(format!(
            "--hourglass must be a finite number >= 0 (got {})",
            opts.hourglass
        )));
    }
    if !(opts.dispersion.is_finite() && opts.dispersion >= 0.0) {
        return Err(BenchError::Input(format!(
            "--dispersion-correction must be a finite number >= 0 (got {})",
            opts.dispersion
        )));
    }
    Ok(())
}

/// The record of one backend's measurement on `case` (asked for `n`
/// particles): `steps` steps a run, each run's wall time in `walls`, the
/// median the record's.
fn record_of(
    opts: &BenchOptions,
    case: &DiskCase,
    n: usize,
    (backend, adapter): (&str, &str),
    steps: u64,
    walls: Vec<f64>,
) -> Record {
    let particles = case.particles();
    let rate = |wall: f64| (steps * particles as u64) as f64 / wall.max(1e-12);
    let mut sorted = walls.clone();
    sorted.sort_by(f64::total_cmp);
    let wall = sorted[sorted.len() / 2];
    Record {
        backend: backend.into(),
        adapter: adapter.into(),
        threads: None,
        integrator: opts.integrator.to_string(),
        hourglass: opts.hourglass,
        dispersion: opts.dispersion,
        support: support_name(opts.support).into(),
        requested_particles: n,
        particles,
        r_over_dx: case.r_over_dx,
        steps,
        wall_seconds: wall,
        particle_steps_per_second: rate(wall),
        rates: walls.iter().map(|&w| rate(w)).collect(),
        particle_steps_per_second_per_core: None,
        mean_neighbours: 0.0,
        bytes_per_particle: 0.0,
        memory_kind: String::new(),
        in_contact: false,
        stages: None,
        work: None,
        step_profile: None,
    }
}
