//! A compiled kernel and how a step dispatches it: into a compute pass, a
//! timed pass or a tally of the work; the step's kernels by role.

use super::*;

/// How many threads a kernel runs.
#[derive(Debug, Clone, Copy)]
pub(super) enum Size {
    Particles,
    Buckets,
    ScanBlocks,
    RedGroups,
    /// One workgroup for the step and one for each observation slot.
    FinalGroups,
    One,
}

/// Which state the evaluation reads: the step's base state or the midpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Var {
    Base,
    Mid,
}

/// Whether a kernel walks the neighbours, and whose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Walk {
    None,
    /// Every particle's thread walks.
    All,
    /// Only the boundary particles' threads walk (the contact).
    Boundary,
    /// The threads of a list of the boundary particles walk, one a
    /// particle (the leapfrog's contact, dispatched over the list).
    Listed,
    /// Every particle's thread visits the pairs of its neighbour mask
    /// (walk.wgsl), or walks in full where the mask overflowed.
    Masked,
}

pub(super) struct Kernel {
    /// The entry point.
    pub(super) name: String,
    /// Its shader (a stage of [`crate::stage::STAGES`]).
    pub(super) stage: String,
    /// Its role where a step runs one entry point in two roles (what a
    /// step profile calls it then, [`Kernel::label`]).
    pub(super) role: Option<&'static str>,
    pub(super) pipeline: Arc<Pipeline>,
    pub(super) bind: wgpu::BindGroup,
    pub(super) groups: (u32, u32),
    pub(super) walk: Walk,
    /// A dispatch sized on the device: its workgroups are the three words
    /// at byte 4 of this buffer (`surf_args`, contact.wgsl).
    pub(super) indirect: Option<wgpu::Buffer>,
}

impl Kernel {
    pub(super) fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline.pipeline);
        pass.set_bind_group(0, &self.bind, &[]);
        match &self.indirect {
            Some(args) => pass.dispatch_workgroups_indirect(args, 4),
            None => pass.dispatch_workgroups(self.groups.0, self.groups.1, 1),
        }
    }

    /// The kernel dispatched over the contact's list of boundary particles.
    pub(super) fn listed(mut self, args: &wgpu::Buffer) -> Self {
        self.walk = Walk::Listed;
        self.indirect = Some(args.clone());
        self
    }

    pub(super) fn walking(mut self, walk: Walk) -> Self {
        self.walk = walk;
        self
    }

    pub(super) fn labelled(mut self, role: &'static str) -> Self {
        self.role = Some(role);
        self
    }

    /// What a step profile calls it: its role, else its entry point.
    pub(super) fn label(&self) -> &str {
        self.role.unwrap_or(&self.name)
    }
}

/// Where a step's dispatches go: into a compute pass, or into a tally of
/// the work ([`GpuSolver::step_work`]). The step is encoded by one code for
/// both, so the tally counts what runs.
pub(super) trait Dispatches {
    fn run(&mut self, k: &Kernel);
}

impl Dispatches for wgpu::ComputePass<'_> {
    fn run(&mut self, k: &Kernel) {
        k.dispatch(self);
    }
}

/// Dispatches and neighbour walks, by kernel entry point in the order run.
#[derive(Default)]
pub(super) struct Tally {
    pub(super) dispatches: u32,
    pub(super) walks: Vec<(String, Walk)>,
}

/// A compute pass with a timestamp after every dispatch
/// ([`GpuSolver::run_batch_profiled`]).
pub(super) struct Timed<'a, 'p> {
    pub(super) pass: &'a mut wgpu::ComputePass<'p>,
    pub(super) timer: &'a mut profile::StepTimer,
}

impl Dispatches for Timed<'_, '_> {
    fn run(&mut self, k: &Kernel) {
        k.dispatch(self.pass);
        self.timer
            .after_pass_dispatch(self.pass, &k.stage, k.label());
    }
}

impl Dispatches for Tally {
    fn run(&mut self, k: &Kernel) {
        self.dispatches += 1;
        if k.walk != Walk::None {
            self.walks.push((k.name.clone(), k.walk));
        }
    }
}

/// An evaluation's kernels for one state variant.
pub(super) struct Eval {
    // The cell list's two per-particle passes read the evaluation's state
    // (a particle's cell is recomputed, not stored; neighbours.wgsl).
    pub(super) cells: Kernel,
    pub(super) scatter: Kernel,
    pub(super) kinematics: Kernel,
    pub(super) forces: Kernel,
    /// The dispersion correction's walks (dispersion.wgsl): `disperse`
    /// after the kinematic walk, `disperse_forces` after the forces walk.
    pub(super) dispersion: Option<[Kernel; 2]>,
    pub(super) contact: Option<ContactKernels>,
}

