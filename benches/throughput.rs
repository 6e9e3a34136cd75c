//! Particle throughput of both backends on the two-disk impact (square
//! lattice), timed while the disks are in contact (see `sphcontact::bench`
//! for the protocol): whole steps (`cpu_step`, `gpu_step` with the midpoint
//! rule, `cpu_step_leapfrog` with the one-evaluation leapfrog), one full CPU
//! rate evaluation and each of its stages (`cpu_stage/<name>`: neighbour list
//! build, EOS, kinematics, forces, the leapfrog's forces_keeping and
//! energy_replay, contact, evaluate) and each GPU stage alone
//! (`gpu_stage/<name>`), at 1e3, 1e4 and 1e5 particles, and 1e6 where
//! `SPHCONTACT_BENCH_MAX_PARTICLES` allows it and the adapter holds it.
//!
//! `SPHCONTACT_BENCH_MAX_PARTICLES` (default 100000) caps the sizes; CI sets
//! it to 1000 and runs `cargo bench --bench throughput -- --test` (each
//! benchmark once, as a smoke test). Without a GPU adapter the GPU groups
//! print one SKIP line; with `SPHCONTACT_REQUIRE_GPU` set that is a failure,
//! as in the tests.

use std::cell::RefCell;
use std::collections::HashMap;
use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, Throughput};

use sphcontact::bench::{cpu_name, CpuBench, DiskCase, GpuBench};
use sphcontact::cpu::kinematics::StressPoint;
use sphcontact::cpu::neighbours::{self, Neighbours};
use sphcontact::cpu::sweep::{self, PairVectors};
use sphcontact::cpu::{self, contact, forces, kinematics};
use sphcontact::gpu::GpuContext;
use sphcontact::model::{Model, State};
use sphcontact::scene::Integrator;
use sphcontact::stage::STAGES;

const SIZES: [usize; 4] = [1_000, 10_000, 100_000, 1_000_000];
const DEFAULT_MAX: usize = 100_000;
/// Most repetitions of a stage in one submission.
const STAGE_CHUNK: u64 = 256;

/// The sizes under `SPHCONTACT_BENCH_MAX_PARTICLES`.
fn sizes() -> Vec<usize> {
    let max = match std::env::var("SPHCONTACT_BENCH_MAX_PARTICLES") {
        Err(_) => DEFAULT_MAX,
        Ok(v) => match v.trim().parse::<usize>() {
            Ok(m) => m,
            Err(_) => {
                eprintln!(
                    "error: SPHCONTACT_BENCH_MAX_PARTICLES must be a particle count (got '{v}')"
                );
                std::process::exit(2);
            }
        },
    };
    let s: Vec<usize> = SIZES.into_iter().filter(|&n| n <= max).collect();
    if s.is_empty() {
        eprintln!(
            "throughput: no size at or below SPHCONTACT_BENCH_MAX_PARTICLES = {max} (sizes: {SIZES:?}); nothing to run"
        );
    }
    s
}

/// The adapter, announced once; `None` with a visible skip line, or a
/// failure under `SPHCONTACT_REQUIRE_GPU`.
fn adapter() -> Option<Arc<GpuContext>> {
    match sphcontact::gpu::shared_context() {
        Ok(ctx) => {
            eprintln!("throughput: GPU adapter {}", ctx.adapter_name());
            Some(ctx)
        }
        Err(e) => {
            if std::env::var_os("SPHCONTACT_REQUIRE_GPU").is_some() {
                panic!("SPHCONTACT_REQUIRE_GPU is set but there is no GPU adapter: {e}");
            }
            eprintln!(
                "SKIP: no GPU adapter ({e}); the gpu_step and gpu_stage benchmarks did not run"
            );
            None
        }
    }
}

/// Few samples of flat iterations: a step at 1e5 particles takes a large
/// fraction of a second on a software adapter.
fn configure(group: &mut BenchmarkGroup<'_, WallTime>) {
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
}

