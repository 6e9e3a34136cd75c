//! The device's kernels for a scene: each entry point compiled with the
//! scene's override constants, its buffers bound by name (aliases where
//! an evaluation reads or writes other buffers than its names say), its
//! workgroups sized.

use super::*;

/// How many particles, cell-list buckets and reduction groups a scene has,
/// and the adapter's largest dispatch along one dimension.
#[derive(Clone, Copy)]
pub(super) struct Sizes {
    pub n: usize,
    pub buckets: u32,
    pub red_groups: u32,
    pub maxd: u32,
}

/// Every kernel of a scene's step, bound to `buffers`.
pub(super) fn make_kernels(
    ctx: &GpuContext,
    model: &Model,
    plan: &ProbePlan,
    buffers: &DeviceBuffers,
    sizes: Sizes,
) -> Result<Kernels, String> {
    let leapfrog = model.integrator == Integrator::Leapfrog;
    // The velocity gradient adaptive supports are carried with at a
    // step's end (`supports_carried_by_gradv`).
    let support_gradient = if supports_carried_by_gradv(model) {
        Buf::Gradv
    } else {
        Buf::Lgrad
    };
    let constants = override_constants(model, plan, support_gradient);
    // The reductions are compiled for this scene's observation slots.
    let binder = Binder {
        ctx,
        buffers,
        sizes,
        plan,
        slot_wgsl: plan.wgsl(),
    };
    let kernel = |stage: &str, entry: &str, size: Size, table: &[(&str, Buf)]| {
        binder.kernel(&constants, stage, entry, size, table)
    };
    let eval = eval_kernels(&binder, model, &constants, support_gradient)?;
    let leap = if leapfrog {
        Some(leap_kernels(&binder, model, &constants)?)
    } else {
        None
    };
    Ok(Kernels {
        clear: kernel("neighbours", "grid_clear", Size::Buckets, &[])?,
        scan_local: kernel("neighbours", "scan_local", Size::ScanBlocks, &[])?,
        scan_add: kernel("neighbours", "scan_add", Size::ScanBlocks, &[])?,
        sort: kernel("neighbours", "grid_sort", Size::Buckets, &[])?,
        eval,
        leap,
        reduce_partial: kernel("reduce", "reduce_partial", Size::RedGroups, &[])?,
        reduce_final: kernel("reduce", "reduce_final", Size::FinalGroups, &[])?,
        advance_half: if leapfrog {
            None
        } else {
            Some(kernel(
                "advance",
                "advance_half",
                Size::Particles,
                aliases::ADVANCE_HALF,
            )?)
        },
        advance_full: if leapfrog {
            None
        } else {
            Some(kernel(
                "advance",
                "advance_full",
                Size::Particles,
                &aliases::ADVANCE_FULL
                    .iter()
                    .copied()
                    .chain([("lgrad", support_gradient)])
                    .collect::<Vec<_>>(),
            )?)
        },
        end_step: kernel("reduce", "end_step", Size::One, &[])?,
        permute_each: permute_each_kernels(&binder, model, &constants)?,
        permute: if leapfrog {
            None
        } else {
            Some(kernel(
                "reorder",
                "permute",
                Size::Particles,
                aliases::PERMUTE,
            )?)
        },
        map_slots: if plan.particles.is_empty() {
            None
        } else {
            Some(kernel("reorder", "map_slots", Size::Particles, &[])?)
        },
    })
}

