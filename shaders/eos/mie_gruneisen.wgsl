// Mie-Grüneisen pressure (CPU twin: physics::eos::mie_gruneisen), from
// mu = rho/rho0 - 1. Constants: Body.eos0 the Hugoniot slope s, Body.eos1
// the Grüneisen coefficient gamma0.

// The Hugoniot's cubic in compression and its slope d/dmu.
fn mie_gruneisen_hugoniot(b: Body, mu: f32) -> vec2<f32> {
    let sm = b.eos0 - 1.0;
    let b0 = b.k * (1.0 + 2.0 * sm);
    let c0 = b.k * (2.0 * sm + 3.0 * sm * sm);
    return vec2<f32>(mu * (b.k + mu * (b0 + mu * c0)), b.k + mu * (2.0 * b0 + 3.0 * mu * c0));
}

fn mie_gruneisen_pressure(b: Body, mu: f32, e: f32) -> f32 {
    var ph = b.k * mu;
    if (mu > 0.0) {
        ph = mie_gruneisen_hugoniot(b, mu).x;
    }
    // The thermal part from e >= 0 only.
    return (1.0 - 0.5 * b.eos1 * mu) * ph + b.eos1 * b.rho0 * (1.0 + mu) * max(e, 0.0);
}

fn mie_gruneisen_dpdrho(b: Body, mu: f32, e: f32) -> f32 {
    let dpdrho = b.k / b.rho0;
    if (mu <= 0.0) {
        return dpdrho;
    }
    let h = mie_gruneisen_hugoniot(b, mu);
    let d = ((1.0 - 0.5 * b.eos1 * mu) * h.y - 0.5 * b.eos1 * h.x) / b.rho0 + b.eos1 * max(e, 0.0);
    return max(dpdrho, d);
}

fn mie_gruneisen_zero_mu(b: Body, e: f32) -> f32 {
    if (b.eos1 == 0.0) {
        return 0.0;
    }
    let ge = b.eos1 * b.rho0 * max(e, 0.0);
    let bb = b.k + ge;
    return -2.0 * ge / (bb + sqrt(bb * bb + 2.0 * b.eos1 * b.k * ge));
}
