//! Run every scene of `scenes/paper/` on the CPU and print the table of the
//! README: exact answer, this solver's figure, error and wall time.
//!
//!     cargo run --release --example paper_table

use sphcontact::output::contact_window;
use sphcontact::physics::exact::{
    bar_impact, hertz_c_inertia, hertz_disks, BarImpact, HERTZ_C_JOHNSON,
};
use sphcontact::physics::material::MaterialModel;
use sphcontact::run::{run_scene, RunOptions, RunOutput};
use sphcontact::Scene;

fn run(path: &str, fine: bool) -> Result<(Scene, RunOutput), Box<dyn std::error::Error>> {
    let mut scene = Scene::from_file(std::path::Path::new(path))?;
    if fine {
        scene.output.history_interval = Some(1e-9);
    }
    let opts = RunOptions {
        silent: true,
        ..Default::default()
    };
    let out = run_scene(&scene, None, &opts)?;
    Ok((scene, out))
}

fn row(case: &str, what: &str, exact: &str, measured: f64, err: Option<f64>, wall: f64) {
    let e = err.map_or("—".to_string(), |e| format!("{:+.2} %", 100.0 * e));
    println!("| {case} | {what} | {exact} | {measured:.4} | {e} | {wall:.1} s |");
}

/// The plateau contact pressure (read at half the contact time) and the
/// separation time of a bar case, against the exact answer.
fn bar_rows(case: &str, stress: &str, out: &RunOutput, ex: &BarImpact) {
    let t = &out.history.times;
    let w = out.summary.wall_seconds;
    let p = out.history.column("contact_pressure").unwrap_or_default();
    let (_, ts) = contact_window(t, &p);
    let k = t.iter().position(|&x| x > 0.5 * ts).unwrap_or(0);
    let s = -ex.contact_stress;
    let exact = format!("{:.1}", s / 1e6);
    row(case, stress, &exact, p[k] / 1e6, Some(p[k] / s - 1.0), w);
    let exact = format!("{:.4}", ex.separation_time * 1e6);
    let err = Some(ts / ex.separation_time - 1.0);
    row(case, "separation (µs)", &exact, ts * 1e6, err, w);
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("| case | observable | exact | measured | error | wall |");
    println!("|---|---|---|---|---|---|");
    for (mode, suffix) in [("penalty", ""), ("kernel", "_kernel")] {
        // Case 1.
        let (scene, out) = run(&format!("scenes/paper/bars_steel{suffix}.toml"), true)?;
        let steel = MaterialModel::new(&scene.materials["steel"]);
        let ex = bar_impact(&steel, 0.005, 10.0, &steel, 0.005, -10.0);
        let w = out.summary.wall_seconds;
        let case = format!("steel bars, {mode}");
        let vl = out.history.column("velocity_left").unwrap_or_default();
        if mode == "penalty" {
            bar_rows(&case, "contact pressure (MPa)", &out, &ex);
        }
        let v = *vl.last().unwrap_or(&f64::NAN);
        row(
            &case,
            "left bar mean velocity at 4 µs (m/s)",
            "−10",
            v,
            Some(v / -10.0 - 1.0),
            w,
        );

        // Case 2.
        let (scene, out) = run(
            &format!("scenes/paper/bars_steel_aluminium{suffix}.toml"),
            true,
        )?;
        let al = MaterialModel::new(&scene.materials["aluminium"]);
        let ex = bar_impact(&steel, 0.005, 10.0, &al, 0.005, -10.0);
        let w = out.summary.wall_seconds;
        let case = format!("steel/aluminium, {mode}");
        if mode == "penalty" {
            bar_rows(&case, "interface stress (MPa)", &out, &ex);
        }
        let va = *out
            .history
            .column("velocity_right")
            .unwrap_or_default()
            .last()
            .unwrap_or(&f64::NAN);
        row(
            &case,
            "aluminium velocity at 4 µs (m/s)",
            &format!("{:.2}", ex.final_velocity_2),
            va,
            Some(va / ex.final_velocity_2 - 1.0),
            w,
        );

        // Case 3.
        let soft = hertz_disks(&steel, 0.005, 10.0, HERTZ_C_JOHNSON);
        let stiff = hertz_disks(&steel, 0.005, 10.0, hertz_c_inertia(steel.nu));
        let bracket = |x: f64, lo: f64, hi: f64| {
            if x < lo {
                Some(x / lo - 1.0)
            } else if x > hi {
                Some(x / hi - 1.0)
            } else {
                Some(0.0)
            }
        };
        for lattice in ["square", "polar"] {
            let (_, out) = run(&format!("scenes/paper/disks_{lattice}{suffix}.toml"), false)?;
            let w = out.summary.wall_seconds;
            let case = format!("disks {lattice}, {mode}");
            let f = out.history.column("contact_force").unwrap_or_default();
            let vl = *out
                .history
                .column("velocity_left")
                .unwrap_or_default()
                .last()
                .unwrap_or(&f64::NAN);
            let vr = *out
                .history
                .column("velocity_right")
                .unwrap_or_default()
                .last()
                .unwrap_or(&f64::NAN);
            if mode == "penalty" {
                let peak = f.iter().cloned().fold(0.0, f64::max);
                let (t0, t1) = contact_window(&out.history.times, &f);
                let b = format!("{:.3}–{:.3}", soft.peak_force / 1e6, stiff.peak_force / 1e6);
                row(
                    &case,
                    "peak force (MN/m)",
                    &b,
                    peak / 1e6,
                    bracket(peak, soft.peak_force, stiff.peak_force),
                    w,
                );
                let b = format!(
                    "{:.2}–{:.2}",
                    stiff.contact_time * 1e6,
                    soft.contact_time * 1e6
                );
                let d = t1 - t0;
                row(
                    &case,
                    "contact time (µs)",
                    &b,
                    d * 1e6,
                    bracket(d, stiff.contact_time, soft.contact_time),
                    w,
                );
            }
            row(&case, "restitution", "≲ 1", (vr - vl) / 10.0, None, w);
        }
    }
    Ok(())
}
