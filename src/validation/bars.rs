//! Cases 1 and 2: the steel bars (Figs. 4–6) and steel against aluminium
//! (Fig. 7), scored against the exact bar answer.

use crate::model::Model;
use crate::physics::material::MaterialModel;
use crate::plot::{Figure, Style};
use crate::probe::particle_value;
use crate::scene::{ParticleQuantity, Scene};
use crate::RunError;

use super::exact::{bar_impact_history, BarId, BarImpactHistory};
use super::report::{exact_series, pts, series, Report};
use super::runs::{bar_scene, last, run_case, CaseRun, PULL_ROUND_OFF};
use super::{Options, BARS, BARS_KERNEL, STEEL_AL, STEEL_AL_KERNEL};

/// Largest tensile (positive) value of column `col` over the run.
fn max_tension(run: &CaseRun, col: &str) -> f64 {
    run.col(col).into_iter().fold(0.0, f64::max)
}

/// Initial distance from the contact face of the particle a probe at `at`
/// follows (the nearest of the left bar, as the probe picks it).
fn probe_distance(scene: &Scene, at: f64) -> f64 {
    let (model, st) = Model::new(scene);
    model.bodies[0]
        .range
        .clone()
        .map(|i| st.x[i].x)
        .min_by(|a, c| (a - at).abs().total_cmp(&(c - at).abs()))
        .map_or(at.abs(), f64::abs)
}

/// The exact answer of a bar case (docs/method.md §10) over the scene's run.
pub(super) fn exact_bars(scene: &Scene, right: &str) -> Result<BarImpactHistory, RunError> {
    let steel = MaterialModel::new(&scene.materials["steel"]);
    let other = MaterialModel::new(&scene.materials[right]);
    let end = scene.simulation.end_time;
    bar_impact_history(&steel, 0.005, 10.0, &other, 0.005, -10.0, end).ok_or_else(|| {
        RunError::Scene(crate::error::SceneError::at(
            "materials",
            "the bar case has no exact answer for these materials",
        ))
    })
}

/// Case 1, Figs. 4–6: velocity at point b, stress at the contact point a,
/// and the bars' mean velocities, kernel and contact modes against exact.
pub(super) fn bars(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let n = opts.resolution.bar_particles;
    let pen = run_case(
        &opts.tuning.apply(bar_scene(BARS, n, 5e-9)),
        opts.backend,
        opts.integrator,
        None,
    )?;
    let ker = run_case(
        &opts.tuning.apply(bar_scene(BARS_KERNEL, n, 5e-9)),
        opts.backend,
        opts.integrator,
        None,
    )?;
    let ex = exact_bars(&pen.scene, "steel")?;
    let fig = BarFigures {
        pen: &pen,
        ker: &ker,
        ex: &ex,
        n,
    };
    fig.velocity_b(rep, probe_distance(&pen.scene, -0.0025))?;
    fig.stress_a(rep)?;
    fig.mean_velocities(rep)?;
    bar_scores(&pen, &ker, &ex, rep);
    Ok(())
}

/// The steel bars' runs (contact and kernel mode, `n` particles a bar)
/// and their exact answer, for Figs. 4–6.
struct BarFigures<'a> {
    pen: &'a CaseRun,
    ker: &'a CaseRun,
    ex: &'a BarImpactHistory,
    n: usize,
}