/// The evaluations' kernels (the cell list, kinematics, forces and the
/// contact's passes): at the base state and, for the midpoint rule, at
/// the midpoint (`MID`), each bound through its aliases.
fn eval_kernels(
    binder: &Binder,
    model: &Model,
    constants: &[(&'static str, f64)],
    support_gradient: Buf,
) -> Result<Vec<Eval>, String> {
    let leapfrog = model.integrator == Integrator::Leapfrog;
    let mut mid_constants = constants.to_vec();
    mid_constants.push(("MID", 1.0));
    let variants: &[Var] = if leapfrog {
        &[Var::Base]
    } else {
        &[Var::Base, Var::Mid]
    };
    let mut evals = Vec::new();
    for &var in variants {
        let (consts, al) = match (var, leapfrog) {
            (Var::Base, false) => (constants, aliases::BASE),
            (Var::Base, true) => (constants, aliases::FIRST),
            (Var::Mid, _) => (mid_constants.as_slice(), aliases::MID),
        };
        let eval_kernel = |stage, entry| binder.kernel(consts, stage, entry, Size::Particles, al);
        // The second evaluation's contact entries go on the list where its
        // pass scratch carries the supports' gradient (contact.wgsl, on_list).
        let listed: Vec<(&str, Buf)> = al
            .iter()
            .copied()
            .chain(aliases::ON_LIST.iter().copied())
            .collect();
        let contact_al = if var == Var::Mid && support_gradient == Buf::Gradv {
            listed.as_slice()
        } else {
            al
        };
        let contact_kernel =
            |entry| binder.kernel(consts, "contact", entry, Size::Particles, contact_al);
        evals.push(Eval {
            cells: eval_kernel("neighbours", "grid_cells")?,
            scatter: eval_kernel("neighbours", "grid_scatter")?,
            kinematics: eval_kernel("kinematics", "kinematics")?.walking(Walk::All),
            forces: eval_kernel("forces", "forces")?.walking(Walk::All),
            dispersion: if model.dispersion > 0.0 {
                Some([
                    eval_kernel("kinematics", "disperse")?.walking(Walk::All),
                    eval_kernel("kinematics", "disperse_forces")?.walking(Walk::All),
                ])
            } else {
                None
            },
            contact: if model.contact {
                Some(ContactKernels {
                    pass1: contact_kernel("contact_pass1")?.walking(Walk::Boundary),
                    pass2: contact_kernel("contact_pass2")?.walking(Walk::Boundary),
                    rub: if model.rubs {
                        Some([
                            contact_kernel("contact_rub")?.walking(Walk::Boundary),
                            contact_kernel("contact_rub_gather")?.walking(Walk::Boundary),
                        ])
                    } else {
                        None
                    },
                    spread: match var {
                        Var::Base => Some(eval_kernel("contact", "contact_spread")?),
                        Var::Mid => None,
                    },
                })
            } else {
                None
            },
        });
    }
    Ok(evals)
}

/// The leapfrog step's kernels besides its first evaluation: the step's
/// (`LEAP = 2`) and the booking's (`LEAP = 3`).
fn leap_kernels(
    binder: &Binder,
    model: &Model,
    constants: &[(&'static str, f64)],
) -> Result<LeapKernels, String> {
    let surf_args = binder.buffers.get(Buf::SurfArgs).cloned();
    let mut step_constants = constants.to_vec();
    step_constants.retain(|c| c.0 != "LEAP");
    let mut book_constants = step_constants.clone();
    step_constants.push(("LEAP", 2.0));
    book_constants.push(("LEAP", 3.0));
    let listed_at_n1: Vec<(&str, Buf)> = aliases::AT_N1
        .iter()
        .chain(aliases::ON_LIST)
        .copied()
        .collect();
    let step = |stage, entry, al| binder.kernel(&step_constants, stage, entry, Size::Particles, al);
    let book = |stage, entry| {
        binder.kernel(
            &book_constants,
            stage,
            entry,
            Size::Particles,
            aliases::BOOKING,
        )
    };
    Ok(LeapKernels {
        kick_drift: binder.kernel(
            constants,
            "advance",
            "kick_drift_cells",
            Size::Particles,
            aliases::STATE_W,
        )?,
        kinematics: step("kinematics", "kinematics_leap", aliases::LEAP_KINEMATICS)?
            .walking(Walk::All),
        forces: step("forces", "forces", aliases::AT_N1)?.walking(Walk::Masked),
        contact: match &surf_args {
            Some(a) => Some(ContactKernels {
                pass1: step("contact", "contact_pass1", &listed_at_n1)?.listed(a),
                pass2: step("contact", "contact_pass2", &listed_at_n1)?.listed(a),
                rub: if model.rubs {
                    Some([
                        step("contact", "contact_rub", &listed_at_n1)?.listed(a),
                        step("contact", "contact_rub_gather", &listed_at_n1)?.listed(a),
                    ])
                } else {
                    None
                },
                spread: Some(step("contact", "contact_spread", aliases::AT_N1)?),
            }),
            None => None,
        },
        book: match &surf_args {
            Some(a) => {
                let mut passes: Vec<(&str, &'static str)> = vec![("contact_pass1", "book_pass1")];
                if model.any_rigid {
                    passes.push(("contact_pass2", "book_pass2"));
                }
                // The rub's heat and rates at v_{n+1} (its forces are the
                // step's: no gather).
                if model.rubs {
                    passes.push(("contact_rub", "book_rub"));
                }
                passes
                    .iter()
                    .map(|&(entry, role)| Ok(book("contact", entry)?.listed(a).labelled(role)))
                    .collect::<Result<_, String>>()?
            }
            None => Vec::new(),
        },
        energy: binder
            .kernel(
                &book_constants,
                "forces",
                "forces",
                Size::Particles,
                aliases::ENERGY,
            )?
            .walking(Walk::Masked)
            .labelled("energy"),
        dispersion: if model.dispersion > 0.0 {
            Some([
                step("kinematics", "disperse_leap", aliases::LEAP_KINEMATICS)?.walking(Walk::All),
                step("kinematics", "disperse_stress", aliases::AT_N1)?.walking(Walk::All),
                step("kinematics", "disperse_forces_leap", aliases::AT_N1)?.walking(Walk::All),
                binder
                    .kernel(
                        &book_constants,
                        "kinematics",
                        "disperse_work",
                        Size::Particles,
                        aliases::ENERGY,
                    )?
                    .walking(Walk::All),
            ])
        } else {
            None
        },
        finish: binder.kernel(
            constants,
            "advance",
            "finish",
            Size::Particles,
            aliases::STATE_W,
        )?,
    })
}

/// The reorder's kernels that permute one array each through `lmat`: the
/// leapfrog's arrays, or those the midpoint rule's `permute` has no room
/// for; with each array's buffer and bytes a particle.
fn permute_each_kernels(
    binder: &Binder,
    model: &Model,
    constants: &[(&'static str, f64)],
) -> Result<Vec<(Kernel, Buf, u64)>, String> {
    let arrays = if model.integrator == Integrator::Leapfrog {
        leap_arrays(model)
    } else {
        let mut a = Vec::new();
        if model.history {
            a.push((Buf::Hist, 16));
        }
        if model.adaptive {
            a.push((Buf::Metric, 16));
        }
        a
    };
    arrays
        .into_iter()
        .map(|(name, bytes)| {
            let &(_, entry, src, dst) = aliases::PERMUTE_EACH
                .iter()
                .find(|p| p.0 == bytes)
                .expect("a permute for each element size");
            let al = [(src, name), (dst, Buf::Lmat)];
            let k = binder.kernel(constants, "reorder", entry, Size::Particles, &al)?;
            Ok((k, name, bytes))
        })
        .collect()
}

/// The override constants of a scene's kernels: what it switches on, so
/// that what it does not is compiled out.
fn override_constants(
    model: &Model,
    plan: &ProbePlan,
    support_gradient: Buf,
) -> Vec<(&'static str, f64)> {
    let contact = model.contact;
    vec![
        ("DIM", model.dim as f64),
        ("CONTACT", contact as u8 as f64),
        (
            "CORRECTED",
            (model.correction == Correction::Gradient) as u8 as f64,
        ),
        ("PLASTIC", model.plastic as u8 as f64),
        ("ART_STRESS", model.artificial_stress.is_some() as u8 as f64),
        (
            "ART_CLOSE",
            model
                .artificial_stress
                .is_some_and(|a| a.pairs == ArtPairs::Close) as u8 as f64,
        ),
        ("ART_KAPPA", !model.close_scale.is_empty() as u8 as f64),
        (
            "ART_HEAT",
            model
                .artificial_stress
                .is_some_and(|a| a.work == ArtWork::Heat) as u8 as f64,
        ),
        ("HEAT_SPEED", crate::physics::tension::HEAT_SPEED),
        ("ART_FLOW", model.art_keyed_on_flow() as u8 as f64),
        (
            "ART_BY_BODY",
            model
                .artificial_stress
                .is_some_and(|a| a.work == ArtWork::Yielding) as u8 as f64,
        ),
        ("YIELD_TOL", crate::model::YIELD_TOL),
        ("RECON", model.av_reconstruct as u8 as f64),
        ("RECON_SURF", model.av_recon_surface as u8 as f64),
        ("RELEASE", model.av_release as u8 as f64),
        ("GRAVITY", model.gravity.is_some() as u8 as f64),
        ("GX", model.gravity.map_or(0.0, |g| g.x)),
        ("GY", model.gravity.map_or(0.0, |g| g.y)),
        ("HELD", !model.held.is_empty() as u8 as f64),
        ("NHELD", model.held.len() as f64),
        ("RUB", model.rubs as u8 as f64),
        ("VARIATIONAL", model.variational as u8 as f64),
        ("HG", model.hourglass),
        ("DISP", model.dispersion),
        ("HISTORY", model.history as u8 as f64),
        ("FAILURE", model.can_fail() as u8 as f64),
        ("CAVITATION", model.cavitates() as u8 as f64),
        ("STRENGTH_LAWS", model.strength_laws() as f64),
        ("EOS_LAWS", model.eos_laws() as f64),
        ("FAILURE_LAWS", model.failure_laws() as f64),
        ("STRAIN_RATE", model.strain_rate as u8 as f64),
        ("AXI", model.axisymmetric as u8 as f64),
        (
            "PLANE",
            model
                .planes
                .iter()
                .map(|m| if m.flip[0] { 1.0 } else { 2.0 })
                .sum(),
        ),
        ("ONPLANE", !model.share.is_empty() as u8 as f64),
        ("ADAPT", model.adaptive as u8 as f64),
        ("LGRAD", (support_gradient == Buf::Lgrad) as u8 as f64),
        ("ADAPT_ROWS", adaptive_rows() as f64),
        ("BAND", model.band.drawn),
        ("BAND_SQ", model.band.squeezed),
        ("WG", WG as f64),
        ("DISS", model.dissipates() as u8 as f64),
        ("GUARD", plan.energy.is_some() as u8 as f64),
        ("RIGID", model.any_rigid as u8 as f64),
        // The leapfrog's kernels outside its step: its first
        // evaluation and the reductions (common.wgsl, LEAP).
        (
            "LEAP",
            (model.integrator == Integrator::Leapfrog) as u8 as f64,
        ),
    ]
}

/// Compiles and binds a scene's kernels.
struct Binder<'a> {
    ctx: &'a GpuContext,
    buffers: &'a DeviceBuffers,
    sizes: Sizes,
    plan: &'a ProbePlan,
    /// The reductions' observation slots, compiled into `reduce`.
    slot_wgsl: String,
}

impl Binder<'_> {
    /// The workgroups of a dispatch over `size`, split over two
    /// dimensions past the adapter's largest along one.
    fn groups(&self, size: Size) -> (u32, u32) {
        let g = match size {
            Size::Particles => (self.sizes.n as u32).div_ceil(WG),
            Size::Buckets => self.sizes.buckets.div_ceil(WG),
            Size::ScanBlocks => self.sizes.buckets.div_ceil(SCAN_BLOCK),
            Size::RedGroups => self.sizes.red_groups,
            Size::FinalGroups => 1 + self.plan.slots.len() as u32,
            Size::One => 1,
        }
        .max(1);
        if g <= self.sizes.maxd {
            (g, 1)
        } else {
            (self.sizes.maxd, g.div_ceil(self.sizes.maxd))
        }
    }

    /// The kernel `stage::entry` compiled with `consts`, its buffers bound
    /// by name through `table`'s aliases, its workgroups for `size`.
    fn kernel(
        &self,
        consts: &[(&str, f64)],
        stage: &str,
        entry: &str,
        size: Size,
        table: &[(&str, Buf)],
    ) -> Result<Kernel, String> {
        let prelude = if stage == "reduce" {
            self.slot_wgsl.as_str()
        } else {
            ""
        };
        let pipeline = self.ctx.pipeline(stage, prelude, entry, consts);
        let storage_used = pipeline.bindings.iter().filter(|b| !b.uniform).count() as u32;
        if storage_used > self.ctx.limits.max_storage_buffers_per_shader_stage {
            return Err(format!(
                "{stage}::{entry} binds {storage_used} storage buffers; this adapter allows {}",
                self.ctx.limits.max_storage_buffers_per_shader_stage
            ));
        }
        // Buffers a scene does not need (artificial stress, contact)
        // are bound to small placeholders the compiled-out code never
        // reads (the bind group keeps them alive); each holds at least
        // one element of the largest struct a kernel binds an array of
        // (a binding's minimum size). A binding that names no buffer is
        // an error, never a placeholder.
        const PLACEHOLDER_BYTES: u64 = 256;
        let mut bound: Vec<(u32, wgpu::Buffer)> = Vec::new();
        for bu in &pipeline.bindings {
            let b = aliases::resolve(table, &bu.name).ok_or_else(|| {
                format!(
                    "{stage}::{entry} binds '{}', which is no device buffer's name and which \
                 its kernel's aliases do not name",
                    bu.name
                )
            })?;
            let buf = self.buffers.get(b).cloned().unwrap_or_else(|| {
                self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&bu.name),
                    size: PLACEHOLDER_BYTES,
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                })
            });
            bound.push((bu.binding, buf));
        }
        let entries: Vec<wgpu::BindGroupEntry> = bound
            .iter()
            .map(|(binding, buf)| wgpu::BindGroupEntry {
                binding: *binding,
                resource: buf.as_entire_binding(),
            })
            .collect();
        let bind = self
            .ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(entry),
                layout: &pipeline.layout,
                entries: &entries,
            });
        Ok(Kernel {
            name: entry.to_string(),
            stage: stage.to_string(),
            role: None,
            pipeline,
            bind,
            groups: self.groups(size),
            walk: Walk::None,
            indirect: None,
        })
    }
}
