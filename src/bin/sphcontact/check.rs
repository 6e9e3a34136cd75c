//! `sphcontact check`: what a scene sets up, without running it.

use std::path::Path;

use sphcontact::model::Model;
use sphcontact::physics::material::series;
use sphcontact::run::{history_times, output_dir, RunOptions};
use sphcontact::scene::{validate::cfl_step_at_start, ArtPairs, ArtWork, Integrator, Scene};

pub(crate) fn check(path: &Path, scene: &Scene) {
    let (model, _) = Model::new(scene);
    let sim = &scene.simulation;
    println!("scene       {}", path.display());
    if let Some(t) = &scene.title {
        println!("title       {t}");
    }
    println!(
        "set-up      {}, interaction {}, correction {}, smoothing ratio {}",
        if scene.axisymmetric() {
            "2-D, bodies of revolution (r–z)"
        } else if sim.dimension == 1 {
            "1-D, uniaxial strain"
        } else {
            "2-D, plane strain"
        },
        format!("{:?}", sim.interaction).to_lowercase(),
        format!("{:?}", sim.correction).to_lowercase(),
        sim.smoothing_ratio
    );
    for s in &scene.symmetry {
        let (k, sign) = s.axis();
        let axis = ["x", "y"][k];
        println!(
            "symmetry    the plane {axis} = {at} m, modelling {axis} {} {at} m; the other half is its mirror image (masses, forces and energies are the modelled half's)",
            if sign > 0.0 { ">" } else { "<" },
            at = s.point[k],
        );
    }
    print_numerics(scene, &model);
    print_bodies(scene, &model);
    let placed = sphcontact::scene::place_bodies(scene);
    let dt = cfl_step_at_start(scene, &placed);
    if model.contact {
        print_contact(scene, &model, dt);
    }
    let [lo, hi] = model.domain;
    if model.dim == 1 {
        println!(
            "domain      x in [{:.4e}, {:.4e}] m (a particle leaving it stops the run)",
            lo.x, hi.x
        );
    } else {
        println!(
            "domain      x in [{:.4e}, {:.4e}] m, y in [{:.4e}, {:.4e}] m (a particle leaving it stops the run)",
            lo.x, hi.x, lo.y, hi.y
        );
    }
    let used = sim.dt.unwrap_or(dt.min(model.contact_dt));
    println!(
        "time        end {:.4e} s, step {:.4e} s ({}), about {} steps, {}",
        sim.end_time,
        used,
        if sim.dt.is_some() {
            "fixed"
        } else if model.contact_dt < dt {
            "the contact's limit"
        } else {
            "CFL at t = 0"
        },
        (sim.end_time / used).ceil(),
        match sim.integrator {
            Integrator::Midpoint => "midpoint rule (two evaluations a step)",
            Integrator::Leapfrog => "leapfrog (one evaluation a step)",
        }
    );
    println!(
        "output      {} ({} history rows, {} probes{})",
        output_dir(scene, Some(path), &RunOptions::default()).display(),
        history_times(sim.end_time, scene.history_interval()).len(),
        scene.probes.len(),
        match scene.output.snapshot_interval {
            // A size to plan disk for.
            Some(dt) => {
                let k = history_times(sim.end_time, dt).len();
                format!(
                    ", {k} snapshots of about {:.0} MB each",
                    (sphcontact::output::vtk::BYTES_PER_PARTICLE * model.len() as u64) as f64 / 1e6
                )
            }
            None => String::new(),
        }
    );
}

