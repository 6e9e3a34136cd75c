//! The solver's device buffers: made within the adapter's limits and the
//! memory budget, each only where the scene needs it, in the precision
//! plan's form ([`super::buffers`] names them).

use super::build::{body_table, initial_control, plastic_gpu};
use super::*;

/// The contact's two gather buffers and the pass-scratch buffer each lives
/// in, if the scene has one (else it gets its own).
///
/// The contact's `cshare` (pass 1 → pass 2) and `cown` (pass 1 → pass 2
/// and the reductions after the first evaluation) are written after the forces pass
/// and dead before the next kinematics pass. The correction matrices (`lmat`), the
/// velocity gradients (`gradv`, reconstructed viscosity) are written by the
/// kinematics pass and last read by the forces pass, and no
/// kernel binds one of them together with the contact buffer it hosts (the
/// reorder uses `lmat` and `cown` as scratch, at the start of a step, as
/// two different buffers). So `cshare` lives in `lmat`, and `cown` in
/// `gradv` when the scene has it: 16 or 32 bytes a particle less. Where
/// adaptive supports are carried with `gradv` (kernels.rs,
/// `support_gradient`), it is live until the step's end, and the midpoint
/// rule's second evaluation keeps both entries on the list (`cown_e`,
/// `cshare_e`, as the leapfrog's force passes do).
/// In the same way the stored spring energy (an observation) goes to
/// `sr2c.x` (`σ_xx/ρ²`, dead after the forces pass; the reductions read only its
/// sound speed `w`), written by the particle's own thread in contact pass 1,
/// which reads no other part of `sr2c`.
///
/// The leapfrog's first evaluation and its booking (after the energy walk,
/// the scratch's last reader) use the same homes; `cown` then carries the
/// forces to the next step's reductions, through the reorder (whose
/// scratch is `lmat`). Its force passes, before the energy walk, keep the
/// entries on the list of boundary particles instead (`cown_e`, `cshare_e`;
/// contact.wgsl).
pub(super) fn contact_homes(model: &Model) -> [(Buf, Option<Buf>); 2] {
    let own_home = model.keeps_gradient().then_some(Buf::Gradv);
    [(Buf::Cshare, Some(Buf::Lmat)), (Buf::Cown, own_home)]
}

/// A buffer another lives in, made by then (`contact_homes`, `mask_home`).
pub(super) fn made(buffers: &DeviceBuffers, home: Buf) -> &wgpu::Buffer {
    buffers
        .get(home)
        .unwrap_or_else(|| panic!("'{}' is made before what lives in it", home.name()))
}

/// Places on the contact's list of boundary particles (kinematics.wgsl,
/// list_surface) that a solver for `n` particles starts with: the boundary
/// of a body large enough to matter for memory is a small share of it
/// (3.2 % of the benchmark's disks at 2e4, 1.4 % at 1e5, 0.25 % at 4e6),
/// so a thirty-second and a margin: 2.4 bytes a particle at 4e6 for the
/// 76 bytes a place holds. A list that the state a run starts from fills
/// past three quarters is lengthened before its first step, and one that
/// fills so during the run pauses it to be made twice as long
/// ([`GpuSolver::run_batch`]).
pub(super) fn surf_capacity(n: usize) -> u32 {
    (n / 32 + 512).min(n).min(MAX_SURF_CAP) as u32
}

/// The most entries the list of boundary particles may have: the kinematics pass writes
/// a particle's place there as a float (kinematics.wgsl, list_surface).
pub(super) const MAX_SURF_CAP: usize = 1 << 24;

/// Where the leapfrog's neighbour masks (common.wgsl) live: with contact in
/// `qrate`, the contact's rates for the ledger's next half step, which the
/// booking writes after the energy walk (the masks' last reader) and the
/// next step's drift reads before the kinematics pass writes the masks again; the first
/// evaluation's contact writes it after its forces pass too. Only the boundary
/// particles' entries are rates (the drift reads no others). Without
/// contact (`None`), in a buffer of their own.
pub(super) fn mask_home(model: &Model) -> Option<Buf> {
    (model.integrator == Integrator::Leapfrog && model.contact).then_some(Buf::Qrate)
}

