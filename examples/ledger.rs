//! Scratch study: where the penalty spring's unbooked work comes from.
//!
//!     cargo run --release --example ledger -- square|polar R_OVER_DX
//!
//! At every step of the disks' contact: the booked spring power Σ ½kδAw
//! against dΦ/dt along the velocities (central differences of the stored
//! energy), with everything live, and with the normals, the areas or both
//! held at the state's values. Their time integrals split the spring loss.

use glam::DVec2;
use sphcontact::cpu::{self, contact, kinematics, neighbours, CpuSolver};
use sphcontact::model::{Model, State};
use sphcontact::validation::disk_scene;

struct Frozen<'a> {
    normal: Option<&'a [DVec2]>,
    area: Option<&'a [f64]>,
}

fn phi(model: &Model, st: &State, surface: &[bool], fz: &Frozen) -> f64 {
    let nb = neighbours::find(model, &st.x);
    let k = kinematics::kinematics(model, st, &nb);
    let _ = k;
    let mut bd = kinematics::boundary(model, &st.x, &nb, surface.to_vec());
    if let Some(n) = fz.normal {
        bd.normal = n.to_vec();
    }
    if let Some(a) = fz.area {
        bd.area = a.to_vec();
    }
    contact::penalty(model, st, &nb, &bd).stats.stored
}

fn moved(st: &State, eps: f64) -> State {
    let mut s = st.clone();
    for (x, v) in s.x.iter_mut().zip(&st.v) {
        *x += *v * eps;
    }
    s
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let lattice = args.first().map_or("polar", String::as_str).to_string();
    let r: f64 = args.get(1).map_or(20.0, |a| a.parse().expect("R/dx"));
    let plain = args.get(2).is_some_and(|a| a == "plain");
    let mut scene = disk_scene(&lattice, r);
    if std::env::var("NOCORR").is_ok() {
        scene.simulation.correction = sphcontact::scene::Correction::None;
    }
    if let Some(c) = args.get(3) {
        scene.simulation.cfl = c.parse().expect("cfl");
    }
    let (model, state) = Model::new(&scene);
    let mut solver = CpuSolver::new(model, state);
    let t_end = scene.simulation.end_time;
    let e0 = {
        let (m, s, d) = solver.observe();
        sphcontact::probe::energies(m, s, d).total()
    };
    // Integrals of (booked − dΦ/dt) for: live, normals frozen, area
    // frozen, both frozen.
    let mut acc = [0.0f64; 4];
    let mut prev: Option<(f64, [f64; 4])> = None;
    let mut worst = (0.0f64, 0.0f64);
    let mut high = 0.0f64;
    let mut line = 0;
    while solver.state.t < t_end {
        let (model, st, diag) = solver.observe();
        let booked = diag.contact.spring_rate;
        let t = st.t;
        let mut rates = [0.0; 4];
        if !plain && (diag.contact.stored > 0.0 || booked != 0.0) {
            let nb = neighbours::find(model, &st.x);
            let k = kinematics::kinematics(model, st, &nb);
            let bd0 = kinematics::boundary(model, &st.x, &nb, k.surface.clone());
            let eps = 1e-3 * diag.cfl_dt;
            let (sp, sm) = (moved(st, eps), moved(st, -eps));
            let live = Frozen {
                normal: None,
                area: None,
            };
            let held = Frozen {
                normal: None,
                area: Some(&bd0.area),
            };
            let d_live = (phi(model, &sp, &k.surface, &live) - phi(model, &sm, &k.surface, &live))
                / (2.0 * eps);
            let d_held = (phi(model, &sp, &k.surface, &held) - phi(model, &sm, &k.surface, &held))
                / (2.0 * eps);
            let drho = cpu::evaluate(model, st).0.drho;
            let with_rho = |s: f64| {
                let mut m = st.clone();
                for (r, d) in m.rho.iter_mut().zip(&drho) {
                    *r += d * s * eps;
                }
                phi(model, &m, &k.surface, &held)
            };
            let d_rho = (with_rho(1.0) - with_rho(-1.0)) / (2.0 * eps);
            rates = [booked - d_held, booked - d_live, -d_rho, 0.0];
        }
        if let Some((tp, rp)) = prev {
            for i in 0..4 {
                acc[i] += 0.5 * (rates[i] + rp[i]) * (t - tp);
            }
        }
        prev = Some((t, rates));
        let total = sphcontact::probe::energies(model, st, diag).total();
        let dev = total / e0 - 1.0;
        if dev < worst.0 {
            worst = (dev, t);
        }
        high = high.max(dev);
        line += 1;
        if line % 40 == 0 && diag.contact.stored > 0.0 {
            println!(
                "t {:.3} µs total {:+.3} % stored {:.2} % | booked-dphi(area held) {:+.3} % booked-dphi(area live) {:+.3} % -dphi/drho {:+.3} % - {:+.3} %",
                t * 1e6,
                100.0 * dev,
                100.0 * diag.contact.stored / e0,
                100.0 * acc[0] / e0,
                100.0 * acc[1] / e0,
                100.0 * acc[2] / e0,
                100.0 * acc[3] / e0,
            );
        }
        solver.step(t_end - t).expect("stable");
    }
    let (model, st, diag) = solver.observe();
    let total = sphcontact::probe::energies(model, st, diag).total();
    println!(
        "{lattice} R/dx {r}: final {:+.3} %, highest {:+.3} %, lowest {:+.3} % at {:.2} µs; spring loss {:+.3} %",
        100.0 * (total / e0 - 1.0),
        100.0 * high,
        100.0 * worst.0,
        1e6 * worst.1,
        100.0 * (st.spring_work - diag.contact.stored) / e0
    );
    println!(
        "integrated booked − dΦ/dt: live {:+.3} %, normals frozen {:+.3} %, area frozen {:+.3} %, both {:+.3} %",
        100.0 * acc[0] / e0,
        100.0 * acc[1] / e0,
        100.0 * acc[2] / e0,
        100.0 * acc[3] / e0
    );
    let _ = cpu::SKIN_FRACTION;
}
