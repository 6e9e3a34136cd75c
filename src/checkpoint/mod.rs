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
use crate::math::Sym;
use crate::model::ContactStats;
use crate::model::Diagnostics;
use crate::model::State;
use crate::scene::{Backend, Scene};

/// The checkpoint's file name in the output directory.
pub const FILE: &str = "checkpoint.bin";

const MAGIC: &[u8; 8] = b"SPHCKPT\n";
/// Version 6: the failure times of a state with a plastic history.
/// (Version 5: a scene without `[artificial_stress]` runs the default
/// close-pair form, so a version 4 checkpoint resumed would change its
/// physics.)
const VERSION: u64 = 6;

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
            .map_err(|e| RunError::Backend(format!("cannot encode the scene: {e}")))?;
        let mut w = Writer(MAGIC.to_vec());
        w.u64(VERSION);
        w.str(&self.scene_label);
        w.str(&scene);
        w.str(&self.backend.to_string());
        w.str(self.adapter.as_deref().unwrap_or(""));
        let l = &self.ledger;
        w.f64(l.base_energy);
        w.f64(l.momentum.x);
        w.f64(l.momentum.y);
        w.f64(l.stored0);
        w.u64(l.max_fallback as u64);
        w.f64(l.wall_seconds);
        w.u64(l.warnings.len() as u64);
        for s in &l.warnings {
            w.str(s);
        }
        let r = &self.recorder;
        w.f64s(&r.times);
        w.u64(r.rows.len() as u64);
        for row in &r.rows {
            w.f64s(row);
        }
        match &r.prev {
            Some((t, obs)) => {
                w.u64(1);
                w.f64(*t);
                w.f64s(obs);
            }
            None => w.u64(0),
        }
        w.u64(r.snapshots.len() as u64);
        for (t, f) in &r.snapshots {
            w.f64(*t);
            w.str(f);
        }
        w.f64(r.checkpoint_every);
        w.f64(r.next_checkpoint);
        match &self.solver {
            SolverState::Cpu(c) => {
                let CpuState {
                    state,
                    initial_dt,
                    energy_limit,
                    lists,
                    carried,
                } = &**c;
                // Kind 2 is kind 0 followed by the carried rates.
                w.u64(if carried.is_some() { 2 } else { 0 });
                w.f64(state.t);
                w.u64(state.step);
                w.vec2s(&state.x);
                w.vec2s(&state.v);
                w.f64s(&state.rho);
                w.f64s(&state.e);
                w.quads(state.s.iter().map(|s| [s.xx, s.yy, s.xy, s.zz]));
                w.f64(state.heat);
                w.f64(state.spring_work);
                w.f64s(&state.entry);
                w.f64s(&state.eps_p);
                w.f64s(&state.temperature);
                w.f64s(&state.damage);
                w.f64s(&state.failed_at);
                w.f64(initial_dt.unwrap_or(f64::NAN));
                w.f64(energy_limit.unwrap_or(f64::NAN));
                w.u32s(&lists.start);
                w.u32s(&lists.list);
                w.u32s(&lists.cross_start);
                w.u32s(&lists.cross);
                w.f64(lists.skin);
                w.vec2s(&lists.x_ref);
                if let Some((r, d)) = carried {
                    w.vec2s(&r.dv);
                    w.f64s(&r.de);
                    w.f64(r.heat_rate);
                    w.f64(r.spring_rate);
                    w.f64(d.cfl_dt);
                    w.u64(d.correction_fallback as u64);
                    w.u64(d.boundary_count as u64);
                    let c = &d.contact;
                    w.u64(c.pairs.len() as u64);
                    for &(a, b, f, p) in &c.pairs {
                        w.u32s(&[a, b]);
                        w.f64(f);
                        w.f64(p);
                    }
                    w.f64(c.stored);
                    w.f64(c.heat_rate);
                    w.f64(c.spring_rate);
                }
            }
            SolverState::Gpu(g) => {
                let d = &g.device;
                w.u64(1);
                w.u64(d.buffers.len() as u64);
                for (name, bytes) in &d.buffers {
                    w.str(name);
                    w.bytes(bytes);
                }
                w.u64(d.encoded);
                w.u64(d.delivered);
                w.u64(d.zero_seen as u64);
                w.f64(d.last_dt);
                w.f64(g.t_last);
                w.f64(g.stored_last);
            }
        }
        let sum = fnv1a(&w.0);
        w.u64(sum);
        Ok(w.0)
    }

    /// Decode a checkpoint file's bytes; `origin` names it in errors.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<Checkpoint, RunError> {
        let bad = |what: String| RunError::Backend(format!("{origin}: {what}"));
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
            let base_energy = r.f64()?;
            let momentum = DVec2::new(r.f64()?, r.f64()?);
            let stored0 = r.f64()?;
            let max_fallback = r.u64()? as u32;
            let wall_seconds = r.f64()?;
            let nw = r.count(8)?;
            let warnings = (0..nw).map(|_| r.str()).collect::<Result<_, _>>()?;
            let times = r.f64s()?;
            let nrows = r.count(8)?;
            let rows = (0..nrows)
                .map(|_| r.f64s())
                .collect::<Result<Vec<_>, _>>()?;
            let prev = match r.u64()? {
                0 => None,
                _ => Some((r.f64()?, r.f64s()?)),
            };
            let nsnap = r.count(16)?;
            let snapshots = (0..nsnap)
                .map(|_| Ok((r.f64()?, r.str()?)))
                .collect::<Result<_, String>>()?;
            let checkpoint_every = r.f64()?;
            let next_checkpoint = r.f64()?;
            let solver = match r.u64()? {
                kind @ (0 | 2) => {
                    let t = r.f64()?;
                    let step = r.u64()?;
                    let x = r.vec2s()?;
                    let v = r.vec2s()?;
                    let rho = r.f64s()?;
                    let e = r.f64s()?;
                    let s: Vec<Sym> = r
                        .quads()?
                        .into_iter()
                        .map(|[xx, yy, xy, zz]| Sym { xx, yy, xy, zz })
                        .collect();
                    let heat = r.f64()?;
                    let spring_work = r.f64()?;
                    let entry = r.f64s()?;
                    let eps_p = r.f64s()?;
                    let temperature = r.f64s()?;
                    let damage = r.f64s()?;
                    let failed_at = r.f64s()?;
                    let initial_dt = Some(r.f64()?).filter(|d| !d.is_nan());
                    let energy_limit = Some(r.f64()?).filter(|d| !d.is_nan());
                    let lists = Neighbours {
                        start: r.u32s()?,
                        list: r.u32s()?,
                        cross_start: r.u32s()?,
                        cross: r.u32s()?,
                        skin: r.f64()?,
                        x_ref: r.vec2s()?,
                        // The sweep's row index is rebuilt from the rows by
                        // the solver that resumes them.
                        ..Default::default()
                    };
                    let carried = if kind == 2 {
                        let dv = r.vec2s()?;
                        let de = r.f64s()?;
                        let (heat_rate, spring_rate) = (r.f64()?, r.f64()?);
                        let cfl_dt = r.f64()?;
                        let correction_fallback = r.u64()? as usize;
                        let boundary_count = r.u64()? as usize;
                        let np = r.count(24)?;
                        let pairs = (0..np)
                            .map(|_| {
                                let ab = r.u32s()?;
                                let [a, b] = ab[..] else {
                                    return Err("a contact pair is not two bodies".to_string());
                                };
                                Ok((a, b, r.f64()?, r.f64()?))
                            })
                            .collect::<Result<_, String>>()?;
                        let contact = ContactStats {
                            pairs,
                            stored: r.f64()?,
                            heat_rate: r.f64()?,
                            spring_rate: r.f64()?,
                        };
                        Some((
                            Rates {
                                dv,
                                de,
                                heat_rate,
                                spring_rate,
                                ..Default::default()
                            },
                            Diagnostics {
                                cfl_dt,
                                contact,
                                correction_fallback,
                                boundary_count,
                            },
                        ))
                    } else {
                        None
                    };
                    SolverState::Cpu(Box::new(CpuState {
                        state: State {
                            t,
                            step,
                            x,
                            v,
                            rho,
                            e,
                            s,
                            heat,
                            spring_work,
                            entry,
                            eps_p,
                            temperature,
                            damage,
                            failed_at,
                        },
                        initial_dt,
                        energy_limit,
                        lists,
                        carried,
                    }))
                }
                1 => {
                    let nb = r.count(16)?;
                    let buffers = (0..nb)
                        .map(|_| Ok((r.str()?, r.bytes()?.to_vec())))
                        .collect::<Result<_, String>>()?;
                    SolverState::Gpu(Box::new(GpuState {
                        device: RawDevice {
                            buffers,
                            encoded: r.u64()?,
                            delivered: r.u64()?,
                            zero_seen: r.u64()? as u32,
                            last_dt: r.f64()?,
                        },
                        t_last: r.f64()?,
                        stored_last: r.f64()?,
                    }))
                }
                k => return Err(format!("unknown solver kind {k}")),
            };
            if r.at != r.b.len() {
                return Err("trailing bytes after the state".into());
            }
            Ok(Checkpoint {
                scene_label,
                scene,
                backend,
                adapter,
                ledger: Ledger {
                    base_energy,
                    momentum,
                    stored0,
                    max_fallback,
                    wall_seconds,
                    warnings,
                },
                recorder: RecorderState {
                    times,
                    rows,
                    prev,
                    snapshots,
                    checkpoint_every,
                    next_checkpoint,
                },
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
            .map_err(|what| RunError::Backend(format!("{origin}: {what}")))
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
                    .map_or(true, |(r, _)| r.dv.len() == n && r.de.len() == n);
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
            RunError::Backend(format!(
                "{}: cannot read the checkpoint ({e}); was the run started with --checkpoint-every?",
                p.display()
            ))
        })?;
        Self::from_bytes(&bytes, &p.display().to_string())
    }
}

/// The checkpoint file of output directory `dir`.
pub fn path(dir: &Path) -> PathBuf {
    dir.join(FILE)
}

mod codec;
#[cfg(test)]
mod tests;

use codec::{fnv1a, Reader, Writer};
