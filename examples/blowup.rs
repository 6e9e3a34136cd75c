//! Study: from a CPU checkpoint, step on and print, each step, the total
//! energy and the particle the contact accelerates most, with what its
//! contact terms are made of.
//!
//!     cargo run --release --example blowup -- OUT_DIR STEPS
use glam::DVec2;
use sphcontact::checkpoint::{Checkpoint, SolverState};
use sphcontact::cpu::{contact, kinematics, neighbours, CpuSolver};
use sphcontact::model::Model;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = std::path::Path::new(&args[0]).join("checkpoint.bin");
    let steps: usize = args[1].parse().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let ck = Checkpoint::from_bytes(&bytes, "ck").unwrap_or_else(|e| panic!("{e:?}"));
    let SolverState::Cpu(c) = ck.solver else {
        panic!("cpu")
    };
    let (model, _) = Model::new(&ck.scene);
    let mut solver = CpuSolver::new(model, c.state);
    let e0 = 12325.0;
    for _ in 0..steps {
        let (m, st, d) = solver.observe();
        let en = sphcontact::probe::energies(m, st, d).total();
        let nb = neighbours::find(m, &st.x);
        let k = kinematics::kinematics(m, st, &nb);
        let bd = kinematics::boundary(m, &st.x, &nb, k.surface);
        let cf = contact::penalty(m, st, &nb, &bd);
        let mut f = vec![DVec2::ZERO; m.len()];
        for (k, &i) in bd.list.iter().enumerate() {
            f[i as usize] += cf.force[k];
        }
        let mut spread = vec![DVec2::ZERO; m.len()];
        for &(i, g) in &cf.spread {
            spread[i as usize] += g;
        }
        let (imax, amax) = (0..m.len())
            .map(|i| (i, (f[i] + spread[i]).length() / m.mass[i]))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let vmax = st.v.iter().map(|v| v.length()).fold(0.0, f64::max);
        let kb = bd.list.binary_search(&(imax as u32)).ok();
        println!(
            "t {:.4} µs E {:+.2} % stored {:.3e} vmax {:.0} | top a {:.3e} at {} (body {}, boundary {}, h|g| {:.3}, area/dx {:.3}, entry/dx {:.3}) own {:.3e} spread {:.3e}",
            st.t * 1e6,
            100.0 * (en / e0 - 1.0),
            d.contact.stored,
            vmax,
            amax,
            imax,
            m.body[imax],
            kb.is_some(),
            m.h[imax] * bd.grad_norm[imax],
            bd.area[imax] / m.bodies[m.body[imax] as usize].spacing,
            st.entry[imax] / m.bodies[m.body[imax] as usize].spacing,
            f[imax].length(),
            spread[imax].length()
        );
        if solver.step(1.0).is_err() {
            println!("unstable");
            break;
        }
    }
}
