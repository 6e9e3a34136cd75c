//! Study of the penalty spring's energy ledger on the paper's two disks.
//!
//!     cargo run --release --example ledger -- square|polar R_OVER_DX [plain|full] [CFL] [ANGLE]
//!
//! `ANGLE` (degrees) turns the line of centres from the velocities: an
//! oblique, sliding (frictionless) impact, the disks still touching at t = 0.
//!
//! Prints the total energy (kinetic + internal + stored spring) against its
//! initial value through the contact. Unless `plain`, also integrates, over
//! the contact, the booked spring power less dΦ/dt by central differences
//! of the stored energy along the velocities (with the contact areas held,
//! and live), and −∂Φ/∂ρ·ρ̇ (what the densities' change would move Φ by):
//! the parts of the ledger no force accounts for.

use sphcontact::cpu::{self, contact, forces, kinematics, neighbours, CpuSolver};
use sphcontact::model::{Model, State};
use sphcontact::validation::disk_scene;

/// The stored energy at `st` with the boundary set `surface`, and the
/// contact areas `area` where given (else their own).
fn phi(model: &Model, st: &State, surface: &[bool], area: Option<&[f64]>) -> f64 {
    let nb = neighbours::find(model, st.frame());
    // The paper's disks are plane: the surface ramp reads `h |∇ψ⁰|`.
    let mut bd = forces::boundary(model, &st.x, &nb, surface.to_vec(), Vec::new());
    if let Some(a) = area {
        bd.area = a.to_vec();
    }
    contact::penalty(model, st, &nb, &bd).stats.stored
}

/// `st` with the positions moved by `s` times the velocities, or the
/// densities by `s` times `drho`.
fn moved(st: &State, s: f64, drho: Option<&[f64]>) -> State {
    let mut m = st.clone();
    match drho {
        None => m.x.iter_mut().zip(&st.v).for_each(|(x, v)| *x += *v * s),
        Some(d) => m.rho.iter_mut().zip(d).for_each(|(r, d)| *r += d * s),
    }
    m
}

const COLUMNS: [&str; 3] = [
    "booked − dΦ/dt (area held)",
    "booked − dΦ/dt (area live)",
    "−∂Φ/∂ρ·ρ̇",
];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let lattice = args.first().map_or("polar", String::as_str).to_string();
    let r: f64 = args.get(1).map_or(20.0, |a| a.parse().expect("R/dx"));
    let plain = args.get(2).is_some_and(|a| a == "plain");
    let mut scene = disk_scene(&lattice, r);
    if let Some(c) = args.get(3) {
        scene.simulation.cfl = c.parse().expect("cfl");
    }
    if let Some(a) = args.get(4) {
        let a: f64 = a.parse::<f64>().expect("angle") * std::f64::consts::PI / 180.0;
        for b in &mut scene.bodies {
            if let sphcontact::scene::Shape::Disk { center, radius, .. } = &mut b.shape {
                let side = center[0].signum();
                center[0] = side * *radius * a.cos();
                center[1] = side * *radius * a.sin();
            }
        }
        // The sliding contact lasts longer along the line of centres.
        scene.simulation.end_time /= a.cos();
    }
    let (model, state) = Model::new(&scene);
    let mut solver = CpuSolver::new(model, state);
    let t_end = scene.simulation.end_time;
    let e0 = {
        let (m, s, d) = solver.observe();
        sphcontact::probe::energies(m, s, d).total()
    };
    let mut acc = [0.0f64; 3];
    let mut prev: Option<(f64, [f64; 3])> = None;
    let (mut low, mut low_t, mut high) = (0.0f64, 0.0f64, 0.0f64);
    let mut line = 0;
    while solver.state.t < t_end {
        let (model, st, diag) = solver.observe();
        let booked = diag.contact.spring_rate;
        let t = st.t;
        let mut rates = [0.0; 3];
        if !plain && (diag.contact.stored > 0.0 || booked != 0.0) {
            let nb = neighbours::find(model, st.frame());
            let surface = kinematics::kinematics(model, st, &nb).surface;
            let area = forces::boundary(model, &st.x, &nb, surface.clone(), Vec::new()).area;
            let eps = 1e-3 * diag.cfl_dt;
            let rate = |area: Option<&[f64]>, drho: Option<&[f64]>| {
                let at = |s: f64| phi(model, &moved(st, s * eps, drho), &surface, area);
                (at(1.0) - at(-1.0)) / (2.0 * eps)
            };
            let drho = cpu::evaluate(model, st).0.drho;
            rates = [
                booked - rate(Some(&area), None),
                booked - rate(None, None),
                -rate(Some(&area), Some(&drho)),
            ];
        }
        if let Some((tp, rp)) = prev {
            for i in 0..3 {
                acc[i] += 0.5 * (rates[i] + rp[i]) * (t - tp);
            }
        }
        prev = Some((t, rates));
        let dev = sphcontact::probe::energies(model, st, diag).total() / e0 - 1.0;
        if dev < low {
            (low, low_t) = (dev, t);
        }
        high = high.max(dev);
        line += 1;
        if line % 40 == 0 && diag.contact.stored > 0.0 {
            print!(
                "t {:.3} µs total {:+.3} % stored {:.2} %",
                t * 1e6,
                100.0 * dev,
                100.0 * diag.contact.stored / e0
            );
            for (name, a) in COLUMNS.iter().zip(acc) {
                print!(" | {name} {:+.3} %", 100.0 * a / e0);
            }
            println!();
        }
        solver.step(t_end - t).expect("stable");
    }
    let (model, st, diag) = solver.observe();
    let total = sphcontact::probe::energies(model, st, diag).total();
    println!(
        "{lattice} R/dx {r}: final {:+.3} %, highest {:+.3} %, lowest {:+.3} % at {:.2} µs; spring loss {:+.6} %",
        100.0 * (total / e0 - 1.0),
        100.0 * high,
        100.0 * low,
        1e6 * low_t,
        100.0 * (st.spring_work - diag.contact.stored) / e0
    );
    if !plain {
        for (name, a) in COLUMNS.iter().zip(acc) {
            println!("integrated {name}: {:+.3} %", 100.0 * a / e0);
        }
    }
}
