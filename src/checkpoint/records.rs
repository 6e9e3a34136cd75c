//! Each record of the checkpoint file, written and read in one place:
//! the ledger, the recorder, the CPU solver's state (particles, lists,
//! the leapfrog's carried rates) and the GPU solver's.

use super::codec::{record, Reader, Record, Writer};
use super::{CpuState, GpuState, Ledger, RecorderState, SolverState};
use crate::cpu::contact::Friction;
use crate::cpu::neighbours::Neighbours;
use crate::cpu::Rates;
use crate::gpu::RawDevice;
use crate::math::Sym;
use crate::model::{ContactStats, Diagnostics, State};

impl Record for Ledger {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        self.base_energy.put(w);
        self.momentum.put(w);
        self.stored0.put(w);
        (self.max_fallback as u64).put(w);
        self.wall_seconds.put(w);
        self.warnings.put(w);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(Ledger {
            base_energy: Record::get(r)?,
            momentum: Record::get(r)?,
            stored0: Record::get(r)?,
            max_fallback: r.u64()? as u32,
            wall_seconds: Record::get(r)?,
            warnings: Record::get(r)?,
        })
    }
}

record!(RecorderState {
    times,
    rows,
    prev,
    snapshots,
    checkpoint_every,
    next_checkpoint
});

/// The deviatoric stresses as one list of their four components each.
impl Record for State {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        self.t.put(w);
        self.step.put(w);
        self.x.put(w);
        self.v.put(w);
        self.rho.put(w);
        self.e.put(w);
        w.quads(self.s.iter().map(|s| [s.xx, s.yy, s.xy, s.zz]));
        self.heat.put(w);
        self.dissipation.put(w);
        self.spring_work.put(w);
        self.entry.put(w);
        self.slip.put(w);
        self.slip_stiffness.put(w);
        self.sliding.put(w);
        self.friction_heat.put(w);
        self.eps_p.put(w);
        self.temperature.put(w);
        self.damage.put(w);
        self.failed_at.put(w);
        self.metric.put(w);
        self.carried.put(w);
        self.held_impulse.put(w);
        self.held_work.put(w);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(State {
            t: Record::get(r)?,
            step: Record::get(r)?,
            x: Record::get(r)?,
            v: Record::get(r)?,
            rho: Record::get(r)?,
            e: Record::get(r)?,
            s: r.quads()?
                .into_iter()
                .map(|[xx, yy, xy, zz]| Sym { xx, yy, xy, zz })
                .collect(),
            heat: Record::get(r)?,
            dissipation: Record::get(r)?,
            spring_work: Record::get(r)?,
            entry: Record::get(r)?,
            slip: Record::get(r)?,
            slip_stiffness: Record::get(r)?,
            sliding: Record::get(r)?,
            friction_heat: Record::get(r)?,
            eps_p: Record::get(r)?,
            temperature: Record::get(r)?,
            damage: Record::get(r)?,
            failed_at: Record::get(r)?,
            metric: Record::get(r)?,
            carried: Record::get(r)?,
            held_impulse: Record::get(r)?,
            held_work: Record::get(r)?,
        })
    }
}

// The sweep's row layout is not saved: the solver that resumes the lists
// rebuilds it from the rows.
record!(
    Neighbours {
        start,
        list,
        cross_start,
        cross,
        skin,
        x_ref,
        support_ref
    }..Default::default()
);

/// Each pair as its two bodies (a list of two), its force and its largest
/// pressure.
impl Record for ContactStats {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        w.u64(self.pairs.len() as u64);
        for &(a, b, f, p) in &self.pairs {
            // The two bodies as a list of two.
            w.u64(2);
            a.put(w);
            b.put(w);
            f.put(w);
            p.put(w);
        }
        self.stored.put(w);
        self.heat_rate.put(w);
        self.spring_rate.put(w);
        self.friction_rate.put(w);
        w.u64(self.tangential.len() as u64);
        for &(a, b, t) in &self.tangential {
            a.put(w);
            b.put(w);
            t.iter().for_each(|x| x.put(w));
        }
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        let np = r.count(24)?;
        let pairs = (0..np)
            .map(|_| {
                let [a, b] = Vec::<u32>::get(r)?[..] else {
                    return Err("a contact pair is not two bodies".to_string());
                };
                Ok((a, b, r.f64()?, r.f64()?))
            })
            .collect::<Result<_, String>>()?;
        Ok(ContactStats {
            pairs,
            stored: Record::get(r)?,
            heat_rate: Record::get(r)?,
            spring_rate: Record::get(r)?,
            friction_rate: Record::get(r)?,
            tangential: {
                let n = r.count(32)?;
                (0..n)
                    .map(|_| {
                        let a: u32 = Record::get(r)?;
                        let b: u32 = Record::get(r)?;
                        Ok((a, b, [r.f64()?, r.f64()?, r.f64()?]))
                    })
                    .collect::<Result<_, String>>()?
            },
        })
    }
}