/// The GPU's particle-probe tables from the plan's `(particle, code)` list:
/// the probed particle ids sorted and deduplicated, padded with `u32::MAX`
/// to one entry a probe, and each probe as `(entry, code)`.
pub(super) fn probe_tables(particles: &[[u32; 2]]) -> (Vec<u32>, Vec<[u32; 2]>) {
    let mut ids: Vec<u32> = particles.iter().map(|p| p[0]).collect();
    ids.sort_unstable();
    ids.dedup();
    let refs = particles
        .iter()
        .map(|p| {
            [
                ids.binary_search(&p[0]).expect("an id of the list") as u32,
                p[1],
            ]
        })
        .collect();
    ids.resize(particles.len(), u32::MAX);
    (ids, refs)
}

/// Makes the solver's device buffers within the adapter's limits and the
/// device memory the solver may take, counting their bytes.
pub(super) struct Maker<'a> {
    ctx: &'a GpuContext,
    n: usize,
    max_binding: u64,
    max_buffer: u64,
    /// The device memory the solver may take, if limited, and what limits
    /// it.
    budget: Option<(u64, &'static str)>,
    bytes: u64,
    buffers: DeviceBuffers,
}

impl<'a> Maker<'a> {
    pub(super) fn new(ctx: &'a GpuContext, opts: &GpuOptions, n: usize) -> Self {
        let limits = &ctx.limits;
        let max_binding = opts
            .max_binding_size
            .map_or(limits.max_storage_buffer_binding_size, |m| {
                m.min(limits.max_storage_buffer_binding_size)
            });
        let budget = match (opts.max_device_bytes, ctx.memory_budget) {
            (Some(a), Some(b)) if b < a => Some((b, "SPHCONTACT_GPU_MEMORY")),
            (Some(a), _) => Some((a, "the solver's device-memory limit")),
            (None, Some(b)) => Some((b, "SPHCONTACT_GPU_MEMORY")),
            (None, None) => None,
        };
        Maker {
            ctx,
            n,
            max_binding,
            max_buffer: limits.max_buffer_size,
            budget,
            bytes: 0,
            buffers: DeviceBuffers::default(),
        }
    }

    /// A device buffer for storage and copies, and any `extra` use.
    /// Past the budget the buffers are only counted, for the error to
    /// say how much the scene needs.
    pub(super) fn make_as(
        &mut self,
        name: Buf,
        size: u64,
        data: Option<&[u8]>,
        extra: wgpu::BufferUsages,
    ) -> Result<(), String> {
        let (n, max_binding, max_buffer) = (self.n, self.max_binding, self.max_buffer);
        let size = size.max(16).next_multiple_of(4);
        if size > max_binding || size > max_buffer {
            let (limit, which) = if max_binding <= max_buffer {
                (
                    max_binding,
                    "storage binding (max_storage_buffer_binding_size)",
                )
            } else {
                (max_buffer, "buffer (max_buffer_size)")
            };
            return Err(format!(
                "the scene does not fit this adapter: its {n} particles need a {size}-byte \
                 device buffer '{}', and the adapter allows {limit} bytes a {which}; at \
                 most {} particles fit; use fewer particles or --backend cpu",
                name.name(),
                particles_within(limit)
            ));
        }
        self.bytes += size;
        if self.budget.is_some_and(|b| self.bytes > b.0) {
            return Ok(());
        }
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST
            | extra;
        let buf = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(name.name()),
            size,
            usage,
            mapped_at_creation: false,
        });
        if let Some(d) = data {
            self.ctx.queue.write_buffer(&buf, 0, d);
        }
        self.buffers.set(name, buf);
        Ok(())
    }

    pub(super) fn make(&mut self, name: Buf, size: u64, data: Option<&[u8]>) -> Result<(), String> {
        self.make_as(name, size, data, wgpu::BufferUsages::empty())
    }

    /// The buffers and their bytes, or why the scene does not fit: past
    /// the budget, or refused by the device (`oom`, the error scope the
    /// buffers were made in).
    pub(super) fn finish(self, oom: wgpu::ErrorScopeGuard) -> Result<(DeviceBuffers, u64), String> {
        let (n, device_bytes, budget) = (self.n, self.bytes, self.budget);
        let per_particle = device_bytes as f64 / n.max(1) as f64;
        if let Some((b, what)) = budget.filter(|b| device_bytes > b.0) {
            return Err(format!(
                "the scene does not fit the device memory the solver may take: its {n} particles \
             need {device_bytes} bytes of device buffers ({per_particle:.1} a particle), and \
             {what} allows {b}; about {} particles fit; use fewer particles or --backend cpu",
                (b as f64 / per_particle).floor() as u64
            ));
        }
        if let Some(e) = pollster::block_on(oom.pop()) {
            return Err(format!(
                "the scene does not fit this adapter's memory: its {n} particles need \
             {device_bytes} bytes of device buffers ({per_particle:.1} a particle), and the \
             device refused them ({e}); use fewer particles (SPHCONTACT_GPU_MEMORY set to \
             the device's free memory gives the count that fits) or --backend cpu"
            ));
        }
        Ok((self.buffers, device_bytes))
    }
}

