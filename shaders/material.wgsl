// The material laws shared by every stage (the host appends this file to
// common.wgsl after kernel.wgsl): the equation of state, damage and the
// failed particle's stress, sound speeds, von Mises and the perfectly
// plastic return.

// The pressure of a body's equation of state, eos_pressure(b, mu, e),
// its dp/drho and its zero-pressure mu come from the registry (shaders/eos/,
// gpu::shaders::eos_laws) with mu = rho/rho0 - 1.

// A failed particle's damage (physics::strength::FAILED).
const FAILED: f32 = 1.0;

// A particle's failure time while it is intact, and while it is intact
// with a void open (physics::strength::INTACT, VOID_OPEN).
const INTACT: f32 = -1.0;
const VOID_OPEN: f32 = -2.0;
// The pressure past which a void closes, a fraction of the cavitation
// pressure (physics::strength::VOID_CLOSES).
const VOID_CLOSES: f32 = 1e-3;

// The damage a particle with history `h` carries its stress with: a
// failed one's while it has a void open (CPU twin: State::damage_of).
fn damage_seen(h: vec4<f32>) -> f32 {
    if (CAVITATION && h.w == VOID_OPEN) {
        return FAILED;
    }
    return h.z;
}

// Whether a particle with damage `d` has failed (or, read through
// `damage_seen`, has a void open): the one test, false where nothing can
// fail or cavitate (physics::strength::failed).
fn failed(d: f32) -> bool {
    return (FAILURE || CAVITATION) && d >= FAILED;
}

// The pressure of a particle with damage `d`: a failed one carries no
// tension (MaterialModel::pressure_of).
fn pressure_of(b: Body, mu: f32, e: f32, d: f32) -> f32 {
    let p = eos_pressure(b, mu, e);
    if (failed(d)) {
        return max(p, 0.0);
    }
    return p;
}

// The sound speed of a particle with damage `d`: a failed one has no
// shear stiffness (MaterialModel::sound_speed_of).
fn sound_speed_of(b: Body, mu: f32, e: f32, d: f32) -> f32 {
    if (failed(d)) {
        return speed_with_shear(b, mu, e, 0.0);
    }
    return speed_with_shear(b, mu, e, b.g);
}

// Longitudinal sound speed with shear modulus `g`, bulk part never below K
// (as the CPU path).
fn speed_with_shear(b: Body, mu: f32, e: f32, g: f32) -> f32 {
    let dpdrho = eos_dpdrho(b, mu, e);
    let rho = b.rho0 * (1.0 + mu);
    return sqrt((rho * dpdrho + 4.0 * g / 3.0) / rho);
}

// Symmetric in-plane tensors are vec4 (xx, yy, xy, zz).
fn sym_mul(t: vec4<f32>, g: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(t.x * g.x + t.z * g.y, t.z * g.x + t.y * g.y);
}

fn von_mises(s: vec4<f32>) -> f32 {
    return sqrt(1.5 * (s.x * s.x + s.y * s.y + s.w * s.w + 2.0 * s.z * s.z));
}

// Perfect plasticity, radial return (docs/method.md §6), on an updated
// deviatoric stress.
// With a plastic history the trial stress is left as it is: the strength
// update returns it (strength.wgsl).
fn plastic_return(sn: vec4<f32>, b: Body) -> vec4<f32> {
    if (PLASTIC && !HISTORY && b.elastic == 0u) {
        let j = von_mises(sn);
        if (j > b.y0) {
            return sn * (b.y0 / j);
        }
    }
    return sn;
}
