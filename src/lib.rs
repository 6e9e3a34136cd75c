//! # sphcontact
//!
//! Smoothed Particle Hydrodynamics for impacts between elastic and
//! elasto-plastic solids, with the virtual-work penalty contact of Seo & Min
//! ("An elastic contact algorithm in SPH by virtual work principle").
//!
//! * [`scene`]: the scene file (TOML) and particle placement;
//! * [`physics`]: kernel, material model, exact answers;
//! * [`stage`]: the time step's stages, each a shader and its CPU twin, and
//!   the two integrators' schedules;
//! * [`cpu`]: the f64 reference solver, one file per stage;
//! * [`gpu`]: the same stages as WGSL compute shaders;
//! * [`run`]: running a scene to its outputs (history, summary, snapshots);
//! * [`probe`]: the recorded observables;
//! * [`mod@bench`]: particle throughput of both backends (`sphcontact bench`).
//!
//! Load a scene, run it in memory, read its history:
//!
//! ```
//! use sphcontact::run::{run_scene, RunOptions};
//! use sphcontact::Scene;
//!
//! let scene = Scene::from_toml_str(r#"
//!     [simulation]
//!     dimension = 1
//!     end_time = 4.0e-7
//!     [materials.steel]
//!     density = 7850.0
//!     shear_modulus = 77.0e9
//!     eos = { kind = "linear", c0 = 4580.0 }
//!     [[bodies]]
//!     name = "left"
//!     material = "steel"
//!     spacing = 1.0e-4
//!     velocity = [10.0]
//!     shape = { kind = "segment", from = -0.002, to = 0.0 }
//!     [[bodies]]
//!     name = "right"
//!     material = "steel"
//!     spacing = 1.0e-4
//!     velocity = [-10.0]
//!     shape = { kind = "segment", from = 0.0, to = 0.002 }
//!     [[probes]]
//!     name = "p"
//!     kind = "contact"
//!     bodies = ["left", "right"]
//!     quantity = "pressure_max"
//! "#, "example")?;
//! let out = run_scene(&scene, None, &RunOptions { silent: true, ..Default::default() })?;
//! assert_eq!(out.summary.particles, 40);
//! // After the first-contact transient, the contact pressure of two steel
//! // bars closing at 20 m/s is ρ0 c_L · 10 m/s = 458.1 MPa.
//! let p = out.history.column("p").unwrap();
//! assert!((p[p.len() - 1] / 458.1e6 - 1.0).abs() < 0.01);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod ballistic;
pub mod bench;
pub mod checkpoint;
pub mod cpu;
pub mod doctor;
pub mod error;
pub mod gpu;
pub mod math;
pub mod model;
pub mod output;
pub mod physics;
pub mod plot;
pub mod probe;
pub mod process;
pub mod run;
pub mod scene;
pub mod stage;
pub mod validation;

pub use error::{RunError, SceneError};
pub use scene::Scene;
