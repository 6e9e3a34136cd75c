//! Hard cases of issue 6, the two-dimensional half and the stability edges
//! (docs/hard_cases.md): a disk bouncing off a rigid wall, the colliding
//! rubber rings of Gray, Monaghan & Swift (2001) with and without artificial
//! stress, and the paper's bars and a coarse disk pair run at the edge of
//! stability. Each case is a scene in `scenes/hard/` whose header states the
//! exact answer and what is asserted here; every case runs on the CPU path
//! and, through `on_gpu`, on the GPU path.

#[path = "../common/mod.rs"]
mod common;

use std::path::Path;
use std::process::Command;
use std::sync::OnceLock;

use common::*;
use sphcontact::run::RunOutput;
use sphcontact::scene::{Backend, Shape};
use sphcontact::validation::exact::{
    hertz_c_inertia, hertz_disk_on_wall, ring_flexural_period, HERTZ_C_JOHNSON,
};

// ---------------------------------------------------------------------------
// 1. A disk bouncing off a rigid wall
// ---------------------------------------------------------------------------

/// The two-disk impact the wall case must reproduce (docs/method.md §8.5):
/// scenes/paper/disks_polar.toml (the same disk, at ±5 m/s) shortened to the
/// wall scene's end time. Run once per test binary, on the CPU path (the
/// oracle), and shared by the CPU and the GPU wall tests; the GPU two-disk
/// run itself is tests/paper_disks.rs's.
struct TwoDisks {
    times: Vec<f64>,
    force: Vec<f64>,
    peak: f64,
    contact_time: f64,
    restitution: f64,
}

mod disk_wall;
mod edge;
mod rings;
