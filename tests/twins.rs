//! Every CPU twin a shader names exists: each `CPU twin: path` (or
//! `twins:` with a list) in a comment of `shaders/*.wgsl`,
//! `shaders/laws/*.wgsl` and `shaders/eos/*.wgsl` resolves to a
//! module, type, function, constant or field of `src/` where the path
//! says, so that a twin which moves or is renamed fails here instead of
//! leaving the shader pointing at nothing.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, by its path relative to the crate root.
fn rust_files(dir: &Path, out: &mut BTreeMap<PathBuf, String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.insert(p.clone(), std::fs::read_to_string(&p).unwrap());
        }
    }
}

struct Source {
    root: PathBuf,
    files: BTreeMap<PathBuf, String>,
}

impl Source {
    fn load() -> Source {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = BTreeMap::new();
        rust_files(&root, &mut files);
        Source { root, files }
    }

    /// The files of module path `mods` (`src/a/b.rs` and everything under
    /// `src/a/b/`); a first segment that is no top-level module is looked
    /// for anywhere (`kernel` for `physics::kernel`).
    fn module(&self, mods: &[&str]) -> Vec<&PathBuf> {
        let base = mods.iter().fold(self.root.clone(), |p, m| p.join(m));
        let found: Vec<&PathBuf> = self
            .files
            .keys()
            .filter(|p| **p == base.with_extension("rs") || p.starts_with(&base))
            .collect();
        if !found.is_empty() || mods.is_empty() {
            return found;
        }
        // `kernel::fit_inverse`: the module by its own name, wherever it is.
        let first = mods[0];
        let homes: Vec<PathBuf> = self
            .files
            .keys()
            .filter_map(|p| {
                let rel = p.strip_prefix(&self.root).ok()?;
                let names: Vec<String> = rel
                    .with_extension("")
                    .iter()
                    .map(|c| c.to_string_lossy().into_owned())
                    .collect();
                let k = names.iter().position(|n| n == first)?;
                Some(names[..k].iter().fold(self.root.clone(), |q, n| q.join(n)))
            })
            .collect();
        homes
            .iter()
            .flat_map(|h| {
                let base = mods.iter().fold(h.clone(), |p, m| p.join(m));
                self.files
                    .keys()
                    .filter(move |p| **p == base.with_extension("rs") || p.starts_with(&base))
            })
            .collect()
    }

    /// Whether one of `files` defines `name`: an item or a field.
    fn defines(&self, files: &[&PathBuf], name: &str) -> bool {
        let items = [
            "fn", "struct", "enum", "const", "type", "mod", "trait", "static",
        ];
        files.iter().any(|f| {
            let text = &self.files[*f];
            text.lines().any(|l| {
                let l = l.trim_start();
                // `pub`, `pub(crate)`, `pub(in crate::cpu)` and the like.
                let l = match l.strip_prefix("pub") {
                    Some(r) if r.starts_with(' ') => &r[1..],
                    Some(r) if r.starts_with('(') => r.split_once(") ").map_or(l, |(_, rest)| rest),
                    _ => l,
                };
                items.iter().any(|k| {
                    l.strip_prefix(k)
                        .and_then(|r| r.strip_prefix(' '))
                        .and_then(|r| r.strip_prefix(name))
                        .is_some_and(|r| !r.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
                }) || l
                    .strip_prefix(name)
                    .is_some_and(|r| r.starts_with(':') && !r.starts_with("::"))
            })
        })
    }

    /// Whether `path` (`a::b::Type::item`, `a::b` a module) resolves.
    fn resolves(&self, path: &str) -> bool {
        let segs: Vec<&str> = path.split("::").collect();
        let (name, prefix) = segs.split_last().unwrap();
        if !self.module(&segs).is_empty() {
            return true;
        }
        let mods: Vec<&str> = prefix
            .iter()
            .copied()
            .filter(|s| s.starts_with(|c: char| c.is_lowercase()))
            .collect();
        let all: Vec<&PathBuf> = self.files.keys().collect();
        if let Some(ty) = prefix
            .iter()
            .rev()
            .find(|s| s.starts_with(char::is_uppercase))
        {
            let home = if mods.is_empty() {
                all.clone()
            } else {
                self.module(&mods)
            };
            if !self.defines(&home, ty) {
                return false;
            }
        }
        let files = if mods.is_empty() {
            all
        } else {
            self.module(&mods)
        };
        !files.is_empty() && self.defines(&files, name)
    }
}

/// A Rust path: identifiers joined by `::`.
fn is_path(t: &str) -> bool {
    !t.is_empty()
        && t.split("::").all(|s| {
            s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
                && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        })
}

/// `a::{x, y}` written out as `a::x, a::y`.
fn expand_braces(s: &str) -> String {
    let mut out = s.to_string();
    while let Some(open) = out.find("::{") {
        let Some(close) = out[open..].find('}').map(|k| open + k) else {
            break;
        };
        let head_start = out[..open]
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
            .map_or(0, |k| k + 1);
        let head = &out[head_start..open];
        let list: Vec<String> = out[open + 3..close]
            .split(',')
            .map(|n| format!("{head}::{}", n.trim()))
            .collect();
        out = format!(
            "{}{}{}",
            &out[..head_start],
            list.join(", "),
            &out[close + 1..]
        );
    }
    out
}

/// The twin pointers of one shader: (line, path), a bare name after a
/// path taken in that path's module (`cpu::contact::is_candidate,
/// surface_ramp`).
fn pointers(text: &str) -> Vec<(usize, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(c) = line.find("//") else { continue };
        let comment = &line[c + 2..];
        let Some(k) = comment.find("twin:").or(comment.find("twins:")) else {
            continue;
        };
        let mut rest = comment[k..].split_once(':').unwrap().1.trim().to_string();
        // The sentence may go on over the next comment lines.
        let mut j = i + 1;
        let ends = |s: &str| {
            let s = s.trim_end();
            s.ends_with('.') || s.contains(". ") || s.contains(')') || s.contains(';')
        };
        while !ends(&rest) && j < lines.len() {
            match lines[j].trim_start().strip_prefix("//") {
                Some(more) => rest = format!("{rest} {}", more.trim()),
                None => break,
            }
            j += 1;
        }
        let sentence = rest
            .split([')', ';'])
            .next()
            .unwrap()
            .split(". ")
            .next()
            .unwrap()
            .trim_end_matches('.');
        let sentence = expand_braces(sentence);
        let mut module: Option<String> = None;
        for item in sentence.split(',').flat_map(|s| s.split(" and ")) {
            let words: Vec<&str> = item
                .split_whitespace()
                .map(|w| w.trim_end_matches(['.', ':']))
                .collect();
            // A lone word, or the path among prose ("with physics::x for").
            let word = match words[..] {
                [w] => w,
                _ => match words.iter().find(|w| w.contains("::")) {
                    Some(w) => w,
                    None => continue,
                },
            };
            if !is_path(word) {
                continue;
            }
            if word.contains("::") {
                module = word.rsplit_once("::").map(|(m, _)| m.to_string());
                out.push((i + 1, word.to_string()));
            } else if let Some(m) = &module {
                out.push((i + 1, format!("{m}::{word}")));
            } else {
                out.push((i + 1, word.to_string()));
            }
        }
    }
    out
}

