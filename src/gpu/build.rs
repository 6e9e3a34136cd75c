//! Making a solver for a scene: the device arrays of its state in the
//! precision plan's form, the buffers the scene needs and no others, and
//! its kernels ([`super::kernels`]).

use super::*;

/// Cell-list buckets for `n` particles: a power of two at least the count.
///
/// A cell's key is row-major over the initial bounding box (`bucket_of`,
/// walk.wgsl), so distinct cells share a bucket only once the keys span
/// more than the bucket count. Cells are a little larger than `h`, so
/// bodies that fill their box (the disks: 0.9 cells a particle) stay
/// collision-free until they have spread over their starting box times the
/// buckets a particle (1 to 2) over 0.9. Twice as many buckets would halve
/// the collisions of scattered bodies (a wasted candidate read each) for 4
/// bytes a particle more.
pub(super) fn bucket_count(n: usize) -> u32 {
    n.next_power_of_two().max(256) as u32
}

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
fn contact_homes(model: &Model) -> [(Buf, Option<Buf>); 2] {
    let own_home = model.keeps_gradient().then_some(Buf::Gradv);
    [(Buf::Cshare, Some(Buf::Lmat)), (Buf::Cown, own_home)]
}

/// A buffer another lives in, made by then (`contact_homes`, `mask_home`).
fn made(buffers: &DeviceBuffers, home: Buf) -> &wgpu::Buffer {
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
fn surf_capacity(n: usize) -> u32 {
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
fn mask_home(model: &Model) -> Option<Buf> {
    (model.integrator == Integrator::Leapfrog && model.contact).then_some(Buf::Qrate)
}

/// The device's constants of a material's strength and failure laws
/// (strength.wgsl, `Plastic`).
fn plastic_gpu(m: &crate::physics::material::MaterialModel) -> PlasticGpu {
    let mut p = PlasticGpu {
        heat: if m.specific_heat > 0.0 {
            (m.taylor_quinney / m.specific_heat) as f32
        } else {
            0.0
        },
        rate0: 1.0,
        melt_rise: 1.0,
        spall: if m.spall.is_finite() {
            m.spall as f32
        } else {
            f32::MAX
        },
        cavitation: if m.cavitation.is_finite() {
            m.cavitation as f32
        } else {
            f32::MAX
        },
        ..Default::default()
    };
    if let Some(law) = &m.strength {
        p.law = law.device_id();
        p.k = law.device();
        p.room = law.room_temperature() as f32;
        p.rate0 = law.reference_strain_rate() as f32;
        p.melt_rise = law
            .melt_temperature()
            .map_or(f32::MAX, |t| (t - law.room_temperature()) as f32);
    }
    if let Some(f) = &m.failure {
        p.damage = 1;
        (p.d1, p.d2, p.d3, p.d4, p.d5) = (
            f.d1 as f32,
            f.d2 as f32,
            f.d3 as f32,
            f.d4 as f32,
            f.d5 as f32,
        );
    }
    p
}

/// The GPU's particle-probe tables from the plan's `(particle, code)` list:
/// the probed particle ids sorted and deduplicated, padded with `u32::MAX`
/// to one entry a probe, and each probe as `(entry, code)`.
fn probe_tables(particles: &[[u32; 2]]) -> (Vec<u32>, Vec<[u32; 2]>) {
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

impl GpuSolver {
    /// Upload a model and state. `probes` are the scene's resolved probes;
    /// `end_time` is where the device stops stepping. `Err` when the scene
    /// does not fit the adapter.
    pub fn new(
        ctx: Arc<GpuContext>,
        model: Model,
        state: &State,
        probes: &[Resolved],
        end_time: f64,
    ) -> Result<Self, String> {
        Self::with_options(ctx, model, state, probes, end_time, GpuOptions::default())
    }

    /// [`GpuSolver::new`] under limits tighter than the adapter's.
    pub fn with_options(
        ctx: Arc<GpuContext>,
        model: Model,
        state: &State,
        probes: &[Resolved],
        end_time: f64,
        opts: GpuOptions,
    ) -> Result<Self, String> {
        Self::build(ctx, model, state, probes, end_time, opts, None)
    }

    /// The solver for a state, on the grid `frame` where given (else the
    /// state's own).
    pub(super) fn build(
        ctx: Arc<GpuContext>,
        model: Model,
        state: &State,
        probes: &[Resolved],
        end_time: f64,
        opts: GpuOptions,
        frame: Option<Frame>,
    ) -> Result<Self, String> {
        if model.dispersion > 0.0 {
            return Err(format!(
                "dispersion_correction = {} runs on the CPU path only",
                model.dispersion
            ));
        }
        let n = model.len();
        let frame = frame.unwrap_or_else(|| frame_of(&model, state));
        let (origin, cell) = (frame.origin, frame.cell);
        // Positions are observed relative to the grid origin; the plan adds
        // it back in f64.
        let plan = ProbePlan::new(probes, &model, origin);
        let maxd = opts
            .max_workgroups_per_dimension
            .map_or(ctx.limits.max_compute_workgroups_per_dimension, |m| {
                m.min(ctx.limits.max_compute_workgroups_per_dimension)
            })
            .max(1);
        let sizes = kernels::Sizes {
            n,
            buckets: bucket_count(n),
            red_groups: (n as u32).div_ceil(RED_CHUNK).max(1),
            maxd,
        };
        let leapfrog = model.integrator == Integrator::Leapfrog;
        let surf_cap = if model.contact {
            opts.surf_capacity
                .unwrap_or_else(|| surf_capacity(n))
                .clamp(1, MAX_SURF_CAP as u32)
        } else {
            0
        };
        let params = params_of(&model, &plan, &frame, end_time, &sizes, surf_cap);
        let mut mk = Maker::new(&ctx, &opts, n);
        // Out-of-memory errors while the buffers are made, for the build
        // to report (a device past its budget refuses a buffer).
        let oom = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        make_state(&mut mk, &model, state, &frame)?;
        make_scheme(&mut mk, &model, state, surf_cap)?;
        let ring_bytes = make_tables(&mut mk, &model, state, &plan, &sizes)?;
        let (mut buffers, device_bytes) = mk.finish(oom)?;
        if let Some(home) = mask_home(&model) {
            buffers.set(Buf::Nmask, made(&buffers, home).clone());
        }
        if model.contact {
            for (name, home) in contact_homes(&model) {
                if let Some(home) = home {
                    let shared = made(&buffers, home).clone();
                    buffers.set(name, shared);
                }
            }
        }
        let dev = &ctx.device;
        let params_buf = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&params_buf, 0, bytemuck::bytes_of(&params));
        buffers.set(Buf::Params, params_buf);
        let staging = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: CTL_BYTES + ring_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let k = kernels::make_kernels(&ctx, &model, &plan, &buffers, sizes)?;
        let solver = Self {
            ctx,
            model,
            n,
            buffers,
            staging,
            plan,
            k,
            encoded: 0,
            delivered: 0,
            zero_seen: 0,
            last_dt: 0.0,
            device_bytes,
            params,
            first_pending: leapfrog,
            origin,
            cell,
            probes: probes.to_vec(),
            opts,
            list_checked: opts.unchecked_list,
            list_full: None,
        };
        solver.refresh_probe_slots();
        Ok(solver)
    }
}

/// The cell grid of a state: cells of `h_max` and a hair more, the origin
/// a cell and a half below the particles (on the axis's cell boundary for
/// a body of revolution).
fn frame_of(model: &Model, state: &State) -> Frame {
    let h_max = model.h.iter().cloned().fold(0.0, f64::max);
    let cell = h_max * CELL_OVER_H;
    let (lo, hi) = crate::math::bounds(&state.x);
    let mut origin = lo - DVec2::splat(1.5 * cell);
    if model.axisymmetric {
        // The axis on a cell boundary: a radius is then the whole
        // cells from it plus the offset in the cell (common.wgsl,
        // `radius_at`), as exact as a pair difference.
        origin.x = -2.0 * cell;
    }
    Frame {
        origin,
        cell,
        row_stride: ((hi.x - origin.x) / cell).floor() as u32 + 3,
    }
}

/// The uniform constants of a scene's step.
fn params_of(
    model: &Model,
    plan: &ProbePlan,
    frame: &Frame,
    end_time: f64,
    sizes: &kernels::Sizes,
    surf_cap: u32,
) -> Params {
    let Frame {
        origin,
        cell,
        row_stride,
    } = *frame;
    let kernels::Sizes {
        n,
        buckets,
        red_groups,
        maxd,
    } = *sizes;
    // Cells of h_max and a hair more: a pair within 2 h_ij is then at
    // most two cells apart along each axis, and a particle's candidates
    // lie in five rows of at most five cells (`row_span`, common.wgsl).
    // Each row's columns are clipped to the disk of radius `reach`
    // cells; the support's 2 h_max / cell is 1.996 cells, and the
    // margin of 1e-3 cells up to 2 covers the f32 rounding of a
    // particle's place in its cell (1e-5 cells at 100 cells from its
    // reference cell).
    let reach = (2.0 / CELL_OVER_H + REACH_MARGIN) as f32;
    let (end_hi, end_lo) = split(end_time);
    Params {
        n: n as u32,
        nbodies: model.bodies.len() as u32,
        buckets,
        row_stride,
        energy_growth: crate::model::ENERGY_GROWTH as f32,
        energy_floor: model.energy_floor as f32,
        inv_cell: (1.0 / cell) as f32,
        alpha: model.alpha as f32,
        beta: model.beta as f32,
        cfl: model.cfl as f32,
        fixed_dt: model.fixed_dt.unwrap_or(0.0) as f32,
        boundary_threshold: model.boundary_threshold as f32,
        as_eps: model.artificial_stress.map_or(0.0, |a| a.epsilon) as f32,
        as_n: model.artificial_stress.map_or(0.0, |a| a.n) as f32,
        end_hi,
        end_lo,
        ring_len: RING_LEN,
        ring_width: plan.row_width() as u32,
        surf_cap,
        nprobes: plan.particles.len() as u32,
        cell: cell as f32,
        red_groups,
        min_sv2: (CORRECTION_MIN_SINGULAR * CORRECTION_MIN_SINGULAR) as f32,
        reach,
        domain: {
            let [lo, hi] = model.domain;
            let (lo, hi) = (lo - origin, hi - origin);
            [lo.x as f32, lo.y as f32, hi.x as f32, hi.y as f32]
        },
        energy_kin: plan.energy.map_or(0, |e| e.0 as u32),
        energy_int: plan.energy.map_or(0, |e| e.1 as u32),
        energy_stored: plan.stored.map_or(NONE, |k| k as u32),
        surf_groups: maxd,
        axis_cell: if model.axisymmetric {
            (-origin.x / cell).round() as f32
        } else {
            0.0
        },
        reach_margin: REACH_MARGIN as f32,
        energy_owed: plan.energy.map_or(0, |e| e.2 as u32),
        contact_dt: model.contact_dt.min(f32::MAX as f64) as f32,
    }
}

/// Each body's constants on the device (common.wgsl, `Body`).
fn body_table(model: &Model) -> Vec<BodyGpu> {
    model
        .bodies
        .iter()
        .map(|b| {
            let m = &b.material;
            BodyGpu {
                rho0: m.rho0 as f32,
                k: m.k as f32,
                s: m.s as f32,
                gamma0: m.gamma0 as f32,
                g: m.g as f32,
                y0: if m.y0.is_finite() { m.y0 as f32 } else { 0.0 },
                z: m.z as f32,
                modulus: m.m as f32,
                spacing: b.spacing as f32,
                h: model.h[b.range.start] as f32,
                rigid: b.rigid as u32,
                linear: m.linear as u32,
                elastic: (!m.y0.is_finite()) as u32,
                debris_n: b.debris_neighbours,
                hg: b.hourglass as f32,
                art: b.art as u32,
            }
        })
        .collect()
}

/// The device's control block at the start: no failure, the energy guard
/// unset, the supports' largest semi-axis.
fn initial_control(state: &State, model: &Model) -> Control {
    // Where supports adapt, the step's largest major semi-axis
    // (common.wgsl, `step_h_top`), in both slots: the device counts its
    // steps from 0 whatever the state's, and the advance clears the
    // next step's slot before it raises it.
    let top = if state.round_supports() {
        model.h.iter().map(|&h| h as f32).fold(0.0f32, f32::max)
    } else {
        state
            .metric
            .iter()
            .map(|q| q.axes().1 as f32)
            .fold(0.0f32, f32::max)
    }
    .to_bits();
    let h_top = [top; 2];
    let out_of_band = [u32::from(!state.round_supports()); 2];
    Control {
        fail_step: NONE,
        fail_code: NONE,
        energy_limit: -1.0,
        h_top,
        out_of_band,
        ..Default::default()
    }
}

/// Makes the solver's device buffers within the adapter's limits and the
/// device memory the solver may take, counting their bytes.
struct Maker<'a> {
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
    fn new(ctx: &'a GpuContext, opts: &GpuOptions, n: usize) -> Self {
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
    fn make_as(
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

    fn make(&mut self, name: Buf, size: u64, data: Option<&[u8]>) -> Result<(), String> {
        self.make_as(name, size, data, wgpu::BufferUsages::empty())
    }

    /// The buffers and their bytes, or why the scene does not fit: past
    /// the budget, or refused by the device (`oom`, the error scope the
    /// buffers were made in).
    fn finish(self, oom: wgpu::ErrorScopeGuard) -> Result<(DeviceBuffers, u64), String> {
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
fn make_state(mk: &mut Maker, model: &Model, state: &State, frame: &Frame) -> Result<(), String> {
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

/// The integrator's, the contact's and the supports' buffers: what the
/// scene's scheme carries between passes and steps, and no more.
fn make_scheme(mk: &mut Maker, model: &Model, state: &State, surf_cap: u32) -> Result<(), String> {
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
fn make_contact(mk: &mut Maker, model: &Model, state: &State, surf_cap: u32) -> Result<(), String> {
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
    // The two gather buffers share memory with pass scratch where
    // the scene has it (below); the rest get their own.
    for (name, home) in contact_homes(model) {
        if home.is_none() {
            mk.make(name, 16 * nn, None)?;
        }
    }
    Ok(())
}

/// The cell list's, the reductions', the probes' and the bodies' tables and
/// the control block. Returns the history ring's bytes (the staging
/// buffer reads it).
fn make_tables(
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