/// The state's buffers (precision plan): positions as reference cells and
/// offsets, velocities, density and energy, stresses, the particles'
/// constants; the plastic history with its laws' constants; the close
/// pairs' scales; a body of revolution's areas and hoop term.
pub(super) fn make_state(
    mk: &mut Maker,
    model: &Model,
    state: &State,
    frame: &Frame,
) -> Result<(), String> {
    let (n, origin, cell) = (model.len(), frame.origin, frame.cell);
    let leapfrog = model.integrator == Integrator::Leapfrog;
    // Per-particle arrays, in the model's order to start with.
    // Reference cell and offset in it (precision plan), from f64.
    let x0: Vec<[f32; 4]> = state
        .x
        .iter()
        .map(|p| {
            let d = (*p - origin) / cell;
            let c = d.floor();
            let off = *p - origin - c * cell;
            [c.x as f32, c.y as f32, off.x as f32, off.y as f32]
        })
        .collect();
    let zeros2 = vec![[0f32; 2]; n];
    let v: Vec<[f32; 2]> = state.v.iter().map(|p| [p.x as f32, p.y as f32]).collect();
    // The device keeps the density itself where the state of a body of
    // revolution keeps eta = 2 pi r rho.
    let r: Vec<[f32; 2]> = (0..n)
        .map(|i| {
            let rho0 = model.material(i).rho0;
            let rho = model.density(state.rho[i], state.x[i]);
            [(rho / rho0 - 1.0) as f32, state.e[i] as f32]
        })
        .collect();
    let s: Vec<[f32; 4]> = state
        .s
        .iter()
        .map(|s| [s.xx as f32, s.yy as f32, s.xy as f32, s.zz as f32])
        .collect();
    let meta: Vec<[u32; 4]> = (0..n)
        .map(|i| {
            [
                (model.mass[i] as f32).to_bits(),
                (model.offset[i] as f32).to_bits(),
                model.body[i],
                i as u32,
            ]
        })
        .collect();
    let hist: Vec<[f32; 4]> = if model.history {
        (0..n)
            .map(|i| {
                let room = model.material(i).initial_temperature();
                [
                    state.eps_p[i] as f32,
                    (state.temperature[i] - room) as f32,
                    state.damage[i] as f32,
                    state.failed_at[i] as f32,
                ]
            })
            .collect()
    } else {
        Vec::new()
    };
    let nn = n as u64;
    mk.make(Buf::X0, 16 * nn, Some(bytemuck::cast_slice(&x0)))?;
    mk.make(Buf::U, 8 * nn, Some(bytemuck::cast_slice(&zeros2)))?;
    mk.make(Buf::V, 8 * nn, Some(bytemuck::cast_slice(&v)))?;
    mk.make(Buf::R, 8 * nn, Some(bytemuck::cast_slice(&r)))?;
    mk.make(Buf::S, 16 * nn, Some(bytemuck::cast_slice(&s)))?;
    mk.make(Buf::Pinfo, 16 * nn, Some(bytemuck::cast_slice(&meta)))?;
    if model.history {
        // The plastic history (strength.wgsl's precision plan), its
        // laws' constants a body, and the midpoint rule's midpoint
        // history and strain rates.
        mk.make(Buf::Hist, 16 * nn, Some(bytemuck::cast_slice(&hist)))?;
        let plastic: Vec<PlasticGpu> = model
            .bodies
            .iter()
            .map(|b| plastic_gpu(&b.material))
            .collect();
        mk.make(
            Buf::Plastic,
            size_of_val(plastic.as_slice()) as u64,
            Some(bytemuck::cast_slice(&plastic)),
        )?;
        if !leapfrog {
            mk.make(Buf::Histm, 16 * nn, None)?;
            if model.strain_rate {
                mk.make(Buf::Srate, 4 * nn, None)?;
            }
        }
    }
    if !model.close_scale.is_empty() {
        // By original index (pinfo.w): constant, never permuted. Not
        // made when every scale is 1 (ART_KAPPA off).
        let k2: Vec<f32> = model.close_scale.iter().map(|&k| k as f32).collect();
        mk.make(Buf::Kappa, 4 * nn, Some(bytemuck::cast_slice(&k2)))?;
    }
    if !model.held.is_empty() || !model.share.is_empty() {
        make_held(mk, model, state)?;
    }
    if model.axisymmetric {
        // Each particle's area as placed, by original index (the
        // contact normals' reference volumes), and the hoop stress's
        // acceleration sigma_tt / (r rho) of an evaluation
        // (kinematics.wgsl to forces.wgsl).
        let a0: Vec<f32> = model.area0.iter().map(|&a| a as f32).collect();
        mk.make(Buf::Area0, 4 * nn, Some(bytemuck::cast_slice(&a0)))?;
        mk.make(Buf::Hoop, 4 * nn, None)?;
    }
    Ok(())
}

