// Shared declarations of every sphcontact compute shader. The host prepends
// this file, kernel.wgsl and material.wgsl to each stage file before
// compiling (WGSL has no includes).
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
// A pair takes the artificial stress only while its work is heat
// (tension::heat_share).
override ART_HEAT: bool = false;
// physics::tension::HEAT_SPEED.
override HEAT_SPEED: f32 = 0.01;
// A pair with a particle that flows plastically (`work = "plastic"`,
// Model::flowing) or, with ART_BY_BODY, of a body that can yield (`work =
// "yielding"`, Model::yields) takes the artificial stress as ART_HEAT
// does; the kinematics pass marks such a particle by the sign of its
// sound speed in sr2c.w (negative: heats).
override ART_FLOW: bool = false;
override ART_BY_BODY: bool = false;
// model::YIELD_TOL.
override YIELD_TOL: f32 = 1e-5;
// Limited reconstruction of the velocity jump in the viscosity (the forces pass reads
// the velocity gradient the kinematics pass stores).
override RECON: bool = false;
// ... at pairs with a surface particle too (`reconstruct_surfaces`).
override RECON_SURF: bool = false;
// The variational stress terms (`stress_form`, docs/method.md §4); else
// the paper's eq. 6.
override VARIATIONAL: bool = true;
// The viscosity acts on receding pairs too (`form = "riemann"`).
override RELEASE: bool = false;
// A body force per unit mass on the deformable particles
// (`[simulation] gravity`, Model::gravity), added where their velocities
// are kicked; none (false) compiles it out.
override GRAVITY: bool = false;
override GX: f32 = 0.0;
override GY: f32 = 0.0;
// Clamped and driven regions (`[[bodies.constraints]]`, Model::held): a
// held particle's held components move at its region's velocity (`hold`);
// NHELD regions in `held`. None (false) compiles them out.
override HELD: bool = false;
override NHELD: u32 = 0u;
// Coulomb friction (`[contact] friction`, Model::rubs; docs/method.md
// §8.6): the contact's rub passes and each particle's elastic slip
// (contact.wgsl, `slip`). None (false) compiles them out.
override RUB: bool = false;
// The hourglass control's coefficient (docs/method.md, "Hourglass
// control"), 0 off; it also reads the stored velocity gradient.
override HG: f32 = 0.0;
// The dispersion correction's theta (docs/method.md, "The dispersion
// correction"; dispersion.wgsl), 0 off. The midpoint rule only.
override DISP: f32 = 0.0;
override WG: u32 = 128u;
// Whether some artificial term books heat (Model::dissipates): the forces
// pass then sums the ledger's artificial dissipation (forces.wgsl, dheat).
override DISS: bool = false;
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
// The hourglass control of a leapfrog step's force passes sees
// v_{n+1/2} (vhalf, gradh), not the predicted velocity: a damping at the
// predicted velocity is stable only to gamma dt < 1, at v_{n+1/2} to 2
// (docs/method.md, "Hourglass control"). CPU twin: Kinematics::hv.
override HG_HALF: bool = HG > 0.0 && LEAP >= 2u;
// The state carries a plastic history (physics::strength): per particle
// (eps_p, T - T_room, D, failure time) in `hist`; the radial return is the
// strength update's (strength.wgsl).
override HISTORY: bool = false;
// Some material can fail (a damage law or a spall pressure): a failed
// particle carries no tension, has the bulk sound speed, no lower density
// bound and no artificial stress.
override FAILURE: bool = false;
// Some material cavitates (MaterialModel::cavitation): the stress update
// tests the EOS pressure against its cavitation pressure.
override CAVITATION: bool = false;
// The strength laws some deformable body uses, a bit `1 << id` each
// (physics::laws; strength.wgsl's dispatch compiles the others out).
override STRENGTH_LAWS: u32 = 0u;
// The damage laws some deformable body uses, a bit `1 << id` each
// (physics::failure; strength.wgsl's dispatch compiles the others out);
// every one where the host does not say.
override FAILURE_LAWS: u32 = 0xffffffffu;
// The equations of state some body uses, a bit `1 << id` each
// (physics::eos; the dispatch compiles the others out); every one where
// the host does not say.
override EOS_LAWS: u32 = 0xffffffffu;
// The strength or damage laws read the equivalent strain rate.
override STRAIN_RATE: bool = false;
// A body of revolution (docs/method.md §12): x is the radius r, y the
// axis z. The state keeps the density itself (mu); the kernel sums weigh
// neighbours by their ring's mass over eta_i = 2 pi r_i rho_i (kinematics)
// and by their areas m/eta (colour gradient, viscosity, close-pair gate),
// and a particle within reach of the axis adds its neighbours' mirror
// images across it (and its own) to its sums (`image_pair`).
override AXI: bool = false;
// The symmetry planes (`[[symmetry]]`, docs/method.md §13): the
// coordinates they reverse, bit 0 x and bit 1 y (0: none; 3: a quadrant),
// at `params.plane_x` and `params.plane_y`. A particle within reach of one
// meets its neighbours' images across it (and its own), as at the axis;
// with two lines (AXI and a plane, or two planes), across each and across
// both (`image_flip`). ONPLANE: some particle lies on a plane, with half
// its mass (a quarter on two: `plane_share`); it moves along it
// (`along_plane`).
override PLANE: u32 = 0u;
override ONPLANE: bool = false;
// Supports that follow the deformation (docs/method.md, "Supports that
// follow the deformation"): each particle's metric Q in `metric`, a pair's
// kernel in their mean metric; the surface set and the contact's normals
// keep the round supports of the bodies' h. ADAPT_ROWS is the most rows
// (cells either side) a walk's stencil reaches.
override ADAPT: bool = false;
override ADAPT_ROWS: u32 = 2u;
// The band within which supports stay round (Model::band), its factors
// for drawn-out (BAND) and squeezed (BAND_SQ) semi-axes: both 1, `metric`
// holds the supports themselves; else it holds the carried ellipses,
// whose supports `metric_banded` gives.
override BAND: f32 = 1.0;
override BAND_SQ: f32 = 1.0;

