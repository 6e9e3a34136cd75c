//! The device state read back and written: downloads, snapshots, and the
//! raw buffers a checkpoint holds.

use std::sync::Mutex;

use super::*;

impl GpuSolver {
    /// Copy `bytes` from the start of each named buffer back to the host.
    pub(super) fn read_buffers(
        &self,
        enc: Option<wgpu::CommandEncoder>,
        names: &[(Buf, u64)],
    ) -> Vec<Vec<u8>> {
        let dev = &self.ctx.device;
        let total: u64 = names.iter().map(|x| x.1.next_multiple_of(4)).sum();
        let stage = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: total.max(4),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = enc.unwrap_or_else(|| dev.create_command_encoder(&Default::default()));
        let mut off = 0;
        for (name, bytes) in names {
            enc.copy_buffer_to_buffer(self.buf(*name), 0, &stage, off, *bytes);
            off += bytes.next_multiple_of(4);
        }
        self.ctx.queue.submit([enc.finish()]);
        let data = map_read(&self.ctx, &stage, total.max(4));
        let mut out = Vec::new();
        let mut off = 0usize;
        for (_, bytes) in names {
            out.push(data[off..off + *bytes as usize].to_vec());
            off += bytes.next_multiple_of(4) as usize;
        }
        out
    }

    /// The device state in f64, in the model's particle order.
    pub fn download(&self) -> State {
        self.download_with_control().0
    }

    /// Give the model back (the device buffers are dropped).
    pub fn into_model(self) -> Model {
        self.model
    }

    /// The state and the control block, in one readback.
    pub fn download_with_control(&self) -> (State, Control) {
        let d = self.read_buffers(None, &self.state_buffers());
        self.unpack_state(&d)
    }

    /// The state with its outward unit normals and boundary set, in the
    /// model's particle order (snapshots). The normals in "nbo" after a step
    /// belong to its midpoint, so the cell list and the kinematics pass run once more at
    /// the state itself first. They only rewrite per-evaluation scratch
    /// that every step recomputes before reading, and the control block,
    /// which is put back (`kinematics_outside_step`).
    /// Normals are zero off the boundary, as on the CPU path.
    pub fn snapshot(&mut self) -> (State, Vec<DVec2>, Vec<bool>) {
        let mut names = self.state_buffers();
        names.push((Buf::Nbo, 16 * self.n as u64));
        let d = if self.k.leap.is_some() {
            // The normals of the last step's kinematic pass, at these
            // positions: an evaluation now would overwrite what the next
            // step's reductions read.
            let mut enc = self.ctx.device.create_command_encoder(&Default::default());
            self.encode_first(&mut enc);
            self.read_buffers(Some(enc), &names)
        } else {
            self.kinematics_outside_step(&names)
        };
        let (st, _) = self.unpack_state(&d);
        let meta: &[[u32; 4]] = bytemuck::cast_slice(&d[5]);
        let nbo: &[[f32; 4]] = bytemuck::cast_slice(d.last().expect("nbo was read"));
        let mut normal = vec![DVec2::ZERO; self.n];
        let mut boundary = vec![false; self.n];
        for (m, nb) in meta.iter().zip(nbo) {
            let i = m[3] as usize;
            if nb[2] > 0.0 {
                boundary[i] = true;
                normal[i] = DVec2::new(nb[0] as f64, nb[1] as f64);
            }
        }
        (st, normal, boundary)
    }

    /// The buffers that carry a run from one step to the next, as stored
    /// (checkpoints): the state and the control block. Everything else is
    /// rewritten by every step before it is read, or (the probed
    /// particles' slots) follows from the state.
    pub(super) fn persistent_buffers(&self) -> Vec<(Buf, u64)> {
        let mut names = self.state_buffers();
        if self.k.leap.is_some() {
            let n = self.n as u64;
            let state: Vec<Buf> = names.iter().map(|b| b.0).collect();
            names.extend(
                leap_arrays(&self.model)
                    .into_iter()
                    .filter(|a| !state.contains(&a.0))
                    .map(|(name, bytes)| (name, bytes * n)),
            );
        }
        names
    }

