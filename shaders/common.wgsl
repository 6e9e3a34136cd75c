// Shared declarations of every sphcontact compute shader. The host prepends
// this file to each stage file before compiling (WGSL has no includes).
//
// Precision plan (f32 on the device, see src/gpu/mod.rs): positions are kept
// as a reference cell (integer), an offset in that cell and a displacement u,
// and pair differences are formed part by part, so round-off scales with
// the pair distance, not with the coordinate. Density is kept as mu = rho/rho0 - 1, the
// quantity the equation of state needs and the one a step changes. Time is a
// compensated (hi, lo) pair.

// Scene switches: physics a scene does not use is compiled out.
override DIM: u32 = 2u;
override CONTACT: bool = false;
override CORRECTED: bool = true;
override PLASTIC: bool = false;
override ART_STRESS: bool = false;
// The artificial stress on close pairs only (forces::close_gate).
override ART_CLOSE: bool = false;
// Some particle's kappa^2 is below 1 (the kappa buffer exists).
override ART_KAPPA: bool = false;
// Limited reconstruction of the velocity jump in the viscosity (the forces pass reads
// the velocity gradient the kinematics pass stores).
override RECON: bool = false;
override WG: u32 = 64u;
// The energy guard (Model::guards_energy) runs in the reductions.
override GUARD: bool = false;
// Whether the scene has a rigid body: only then does a contact pass hand
// heat to its partners (a rigid particle cannot keep it), and the
// leapfrog's booking needs its second pass (contact.wgsl, pass1_at).
override RIGID: bool = false;
// Which evaluation of the midpoint step a pass belongs to (docs/method.md §9).
// At the base state (false) the kinematics and forces passes and the contact store their
// particle's rates in the midpoint buffers, which advance_half then turns
// into the midpoint state in place. At the midpoint (true) they add
// dt x rate to the base state in place: only particle i reads or writes its
// own base state during that evaluation (the neighbours' are read from the
// midpoint buffers), so no rate buffer is needed.
override MID: bool = false;
// The leapfrog (kick-drift-kick, one evaluation a step; gpu::Integrator):
// 0 not the leapfrog; 1 its first evaluation, at the initial state, whose
// rates it carries into the first step; 2 the step's evaluation at n+1
// (kinematics, momentum and contact forces at the predicted velocity
// vstar); 3 the step's booking at v_{n+1} (the energy sums and the
// contact's heat). CPU twin: cpu::CpuSolver::leapfrog.
override LEAP: u32 = 0u;
// The state carries a plastic history (physics::strength): per particle
// (eps_p, T - T_room, D, failure time) in `hist`; the radial return is the
// strength update's (strength.wgsl).
override HISTORY: bool = false;
// Some material can fail (a damage law or a spall pressure): a failed
// particle carries no tension, has the bulk sound speed, no lower density
// bound and no artificial stress.
override FAILURE: bool = false;
// The strength or damage laws read the equivalent strain rate.
override STRAIN_RATE: bool = false;

const NONE: u32 = 0xffffffffu;
const BIG: f32 = 3.0e38;
const PI: f32 = 3.14159265358979;

// Run-wide constants (mirrored by `gpu::layout::Params`).
struct Params {
    n: u32,
    nbodies: u32,
    buckets: u32,
    row_stride: u32,
    // The energy guard's growth factor and floor (Model::guards_energy).
    energy_growth: f32,
    energy_floor: f32,
    inv_cell: f32,
    alpha: f32,
    beta: f32,
    cfl: f32,
    fixed_dt: f32,
    boundary_threshold: f32,
    as_eps: f32,
    as_n: f32,
    end_hi: f32,
    end_lo: f32,
    ring_len: u32,
    ring_width: u32,
    // Entries of the leapfrog contact's list of boundary particles
    // (contact.wgsl; 0 without one).
    surf_cap: u32,
    nprobes: u32,
    cell: f32,
    red_groups: u32,
    min_det: f32,
    // A particle's support radius in cells, with a margin for f32 rounding
    // (`row_span`).
    reach: f32,
    // The domain relative to the grid origin: lower x, lower y, upper x, upper y.
    domain: vec4<f32>,
    // The energy guard (Model::guards_energy): the ring-row slots of the
    // kinetic, internal and stored penalty energy (stored: NONE without
    // contact).
    energy_kin: u32,
    energy_int: u32,
    energy_stored: u32,
    // The most workgroups of a dispatch along x (the contact's indirect
    // dispatch has at most this many).
    surf_groups: u32,
}

