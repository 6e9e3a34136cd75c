//! Study of the spring's ledger in a scene: how much of its loss
//! (`energy_spring_loss`) is the stored energy jumping where the boundary
//! set changes between steps, and how many particles carry an entry
//! overlap (`State::entry`).
//!
//!     cargo run --release --example jumps -- SCENE.toml T_END
use sphcontact::cpu::{contact, kinematics, neighbours, CpuSolver};
use sphcontact::model::{Model, State};
use sphcontact::scene::Scene;

fn phi(model: &Model, st: &State, surface: &[bool]) -> f64 {
    let nb = neighbours::find(model, &st.x);
    let bd = kinematics::boundary(model, &st.x, &nb, surface.to_vec());
    contact::penalty(model, st, &nb, &bd).stats.stored
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = Scene::from_file(std::path::Path::new(&args[0])).expect("scene");
    let t_end: f64 = args[1].parse().unwrap();
    let (model, state) = Model::new(&scene);
    let mut solver = CpuSolver::new(model, state);
    let e0 = {
        let (m, s, d) = solver.observe();
        sphcontact::probe::energies(m, s, d).total()
    };
    let surf = |m: &Model, s: &State| {
        let nb = neighbours::find(m, &s.x);
        kinematics::kinematics(m, s, &nb).surface
    };
    let mut jset = 0.0;
    let (mut ins, mut outs) = (0usize, 0usize);
    let mut line = 0;
    while solver.state.t < t_end {
        let s0 = surf(&solver.model, &solver.state);
        let t = solver.state.t;
        if solver.step(t_end - t).is_err() {
            println!("unstable at {:.3} µs", t * 1e6);
            break;
        }
        let (m, st) = (&solver.model, &solver.state);
        let s1 = surf(m, st);
        let p1 = phi(m, st, &s1);
        let p0 = phi(m, st, &s0);
        jset += p1 - p0;
        for (a, b) in s0.iter().zip(&s1) {
            match (a, b) {
                (false, true) => ins += 1,
                (true, false) => outs += 1,
                _ => {}
            }
        }
        line += 1;
        if line % 50 == 0 {
            let (m, s, d) = solver.observe();
            let en = sphcontact::probe::energies(m, s, d);
            println!(
                "t {:.3} µs total {:+.3} % stored {:.3} % spring loss {:+.3} % set jumps {:+.3} % (in {ins} out {outs})",
                s.t * 1e6,
                100.0 * (en.total() / e0 - 1.0),
                100.0 * d.contact.stored / e0,
                100.0 * (s.spring_work - d.contact.stored) / e0,
                100.0 * jset / e0
            );
            let pos = s.entry.iter().filter(|&&e| e > 0.0).count();
            let mx = s.entry.iter().cloned().fold(0.0, f64::max);
            println!("  entries > 0: {pos}, largest {mx:e}");
        }
    }
}
