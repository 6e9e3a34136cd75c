//! Which buffer a kernel binds where a shader's binding name is not the
//! buffer's ([`super::buffers::Buf`]): one table a kernel variant, each
//! `(binding name, buffer)`. A kernel looks its bindings up in its own
//! table, then [`WRITERS`], then [`STEP_ONLY`], then by the buffer's name;
//! a binding found nowhere is an error (`kernels::make_kernels`). The
//! tests hold every binding name of every shader to a buffer or a table,
//! and every table's names to the shaders.

use super::buffers::Buf;

/// The buffer a kernel with alias table `table` binds under `name`.
pub(super) fn resolve(table: &[(&str, Buf)], name: &str) -> Option<Buf> {
    table
        .iter()
        .chain(WRITERS)
        .chain(STEP_ONLY)
        .find(|a| a.0 == name)
        .map(|a| a.1)
        .or_else(|| Buf::from_name(name))
}

/// An alias table.
pub(super) type Aliases = &'static [(&'static str, Buf)];

/// The cell list's build writes, under these names, the buffers every other
/// stage reads under the second names.
pub(super) const WRITERS: Aliases = &[
    ("bstart_w", Buf::Bstart),
    ("blist_w", Buf::Blist),
    ("hist_w", Buf::Hist),
    ("metric_w", Buf::Metric),
];

/// Bindings only the leapfrog's step (`vkick`, LEAP 2) and booking
/// (`vbook`, LEAP 3) variants touch: every other variant binds a
/// placeholder unless its own table says otherwise.
pub(super) const STEP_ONLY: Aliases = &[("vkick", Buf::Unused), ("vbook", Buf::Unused)];

/// The midpoint rule's evaluation at the base state (common.wgsl, MID):
/// its rates go into the midpoint buffers; the contact books no heat
/// there.
pub(super) const BASE: Aliases = &[
    ("dv", Buf::Vm),
    ("dr", Buf::Rm),
    ("ds", Buf::Sm),
    ("qheat_w", Buf::Unused),
];

/// The evaluation at the midpoint, which it reads instead of the base
/// state: its rates go into the base state.
pub(super) const MID: Aliases = &[
    ("hist", Buf::Histm),
    ("hist_w", Buf::Histm),
    ("u", Buf::Um),
    ("v", Buf::Vm),
    ("r", Buf::Rm),
    ("s", Buf::Sm),
    ("dv", Buf::V),
    ("dr", Buf::R),
    ("ds", Buf::S),
    ("qheat_w", Buf::Qheat),
];

/// The leapfrog's first evaluation: a_0 and de_0 into the carried rates,
/// no density or stress rates, no heat.
pub(super) const FIRST: Aliases = &[
    ("dv", Buf::Acc),
    ("dr", Buf::Rdt),
    ("ds", Buf::Unused),
    ("qheat_w", Buf::Unused),
];

/// The contact's entries kept on the list of boundary particles, where
/// the pass scratch they live in is taken (contact.wgsl, on_list).
pub(super) const ON_LIST: Aliases = &[("cown", Buf::CownE), ("cshare", Buf::CshareE)];

/// The leapfrog's kick-drift and finish: the state written in place.
pub(super) const STATE_W: Aliases = &[
    ("u_w", Buf::U),
    ("v_w", Buf::V),
    ("r_w", Buf::R),
    ("qheat_w", Buf::Qheat),
];

/// The leapfrog step's kinematics pass: the stress in place.
pub(super) const LEAP_KINEMATICS: Aliases = &[("ds", Buf::S)];

/// The leapfrog step's force passes at t_{n+1}: they read the predicted
/// velocity, write the carried rates and kick the velocity; the booking
/// after the energy walk books the heat.
pub(super) const AT_N1: Aliases = &[
    ("v", Buf::Vstar),
    ("dv", Buf::Acc),
    ("dr", Buf::Rdt),
    ("vkick", Buf::V),
    ("qheat_w", Buf::Unused),
];

/// The leapfrog's contact booking at v_{n+1}.
pub(super) const BOOKING: Aliases = &[
    ("v", Buf::Vstar),
    ("vbook", Buf::V),
    ("dr", Buf::Rdt),
    ("dv", Buf::Unused),
    ("qheat_w", Buf::Qheat),
];

/// The leapfrog's energy walk.
pub(super) const ENERGY: Aliases = &[("dr", Buf::Rdt), ("dv", Buf::Unused)];

/// The midpoint rule's half step: the midpoint state written.
pub(super) const ADVANCE_HALF: Aliases = &[
    ("u_w", Buf::Um),
    ("v_w", Buf::Vm),
    ("r_w", Buf::Rm),
    ("s_w", Buf::Sm),
    ("hist_w", Buf::Histm),
];

