//! `sphcontact ballistic`: the bisection over whole runs, its outputs and
//! its refusals, on the penetration scene at a coarse spacing (Δx = 0.2 mm,
//! 2,300 particles).

use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_sphcontact");
const SCENE: &str = "scenes/penetration/tungsten_rod_steel_plate.toml";

fn ballistic(out: &Path, extra: &[&str]) -> Output {
    ballistic_of(Path::new(SCENE), out, extra)
}

fn ballistic_of(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(BIN)
        .env("SPHCONTACT_FONT", "")
        .arg("ballistic")
        .arg(scene)
        .args(["--spacing", "2e-4", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .expect("runs")
}

/// The penetration scene with round supports (`support = "fixed"`), written
/// into `dir`: the shots are about the bisection, and round supports take
/// half the steps of the squeezed ones.
fn round_scene(dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(SCENE).expect("the scene");
    assert!(text.contains("[simulation]\n"));
    let path = dir.join("round.toml");
    std::fs::write(
        &path,
        text.replace("[simulation]\n", "[simulation]\nsupport = \"fixed\"\n"),
    )
    .expect("written");
    path
}

/// A slow shot that stays in the plate, a fast one that comes through and
/// one bisection between them: the bracket follows the shots, the
/// residual velocity is 0 below it and between 0 and the impact speed
/// above it, and the rod that comes through has broken the plate.
#[test]
fn bisection_brackets_the_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = round_scene(tmp.path());
    let out = ballistic_of(
        &scene,
        tmp.path(),
        &[
            "--projectile",
            "rod",
            "--target",
            "plate",
            "--low",
            "300",
            "--high",
            "1500",
            "--tolerance",
            "700",
            "--backend",
            "cpu",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let b: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("ballistic.json")).unwrap()).unwrap();
    let shots = b["shots"].as_array().unwrap();
    assert_eq!(shots.len(), 3, "{b}");
    let shot = |k: usize| {
        let s = &shots[k];
        (
            s["speed"].as_f64().unwrap(),
            s["perforated"].as_bool().unwrap(),
            s["residual_velocity"].as_f64().unwrap(),
            s["target_failed"].as_u64().unwrap(),
        )
    };
    assert!(shots.iter().all(|s| s["undecided"] == false), "{b}");
    assert!(b["stopped"].is_null(), "{b}");
    let (v0, p0, r0, _) = shot(0);
    assert_eq!((v0, p0, r0), (300.0, false, 0.0));
    let (v1, p1, r1, f1) = shot(1);
    assert!(v1 == 1500.0 && p1 && r1 > 0.0 && r1 < v1 && f1 > 0, "{b}");
    let (v2, p2, r2, _) = shot(2);
    assert_eq!(v2, 900.0);
    assert_eq!(r2 > 0.0, p2);
    let bracket = [
        b["limit_bracket"][0].as_f64().unwrap(),
        b["limit_bracket"][1].as_f64().unwrap(),
    ];
    assert_eq!(bracket, if p2 { [300.0, 900.0] } else { [900.0, 1500.0] });
    assert_eq!(b["spacing"][0].as_f64(), Some(2e-4));
    let csv = std::fs::read_to_string(tmp.path().join("residual.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(tmp.path().join("v1500/summary.json").exists());
}

fn refused(extra: &[&str], needle: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let out = ballistic(tmp.path(), extra);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(needle), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn bad_searches_are_refused() {
    let base = ["--low", "300", "--high", "1500"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        base.iter().chain(extra).copied().collect()
    };
    refused(
        &with(&["--projectile", "bullet", "--target", "plate"]),
        "--projectile bullet: no such body (the scene has rod, plate)",
    );
    refused(
        &with(&["--projectile", "rod", "--target", "rod"]),
        "the same body",
    );
    refused(
        &with(&["--projectile", "plate", "--target", "rod"]),
        "has no velocity",
    );
    refused(
        &[
            "--projectile",
            "rod",
            "--target",
            "plate",
            "--low",
            "900",
            "--high",
            "800",
        ],
        "0 < low < high",
    );
    refused(
        &with(&[
            "--projectile",
            "rod",
            "--target",
            "plate",
            "--tolerance",
            "0",
        ]),
        "--tolerance",
    );
    refused(
        &with(&["--projectile", "rod", "--target", "plate", "--speeds", "0"]),
        "--speeds",
    );
}
