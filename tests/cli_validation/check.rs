//! `check`: what it says of a scene's set-up.

use super::*;

/// `check` gives the contact's step limit, and says when it sets the step:
/// not at the paper's CFL 0.3, at the stiff scenes' 0.9.
#[test]
fn check_names_the_contacts_step_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (scene, sets) in [
        ("scenes/paper/bars_steel.toml", false),
        ("scenes/hard/bars_stiff.toml", true),
    ] {
        let out = sphcontact(tmp.path(), &["check", root.join(scene).to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(0));
        let stdout = String::from_utf8_lossy(&out.stdout);
        // Δx / (√2 c_L) for the bars' steel at 50 µm.
        assert!(
            stdout.contains("step limit of the stiffest spring 6.0585e-9 s"),
            "{stdout}"
        );
        assert_eq!(stdout.contains("it sets the step"), sets, "{stdout}");
        // Under the contact's lines, which it belongs to.
        let lines: Vec<&str> = stdout.lines().collect();
        let k = lines
            .iter()
            .position(|l| l.contains("step limit of the stiffest spring"))
            .unwrap();
        assert!(lines[k - 1].starts_with("contact"), "{stdout}");
        assert_eq!(stdout.contains("(the contact's limit)"), sets, "{stdout}");
    }
}

/// `check` says whether the hourglass control runs and at what coefficient.
#[test]
fn check_names_the_hourglass_control() {
    let tmp = tempfile::tempdir().unwrap();
    let off = write_scene(tmp.path(), "off", BASE_1D);
    let text = format!("{BASE_1D}\n[artificial_viscosity]\nhourglass = 0.5\n");
    let on = write_scene(tmp.path(), "on", &text);
    for (scene, line) in [
        (off, "hourglass control off"),
        (on, "hourglass control 0.5"),
    ] {
        check_says(tmp.path(), &scene, line);
    }
}