/// The clamped and driven regions (common.wgsl, HELD), by original index,
/// never permuted: each region's held components (bit 0 x, bit 1 y) and
/// velocity, then each particle's region (`Model::held_of`); and the
/// impulse the regions gave each particle, a state's region impulse in
/// its first particle's entry.
fn make_held(mk: &mut Maker, model: &Model, state: &State) -> Result<(), String> {
    let mut table: Vec<u32> = Vec::with_capacity(4 * model.held.len() + model.len());
    for c in &model.held {
        let mask = (c.mask.x > 0.0) as u32 | ((c.mask.y > 0.0) as u32) << 1;
        let (vx, vy) = (c.velocity.x as f32, c.velocity.y as f32);
        table.extend([mask, vx.to_bits(), vy.to_bits(), 0]);
    }
    // The symmetry planes a particle lies on: its word's top two bits
    // (common.wgsl, ON_PLANES).
    table.extend((0..model.len()).map(|i| {
        let k = model.held_of.get(i).copied().unwrap_or(0);
        k | u32::from(model.on_plane.get(i).copied().unwrap_or(0)) << 30
    }));
    if model.held.is_empty() {
        mk.make(
            Buf::Held,
            4 * table.len() as u64,
            Some(bytemuck::cast_slice(&table)),
        )?;
        return Ok(());
    }
    mk.make(
        Buf::Held,
        4 * table.len() as u64,
        Some(bytemuck::cast_slice(&table)),
    )?;
    let mut w = vec![[0f32; 4]; model.len()];
    for (c, j) in model.held.iter().zip(&state.held_impulse) {
        if let Some(&i) = c.particles.first() {
            let ((xh, xl), (yh, yl)) = (split(j.x), split(j.y));
            w[i] = [xh, yh, xl, yl];
        }
    }
    mk.make(
        Buf::HeldW,
        16 * model.len() as u64,
        Some(bytemuck::cast_slice(&w)),
    )?;
    Ok(())
}