impl BarFigures<'_> {
    /// Fig. 4: the velocity at b, `d_b` from the contact.
    fn velocity_b(&self, rep: &mut Report, d_b: f64) -> Result<(), RunError> {
        let (pen, ker, ex, n) = (self.pen, self.ker, self.ex, self.n);
        let t = pen.times().to_vec();
        let tk = ker.times().to_vec();
        let us = 1e6;
        // Fig. 4: velocity at b.
        let exact_vb: Vec<f64> = t
            .iter()
            .map(|&s| ex.point_velocity(BarId::One, d_b, s))
            .collect();
        let (vb_p, vb_k) = (pen.col("velocity_b"), ker.col("velocity_b"));
        let mut f = Figure::new(
            &format!(
                "Fig. 4: velocity at b ({:.2} mm from the contact), steel bars, N = {n}",
                d_b * 1e3
            ),
            "time (µs)",
            "velocity (m/s)",
        );
        f.series.push(series(
            "kernel mode",
            pts(&tk, &vb_k, us, 1.0),
            Style::Solid,
            1,
        ));
        f.series.push(series(
            "contact mode",
            pts(&t, &vb_p, us, 1.0),
            Style::Solid,
            0,
        ));
        f.series
            .push(exact_series("exact", pts(&t, &exact_vb, us, 1.0)));
        rep.figure("fig4_velocity_b", &f);
        rep.csv(
            "fig4_velocity_b",
            &["time_s", "exact_m_s", "contact_m_s", "kernel_m_s"],
            &[t.clone(), exact_vb, vb_p, vb_k],
        )?;
        Ok(())
    }

    /// Fig. 5: the stress at the contact point a.
    fn stress_a(&self, rep: &mut Report) -> Result<(), RunError> {
        let (pen, ker, ex, n) = (self.pen, self.ker, self.ex, self.n);
        let t = pen.times().to_vec();
        let tk = ker.times().to_vec();
        let us = 1e6;
        // Fig. 5: stress at the contact point a. In contact mode that is the
        // contact pressure (docs/method.md §11); in kernel mode the SPH stress of the
        // face particle (tension positive), shown as −σ_xx (compression up).
        let p_pen = pen.col("contact_pressure");
        let s_ker: Vec<f64> = ker.col("stress_a").iter().map(|s| -s).collect();
        let exact_p: Vec<f64> = t.iter().map(|&s| -ex.interface_stress(s)).collect();
        let mut f = Figure::new(
            &format!("Fig. 5: stress at the contact point a, steel bars, N = {n}"),
            "time (µs)",
            "contact stress (MPa)",
        );
        f.series.push(series(
            "kernel mode (−σxx of the face particle)",
            pts(&tk, &s_ker, us, 1e-6),
            Style::Solid,
            1,
        ));
        f.series.push(series(
            "contact mode (contact pressure p)",
            pts(&t, &p_pen, us, 1e-6),
            Style::Solid,
            0,
        ));
        f.series
            .push(exact_series("exact", pts(&t, &exact_p, us, 1e-6)));
        rep.figure("fig5_stress_a", &f);
        rep.csv(
            "fig5_stress_a",
            &[
                "time_s",
                "exact_pressure_pa",
                "contact_pressure_pa",
                "kernel_minus_stress_xx_pa",
            ],
            &[t.clone(), exact_p, p_pen, s_ker],
        )?;
        Ok(())
    }

    /// Fig. 6: the bars' mean velocities.
    fn mean_velocities(&self, rep: &mut Report) -> Result<(), RunError> {
        let (pen, ker, ex, n) = (self.pen, self.ker, self.ex, self.n);
        let t = pen.times().to_vec();
        let us = 1e6;
        // Fig. 6: mean velocities.
        let ex_l: Vec<f64> = t.iter().map(|&s| ex.mean_velocity(BarId::One, s)).collect();
        let ex_r: Vec<f64> = t.iter().map(|&s| ex.mean_velocity(BarId::Two, s)).collect();
        let mut f = Figure::new(
            &format!("Fig. 6: mean velocities of the bars, steel bars, N = {n}"),
            "time (µs)",
            "mean velocity (m/s)",
        );
        let cols = [
            ("kernel mode, left", &ker, "velocity_left", 1),
            ("kernel mode, right", &ker, "velocity_right", 3),
            ("contact mode, left", &pen, "velocity_left", 0),
            ("contact mode, right", &pen, "velocity_right", 2),
        ]
        .map(|(label, run, col, color)| {
            let v = run.col(col);
            f.series.push(series(
                label,
                pts(run.times(), &v, us, 1.0),
                Style::Solid,
                color,
            ));
            v
        });
        f.series
            .push(exact_series("exact", pts(&t, &ex_l, us, 1.0)));
        f.series.push(exact_series("", pts(&t, &ex_r, us, 1.0)));
        rep.figure("fig6_mean_velocity", &f);
        let [kl, kr, cl, cr] = cols;
        rep.csv(
            "fig6_mean_velocity",
            &[
                "time_s",
                "exact_left_m_s",
                "exact_right_m_s",
                "contact_left_m_s",
                "contact_right_m_s",
                "kernel_left_m_s",
                "kernel_right_m_s",
            ],
            &[t, ex_l, ex_r, cl, cr, kl, kr],
        )?;
        Ok(())
    }
}