fn case(n: usize) -> DiskCase {
    DiskCase::new(n).unwrap_or_else(|e| panic!("the disk case at {n} particles: {e}"))
}

/// The CPU bench at `n`, built on first use only, so that a filtered run
/// builds nothing it does not time.
fn cpu_at(benches: &mut HashMap<usize, CpuBench>, n: usize) -> &mut CpuBench {
    benches
        .entry(n)
        .or_insert_with(|| CpuBench::new(&case(n)).unwrap_or_else(|e| panic!("{e}")))
}

/// The GPU bench at `n`, built on first use only and shared by the step
/// and stage groups.
fn gpu_at<'a>(
    benches: &'a mut HashMap<usize, GpuBench>,
    ctx: &Arc<GpuContext>,
    n: usize,
) -> &'a mut GpuBench {
    benches
        .entry(n)
        .or_insert_with(|| GpuBench::new(ctx.clone(), &case(n)).unwrap_or_else(|e| panic!("{e}")))
}

fn cpu_benches(c: &mut Criterion, sizes: &[usize]) {
    eprintln!(
        "throughput: CPU {} ({} threads)",
        cpu_name(),
        rayon::current_num_threads()
    );
    let mut benches: HashMap<usize, CpuBench> = HashMap::new();

    let mut group = c.benchmark_group("cpu_step");
    configure(&mut group);
    for &n in sizes {
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            let bench = cpu_at(&mut benches, n);
            b.iter_custom(|iters| bench.time_steps(iters).unwrap_or_else(|e| panic!("{e}")));
        });
    }
    group.finish();

    // The whole step with the two-evaluation midpoint rule (its own
    // solvers, stepped into contact by the midpoint rule; the default is
    // the leapfrog).
    let mut group = c.benchmark_group("cpu_step_midpoint");
    configure(&mut group);
    for &n in sizes {
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            let mut bench = CpuBench::new(&case(n).with_integrator(Integrator::Midpoint))
                .unwrap_or_else(|e| panic!("{e}"));
            b.iter_custom(|iters| bench.time_steps(iters).unwrap_or_else(|e| panic!("{e}")));
        });
    }
    group.finish();

    // The CPU stages one evaluation runs, each alone on the contact-phase
    // state with its inputs made beforehand; `evaluate` is all of them on
    // lists that are still valid, as in a step that does not rebuild them,
    // and `neighbours` is one rebuild.
    type Stage = fn(&Model, &State, &Inputs);
    let stages: [(&str, Stage); 8] = [
        ("neighbours", |m, s, _| {
            black_box(neighbours::find_with_skin(m, s.frame(), skin(m)));
        }),
        ("eos", |m, s, _| {
            black_box(cpu::eos_and_stress(m, s));
        }),
        ("kinematics", |m, s, i| {
            black_box(sweep::kinematics(m, s, &i.nb));
        }),
        ("forces", |m, s, i| {
            black_box(sweep::momentum_energy(m, s, &i.nb, &i.k, &i.pts));
        }),
        // The leapfrog's momentum pass (pair vectors kept, no energy
        // sums) and its energy replay from them.
        ("forces_keeping", |m, s, i| {
            let mut kept = i.scratch.borrow_mut();
            black_box(sweep::momentum_keeping(
                m, s, &i.nb, &i.k, &i.pts, &mut kept,
            ));
        }),
        ("energy_replay", |m, s, i| {
            black_box(sweep::energy_replay(m, &i.nb, &i.kept, &s.v));
        }),
        ("contact", |m, s, i| {
            let k = &i.k;
            let bd = forces::boundary_of(m, &s.x, &i.nb, k);
            black_box(contact::penalty(m, s, &i.nb, &bd));
        }),
        ("evaluate", |m, s, i| {
            black_box(cpu::evaluate_with(m, s, &i.nb));
        }),
    ];
    let mut inputs: HashMap<usize, Inputs> = HashMap::new();
    for (name, run) in stages {
        let mut group = c.benchmark_group(format!("cpu_stage/{name}"));
        configure(&mut group);
        for &n in sizes {
            group.throughput(Throughput::Elements(n as u64));
            group.bench_function(BenchmarkId::from_parameter(n), |b| {
                let bench = cpu_at(&mut benches, n);
                let (model, state) = (bench.model(), bench.state());
                let input = inputs.entry(n).or_insert_with(|| Inputs::new(model, state));
                b.iter(|| run(model, state, input));
            });
        }
        group.finish();
    }
}