/// The leapfrog's carried rates: `dv`, `de` and the totals, with the
/// diagnostics of their evaluation.
impl Record for (Rates, Diagnostics) {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        let (r, d) = self;
        r.dv.put(w);
        r.de.put(w);
        r.heat_rate.put(w);
        r.spring_rate.put(w);
        r.dissipation_rate.put(w);
        r.friction_rate.put(w);
        put_friction(&r.friction, w);
        d.cfl_dt.put(w);
        (d.correction_fallback as u64).put(w);
        (d.boundary_count as u64).put(w);
        d.contact.put(w);
        d.held_force.put(w);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        let rates = Rates {
            dv: Record::get(r)?,
            de: Record::get(r)?,
            heat_rate: Record::get(r)?,
            spring_rate: Record::get(r)?,
            dissipation_rate: Record::get(r)?,
            friction_rate: Record::get(r)?,
            friction: get_friction(r)?,
            ..Default::default()
        };
        let diag = Diagnostics {
            cfl_dt: Record::get(r)?,
            correction_fallback: r.u64()? as usize,
            boundary_count: r.u64()? as usize,
            contact: Record::get(r)?,
            held_force: Record::get(r)?,
        };
        Ok((rates, diag))
    }
}

/// The carried rates' friction: its length, then each entry's particle,
/// stiffness, limit and rate.
fn put_friction(f: &[(u32, Friction)], w: &mut Writer) {
    w.u64(f.len() as u64);
    for &(i, fr) in f {
        i.put(w);
        fr.stiffness.put(w);
        fr.cap.put(w);
        fr.rate.put(w);
        fr.sliding.put(w);
    }
}

fn get_friction(r: &mut Reader) -> Result<Vec<(u32, Friction)>, String> {
    let n = r.count(29)?;
    (0..n)
        .map(|_| {
            let i: u32 = Record::get(r)?;
            let stiffness = Record::get(r)?;
            let cap = Record::get(r)?;
            let rate = Record::get(r)?;
            let sliding = Record::get(r)?;
            Ok((
                i,
                Friction {
                    stiffness,
                    cap,
                    rate,
                    sliding,
                },
            ))
        })
        .collect()
}

/// A number that may be unset, as NaN when it is.
fn put_maybe(v: Option<f64>, w: &mut Writer) {
    w.f64(v.unwrap_or(f64::NAN));
}

fn get_maybe(r: &mut Reader) -> Result<Option<f64>, String> {
    Ok(Some(r.f64()?).filter(|d| !d.is_nan()))
}

/// The device's buffers as (name, bytes), its counters and last step.
impl Record for GpuState {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        let d = &self.device;
        w.u64(d.buffers.len() as u64);
        for (name, bytes) in &d.buffers {
            w.str(name);
            w.bytes(bytes);
        }
        d.encoded.put(w);
        d.delivered.put(w);
        (d.zero_seen as u64).put(w);
        d.last_dt.put(w);
        self.t_last.put(w);
        self.stored_last.put(w);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        let nb = r.count(16)?;
        let buffers = (0..nb)
            .map(|_| Ok((r.str()?, r.bytes()?.to_vec())))
            .collect::<Result<_, String>>()?;
        Ok(GpuState {
            device: RawDevice {
                buffers,
                encoded: Record::get(r)?,
                delivered: Record::get(r)?,
                zero_seen: r.u64()? as u32,
                last_dt: Record::get(r)?,
            },
            t_last: Record::get(r)?,
            stored_last: Record::get(r)?,
        })
    }
}

/// The solver's kind first: 0 the CPU's, 2 the CPU's with the leapfrog's
/// carried rates (after its lists), 1 the GPU's.
impl Record for SolverState {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        match self {
            SolverState::Cpu(c) => {
                w.u64(if c.carried.is_some() { 2 } else { 0 });
                c.state.put(w);
                put_maybe(c.initial_dt, w);
                put_maybe(c.energy_limit, w);
                c.lists.put(w);
                if let Some(carried) = &c.carried {
                    carried.put(w);
                }
            }
            SolverState::Gpu(g) => {
                w.u64(1);
                g.put(w);
            }
        }
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(match r.u64()? {
            kind @ (0 | 2) => SolverState::Cpu(Box::new(CpuState {
                state: Record::get(r)?,
                initial_dt: get_maybe(r)?,
                energy_limit: get_maybe(r)?,
                lists: Record::get(r)?,
                carried: if kind == 2 {
                    Some(Record::get(r)?)
                } else {
                    None
                },
            })),
            1 => SolverState::Gpu(Box::new(Record::get(r)?)),
            k => return Err(format!("unknown solver kind {k}")),
        })
    }
}