/// Case 1's scores: the contact mode against the exact answer, the kernel
/// mode's failure (the paper's point).
fn bar_scores(pen: &CaseRun, ker: &CaseRun, ex: &BarImpactHistory, rep: &mut Report) {
    // Scores.
    // The bars never pull each other (docs/method.md §11): read from the
    // left bar's momentum, which only the contact changes.
    let (pull, push) = pen.pull_and_push(0, "velocity_left");
    let case = "steel bars, contact";
    let r = &ex.result;
    let sc = rep.contact_phase(case, "contact pressure plateau (Pa)", pen, r, 0.01);
    rep.add(
        case,
        "rebound: left bar mean velocity at 4 µs (m/s)",
        r.final_velocity_1,
        sc.final_left,
        pen,
        "≥ 0.97 of exact",
        sc.final_left / r.final_velocity_1 >= 0.97,
    );
    rep.add(
        case,
        "largest pull between the bars, from the left bar's momentum (Pa)",
        0.0,
        pull.max(0.0),
        pen,
        "round-off: ≤ 1e-4 of the largest push",
        pull <= PULL_ROUND_OFF * push,
    );
    rep.momentum(case, "kg m/s per m²", pen, 2.0 * 39.25 * 10.0);
    let s = &pen.out.summary;
    let de = s.energy_final / s.energy_initial - 1.0;
    rep.add(
        case,
        "total energy change (relative)",
        0.0,
        de,
        pen,
        "|·| < 1e-3 (docs/method.md §11)",
        de.abs() < 1e-3,
    );

    // Kernel mode: the paper's point is that it fails; the records pass
    // when it does (bars still stuck, tension at the face).
    let case = "steel bars, kernel";
    let v = last(ker, "velocity_left");
    rep.add(
        case,
        "left bar mean velocity at 4 µs (m/s)",
        r.final_velocity_1,
        v,
        ker,
        "off by > 10 % (the paper's point)",
        (v / r.final_velocity_1 - 1.0).abs() > 0.1,
    );
    // The bodies pull on each other through the SPH sums: the face
    // particle's own stress shows it.
    let tension = max_tension(ker, "stress_a");
    rep.add(
        case,
        "largest tension at the contact face (Pa)",
        0.0,
        tension,
        ker,
        "> 10 % of the contact stress (the paper's point)",
        tension > 0.1 * r.contact_stress.abs(),
    );
}

