//! Running batches of steps on the device: encoding and submitting them,
//! reading back the control block and the observations, the contact list
//! grown when it runs short, and the instabilities the device reports.

use super::state::map_read;
use super::*;

impl GpuSolver {
    /// The contact's list of boundary particles made `cap` places long: the
    /// solver remade on the same grid and the device state carried over,
    /// byte for byte (the list itself is rebuilt by every evaluation).
    pub(super) fn lengthen_list(&mut self, cap: u32) -> Result<(), String> {
        let raw = self.save_raw();
        // The state the new solver is first made with (the saved buffers
        // then replace it): the saved buffers begin with the state's.
        let saved: Vec<&[u8]> = raw.buffers.iter().map(|b| b.1.as_slice()).collect();
        let (state, _) = self.unpack_state(&saved);
        let opts = GpuOptions {
            surf_capacity: Some(cap),
            ..self.opts
        };
        let frame = Frame {
            origin: self.origin,
            cell: self.cell,
            row_stride: self.params.row_stride,
        };
        let end = self.params.end_hi as f64 + self.params.end_lo as f64;
        let mut g = Self::build(
            self.ctx.clone(),
            self.model.clone(),
            &state,
            &self.probes,
            end,
            opts,
            Some(frame),
        )?;
        g.restore_raw(&raw)?;
        g.first_pending = self.first_pending;
        g.list_checked = true;
        g.clear_list_full();
        *self = g;
        Ok(())
    }

    /// The control block's record of a full list cleared: that pause is
    /// over (a failure of the state itself is kept).
    pub(super) fn clear_list_full(&self) {
        let mut ctl = self.control();
        if ctl.fail_code == LIST_FULL {
            ctl.fail_step = NONE;
            ctl.fail_code = NONE;
        }
        ctl.list_peak = 0;
        self.ctx
            .queue
            .write_buffer(self.buf(Buf::Ctl), 0, bytemuck::bytes_of(&ctl));
    }

    /// Before a solver's first steps: the list of boundary particles long
    /// enough for the state it starts from, with a quarter to spare (the
    /// steps only pause to lengthen it as the boundary grows).
    pub(super) fn make_list_room(&mut self) -> Result<(), String> {
        if self.list_checked || !self.model.contact {
            return Ok(());
        }
        self.list_checked = true;
        loop {
            let cap = self.params.surf_cap;
            if cap as usize >= self.n {
                return Ok(());
            }
            let count = self.boundary_count();
            if count <= cap - cap / 4 {
                return Ok(());
            }
            self.lengthen_list(grown_capacity(cap, count, self.n))?;
        }
    }

    /// The boundary particles at the current state.
    pub(super) fn boundary_count(&mut self) -> u32 {
        let d = self.kinematics_outside_step(&[(Buf::SurfArgs, 4)]);
        bytemuck::pod_read_unaligned(&d[0])
    }

    /// Run up to `steps` steps in one submission and deliver the states
    /// they observed.
    ///
    /// A list of boundary particles that fills past three quarters pauses
    /// the steps (the batch ends early, the state where it paused): the
    /// solver is remade with a list twice as long, and the next batch goes
    /// on from there, bitwise as if the list had been long enough from the
    /// start. A boundary that outgrows the list within a step, or a longer
    /// list the adapter has no room for, is the batch's failure.
    pub fn run_batch(&mut self, steps: u32) -> Batch {
        if let Err(e) = self.make_list_room() {
            return self.list_failure(e);
        }
        let batch = self.batch_with(steps, None).0;
        self.after_batch(batch)
    }

    /// A batch that paused for a full list: the list lengthened.
    pub(super) fn after_batch(&mut self, mut batch: Batch) -> Batch {
        if let Some(count) = self.list_full.take() {
            let cap = self.params.surf_cap;
            if let Err(e) = self.lengthen_list(grown_capacity(cap, count, self.n)) {
                batch.failure = self.list_failure(e).failure;
            }
        }
        batch
    }

    /// A batch that could not go on for want of a longer list.
    pub(super) fn list_failure(&self, why: String) -> Batch {
        let ctl = self.control();
        let time = ctl.t_hi as f64 + ctl.t_lo as f64;
        Batch {
            states: Vec::new(),
            done: false,
            failure: Some(self.list_instability(&ctl, ctl.step, time, &why)),
        }
    }

