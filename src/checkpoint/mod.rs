//! Checkpoints: the whole state of a run at one of its steps, written by
//! `run --checkpoint-every T` and continued by `run --resume DIR`.
//!
//! A resumed run gives the same history, byte for byte, as the run that was
//! never stopped, on either backend (on the GPU path, on the same adapter).
//! That takes more than the particles' state:
//!
//! * the CPU path saves its candidate neighbour lists with their reference
//!   positions: the lists fix the order of every SPH sum, and lists rebuilt
//!   at another step would add the same terms in another order;
//! * the GPU path saves its device buffers as they are (f32, in the
//!   device's cell order) and its step counters, rather than an f64 state
//!   that would be rounded again on upload;
//! * the recorder saves the history rows so far and the last observation,
//!   which the next row is interpolated from.
//!
//! Checkpoints never shorten a step: one is written at the first state at
//! or after each multiple of the interval (on the GPU path, where the host
//! sees the state between batches of steps, at the end of the batch sized
//! to reach that time: a step or two past it), so a run with checkpoints
//! takes the same steps as one without.
//!
//! The file (`checkpoint.bin` in the output directory) is written through a
//! temporary file and a rename, so a run killed while writing one leaves the
//! previous checkpoint whole. It is a versioned little-endian format closed
//! by a checksum; a damaged or foreign file is refused with a message, never
//! read into a state.

use glam::DVec2;
use std::path::{Path, PathBuf};

use crate::cpu::neighbours::Neighbours;
use crate::cpu::Rates;
use crate::error::RunError;
use crate::gpu::RawDevice;
use crate::model::Diagnostics;
use crate::model::State;
use crate::scene::{Backend, Scene};

/// The checkpoint's file name in the output directory.
pub const FILE: &str = "checkpoint.bin";

const MAGIC: &[u8; 8] = b"SPHCKPT\n";
/// Version 14: a state's tangential slips and frictional heat, and the
/// friction the leapfrog carries. (Version 12: a scene without `support` adapts its supports, and a state
/// whose supports are all round holds none (a version 11 checkpoint
/// resumed would change its physics). (Version 11: the carried ellipses
/// of supports that adapt within a band, and an adaptive scene without
/// `support_band` runs the default band.)
/// (Version 10: a scene's artificial stress without `work` takes only its
/// heat in bodies that can yield.) (Version 9: a scene without `stress_form` runs the variational stress
/// terms, so a version 8 checkpoint resumed would change its physics.
/// (Version 8: the cumulative artificial dissipation of a state and the
/// rate the leapfrog carries.) (Version 7: the supports' metrics of a state
/// whose supports adapt, and the lists' reaches. Version 6: the failure times of a state with a
/// plastic history.)
/// (Version 5: a scene without `[artificial_stress]` runs the default
/// close-pair form, so a version 4 checkpoint resumed would change its
/// physics.)
const VERSION: u64 = 15;

/// What the summary of the whole run needs from its start.
#[derive(Debug, Clone, PartialEq)]
pub struct Ledger {
    /// Total energy of the initial state without the stored penalty energy.
    pub base_energy: f64,
    /// Total momentum of the initial state.
    pub momentum: DVec2,
    /// Stored penalty energy at the first state.
    pub stored0: f64,
    /// Most particles at once on the identity correction so far.
    pub max_fallback: u32,
    /// Wall seconds the run took before this checkpoint.
    pub wall_seconds: f64,
    pub warnings: Vec<String>,
}

/// The recorder's state: the rows written so far, the observation the next
/// rows are interpolated from, the snapshots written and the next
/// checkpoint's time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RecorderState {
    pub times: Vec<f64>,
    pub rows: Vec<Vec<f64>>,
    pub prev: Option<(f64, Vec<f64>)>,
    pub snapshots: Vec<(f64, String)>,
    /// The checkpoint interval the run was started with, and the time of
    /// the checkpoint after this one.
    pub checkpoint_every: f64,
    pub next_checkpoint: f64,
}

/// The CPU solver's state: the particles, the first step (the reference
/// of the time-step collapse test), the energy guard's limit and the
/// candidate lists.
#[derive(Debug, Clone)]
pub struct CpuState {
    pub state: State,
    pub initial_dt: Option<f64>,
    /// The energy guard's limit, once set.
    pub energy_limit: Option<f64>,
    pub lists: Neighbours,
    /// The leapfrog's rates at the state ([`crate::cpu::CpuSolver::carried`]).
    pub carried: Option<(Rates, Diagnostics)>,
}

/// The GPU solver's state: the device's own, and the last delivered
/// state's time and stored penalty energy.
#[derive(Debug, Clone, PartialEq)]
pub struct GpuState {
    pub device: RawDevice,
    pub t_last: f64,
    pub stored_last: f64,
}

/// The solver's state.
#[derive(Debug, Clone)]
pub enum SolverState {
    Cpu(Box<CpuState>),
    Gpu(Box<GpuState>),
}

/// A whole checkpoint.
#[derive(Debug, Clone)]
pub struct Checkpoint {
    /// The scene as the summary names it (its path when run from a file).
    pub scene_label: String,
    /// The scene as run (an `--end-time` applied).
    pub scene: Scene,
    pub backend: Backend,
    pub adapter: Option<String>,
    pub ledger: Ledger,
    pub recorder: RecorderState,
    pub solver: SolverState,
}

impl Checkpoint {
    /// The simulated time of the saved state.
    pub fn time(&self) -> f64 {
        match &self.solver {
            SolverState::Cpu(c) => c.state.t,
            SolverState::Gpu(g) => g.t_last,
        }
    }