/// The numerics' lines: the dispersion correction, the supports, the
/// viscosity and the hourglass control, the artificial stress.
fn print_numerics(scene: &Scene, model: &Model) {
    let sim = &scene.simulation;
    println!(
        "dispersion  {}",
        if sim.dispersion_correction > 0.0 {
            format!(
                "corrected, theta {} (more pair sweeps: two a midpoint evaluation, four a leapfrog step)",
                sim.dispersion_correction
            )
        } else {
            "uncorrected (dispersion_correction = 0)".to_string()
        }
    );
    println!(
        "support     {}",
        if model.adaptive {
            let band = if model.carries_band() {
                let b = model.band;
                let by = if b.drawn == b.squeezed {
                    format!("drawn out or squeezed by {}", b.drawn)
                } else {
                    format!("drawn out by {} or squeezed by {}", b.drawn, b.squeezed)
                };
                format!("round until the material is {by}, then following it beyond that")
            } else {
                "carried with the deformation".to_string()
            };
            format!(
                "adaptive: {band}, semi-axes between h/{} and {} h",
                sphcontact::physics::support::SQUEEZE_MAX,
                sphcontact::physics::support::STRETCH_MAX
            )
        } else {
            "fixed: round, radius 2h".to_string()
        }
    );
    if let Some(g) = model.gravity {
        let g = if model.dim == 1 {
            format!("[{}]", g.x)
        } else {
            format!("[{}, {}]", g.x, g.y)
        };
        println!("gravity     {g} m/s² on the deformable bodies (the energy guard off)");
    }
    let av = scene.viscosity();
    println!(
        "viscosity   {}, alpha {}, beta {}, {}; hourglass control {}",
        match av.form {
            sphcontact::scene::ViscosityForm::Monaghan => "Monaghan (approaching pairs)",
            sphcontact::scene::ViscosityForm::Riemann => "Riemann (approaching and receding pairs)",
        },
        av.alpha,
        av.beta,
        match (av.reconstruct, av.reconstruct_surfaces) {
            (true, false) => "on the reconstructed velocity jump (plain at surfaces)",
            (true, true) => "on the reconstructed velocity jump",
            (false, _) => "on the plain velocity jump",
        },
        if av.hourglass > 0.0 {
            av.hourglass.to_string()
        } else {
            "off".to_string()
        }
    );
    println!(
        "tension     {}",
        match model.artificial_stress {
            None => "no artificial stress".to_string(),
            Some(a) => format!(
                "artificial stress epsilon {}, n {}, {}; {}",
                a.epsilon,
                a.n,
                match a.pairs {
                    ArtPairs::All => "every pair in tension",
                    ArtPairs::Close => "close pairs",
                },
                match a.work {
                    ArtWork::Heat => "only heat",
                    ArtWork::Either => "its work of either sign",
                    ArtWork::Plastic if model.plastic => "only heat where it flows plastically",
                    ArtWork::Plastic => "its work of either sign (nothing yields)",
                    ArtWork::Yielding if model.plastic => {
                        "only heat in bodies that can yield, of either sign elsewhere"
                    }
                    ArtWork::Yielding => "its work of either sign (nothing can yield)",
                }
            ),
        }
    );
    // Bodies that can yield and take the hourglass control in place of
    // the artificial stress (`plastic = "hourglass"`).
    let keyed: Vec<&sphcontact::model::BodyInfo> = model.bodies.iter().filter(|b| !b.art).collect();
    if let Some(b) = keyed.first() {
        println!(
            "plastic     {}: the hourglass control {} in place of the artificial stress",
            keyed
                .iter()
                .map(|b| b.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            b.hourglass
        );
    }
}

/// The particles' line and each body's lines.
fn print_bodies(scene: &Scene, model: &Model) {
    // A body's mass: per unit area in 1-D, per unit depth in plane strain,
    // the whole revolution's in a body of revolution.
    let mass_unit = if scene.axisymmetric() {
        "kg"
    } else if scene.simulation.dimension == 1 {
        "kg/m2"
    } else {
        "kg/m"
    };
    println!("particles   {}", model.len());
    for (bi, (b, sb)) in model.bodies.iter().zip(&scene.bodies).enumerate() {
        let m = &b.material;
        let mass: f64 = b.range.clone().map(|i| model.mass[i]).sum();
        println!(
            "body        {:<12} {:>8} particles, spacing {:.4e} m, h {:.4e} m, mass {:.6e} {mass_unit}, velocity ({}, {}) m/s{}",
            b.name,
            b.range.len(),
            b.spacing,
            model.h[b.range.start],
            mass,
            b.velocity0.x,
            b.velocity0.y,
            if b.rigid { ", rigid" } else { "" }
        );
        if let sphcontact::scene::Shape::Polygon {
            vertices, holes, ..
        } = &sb.shape
        {
            // The outline's extent: where a drawing's unit went wrong, it
            // shows here.
            let span = |k: usize| {
                vertices
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p[k]), hi.max(p[k]))
                    })
            };
            let ((x0, x1), (y0, y1)) = (span(0), span(1));
            println!(
                "            polygon of {} vertices, {} hole{}, x in [{x0:.4e}, {x1:.4e}] m, y in [{y0:.4e}, {y1:.4e}] m",
                vertices.len(),
                holes.len(),
                if holes.len() == 1 { "" } else { "s" }
            );
        }
        if let Some(sphcontact::scene::VelocityField::Radial {
            center,
            speed,
            radius,
            exponent,
        }) = &sb.velocity_field
        {
            println!(
                "            plus a radial velocity field {speed} m/s × ({radius} m / r)^{exponent} from ({}, {})",
                center[0],
                center.get(1).copied().unwrap_or(0.0)
            );
        }
        for c in model
            .held
            .iter()
            .filter(|c| b.range.contains(&c.particles[0]))
        {
            let comp = |m: f64, v: f64| {
                if m > 0.0 {
                    v.to_string()
                } else {
                    "free".to_string()
                }
            };
            let v = if model.dim == 1 {
                format!("[{}]", comp(c.mask.x, c.velocity.x))
            } else {
                format!(
                    "[{}, {}]",
                    comp(c.mask.x, c.velocity.x),
                    comp(c.mask.y, c.velocity.y)
                )
            };
            println!(
                "            constraint '{}': {} particles held at {v} m/s",
                c.name,
                c.particles.len()
            );
        }
        if let Some(j) = sb.jitter.filter(|&j| j > 0.0) {
            println!(
                "            jitter ±{j} Δx per coordinate (seed {}), mass from the nominal cells",
                sb.seed
                    .map_or_else(|| format!("{bi}, the body's index"), |s| s.to_string())
            );
        }
        println!(
            "            rho0 {} kg/m3, K {:.4e} Pa, G {:.4e} Pa, E {:.4e} Pa, nu {:.4}, c_L {:.2} m/s, Z {:.4e} Pa s/m{}",
            m.rho0,
            m.k,
            m.g,
            m.e,
            m.nu,
            m.c_l,
            m.z,
            if m.y0.is_finite() { format!(", Y0 {:.4e} Pa", m.y0) } else { String::new() }
        );
    }
}