// Whether there is no band (`metric` holds the supports).
fn no_band() -> bool {
    return BAND == 1.0 && BAND_SQ == 1.0;
}
// Supports carried with their own copy of the step's velocity gradient
// (`lgrad`); off where the viscosity's (`gradv`) is that gradient
// (Model::kept_gradient_is_the_steps) and the advance reads it instead.
override LGRAD: bool = true;

// The copy holds dt l as four half floats (8 bytes a particle, not 16),
// scaled by 2^16 so that their normal range spans |dt l| from 1e-9 to
// 0.99: a component's relative error is at most 2^-11 (rounded to nearest,
// ties to even), and where |dt l| < 1e-9 it is flushed to zero, an error
// below the f32 rounding of the carry itself (docs/implementation.md, "f32
// with a precision plan"). Written with integer operations (WGSL's
// pack2x16float needs a capability some adapters lack, and may round
// either way). A step cannot strain a particle by 99 % (its CFL step);
// the clamp keeps the half finite if one did.
const DTL_SCALE: f32 = 65536.0;
const DTL_MAX: f32 = 64880.0;

// A half's bits from an f32 in its normal range (or below it: zero).
fn half_bits(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    let sign = (b >> 16u) & 0x8000u;
    let a = b & 0x7fffffffu;
    // 2^-14, the smallest normal half.
    if (a < 0x38800000u) {
        return sign;
    }
    let r = a + 0xfffu + ((a >> 13u) & 1u);
    return (sign | ((r >> 13u) - (112u << 10u))) & 0xffffu;
}

fn half_value(h: u32) -> f32 {
    let sign = (h & 0x8000u) << 16u;
    let a = h & 0x7fffu;
    if (a == 0u) {
        return bitcast<f32>(sign);
    }
    return bitcast<f32>(sign | ((a + (112u << 10u)) << 13u));
}

