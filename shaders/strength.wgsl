// The stress update with a plastic history (docs/method.md, "Strength and
// failure"): the radial return onto the yield surface of a strength law
// (shaders/laws/, dispatched by `law_factor` and `law_curve`, which the
// host writes from the registry) or of perfect plasticity, the plastic
// work's heating, Johnson–Cook damage, spall, and a failed particle's
// density floor. Part of the stages that run it: the kinematics pass (the
// leapfrog's step) and the midpoint rule's advance passes. CPU twin:
// physics::strength::update, with physics::laws for the laws.
//
// Precision plan: a particle's history is (eps_p, T - T_room, D, failure
// time) in f32. The temperature is kept as its rise above room temperature
// so that a step's heating (millikelvins) is not lost against 300 K; the
// host adds the room temperature back in f64.

// Per-body constants of the strength and failure laws (mirrored by
// `gpu::layout::PlasticGpu`).
struct Plastic {
    // The strength law's constants, as its file in shaders/laws/ reads
    // them.
    k: array<f32, 8>,
    // The strength law's number (physics::laws registry; 0: perfect
    // plasticity at Body.y0, or elastic).
    law: u32,
    // Room temperature, K.
    room: f32,
    // The damage law's reference strain rate, 1/s.
    rate0: f32,
    // T_melt - T_room, K (BIG: no melt).
    melt_rise: f32,
    // Taylor–Quinney fraction over the specific heat, K kg/J.
    heat: f32,
    // The damage law's constants, as its file in shaders/failure/ reads
    // them.
    d1: f32,
    d2: f32,
    d3: f32,
    d4: f32,
    d5: f32,
    // Spall pressure, Pa (BIG: none).
    spall: f32,
    // Cavitation pressure, Pa (BIG: none).
    cavitation: f32,
    // The damage law's number (physics::failure registry; 0: none).
    damage: u32,
}

@group(0) @binding(79) var<storage, read> plastic: array<Plastic>;

// physics::failure::TRIAXIALITY_BOUND.
const TRIAXIALITY_BOUND: f32 = 1.5;

// sqrt(2/3 d':d') of a velocity gradient (xx, xy, yx, yy), plane strain
// (physics::strength::equivalent_strain_rate).
fn equivalent_rate(gv: vec4<f32>, d_tt: f32) -> f32 {
    let dxy = 0.5 * (gv.y + gv.z);
    if (AXI) {
        // The third normal rate is the hoop rate d_tt
        // (strength::equivalent_strain_rate_3).
        let t3 = (gv.x + gv.w + d_tt) / 3.0;
        let a = gv.x - t3;
        let b = gv.w - t3;
        let c = d_tt - t3;
        return sqrt((2.0 / 3.0) * (a * a + b * b + c * c + 2.0 * dxy * dxy));
    }
    let tr3 = (gv.x + gv.w) / 3.0;
    let a = gv.x - tr3;
    let b = gv.w - tr3;
    return sqrt((2.0 / 3.0) * (a * a + b * b + tr3 * tr3 + 2.0 * dxy * dxy));
}

// The homologous temperature T* from the rise above room temperature.
fn homologous(p: Plastic, rise: f32) -> f32 {
    return clamp(rise / p.melt_rise, 0.0, 1.0);
}

// The plastic strain increment of the return from von Mises stress `q`
// with shear modulus `g` at plastic strain `eps` onto the law's curve, its
// rate and temperature factor `f` held: safeguarded Newton on a bracket,
// to f32 round-off (physics::laws::return_increment).
fn return_increment(p: Plastic, q: f32, g: f32, eps: f32, f: f32) -> f32 {
    if (q - law_curve(p, f, eps).x <= 0.0) {
        return 0.0;
    }
    var lo = 0.0;
    var hi = q / (3.0 * g);
    var d = 0.5 * hi;
    for (var it = 0; it < 60; it++) {
        let c = law_curve(p, f, eps + d);
        let r = q - 3.0 * g * d - c.x;
        let dr = -3.0 * g - c.y;
        if (r > 0.0) {
            lo = d;
        } else {
            hi = d;
        }
        let newton = d - r / dr;
        if (newton >= lo && newton <= hi) {
            let done = abs(newton - d) <= 1e-7 * d;
            d = newton;
            if (done) {
                break;
            }
        } else {
            d = 0.5 * (lo + hi);
        }
        if (r == 0.0 || hi - lo <= 1e-7 * hi) {
            break;
        }
    }
    return d;
}

