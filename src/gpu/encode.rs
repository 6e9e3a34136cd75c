//! Encoding the step: each entry of the integrator's schedule
//! ([`crate::stage`]) as its dispatches, the periodic reorder, and the
//! leapfrog's first evaluation.

use super::*;

impl GpuSolver {
    /// Find the probed particles' slots (nothing without particle probes).
    pub(super) fn encode_map_slots(&self, enc: &mut wgpu::CommandEncoder) {
        if let Some(k) = &self.k.map_slots {
            let mut pass = enc.begin_compute_pass(&Default::default());
            k.dispatch(&mut pass);
        }
    }

    /// [`Self::encode_map_slots`] submitted on its own: for a state that
    /// did not come from a step (built, or restored from a checkpoint).
    pub(super) fn refresh_probe_slots(&self) {
        if self.k.map_slots.is_none() {
            return;
        }
        let mut enc = self.ctx.device.create_command_encoder(&Default::default());
        self.encode_map_slots(&mut enc);
        self.ctx.queue.submit([enc.finish()]);
    }

    pub(super) fn encode_grid(&self, pass: &mut impl Dispatches, var: Var) {
        let k = &self.k;
        pass.run(&k.clear);
        pass.run(&k.eval[var as usize].cells);
        self.encode_grid_after_counts(pass, var);
    }

    /// The cell list from its counts on: the scan, the scatter, the sort.
    pub(super) fn encode_grid_after_counts(&self, pass: &mut impl Dispatches, var: Var) {
        let k = &self.k;
        pass.run(&k.scan_local);
        pass.run(&k.scan_add);
        pass.run(&k.eval[var as usize].scatter);
        pass.run(&k.sort);
    }

    /// An evaluation: the cell list, the kinematics, the forces and the
    /// contact. The midpoint rule's advance passes gather the contact's
    /// spread (advance.wgsl); the leapfrog's first evaluation runs it.
    pub(super) fn encode_eval(&self, pass: &mut impl Dispatches, var: Var) {
        self.encode_grid(pass, var);
        let e = &self.k.eval[var as usize];
        e.kinematics_all().for_each(|k| pass.run(k));
        e.forces_all().for_each(|k| pass.run(k));
        self.encode_contact(pass, var);
    }

    /// An evaluation's contact passes, and the spread where it is a pass
    /// of its own: in the leapfrog's first evaluation, and in the midpoint
    /// rule's at the base state where regions are held, whose forces the
    /// reductions then read whole (reduce.wgsl, held slots); advance_half
    /// finds nothing left to gather.
    fn encode_contact(&self, pass: &mut impl Dispatches, var: Var) {
        let Some(c) = &self.k.eval[var as usize].contact else {
            return;
        };
        pass.run(&c.pass1);
        pass.run(&c.pass2);
        c.rub.iter().flatten().for_each(|k| pass.run(k));
        let own_spread = self.k.leap.is_some() || !self.model.held.is_empty();
        if let Some(spread) = c.spread.as_ref().filter(|_| own_spread) {
            pass.run(spread);
        }
    }