/// `check` says which form of the viscosity runs and on which jump; a
/// bad `form` is a clear error naming the key.
#[test]
fn check_names_the_viscosity_form() {
    let tmp = tempfile::tempdir().unwrap();
    let default = write_scene(tmp.path(), "default", BASE_1D);
    let text = format!("{BASE_1D}\n[artificial_viscosity]\nform = \"monaghan\"\n");
    let monaghan = write_scene(tmp.path(), "monaghan", &text);
    let text = format!("{BASE_1D}\n[artificial_viscosity]\nreconstruct_surfaces = false\n");
    let plain = write_scene(tmp.path(), "plain", &text);
    for (scene, line) in [
        (
            default,
            "viscosity   Riemann (approaching and receding pairs), alpha 0.75, beta 0.75, on the reconstructed velocity jump;",
        ),
        (
            monaghan,
            "viscosity   Monaghan (approaching pairs), alpha 0.75, beta 0.75, on the reconstructed velocity jump;",
        ),
        (
            plain,
            "viscosity   Riemann (approaching and receding pairs), alpha 0.75, beta 0.75, on the reconstructed velocity jump (plain at surfaces);",
        ),
    ] {
        check_says(tmp.path(), &scene, line);
    }
    let bad = format!("{BASE_1D}\n[artificial_viscosity]\nform = \"godunov\"\n");
    let bad = write_scene(tmp.path(), "bad", &bad);
    let out = sphcontact(tmp.path(), &["check", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("artificial_viscosity.form") && stderr.contains("riemann"),
        "{stderr}"
    );
}

/// `check` says which artificial stress runs, where its work may only be
/// heat and which bodies take the hourglass control in its place; a bad
/// `work` is a clear error.
#[test]
fn check_names_the_artificial_stress() {
    let tmp = tempfile::tempdir().unwrap();
    let default = write_scene(tmp.path(), "default", BASE_1D);
    let heat = format!("{BASE_1D}\n[artificial_stress]\nwork = \"heat\"\n");
    let heat = write_scene(tmp.path(), "heat", &heat);
    let off = format!("{BASE_1D}\n[artificial_stress]\nepsilon = 0\n");
    let off = write_scene(tmp.path(), "off", &off);
    let plastic =
        format!("{BASE_1D}\n[artificial_stress]\npairs = \"close\"\nwork = \"plastic\"\n");
    let yielding = write_scene(tmp.path(), "yielding", &plastic);
    let elastic = plastic.replacen("yield_stress = 600.0e6\n", "", 1);
    assert_ne!(elastic, plastic);
    let elastic = write_scene(tmp.path(), "elastic", &elastic);
    let default_elastic = BASE_1D.replacen("yield_stress = 600.0e6\n", "", 1);
    assert_ne!(default_elastic, BASE_1D);
    let default_elastic = write_scene(tmp.path(), "default_elastic", &default_elastic);
    let either = format!("{BASE_1D}\n[artificial_stress]\npairs = \"close\"\nwork = \"either\"\n");
    let either = write_scene(tmp.path(), "either", &either);
    for (scene, line) in [
        (
            default,
            "artificial stress epsilon 0.3, n 4, close pairs; only heat in bodies that can yield, of either sign elsewhere",
        ),
        (
            default_elastic,
            "close pairs; its work of either sign (nothing can yield)",
        ),
        (
            either,
            "artificial stress epsilon 0.3, n 4, close pairs; its work of either sign",
        ),
        (
            heat,
            "artificial stress epsilon 0.3, n 4, every pair in tension; only heat",
        ),
        (off, "no artificial stress"),
        (
            elastic,
            "close pairs; its work of either sign (nothing yields)",
        ),
        (
            yielding,
            "close pairs; only heat where it flows plastically",
        ),
    ] {
        check_says(tmp.path(), &scene, line);
    }
    // The hourglass control in place of the term where a body can yield:
    // both bars can, so no artificial stress runs; without a yield
    // stress the key changes nothing.
    let keyed = format!(
        "{BASE_1D}\n[artificial_stress]\nplastic = \"hourglass\"\nplastic_hourglass = 0.5\n"
    );
    let keyed_elastic = keyed.replacen("yield_stress = 600.0e6\n", "", 1);
    let keyed = write_scene(tmp.path(), "keyed", &keyed);
    check_says(
        tmp.path(),
        &keyed,
        "plastic     left, right: the hourglass control 0.5 in place of the artificial stress",
    );
    check_says(tmp.path(), &keyed, "no artificial stress");
    let keyed_elastic = write_scene(tmp.path(), "keyed_elastic", &keyed_elastic);
    let out = sphcontact(tmp.path(), &["check", keyed_elastic.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains("every pair in tension; its work of either sign")
            && !stdout.contains("in place of"),
        "{stdout}"
    );
    let bad = format!("{BASE_1D}\n[artificial_stress]\nwork = \"cold\"\n");
    let bad = write_scene(tmp.path(), "bad", &bad);
    let out = sphcontact(tmp.path(), &["check", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("work"), "{stderr}");
}

#[test]
fn check_prints_the_derived_set_up() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/paper/bars_steel.toml");
    let out = sphcontact(tmp.path(), &["check", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let particles = stdout
        .lines()
        .find(|l| l.starts_with("particles"))
        .unwrap_or_else(|| panic!("no particle count: {stdout}"));
    assert_eq!(
        particles.split_whitespace().nth(1),
        Some("200"),
        "{particles}"
    );
    // c_L = sqrt((K + 4G/3) / ρ0) with K = ρ0 c0²: 5835.66 m/s for this steel.
    assert!(stdout.contains("c_L 5835."), "{stdout}");
    // The geometry, and each body's mass and velocity with their units.
    assert!(
        stdout
            .contains("set-up      1-D, uniaxial strain, interaction penalty, correction gradient"),
        "{stdout}"
    );
    assert!(stdout.contains(" kg/m2, velocity (10, 0) m/s"), "{stdout}");
    let axi =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/axisymmetric/taylor_bar_bilinear.toml");
    let out = sphcontact(tmp.path(), &["check", axi.to_str().unwrap()]);
    let axi = String::from_utf8_lossy(&out.stdout);
    assert!(
        axi.contains("set-up      2-D, bodies of revolution (r–z)"),
        "{axi}"
    );
    assert!(axi.contains(" kg, velocity (0, -227) m/s"), "{axi}");
    assert!(
        stdout.contains("leapfrog (one evaluation a step)"),
        "{stdout}"
    );
    // A polygon's outline, read from a drawing in millimetres, in metres.
    let drawn = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/shapes/rings_drawn.toml");
    let out = sphcontact(tmp.path(), &["check", drawn.to_str().unwrap()]);
    let drawn = String::from_utf8_lossy(&out.stdout);
    assert!(
        drawn.contains(
            "polygon of 64 vertices, 1 hole, x in [-1.0000e-2, 0.0000e0] m, y in [-5.0000e-3, 5.0000e-3] m"
        ),
        "{drawn}"
    );
    // check runs nothing and writes nothing.
    assert!(std::fs::read_dir(tmp.path()).unwrap().next().is_none());
}