fn pack_step_gradient(l: vec4<f32>, dt: f32) -> vec2<u32> {
    let s = clamp(l * (dt * DTL_SCALE), vec4<f32>(-DTL_MAX), vec4<f32>(DTL_MAX));
    return vec2<u32>(half_bits(s.x) | (half_bits(s.y) << 16u), half_bits(s.z) | (half_bits(s.w) << 16u));
}

fn unpack_step_gradient(p: vec2<u32>) -> vec4<f32> {
    let h = vec4<f32>(
        half_value(p.x & 0xffffu),
        half_value(p.x >> 16u),
        half_value(p.y & 0xffffu),
        half_value(p.y >> 16u),
    );
    return h * (1.0 / DTL_SCALE);
}

const NONE: u32 = 0xffffffffu;
const BIG: f32 = 3.0e38;
const PI: f32 = 3.14159265358979;

// Run-wide constants (mirrored by `gpu::layout::Params`).
// Why a step failed: Control.fail_code is the particle's id times 8 plus
// one of these (its twin: gpu::fail, which a test holds to these values).
// The time step's and the energy guard's name no particle; a list of
// boundary particles more than three quarters full (kinematics.wgsl,
// list_surface) is no failure: the host makes it longer and the run goes on.
const FAIL_POSITION: u32 = 0u;
const FAIL_VELOCITY: u32 = 1u;
const FAIL_ENERGY: u32 = 2u;
const FAIL_DENSITY: u32 = 3u;
const FAIL_TIME_STEP: u32 = 4u;
const FAIL_DOMAIN: u32 = 5u;
const FAIL_ENERGY_GUARD: u32 = 6u;
const FAIL_LIST_FULL: u32 = 7u;

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
    // The square of the smallest singular value the correction accepts.
    min_sv2: f32,
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
    // Bodies of revolution: the axis r = 0 in cells of the grid (a whole
    // number, so a radius is formed from a particle's cell exactly).
    axis_cell: f32,
    // The margin, in cells, of a walk's reach where supports adapt.
    reach_margin: f32,
    // The energy guard's slot of the internal energy held below zero.
    energy_owed: u32,
    // The longest step the penalty spring allows (Model::contact_dt;
    // the largest f32 without contact).
    contact_dt: f32,
    // The symmetry planes (PLANE) in cells of the grid: the one reversing
    // x at x = plane_x, the one reversing y at y = plane_y (whole
    // numbers, as `axis_cell`).
    plane_x: f32,
    plane_y: f32,
    pad1: u32,
    pad2: u32,
}

// Per-body constants (mirrored by `gpu::layout::BodyGpu`).
struct Body {
    rho0: f32,
    k: f32,
    // The equation of state's two constants (physics::eos::PressureLaw::
    // device).
    eos0: f32,
    eos1: f32,
    g: f32,
    y0: f32,
    z: f32,
    // Constrained modulus M = K + 4G/3 (the penalty spring's layers).
    modulus: f32,
    spacing: f32,
    h: f32,
    rigid: u32,
    // The equation of state's number (physics::eos::Eos::device_id).
    eos: u32,
    elastic: u32,
    // The fewest same-body neighbours a particle keeps its correction
    // with (model::BodyInfo::debris_neighbours).
    debris_n: u32,
    // The hourglass control's coefficient on the body's families (HG is
    // the largest), and 1 where its particles carry the artificial stress.
    hg: f32,
    art: u32,
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
    // Supports that adapt: the largest major semi-axis of a step's
    // supports, as the bits of a positive f32, by the step's parity: a
    // step's walks read their own (`step_h_top`), its advance raises the
    // next step's with each particle's new support (advance.wgsl).
    h_top: array<atomic<u32>, 2>,
    // Supports that adapt within a band: nonzero where one of a step's
    // supports is not round, by the step's parity as `h_top`.
    out_of_band: array<atomic<u32>, 2>,
}