    /// The device's state as stored, with the host's step counters (a
    /// checkpoint's part from the device).
    pub fn save_raw(&self) -> RawDevice {
        let names = self.persistent_buffers();
        let data = self.read_buffers(None, &names);
        let mut buffers: Vec<(String, Vec<u8>)> = names
            .iter()
            .zip(data)
            .map(|((name, _), d)| (name.name().to_string(), d))
            .collect();
        buffers.push((FRAME.to_string(), self.frame_bytes()));
        RawDevice {
            buffers,
            encoded: self.encoded,
            delivered: self.delivered,
            zero_seen: self.zero_seen,
            last_dt: self.last_dt,
        }
    }

    /// The grid the reference positions are given in: origin and cell
    /// size, as f64 bytes.
    pub(super) fn frame_bytes(&self) -> Vec<u8> {
        [self.origin.x, self.origin.y, self.cell]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect()
    }

    /// Put a saved device state back (a solver made for the same scene):
    /// the buffers byte for byte, then the counters. `Err` when the saved
    /// buffers are not this solver's.
    pub fn restore_raw(&mut self, raw: &RawDevice) -> Result<(), String> {
        let names = self.persistent_buffers();
        // The reference cells in `x0` count cells of this solver's grid.
        let frame = raw.buffers.iter().find(|(m, _)| m == FRAME);
        if frame.map(|f| &f.1) != Some(&self.frame_bytes()) {
            return Err(
                "the saved device state is laid out on another cell grid than this \
                        build's (a checkpoint of an older build, or of another scene); resume \
                        it with the build that wrote it"
                    .into(),
            );
        }
        // Checkpoints from before the probes kept their own slots also hold
        // a map of every particle's slot: not needed, rebuilt below.
        let saved: Vec<&(String, Vec<u8>)> = raw
            .buffers
            .iter()
            .filter(|(m, _)| m != "slot_of" && m != FRAME)
            .collect();
        let same = names.len() == saved.len()
            && names
                .iter()
                .zip(&saved)
                .all(|((n, size), (m, d))| n.name() == m && *size == d.len() as u64);
        if !same {
            return Err("the saved device buffers do not match this scene's".into());
        }
        for ((name, _), (_, d)) in names.iter().zip(saved) {
            self.ctx.queue.write_buffer(self.buf(*name), 0, d);
        }
        self.refresh_probe_slots();
        self.first_pending = false;
        self.encoded = raw.encoded;
        self.delivered = raw.delivered;
        self.zero_seen = raw.zero_seen;
        self.last_dt = raw.last_dt;
        Ok(())
    }

    /// The buffers the state is read from, in the order `unpack_state`
    /// takes them.
    pub(super) fn state_buffers(&self) -> Vec<(Buf, u64)> {
        let n = self.n as u64;
        let mut names = vec![
            (Buf::X0, 16 * n),
            (Buf::U, 8 * n),
            (Buf::V, 8 * n),
            (Buf::R, 8 * n),
            (Buf::S, 16 * n),
            (Buf::Pinfo, 16 * n),
            (Buf::Ctl, CTL_BYTES),
        ];
        if self.model.contact {
            names.push((Buf::Qheat, 8 * n));
            names.push((Buf::Centry, 4 * n));
        }
        if self.model.history {
            names.push((Buf::Hist, 16 * n));
        }
        if self.model.adaptive {
            names.push((Buf::Metric, 16 * n));
        }
        if self.model.dissipates() {
            names.push((Buf::Dheat, 16 * particle_groups(self.n)));
        }
        if !self.model.held.is_empty() {
            names.push((Buf::HeldW, 16 * n));
        }
        if self.model.rubs {
            names.push((Buf::Slip, 16 * n));
            // The leapfrog carries its booking's friction to the next
            // step's first half and reductions.
            if self.k.leap.is_some() {
                names.push((Buf::Frub, 16 * n));
                names.push((Buf::Crubo, 16 * n));
            }
        }
        names
    }