/// The integrator's, the contact's and the supports' buffers: what the
/// scene's scheme carries between passes and steps, and no more.
pub(super) fn make_scheme(
    mk: &mut Maker,
    model: &Model,
    state: &State,
    surf_cap: u32,
) -> Result<(), String> {
    let (n, nn) = (model.len(), model.len() as u64);
    let leapfrog = model.integrator == Integrator::Leapfrog;
    let contact = model.contact;
    if model.correction == Correction::Gradient && !leapfrog {
        // The base pass's debris, a bit a particle, for the midpoint
        // pass (kinematics.wgsl, walk_and_correct).
        mk.make(Buf::DebrisBits, 4 * nn.div_ceil(32), None)?;
    }
    if leapfrog {
        // The carried rates a_n and (_, de_n/dt), and the predicted
        // velocity (common.wgsl, LEAP); buffers wgpu zeroes.
        for name in [Buf::Acc, Buf::Rdt, Buf::Vstar] {
            mk.make(name, 8 * nn, None)?;
        }
        if mask_home(model).is_none() {
            mk.make(Buf::Nmask, 8 * nn, None)?;
        }
        if contact {
            mk.make(Buf::Qrate, 8 * nn, None)?;
            // The force passes' entries, on the list.
            for name in [Buf::CownE, Buf::CshareE] {
                mk.make(name, 16 * surf_cap as u64, None)?;
            }
        }
    } else {
        // The midpoint state; the evaluation at the base state leaves
        // its rates there (common.wgsl, MID), so there are no rate
        // buffers.
        for name in [Buf::Um, Buf::Vm, Buf::Rm, Buf::Sm] {
            mk.make(name, if name == Buf::Sm { 16 } else { 8 } * nn, None)?;
        }
        if contact && supports_carried_by_gradv(model) {
            // The second evaluation's entries, on the list: its pass
            // scratch (`gradv`) carries the supports' gradient on to
            // the step's end (contact.wgsl, on_list).
            for name in [Buf::CownE, Buf::CshareE] {
                mk.make(name, 16 * surf_cap as u64, None)?;
            }
        }
    }
    for name in [Buf::Lmat, Buf::Nbo, Buf::Sr2c] {
        mk.make(name, 16 * nn, None)?;
    }
    if model.keeps_gradient() {
        mk.make(Buf::Gradv, 16 * nn, None)?;
    }
    if model.dispersion > 0.0 {
        for name in [Buf::Gdisp, Buf::Sdisp] {
            mk.make(name, 16 * nn, None)?;
        }
    }
    if leapfrog && model.hourglass > 0.0 {
        // The velocity v_{n+1/2} the hourglass control sees in a step
        // and its gradient (common.wgsl, HG_HALF).
        mk.make(Buf::Vhalf, 8 * nn, None)?;
        mk.make(Buf::Gradh, 16 * nn, None)?;
    }
    if model.adaptive {
        // Each particle's support (f32), and the velocity gradient
        // the step's end carries it with (kinematics.wgsl to
        // advance.wgsl) unless the viscosity's is that one.
        // With a band the carried ellipses (common.wgsl, BAND).
        let held = if model.carries_band() {
            &state.carried
        } else {
            &state.metric
        };
        let q: Vec<[f32; 4]> = held
            .iter()
            .map(|q| [q.xx as f32, q.xy as f32, q.yy as f32, 0.0])
            .collect();
        mk.make(Buf::Metric, 16 * nn, Some(bytemuck::cast_slice(&q)))?;
        if !supports_carried_by_gradv(model) {
            // dt l in f16 pairs (common.wgsl, pack_step_gradient).
            mk.make(Buf::Lgrad, 8 * nn, None)?;
        }
    }
    if model.dissipates() {
        // Per workgroup of particles: the artificial dissipation
        // booked (compensated) and the leapfrog's carried rate
        // (forces.wgsl); a state's total starts in the first.
        let mut d = vec![[0f32; 4]; particle_groups(n) as usize];
        let (hi, lo) = split(state.dissipation);
        d[0] = [hi, lo, 0.0, 0.0];
        mk.make(
            Buf::Dheat,
            16 * particle_groups(n),
            Some(bytemuck::cast_slice(&d)),
        )?;
    }
    if contact {
        make_contact(mk, model, state, surf_cap)?;
    }
    Ok(())
}

