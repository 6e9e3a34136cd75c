//! Property test of the scene parser: whatever the text, `Scene::from_toml_str`
//! returns a scene or a [`SceneError`] naming the file, never a panic
//! (docs/scenes.md, "Errors": never a panic or a backtrace).
//!
//! Thousands of inputs from three generators, all from a fixed seed so a
//! failure reproduces: random TOML-ish text, random edits of the paper's
//! scenes (deleted spans, duplicated or dropped lines, truncation, garbage),
//! and the paper's scenes with values swapped for random ones of every TOML
//! type, extreme floats included. A failure prints the input that broke it.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use sphcontact::Scene;

/// xorshift64*: small, deterministic, good enough to pick edits.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

/// The paper's scenes: valid, small to place (at most some 16,000 particles).
fn seeds() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper");
    let mut out: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    out.sort();
    assert!(out.len() >= 4, "the paper's scenes");
    out
}

const EXTREME: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1",
    "2",
    "0.5",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "+inf",
    "9223372036854775807",
    "-9223372036854775808",
    "1e9",
    "3.0e-3",
    "\"\"",
    "\"steel\"",
    "\"x\"",
    "true",
    "false",
    "[]",
    "[1.0]",
    "[1.0, 2.0]",
    "[1.0, 2.0, 3.0]",
    "[nan, inf]",
    "[[]]",
    "{}",
    "{ kind = \"disk\" }",
    "{ kind = \"segment\", from = 1.0, to = 0.0 }",
    "{ kind = \"rectangle\", min = [0.0, 0.0], max = [0.0, 0.0] }",
    "1979-05-27T07:32:00Z",
    "0x10",
    "1_000",
];