    /// A boundary the contact's list could not hold, at `step` and `time`.
    pub(super) fn list_instability(
        &self,
        ctl: &Control,
        step: u32,
        time: f64,
        why: &str,
    ) -> Instability {
        Instability {
            step: step as u64,
            time,
            body: self.model.bodies[0].name.clone(),
            particle: 0,
            quantity: format!(
                "boundary particles, more than the contact's list of {} holds ({why})",
                self.params.surf_cap
            ),
            value: ctl.list_peak as f64,
        }
    }

    /// [`Self::run_batch`] with a timestamp after every dispatch: the same
    /// steps, and where their device time went. `Err` where the adapter
    /// has no timestamp queries inside passes.
    pub fn run_batch_profiled(
        &mut self,
        steps: u32,
    ) -> Result<(Batch, profile::StepProfile), String> {
        if !self.ctx.timestamps {
            return Err(format!(
                "the adapter {} has no timestamp queries inside compute passes",
                self.ctx.adapter_name()
            ));
        }
        let steps = steps.clamp(1, RING_LEN - 2);
        let mut tally = Tally::default();
        self.encode_step_pass(&mut tally);
        // A timestamp after each dispatch and after each reorder, and the
        // first; within the query set's limit (fewer steps where it binds).
        let per_step = tally.dispatches + 1;
        let steps = steps.min((wgpu::QUERY_SET_MAX_QUERIES - 1) / per_step);
        let mut timer = profile::StepTimer::new(&self.ctx.device, per_step * steps + 1);
        let (batch, ticks) = self.batch_with(steps, Some(&mut timer));
        let batch = self.after_batch(batch);
        let ticks = ticks.expect("timestamps resolved with a timer");
        let period = self.ctx.queue.get_timestamp_period();
        Ok((batch, timer.profile(&ticks, period, steps)))
    }

    /// A batch of steps, timed where `timer` is given (then also the
    /// resolved timestamps).
    pub(super) fn batch_with(
        &mut self,
        steps: u32,
        mut timer: Option<&mut profile::StepTimer>,
    ) -> (Batch, Option<Vec<u64>>) {
        let steps = steps.clamp(1, RING_LEN - 2);
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        self.encode_first(&mut enc);
        if let Some(t) = timer.as_deref_mut() {
            t.start(&mut enc);
        }
        let dev = &self.ctx.device;
        for s in 0..steps as u64 {
            self.encode_step(&mut enc, self.encoded + s, timer.as_deref_mut());
        }
        let ring_bytes = self.staging.size() - CTL_BYTES;
        enc.copy_buffer_to_buffer(self.buf(Buf::Ctl), 0, &self.staging, 0, CTL_BYTES);
        enc.copy_buffer_to_buffer(self.buf(Buf::Ring), 0, &self.staging, CTL_BYTES, ring_bytes);
        let stamps = timer.map(|t| {
            let n = t.written();
            let bytes = 8 * n as u64;
            let resolved = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps read"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            enc.resolve_query_set(&t.set, 0..n, &resolved, 0);
            enc.copy_buffer_to_buffer(&resolved, 0, &read, 0, bytes);
            (read, bytes)
        });
        self.ctx.queue.submit([enc.finish()]);
        let ticks = stamps.map(|(read, bytes)| {
            bytemuck::cast_slice::<u8, u64>(&map_read(&self.ctx, &read, bytes)).to_vec()
        });
        (self.finish_batch(), ticks)
    }

    /// The batch's states from the control block and the ring, once the
    /// submission that copied them to the staging buffer is done.
    pub(super) fn finish_batch(&mut self) -> Batch {
        let data = map_read(&self.ctx, &self.staging, self.staging.size());
        if self.ctx.fault().is_some() {
            // Nothing came back: no states (the run stops on the fault).
            return Batch::default();
        }
        let ctl: Control = bytemuck::pod_read_unaligned(&data[..CTL_BYTES as usize]);
        let ring: &[f32] = bytemuck::cast_slice(&data[CTL_BYTES as usize..]);
        let width = self.plan.row_width();
        let row = |s: u64| {
            let r = (s % RING_LEN as u64) as usize * width;
            &ring[r..r + width]
        };
        let mut batch = Batch::default();
        let failed = ctl.fail_step != NONE;
        // A list that filled past three quarters pauses the steps as a
        // failure does; one that overflowed within a step is one.
        let paused = failed && ctl.fail_code == LIST_FULL && ctl.list_peak <= self.params.surf_cap;
        if paused {
            self.list_full = Some(ctl.list_peak);
        }
        let reached = ctl.step as u64;
        self.encoded = reached;
        let done = ctl.zero_steps > self.zero_seen;
        self.zero_seen = ctl.zero_steps;
        // States before `reached` were observed by the step that left them;
        // `reached` itself only by a zero-length step at the end.
        let last = if failed {
            ctl.fail_step as u64
        } else if done {
            reached
        } else {
            reached.saturating_sub(1)
        };
        while self.delivered <= last && (self.delivered < reached || done || failed) {
            let r = row(self.delivered);
            let t = r[0] as f64 + r[1] as f64;
            batch
                .states
                .push((t, self.plan.values(r), self.plan.stored_energy(r)));
            self.delivered += 1;
        }
        let r = row(reached.saturating_sub(1));
        if r[2] > 0.0 {
            self.last_dt = r[2] as f64;
        }
        batch.done = done && !failed;
        if failed && !paused {
            batch.failure = Some(self.instability(&ctl, row(ctl.fail_step as u64)));
        }
        batch
    }