impl Eval {
    /// The kinematics stage's dispatches.
    pub(super) fn kinematics_all(&self) -> impl Iterator<Item = &Kernel> {
        std::iter::once(&self.kinematics).chain(self.dispersion.iter().map(|d| &d[0]))
    }

    /// The forces stage's dispatches.
    pub(super) fn forces_all(&self) -> impl Iterator<Item = &Kernel> {
        std::iter::once(&self.forces).chain(self.dispersion.iter().map(|d| &d[1]))
    }
}

/// The contact's force passes in their order: the two gathers, then the
/// spread of the spring's pull through the normals (contact.wgsl), which
/// the midpoint rule's steps gather in their advance passes instead: its
/// evaluation at the midpoint has none, its base one serves only the
/// stage outputs the tests read ([`GpuSolver::stage_outputs`]).
pub(super) struct ContactKernels {
    pub(super) pass1: Kernel,
    pub(super) pass2: Kernel,
    /// With friction, the rub pass and its gather (contact.wgsl, RUB),
    /// after pass 2.
    pub(super) rub: Option<[Kernel; 2]>,
    pub(super) spread: Option<Kernel>,
}

impl ContactKernels {
    pub(super) fn all(&self) -> impl Iterator<Item = &Kernel> {
        [&self.pass1, &self.pass2]
            .into_iter()
            .chain(self.rub.iter().flatten())
            .chain(&self.spread)
    }
}

/// The leapfrog step's kernels besides the cell list and the reductions
/// (advance.wgsl has the order).
pub(super) struct LeapKernels {
    pub(super) kick_drift: Kernel,
    pub(super) kinematics: Kernel,
    pub(super) forces: Kernel,
    pub(super) contact: Option<ContactKernels>,
    /// The booking's contact passes (none without contact): the first,
    /// and the second only with a rigid body (contact.wgsl, pass1_at).
    pub(super) book: Vec<Kernel>,
    pub(super) energy: Kernel,
    /// The dispersion correction's walks (dispersion.wgsl):
    /// `disperse_leap` and `disperse_stress` after the kinematic walk,
    /// `disperse_forces_leap` after the forces walk, `disperse_work` after
    /// the energy walk.
    pub(super) dispersion: Option<[Kernel; 4]>,
    pub(super) finish: Kernel,
}

impl LeapKernels {
    /// The kinematics stage's dispatches.
    pub(super) fn kinematics_all(&self) -> impl Iterator<Item = &Kernel> {
        std::iter::once(&self.kinematics).chain(self.dispersion.iter().flat_map(|d| &d[..2]))
    }

    /// The forces stage's dispatches at n+1.
    pub(super) fn forces_all(&self) -> impl Iterator<Item = &Kernel> {
        std::iter::once(&self.forces).chain(self.dispersion.iter().map(|d| &d[2]))
    }

    /// The energy walk's dispatches.
    pub(super) fn energy_all(&self) -> impl Iterator<Item = &Kernel> {
        std::iter::once(&self.energy).chain(self.dispersion.iter().map(|d| &d[3]))
    }
}

pub(super) struct Kernels {
    pub(super) clear: Kernel,
    pub(super) scan_local: Kernel,
    pub(super) scan_add: Kernel,
    pub(super) sort: Kernel,
    /// The evaluation at the base state and, for the midpoint rule, at the
    /// midpoint; for the leapfrog its first evaluation (LEAP = 1) alone.
    pub(super) eval: Vec<Eval>,
    pub(super) leap: Option<LeapKernels>,
    /// The reductions (reduce.wgsl): the CFL minimum and the observation
    /// sums over the particles, then the step, the observations, the
    /// energy guard and the probes.
    pub(super) reduce_partial: Kernel,
    pub(super) reduce_final: Kernel,
    pub(super) advance_half: Option<Kernel>,
    pub(super) advance_full: Option<Kernel>,
    pub(super) end_step: Kernel,
    /// The midpoint rule's reorder: every array at once into the midpoint
    /// state's buffers and pass scratch.
    pub(super) permute: Option<Kernel>,
    /// The leapfrog's: each array of [`leap_arrays`] in turn through one
    /// scratch buffer (`lmat`), with its name and bytes a particle.
    pub(super) permute_each: Vec<(Kernel, Buf, u64)>,
    /// Refreshes the probed particles' slots after a reorder (none without
    /// particle probes).
    pub(super) map_slots: Option<Kernel>,
}