// A particle's stress and history after the update, and its mu (raised to
// the floor where it fails).
struct Updated {
    s: vec4<f32>,
    h: vec4<f32>,
    mu: f32,
}

// The stress update of a particle of body `bi` (physics::strength::update):
// trial deviatoric stress `trial` at strain rate `rate`, ending at (mu, e),
// from history `h`; `t_end` is the time the step ends at (a particle
// failing now fails then).
fn strength_update(bi: u32, trial: vec4<f32>, rate: f32, mu: f32, e: f32, h_in: vec4<f32>, t_end: f32) -> Updated {
    var h = h_in;
    let b = bodies[bi];
    if (failed(h.z)) {
        return Updated(vec4<f32>(0.0), h, max(mu, eos_zero_mu(b, e)));
    }
    let pl = plastic[bi];
    let q = von_mises(trial);
    var s = trial;
    var d_eps = 0.0;
    var flow = q;
    if (pl.law != 0u) {
        let f = law_factor(pl, rate, h.y);
        d_eps = return_increment(pl, q, b.g, h.x, f);
        if (d_eps > 0.0) {
            flow = q - 3.0 * b.g * d_eps;
            s = trial * (flow / q);
            h.y += pl.heat * flow * d_eps / (b.rho0 * (1.0 + mu));
        }
    } else if (b.elastic == 0u && q > b.y0) {
        d_eps = (q - b.y0) / (3.0 * b.g);
        flow = b.y0;
        s = trial * (b.y0 / q);
    }
    h.x += d_eps;
    var mu_out = mu;
    if (FAILURE) {
        let p = eos_pressure(b, mu, e);
        if (pl.damage != 0u && d_eps > 0.0) {
            // A melted particle (no flow stress) at the bound of its sign.
            var triax = BIG;
            if (p >= 0.0) {
                triax = -BIG;
            }
            if (flow > 0.0) {
                triax = -p / flow;
            }
            var rate_star = rate;
            var t_star = 0.0;
            if (pl.law != 0u) {
                rate_star = rate / pl.rate0;
                t_star = homologous(pl, h.y);
            }
            let eps_f = failure_strain(pl, clamp(triax, -TRIAXIALITY_BOUND, TRIAXIALITY_BOUND), rate_star, t_star);
            h.z = min(h.z + d_eps / eps_f, FAILED);
        }
        if (p < -pl.spall) {
            h.z = FAILED;
        }
        if (failed(h.z)) {
            s = vec4<f32>(0.0);
            mu_out = max(mu, eos_zero_mu(b, e));
            if (h.w < 0.0) {
                h.w = t_end;
            }
        }
    }
    // Drawn past the cavitation pressure, an intact particle opens a void
    // that compression closes; while it is open the particle's deviatoric
    // stress is zero and its density held at the failed floor (CPU twin:
    // physics::strength::void_state, cpu::advance::return_with_history).
    if (CAVITATION && !failed(h.z)) {
        let p = eos_pressure(b, mu, e);
        if (p < -pl.cavitation) {
            h.w = VOID_OPEN;
        } else if (h.w == VOID_OPEN && p > VOID_CLOSES * pl.cavitation) {
            h.w = INTACT;
        }
        if (h.w == VOID_OPEN) {
            s = vec4<f32>(0.0);
            mu_out = max(mu, eos_zero_mu(b, e));
        }
    }
    return Updated(s, h, mu_out);
}
