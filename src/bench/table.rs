//! The Markdown tables `bench` prints: the records, the GPU/CPU ratios and
//! the GPU stages.

use crate::gpu::profile::StepProfile;
use crate::gpu::work::StepWork;

use super::Record;

/// The work of a GPU step as a table: one row a neighbour walk.
fn work_table(w: &StepWork) -> String {
    let mut s = format!(
        "A step: {} dispatches (the reorder every {} steps aside), {} neighbour walks over every \
         particle and {} over the boundary particles, {:.1} device bytes a particle.\n\n",
        w.dispatches,
        crate::gpu::REORDER_EVERY,
        w.walks,
        w.contact_walks,
        w.device_bytes_per_particle
    );
    s.push_str(&table_head(&[
        "walk",
        "per step",
        "walking particles",
        "candidates a particle",
        &format!("trips of a {}-thread group", crate::gpu::work::WARP),
        "lanes used",
    ]));
    for k in &w.per_walk {
        s.push_str(&format!(
            "| {} | {} | {} | {:.1} | {:.1} | {:.0} % |\n",
            k.name,
            k.per_step,
            k.walkers,
            k.candidates,
            k.group_trips,
            100.0 * k.lane_use
        ));
    }
    s.push('\n');
    s
}

/// A Markdown table's header row and the rule under it.
fn table_head(columns: &[&str]) -> String {
    format!(
        "| {} |\n{}|\n",
        columns.join(" | "),
        "|---".repeat(columns.len())
    )
}

/// `1.23e6`-style number for the table.
fn sci(x: f64) -> String {
    format!("{x:.3e}")
}

/// The rate, and with repeated measurements their range: `median (min–max)`.
fn rate_cell(r: &Record) -> String {
    let (lo, hi) = r
        .rates
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if r.rates.len() > 1 {
        format!(
            "{} ({}–{})",
            sci(r.particle_steps_per_second),
            sci(lo),
            sci(hi)
        )
    } else {
        sci(r.particle_steps_per_second)
    }
}

/// The integrator, the hourglass control and the dispersion correction
/// where they are on and the supports where they are fixed (not the
/// default).
fn integrator_cell(r: &Record) -> String {
    let mut s = r.integrator.clone();
    if r.hourglass > 0.0 {
        s += &format!(", hourglass {}", r.hourglass);
    }
    if r.dispersion > 0.0 {
        s += &format!(", dispersion correction {}", r.dispersion);
    }
    if r.support != "adaptive" {
        s += &format!(", {} supports", r.support);
    }
    s
}

/// The records as a Markdown table, the GPU/CPU ratios and, where timed,
/// the GPU stages.
pub fn table(records: &[Record]) -> String {
    let mut s = String::new();
    s.push_str(&table_head(&[
        "backend",
        "adapter",
        "integrator",
        "particles",
        "R/Δx",
        "mean neighbours",
        "steps",
        "wall (s)",
        "particle-steps/s",
        "per core",
        "memory/particle",
        "in contact",
    ]));
    for r in records {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {:.1} | {} | {:.3} | {} | {} | {:.0} B ({}) | {} |\n",
            r.backend,
            r.adapter,
            integrator_cell(r),
            r.particles,
            r.r_over_dx,
            r.mean_neighbours,
            r.steps,
            r.wall_seconds,
            rate_cell(r),
            r.particle_steps_per_second_per_core.map_or("–".into(), sci),
            r.bytes_per_particle,
            r.memory_kind,
            if r.in_contact { "yes" } else { "no" },
        ));
    }
    let mut ratios = String::new();
    for g in records.iter().filter(|r| r.backend == "gpu") {
        if let Some(c) = records
            .iter()
            .find(|c| c.backend == "cpu" && c.particles == g.particles)
        {
            ratios.push_str(&format!(
                "GPU/CPU throughput at {} particles: {:.3}\n",
                g.particles,
                g.particle_steps_per_second / c.particle_steps_per_second
            ));
        }
    }
    if !ratios.is_empty() {
        s.push('\n');
        s.push_str(&ratios);
    }
    for g in records.iter().filter(|r| r.stages.is_some()) {
        let stages = g.stages.as_deref().unwrap_or_default();
        let step = g.wall_seconds / g.steps as f64;
        let sum: f64 = stages.iter().map(|t| t.seconds_per_step).sum();
        s.push_str(&format!(
            "\nGPU stages alone at {} particles ({}): step {:.3} ms measured, {:.3} ms as the sum of its stages\n\n",
            g.particles,
            g.adapter,
            1e3 * step,
            1e3 * sum
        ));
        if let Some(w) = &g.work {
            s.push_str(&work_table(w));
        }
        s.push_str(&table_head(&[
            "stage",
            "per call (ms)",
            "calls per step",
            "per step (ms)",
            "share of the sum",
        ]));
        for t in stages {
            s.push_str(&format!(
                "| {} | {:.4} | {} | {:.4} | {:.1} % |\n",
                t.name,
                1e3 * t.seconds_per_call,
                t.calls_per_step,
                1e3 * t.seconds_per_step,
                100.0 * t.seconds_per_step / sum.max(1e-300)
            ));
        }
        if let Some(p) = &g.step_profile {
            s.push_str(&profile_table(p, step));
        }
    }
    s
}

/// Each dispatch's time inside real steps, as a table.
fn profile_table(p: &StepProfile, wall_step: f64) -> String {
    let mut s = format!(
        "\nInside {} real steps (timestamp queries): {:.3} ms of device time a step \
         ({:.3} ms wall a step in the timed batches)\n\n",
        p.steps,
        1e3 * p.seconds_per_step,
        1e3 * wall_step
    );
    s.push_str(&table_head(&[
        "stage",
        "dispatch",
        "calls per step",
        "per step (ms)",
        "share of the step",
    ]));
    for d in &p.dispatches {
        s.push_str(&format!(
            "| {} | {} | {:.4} | {:.4} | {:.1} % |\n",
            d.stage,
            d.kernel,
            d.calls_per_step,
            1e3 * d.seconds_per_step,
            100.0 * d.seconds_per_step / p.seconds_per_step.max(1e-300)
        ));
    }
    s
}
