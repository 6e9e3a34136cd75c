//! # sphcontact
//!
//! Smoothed Particle Hydrodynamics for impacts between elastic and
//! elasto-plastic solids, with the virtual-work penalty contact of Seo & Min
//! ("An elastic contact algorithm in SPH by virtual work principle").
//!
//! * [`scene`]: the scene file (TOML) and particle placement;
//! * [`physics`]: kernel, material model, exact answers;
//! * [`cpu`]: the f64 reference solver, one function per stage;
//! * [`run`]: running a scene to its outputs (history, summary);
//! * [`probe`]: the recorded observables.

pub mod cpu;
pub mod error;
pub mod math;
pub mod model;
pub mod output;
pub mod physics;
pub mod probe;
pub mod run;
pub mod scene;

pub use error::{RunError, SceneError};
pub use scene::Scene;