/// Each pair of bodies' contact constants and the spring's step limit
/// against the CFL step `dt`.
fn print_contact(scene: &Scene, model: &Model, dt: f64) {
    let sim = &scene.simulation;
    let inf = |b: &sphcontact::model::BodyInfo, v: f64| if b.rigid { f64::INFINITY } else { v };
    for (i, a) in model.bodies.iter().enumerate() {
        for b in &model.bodies[i + 1..] {
            let z = series(inf(a, a.material.z), inf(b, b.material.z));
            // The spring at conforming-lattice offsets (Δx/2 each side).
            let k = sphcontact::physics::penalty::spring_stiffness(
                0.5 * a.spacing,
                a.spacing,
                inf(a, a.material.m),
                0.5 * b.spacing,
                b.spacing,
                inf(b, b.material.m),
            );
            let spring = format!("spring (surface layers Δx/2) {k:.4e} Pa/m");
            println!(
                "contact     {} | {}: Z* {:.4e} Pa s/m, {}",
                a.name, b.name, z, spring
            );
        }
    }
    let coulomb = |mu: sphcontact::model::Coulomb| {
        if mu.sticking > mu.sliding {
            format!("μ {} (static {})", mu.sliding, mu.sticking)
        } else {
            format!("μ {}", mu.sliding)
        }
    };
    if model.friction.sticking > 0.0 {
        println!(
            "            Coulomb friction {} on every pair",
            coulomb(model.friction)
        );
    }
    for &(a, b, mu) in &model.friction_pairs {
        println!(
            "            Coulomb friction {} between {} and {}",
            coulomb(mu),
            model.bodies[a as usize].name,
            model.bodies[b as usize].name
        );
    }
    println!(
        "            step limit of the stiffest spring {:.4e} s (ω Δt = {}){}",
        model.contact_dt,
        sphcontact::physics::penalty::CONTACT_STEP,
        if sim.dt.is_none() && model.contact_dt < dt {
            ", below the CFL step: it sets the step"
        } else {
            ""
        }
    );
}