// Per-body constants (mirrored by `gpu::layout::BodyGpu`).
struct Body {
    rho0: f32,
    k: f32,
    s: f32,
    gamma0: f32,
    g: f32,
    y0: f32,
    z: f32,
    // Constrained modulus M = K + 4G/3 (the penalty spring's layers).
    modulus: f32,
    spacing: f32,
    h: f32,
    rigid: u32,
    linear: u32,
    elastic: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// Time and run status (mirrored by `gpu::layout::Control`).
struct Control {
    t_hi: f32,
    t_lo: f32,
    dt: f32,
    dt0: f32,
    step: u32,
    zero_steps: u32,
    fail_step: atomic<u32>,
    fail_code: atomic<u32>,
    fallback_now: atomic<u32>,
    fallback_max: u32,
    multi_partner: atomic<u32>,
    // The energy guard's limit: negative until the first state sets it.
    energy_limit: f32,
    // The contact list's peak length past three quarters full
    // (kinematics.wgsl, list_surface).
    list_peak: atomic<u32>,
}

// A pass of a zero-length step (past the stop, or after a failure) that
// has nothing to do: the leapfrog step's, and the midpoint evaluation's,
// whose inputs advance_half left as they were and whose results nothing
// reads. (The midpoint rule's evaluation at the base state still runs: the
// reductions observe the state through it.)
fn zero_length_pass() -> bool {
    return (MID || LEAP >= 2u) && ctl.dt == 0.0;
}

// Where boundary particle i, at place `place` on the list of boundary
// particles (its nbo.w, kinematics.wgsl), has its contact area: the
// leapfrog carries the area a particle (its next step's reductions read
// it); the midpoint rule keeps it on the list.
fn area_index(i: u32, place: f32) -> u32 {
    if (LEAP == 0u) {
        return u32(place);
    }
    return i;
}

// Global invocation index of a 2-D dispatch of `WG`-wide workgroups
// (dispatches past 65,535 workgroups wrap into y).
fn flat_index(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return gid.x + gid.y * nwg.x * WG;
}

// Bindings every stage may read (an entry point binds only those it uses).
// Each stage file declares the rest with its own binding numbers; the host
// binds buffers by name.
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> bodies: array<Body>;
@group(0) @binding(2) var<storage, read_write> ctl: Control;
// Particle reference position (see `cand`), displacement, and
// (mass bits, surface offset bits, body, original index).
@group(0) @binding(3) var<storage, read> x0: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> u: array<vec2<f32>>;
@group(0) @binding(8) var<storage, read> pinfo: array<vec4<u32>>;
// The cell list (written by neighbours.wgsl): the start of each bucket in the
// sorted list, the sorted list of particles. A particle's cell is not
// stored: `current_cell` recomputes it from the reference cell and the
// displacement a pair reads anyway, with the same arithmetic the build used.
@group(0) @binding(10) var<storage, read> bstart: array<u32>;
@group(0) @binding(11) var<storage, read> blist: array<u32>;

// Cubic B-spline (docs/method.md §3).
fn kernel_alpha(h: f32) -> f32 {
    if (DIM == 1u) {
        return 2.0 / (3.0 * h);
    }
    return 10.0 / (7.0 * PI * h * h);
}

// The 2-D kernel's integral along a line through its centre, 15/(7 pi h)
// (CPU twin: physics::kernel::line_integral_2d).
fn line_integral(h: f32) -> f32 {
    return 15.0 / (7.0 * PI * h);
}

fn kernel_w(r: f32, h: f32) -> f32 {
    let q = r / h;
    var f = 0.0;
    if (q < 1.0) {
        f = 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    } else if (q < 2.0) {
        let t = 2.0 - q;
        f = 0.25 * t * t * t;
    }
    return kernel_alpha(h) * f;
}

// The cubic spline's shape inside the support (W = alpha f).
fn kernel_shape(q: f32) -> f32 {
    if (q < 1.0) {
        return 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    }
    let t = max(2.0 - q, 0.0);
    return 0.25 * t * t * t;
}

// The artificial stress's pair weight f^n, f = W(r)/W(dp) at h (the
// normalisation cancels); n = 4, the usual choice, by two squarings
// (pow is exp2(n log2 f), undefined at f = 0).
fn art_weight(r: f32, dp: f32, h: f32) -> f32 {
    let f = kernel_shape(r / h) / kernel_shape(dp / h);
    if (params.as_n == 4.0) {
        let f2 = f * f;
        return f2 * f2;
    }
    return pow(f, params.as_n);
}

// The artificial stress R from t = sigma/rho^2 (xyz): -eps times the
// tensile principal part of t, which is sigma's over rho^2. Without the
// angle: both tensile, -eps t; one (a > 0 >= b), -eps a (t - b I)/(a - b);
// none, zero (the CPU's forces::artificial_stress).
fn art_of(t: vec4<f32>) -> vec4<f32> {
    let m = 0.5 * (t.x + t.y);
    let d = 0.5 * (t.x - t.y);
    let rad = sqrt(d * d + t.z * t.z);
    let a = m + rad;
    let b = m - rad;
    if (b > 0.0) {
        return vec4<f32>(-params.as_eps * t.xyz, 0.0);
    }
    if (a > 0.0) {
        let s = -params.as_eps * a / (a - b);
        return vec4<f32>(s * (t.x - b), s * (t.y - b), s * t.z, 0.0);
    }
    return vec4<f32>(0.0);
}

// The close-pair gate (forces::close_gate): 0 at or beyond the local
// spacing s = kappa vol^(1/d), 1 from CLOSE_FULL s in, linear in (r/s)^2.
const CLOSE_FULL: f32 = 0.95;
fn close_gate(r2: f32, vol: f32, k2: f32) -> f32 {
    var s2 = vol * k2;
    if (DIM == 1u) {
        s2 = vol * vol * k2;
    }
    return clamp((1.0 - r2 / s2) / (1.0 - CLOSE_FULL * CLOSE_FULL), 0.0, 1.0);
}

fn kernel_dw(r: f32, h: f32) -> f32 {
    let q = r / h;
    var f = 0.0;
    if (q < 1.0) {
        f = -3.0 * q + 2.25 * q * q;
    } else if (q < 2.0) {
        let t = 2.0 - q;
        f = -0.75 * t * t;
    }
    return kernel_alpha(h) * f / h;
}

// The Hessian of W at distance r as (s, t), grad grad W = s I + t d d^T for
// the separation d: s = (dW/dr)/r, t = (ds/dr)/r (zero at r = 0 and beyond
// the support). CPU twin: physics::kernel::hessian.
fn kernel_hess(r: f32, h: f32) -> vec2<f32> {
    let q = r / h;
    if (q <= 0.0 || q >= 2.0) {
        return vec2<f32>(0.0);
    }
    let a = kernel_alpha(h) / (h * h);
    if (q < 1.0) {
        return vec2<f32>(a * (-3.0 + 2.25 * q), a * 2.25 / (q * h * h));
    }
    let t = 2.0 - q;
    return vec2<f32>(a * (-0.75 * t * t / q), a * 0.75 * t * (2.0 + q) / (q * q * q * h * h));
}

// grad grad W of separation d, distance r, applied to b.
fn hess_times(d: vec2<f32>, r: f32, h: f32, b: vec2<f32>) -> vec2<f32> {
    let st = kernel_hess(r, h);
    return b * st.x + d * (st.y * dot(d, b));
}

// The left-hand perpendicular: a boundary normal's tangent.
fn perp(n: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(-n.y, n.x);
}

// Mie-Grüneisen or linear pressure (docs/method.md §6), from mu = rho/rho0 - 1.
fn eos_pressure(b: Body, mu: f32, e: f32) -> f32 {
    if (b.linear != 0u) {
        return b.k * mu;
    }
    var ph = b.k * mu;
    if (mu > 0.0) {
        let sm = b.s - 1.0;
        let b0 = b.k * (1.0 + 2.0 * sm);
        let c0 = b.k * (2.0 * sm + 3.0 * sm * sm);
        ph = mu * (b.k + mu * (b0 + mu * c0));
    }
    return (1.0 - 0.5 * b.gamma0 * mu) * ph + b.gamma0 * b.rho0 * (1.0 + mu) * e;
}

// A failed particle's damage (physics::strength::FAILED).
const FAILED: f32 = 1.0;

// Whether a particle with damage `d` has failed: the one test, false
// where nothing can fail (physics::strength::failed).
fn failed(d: f32) -> bool {
    return FAILURE && d >= FAILED;
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
    var dpdrho = b.k / b.rho0;
    if (b.linear == 0u && mu > 0.0) {
        let sm = b.s - 1.0;
        let b0 = b.k * (1.0 + 2.0 * sm);
        let c0 = b.k * (2.0 * sm + 3.0 * sm * sm);
        let ph = mu * (b.k + mu * (b0 + mu * c0));
        let dph = b.k + mu * (2.0 * b0 + 3.0 * mu * c0);
        let d = ((1.0 - 0.5 * b.gamma0 * mu) * dph - 0.5 * b.gamma0 * ph) / b.rho0 + b.gamma0 * e;
        dpdrho = max(dpdrho, d);
    }
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

// 2x2 matrices are vec4 (xx, xy, yx, yy).
fn mat_mul(m: vec4<f32>, g: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(m.x * g.x + m.y * g.y, m.z * g.x + m.w * g.y);
}

fn outer(a: vec2<f32>, b: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(a.x * b.x, a.x * b.y, a.y * b.x, a.y * b.y);
}

// Bucket of a cell in the hashed cell table: row-major keys modulo a power
// of two, so neighbouring cells of a row are neighbouring buckets and
// far-apart bodies need no large grid.
fn bucket_of(c: vec2<i32>) -> u32 {
    return (bitcast<u32>(c.x) + bitcast<u32>(c.y) * params.row_stride) & (params.buckets - 1u);
}

// Cells are a hair larger than the largest h, so a pair within 2 h_ij is at
// most REACH = 2 cells apart along each axis: a particle's candidates lie in
// the 5 x 5 cells around its own (5 cells in 1-D).
const REACH: i32 = 2;

// Where a particle is in the grid: its cell, and its place inside the cell
// in units of the cell, in [0, 1) along each axis. The cell list and every
// neighbour loop call this one function on the same state, so they agree
// on every particle's cell bit for bit (an add, a multiply and a floor:
// nothing a compiler may contract).
struct Home {
    cell: vec2<i32>,
    frac: vec2<f32>,
}

// `home` of a particle with reference `a` (its x0) and displacement `un`.
fn home_at(a: vec4<f32>, un: vec2<f32>) -> Home {
    return home_in(a, un, params.inv_cell);
}

fn home_in(a: vec4<f32>, un: vec2<f32>, inv_cell: f32) -> Home {
    let p = (a.zw + un) * inv_cell;
    let f = floor(p);
    return Home(vec2<i32>(a.xy) + vec2<i32>(f), p - f);
}

// The cell a particle is in now: its reference cell plus whole cells moved.
fn current_cell(i: u32) -> vec2<i32> {
    return home_at(x0[i], u[i]).cell;
}

// Rows of the stencil, bottom to top, always in this order (the order of
// every neighbour sum is fixed).
fn scan_rows() -> u32 {
    if (DIM == 1u) {
        return 1u;
    }
    return 5u;
}

// One row of a particle's stencil: the row `cy`, its columns `lo..=hi` (the
// cells its support reaches), and the range of the sorted particle list
// that holds their buckets. Row-major keys make a row's cells consecutive
// buckets, so the row is one contiguous range: a warp's lanes run five
// loops a walk, not nine or twenty-five. When the buckets wrap past the
// last, the range runs on past `n` into the list's start (`cand`).
// A bucket may also hold cells of other rows: callers keep only particles
// whose cell is in the span (`in_row`).
struct RowSpan {
    cy: i32,
    lo: i32,
    hi: i32,
    start: u32,
    end: u32,
}

fn row_span(hm: Home, row: u32) -> RowSpan {
    var dy = i32(row) - REACH;
    // The distance in cells from the particle to the row's band.
    var gap = 0.0;
    if (DIM == 1u) {
        dy = 0;
    } else if (dy > 0) {
        gap = f32(dy) - hm.frac.y;
    } else if (dy < 0) {
        gap = hm.frac.y - f32(dy + 1);
    }
    let cy = hm.cell.y + dy;
    if (gap >= params.reach) {
        return RowSpan(cy, 1, 0, 0u, 0u);
    }
    // The columns a disk of radius `reach` reaches in this row.
    let w = sqrt(params.reach * params.reach - gap * gap);
    let lo = max(-REACH, i32(floor(hm.frac.x - w)));
    let hi = min(REACH, i32(floor(hm.frac.x + w)));
    let b = bucket_of(vec2<i32>(hm.cell.x + lo, cy));
    let e = b + u32(hi - lo + 1);
    var end = 0u;
    if (e <= params.buckets) {
        end = bstart[e];
    } else {
        end = bstart[e - params.buckets] + params.n;
    }
    return RowSpan(cy, hm.cell.x + lo, hm.cell.x + hi, bstart[b], end);
}

// Whether cell `c` is one of the span's.
fn in_row(c: vec2<i32>, span: RowSpan) -> bool {
    return c.y == span.cy && c.x >= span.lo && c.x <= span.hi;
}

// A neighbour walk reads everything it can before its loop: on a software
// adapter (lavapipe) every read inside the loop, a uniform's too, is a
// scalar load for each lane, and these reads were most of a walk's cost.
//
// The run constants a walk's loop uses.
struct Consts {
    n: u32,
    cell: f32,
    inv_cell: f32,
}

fn consts() -> Consts {
    return Consts(params.n, params.cell, params.inv_cell);
}

// The walking particle: its index, reference, displacement and grid home.
struct Walker {
    i: u32,
    a: vec4<f32>,
    un: vec2<f32>,
    hm: Home,
}

fn walker(i: u32) -> Walker {
    let a = x0[i];
    let un = u[i];
    return Walker(i, a, un, home_at(a, un));
}

// Candidate j at place k of a row's range (a range that wraps past the
// last bucket runs on past `n`): its cell, and the pair difference
// d = x_i - x_j from one read of its position. x0 holds each particle's
// reference cell (integral, exact in f32) and its offset in that cell at
// the start, u the displacement since; the difference is formed part by
// part, so its round-off scales with the pair distance, not with the
// distance from the origin. (x_j - x_i is exactly -d: each part negates.)
struct Cand {
    j: u32,
    cell: vec2<i32>,
    d: vec2<f32>,
}

fn cand(w: Walker, k: u32, c: Consts) -> Cand {
    let j = sorted_at(k, c);
    let b = x0[j];
    let uj = u[j];
    let cell = home_in(b, uj, c.inv_cell).cell;
    return Cand(j, cell, pair_diff(w, b, uj, c));
}

// The particle at place k of the sorted list, run on past `n` where a row
// range wraps round the bucket table.
fn sorted_at(k: u32, c: Consts) -> u32 {
    return blist[select(k, k - c.n, k >= c.n)];
}

// x_i - x_j of the walker and a particle at reference cell and offset `b`
// and displacement `uj` (the precision plan: cells and offsets apart).
fn pair_diff(w: Walker, b: vec4<f32>, uj: vec2<f32>, c: Consts) -> vec2<f32> {
    return (w.a.xy - b.xy) * c.cell + (w.a.zw - b.zw) + (w.un - uj);
}

// An SPH pair (i, j), h_ij the mean of the bodies' h: separation x_i - x_j,
// distance, and grad_i W_ij (computed only inside the support, zero at zero
// distance); `inside` when the distance is below 2 h_ij.
struct Pair {
    d: vec2<f32>,
    dist: f32,
    hij: f32,
    gw: vec2<f32>,
    inside: bool,
}

// The SPH pair of walker `w` (particle i, body bi, smoothing length hi) and
// candidate `cd` of row `span` (body bj). `inside` is false when j is i,
// lies in a cell outside the span that shares a bucket, or (with contact
// on) belongs to another body: bodies then meet only through the contact
// force. Every SPH sum scans its neighbours through this filter.
fn body_pair(w: Walker, cd: Cand, bj: u32, span: RowSpan, hi: f32, bi: u32) -> Pair {
    if (cd.j == w.i || !in_row(cd.cell, span) || (CONTACT && bj != bi)) {
        return Pair(vec2<f32>(0.0), 0.0, 0.0, vec2<f32>(0.0), false);
    }
    return pair_at(cd.d, pair_h(hi, bj));
}

// h_ij of a pair with i's h `hi` and j of body `bj`. With contact on, SPH
// pairs are of one body: h_ij is h_i, the same bits as the mean, without
// the partner's body read.
fn pair_h(hi: f32, bj: u32) -> f32 {
    if (!CONTACT) {
        return 0.5 * (hi + bodies[bj].h);
    }
    return hi;
}

// The SPH pair of separation `d` and smoothing length `hij`.
fn pair_at(d: vec2<f32>, hij: f32) -> Pair {
    let dist = length(d);
    let inside = dist < 2.0 * hij;
    var gw = vec2<f32>(0.0);
    if (inside && dist > 0.0) {
        gw = d * (kernel_dw(dist, hij) / dist);
    }
    return Pair(d, dist, hij, gw, inside);
}

// The neighbour mask (leapfrog only, LEAP != 0): the kinematic walk
// (kinematics.wgsl) numbers a particle's candidates in walk order, rows bottom
// to top and each row's range in order, and sets bit o of the mask when
// candidate o is an SPH pair (`body_pair` inside); the walks after it at
// the same positions and cell list (forces.wgsl) visit only those, in the
// same order, so every sum keeps its order and its bits. Ordinals 0..62
// fit; a particle with more candidates sets MASK_FULL and is walked in
// full.
const MASK_FULL: u32 = 0x80000000u;
const MASK_BITS: u32 = 63u;

fn mask_set(m: vec2<u32>, o: u32) -> vec2<u32> {
    if (o < 32u) {
        return vec2<u32>(m.x | (1u << o), m.y);
    }
    return vec2<u32>(m.x, m.y | (1u << (o - 32u)));
}

// Where ordinal o of a walk lies in the sorted list: o plus the offset of
// its row (`start` of the row less the ordinals before it); rows past the
// last reached have no ordinals.
struct RowMap {
    // The first ordinal of rows 1..4.
    first: vec4<u32>,
    // Each row's offset (wrapping u32 arithmetic).
    off0: u32,
    off: vec4<u32>,
}

fn row_map(hm: Home) -> RowMap {
    var first = vec4<u32>(0u);
    var off = vec4<u32>(0u);
    let s0 = row_span(hm, 0u);
    var o = s0.end - s0.start;
    for (var row = 1u; row < scan_rows(); row++) {
        let sp = row_span(hm, row);
        first[row - 1u] = o;
        off[row - 1u] = sp.start - o;
        o += sp.end - sp.start;
    }
    if (scan_rows() == 1u) {
        // 1-D: one row, every later row starts past the mask.
        first = vec4<u32>(64u);
    }
    return RowMap(first, s0.start, off);
}

// The place in the sorted list (run on past `n` where a range wraps, as
// `cand`) of ordinal o.
fn row_place(rm: RowMap, o: u32) -> u32 {
    var off = rm.off0;
    if (o >= rm.first.x) {
        off = rm.off.x;
    }
    if (o >= rm.first.y) {
        off = rm.off.y;
    }
    if (o >= rm.first.z) {
        off = rm.off.z;
    }
    if (o >= rm.first.w) {
        off = rm.off.w;
    }
    return o + off;
}

// Take the lowest set bit of the mask: its ordinal (64 when none is left).
fn mask_next(m: ptr<function, vec2<u32>>) -> u32 {
    let x = (*m).x;
    if (x != 0u) {
        (*m).x = x & (x - 1u);
        return countTrailingZeros(x);
    }
    let y = (*m).y;
    if (y != 0u) {
        (*m).y = y & (y - 1u);
        return 32u + countTrailingZeros(y);
    }
    return 64u;
}

// The pair difference d = x_i - x_j of the walker and particle j (as `cand`).
fn pair_d(w: Walker, j: u32, c: Consts) -> vec2<f32> {
    return pair_diff(w, x0[j], u[j], c);
}

// Position relative to the grid origin (output only). The host adds the
// origin in f64 (gpu::probes): far from the coordinate origin an absolute
// f32 position is coarse (7.6e-6 m near 100 m, 0.15 of a typical spacing),
// while this relative one keeps the f32 resolution of the bodies' own size.
fn position_rel(i: u32) -> vec2<f32> {
    let a = x0[i];
    return a.xy * params.cell + (a.zw + u[i]);
}
