//! The device's buffers by name: one field a buffer, and [`Buf`], the
//! names a kernel's bindings resolve to. A buffer the code names is a
//! `Buf` variant, so a misspelt one does not compile; a shader binding
//! that is neither a buffer's name nor aliased by its kernel's table is a
//! build error (`kernels::make_kernels`), never a silent placeholder.

/// Declares [`Buf`] and [`DeviceBuffers`] from one list, `Variant =>
/// field`: the field's name is the WGSL binding name the buffer is bound
/// under when no alias says otherwise, and the name checkpoints store it by.
macro_rules! device_buffers {
    ($($(#[$doc:meta])* $variant:ident => $field:ident,)*) => {
        /// A device buffer, by name.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub(crate) enum Buf {
            $($(#[$doc])* $variant,)*
        }

        impl Buf {
            /// Every buffer, in declaration order.
            #[cfg(test)]
            pub(crate) const ALL: &[Buf] = &[$(Buf::$variant),*];

            /// The WGSL binding name, and the name a checkpoint stores.
            pub(crate) fn name(self) -> &'static str {
                match self {
                    $(Buf::$variant => stringify!($field),)*
                }
            }

            /// The buffer a shader binding of this name binds when no
            /// alias says otherwise.
            pub(crate) fn from_name(name: &str) -> Option<Buf> {
                match name {
                    $(stringify!($field) => Some(Buf::$variant),)*
                    _ => None,
                }
            }
        }

        /// The buffers a solver made: `None` where its scene needs none
        /// (a kernel binds a placeholder there, which the scene's override
        /// constants compile out).
        #[derive(Default)]
        pub(crate) struct DeviceBuffers {
            $(pub(crate) $field: Option<wgpu::Buffer>,)*
        }

        impl DeviceBuffers {
            pub(crate) fn get(&self, b: Buf) -> Option<&wgpu::Buffer> {
                match b {
                    $(Buf::$variant => self.$field.as_ref(),)*
                }
            }

            pub(crate) fn set(&mut self, b: Buf, buf: wgpu::Buffer) {
                match b {
                    $(Buf::$variant => self.$field = Some(buf),)*
                }
            }
        }
    };
}

device_buffers! {
    /// Reference positions: the cell (x, y) and the offset within it.
    X0 => x0,
    /// Displacements from the reference positions.
    U => u,
    V => v,
    /// Density as μ = ρ/ρ0 − 1, and specific internal energy.
    R => r,
    /// Deviatoric stress.
    S => s,
    /// Per particle: mass and surface-layer offset (f32 bits), body and
    /// original index.
    Pinfo => pinfo,
    /// The plastic history (strength.wgsl's precision plan).
    Hist => hist,
    /// A body's strength and failure constants.
    Plastic => plastic,
    /// The midpoint rule's midpoint history.
    Histm => histm,
    /// The midpoint rule's equivalent strain rates.
    Srate => srate,
    /// The artificial stress's close-pair scale, by original index.
    Kappa => kappa,
    /// Each particle's area as placed (bodies of revolution).
    Area0 => area0,
    /// The clamped and driven regions: each one's (held components,
    /// velocity), then each particle's region by original index.
    Held => held,
    /// The impulse each held particle's region gave it so far, by
    /// original index (compensated: hi, lo).
    HeldW => held_w,
    /// The hoop stress's acceleration of an evaluation.
    Hoop => hoop,
    /// The base pass's debris, a bit a particle.
    DebrisBits => debris_bits,
    /// The leapfrog's carried acceleration.
    Acc => acc,
    /// The leapfrog's carried (_, de/dt).
    Rdt => rdt,
    /// The leapfrog's predicted velocity.
    Vstar => vstar,
    /// The leapfrog's neighbour masks (in `qrate` where there is contact).
    Nmask => nmask,
    /// The leapfrog's carried contact rates.
    Qrate => qrate,
    /// Contact entries kept on the list of boundary particles.
    CownE => cown_e,
    CshareE => cshare_e,
    /// The midpoint state.
    Um => um,
    Vm => vm,
    Rm => rm,
    Sm => sm,
    /// The correction matrices; the reorder's scratch.
    Lmat => lmat,
    /// Normals and boundary flags.
    Nbo => nbo,
    /// σ/ρ² and the sound speed.
    Sr2c => sr2c,
    /// Velocity gradients.
    Gradv => gradv,
    /// The dispersion correction's plain velocity gradient and extra
    /// stress (dispersion.wgsl).
    Gdisp => gdisp,
    Sdisp => sdisp,
    /// The hourglass control's half-step velocity and its gradient.
    Vhalf => vhalf,
    Gradh => gradh,
    /// Adaptive supports.
    Metric => metric,
    /// The supports' step gradient in f16 pairs.
    Lgrad => lgrad,
    /// The artificial dissipation booked, a workgroup.
    Dheat => dheat,
    /// Per particle: the dashpot heat and the spring's work.
    Qheat => qheat,
    /// The list of boundary particles and what each carries between the
    /// contact's passes.
    Surf => surf,
    Cn => cn,
    Cbar0 => cbar0,
    Cbar1 => cbar1,
    Ckeep => ckeep,
    Bt => bt,
    Area => area,
    /// The spread's claims, a bit a particle.
    Claim => claim,
    /// The contact's entry overlaps.
    Centry => centry,
    /// Coulomb friction: each particle's elastic slip by original index,
    /// its friction in an evaluation, what the rub pass reads and hands
    /// on the list, and the coefficients of each pair of bodies.
    Slip => slip,
    Frub => frub,
    Crub0 => crub0,
    Crub1 => crub1,
    Crubo => crubo,
    Coulomb => coulomb,
    /// The contact's gather buffers (in pass scratch where there is some,
    /// `make::contact_homes`).
    Cshare => cshare,
    Cown => cown,
    /// The cell list.
    Blist => blist,
    Bstart => bstart,
    Bsum => bsum,
    /// The reductions' partial sums.
    Red => red,
    /// The history rows of a batch.
    Ring => ring,
    /// The particle probes' tables.
    Probes => probes,
    ProbeIds => probe_ids,
    ProbeSlot => probe_slot,
    /// The bodies' constants.
    Bodies => bodies,
    /// The control block.
    Ctl => ctl,
    /// The contact list's count and indirect dispatch arguments.
    SurfArgs => surf_args,
    /// The run-wide constants (uniform).
    Params => params,
    /// Never made: a binding a kernel's variant never touches, bound to a
    /// placeholder.
    Unused => unused,
}

#[cfg(test)]
mod tests {
    use super::Buf;

    #[test]
    fn names_round_trip() {
        for &b in Buf::ALL {
            assert_eq!(Buf::from_name(b.name()), Some(b));
        }
        assert_eq!(Buf::from_name("u_w"), None);
    }
}