#[test]
fn every_cpu_twin_a_shader_names_exists() {
    let src = Source::load();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut found = 0;
    let mut missing = Vec::new();
    // The stages' files, the strength laws' (shaders/laws/) and the
    // equations of state's (shaders/eos/).
    let mut names: Vec<PathBuf> = [
        dir.clone(),
        dir.join("laws"),
        dir.join("eos"),
        dir.join("failure"),
    ]
    .iter()
    .flat_map(|d| std::fs::read_dir(d).unwrap())
    .map(|e| e.unwrap().path())
    .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
    .collect();
    names.sort();
    for path in names {
        let text = std::fs::read_to_string(&path).unwrap();
        for (line, twin) in pointers(&text) {
            found += 1;
            if !src.resolves(&twin) {
                let file = path.file_name().unwrap().to_string_lossy();
                missing.push(format!("{file}:{line}: {twin}"));
            }
        }
    }
    println!("{found} twin pointers");
    // The shaders name about fifty; far fewer means the reading broke.
    assert!(found >= 40, "only {found} twin pointers read");
    assert!(
        missing.is_empty(),
        "twins not found:\n{}",
        missing.join("\n")
    );
}

/// The resolver itself: what exists resolves, what does not fails.
#[test]
fn the_twin_resolver_tells_present_from_absent() {
    let src = Source::load();
    for present in [
        "cpu::advance",
        "cpu::CpuSolver::leapfrog",
        "physics::kernel::hessian",
        "kernel::fit_inverse",
        "State::round_supports",
        "Model::contact_dt",
        "physics::penalty::CONTACT_STEP",
    ] {
        assert!(src.resolves(present), "{present}");
    }
    for absent in [
        "cpu::contact::spring_stiffness",
        "cpu::nowhere",
        "physics::kernel::no_such_fn",
        "NoSuchType::leapfrog",
        "cpu::CpuSolver::no_such_method",
    ] {
        assert!(!src.resolves(absent), "{absent}");
    }
    let text = "// CPU twins: cpu::contact::is_candidate, surface_ramp and\n// physics::penalty::{gap, gap_bar}, with physics::johnson_cook for the\n// laws, steps 2 and 3 (the law).\n";
    let p: Vec<String> = pointers(text).into_iter().map(|(_, t)| t).collect();
    assert_eq!(
        p,
        [
            "cpu::contact::is_candidate",
            "cpu::contact::surface_ramp",
            "physics::penalty::gap",
            "physics::penalty::gap_bar",
            "physics::johnson_cook"
        ]
    );
}