// The largest major semi-axis of this step's supports.
fn step_h_top() -> f32 {
    return bitcast<f32>(atomicLoad(&ctl.h_top[ctl.step & 1u]));
}

// Whether this step's SPH sums take the supports' metrics: where they
// adapt and (within a band) one of them is not round. While every one is
// round the walks are the round kernel's (CPU twin: State::round_supports).
fn adapting() -> bool {
    if (!ADAPT) {
        return false;
    }
    if (no_band()) {
        return true;
    }
    return atomicLoad(&ctl.out_of_band[ctl.step & 1u]) != 0u;
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

// The midpoint rule's compatible energy (docs/method.md §9; CPU twin:
// cpu::advance::compatible_energy): the specific internal energy to book
// with a kick of the base velocity from w0 to w1 by rates evaluated at the
// midpoint velocity vm. Booked at each of a step's kicks (the forces, the
// contact's pass 2, the spread), whose terms sum to the twin's over the
// whole step: -(v_{n+1} - v_n).(vbar - vm), vbar = (v_n + v_{n+1})/2.
fn compatible_energy(w0: vec2<f32>, w1: vec2<f32>, vm: vec2<f32>) -> f32 {
    return -dot(w1 - w0, 0.5 * (w0 + w1) - vm);
}

// The weight c of the leapfrog's predicted velocity v_n + c dt a_n (the
// viscosity's and the dashpot's): 1 / (1 + 4 alpha c_L dt / h) with the
// body's placed h and its material's c_L; 1 without viscosity. CPU twin:
// physics::viscosity::predictor_weight (PREDICTOR_RATE).
const PREDICTOR_RATE: f32 = 4.0;

fn predictor_weight(c_l: f32, h: f32, dt: f32) -> f32 {
    return 1.0 / (1.0 + PREDICTOR_RATE * params.alpha * c_l * dt / h);
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

// The circumference 2 pi r of the circle at radius r: what a point of a
// body of revolution's r-z plane stands for (crate::math::circumference).
fn circumference(r: f32) -> f32 {
    return 2.0 * PI * r;
}

// Mirror images (`image_flip`: bit 0 reverses x, bit 1 y; the axis of a
// body of revolution is x's): of a vector, of a symmetric tensor (xx, yy,
// xy, zz) and of a 2x2 matrix (xx, xy, yx, yy), P T P with P diagonal.
// Reversing both coordinates keeps a tensor's off-diagonal entries.
fn mirror_vec(f: u32, a: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(select(a.x, -a.x, (f & 1u) != 0u), select(a.y, -a.y, (f & 2u) != 0u));
}

fn shears(f: u32) -> bool {
    return f == 1u || f == 2u;
}

fn mirror_sym(f: u32, t: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(t.x, t.y, select(t.z, -t.z, shears(f)), t.w);
}

fn mirror_mat(f: u32, m: vec4<f32>) -> vec4<f32> {
    if (!shears(f)) {
        return m;
    }
    return vec4<f32>(m.x, -m.y, -m.z, m.w);
}

// The deviatoric stress rate with a body of revolution's hoop strain rate
// d_tt = v_r / r added to the plane's (`stress_rate` with d_tt = 0): the
// trace takes it and s_tt, kept as zz, follows it (cpu::kinematics::with_hoop).
fn with_hoop(g: f32, ds: vec4<f32>, d_tt: f32) -> vec4<f32> {
    let third = d_tt / 3.0;
    return vec4<f32>(ds.x - 2.0 * g * third, ds.y - 2.0 * g * third, ds.z, ds.w + 4.0 * g * third);
}

// 2x2 matrices are vec4 (xx, xy, yx, yy).
fn mat_mul(m: vec4<f32>, g: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(m.x * g.x + m.y * g.y, m.z * g.x + m.w * g.y);
}

fn outer(a: vec2<f32>, b: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(a.x * b.x, a.x * b.y, a.y * b.x, a.y * b.y);
}

// The leapfrog's compatible energy: a half kick by a over h books its
// work at one end, the kinetic energy changes by it at the mean velocity
// (advance.wgsl books it, kinematics.wgsl's prediction takes it back;
// CPU twin: cpu::leapfrog::kick_energy).
fn kick_energy(a: vec2<f32>, h: f32) -> f32 {
    let k = a * h;
    return -0.5 * dot(k, k);
}

// A compensated sum (hi, lo) plus x.
fn two_sum(a: vec2<f32>, x: f32) -> vec2<f32> {
    let y = x + a.y;
    let t = a.x + y;
    return vec2<f32>(t, y - (t - a.x));
}

// The body force per unit mass (GRAVITY).
fn gravity() -> vec2<f32> {
    return vec2<f32>(GX, GY);
}

// The regions (HELD; gpu::make::make_held): NHELD entries of (held
// components, bit 0 x and bit 1 y; velocity x, y as f32 bits; 0), then
// each particle's region k + 1 (0: free) by original index.
@group(0) @binding(94) var<storage, read> held: array<u32>;

// A particle's word in `held`: its region (REGION_BITS) and, from bit
// ON_PLANES on, the symmetry planes it lies on (ONPLANE), as the
// coordinates they reverse (bit 0 x, bit 1 y).
const REGION_BITS: u32 = 0x3fffffffu;
const ON_PLANES: u32 = 30u;

// The planes particle i lies on (0: none).
fn planes_of(i: u32) -> u32 {
    if (!ONPLANE) {
        return 0u;
    }
    return held[4u * NHELD + pinfo[i].w] >> ON_PLANES;
}

// Particle i's share of itself on the modelled side of the symmetry planes
// (Model::share): 1/2 on a plane, 1/4 on two, 1 elsewhere.
fn plane_share(i: u32) -> f32 {
    if (!ONPLANE) {
        return 1.0;
    }
    return 1.0 / f32(1u << countOneBits(planes_of(i)));
}

// v of particle i without its components normal to the symmetry planes it
// lies on (CPU twin: Model::along_plane).
fn along_plane(i: u32, v: vec2<f32>) -> vec2<f32> {
    if (!ONPLANE) {
        return v;
    }
    let b = planes_of(i);
    return vec2<f32>(select(v.x, 0.0, (b & 1u) != 0u), select(v.y, 0.0, (b & 2u) != 0u));
}

// Particle i's region entry's start in `held`, or NONE where it is free.
fn region_at(i: u32) -> u32 {
    if (!HELD) {
        return NONE;
    }
    let k = held[4u * NHELD + pinfo[i].w] & REGION_BITS;
    if (k == 0u) {
        return NONE;
    }
    return 4u * (k - 1u);
}

// 1 in each component particle i's region holds, 0 in a free one.
fn held_mask(i: u32) -> vec2<f32> {
    let t = region_at(i);
    if (t == NONE) {
        return vec2<f32>(0.0);
    }
    let b = held[t];
    return vec2<f32>(f32(b & 1u), f32((b >> 1u) & 1u));
}

// v with particle i's held components at its region's velocity (CPU twin:
// Model::hold).
// A particle on a symmetry plane moves along it too.
fn hold(i: u32, v: vec2<f32>) -> vec2<f32> {
    let t = region_at(i);
    if (t == NONE) {
        return along_plane(i, v);
    }
    let b = held[t];
    return along_plane(i, vec2<f32>(
        select(v.x, bitcast<f32>(held[t + 1u]), (b & 1u) != 0u),
        select(v.y, bitcast<f32>(held[t + 2u]), (b & 2u) != 0u),
    ));
}

// The part of particle i's acceleration a that moves it: a less its held
// components, whose kinetic energy does not change (the leapfrog's
// compatible terms; CPU twin: Model::moving_part).
fn moving_part(i: u32, a: vec2<f32>) -> vec2<f32> {
    if (!HELD) {
        return along_plane(i, a);
    }
    return along_plane(i, a * (vec2<f32>(1.0) - held_mask(i)));
}
