// The kinematics stage's per-particle part (the host appends it to the
// kinematics stage's module, kinematics.wgsl, which declares the buffers it
// reads): the gradient correction, the boundary test, the stress point with
// the EOS, and the density and stress rates.

// L_i from M_i, or the identity (counted) when M_i cannot be inverted.
// `ok`: `conditioned(dim_fixed(m_in), params.min_sv2)`, which the caller
// also needs (debris).
fn correction(m_in: vec4<f32>, ok: bool) -> vec4<f32> {
    var l = vec4<f32>(1.0, 0.0, 0.0, 1.0);
    if (CORRECTED) {
        let m = dim_fixed(m_in);
        if (ok) {
            let q = 1.0 / (m.x * m.w - m.y * m.z);
            l = vec4<f32>(m.w * q, -m.y * q, -m.z * q, m.x * q);
        } else {
            atomicAdd(&ctl.fallback_now, 1u);
        }
    }
    return l;
}

// M with 1-D's unused yy entry neutral.
fn dim_fixed(m_in: vec4<f32>) -> vec4<f32> {
    var m = m_in;
    if (DIM == 1u) {
        m.w = 1.0;
    }
    return m;
}

// Both singular values of m at least sqrt(floor2) (kernel::well_conditioned).
fn conditioned(m: vec4<f32>, floor2: f32) -> bool {
    let det = m.x * m.w - m.y * m.z;
    let f = dot(m, m);
    let disc = sqrt(max(f * f - 4.0 * det * det, 0.0));
    return 2.0 * det * det >= floor2 * (f + disc) && det != 0.0;
}

// The inverse the stored velocity gradient takes: the correction `l`, or
// where the hourglass control is on and the correction fell back, the
// least-squares fit's (CPU twin: kernel::fit_inverse).
fn fit_of(m_in: vec4<f32>, l: vec4<f32>) -> vec4<f32> {
    if (HG <= 0.0 || !CORRECTED) {
        return l;
    }
    let m = dim_fixed(m_in);
    if (conditioned(m, params.min_sv2)) {
        return l;
    }
    if (conditioned(m, FIT_MIN_SV2)) {
        let q = 1.0 / (m.x * m.w - m.y * m.z);
        return vec4<f32>(m.w * q, -m.y * q, -m.z * q, m.x * q);
    }
    let f = dot(m, m);
    if (f > 0.0) {
        return vec4<f32>(m.x, m.z, m.y, m.w) / f;
    }
    return vec4<f32>(0.0);
}

// Particle i's damage in the state evaluated, a failed one's while it has a
// void open (0 where nothing can fail or cavitate).
fn damage_of(i: u32) -> f32 {
    if (FAILURE || CAVITATION) {
        return damage_seen(hist_w[i]);
    }
    return 0.0;
}

// Outward normal and boundary flag (> 0 on the boundary) from the colour
// gradient and, in a body of revolution, the colour function it is taken
// relative to (CPU twin: cpu::kinematics::surface_measure). There the
// flag is the measure itself, which the contact's surface ramp reads
// (contact.wgsl, ramp_measure).
fn surface_of(gpsi: vec2<f32>, psi: f32, hi: f32) -> vec3<f32> {
    var normal = vec2<f32>(0.0);
    let glen = length(gpsi);
    if (glen > 0.0) {
        normal = gpsi / glen;
    }
    var measure = hi * glen;
    if (AXI) {
        measure /= psi;
    }
    var boundary = 0.0;
    if (measure > params.boundary_threshold) {
        boundary = 1.0;
        if (AXI) {
            boundary = measure;
        }
    }
    return vec3<f32>(normal, boundary);
}

// Whether the pairs of particle i, of deviatoric stress `si`, take only
// the artificial stress's heat (ART_FLOW; CPU twin: Model::art_heats):
// with ART_BY_BODY where its body can yield, else where it flows
// plastically: it has plastic strain where the state carries it, else its
// stress is on the yield surface.
fn flows(i: u32, body: Body, si: vec4<f32>) -> bool {
    if (!ART_FLOW) {
        return false;
    }
    if (ART_BY_BODY) {
        return body.elastic == 0u && body.rigid == 0u;
    }
    if (HISTORY) {
        return hist_w[i].x > 0.0;
    }
    return body.elastic == 0u && von_mises(si) >= (1.0 - YIELD_TOL) * body.y0;
}