    /// Where buffer `name` is among `state_buffers`.
    pub(super) fn state_index(&self, name: Buf) -> usize {
        self.state_buffers()
            .iter()
            .position(|b| b.0 == name)
            .unwrap_or_else(|| panic!("no state buffer '{}'", name.name()))
    }

    /// Particle i's history `(ε_p, T, D, t_f)` in f64 from the device's
    /// (strength.wgsl's precision plan: the temperature as its rise).
    pub(super) fn history_of(&self, i: usize, h: [f32; 4]) -> [f64; 4] {
        let room = self.model.material(i).initial_temperature();
        let [eps, rise, d, t] = h.map(f64::from);
        [eps, room + rise, d, t]
    }

    /// The f64 state (model order) and the control block from the buffers
    /// of `state_buffers`.
    pub(super) fn unpack_state<B: AsRef<[u8]>>(&self, d: &[B]) -> (State, Control) {
        let x0: &[[f32; 4]] = bytemuck::cast_slice(d[0].as_ref());
        let u: &[[f32; 2]] = bytemuck::cast_slice(d[1].as_ref());
        let v: &[[f32; 2]] = bytemuck::cast_slice(d[2].as_ref());
        let r: &[[f32; 2]] = bytemuck::cast_slice(d[3].as_ref());
        let s: &[[f32; 4]] = bytemuck::cast_slice(d[4].as_ref());
        let meta: &[[u32; 4]] = bytemuck::cast_slice(d[5].as_ref());
        let ctl: Control = bytemuck::pod_read_unaligned(d[6].as_ref());
        let n = self.n;
        let mut st = State {
            t: ctl.t_hi as f64 + ctl.t_lo as f64,
            step: ctl.step as u64,
            x: vec![DVec2::ZERO; n],
            v: vec![DVec2::ZERO; n],
            rho: vec![0.0; n],
            e: vec![0.0; n],
            s: vec![Sym::default(); n],
            heat: 0.0,
            spring_work: 0.0,
            ..Default::default()
        };
        for k in 0..n {
            let i = meta[k][3] as usize;
            let c = DVec2::new(x0[k][0] as f64, x0[k][1] as f64);
            let off = DVec2::new(
                x0[k][2] as f64 + u[k][0] as f64,
                x0[k][3] as f64 + u[k][1] as f64,
            );
            st.x[i] = self.origin + c * self.cell + off;
            st.v[i] = DVec2::new(v[k][0] as f64, v[k][1] as f64);
            let rho = self.model.material(i).rho0 * (1.0 + r[k][0] as f64);
            st.rho[i] = self.model.state_rho(rho, st.x[i]);
            st.e[i] = r[k][1] as f64;
            st.s[i] = sym_of(s[k]);
        }
        if self.model.contact {
            let q: &[[f32; 2]] = bytemuck::cast_slice(d[self.state_index(Buf::Qheat)].as_ref());
            st.heat = q.iter().map(|x| x[0] as f64).sum();
            st.spring_work = q.iter().map(|x| x[1] as f64).sum();
            let e: &[f32] = bytemuck::cast_slice(d[self.state_index(Buf::Centry)].as_ref());
            st.entry = vec![0.0; n];
            for k in 0..n {
                st.entry[meta[k][3] as usize] = e[k] as f64;
            }
        }
        if self.model.history {
            let h: &[[f32; 4]] = bytemuck::cast_slice(d[self.state_index(Buf::Hist)].as_ref());
            st.eps_p = vec![0.0; n];
            st.temperature = vec![0.0; n];
            st.damage = vec![0.0; n];
            st.failed_at = vec![0.0; n];
            for k in 0..n {
                let i = meta[k][3] as usize;
                [
                    st.eps_p[i],
                    st.temperature[i],
                    st.damage[i],
                    st.failed_at[i],
                ] = self.history_of(i, h[k]);
            }
        }
        if self.model.dissipates() {
            let q: &[[f32; 4]] = bytemuck::cast_slice(d[self.state_index(Buf::Dheat)].as_ref());
            st.dissipation = q.iter().map(|x| x[0] as f64 + x[1] as f64).sum();
        }
        if !self.model.held.is_empty() {
            // By original index (make::make_held).
            let w: &[[f32; 4]] = bytemuck::cast_slice(d[self.state_index(Buf::HeldW)].as_ref());
            let m = &self.model;
            st.held_impulse = m
                .held
                .iter()
                .map(|c| {
                    c.particles
                        .iter()
                        .map(|&i| {
                            let q = w[i].map(f64::from);
                            DVec2::new(q[0] + q[2], q[1] + q[3])
                        })
                        .sum()
                })
                .collect();
            st.held_work = m
                .held
                .iter()
                .zip(&st.held_impulse)
                .map(|(c, j)| c.velocity.dot(*j))
                .sum();
        }
        if self.model.rubs {
            // By original index (make::make_friction).
            let q: &[[f32; 4]] = bytemuck::cast_slice(d[self.state_index(Buf::Slip)].as_ref());
            st.slip = q.iter().map(|x| x[0] as f64).collect();
            st.slip_stiffness = q.iter().map(|x| x[1].abs() as f64).collect();
            st.sliding = q.iter().map(|x| x[1] < 0.0).collect();
            st.friction_heat = q.iter().map(|x| x[3] as f64).sum();
        }
        if self.model.adaptive {
            let q: &[[f32; 4]] = bytemuck::cast_slice(d[self.state_index(Buf::Metric)].as_ref());
            st.metric = vec![Default::default(); n];
            for k in 0..n {
                st.metric[meta[k][3] as usize] = crate::physics::support::Metric {
                    xx: q[k][0] as f64,
                    xy: q[k][1] as f64,
                    yy: q[k][2] as f64,
                };
            }
            if self.model.carries_band() {
                st.carried = std::mem::take(&mut st.metric);
                self.model.supports_of(&st.carried, &mut st.metric);
            }
        }
        (st, ctl)
    }