/// The midpoint rule's full step: the base state written; the spread reads
/// the midpoint's positions, which its cell list was made at. (The
/// supports' gradient, `lgrad`, is the scene's: `kernels::make_kernels`.)
pub(super) const ADVANCE_FULL: Aliases = &[
    ("u_w", Buf::U),
    ("v_w", Buf::V),
    ("r_w", Buf::R),
    ("s_w", Buf::S),
    ("u", Buf::Um),
    ("qheat_w", Buf::Qheat),
];

/// The midpoint rule's reorder: the state gathered into scratch that is
/// dead at a step's start (copied back by `encode_reorder`).
pub(super) const PERMUTE: Aliases = &[
    ("t_x0", Buf::Lmat),
    ("t_u", Buf::Um),
    ("t_v", Buf::Vm),
    ("t_r", Buf::Rm),
    ("t_s", Buf::Sm),
    ("t_pinfo", Buf::Sr2c),
    ("t_qheat", Buf::Cown),
    ("t_centry", Buf::Nbo),
];

/// The one-array permutes' bindings (source, destination) by bytes an
/// element: the destination is always `lmat`, the source the array.
pub(super) const PERMUTE_EACH: &[(u64, &str, &str, &str)] = &[
    (16, "permute4", "p_src4", "p_dst4"),
    (8, "permute2", "p_src2", "p_dst2"),
    (4, "permute1", "p_src1", "p_dst1"),
];

/// The test kernels' own buffers (debug.wgsl), made where they run
/// (`GpuSolver::stage_outputs`, `GpuSolver::equation_of_state`,
/// `GpuSolver::strength_law`).
#[cfg(test)]
pub(super) const TEST_ONLY: &[&str] = &["dump", "eos_in", "eos_out", "law_in", "law_out"];

/// Every fixed table, for the tests.
#[cfg(test)]
pub(super) const ALL: &[Aliases] = &[
    WRITERS,
    STEP_ONLY,
    BASE,
    MID,
    FIRST,
    ON_LIST,
    STATE_W,
    LEAP_KINEMATICS,
    AT_N1,
    BOOKING,
    ENERGY,
    ADVANCE_HALF,
    ADVANCE_FULL,
    PERMUTE,
];

#[cfg(test)]
mod tests {
    use super::super::buffers::Buf;
    use super::super::shaders;
    use super::*;
    use std::collections::BTreeSet;

    /// Every binding name of every entry point of every stage.
    fn binding_names() -> BTreeSet<String> {
        let mut names = BTreeSet::new();
        for stage in shaders::modules() {
            let r = shaders::reflect(stage, &shaders::sample_prelude(stage)).unwrap();
            for e in r.entry_points() {
                names.extend(r.bindings(&e).into_iter().map(|b| b.name));
            }
        }
        names
    }

    #[test]
    fn a_kernels_table_comes_first() {
        assert_eq!(resolve(MID, "hist_w"), Some(Buf::Histm));
        assert_eq!(resolve(BASE, "hist_w"), Some(Buf::Hist));
        assert_eq!(resolve(AT_N1, "vkick"), Some(Buf::V));
        assert_eq!(resolve(BASE, "vkick"), Some(Buf::Unused));
        assert_eq!(resolve(BASE, "x0"), Some(Buf::X0));
        assert_eq!(resolve(BASE, "u_w"), None);
    }

    /// A binding that is no buffer's name is aliased by some table (the
    /// build then names any kernel whose table misses it), and every
    /// table names bindings the shaders have and never the buffer of the
    /// same name (a no-op alias hides a misspelling).
    #[test]
    fn every_binding_resolves_and_every_alias_binds() {
        let names = binding_names();
        let aliased: BTreeSet<&str> = ALL
            .iter()
            .flat_map(|t| t.iter().map(|a| a.0))
            .chain(PERMUTE_EACH.iter().flat_map(|p| [p.2, p.3]))
            .chain(TEST_ONLY.iter().copied())
            .chain(["lgrad"])
            .collect();
        for n in &names {
            assert!(
                Buf::from_name(n).is_some() || aliased.contains(n.as_str()),
                "the shaders bind '{n}', which is no buffer and no alias"
            );
        }
        for a in &aliased {
            assert!(
                names.contains(*a),
                "an alias names '{a}', which no shader binds"
            );
        }
        for t in ALL {
            for (from, to) in t.iter() {
                assert_ne!(
                    Buf::from_name(from),
                    Some(*to),
                    "'{from}' aliased to itself"
                );
            }
        }
    }
}