    /// Reorder the particles by cell: gather into scratch, copy back.
    pub(super) fn encode_reorder(&self, enc: &mut wgpu::CommandEncoder) {
        let n = self.n as u64;
        if self.k.leap.is_some() {
            self.encode_grid(&mut enc.begin_compute_pass(&Default::default()), Var::Base);
            for (k, name, bytes) in &self.k.permute_each {
                k.dispatch(&mut enc.begin_compute_pass(&Default::default()));
                enc.copy_buffer_to_buffer(self.buf(Buf::Lmat), 0, self.buf(*name), 0, bytes * n);
            }
            self.encode_map_slots(enc);
            // Between leapfrog steps the cell list's counts are zero.
            self.k
                .clear
                .dispatch(&mut enc.begin_compute_pass(&Default::default()));
            return;
        }
        let Some(permute) = &self.k.permute else {
            return;
        };
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            self.encode_grid(&mut pass, Var::Base);
            permute.dispatch(&mut pass);
        }
        let mut copy = |from: Buf, to: Buf, bytes: u64| {
            enc.copy_buffer_to_buffer(self.buf(from), 0, self.buf(to), 0, bytes * n);
        };
        copy(Buf::Lmat, Buf::X0, 16);
        copy(Buf::Um, Buf::U, 8);
        copy(Buf::Vm, Buf::V, 8);
        copy(Buf::Rm, Buf::R, 8);
        copy(Buf::Sm, Buf::S, 16);
        copy(Buf::Sr2c, Buf::Pinfo, 16);
        if self.model.contact {
            copy(Buf::Cown, Buf::Qheat, 8);
            copy(Buf::Nbo, Buf::Centry, 4);
        }
        // The arrays `permute` has no room for, through `lmat` (its x0 is
        // copied out above).
        for (k, name, bytes) in &self.k.permute_each {
            k.dispatch(&mut enc.begin_compute_pass(&Default::default()));
            enc.copy_buffer_to_buffer(self.buf(Buf::Lmat), 0, self.buf(*name), 0, bytes * n);
        }
        self.encode_map_slots(enc);
    }

    /// The reductions after the first evaluation of a step: the CFL step,
    /// then the per-step observations and probes when the run records any.
    /// One sequence for the step and for timing the stage alone.
    pub(super) fn encode_reduce(&self, pass: &mut impl Dispatches) {
        pass.run(&self.k.reduce_partial);
        pass.run(&self.k.reduce_final);
    }

    pub(super) fn encode_step(
        &self,
        enc: &mut wgpu::CommandEncoder,
        step_index: u64,
        mut timer: Option<&mut profile::StepTimer>,
    ) {
        if step_index.is_multiple_of(REORDER_EVERY) {
            self.encode_reorder(enc);
            if let Some(t) = timer.as_deref_mut() {
                t.after_encoder_work(enc, "reorder", "reorder");
            }
        }
        let mut pass = enc.begin_compute_pass(&Default::default());
        match timer {
            Some(timer) => self.encode_step_pass(&mut Timed {
                pass: &mut pass,
                timer,
            }),
            None => self.encode_step_pass(&mut pass),
        }
    }

    /// The step's schedule ([`crate::stage`]).
    pub(super) fn schedule(&self) -> &'static [Scheduled] {
        stage::schedule(self.model.integrator)
    }

    /// A step's dispatches after the periodic reorder, in one compute
    /// pass: the schedule's entries in order.
    pub(super) fn encode_step_pass(&self, pass: &mut impl Dispatches) {
        for &e in self.schedule() {
            if e.stage != Stage::Reorder {
                self.encode_entry(pass, e);
            }
        }
    }

    /// The dispatches of one entry of the schedule (the reorder aside: it
    /// copies buffers between its dispatches, [`GpuSolver::encode_reorder`]).
    ///
    /// Leapfrog: the reductions read the state the step starts from; the
    /// cell list at `x_{n+1}` takes its counts from the drift (the last
    /// step's `finish` zeroed them); the energy walk reads the neighbour
    /// masks that the booking's rates then overwrite (`mask_home`).
    pub(super) fn encode_entry(&self, pass: &mut impl Dispatches, e: Scheduled) {
        let k = &self.k;
        let var = if e.role == Role::Mid {
            Var::Mid
        } else {
            Var::Base
        };
        let ev = &k.eval[var as usize];
        let midpoint = "a kernel of the midpoint rule";
        match (e.stage, e.role, &k.leap) {
            (Stage::Neighbours, Role::Drifted, Some(_)) => {
                self.encode_grid_after_counts(pass, Var::Base)
            }
            (Stage::Neighbours, _, None) => self.encode_grid(pass, var),
            (Stage::Kinematics, _, Some(l)) => l.kinematics_all().for_each(|k| pass.run(k)),
            (Stage::Kinematics, _, None) => ev.kinematics_all().for_each(|k| pass.run(k)),
            (Stage::Forces, Role::Energy, Some(l)) => l.energy_all().for_each(|k| pass.run(k)),
            (Stage::Forces, _, Some(l)) => l.forces_all().for_each(|k| pass.run(k)),
            (Stage::Forces, _, None) => ev.forces_all().for_each(|k| pass.run(k)),
            (Stage::Contact, Role::Book, Some(l)) => l.book.iter().for_each(|k| pass.run(k)),
            (Stage::Contact, _, Some(l)) => l
                .contact
                .iter()
                .flat_map(ContactKernels::all)
                .for_each(|k| pass.run(k)),
            (Stage::Contact, _, None) => self.encode_contact(pass, var),
            (Stage::Reduce, _, _) => self.encode_reduce(pass),
            (Stage::Advance, Role::HalfStep, None) => {
                pass.run(k.advance_half.as_ref().expect(midpoint))
            }
            (Stage::Advance, Role::FullStep, None) => {
                pass.run(k.advance_full.as_ref().expect(midpoint));
                pass.run(&k.end_step);
            }
            (Stage::Advance, Role::KickDrift, Some(l)) => pass.run(&l.kick_drift),
            (Stage::Advance, Role::Finish, Some(l)) => {
                pass.run(&l.finish);
                pass.run(&k.end_step);
            }
            _ => unreachable!("{e:?} is not an entry of this integrator's step"),
        }
    }

    /// The leapfrog's first evaluation, if the run has not made it yet: the
    /// rates at the initial state that its first step starts from.
    pub(super) fn encode_first(&mut self, enc: &mut wgpu::CommandEncoder) {
        if !self.first_pending {
            return;
        }
        self.first_pending = false;
        let mut pass = enc.begin_compute_pass(&Default::default());
        self.encode_eval(&mut pass, Var::Base);
        self.k.clear.dispatch(&mut pass);
    }

    /// After a cell list built outside a leapfrog step: zero the counts
    /// again, which the next step's drift counts into (advance.wgsl,
    /// finish).
    pub(super) fn leap_clear(&self) {
        if self.k.leap.is_some() {
            let mut enc = self.ctx.device.create_command_encoder(&Default::default());
            self.k
                .clear
                .dispatch(&mut enc.begin_compute_pass(&Default::default()));
            self.ctx.queue.submit([enc.finish()]);
        }
    }
}