/// A random value of some TOML type, extreme ones often.
fn value(rng: &mut Rng) -> String {
    match rng.below(6) {
        0 | 1 => rng.pick(EXTREME).to_string(),
        // Floats over eight decades either way (no spacing that small on
        // a 1 cm body: placement stays quick).
        2 => format!("{:e}", 10f64.powf(rng.below(8001) as f64 / 1000.0 - 4.0)),
        3 => format!("-{:e}", 10f64.powf(rng.below(8001) as f64 / 1000.0 - 4.0)),
        4 => format!(
            "[{}]",
            (0..rng.below(4))
                .map(|_| rng.pick(EXTREME).to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        _ => format!("\"{}\"", word(rng)),
    }
}

fn word(rng: &mut Rng) -> String {
    const WORDS: &[&str] = &[
        "steel",
        "left",
        "right",
        "disk",
        "segment",
        "rectangle",
        "penalty",
        "kernel",
        "gradient",
        "none",
        "auto",
        "gpu",
        "cpu",
        "mie_gruneisen",
        "linear",
        "velocity_x",
        "contact",
        "pressure_max",
        "force",
        "energy",
        "total",
        "body",
        "particle",
        "é",
        "\\u0000",
        "",
    ];
    rng.pick(WORDS).to_string()
}

/// Random text over TOML's punctuation, digits, keys and a little Unicode.
fn noise(rng: &mut Rng) -> String {
    const PIECES: &[&str] = &[
        "[",
        "]",
        "[[",
        "]]",
        "{",
        "}",
        "=",
        ",",
        ".",
        "\"",
        "'",
        "#",
        "\n",
        " ",
        "\t",
        "-",
        "+",
        "e",
        "0",
        "1",
        "9",
        "1.5",
        "1e-3",
        "nan",
        "inf",
        "true",
        "[simulation]",
        "[[bodies]]",
        "[materials.steel]",
        "[[probes]]",
        "[output]",
        "dimension",
        "end_time",
        "spacing",
        "shape",
        "kind",
        "name",
        "material",
        "velocity",
        "density",
        "eos",
        "c0",
        "ω",
        "\u{feff}",
        "\r\n",
        "\\",
        "\"\"\"",
        "'''",
    ];
    let len = rng.below(120);
    (0..len).map(|_| *rng.pick(PIECES)).collect()
}

/// One to four random edits of a valid scene.
fn mutate(rng: &mut Rng, base: &str) -> String {
    let mut s = base.to_string();
    for _ in 0..1 + rng.below(4) {
        let len = s.len();
        let at = floor_char(&s, rng.below(len + 1));
        match rng.below(7) {
            0 => {
                let end = floor_char(&s, (at + rng.below(40)).min(len));
                s.replace_range(at..end, "");
            }
            1 => {
                let garbage = noise(rng);
                s.insert_str(at, &garbage);
            }
            2 => s.truncate(at),
            3 | 4 => {
                // Swap the value of one `key = value` line.
                let lines: Vec<&str> = s.lines().collect();
                let keyed: Vec<usize> = (0..lines.len())
                    .filter(|&i| lines[i].contains('=') && !lines[i].trim_start().starts_with('#'))
                    .collect();
                if keyed.is_empty() {
                    continue;
                }
                let i = *rng.pick(&keyed);
                let key = lines[i].split('=').next().unwrap();
                let new = format!("{key}= {}", value(rng));
                let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
                out[i] = new;
                s = out.join("\n");
            }
            5 => {
                // Duplicate or drop a line.
                let mut lines: Vec<String> = s.lines().map(str::to_string).collect();
                if lines.is_empty() {
                    continue;
                }
                let i = rng.below(lines.len());
                if rng.below(2) == 0 {
                    let l = lines[i].clone();
                    lines.insert(i, l);
                } else {
                    lines.remove(i);
                }
                s = lines.join("\n");
            }
            _ => {
                // A stray header or key somewhere.
                let line = format!(
                    "\n{} = {}\n",
                    rng.pick(&["dimension", "spacing", "x", "bodies", "probes", "cfl", "dt"]),
                    value(rng)
                );
                s.insert_str(at, &line);
            }
        }
    }
    s
}

fn floor_char(s: &str, mut i: usize) -> usize {
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Parse `text`; a panic fails the test with the input, an error must name
/// the file and say something.
fn survives(text: &str, stats: &mut (usize, usize)) {
    let result = catch_unwind(AssertUnwindSafe(|| Scene::from_toml_str(text, "fuzz.toml")));
    match result {
        Err(_) => panic!("the parser panicked on this input:\n-----\n{text}\n-----"),
        Ok(Ok(_)) => stats.0 += 1,
        Ok(Err(e)) => {
            stats.1 += 1;
            assert_eq!(e.file, "fuzz.toml", "{e}");
            assert!(
                !e.message.trim().is_empty(),
                "an empty message ({e:?}) for:\n{text}"
            );
            let shown = e.to_string();
            assert!(shown.starts_with("fuzz.toml"), "{shown}");
        }
    }
}

#[test]
fn random_text_never_panics() {
    let mut rng = Rng(0x5eed_0001);
    let mut stats = (0, 0);
    for _ in 0..3000 {
        survives(&noise(&mut rng), &mut stats);
    }
    // Raw bytes as text, invalid UTF-8 replaced.
    for _ in 0..1000 {
        let bytes: Vec<u8> = (0..rng.below(200)).map(|_| rng.next() as u8).collect();
        survives(&String::from_utf8_lossy(&bytes), &mut stats);
    }
    // None of it is a scene: a scene needs its simulation, materials and
    // bodies, and the empty text among these inputs must be refused too.
    assert_eq!(stats.0, 0, "random text taken for a scene");
}

#[test]
fn edited_scenes_never_panic() {
    let seeds = seeds();
    let mut rng = Rng(0x5eed_0002);
    let mut stats = (0, 0);
    for _ in 0..6000 {
        let base = rng.pick(&seeds).clone();
        let text = mutate(&mut rng, &base);
        survives(&text, &mut stats);
    }
    // The edits reach both outcomes: valid scenes after a harmless edit
    // (a dropped comment, a value within its range) and every kind of error.
    assert!(stats.0 > 100, "valid after an edit: {}", stats.0);
    assert!(stats.1 > 2000, "errors: {}", stats.1);
}