    /// The control block: time, step, status, and the counts of particles
    /// whose correction fell back to `L = I` (most at one state) and of
    /// contact evaluations that met two partner bodies.
    pub fn control(&self) -> Control {
        let d = self.read_buffers(None, &[(Buf::Ctl, CTL_BYTES)]);
        bytemuck::pod_read_unaligned(&d[0])
    }
}

/// Map a MAP_READ buffer and copy out its first `size` bytes.
pub(super) fn map_read(ctx: &GpuContext, buf: &wgpu::Buffer, size: u64) -> Vec<u8> {
    // A device that failed hands back zeros and keeps the fault, which the
    // run checks before it reads what came back (GpuSolver::fault).
    let failed = Arc::new(Mutex::new(None));
    let slice = buf.slice(0..size);
    let f = failed.clone();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        if let Err(e) = r {
            *f.lock().unwrap_or_else(|p| p.into_inner()) = Some(e.to_string());
        }
    });
    if let Err(e) = ctx.device.poll(wgpu::PollType::wait_indefinitely()) {
        ctx.record_fault(format!("the device did not finish its work: {e}"));
    }
    if let Some(e) = failed.lock().unwrap_or_else(|p| p.into_inner()).take() {
        ctx.record_fault(format!("a readback failed: {e}"));
    }
    if ctx.fault().is_some() {
        return vec![0; size as usize];
    }
    let data = match slice.get_mapped_range() {
        Ok(range) => range.to_vec(),
        Err(e) => {
            ctx.record_fault(format!("a readback failed: {e}"));
            return vec![0; size as usize];
        }
    };
    buf.unmap();
    data
}