    /// The device's fault (an error it reported, or its loss), after which
    /// nothing it hands back is a state: the run stops on it.
    pub fn fault(&self) -> Option<String> {
        self.ctx.fault()
    }

    /// Destroy the device, as a driver reset would lose it: every later
    /// use of it in this process fails (`SPHCONTACT_GPU_LOSE_AT`, the
    /// tests of a run that loses its device).
    pub fn lose_device(&self) {
        self.ctx.device.destroy();
    }

    /// The last step the device took (for sizing the next batch).
    pub fn last_dt(&self) -> f64 {
        self.last_dt
    }

    pub(super) fn instability(&self, ctl: &Control, row: &[f32]) -> Instability {
        let code = ctl.fail_code;
        let (id, q) = ((code / 8) as usize, code % 8);
        let time = row[0] as f64 + row[1] as f64;
        if code == LIST_FULL {
            let why = "the boundary grew by more than a quarter of it within one step";
            return self.list_instability(ctl, ctl.fail_step, time, why);
        }
        let guard = q == fail::ENERGY_GUARD;
        let (quantity, value) = if q == fail::TIME_STEP {
            ("time step".to_string(), row[2] as f64)
        } else if guard {
            let (e, owed) = (self.plan.guarded_energy(row), self.plan.guarded_owed(row));
            self.model.energy_quantity(ctl.energy_limit as f64, e, owed)
        } else {
            let st = self.download();
            let named = |name: &str, v: f64| (name.to_string(), v);
            match q {
                fail::POSITION => named("position", st.x[id].x + st.x[id].y),
                fail::VELOCITY => named("velocity", st.v[id].x + st.v[id].y),
                fail::ENERGY => named("internal energy", st.e[id]),
                fail::DOMAIN => self.model.outside_domain(st.x[id]),
                _ => {
                    debug_assert_eq!(q, fail::DENSITY);
                    named("density", st.rho[id])
                }
            }
        };
        let id = match q {
            fail::TIME_STEP => 0,
            fail::ENERGY_GUARD => self.model.guarded_particle(
                &self.download(),
                ctl.energy_limit as f64,
                self.plan.guarded_energy(row),
            ),
            _ => id,
        };
        let (body, particle) = self.model.locate(id.min(self.n - 1));
        // As the CPU path: a bad state is reported with its own step and
        // time; a collapsed step with the state it was computed at.
        let (step, time) = if q == fail::TIME_STEP || guard {
            (ctl.fail_step as u64, time)
        } else {
            (ctl.fail_step as u64 + 1, time + row[2] as f64)
        };
        Instability {
            step,
            time,
            body: body.to_string(),
            particle,
            quantity,
            value,
        }
    }

    /// Move the time the device stops at (a snapshot time, then the end
    /// time): the step that would cross it is shortened to land on it and
    /// the steps after it have zero length, as at the end of a run, until
    /// the stop moves again. Takes effect from the next batch.
    pub fn set_stop_time(&mut self, t: f64) {
        let (hi, lo) = split(t);
        (self.params.end_hi, self.params.end_lo) = (hi, lo);
        let at = std::mem::offset_of!(Params, end_hi) as u64;
        debug_assert_eq!(std::mem::offset_of!(Params, end_lo) as u64, at + 4);
        self.ctx
            .queue
            .write_buffer(self.buf(Buf::Params), at, bytemuck::cast_slice(&[hi, lo]));
    }
}
