//! `sphcontact doctor`: it names every adapter the solver can see, says
//! which path `run` takes and why, and its exit status says whether a
//! hardware adapter is usable.

use std::process::Command;

#[test]
fn doctor_names_the_adapter_and_the_path_run_takes() {
    let out = Command::new(env!("CARGO_BIN_EXE_sphcontact"))
        .arg("doctor")
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("the sphcontact binary runs");
    let text = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(text.contains("adapters ("), "{text}");
    // The adapter `run` would open, as the solver's own context sees it.
    match sphcontact::gpu::GpuContext::new() {
        Ok(ctx) if !ctx.is_software() => {
            assert_eq!(out.status.code(), Some(0), "{text}");
            assert!(text.contains("takes the GPU path"), "{text}");
            assert!(text.contains(&ctx.info.name), "{text}");
        }
        Ok(ctx) => {
            // A software rasteriser (lavapipe on CI): the CPU path, why,
            // and what to install.
            assert_eq!(out.status.code(), Some(1), "{text}");
            assert!(
                text.contains("takes the CPU path: the only adapter is a software one"),
                "{text}"
            );
            assert!(text.contains(&ctx.info.name), "{text}");
            assert!(text.contains("to use a GPU:"), "{text}");
        }
        Err(e) => {
            assert_eq!(out.status.code(), Some(1), "{text}");
            assert!(text.contains(&format!("takes the CPU path: {e}")), "{text}");
            assert!(text.contains("to use a GPU:"), "{text}");
        }
    }
    // Every adapter line carries the limits the solver needs, against its
    // need.
    let needed = sphcontact::doctor::storage_buffers_needed();
    assert!(
        needed >= 8,
        "the busiest kernel binds {needed} storage buffers"
    );
    assert!(
        text.contains(&format!("(the solver needs {needed}")),
        "{text}"
    );
}
