//! Shared helpers of the integration tests: run a scene through the library
//! and read observables off its history.
#![allow(dead_code)]

use std::path::Path;

use sphcontact::physics::material::MaterialModel;
use sphcontact::run::{run_scene, RunOptions, RunOutput};
use sphcontact::Scene;

pub fn load(path: &str) -> Scene {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    Scene::from_file(&root.join(path)).expect("a valid scene")
}

pub fn parse(text: &str) -> Scene {
    Scene::from_toml_str(text, "test scene").expect("a valid scene")
}

/// Run silently, in memory.
pub fn run(scene: &Scene) -> RunOutput {
    run_scene(
        scene,
        None,
        &RunOptions {
            silent: true,
            ..Default::default()
        },
    )
    .expect("the run completes")
}

pub fn material(scene: &Scene, name: &str) -> MaterialModel {
    MaterialModel::new(&scene.materials[name])
}

pub fn column(out: &RunOutput, name: &str) -> Vec<f64> {
    out.history
        .column(name)
        .unwrap_or_else(|| panic!("no probe '{name}'"))
}

#[allow(unused_imports)]
pub use sphcontact::output::contact_window;

/// Momentum to round-off (relative to Σ m |v0|) and total energy (kinetic +
/// internal + stored penalty; dashpot heat is inside the internal energy)
/// within 0.5 %.
pub fn assert_conserved(scene: &Scene, out: &RunOutput) {
    let s = &out.summary;
    let scale: f64 = s
        .bodies
        .iter()
        .zip(&scene.bodies)
        .map(|(b, sb)| {
            let v = sb.velocity.clone().unwrap_or_default();
            b.mass * v.iter().map(|x| x * x).sum::<f64>().sqrt()
        })
        .sum::<f64>()
        .max(1e-300);
    for (a, b) in s.momentum_initial.iter().zip(&s.momentum_final) {
        assert!(
            (a - b).abs() <= 1e-12 * scale,
            "momentum drifted: {a} -> {b} (scale {scale})"
        );
    }
    if s.energy_initial > 0.0 {
        let drift = (s.energy_final - s.energy_initial).abs() / s.energy_initial;
        assert!(drift < 5e-3, "energy drift {drift:e}");
    }
}

/// The GPU context shared by a test binary, or `None` with a visible skip
/// line. With `SPHCONTACT_REQUIRE_GPU` set (CI), a missing adapter fails
/// the test instead.
pub fn gpu() -> Option<std::sync::Arc<sphcontact::gpu::GpuContext>> {
    use std::sync::{Arc, OnceLock};
    static CTX: OnceLock<Result<Arc<sphcontact::gpu::GpuContext>, String>> = OnceLock::new();
    let ctx = CTX.get_or_init(|| sphcontact::gpu::GpuContext::new().map(Arc::new));
    match ctx {
        Ok(c) => Some(c.clone()),
        Err(e) => {
            if std::env::var_os("SPHCONTACT_REQUIRE_GPU").is_some() {
                panic!("SPHCONTACT_REQUIRE_GPU is set but there is no GPU adapter: {e}");
            }
            eprintln!("SKIP: no GPU adapter ({e}); this GPU test did not run");
            None
        }
    }
}
