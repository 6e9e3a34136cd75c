//! Plain functions of scalars and small tensors: the kernel, the material
//! model, the artificial viscosity and stress, the penalty law and the
//! strength and failure laws; they depend on [`crate::math`] alone. Used by the CPU path (and
//! mirrored by the shaders of the GPU path); the exact answers of the
//! validation cases are in [`crate::validation::exact`].

pub mod eos;
pub mod failure;
pub mod kernel;
pub mod laws;
pub mod material;
pub mod penalty;
pub mod strength;
pub mod support;
pub mod tension;
pub mod viscosity;
