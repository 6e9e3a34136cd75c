//! The device's kernels for a scene: each entry point compiled with the
//! scene's override constants, its buffers bound by name (aliases where
//! an evaluation reads or writes other buffers than its names say), its
//! workgroups sized.

use std::collections::HashMap;

use super::*;

/// How many particles, cell-list buckets and reduction groups a scene has,
/// and the adapter's largest dispatch along one dimension.
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
    buffers: &HashMap<&'static str, wgpu::Buffer>,
    sizes: Sizes,
) -> Result<Kernels, String> {
    let Sizes {
        n,
        buckets,
        red_groups,
        maxd,
    } = sizes;
    let dev = &ctx.device;
    let limits = &ctx.limits;
    let contact = model.contact;
    let leapfrog = model.integrator == Integrator::Leapfrog;
    let surf_args = buffers.get("surf_args").cloned();
    // The velocity gradient adaptive supports are carried with at a
    // step's end (`supports_carried_by_gradv`).
    let support_gradient = if supports_carried_by_gradv(model) {
        "gradv"
    } else {
        "lgrad"
    };
    let constants: Vec<(&str, f64)> = vec![
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
        ("VARIATIONAL", model.variational as u8 as f64),
        ("HG", model.hourglass),
        ("HISTORY", model.history as u8 as f64),
        ("FAILURE", model.can_fail() as u8 as f64),
        ("CAVITATION", model.cavitates() as u8 as f64),
        ("STRAIN_RATE", model.strain_rate as u8 as f64),
        ("AXI", model.axisymmetric as u8 as f64),
        ("ADAPT", model.adaptive as u8 as f64),
        ("LGRAD", (support_gradient == "lgrad") as u8 as f64),
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
    ];
    let groups_of = |size: Size| -> (u32, u32) {
        let g = match size {
            Size::Particles => (n as u32).div_ceil(WG),
            Size::Buckets => buckets.div_ceil(WG),
            Size::ScanBlocks => buckets.div_ceil(SCAN_BLOCK),
            Size::RedGroups => red_groups,
            Size::FinalGroups => 1 + plan.slots.len() as u32,
            Size::One => 1,
        }
        .max(1);
        if g <= maxd {
            (g, 1)
        } else {
            (maxd, g.div_ceil(maxd))
        }
    };
    // Where an evaluation's rates go (common.wgsl, MID): at the base
    // state into the midpoint buffers; at the midpoint, which the
    // evaluation reads instead of the base state, into the base state.
    let base_aliases: &[(&str, &str)] = &[("dv", "vm"), ("dr", "rm"), ("ds", "sm")];
    let mid_aliases: &[(&str, &str)] = &[
        ("hist", "histm"),
        ("hist_w", "histm"),
        ("u", "um"),
        ("v", "vm"),
        ("r", "rm"),
        ("s", "sm"),
        ("dv", "v"),
        ("dr", "r"),
        ("ds", "s"),
        ("qheat_w", "qheat"),
    ];
    // The reductions are compiled for this scene's observation slots.
    let slot_wgsl = plan.wgsl();
    let mut mid_constants = constants.clone();
    mid_constants.push(("MID", 1.0));
    let kernel_in = |consts: &[(&str, f64)],
                     stage: &str,
                     entry: &str,
                     size: Size,
                     aliases: &[(&str, &str)]|
     -> Result<Kernel, String> {
        let prelude = if stage == "reduce" {
            slot_wgsl.as_str()
        } else {
            ""
        };
        let pipeline = ctx.pipeline(stage, prelude, entry, consts);
        let storage_used = pipeline.bindings.iter().filter(|b| !b.uniform).count() as u32;
        if storage_used > limits.max_storage_buffers_per_shader_stage {
            return Err(format!(
                "{stage}::{entry} binds {storage_used} storage buffers; this adapter allows {}",
                limits.max_storage_buffers_per_shader_stage
            ));
        }
        // Buffers a scene does not need (artificial stress, contact)
        // are bound to small placeholders the compiled-out code never
        // reads (the bind group keeps them alive); each holds at least
        // one element of the largest struct a kernel binds an array of
        // (a binding's minimum size).
        let key_of = |name: &str| -> String {
            aliases
                .iter()
                .chain(WRITER_ALIASES)
                .find(|a| a.0 == name)
                .map_or(name, |a| a.1)
                .to_string()
        };
        const PLACEHOLDER_BYTES: u64 = 256;
        let placeholders: Vec<(u32, wgpu::Buffer)> = pipeline
            .bindings
            .iter()
            .filter(|bu| !buffers.contains_key(key_of(&bu.name).as_str()))
            .map(|bu| {
                let buf = dev.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&bu.name),
                    size: PLACEHOLDER_BYTES,
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                });
                (bu.binding, buf)
            })
            .collect();
        let mut entries: Vec<wgpu::BindGroupEntry> = pipeline
            .bindings
            .iter()
            .filter_map(|bu| {
                buffers
                    .get(key_of(&bu.name).as_str())
                    .map(|buf| wgpu::BindGroupEntry {
                        binding: bu.binding,
                        resource: buf.as_entire_binding(),
                    })
            })
            .collect();
        entries.extend(placeholders.iter().map(|(b, buf)| wgpu::BindGroupEntry {
            binding: *b,
            resource: buf.as_entire_binding(),
        }));
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
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
            groups: groups_of(size),
            walk: Walk::None,
            indirect: None,
        })
    };
    let kernel = |stage: &str, entry: &str, size: Size, aliases: &[(&str, &str)]| {
        kernel_in(&constants, stage, entry, size, aliases)
    };

    // The leapfrog's first evaluation leaves a_0 and de_0 in the carried
    // rates and makes no density or stress rates.
    let first_aliases: &[(&str, &str)] = &[("dv", "acc"), ("dr", "rdt"), ("ds", UNUSED)];
    let variants: &[Var] = if leapfrog {
        &[Var::Base]
    } else {
        &[Var::Base, Var::Mid]
    };
    let mut evals = Vec::new();
    for &var in variants {
        let (consts, al) = match (var, leapfrog) {
            (Var::Base, false) => (constants.as_slice(), base_aliases),
            (Var::Base, true) => (constants.as_slice(), first_aliases),
            (Var::Mid, _) => (mid_constants.as_slice(), mid_aliases),
        };
        let eval_kernel = |stage, entry| kernel_in(consts, stage, entry, Size::Particles, al);
        // The second evaluation's contact entries go on the list where its
        // pass scratch carries the supports' gradient (contact.wgsl, on_list).
        let listed: Vec<(&str, &str)> = al
            .iter()
            .copied()
            .chain([("cown", "cown_e"), ("cshare", "cshare_e")])
            .collect();
        let contact_al = if var == Var::Mid && support_gradient == "gradv" {
            listed.as_slice()
        } else {
            al
        };
        let contact_kernel =
            |entry| kernel_in(consts, "contact", entry, Size::Particles, contact_al);
        evals.push(Eval {
            cells: eval_kernel("neighbours", "grid_cells")?,
            scatter: eval_kernel("neighbours", "grid_scatter")?,
            kinematics: eval_kernel("kinematics", "kinematics")?.walking(Walk::All),
            forces: eval_kernel("forces", "forces")?.walking(Walk::All),
            contact: if contact {
                Some(ContactKernels {
                    pass1: contact_kernel("contact_pass1")?.walking(Walk::Boundary),
                    pass2: contact_kernel("contact_pass2")?.walking(Walk::Boundary),
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
    let leap = if leapfrog {
        let mut step_constants = constants.clone();
        step_constants.retain(|c| c.0 != "LEAP");
        let mut book_constants = step_constants.clone();
        step_constants.push(("LEAP", 2.0));
        book_constants.push(("LEAP", 3.0));
        let state_w: &[(&str, &str)] = &[
            ("u_w", "u"),
            ("v_w", "v"),
            ("r_w", "r"),
            ("qheat_w", "qheat"),
        ];
        let at_n1: &[(&str, &str)] =
            &[("v", "vstar"), ("dv", "acc"), ("dr", "rdt"), ("vkick", "v")];
        let listed_at_n1: Vec<(&str, &str)> = at_n1
            .iter()
            .copied()
            .chain([("cown", "cown_e"), ("cshare", "cshare_e")])
            .collect();
        let booking: &[(&str, &str)] = &[
            ("v", "vstar"),
            ("vbook", "v"),
            ("dr", "rdt"),
            ("dv", UNUSED),
            ("qheat_w", "qheat"),
        ];
        let energy: &[(&str, &str)] = &[("dr", "rdt"), ("dv", UNUSED)];
        let step = |stage, entry, al| kernel_in(&step_constants, stage, entry, Size::Particles, al);
        let book =
            |stage, entry| kernel_in(&book_constants, stage, entry, Size::Particles, booking);
        Some(LeapKernels {
            kick_drift: kernel("advance", "kick_drift_cells", Size::Particles, state_w)?,
            kinematics: step("kinematics", "kinematics_leap", &[("ds", "s")])?.walking(Walk::All),
            forces: step("forces", "forces", at_n1)?.walking(Walk::Masked),
            contact: match &surf_args {
                Some(a) => Some(ContactKernels {
                    pass1: step("contact", "contact_pass1", &listed_at_n1)?.listed(a),
                    pass2: step("contact", "contact_pass2", &listed_at_n1)?.listed(a),
                    spread: Some(step("contact", "contact_spread", at_n1)?),
                }),
                None => None,
            },
            book: match &surf_args {
                Some(a) => {
                    let passes: &[(&str, &'static str)] = if model.any_rigid {
                        &[
                            ("contact_pass1", "book_pass1"),
                            ("contact_pass2", "book_pass2"),
                        ]
                    } else {
                        &[("contact_pass1", "book_pass1")]
                    };
                    passes
                        .iter()
                        .map(|&(entry, role)| Ok(book("contact", entry)?.listed(a).labelled(role)))
                        .collect::<Result<_, String>>()?
                }
                None => Vec::new(),
            },
            energy: kernel_in(&book_constants, "forces", "forces", Size::Particles, energy)?
                .walking(Walk::Masked)
                .labelled("energy"),
            finish: kernel("advance", "finish", Size::Particles, state_w)?,
        })
    } else {
        None
    };
    Ok(Kernels {
        clear: kernel("neighbours", "grid_clear", Size::Buckets, &[])?,
        scan_local: kernel("neighbours", "scan_local", Size::ScanBlocks, &[])?,
        scan_add: kernel("neighbours", "scan_add", Size::ScanBlocks, &[])?,
        sort: kernel("neighbours", "grid_sort", Size::Buckets, &[])?,
        eval: evals,
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
                &[
                    ("u_w", "um"),
                    ("v_w", "vm"),
                    ("r_w", "rm"),
                    ("s_w", "sm"),
                    ("hist_w", "histm"),
                ],
            )?)
        },
        advance_full: if leapfrog {
            None
        } else {
            Some(kernel(
                "advance",
                "advance_full",
                Size::Particles,
                // The spread reads the midpoint's positions, which
                // its cell list was made at.
                &[
                    ("u_w", "u"),
                    ("v_w", "v"),
                    ("r_w", "r"),
                    ("s_w", "s"),
                    ("u", "um"),
                    ("lgrad", support_gradient),
                ],
            )?)
        },
        end_step: kernel("reduce", "end_step", Size::One, &[])?,
        permute_each: {
            let arrays = if leapfrog {
                leap_arrays(model)
            } else {
                // The midpoint rule's `permute` has no room for these.
                let mut a = Vec::new();
                if model.history {
                    a.push(("hist", 16));
                }
                if model.adaptive {
                    a.push(("metric", 16));
                }
                a
            };
            arrays
                .into_iter()
                .map(|(name, bytes)| {
                    let (entry, src, dst) = match bytes {
                        16 => ("permute4", "p_src4", "p_dst4"),
                        8 => ("permute2", "p_src2", "p_dst2"),
                        _ => ("permute1", "p_src1", "p_dst1"),
                    };
                    let al = [(src, name), (dst, "lmat")];
                    Ok((kernel("reorder", entry, Size::Particles, &al)?, name, bytes))
                })
                .collect::<Result<_, String>>()?
        },
        permute: if leapfrog {
            None
        } else {
            Some(kernel(
                "reorder",
                "permute",
                Size::Particles,
                &[
                    ("t_x0", "lmat"),
                    ("t_u", "um"),
                    ("t_v", "vm"),
                    ("t_r", "rm"),
                    ("t_s", "sm"),
                    ("t_pinfo", "sr2c"),
                    ("t_qheat", "cown"),
                    ("t_centry", "nbo"),
                ],
            )?)
        },
        map_slots: if plan.particles.is_empty() {
            None
        } else {
            Some(kernel("reorder", "map_slots", Size::Particles, &[])?)
        },
    })
}