/// The skin the CPU solver builds its lists with.
fn skin(model: &Model) -> f64 {
    cpu::SKIN_FRACTION * 2.0 * model.h.iter().cloned().fold(0.0, f64::max)
}

/// What the CPU stages take from the ones before them.
struct Inputs {
    nb: Neighbours,
    pts: Vec<StressPoint>,
    k: kinematics::Kinematics,
    /// The pair vectors the leapfrog's momentum pass keeps at this state.
    kept: Vec<PairVectors>,
    /// The buffer a timed keeping pass writes into (kept between runs,
    /// as the solver keeps its own).
    scratch: RefCell<Vec<PairVectors>>,
}

impl Inputs {
    fn new(model: &Model, state: &State) -> Self {
        let nb = neighbours::find_with_skin(model, state.frame(), skin(model));
        let k = sweep::kinematics(model, state, &nb);
        let pts = cpu::eos_and_stress(model, state);
        let mut kept = Vec::new();
        sweep::momentum_keeping(model, state, &nb, &k, &pts, &mut kept);
        Inputs {
            pts,
            k,
            nb,
            scratch: RefCell::new(kept.clone()),
            kept,
        }
    }
}

fn gpu_benches(c: &mut Criterion, sizes: &[usize], ctx: Arc<GpuContext>) {
    let sizes: Vec<usize> = sizes
        .iter()
        .copied()
        .filter(|&n| {
            let ok = sphcontact::gpu::fits(&ctx, n);
            if !ok {
                eprintln!("SKIP: gpu at {n} particles: larger than this adapter's buffers allow");
            }
            ok
        })
        .collect();
    let mut benches: HashMap<usize, GpuBench> = HashMap::new();

    let mut group = c.benchmark_group("gpu_step");
    configure(&mut group);
    for &n in &sizes {
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            let bench = gpu_at(&mut benches, &ctx, n);
            b.iter_custom(|iters| bench.time_steps(iters).unwrap_or_else(|e| panic!("{e}")));
        });
    }
    group.finish();

    // (The disk scene has contact, so every stage runs.)
    for stage in STAGES {
        let mut group = c.benchmark_group(format!("gpu_stage/{}", stage.name));
        configure(&mut group);
        for &n in &sizes {
            group.throughput(Throughput::Elements(n as u64));
            group.bench_function(BenchmarkId::from_parameter(n), |b| {
                let solver = gpu_at(&mut benches, &ctx, n).solver();
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    let mut left = iters;
                    while left > 0 {
                        let reps = left.min(STAGE_CHUNK);
                        total += solver
                            .time_stage(stage.name, reps as u32)
                            .unwrap_or_else(|e| panic!("{e}"));
                        left -= reps;
                    }
                    total
                });
            });
        }
        group.finish();
    }
}

/// The command line's allocator, so that the figures match `sphcontact bench`.
#[global_allocator]
static ALLOC: sphcontact::process::HugePages = sphcontact::process::HugePages;

fn main() {
    // The command line's set-up, so the figures match `sphcontact bench`
    // (docs/performance.md).
    sphcontact::process::solver_process(benches);
}

fn benches() {
    let sizes = sizes();
    let ctx = adapter();
    let mut c = Criterion::default().configure_from_args();
    cpu_benches(&mut c, &sizes);
    if let Some(ctx) = ctx {
        gpu_benches(&mut c, &sizes, ctx);
    }
    c.final_summary();
}