// Equation of state at (mu, e, s) with damage `d`: sigma/rho^2 (tension
// positive) and the sound speed into sr2c, negative where the particle
// flows (ART_FLOW).
// In a body of revolution the momentum sums take sigma/(eta rho), eta =
// 2 pi r rho (the divergence of 2 pi r sigma per unit eta), and the hoop
// stress's acceleration sigma_tt / (r rho) goes to `hoop` (CPU twin:
// cpu::kinematics::stress_point).
// `ri` is the particle's radius (KinSums).
// A debris particle (`debris`, its correction fell back) carries no
// deviatoric stress and no tension (CPU twin: cpu::kinematics::debris_point).
fn stress_point(i: u32, ri: f32, body: Body, mu: f32, e: f32, si: vec4<f32>, d: f32, debris: bool) {
    var p = pressure_of(body, mu, e, d);
    var c = sound_speed_of(body, mu, e, d);
    var sd = si;
    if (debris) {
        p = max(eos_pressure(body, mu, e), 0.0);
        c = speed_with_shear(body, mu, e, 0.0);
        sd = vec4<f32>(0.0);
    }
    let sig = vec4<f32>(sd.x - p, sd.y - p, sd.z, sd.w - p);
    let rho = body.rho0 * (1.0 + mu);
    if (flows(i, body, si)) {
        c = -c;
    }
    if (AXI) {
        sr2c[i] = vec4<f32>(sig.xyz / (rho * (circumference(ri) * rho)), c);
        hoop[i] = sig.w / (ri * rho);
        return;
    }
    sr2c[i] = vec4<f32>(sig.xyz / (rho * rho), c);
}

// The hoop strain rate v_r / r of a particle at radius `ri` and velocity
// `vi` (0 in plane strain).
fn hoop_rate(ri: f32, vi: vec2<f32>) -> f32 {
    if (!AXI) {
        return 0.0;
    }
    return vi.x / ri;
}

// The density rate d mu/dt at mu from the velocity gradient, with a body of
// revolution's hoop strain rate `d_tt`: the CPU's eta = 2 pi r rho follows
// the plane's continuity, rho itself takes the hoop rate too.
fn density_rate(mu: f32, gv: vec4<f32>, d_tt: f32) -> f32 {
    return (1.0 + mu) * density_log_rate(gv, d_tt);
}

// d(ln rho)/dt = -tr(grad v) (with the hoop strain rate in a body of
// revolution).
fn density_log_rate(gv: vec4<f32>, d_tt: f32) -> f32 {
    if (AXI) {
        return -(gv.x + gv.w + d_tt);
    }
    return -(gv.x + gv.w);
}

// The leapfrog's density over a step at a constant strain rate, exact:
// rho_{n+1} = rho_n exp(x), x = dt d(ln rho)/dt, as mu_{n+1} = mu_n +
// (1 + mu_n) expm1(x) (|x| is a few 1e-4 at most: the series' next term is
// below f32's rounding). CPU twin: cpu::leapfrog::density_after.
fn density_after(mu: f32, x: f32) -> f32 {
    return mu + (1.0 + mu) * (x + x * x * (0.5 + x * (1.0 / 6.0)));
}

// The deviatoric stress rate (`stress_rate`), with the hoop strain rate in
// a body of revolution.
fn deviator_rate(g: f32, si: vec4<f32>, gv: vec4<f32>, d_tt: f32) -> vec4<f32> {
    let rate = stress_rate(g, si, gv);
    if (AXI) {
        return with_hoop(g, rate, d_tt);
    }
    return rate;
}

// Velocity gradient with the corrected kernel gradient (docs/method.md §6):
// gsum L^T, in the order of math::Mat2::mul_transpose.
fn velocity_gradient(gsum: vec4<f32>, l: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        gsum.x * l.x + gsum.y * l.y,
        gsum.x * l.z + gsum.y * l.w,
        gsum.z * l.x + gsum.w * l.y,
        gsum.z * l.z + gsum.w * l.w,
    );
}

// The velocity gradient `g` taken at positions `c v` ahead of where it is
// wanted, mapped back there: (I - c g)^-1 g = (g - c det g I) / det(I - c g),
// det(I - c g) = 1 - c tr g + c^2 det g; `g` itself where that is not
// positive (the motion would have folded the neighbourhood). CPU twin:
// Mat2::gradient_behind.
fn gradient_behind(g: vec4<f32>, c: f32) -> vec4<f32> {
    let cd = c * (g.x * g.w - g.y * g.z);
    let den = 1.0 - c * (g.x + g.w) + c * cd;
    if (!(den > 0.0)) {
        return g;
    }
    let r = 1.0 / den;
    return vec4<f32>((g.x - cd) * r, g.y * r, g.z * r, (g.w - cd) * r);
}

// Jaumann-rate hypoelastic deviatoric stress rate, plane strain.
fn stress_rate(g: f32, si: vec4<f32>, gv: vec4<f32>) -> vec4<f32> {
    let tr = gv.x + gv.w;
    let exy = 0.5 * (gv.y + gv.z);
    let w = 0.5 * (gv.y - gv.z);
    let tr3 = tr / 3.0;
    return vec4<f32>(
        2.0 * g * (gv.x - tr3) + 2.0 * w * si.z,
        2.0 * g * (gv.w - tr3) - 2.0 * w * si.z,
        2.0 * g * exy + w * (si.y - si.x),
        -2.0 * g * tr3,
    );
}
