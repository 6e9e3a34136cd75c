//! Case 3: the two steel disks on both lattices (Figs. 8 and 9), scored
//! against the dynamic reference and drawn with the Hertz bracket.

use crate::physics::material::MaterialModel;
use crate::plot::{self, Field, Figure, Style};
use crate::probe::particle_value;
use crate::scene::{ParticleQuantity, Scene};
use crate::RunError;

use super::exact::{hertz_c_inertia, hertz_disks, HERTZ_C_JOHNSON};
use super::report::{exact_series, pts, series, Report};
use super::runs::{disk_scene, run_case, CaseRun, DiskScores, PULL_ROUND_OFF};
use super::{Options, DISKS_CONTACT_TIME, DISKS_PEAK_FORCE};

/// Case 3, Figs. 8 and 9: the two disks on both lattices.
pub(super) fn disks(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let r = opts.resolution.disk_r_over_dx;
    let us = 1e6;
    let mut fig9 = Figure::new(
        &format!("Fig. 9: contact force, two steel disks (R = 5 mm, 10 m/s), R/Δx = {r}"),
        "time (µs)",
        "contact force (MN/m)",
    );
    let mut header = Vec::new();
    let mut cols = Vec::new();
    let mut polar_peak = None;
    for (k, lattice) in ["square", "polar"].into_iter().enumerate() {
        let run = run_case(
            &opts.tuning.apply(disk_scene(lattice, r)),
            opts.backend,
            opts.integrator,
            None,
        )?;
        let sc = DiskScores::of(&run);
        disk_scores(rep, lattice, &run, &sc);
        let fc = run.col("contact_force");
        let t = run.times().to_vec();
        fig9.series.push(series(
            &format!("SPH, {lattice} lattice"),
            pts(&t, &fc, us, 1e-6),
            Style::Solid,
            k,
        ));
        header.push(format!("{lattice}_time_s"));
        header.push(format!("{lattice}_force_n_per_m"));
        cols.push(t);
        cols.push(fc);
        if lattice == "polar" {
            polar_peak = Some((run.scene, sc.t_peak));
        }
    }
    hertz_bracket(r, &mut fig9, &mut header, &mut cols);
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    rep.csv("fig9_contact_force", &h, &cols)?;
    rep.figure("fig9_contact_force", &fig9);

    // Fig. 8: the von Mises field at peak force (polar lattice), from a run
    // stopped at that instant.
    if let Some((scene, tp)) = polar_peak {
        von_mises_at_peak(opts, rep, &scene, tp)?;
    }
    Ok(())
}

/// One lattice's scores: the peak force and contact time against the
/// dynamic reference, the restitution, the pull, the ledger, momentum.
fn disk_scores(rep: &mut Report, lattice: &str, run: &CaseRun, sc: &DiskScores) {
    let case = format!("disks, {lattice} lattice, contact");
    rep.within(
        &case,
        "peak contact force (N/m)",
        DISKS_PEAK_FORCE,
        sc.peak,
        run,
        0.03,
    );
    rep.within(
        &case,
        "contact time (s)",
        DISKS_CONTACT_TIME,
        sc.contact_time,
        run,
        0.03,
    );
    let e = sc.restitution;
    rep.add(
        &case,
        "restitution",
        1.0,
        e,
        run,
        "0.95 to 1",
        (0.95..=1.0).contains(&e),
    );
    // Read from the left disk's momentum, which only the contact
    // changes.
    let (pull, push) = run.pull_and_push(0, "velocity_left");
    rep.add(
        &case,
        "largest pull between the disks, from the left disk's momentum (N/m)",
        0.0,
        pull.max(0.0),
        run,
        "round-off: ≤ 1e-4 of the largest push",
        pull <= PULL_ROUND_OFF * push,
    );
    let s = &run.out.summary;
    // The ledger: bodies' energy plus what the discrete spring lost
    // against the start; the loss itself falls with resolution
    // (0.7 % at R/Δx = 25, 0.08 % at 50 on the polar lattice).
    let balance = s.energy_balance();
    rep.add(
        &case,
        "energy balance incl. spring loss (relative)",
        0.0,
        balance,
        run,
        "|·| < 5e-3",
        balance.abs() < 5e-3,
    );
    let loss = s.energy_spring_loss / s.energy_initial;
    rep.add(
        &case,
        "energy lost by the penalty spring (relative)",
        0.0,
        loss,
        run,
        "< 1e-2",
        (-1e-3..1e-2).contains(&loss),
    );
    let mass: f64 = s.bodies.iter().map(|b| b.mass).sum();
    rep.momentum(&case, "kg m/s per m", run, 5.0 * mass);
}

/// The Hertz bracket (C = 1 and the free disk's C) drawn in Fig. 9 and
/// added to its CSV columns, for the disks at `r` = R/Δx.
fn hertz_bracket(r: f64, fig9: &mut Figure, header: &mut Vec<String>, cols: &mut Vec<Vec<f64>>) {
    let us = 1e6;
    let scene = disk_scene("polar", r);
    let steel = MaterialModel::new(&scene.materials["steel"]);
    for (c, name, key) in [
        (HERTZ_C_JOHNSON, "Hertz, C = 1 (Johnson)", "c1"),
        (
            hertz_c_inertia(steel.nu),
            "Hertz, C = 1.742 (free disk)",
            "c1742",
        ),
    ] {
        let h = hertz_disks(&steel, 0.005, 10.0, c);
        let tt: Vec<f64> = h.curve.iter().map(|p| p.0).collect();
        let ff: Vec<f64> = h.curve.iter().map(|p| p.1).collect();
        // Both ends of the bracket drawn as references: C = 1 black dashed,
        // the other dashed in colour.
        let mut s = exact_series(name, pts(&tt, &ff, us, 1e-6));
        if key == "c1742" {
            s.exact = false;
            s.color = Some(4);
        }
        fig9.series.push(s);
        header.push(format!("hertz_{key}_time_s"));
        header.push(format!("hertz_{key}_force_n_per_m"));
        cols.push(tt);
        cols.push(ff);
    }
}

/// Fig. 8: the von Mises field of `scene` at peak force `tp`, from a run
/// stopped at that instant.
fn von_mises_at_peak(
    opts: &Options,
    rep: &mut Report,
    scene: &Scene,
    tp: f64,
) -> Result<(), RunError> {
    let r = opts.resolution.disk_r_over_dx;
    let run = run_case(scene, opts.backend, opts.integrator, Some(tp))?;
    let (m, st) = (&run.out.model, &run.out.state);
    let x: Vec<f64> = st.x.iter().map(|p| p.x * 1e3).collect();
    let y: Vec<f64> = st.x.iter().map(|p| p.y * 1e3).collect();
    let vm: Vec<f64> = (0..m.len())
        .map(|i| particle_value(m, st, i, ParticleQuantity::VonMises) * 1e-9)
        .collect();
    rep.csv(
        "fig8_von_mises",
        &["x_mm", "y_mm", "von_mises_gpa"],
        &[x.clone(), y.clone(), vm.clone()],
    )?;
    let title = format!(
        "Fig. 8: von Mises stress at peak force (t = {:.2} µs), polar, R/Δx = {r}",
        tp * 1e6
    );
    let field = Field {
        x,
        y,
        value: vm,
        range: None,
        ..Field::default()
    };
    let path = rep.out.join("fig8_von_mises.png");
    if let Err(e) = plot::field_plot(
        &path,
        &title,
        "x (mm)",
        "y (mm)",
        "von Mises stress (GPa)",
        &field,
    ) {
        rep.warnings.push(format!("{}: {e}", path.display()));
    }
    Ok(())
}
