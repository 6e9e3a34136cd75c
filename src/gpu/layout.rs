//! Host mirrors of the WGSL structs, byte for byte (checked against naga's
//! layouter by [`check_layouts`]).

use bytemuck::{Pod, Zeroable};

/// `Params` in common.wgsl: run-wide constants.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Params {
    pub n: u32,
    pub nbodies: u32,
    pub buckets: u32,
    pub row_stride: u32,
    /// The energy guard's growth factor ([`crate::model::ENERGY_GROWTH`])
    /// and the model's energy floor ([`crate::model::Model::guards_energy`]).
    pub energy_growth: f32,
    pub energy_floor: f32,
    pub inv_cell: f32,
    pub alpha: f32,
    pub beta: f32,
    pub cfl: f32,
    pub fixed_dt: f32,
    pub boundary_threshold: f32,
    pub as_eps: f32,
    pub as_n: f32,
    pub end_hi: f32,
    pub end_lo: f32,
    pub ring_len: u32,
    pub ring_width: u32,
    /// Entries of the leapfrog contact's list of boundary particles
    /// (contact.wgsl; 0 without one).
    pub surf_cap: u32,
    pub nprobes: u32,
    pub cell: f32,
    pub red_groups: u32,
    pub min_sv2: f32,
    /// A particle's support radius in cells, with a margin for f32
    /// rounding (`row_span` in common.wgsl).
    pub reach: f32,
    /// The domain ([`crate::model::Model::domain_of`]) relative to the grid
    /// origin: lower x, lower y, upper x, upper y.
    pub domain: [f32; 4],
    /// The energy guard ([`crate::model::Model::guards_energy`]): the
    /// ring-row slots of the kinetic, internal and stored penalty energy
    /// (stored: `u32::MAX` without contact; the guard kernel runs only
    /// when the run is guarded).
    pub energy_kin: u32,
    pub energy_int: u32,
    pub energy_stored: u32,
    /// The most workgroups of a dispatch along x (the contact's indirect
    /// dispatch is sized to at most this many).
    pub surf_groups: u32,
    /// Bodies of revolution: the axis `r = 0` in cells from the grid
    /// origin, a whole number (0 in plane strain).
    pub axis_cell: f32,
    /// The margin, in cells, of a walk's reach where supports adapt
    /// (walk.wgsl, `walker`): the f32 rounding of a particle's place.
    pub reach_margin: f32,
    /// The ring-row slot of the internal energy held below zero, which
    /// the energy guard reads too ([`crate::model::Model::energy_owed_bound`]).
    pub energy_owed: u32,
    /// The longest step the penalty spring allows
    /// ([`crate::model::Model::contact_dt`]; `f32::MAX` without contact).
    pub contact_dt: f32,
    /// The symmetry plane reversing x in cells from the grid origin, a
    /// whole number (0 without one).
    pub plane_x: f32,
    /// The one reversing y, likewise.
    pub plane_y: f32,
    pub pad1: u32,
    pub pad2: u32,
}

/// `Body` in common.wgsl: per-body constants.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct BodyGpu {
    pub rho0: f32,
    pub k: f32,
    /// The equation of state's constants ([`crate::physics::eos::PressureLaw::device`]).
    pub eos0: f32,
    pub eos1: f32,
    pub g: f32,
    pub y0: f32,
    pub z: f32,
    pub modulus: f32,
    pub spacing: f32,
    pub h: f32,
    pub rigid: u32,
    /// The equation of state's number ([`crate::physics::eos::Eos::device_id`]).
    pub eos: u32,
    pub elastic: u32,
    /// The fewest same-body neighbours a particle keeps its correction
    /// with ([`crate::model::BodyInfo::debris_neighbours`]).
    pub debris_n: u32,
    /// The hourglass control's coefficient on the body's families
    /// ([`crate::model::BodyInfo::hourglass`]).
    pub hg: f32,
    /// 1 where the body's particles carry the artificial stress
    /// ([`crate::model::BodyInfo::art`]).
    pub art: u32,
}

/// `Plastic` in strength.wgsl: per-body constants of the strength and
/// failure laws (only with a plastic history).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct PlasticGpu {
    /// The strength law's constants ([`crate::physics::laws::Law::device`]).
    pub k: [f32; crate::physics::laws::DEVICE_CONSTANTS],
    /// The strength law's number (0: none).
    pub law: u32,
    /// Room temperature, K.
    pub room: f32,
    /// The damage law's reference strain rate, 1/s.
    pub rate0: f32,
    /// Melt temperature less room temperature, K (`f32::MAX`: no melt).
    pub melt_rise: f32,
    /// Taylor–Quinney fraction over the specific heat.
    pub heat: f32,
    pub d1: f32,
    pub d2: f32,
    pub d3: f32,
    pub d4: f32,
    pub d5: f32,
    /// Spall pressure, Pa (`f32::MAX`: none).
    pub spall: f32,
    /// Cavitation pressure, Pa (`f32::MAX`: none).
    pub cavitation: f32,
    /// 1: Johnson–Cook damage.
    pub damage: u32,
}

