//! Each strength law of the registry on the device against its formula,
//! written out here (Johnson–Cook, its multiplicative rate form, and
//! Zerilli–Armstrong in its FCC and BCC forms): the rate and temperature
//! factor, the flow stress and its slope at plastic strains, rates and
//! temperatures across an impact's, and the radial return's plastic strain
//! increment, which must land on the formula's surface.

use super::*;
use sphcontact::physics::laws::{
    johnson_cook, modified_johnson_cook, zerilli_armstrong, StrengthLaw,
};

/// The laws, each with its formula `σ_y(ε_p, ε̇, T)`.
type Formula = fn(f64, f64, f64) -> f64;

fn jc_4340() -> johnson_cook::Strength {
    johnson_cook::Strength {
        a: 792e6,
        b: 510e6,
        n: 0.26,
        c: 0.014,
        m: 1.03,
        reference_strain_rate: 1.0,
        room_temperature: 294.0,
        melt_temperature: 1793.0,
    }
}

fn laws() -> Vec<(&'static str, StrengthLaw, Formula)> {
    let za = |c0, c1, c2, c3, c4, c5, n| zerilli_armstrong::Strength {
        c0,
        c1,
        c2,
        c3,
        c4,
        c5,
        n,
        room_temperature: 294.0,
        melt_temperature: None,
        minimum_strain_rate: 1e-3,
    };
    vec![
        (
            "Johnson–Cook",
            StrengthLaw::JohnsonCook(jc_4340()),
            |e, r, t| {
                let ts = ((t - 294.0) / (1793.0 - 294.0)).clamp(0.0, 1.0);
                (792e6 + 510e6 * e.powf(0.26))
                    * (1.0 + 0.014 * r.max(1.0).ln())
                    * (1.0 - ts.powf(1.03))
            },
        ),
        (
            "modified Johnson–Cook",
            StrengthLaw::ModifiedJohnsonCook(modified_johnson_cook::Strength(
                johnson_cook::Strength {
                    a: 490e6,
                    b: 807e6,
                    n: 0.73,
                    c: 0.0114,
                    m: 0.94,
                    reference_strain_rate: 5e-4,
                    room_temperature: 294.0,
                    melt_temperature: 1800.0,
                },
            )),
            |e, r, t| {
                let ts = ((t - 294.0) / (1800.0 - 294.0)).clamp(0.0, 1.0);
                (490e6 + 807e6 * e.powf(0.73))
                    * (1.0 + r / 5e-4).powf(0.0114)
                    * (1.0 - ts.powf(0.94))
            },
        ),
        (
            "Zerilli–Armstrong FCC",
            StrengthLaw::ZerilliArmstrong(za(65e6, 0.0, 890e6, 0.0028, 0.000115, 0.0, 0.0)),
            |e, r, t| {
                65e6 + 890e6 * e.sqrt() * (-0.0028 * t + 0.000115 * t * r.max(1e-3).ln()).exp()
            },
        ),
        (
            "Zerilli–Armstrong BCC",
            StrengthLaw::ZerilliArmstrong(za(70e6, 1033e6, 0.0, 0.00698, 0.000415, 266e6, 0.289)),
            |e, r, t| {
                70e6 + 1033e6 * (-0.00698 * t + 0.000415 * t * r.max(1e-3).ln()).exp()
                    + 266e6 * e.powf(0.289)
            },
        ),
    ]
}

/// A scene whose steel bars carry `law`.
fn scene_with(law: StrengthLaw) -> sphcontact::Scene {
    let mut scene = load("scenes/paper/bars_steel.toml");
    let m = scene.materials.get_mut("steel").expect("steel");
    (m.yield_stress, m.strength, m.specific_heat) = (None, Some(law), Some(477.0));
    scene
}

/// The device's factor, flow stress and slope (against the formula's
/// central difference) within 1e-6 of the formula's, and the return's
/// increment leaving the stress on the formula's surface within 1e-6 of
/// the trial stress (f32; measured at most 3.2e-7, lavapipe). The
/// CPU law meets the formula to 1e-13.
#[test]
fn each_law_meets_its_formula_on_both_backends() {
    for (name, law, formula) in laws() {
        let scene = scene_with(law);
        let (model, st) = Model::new(&scene);
        let g_mod = model.material(0).g;
        let mut rows = Vec::new();
        for eps in [0.0f64, 0.01, 0.1, 0.5, 2.0] {
            for rate in [0.5f64, 1e3, 1e5] {
                for rise in [0.0f64, 300.0] {
                    // A trial stress 30 % above the surface: it yields.
                    let q = 1.3 * formula(eps, rate, 294.0 + rise);
                    rows.push([eps, rate, rise, q]);
                }
            }
        }
        let mut worst = [0.0f64; 4];
        for r in &rows {
            let (eps, rate, t) = (r[0], r[1], 294.0 + r[2]);
            let y = law.flow_stress(eps, rate, t);
            let want = formula(eps, rate, t);
            assert!(
                (y / want - 1.0).abs() < 1e-13,
                "{name} CPU {r:?}: {y} vs {want}"
            );
        }
        let Some(ctx) = gpu() else { continue };
        let gs = GpuSolver::new(ctx, model, &st, &[], 1.0).expect("fits");
        let rows32: Vec<[f32; 4]> = rows.iter().map(|r| r.map(|x| x as f32)).collect();
        let out = gs.strength_law(0, &rows32);
        for (r, o) in rows.iter().zip(&out) {
            let (eps, rate, t, q) = (r[0], r[1], 294.0 + r[2], r[3]);
            let f = law.factor(rate, t);
            let y = formula(eps, rate, t);
            let errs = [
                (o[0] as f64 / f - 1.0).abs(),
                (o[1] as f64 / y - 1.0).abs(),
                if eps > 0.0 {
                    let h = 1e-5 * eps;
                    let fd = (formula(eps + h, rate, t) - formula(eps - h, rate, t)) / (2.0 * h);
                    (o[2] as f64 / fd - 1.0).abs()
                } else {
                    0.0
                },
                {
                    let d = o[3] as f64;
                    let on = formula(eps + d, rate, t);
                    assert!(d > 0.0, "{name} {r:?}: yields");
                    ((q - 3.0 * g_mod * d) - on).abs() / q
                },
            ];
            for k in 0..4 {
                worst[k] = worst[k].max(errs[k]);
            }
        }
        println!(
            "{name}: factor {:.1e}, flow stress {:.1e}, slope {:.1e}, return {:.1e}",
            worst[0], worst[1], worst[2], worst[3]
        );
        assert!(worst.iter().all(|&w| w < 1e-6), "{name}: {worst:?}");
    }
}