/// What a contact carries between passes and steps.
pub(super) fn make_contact(
    mk: &mut Maker,
    model: &Model,
    state: &State,
    surf_cap: u32,
) -> Result<(), String> {
    let (n, nn) = (model.len(), model.len() as u64);
    let leapfrog = model.integrator == Integrator::Leapfrog;
    // Per particle: (dashpot heat booked, spring work of its passes).
    mk.make(
        Buf::Qheat,
        8 * nn,
        Some(bytemuck::cast_slice(&vec![0f32; 2 * n])),
    )?;
    // What a boundary particle carries between the contact's passes
    // on the list of boundary particles (kinematics.wgsl,
    // list_surface): the list, the normals, the spring's derivative
    // and dPhi/dg (contact.wgsl); the midpoint rule's contact areas
    // too, which the leapfrog carries a particle from step to step
    // (common.wgsl, area_index).
    let cap = surf_cap as u64;
    mk.make(Buf::Surf, 4 * cap, None)?;
    for name in [Buf::Cn, Buf::Cbar0, Buf::Cbar1, Buf::Ckeep] {
        mk.make(name, 16 * cap, None)?;
    }
    mk.make(Buf::Bt, 4 * cap, None)?;
    mk.make(Buf::Area, 4 * if leapfrog { nn } else { cap }, None)?;
    // The spread's claims, a bit a particle (spread.wgsl).
    mk.make(Buf::Claim, 4 * nn.div_ceil(32), None)?;
    let entry: Vec<f32> = state.entry.iter().map(|&e| e as f32).collect();
    mk.make(Buf::Centry, 4 * nn, Some(bytemuck::cast_slice(&entry)))?;
    if model.rubs {
        make_friction(mk, model, state, cap)?;
    }
    // The two gather buffers share memory with pass scratch where
    // the scene has it (below); the rest get their own.
    for (name, home) in contact_homes(model) {
        if home.is_none() {
            mk.make(name, 16 * nn, None)?;
        }
    }
    Ok(())
}

/// Coulomb friction's buffers (contact.wgsl, RUB): each particle's slip
/// by original index, never permuted, `(u, f A k_t` (negative while it
/// slides), `u` at the midpoint, its frictional heat`)`, a state's
/// frictional heat in the first particle's entry; each particle's friction
/// in an evaluation and what its rub pass hands on, by original index;
/// what the rub pass reads, on the list; the coefficients of each pair of
/// bodies, a row a body.
fn make_friction(mk: &mut Maker, model: &Model, state: &State, cap: u64) -> Result<(), String> {
    let n = model.len();
    let mut slip = vec![[0f32; 4]; n];
    for (i, q) in slip.iter_mut().enumerate() {
        let c = state.slip_stiffness[i] as f32;
        let u = state.slip[i] as f32;
        *q = [u, if state.sliding[i] { -c } else { c }, u, 0.0];
    }
    if let Some(q) = slip.first_mut() {
        q[3] = state.friction_heat as f32;
    }
    mk.make(Buf::Slip, 16 * n as u64, Some(bytemuck::cast_slice(&slip)))?;
    for name in [Buf::Frub, Buf::Crubo] {
        mk.make(name, 16 * n as u64, None)?;
    }
    for name in [Buf::Crub0, Buf::Crub1] {
        mk.make(name, 16 * cap, None)?;
    }
    let nb = model.bodies.len() as u32;
    let table: Vec<[f32; 2]> = (0..nb * nb)
        .map(|k| {
            let c = model.friction_between(k / nb, k % nb);
            [c.sliding as f32, c.sticking as f32]
        })
        .collect();
    mk.make(
        Buf::Coulomb,
        8 * table.len() as u64,
        Some(bytemuck::cast_slice(&table)),
    )?;
    Ok(())
}