/// `Control` in common.wgsl: time, step and run status on the device.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub struct Control {
    pub t_hi: f32,
    pub t_lo: f32,
    pub dt: f32,
    pub dt0: f32,
    pub step: u32,
    pub zero_steps: u32,
    pub fail_step: u32,
    pub fail_code: u32,
    pub fallback_now: u32,
    pub fallback_max: u32,
    pub multi_partner: u32,
    /// The energy guard's limit ([`crate::model::Model::guards_energy`]):
    /// negative until the first state sets it.
    pub energy_limit: f32,
    /// The longest the contact's list of boundary particles has been since
    /// the host last looked, where more than three quarters full
    /// (kinematics.wgsl, list_surface).
    pub list_peak: u32,
    /// Supports that adapt: the bits of the largest major semi-axis of a
    /// step's supports, by the step's parity (common.wgsl).
    pub h_top: [u32; 2],
    /// Supports that adapt within a band: nonzero where one of a step's
    /// supports is not round, by the step's parity (common.wgsl,
    /// `adapting`).
    pub out_of_band: [u32; 2],
}

/// Shared structs declared outside common.wgsl, in the files of the stages
/// that use them.
const OWN_FILE: &[&str] = &["Plastic"];

/// Field offsets of a host struct, for the layout check.
macro_rules! offsets {
    ($t:ty, $($f:ident),*) => {
        vec![$((stringify!($f), std::mem::offset_of!($t, $f))),*]
    };
}

/// A host struct's WGSL name, size and `(field, offset)` list.
pub type HostLayout = (&'static str, usize, Vec<(&'static str, usize)>);

/// The layout of every shared struct.
pub fn host_layouts() -> Vec<HostLayout> {
    vec![
        (
            "Params",
            size_of::<Params>(),
            offsets!(
                Params,
                n,
                nbodies,
                buckets,
                row_stride,
                energy_growth,
                energy_floor,
                inv_cell,
                alpha,
                beta,
                cfl,
                fixed_dt,
                boundary_threshold,
                as_eps,
                as_n,
                end_hi,
                end_lo,
                ring_len,
                ring_width,
                surf_cap,
                nprobes,
                cell,
                red_groups,
                min_sv2,
                reach,
                domain,
                energy_kin,
                energy_int,
                energy_stored,
                surf_groups,
                axis_cell,
                reach_margin,
                energy_owed,
                contact_dt,
                plane_x,
                plane_y,
                pad1,
                pad2
            ),
        ),
        (
            "Body",
            size_of::<BodyGpu>(),
            offsets!(
                BodyGpu, rho0, k, eos0, eos1, g, y0, z, modulus, spacing, h, rigid, eos, elastic,
                debris_n, hg, art
            ),
        ),
        (
            "Plastic",
            size_of::<PlasticGpu>(),
            offsets!(
                PlasticGpu, k, law, room, rate0, melt_rise, heat, d1, d2, d3, d4, d5, spall,
                cavitation, damage
            ),
        ),
        (
            "Control",
            size_of::<Control>(),
            offsets!(
                Control,
                t_hi,
                t_lo,
                dt,
                dt0,
                step,
                zero_steps,
                fail_step,
                fail_code,
                fallback_now,
                fallback_max,
                multi_partner,
                energy_limit,
                list_peak,
                h_top,
                out_of_band
            ),
        ),
    ]
}

/// Compare every host struct with naga's layout of the WGSL struct of the
/// same name: size, and each member's name and offset, in order. The
/// structs of common.wgsl must be in every module; the others are checked
/// where a module has them. Returns the names checked.
pub fn check_layouts(module: &naga::Module) -> Result<Vec<&'static str>, String> {
    let mut checked = Vec::new();
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| format!("naga layouter: {e}"))?;
    for (name, size, fields) in host_layouts() {
        let found = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name));
        let Some((handle, ty)) = found else {
            if OWN_FILE.contains(&name) {
                continue;
            }
            return Err(format!("no WGSL struct {name}"));
        };
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            return Err(format!("{name} is not a struct"));
        };
        if *span as usize != size || layouter[handle].size as usize != size {
            return Err(format!("{name}: WGSL size {span}, host size {size}"));
        }
        if members.len() != fields.len() {
            return Err(format!(
                "{name}: WGSL has {} members, host {}",
                members.len(),
                fields.len()
            ));
        }
        for (m, (f, off)) in members.iter().zip(&fields) {
            let mname = m.name.as_deref().unwrap_or("");
            if mname != *f || m.offset as usize != *off {
                return Err(format!(
                    "{name}.{mname} at {} but host {f} at {off}",
                    m.offset
                ));
            }
        }
        checked.push(name);
    }
    Ok(checked)
}
