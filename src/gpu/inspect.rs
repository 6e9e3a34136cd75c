//! The device looked at from outside a run: each stage timed alone, the
//! work of a step, and one evaluation's stage outputs for the tests that
//! hold the shaders to their CPU twins.

use super::state::map_read;
use super::*;

impl GpuSolver {
    /// The cell list and the kinematics pass at the current state, outside
    /// a step, and `read` read back after them. What they change that a
    /// run carries is put back: the leapfrog's carried arrays, and the
    /// control block (the correction fallbacks and the list's fill they
    /// count).
    pub(super) fn kinematics_outside_step(&mut self, read: &[(Buf, u64)]) -> Vec<Vec<u8>> {
        let leap = self.k.leap.is_some();
        let raw = leap.then(|| self.save_raw());
        let ctl = (!leap).then(|| self.read_buffers(None, &[(Buf::Ctl, CTL_BYTES)]).remove(0));
        let pending = self.first_pending;
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            self.k.eval[Var::Base as usize]
                .kinematics_all()
                .for_each(|k| pass.run(k));
        }
        let d = self.read_buffers(Some(enc), read);
        if let Some(raw) = raw {
            self.restore_raw(&raw).expect("the state just saved");
            self.first_pending = pending;
            self.leap_clear();
        }
        if let Some(ctl) = ctl {
            self.ctx.queue.write_buffer(self.buf(Buf::Ctl), 0, &ctl);
        }
        d
    }

    /// The work of a step: its dispatches and neighbour walks (tallied from
    /// the code that encodes a step), the device bytes, and each walk's
    /// candidates and group trips counted on the host from the cell list
    /// the device builds at the current state ([`work`]).
    pub fn step_work(&mut self) -> work::StepWork {
        let mut tally = Tally::default();
        self.encode_step_pass(&mut tally);
        let nn = self.n as u64;
        let buckets = self.params.buckets as u64;
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        self.encode_first(&mut enc);
        self.ctx.queue.submit([enc.finish()]);
        // The kinematics pass gives the boundary flags and the leapfrog's
        // neighbour masks at these positions.
        let mut read = vec![
            (Buf::X0, 16 * nn),
            (Buf::U, 8 * nn),
            (Buf::Bstart, 4 * (buckets + 1)),
            (Buf::Nbo, 16 * nn),
        ];
        if self.k.leap.is_some() {
            read.push((Buf::Nmask, 8 * nn));
        }
        let d = self.kinematics_outside_step(&read);
        let x0: &[[f32; 4]] = bytemuck::cast_slice(&d[0]);
        let u: &[[f32; 2]] = bytemuck::cast_slice(&d[1]);
        let bstart: &[u32] = bytemuck::cast_slice(&d[2]);
        let nbo: &[[f32; 4]] = bytemuck::cast_slice(&d[3]);
        let masks: &[[u32; 2]] = d.get(4).map_or(&[], |m| bytemuck::cast_slice(m));
        let view = work::GridView {
            params: &self.params,
            dim: self.model.dim,
            x0,
            u,
            bstart,
        };
        // Each distinct walk once, with how often a step runs it.
        let mut per_walk: Vec<work::WalkWork> = Vec::new();
        for (name, walk) in &tally.walks {
            if let Some(w) = per_walk.iter_mut().find(|w| &w.name == name) {
                w.per_step += 1;
                continue;
            }
            let boundary = |i: usize| nbo[i][2] > 0.0;
            per_walk.push(match walk {
                Walk::Masked => view.count_masked(name, 1, masks),
                Walk::Boundary => view.count_walk(name, 1, &boundary, false),
                Walk::Listed => view.count_walk(name, 1, &boundary, true),
                _ => view.count_walk(name, 1, &|_| true, false),
            });
        }
        let count = |w: Walk| tally.walks.iter().filter(|x| x.1 == w).count() as u32;
        work::StepWork {
            dispatches: tally.dispatches,
            walks: count(Walk::All) + count(Walk::Masked),
            contact_walks: count(Walk::Boundary) + count(Walk::Listed),
            device_bytes_per_particle: self.device_bytes as f64 / self.n as f64,
            per_walk,
        }
    }

    /// The stages [`GpuSolver::time_stage`] can run for this scene (the
    /// contact only when the scene has contact), in the order of
    /// [`stage::STAGES`].
    pub fn stage_names(&self) -> Vec<&'static str> {
        stage::STAGES
            .iter()
            .filter(|s| s.stage != Stage::Contact || self.model.contact)
            .map(|s| s.name)
            .collect()
    }

    /// How many times a step runs what [`GpuSolver::time_stage`] times of
    /// a stage: its entries at the step's own state (the evaluation at the
    /// midpoint runs the same kernels again).
    pub fn stage_per_step(&self, name: &str) -> f64 {
        Stage::named(name).map_or(1.0, |s| stage::per_step(self.schedule(), s, REORDER_EVERY))
    }

    /// Encode one run of a stage: its entries of the schedule at the base
    /// state ([`stage::at_base`]).
    pub(super) fn encode_stage(&self, enc: &mut wgpu::CommandEncoder, stage: Stage) {
        if stage == Stage::Reorder {
            self.encode_reorder(enc);
            return;
        }
        let mut pass = enc.begin_compute_pass(&Default::default());
        for e in stage::at_base(self.schedule(), stage) {
            if e.role == Role::Drifted {
                // Alone, the cell list counts for itself (in a step the
                // drift counts).
                self.encode_grid(&mut pass, Var::Base);
            } else {
                self.encode_entry(&mut pass, e);
            }
        }
    }

    /// Wall time of `reps` runs of one stage (a name of
    /// [`GpuSolver::stage_names`]) encoded into one command buffer, from
    /// submission to the device going idle: one stage timed alone, on the
    /// current state.
    ///
    /// Before timing, one untimed evaluation at the current state (cell
    /// list, passes, contact, CFL step) gives every stage valid inputs, so
    /// a stage can be timed in any order. The state is left as it was: the
    /// evaluation stages only rewrite per-evaluation scratch that the next
    /// step recomputes, the reordering only permutes the particles, and
    /// what the rest changes (the control block's counters, and for
    /// `advance`, which is not idempotent, the state itself) is saved
    /// before and copied back after, so stepping may go on afterwards.
    /// (A reordering timed between the steps that reorder anyway leaves a
    /// different particle order until the next one, so the sums after it
    /// may differ from an untimed run's in the last bits.)
    ///
    /// Wall time rather than timestamp queries: it needs no optional
    /// adapter feature, and over many repetitions the one submission's
    /// overhead is small.
    pub fn time_stage(&mut self, name: &str, reps: u32) -> Result<std::time::Duration, String> {
        let names = self.stage_names();
        let stage = match Stage::named(name) {
            Some(s) if names.contains(&name) => s,
            _ => {
                return Err(format!(
                    "no GPU stage '{name}' for this scene (stages: {})",
                    names.join(", ")
                ))
            }
        };
        if reps == 0 {
            return Err("a stage is timed over at least one repetition".into());
        }
        let ctx = self.ctx.clone();
        let dev = &ctx.device;
        let nn = self.n as u64;
        let mut saved = vec![(Buf::Ctl, CTL_BYTES)];
        if self.k.leap.is_some() {
            // Every stage of a leapfrog step changes the state or what it
            // carries: all of it is put back afterwards.
            saved = self.persistent_buffers();
        } else if stage == Stage::Advance {
            // Of the state it moves the positions only (and carries the
            // supports where they adapt): the rest of the full step is
            // added in place by the passes at the midpoint.
            saved.push((Buf::U, 8 * nn));
            if self.model.adaptive {
                saved.push((Buf::Metric, 16 * nn));
            }
        }
        let backups: Vec<wgpu::Buffer> = saved
            .iter()
            .map(|(label, bytes)| {
                dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label.name()),
                    size: *bytes,
                    usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let wait = || {
            dev.poll(wgpu::PollType::wait_indefinitely())
                .map(|_| ())
                .map_err(|e| format!("waiting for the device: {e}"))
        };

        let mut enc = dev.create_command_encoder(&Default::default());
        self.encode_first(&mut enc);
        for ((from, bytes), to) in saved.iter().zip(&backups) {
            enc.copy_buffer_to_buffer(self.buf(*from), 0, to, 0, *bytes);
        }
        if let Some(l) = &self.k.leap {
            // A whole step, then the cell list it ends by zeroing and the
            // neighbour masks its booking overwrites: every stage's inputs
            // are then valid. The kinematics pass lists the boundary particles again,
            // from an empty list.
            self.encode_step_pass(&mut enc.begin_compute_pass(&Default::default()));
            if let Some(args) = self.buffers.get(Buf::SurfArgs) {
                enc.clear_buffer(args, 0, Some(4));
            }
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            l.kinematics_all().for_each(|k| pass.run(k));
        } else {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_eval(&mut pass, Var::Base);
            self.encode_reduce(&mut pass);
        }
        self.ctx.queue.submit([enc.finish()]);
        wait()?;

        let mut enc = dev.create_command_encoder(&Default::default());
        for _ in 0..reps {
            self.encode_stage(&mut enc, stage);
        }
        let commands = enc.finish();
        let start = std::time::Instant::now();
        self.ctx.queue.submit([commands]);
        wait()?;
        let elapsed = start.elapsed();

        let mut enc = dev.create_command_encoder(&Default::default());
        for ((to, bytes), from) in saved.iter().zip(&backups) {
            enc.copy_buffer_to_buffer(from, 0, self.buf(*to), 0, *bytes);
        }
        self.ctx.queue.submit([enc.finish()]);
        self.leap_clear();
        if self.k.leap.is_some() {
            // The particles are back in their order; the probes' slots too.
            self.refresh_probe_slots();
        }
        wait()?;
        Ok(elapsed)
    }

    /// A test kernel's bind group (debug.wgsl): its own buffers `own` by
    /// name, the solver's for the rest.
    fn test_bind(&self, p: &Pipeline, own: &[(&str, &wgpu::Buffer)]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = p
            .bindings
            .iter()
            .map(|b| wgpu::BindGroupEntry {
                binding: b.binding,
                resource: match own.iter().find(|o| o.0 == b.name) {
                    Some(o) => o.1.as_entire_binding(),
                    None => {
                        let name = Buf::from_name(&b.name);
                        self.buf(name.expect("a test kernel binds device buffers by name"))
                            .as_entire_binding()
                    }
                },
            })
            .collect();
        self.ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("test kernel"),
                layout: &p.layout,
                entries: &entries,
            })
    }

    /// The device's equation of state (common.wgsl, `pressure_of` and
    /// `sound_speed_of`) at `states`, each `[μ, e, damage]` of body
    /// `body`: `(pressure, sound speed)` each (tests: the EOS against its
    /// formula and its CPU twin).
    pub fn equation_of_state(&self, body: u32, states: &[[f32; 3]]) -> Vec<[f32; 2]> {
        let input: Vec<[f32; 4]> = states
            .iter()
            .map(|s| [s[0], s[1], s[2], body as f32])
            .collect();
        let out = self.table("eos_table", ("eos_in", "eos_out"), &input, 8);
        bytemuck::cast_slice::<u8, [f32; 2]>(&out)[..states.len()].to_vec()
    }

    /// The device's strength law of body `body` (strength.wgsl's
    /// `law_factor`, `law_curve` and `return_increment`) at `rows`, each
    /// `[ε_p, ε̇, T − T_room, q_trial]`: `[factor, σ_y, dσ_y/dε_p, Δε_p]`
    /// each, the return from `q_trial` with the body's shear modulus
    /// (tests: each law against its formula on the device).
    pub fn strength_law(&self, body: u32, rows: &[[f32; 4]]) -> Vec<[f32; 4]> {
        let input: Vec<[f32; 4]> = rows
            .iter()
            .flat_map(|r| [*r, [body as f32, 0.0, 0.0, 0.0]])
            .collect();
        let out = self.table("law_table", ("law_in", "law_out"), &input, 16);
        bytemuck::cast_slice::<u8, [f32; 4]>(&out)
            .chunks(2)
            .take(rows.len())
            .map(|c| c[0])
            .collect()
    }

    /// Run the test kernel `entry` (debug.wgsl) over `input`, one thread a
    /// row, its buffers named `names` (in, out): the output, `stride` bytes
    /// a row.
    fn table(&self, entry: &str, names: (&str, &str), input: &[[f32; 4]], stride: u64) -> Vec<u8> {
        let dev = &self.ctx.device;
        let consts = [
            ("WG", WG as f64),
            ("FAILURE", self.model.can_fail() as u8 as f64),
            ("CAVITATION", self.model.cavitates() as u8 as f64),
            ("STRENGTH_LAWS", self.model.strength_laws() as f64),
            ("EOS_LAWS", self.model.eos_laws() as f64),
            ("FAILURE_LAWS", self.model.failure_laws() as f64),
        ];
        let p = self.ctx.pipeline("debug", "", entry, &consts);
        let len = input.len().max(1) as u64;
        let buffer = |label, size, usage| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let t_in = buffer(names.0, 16 * len, wgpu::BufferUsages::COPY_DST);
        let t_out = buffer(names.1, stride * len, wgpu::BufferUsages::COPY_SRC);
        self.ctx
            .queue
            .write_buffer(&t_in, 0, bytemuck::cast_slice(input));
        let bind = self.test_bind(&p, &[(names.0, &t_in), (names.1, &t_out)]);
        let read = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("table_read"),
            size: stride * len,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&p.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups((len as u32).div_ceil(WG), 1, 1);
        }
        enc.copy_buffer_to_buffer(&t_out, 0, &read, 0, stride * len);
        self.ctx.queue.submit([enc.finish()]);
        map_read(&self.ctx, &read, stride * len)
    }

    /// One evaluation at the current state, with every stage's output read
    /// back (tests: the device against its CPU twins). Does not step.
    pub fn stage_outputs(&mut self) -> StageOutputs {
        assert!(
            self.k.leap.is_none(),
            "stage_outputs reads the midpoint rule's evaluation"
        );
        let n = self.n;
        let nn = n as u64;
        let dev = &self.ctx.device;
        // Reorder first, as a run does, so the check covers permuted slots.
        let mut enc = dev.create_command_encoder(&Default::default());
        self.encode_reorder(&mut enc);
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            let e = &self.k.eval[0];
            e.kinematics_all().for_each(|k| k.dispatch(&mut pass));
            e.forces_all().for_each(|k| k.dispatch(&mut pass));
        }
        let first = self.read_buffers(
            Some(enc),
            &[
                (Buf::Pinfo, 16 * nn),
                (Buf::Lmat, 16 * nn),
                (Buf::Nbo, 16 * nn),
                (Buf::Sr2c, 16 * nn),
                // The rates at the base state, left in the midpoint buffers.
                (Buf::Rm, 8 * nn),
                (Buf::Sm, 16 * nn),
                (Buf::Vm, 8 * nn),
            ],
        );
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            for k in self.k.eval[0].contact.iter().flat_map(ContactKernels::all) {
                k.dispatch(&mut pass);
            }
            self.encode_reduce(&mut pass);
        }
        let mut names = vec![(Buf::Vm, 8 * nn), (Buf::Rm, 8 * nn), (Buf::Ctl, CTL_BYTES)];
        if self.model.contact {
            let cap = self.params.surf_cap as u64;
            names.push((Buf::Area, 4 * cap));
            names.push((Buf::Cn, 16 * cap));
        }
        let second = self.read_buffers(Some(enc), &names);
        // The strength update of the midpoint state, at the step the
        // reductions chose.
        let mid = self.model.history.then(|| {
            let mut enc = dev.create_command_encoder(&Default::default());
            if let Some(k) = &self.k.advance_half {
                k.dispatch(&mut enc.begin_compute_pass(&Default::default()));
            }
            self.read_buffers(
                Some(enc),
                &[(Buf::Sm, 16 * nn), (Buf::Rm, 8 * nn), (Buf::Histm, 16 * nn)],
            )
        });

        // Neighbour dump (test-only kernel), indexed by original id.
        let dump_data = self.dump_neighbours();
        let dump_u: &[u32] = bytemuck::cast_slice(&dump_data);

        let meta: &[[u32; 4]] = bytemuck::cast_slice(&first[0]);
        let l: &[[f32; 4]] = bytemuck::cast_slice(&first[1]);
        let nbo: &[[f32; 4]] = bytemuck::cast_slice(&first[2]);
        let sr2c: &[[f32; 4]] = bytemuck::cast_slice(&first[3]);
        let dr1: &[[f32; 2]] = bytemuck::cast_slice(&first[4]);
        let ds: &[[f32; 4]] = bytemuck::cast_slice(&first[5]);
        let dv1: &[[f32; 2]] = bytemuck::cast_slice(&first[6]);
        let dv2: &[[f32; 2]] = bytemuck::cast_slice(&second[0]);
        let dr2: &[[f32; 2]] = bytemuck::cast_slice(&second[1]);
        let ctl: Control = bytemuck::pod_read_unaligned(&second[2]);
        // With contact, the areas and the contact's normals (forces.wgsl)
        // at each boundary particle's place on the list; else the colour
        // gradient's normals.
        let area: Option<&[f32]> = second.get(3).map(|a| bytemuck::cast_slice(a));
        let cn: Option<&[[f32; 4]]> = second.get(4).map(|a| bytemuck::cast_slice(a));
        let mut out = StageOutputs::empty(n, ctl.dt as f64);
        if let Some(m) = &mid {
            self.fill_mid(&mut out, meta, m);
        }
        let v2 = |a: [f32; 2]| DVec2::new(a[0] as f64, a[1] as f64);
        for k in 0..n {
            let i = meta[k][3] as usize;
            let base = i * 128;
            let cnt = dump_u[base] as usize;
            let mut nb = dump_u[base + 1..base + 1 + cnt].to_vec();
            nb.sort_unstable();
            out.neighbours[i] = nb;
            out.visits[i] = dump_u[base + 127];
            out.l[i] = l[k].map(|x| x as f64);
            out.boundary[i] = nbo[k][2] > 0.0;
            let place = nbo[k][3] as usize;
            let nk = match cn {
                Some(c) if out.boundary[i] => c[place],
                Some(_) => [0.0; 4],
                None => nbo[k],
            };
            out.normal[i] = DVec2::new(nk[0] as f64, nk[1] as f64);
            out.sr2[i] = [sr2c[k][0] as f64, sr2c[k][1] as f64, sr2c[k][2] as f64];
            // The sign marks a particle that flows (kinematics.wgsl, flows).
            out.c[i] = (sr2c[k][3] as f64).abs();
            out.flows[i] = sr2c[k][3] < 0.0;
            out.drho[i] = self.model.material(i).rho0 * dr1[k][0] as f64;
            out.ds[i] = sym_of(ds[k]);
            out.dv_sph[i] = v2(dv1[k]);
            out.de_sph[i] = dr1[k][1] as f64;
            out.dv[i] = v2(dv2[k]);
            out.de[i] = dr2[k][1] as f64;
            out.contact_force[i] = (out.dv[i] - out.dv_sph[i]) * self.model.mass[i];
            if let Some(a) = area.filter(|_| out.boundary[i]) {
                out.area[i] = a[place] as f64;
            }
        }
        out
    }

    /// The midpoint state's stress, density and history (`m`: the
    /// buffers `sm`, `rm`, `histm`) by original id into `out`.
    fn fill_mid(&self, out: &mut StageOutputs, meta: &[[u32; 4]], m: &[Vec<u8>]) {
        let n = self.n;
        let sm: &[[f32; 4]] = bytemuck::cast_slice(&m[0]);
        let rm: &[[f32; 2]] = bytemuck::cast_slice(&m[1]);
        let hm: &[[f32; 4]] = bytemuck::cast_slice(&m[2]);
        out.mid_s = vec![Sym::default(); n];
        out.mid_rho = vec![0.0; n];
        out.mid_hist = vec![[0.0; 4]; n];
        for k in 0..n {
            let i = meta[k][3] as usize;
            let mat = self.model.material(i);
            out.mid_s[i] = sym_of(sm[k]);
            out.mid_rho[i] = mat.rho0 * (1.0 + rm[k][0] as f64);
            out.mid_hist[i] = self.history_of(i, hm[k]);
        }
    }

    /// Each particle's neighbour list as the walk visits it (the test-only
    /// kernel `dump_neighbours`): 128 words a particle by original id, the
    /// count first and the visits last.
    fn dump_neighbours(&self) -> Vec<u8> {
        let (n, nn, dev) = (self.n, self.n as u64, &self.ctx.device);
        let consts = [("DIM", self.model.dim as f64), ("WG", WG as f64)];
        let p = self.ctx.pipeline("debug", "", "dump_neighbours", &consts);
        let dump = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dump"),
            size: 4 * 128 * nn,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind = self.test_bind(&p, &[("dump", &dump)]);
        let mut enc = dev.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&p.pipeline);
            pass.set_bind_group(0, &bind, &[]);
            let g = (n as u32).div_ceil(WG);
            let maxd = self.ctx.limits.max_compute_workgroups_per_dimension;
            if g <= maxd {
                pass.dispatch_workgroups(g, 1, 1);
            } else {
                pass.dispatch_workgroups(maxd, g.div_ceil(maxd), 1);
            }
        }
        let stage = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("dump readback"),
            size: 4 * 128 * nn,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        enc.copy_buffer_to_buffer(&dump, 0, &stage, 0, 4 * 128 * nn);
        self.ctx.queue.submit([enc.finish()]);
        map_read(&self.ctx, &stage, 4 * 128 * nn)
    }
}

impl StageOutputs {
    /// Outputs of `n` particles, all zero, at the step `dt`.
    fn empty(n: usize, dt: f64) -> StageOutputs {
        StageOutputs {
            neighbours: vec![Vec::new(); n],
            visits: vec![0; n],
            l: vec![[0.0; 4]; n],
            normal: vec![DVec2::ZERO; n],
            boundary: vec![false; n],
            sr2: vec![[0.0; 3]; n],
            c: vec![0.0; n],
            flows: vec![false; n],
            drho: vec![0.0; n],
            ds: vec![Sym::default(); n],
            dv_sph: vec![DVec2::ZERO; n],
            de_sph: vec![0.0; n],
            area: vec![0.0; n],
            contact_force: vec![DVec2::ZERO; n],
            dv: vec![DVec2::ZERO; n],
            de: vec![0.0; n],
            dt,
            mid_s: Vec::new(),
            mid_rho: Vec::new(),
            mid_hist: Vec::new(),
        }
    }
}
