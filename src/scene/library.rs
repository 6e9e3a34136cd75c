//! The material library: named materials with published constants, usable
//! in a scene as `library = "name"` (the scene's own keys override the
//! entry's). The entries live in `library.toml` beside this file, each with
//! its sources.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use super::{Material, MaterialSpec};

/// The library's text, as shipped.
pub const TEXT: &str = include_str!("library.toml");

/// Every entry, parsed once.
pub fn entries() -> &'static BTreeMap<String, Material> {
    static LIB: OnceLock<BTreeMap<String, Material>> = OnceLock::new();
    LIB.get_or_init(|| {
        let specs: BTreeMap<String, MaterialSpec> =
            toml::from_str(TEXT).expect("the shipped library parses");
        specs
            .into_iter()
            .map(|(name, spec)| {
                assert!(spec.library.is_none(), "{name}: an entry names no other");
                let m = Material::try_from(spec).expect("the shipped library is complete");
                (name, m)
            })
            .collect()
    })
}

/// The entry called `name`, or a message listing the names there are.
pub fn entry(name: &str) -> Result<Material, String> {
    entries().get(name).cloned().ok_or_else(|| {
        let names: Vec<&str> = entries().keys().map(String::as_str).collect();
        format!(
            "unknown library material '{name}' (the library has: {})",
            names.join(", ")
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// Every entry is usable by name: a scene of one body of it passes
    /// validation, with a strength law, a specific heat and a source; a
    /// key beside `library` overrides the entry's.
    #[test]
    fn every_entry_is_usable_by_name() {
        assert!(entries().len() >= 4);
        for (name, m) in entries() {
            let text = format!(
                "[simulation]\ndimension = 1\nend_time = 1e-7\n[materials.m]\nlibrary = \"{name}\"\n\
                 [[bodies]]\nname = \"b\"\nmaterial = \"m\"\nspacing = 1e-4\n\
                 shape = {{ kind = \"segment\", from = 0.0, to = 0.001 }}\n"
            );
            let scene = Scene::from_toml_str(&text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
            let named = Material {
                library: Some(name.clone()),
                ..m.clone()
            };
            assert_eq!(scene.materials["m"], named);
            assert!(m.strength.is_some() && m.specific_heat.is_some(), "{name}");
            assert!(m.source.as_ref().is_some_and(|s| !s.is_empty()), "{name}");
            let over = text.replace(
                "library = \"steel_4340\"",
                "library = \"steel_4340\"\nspall_pressure = 3.0e9\ndensity = 7850.0",
            );
            if over != text {
                let s = Scene::from_toml_str(&over, name).unwrap();
                let o = &s.materials["m"];
                assert_eq!((o.density, o.spall_pressure), (7850.0, Some(3.0e9)));
                assert_eq!(o.strength, m.strength);
            }
        }
    }
}
