//! The complete scenes docs/scenes.md shows are valid scenes: each parses,
//! comes back equal from its own TOML, and runs on the CPU path with its
//! energy ledger closed, so the example a user copies works as written.

use sphcontact::run::{run_scene, RunOptions};
use sphcontact::scene::{Backend, Scene};

/// The ```toml blocks of docs/scenes.md that are whole scenes (they have a
/// `[simulation]` table), in order.
fn complete_scenes() -> Vec<String> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scenes.md");
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = Vec::new();
    let mut block: Option<String> = None;
    for line in text.lines() {
        match (&mut block, line.trim_end()) {
            (None, "```toml") => block = Some(String::new()),
            (Some(b), "```") => {
                if b.contains("\n[simulation]\n") {
                    out.push(std::mem::take(b));
                }
                block = None;
            }
            (Some(b), l) => {
                b.push_str(l);
                b.push('\n');
            }
            (None, _) => {}
        }
    }
    out
}

#[test]
fn the_complete_scenes_of_the_docs_parse_round_trip_and_run() {
    let scenes = complete_scenes();
    let dims: Vec<u32> = scenes
        .iter()
        .map(|t| {
            Scene::from_toml_str(t, "docs/scenes.md")
                .unwrap_or_else(|e| panic!("{e}\n{t}"))
                .simulation
                .dimension
        })
        .collect();
    // A 1-D and a 2-D example at least.
    assert!(dims.contains(&1) && dims.contains(&2), "{dims:?}");
    for text in &scenes {
        let scene = Scene::from_toml_str(text, "docs/scenes.md").unwrap();
        let back = toml::to_string(&scene).unwrap();
        assert_eq!(
            Scene::from_toml_str(&back, "round trip").unwrap(),
            scene,
            "{back}"
        );
        // Its first microsecond on the CPU path: no error, the ledger closed.
        let opts = RunOptions {
            backend: Some(Backend::Cpu),
            end_time: Some(1.0e-6),
            silent: true,
            write: false,
            ..Default::default()
        };
        let out = run_scene(&scene, None, &opts).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(out.summary.status, "completed");
        let e = &out.summary.energy;
        println!(
            "{}: {} particles, {} steps, residual {:e} of {:e}",
            scene.title.as_deref().unwrap_or("untitled"),
            out.summary.particles,
            out.summary.steps,
            e.residual,
            e.initial
        );
        assert!(e.residual.abs() < 1e-9 * e.initial, "residual {e:?}");
    }
}
