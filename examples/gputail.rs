//! Study: resume a GPU checkpoint and step it one step a batch, printing
//! the time, the step and the particle states that limit the step.
//!
//!     cargo run --release --example gputail -- OUT_DIR STEPS
use sphcontact::checkpoint::{Checkpoint, SolverState};
use sphcontact::gpu::{shared_context, GpuSolver};
use sphcontact::model::Model;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = std::path::Path::new(&args[0]).join("checkpoint.bin");
    let steps: usize = args[1].parse().unwrap();
    let ck = Checkpoint::from_bytes(&std::fs::read(&path).unwrap(), "ck")
        .unwrap_or_else(|e| panic!("{e:?}"));
    let SolverState::Gpu(g) = ck.solver else {
        panic!("gpu")
    };
    let (model, state) = Model::new(&ck.scene);
    let ctx = shared_context().unwrap();
    let mut s = GpuSolver::new(ctx, model.clone(), &state, &[], 1.0).unwrap();
    s.restore_raw(&g.device).unwrap();
    s.set_stop_time(ck.scene.simulation.end_time);
    for k in 0..steps {
        let b = s.run_batch(1);
        let st = s.download();
        if k % 20 != 0 && k + 1 != steps {
            continue;
        }
        let (mut vi, mut vmax, mut ri, mut rmax) = (0, 0.0, 0, 0.0);
        for i in 0..model.len() {
            let v = st.v[i].length();
            if v > vmax {
                (vi, vmax) = (i, v);
            }
            let r = st.rho[i] / model.material(i).rho0;
            let dev = r.max(1.0 / r);
            if dev > rmax {
                (ri, rmax) = (i, dev);
            }
        }
        println!(
            "t {:.9e} step {} failure {:?} | vmax {vmax:.3e} at {vi} | rho dev {rmax:.3} at {ri} (rho/rho0 {:.3}, e {:.3e})",
            st.t,
            st.step,
            b.failure.map(|f| f.to_string()),
            st.rho[ri] / model.material(ri).rho0,
            st.e[ri]
        );
    }
}
