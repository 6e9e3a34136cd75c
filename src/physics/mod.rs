//! Plain functions of scalars: the kernel, the material model and the exact
//! answers of the paper's cases. Used by the CPU path (and mirrored by the
//! shaders of the GPU path).

pub mod exact;
pub mod johnson_cook;
pub mod kernel;
pub mod material;
pub mod penalty;
pub mod strength;