/// Case 2, Fig. 7: axial stress against position at fixed times, steel
/// against aluminium, kernel and contact modes against the exact profile.
pub(super) fn steel_aluminium(opts: &Options, rep: &mut Report) -> Result<(), RunError> {
    let n = opts.resolution.bar_particles;
    let pen = run_case(
        &opts.tuning.apply(bar_scene(STEEL_AL, n, 5e-9)),
        opts.backend,
        opts.integrator,
        None,
    )?;
    let kscene = opts.tuning.apply(bar_scene(STEEL_AL_KERNEL, n, 5e-9));
    let ex = exact_bars(&pen.scene, "aluminium")?;
    // Particle positions at t = 0 (the profiles are drawn against them; the
    // displacements are micrometres) and the exact profile's coordinates.
    let (m0, s0) = Model::new(&pen.scene);
    let x0: Vec<f64> = s0.x.iter().map(|x| x.x).collect();
    let at_face: Vec<(BarId, f64)> = (0..m0.len())
        .map(|i| {
            if m0.body[i] == 0 {
                (BarId::One, -x0[i])
            } else {
                (BarId::Two, x0[i])
            }
        })
        .collect();
    let stress = |r: &CaseRun| -> Vec<f64> {
        (0..r.out.model.len())
            .map(|i| particle_value(&r.out.model, &r.out.state, i, ParticleQuantity::StressXx))
            .collect()
    };
    let scale = ex.result.contact_stress.abs();

    // Profiles at three times inside the contact (the exact answer ends at
    // separation, 1.574 µs).
    let title =
        |mode: &str| format!("Fig. 7: σxx against position, steel | aluminium, {mode}, N = {n}");
    let ylabel = "σxx (MPa, tension positive)";
    let mut f = Figure::new(&title("contact mode"), "position (mm)", ylabel);
    let mut fk = Figure::new(&title("kernel mode"), "position (mm)", ylabel);
    let mut header = vec!["position_m".to_string()];
    let mut cols = vec![x0.clone()];
    for (k, tk) in [0.3e-6, 0.6e-6, 1.2e-6].into_iter().enumerate() {
        let p = run_case(&pen.scene, opts.backend, opts.integrator, Some(tk))?;
        let kr = run_case(&kscene, opts.backend, opts.integrator, Some(tk))?;
        let (sp, sk) = (stress(&p), stress(&kr));
        let exact: Vec<f64> = at_face
            .iter()
            .map(|&(bar, d)| ex.point_stress(bar, d, tk))
            .collect();
        // Mean |σ − σ_exact| over the particles, relative to the contact
        // stress (each front is a jump any particle spacing smears).
        let l1 = |s: &[f64]| {
            s.iter()
                .zip(&exact)
                .map(|(a, b)| (a - b).abs())
                .sum::<f64>()
                / s.len() as f64
                / scale
        };
        let (err, err_k) = (l1(&sp), l1(&sk));
        let label = format!("{:.1} µs", tk * 1e6);
        let obs = format!("stress profile at {label}: mean |error| / |σ_contact|");
        rep.add(
            "steel/aluminium, contact",
            &obs,
            0.0,
            err,
            &p,
            "< 0.1",
            err < 0.1,
        );
        rep.add(
            "steel/aluminium, kernel",
            &obs,
            0.0,
            err_k,
            &kr,
            "worse than contact mode (the paper's point)",
            err_k > err,
        );
        f.series.push(series(
            &format!("SPH, {label}"),
            pts(&x0, &sp, 1e3, 1e-6),
            Style::Solid,
            k,
        ));
        fk.series.push(series(
            &format!("SPH, {label}"),
            pts(&x0, &sk, 1e3, 1e-6),
            Style::Solid,
            k,
        ));
        let mut ep = pts(&x0, &exact, 1e3, 1e-6);
        ep.sort_by(|a, b| a.0.total_cmp(&b.0));
        let label_ex = if k == 0 { "exact" } else { "" };
        f.series.push(exact_series(label_ex, ep.clone()));
        fk.series.push(exact_series(label_ex, ep));
        for (name, c) in [("contact", sp), ("kernel", sk), ("exact", exact)] {
            header.push(format!("{name}_{:.1}us_pa", tk * 1e6));
            cols.push(c);
        }
    }
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    rep.csv("fig7_stress_profiles", &h, &cols)?;
    rep.figure("fig7_stress_profiles", &f);
    rep.figure("fig7_stress_profiles_kernel", &fk);

    let case = "steel/aluminium, contact";
    let r = &ex.result;
    let sc = rep.contact_phase(case, "interface stress plateau (Pa)", &pen, r, 0.03);
    rep.within(
        case,
        "aluminium mean velocity at 4 µs (m/s)",
        r.final_velocity_2,
        sc.final_right,
        &pen,
        0.03,
    );
    Ok(())
}
