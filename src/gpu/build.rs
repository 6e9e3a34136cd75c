//! Making a solver for a scene: the device arrays of its state in the
//! precision plan's form, the buffers the scene needs and no others, and
//! its kernels ([`super::kernels`]).

use super::*;
use make::*;

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

/// The device's constants of a material's strength and failure laws
/// (strength.wgsl, `Plastic`).
pub(super) fn plastic_gpu(m: &crate::physics::material::MaterialModel) -> PlasticGpu {
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
        p.damage = f.device_id();
        [p.d1, p.d2, p.d3, p.d4, p.d5] = f.device();
    }
    p
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
    for (k, at) in plane_lines(model) {
        // Each symmetry plane on a cell boundary too: a particle's offset
        // from it is its whole cells from it plus its offset in the cell
        // (walk.wgsl, `offsets_at`).
        origin[k] = at - ((at - origin[k]) / cell).ceil() * cell;
    }
    Frame {
        origin,
        cell,
        row_stride: ((hi.x - origin.x) / cell).floor() as u32 + 3,
    }
}

/// The coordinate each symmetry plane reverses and where its line lies.
fn plane_lines(model: &Model) -> impl Iterator<Item = (usize, f64)> + '_ {
    model.planes.iter().map(|m| {
        let k = usize::from(!m.flip[0]);
        (k, m.at[k])
    })
}

/// The line of the symmetry plane reversing coordinate `k` in cells of
/// `frame`'s grid from its origin (0 without one).
fn plane_cells(model: &Model, frame: &Frame, k: usize) -> f32 {
    plane_lines(model)
        .find(|&(a, _)| a == k)
        .map_or(0.0, |(_, at)| {
            ((at - frame.origin[k]) / frame.cell).round() as f32
        })
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
        plane_x: plane_cells(model, frame, 0),
        plane_y: plane_cells(model, frame, 1),
        ..Params::default()
    }
}

/// Each body's constants on the device (common.wgsl, `Body`).
pub(super) fn body_table(model: &Model) -> Vec<BodyGpu> {
    model
        .bodies
        .iter()
        .map(|b| {
            let m = &b.material;
            BodyGpu {
                rho0: m.rho0 as f32,
                k: m.k as f32,
                eos0: m.eos.device()[0],
                eos1: m.eos.device()[1],
                g: m.g as f32,
                y0: if m.y0.is_finite() { m.y0 as f32 } else { 0.0 },
                z: m.z as f32,
                modulus: m.m as f32,
                spacing: b.spacing as f32,
                h: model.h[b.range.start] as f32,
                rigid: b.rigid as u32,
                eos: m.eos.device_id(),
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
pub(super) fn initial_control(state: &State, model: &Model) -> Control {
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