/// The cell list's, the reductions', the probes' and the bodies' tables and
/// the control block. Returns the history ring's bytes (the staging
/// buffer reads it).
pub(super) fn make_tables(
    mk: &mut Maker,
    model: &Model,
    state: &State,
    plan: &ProbePlan,
    sizes: &kernels::Sizes,
) -> Result<u64, String> {
    let nn = model.len() as u64;
    let kernels::Sizes {
        buckets,
        red_groups,
        ..
    } = *sizes;
    let contact = model.contact;
    let bodies = body_table(model);
    let control = initial_control(state, model);
    // Particle probes find their particle through a slot per probed
    // particle, not a map of every particle (4 B a particle): the probed
    // ids sorted (padded to one per probe with ids no particle has, so
    // that the kernels know the length), each probe pointing at its
    // entry, and the entry's slot, found by a binary search from every
    // particle (reorder.wgsl, map_slots) now and after each reorder.
    let (probe_ids, probe_refs) = probe_tables(&plan.particles);
    mk.make(Buf::Blist, 4 * nn, None)?;
    // Counts, then ends, then starts (neighbours.wgsl): one array.
    mk.make(Buf::Bstart, 4 * (buckets as u64 + 1), None)?;
    mk.make(Buf::Bsum, 4 * buckets.div_ceil(SCAN_BLOCK) as u64, None)?;
    let red_len = red_groups as u64 * (1 + plan.slots.len() as u64);
    mk.make(Buf::Red, 4 * red_len, None)?;
    let ring_bytes = 4 * RING_LEN as u64 * plan.row_width() as u64;
    mk.make(Buf::Ring, ring_bytes, None)?;
    mk.make(
        Buf::Probes,
        8 * plan.particles.len() as u64,
        Some(bytemuck::cast_slice(&probe_refs)),
    )?;
    if !plan.particles.is_empty() {
        mk.make(
            Buf::ProbeIds,
            4 * probe_ids.len() as u64,
            Some(bytemuck::cast_slice(&probe_ids)),
        )?;
        mk.make(Buf::ProbeSlot, 4 * probe_ids.len() as u64, None)?;
    }
    mk.make(
        Buf::Bodies,
        64 * bodies.len() as u64,
        Some(bytemuck::cast_slice(&bodies)),
    )?;
    mk.make(Buf::Ctl, CTL_BYTES, Some(bytemuck::bytes_of(&control)))?;
    if contact {
        // The contact list's (count, workgroups x, y, z): the
        // leapfrog's indirect dispatch's arguments from byte 4
        // (contact.wgsl).
        mk.make_as(
            Buf::SurfArgs,
            16,
            Some(bytemuck::cast_slice(&[0u32, 0, 1, 1])),
            wgpu::BufferUsages::INDIRECT,
        )?;
    }
    Ok(ring_bytes)
}

#[cfg(test)]
mod tests {
    use super::probe_tables;

    #[test]
    fn probe_tables_sort_deduplicate_and_pad() {
        // Three probes on two particles, out of order.
        let (ids, refs) = probe_tables(&[[40, 1], [7, 2], [40, 5]]);
        assert_eq!(ids, vec![7, 40, u32::MAX]);
        assert_eq!(refs, vec![[1, 1], [0, 2], [1, 5]]);
        let (ids, refs) = probe_tables(&[]);
        assert!(ids.is_empty() && refs.is_empty());
    }
}
