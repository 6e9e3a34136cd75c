//! The crate's `rust-version` is no older than what its locked
//! dependencies declare: a toolchain the manifest accepts builds them.

use std::process::Command;

/// `1.87` or `1.87.0` as comparable numbers.
fn version(v: &str) -> Vec<u64> {
    let mut parts: Vec<u64> = v.split('.').map(|p| p.parse().unwrap()).collect();
    parts.resize(3, 0);
    parts
}

/// The host's target triple, from `rustc -vV`.
fn host() -> String {
    let out = Command::new("rustc")
        .arg("-vV")
        .output()
        .expect("rustc runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.lines()
        .find_map(|l| l.strip_prefix("host: "))
        .expect("rustc names its host")
        .to_string()
}

/// The dependencies this host builds: `--filter-platform`, because a
/// fresh checkout's registry holds only them (`cargo build` fetches no
/// other platform's crates), and offline `cargo metadata` would fail on the
/// rest.
#[test]
fn rust_version_covers_every_locked_dependency() {
    let out = Command::new(env!("CARGO"))
        .args(["metadata", "--format-version", "1", "--offline", "--locked"])
        .args(["--filter-platform", &host()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let resolved: Vec<&str> = meta["resolve"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["id"].as_str().unwrap())
        .collect();
    let packages = meta["packages"].as_array().unwrap();
    let ours = packages
        .iter()
        .find(|p| p["name"] == "sphcontact")
        .expect("this crate");
    let floor = version(ours["rust_version"].as_str().expect("a rust-version"));
    let mut needs: Vec<(Vec<u64>, String)> = packages
        .iter()
        .filter(|p| p["name"] != "sphcontact" && resolved.contains(&p["id"].as_str().unwrap()))
        .filter_map(|p| {
            let v = p["rust_version"].as_str()?;
            Some((
                version(v),
                format!(
                    "{} {} needs {v}",
                    p["name"].as_str().unwrap(),
                    p["version"].as_str().unwrap()
                ),
            ))
        })
        .collect();
    needs.sort();
    let (newest, who) = needs.last().expect("dependencies that declare one");
    println!("rust-version {floor:?}; the newest a dependency needs: {who}");
    assert!(
        *newest <= floor,
        "rust-version {floor:?} is older than {who}"
    );
}
