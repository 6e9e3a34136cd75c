// Linear pressure p = K mu (CPU twin: physics::eos::linear); no constants.

fn linear_pressure(b: Body, mu: f32, e: f32) -> f32 {
    return b.k * mu;
}

fn linear_dpdrho(b: Body, mu: f32, e: f32) -> f32 {
    return b.k / b.rho0;
}

fn linear_zero_mu(b: Body, e: f32) -> f32 {
    return 0.0;
}
