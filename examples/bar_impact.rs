//! Build a scene in code and run it through the library API: a steel bar
//! striking an aluminium bar twice its length, compared with the exact
//! 1-D answer.
//!
//!     cargo run --release --example bar_impact

use sphcontact::output::contact_window;
use sphcontact::physics::material::MaterialModel;
use sphcontact::run::{run_scene, RunOptions};
use sphcontact::scene::{
    default_cfl, default_smoothing_ratio, Backend, Body, ContactQuantity, Correction, Eos,
    Geometry, Integrator, Interaction, Material, Output, Probe, Scene, Shape, Simulation,
    StressForm,
};
use sphcontact::validation::exact::bar_impact;
use std::collections::BTreeMap;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let steel = Material {
        shear_modulus: Some(77e9),
        ..Material::basic(7850.0, Eos::mie_gruneisen(4580.0, 1.49, 2.02))
    };
    let aluminium = Material {
        shear_modulus: Some(25e9),
        ..Material::basic(2790.0, Eos::mie_gruneisen(5330.0, 1.34, 2.0))
    };
    let bar = |name: &str, material: &str, from: f64, to: f64, v: f64| Body {
        name: name.into(),
        material: material.into(),
        spacing: 5e-5,
        velocity: Some(vec![v]),
        rigid: false,
        shape: Shape::Segment { from, to },
        jitter: None,
        seed: None,
        velocity_field: None,
        constraints: vec![],
    };
    let scene = Scene {
        title: Some("steel striker onto a long aluminium bar".into()),
        simulation: Simulation {
            dimension: 1,
            end_time: 4e-6,
            cfl: default_cfl(),
            dt: None,
            interaction: Interaction::Penalty,
            smoothing_ratio: default_smoothing_ratio(),
            correction: Correction::Gradient,
            stress_form: StressForm::Variational,
            backend: Backend::Cpu,
            integrator: Integrator::Midpoint,
            geometry: Geometry::Planar,
            support: None,
            support_band: None,
            dispersion_correction: 0.0,
            gravity: None,
        },
        artificial_stress: None,
        artificial_viscosity: None,
        contact: None,
        materials: BTreeMap::from([("steel".into(), steel), ("aluminium".into(), aluminium)]),
        bodies: vec![
            bar("striker", "steel", -0.005, 0.0, 20.0),
            bar("target", "aluminium", 0.0, 0.010, 0.0),
        ],
        probes: vec![Probe::Contact {
            name: "pressure".into(),
            bodies: ["striker".into(), "target".into()],
            quantity: ContactQuantity::PressureMax,
        }],
        output: Output {
            history_interval: Some(1e-9),
            ..Default::default()
        },
        symmetry: vec![],
    };
    // The same checks a scene file gets.
    sphcontact::scene::validate(&scene)?;

    let out = run_scene(
        &scene,
        None,
        &RunOptions {
            silent: true,
            ..Default::default()
        },
    )?;
    let exact = bar_impact(
        &MaterialModel::new(&scene.materials["steel"]),
        0.005,
        20.0,
        &MaterialModel::new(&scene.materials["aluminium"]),
        0.010,
        0.0,
    );
    let p = out.history.column("pressure").expect("probe exists");
    let (_, t_sep) = contact_window(&out.history.times, &p);
    let plateau = p[out
        .history
        .times
        .iter()
        .position(|&t| t > 0.5e-6)
        .unwrap_or(0)];
    println!("{}", scene.title.as_deref().unwrap_or(""));
    println!(
        "contact pressure  {:.4e} Pa   exact {:.4e} Pa",
        plateau, -exact.contact_stress
    );
    println!(
        "separation        {:.4e} s    exact {:.4e} s",
        t_sep, exact.separation_time
    );
    for b in &out.summary.bodies {
        println!("{:<8} leaves at {:+.3} m/s", b.name, b.velocity_final[0]);
    }
    println!(
        "exact: striker {:+.3} m/s, target {:+.3} m/s",
        exact.final_velocity_1, exact.final_velocity_2
    );
    Ok(())
}
