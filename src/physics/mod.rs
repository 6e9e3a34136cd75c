//! Plain functions of scalars and small tensors: the kernel, the material
//! model, the artificial viscosity and stress, the penalty law and the
//! strength and failure laws; they depend on [`crate::math`] alone. Used by the CPU path (and
//! mirrored by the shaders of the GPU path); the exact answers of the
//! validation cases are in [`crate::validation::exact`].

/// A law as the device knows it: its number (the body's or material's law
/// field on the device), its kind (the scene's `kind`, the WGSL file's
/// stem and its functions' prefix) and its WGSL.
pub struct DeviceLaw {
    pub id: u32,
    pub kind: &'static str,
    pub wgsl: &'static str,
}

/// A registry of laws of one family (strength, equation of state, damage):
/// one line per law, `id => Variant(module)`. It declares the modules and
/// writes the scene's enum (`kind = "<module>"`, the module's `$keys`
/// struct holding the keys), its `Deref` to the family's trait, the
/// device number of each law and `DEVICE`, every law's WGSL from
/// `shaders/<dir>/<module>.wgsl`.
macro_rules! law_registry {
    (
        $(#[$doc:meta])*
        enum $enum:ident: dyn $trait:ident, keys $keys:ident, shaders $dir:literal;
        $($id:literal => $variant:ident($module:ident)),* $(,)?
    ) => {
        $(pub mod $module;)*

        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(tag = "kind", rename_all = "snake_case")]
        pub enum $enum {
            $($variant($module::$keys)),*
        }

        /// The law's functions through the family's trait.
        impl std::ops::Deref for $enum {
            type Target = dyn $trait;

            fn deref(&self) -> &Self::Target {
                match self {
                    $(Self::$variant(l) => l),*
                }
            }
        }

        impl $enum {
            /// The law's number on the device.
            pub fn device_id(&self) -> u32 {
                match self {
                    $(Self::$variant(_) => $id),*
                }
            }
        }

        /// Every law's device side, in the registry's order.
        pub const DEVICE: &[$crate::physics::DeviceLaw] = &[$($crate::physics::DeviceLaw {
            id: $id,
            kind: stringify!($module),
            wgsl: include_str!(concat!(
                env!("CARGO_MANIFEST_DIR"), "/shaders/", $dir, "/", stringify!($module), ".wgsl"
            )),
        }),*];
    };
}

/// The test of a registry against its folder: every file in
/// `shaders/<dir>/` is a registered law's, each defines `fn <kind>_<f>`
/// for every `f` of `functions` (a signature's start), and the device numbers are distinct bits of
/// an override (below 32) and not `reserved`.
#[cfg(test)]
fn check_registry(dir: &str, device: &[DeviceLaw], functions: &[&str], reserved: Option<u32>) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("shaders")
        .join(dir);
    let mut on_disk: Vec<String> = std::fs::read_dir(path)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = device.iter().map(|l| format!("{}.wgsl", l.kind)).collect();
    listed.sort();
    assert_eq!(on_disk, listed);
    for l in device {
        for f in functions {
            let sig = format!("fn {}_{f}", l.kind);
            assert!(l.wgsl.contains(&sig), "{dir}/{}.wgsl: no `{sig}…`", l.kind);
        }
        assert!(l.id < 32, "{}: an id is a bit of the override", l.kind);
        assert!(Some(l.id) != reserved, "{}: {} means no law", l.kind, l.id);
    }
    let mut ids: Vec<u32> = device.iter().map(|l| l.id).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), device.len(), "{dir}: ids are distinct");
}

pub mod eos;
pub mod failure;
pub mod kernel;
pub mod laws;
pub mod material;
pub mod penalty;
pub mod strength;
pub mod support;
pub mod tension;
pub mod viscosity;