    /// Encode into the file format.
    pub fn to_bytes(&self) -> Result<Vec<u8>, RunError> {
        let scene = toml::to_string(&self.scene)
            .map_err(|e| RunError::checkpoint(FILE, format!("cannot encode the scene: {e}")))?;
        let mut w = Writer(MAGIC.to_vec());
        w.u64(VERSION);
        w.str(&self.scene_label);
        w.str(&scene);
        w.str(&self.backend.to_string());
        w.str(self.adapter.as_deref().unwrap_or(""));
        self.ledger.put(&mut w);
        self.recorder.put(&mut w);
        self.solver.put(&mut w);
        let sum = fnv1a(&w.0);
        w.u64(sum);
        Ok(w.0)
    }

    /// Decode a checkpoint file's bytes; `origin` names it in errors.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<Checkpoint, RunError> {
        let bad = |what: String| RunError::checkpoint(origin, what);
        if bytes.len() < MAGIC.len() + 16 || &bytes[..MAGIC.len()] != MAGIC {
            return Err(bad("not a sphcontact checkpoint".into()));
        }
        let (body, sum) = bytes.split_at(bytes.len() - 8);
        let sum = u64::from_le_bytes(sum.try_into().expect("8 bytes"));
        if fnv1a(body) != sum {
            return Err(bad(
                "the checkpoint is damaged (its checksum does not match); resume from an intact copy or rerun".into(),
            ));
        }
        let mut r = Reader {
            b: body,
            at: MAGIC.len(),
        };
        let decode = |r: &mut Reader| -> Result<Checkpoint, String> {
            let version = r.u64()?;
            if version != VERSION {
                return Err(format!(
                    "checkpoint format version {version}; this build reads version {VERSION}"
                ));
            }
            let scene_label = r.str()?;
            let scene_text = r.str()?;
            let scene = Scene::from_toml_str(&scene_text, "the checkpoint's scene")
                .map_err(|e| e.to_string())?;
            let backend = match r.str()?.as_str() {
                "cpu" => Backend::Cpu,
                "gpu" => Backend::Gpu,
                other => return Err(format!("unknown backend '{other}'")),
            };
            let adapter = Some(r.str()?).filter(|a| !a.is_empty());
            let ledger = Ledger::get(r)?;
            let recorder = RecorderState::get(r)?;
            let solver = SolverState::get(r)?;
            if r.at != r.b.len() {
                return Err("trailing bytes after the state".into());
            }
            Ok(Checkpoint {
                scene_label,
                scene,
                backend,
                adapter,
                ledger,
                recorder,
                solver,
            })
        };
        decode(&mut r).map_err(bad)
    }

    /// The saved arrays agree with `model` (the scene's, built by the run
    /// that resumes) and the history's width, so a state is never
    /// half-filled. `origin` names the checkpoint in the error.
    pub fn check_sizes(&self, model: &crate::model::Model, origin: &str) -> Result<(), RunError> {
        self.sizes_match(model.len(), model.contact, model.history)
            .map_err(|what| RunError::checkpoint(origin, what))
    }

    fn sizes_match(&self, n: usize, contact: bool, history: bool) -> Result<(), String> {
        let width = self.scene.probes.len();
        let r = &self.recorder;
        if r.rows.len() != r.times.len()
            || r.rows.iter().any(|row| row.len() != width)
            || r.prev.as_ref().is_some_and(|p| p.1.len() != width)
        {
            return Err("its history rows do not match the scene's probes".into());
        }
        if let SolverState::Cpu(c) = &self.solver {
            let (state, lists) = (&c.state, &c.lists);
            let ok = state.x.len() == n
                && state.v.len() == n
                && state.rho.len() == n
                && state.e.len() == n
                && state.s.len() == n
                && state.entry.len() == if contact { n } else { 0 }
                && [
                    &state.eps_p,
                    &state.temperature,
                    &state.damage,
                    &state.failed_at,
                ]
                .iter()
                .all(|a| a.len() == if history { n } else { 0 })
                && lists.start.len() == n + 1
                && lists.cross_start.len() == n + 1
                && lists.x_ref.len() == n
                && lists
                    .start
                    .last()
                    .is_some_and(|&k| k as usize == lists.list.len())
                && lists
                    .cross_start
                    .last()
                    .is_some_and(|&k| k as usize == lists.cross.len())
                && lists
                    .list
                    .iter()
                    .chain(&lists.cross)
                    .all(|&j| (j as usize) < n)
                && c.carried
                    .as_ref()
                    .is_none_or(|(r, _)| r.dv.len() == n && r.de.len() == n);
            if !ok {
                return Err(format!(
                    "its particle arrays do not match the scene's {n} particles"
                ));
            }
        }
        Ok(())
    }

    /// Write atomically to `dir/checkpoint.bin`.
    pub fn write(&self, dir: &Path) -> Result<(), RunError> {
        crate::output::write_atomic(&path(dir), &self.to_bytes()?)
    }

    /// Read `dir/checkpoint.bin`.
    pub fn read(dir: &Path) -> Result<Checkpoint, RunError> {
        let p = path(dir);
        let bytes = std::fs::read(&p).map_err(|e| {
            RunError::checkpoint(
                p.display().to_string(),
                format!("cannot read the checkpoint ({e}); was the run started with --checkpoint-every?"),
            )
        })?;
        Self::from_bytes(&bytes, &p.display().to_string())
    }
}

/// The checkpoint file of output directory `dir`.
pub fn path(dir: &Path) -> PathBuf {
    dir.join(FILE)
}

mod codec;
mod records;
#[cfg(test)]
mod tests;

use codec::{fnv1a, Reader, Record, Writer};
