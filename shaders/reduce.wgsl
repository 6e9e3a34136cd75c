// Reductions and bookkeeping, all in a fixed order (deterministic):
// the CFL step (docs/method.md §9) as a two-level minimum, the time and step
// counters, and the per-step observations the history is built from
// (body sums, contact statistics, particle probes) written into a ring the
// host reads back only when it needs rows.

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read> s: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read> nbo: array<vec4<f32>>;
@group(0) @binding(14) var<storage, read> sr2c: array<vec4<f32>>;
@group(0) @binding(19) var<storage, read> area: array<f32>;
@group(0) @binding(20) var<storage, read> cown: array<vec4<f32>>;
@group(0) @binding(24) var<storage, read> qheat: array<vec2<f32>>;
@group(0) @binding(25) var<storage, read_write> red: array<f32>;
@group(0) @binding(26) var<storage, read_write> ring: array<f32>;
// Particle probes: (entry of `probe_slot`, quantity code).
@group(0) @binding(28) var<storage, read> probes: array<vec2<u32>>;
// Each probed particle's slot (reorder.wgsl, map_slots).
@group(0) @binding(48) var<storage, read> probe_slot: array<u32>;
// The plastic history (common.wgsl, HISTORY), for the probes.
@group(0) @binding(76) var<storage, read> hist: array<vec4<f32>>;
// The artificial dissipation by workgroup of the forces pass (DISS).
@group(0) @binding(89) var<storage, read> dheat: array<vec4<f32>>;
// The rates of the evaluation at the observed state, which the held slots
// read (HELD): the leapfrog's carried a_n, the midpoint rule's in the
// midpoint buffer before advance_half turns it into the midpoint state
// (the spread already in: gpu::encode, encode_contact).
@group(0) @binding(51) var<storage, read> acc: array<vec2<f32>>;
@group(0) @binding(35) var<storage, read> vm: array<vec2<f32>>;
// Coulomb friction (RUB; contact.wgsl): each particle's slip, its
// friction in the evaluation and what its rub pass found, by original
// index.
@group(0) @binding(96) var<storage, read> slip: array<vec4<f32>>;
@group(0) @binding(97) var<storage, read> frub: array<vec4<f32>>;
@group(0) @binding(100) var<storage, read> crubo: array<vec4<f32>>;

// The scene's observation slots are constants the host puts before this
// file (gpu::probes::ProbePlan::wgsl): NSLOTS, and for each slot its code
// (SLOT_CODE), body or body pair (SLOT_A, SLOT_B; NONE: every body) and
// whether it sums (0) or takes the maximum (1) (SLOT_OP).

const RED: u32 = 256u;
var<workgroup> shf: array<f32, 256>;

// Two values combined by operation `op`: 0 the sum, 1 the maximum, 2 the
// minimum.
fn apply_op(op: u32, a: f32, b: f32) -> f32 {
    if (op == 1u) {
        return max(a, b);
    }
    if (op == 2u) {
        return min(a, b);
    }
    return a + b;
}

// Tree reduction of `shf` by operation `op` (apply_op), result in shf[0].
fn reduce_shared(lid: u32, op: u32) {
    for (var off = RED / 2u; off > 0u; off = off / 2u) {
        workgroupBarrier();
        if (lid < off) {
            shf[lid] = apply_op(op, shf[lid], shf[lid + off]);
        }
    }
    workgroupBarrier();
}

fn row_base() -> u32 {
    return (ctl.step % params.ring_len) * params.ring_width;
}

// What the observations read of a particle, read once for all its slots
// (a software adapter reads each value lane by lane; reading them per slot
// was most of the reductions' time).
struct Obs {
    m: f32,
    body: u32,
    rigid: bool,
    v: vec2<f32>,
    e: f32,
    // Its CFL step (BIG for a rigid particle).
    cfl: f32,
}

fn observe(i: u32) -> Obs {
    let mi = pinfo[i];
    let b = bodies[mi.z];
    let vi = v[i];
    let rigid = b.rigid != 0u;
    var cfl = BIG;
    if (!rigid) {
        // Where supports adapt (and one is not round), the support's
        // minor semi-axis for h.
        var h = b.h;
        if (adapting()) {
            h = metric_axes(metric_banded(metric[i], b.h)).x;
        }
        cfl = params.cfl * h / (abs(sr2c[i].w) + length(vi));
    }
    return Obs(bitcast<f32>(mi.x), mi.z, rigid, vi, r[i].y, cfl);
}

// The value particle i (observed as `o`) adds to observation slot `sl`
// (codes: gpu::probes).
fn slot_value(sl: u32, i: u32, o: Obs) -> f32 {
    let code = SLOT_CODE[sl];
    let a = SLOT_A[sl];
    if (code == 10u) {
        // The internal energy held below zero (the energy guard's).
        if (o.rigid) {
            return 0.0;
        }
        return o.m * min(o.e, 0.0);
    }
    if (code == 12u) {
        // The body force's potential against the grid origin (the plan
        // takes off its value as placed: gpu::probes).
        if (!GRAVITY || o.rigid) {
            return 0.0;
        }
        return o.m * dot(gravity(), position_rel(i));
    }
    if (code == 13u || code == 14u) {
        // Region a's force on its particles, -sum m (a + g) over its held
        // components (CPU twin: Model::held_forces).
        if (!HELD || o.rigid || region_at(i) != 4u * a) {
            return 0.0;
        }
        var rate: vec2<f32>;
        if (LEAP != 0u) {
            rate = acc[i];
        } else {
            rate = vm[i];
        }
        if (GRAVITY) {
            rate += gravity();
        }
        let f = -o.m * rate * held_mask(i);
        return select(f.y, f.x, code == 13u);
    }
    if (code == 11u) {
        // The artificial dissipation booked so far: each forces
        // workgroup's sum (forces.wgsl, dheat), taken by its first particle.
        if (!DISS || i % WG != 0u) {
            return 0.0;
        }
        let d = dheat[i / WG];
        return d.x + d.y;
    }
    if (code >= 19u) {
        // Friction (gpu::probes, FRICTION_HEAT on).
        if (!RUB || o.rigid) {
            return 0.0;
        }
        if (code == 19u) {
            return slip[pinfo[i].w].w;
        }
        // A rubbing particle's pass against the pair's other body.
        if (nbo[i].z <= 0.0 || frub[pinfo[i].w].x == 0.0) {
            return 0.0;
        }
        let fa = f32(a);
        let fb = f32(SLOT_B[sl]);
        let body = f32(o.body);
        let partner = cown[i].w;
        if (!((body == fa && partner == fb) || (body == fb && partner == fa))) {
            return 0.0;
        }
        let h = crubo[pinfo[i].w];
        switch code {
            case 20u: { return h.z; }
            case 21u: { return h.w; }
            default: { return area[area_index(i, nbo[i].w)]; }
        }
    }
    if (code >= 15u) {
        // Body a's sums about its centre as placed (gpu::probes, SPIN).
        if (o.body != a) {
            return 0.0;
        }
        let r = position_rel(i) - SLOT_C[SLOT_B[sl]];
        switch code {
            case 15u: { return o.m * (r.x * o.v.y - r.y * o.v.x); }
            case 16u: { return o.m * dot(r, r); }
            case 17u: { return o.m * r.x; }
            default: { return o.m * r.y; }
        }
    }
    if (code <= 5u) {
        if (a != NONE && o.body != a) {
            return 0.0;
        }
        switch code {
            case 0u: { return o.m * o.v.x; }
            case 1u: { return o.m * o.v.y; }
            case 2u: { return o.m * position_rel(i).x; }
            case 3u: { return o.m * position_rel(i).y; }
            case 4u: { return 0.5 * o.m * dot(o.v, o.v); }
            default: {
                if (o.rigid) {
                    return 0.0;
                }
                return o.m * o.e;
            }
        }
    }
    if (!CONTACT) {
        return 0.0;
    }
    switch code {
        case 6u, 7u: {
            // The leapfrog's contact writes only its boundary particles'
            // entries (contact.wgsl).
            if (LEAP != 0u && nbo[i].z <= 0.0) {
                return 0.0;
            }
            let own = cown[i];
            let fa = f32(a);
            let fb = f32(SLOT_B[sl]);
            let body = f32(o.body);
            if ((body == fa && own.w == fb) || (body == fb && own.w == fa)) {
                // The particle's own contact force, p A / 2 (contact.wgsl).
                let f = length(own.xy);
                if (code == 6u) {
                    return f;
                }
                // Its pressure p.
                let ar = area[area_index(i, nbo[i].w)];
                if (ar > 0.0) {
                    return 2.0 * f / ar;
                }
                return 0.0;
            }
            return 0.0;
        }
        // The stored spring energy, left by the contact in sr2c.x
        // (contact.wgsl, store_energy).
        case 8u: {
            // And the tangential springs' (contact.wgsl, slip).
            var stored = 0.0;
            if (RUB) {
                let sl = slip[pinfo[i].w];
                stored = 0.5 * abs(sl.y) * sl.x * sl.x;
            }
            if (LEAP != 0u && nbo[i].z <= 0.0) {
                return stored;
            }
            return sr2c[i].x + stored;
        }
        default: { return qheat[i].x; }
    }
}

// Level 1 of the reductions, one workgroup per RED_CHUNK particles: each
// thread folds its particles (RED_THREADS apart, so that neighbouring threads
// read neighbouring particles) into the CFL minimum and every slot's sum or
// maximum, then the workgroup combines its threads' values, all slots at
// once, in a tree. Every sum has one fixed order (deterministic).
const RED_THREADS: u32 = 64u;
const RED_CHUNK: u32 = 1024u;
// Values a thread carries: the CFL minimum, then the slots.
const NVALS: u32 = NSLOTS + 1u;
// Values combined at once in the tree (workgroup memory: 64 x 16 floats).
const GROUPV: u32 = 16u;
var<workgroup> shv: array<f32, 1024>;

// How value `k` (0: the CFL minimum, 1 + s: slot s) combines.
fn combine(k: u32, a: f32, b: f32) -> f32 {
    if (k == 0u) {
        return min(a, b);
    }
    return apply_op(SLOT_OP[k - 1u], a, b);
}

@compute @workgroup_size(64)
fn reduce_partial(@builtin(local_invocation_id) lid3: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let lid = lid3.x;
    let g = wid.x + wid.y * nwg.x;
    // A wrapped 2-D dispatch has a few whole workgroups past the end.
    if (g >= params.red_groups) {
        return;
    }
    let n = params.n;
    var acc: array<f32, NVALS>;
    acc[0] = BIG;
    for (var k = 0u; k < RED_CHUNK / RED_THREADS; k++) {
        let i = g * RED_CHUNK + k * RED_THREADS + lid;
        if (i < n) {
            let o = observe(i);
            acc[0] = min(acc[0], o.cfl);
            fold_slots(&acc, i, o);
        }
    }
    for (var g0 = 0u; g0 < NVALS; g0 += GROUPV) {
        let nv = min(GROUPV, NVALS - g0);
        workgroupBarrier();
        for (var v = 0u; v < nv; v++) {
            shv[v * RED_THREADS + lid] = acc[g0 + v];
        }
        for (var off = RED_THREADS / 2u; off > 0u; off = off / 2u) {
            workgroupBarrier();
            if (lid < off) {
                for (var v = 0u; v < nv; v++) {
                    let at = v * RED_THREADS + lid;
                    shv[at] = combine(g0 + v, shv[at], shv[at + off]);
                }
            }
        }
        workgroupBarrier();
        if (lid < nv) {
            let k = g0 + lid;
            let x = shv[lid * RED_THREADS];
            if (k == 0u) {
                red[g] = x;
            } else {
                red[params.red_groups + (k - 1u) * params.red_groups + g] = x;
            }
        }
    }
}

// Observation slot `sl` summed (or its maximum) over the level-1 partials,
// in shf[0]; every thread of the workgroup takes part.
fn slot_total(lid: u32, sl: u32) -> f32 {
    let op = SLOT_OP[sl];
    var acc = 0.0;
    for (var k = lid; k < params.red_groups; k += RED) {
        acc = apply_op(op, acc, red[params.red_groups + sl * params.red_groups + k]);
    }
    workgroupBarrier();
    shf[lid] = acc;
    reduce_shared(lid, op);
    return shf[0];
}

// Level 2, one dispatch: workgroup 0 the CFL step (dt = min(CFL step, time
// left), the time record of this state's ring row, the dt-collapse check),
// the energy guard and the particle probes; workgroup 1 + k observation
// slot k into this state's ring row.
@compute @workgroup_size(256)
fn reduce_final(@builtin(local_invocation_id) lid3: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let lid = lid3.x;
    let w = wid.x + wid.y * nwg.x;
    if (w > NSLOTS) {
        return;
    }
    if (w > 0u) {
        let total = slot_total(lid, w - 1u);
        if (lid == 0u) {
            ring[row_base() + 3u + w - 1u] = total;
        }
        return;
    }
    var m = BIG;
    for (var k = lid; k < params.red_groups; k += RED) {
        m = min(m, red[k]);
    }
    shf[lid] = m;
    reduce_shared(lid, 2u);
    let cfl_min = shf[0];
    // The energy guard's total: the same sums, in the same order, as the
    // slots' own workgroups write to the ring.
    var e = 0.0;
    var owed = 0.0;
    if (GUARD) {
        e = slot_total(lid, params.energy_kin) + slot_total(lid, params.energy_int);
        if (params.energy_stored != NONE) {
            e += slot_total(lid, params.energy_stored);
        }
        owed = slot_total(lid, params.energy_owed);
    }
    for (var k = lid; k < params.nprobes; k += RED) {
        probe_value(k);
    }
    if (lid == 0u) {
        cfl_step(cfl_min);
        if (GUARD) {
            energy_guard(e, owed);
        }
    }
}

// dt from the CFL minimum over the particles (thread 0 of reduce_final).
fn cfl_step(cfl_min: f32) {
    var cfl_dt = min(cfl_min, params.contact_dt);
    if (params.fixed_dt > 0.0) {
        cfl_dt = params.fixed_dt;
    }
    let rem = (params.end_hi - ctl.t_hi) + (params.end_lo - ctl.t_lo);
    var dt = min(cfl_dt, rem);
    // The end is reached when what is left is round-off of the time sum:
    // a ten-thousandth of a step, or below what f32 resolves at the stop
    // (a step shorter than that could leave the time where it is, and the
    // run would never reach its stop).
    if (rem <= max(1e-4 * cfl_dt, 2.4e-7 * abs(params.end_hi))) {
        dt = 0.0;
    }
    // After a failure the rest of the batch takes zero-length steps, so the
    // state read back is the one that failed, with its time and step (as on
    // the CPU path), not what the bad values made of it since.
    if (atomicLoad(&ctl.fail_step) != NONE) {
        dt = 0.0;
    }
    if (ctl.dt0 == 0.0 && dt > 0.0) {
        ctl.dt0 = dt;
    }
    if (dt > 0.0 && !(cfl_dt > 1e-6 * ctl.dt0 && cfl_dt < BIG)) {
        let fs = atomicLoad(&ctl.fail_step);
        if (fs == NONE) {
            atomicMin(&ctl.fail_step, ctl.step);
            atomicMin(&ctl.fail_code, FAIL_TIME_STEP);
        }
    }
    ctl.dt = dt;
    ctl.fallback_max = max(ctl.fallback_max, atomicLoad(&ctl.fallback_now));
    if (LEAP != 0u) {
        // The leapfrog's kinematic pass ran in the step before this one
        // (or its first evaluation): its count is read here, then cleared.
        atomicStore(&ctl.fallback_now, 0u);
    }
    let row = row_base();
    ring[row] = ctl.t_hi;
    ring[row + 1u] = ctl.t_lo;
    ring[row + 2u] = dt;
}

// The energy guard (Model::guards_energy): `e`, the total energy (kinetic
// + internal + stored penalty) of the state this step starts from, and
// `owed`, the internal energy its particles hold below zero
// (Model::energy_owed_bound). The
// first state sets the limit; out of the band (Model::energy_outside) the
// step gets zero length (the advances leave the state as it is) and the
// failure is recorded against this state: code 6, the host names the
// particle.
fn energy_guard(e: f32, owed: f32) {
    if (ctl.energy_limit < 0.0) {
        // As Model::energy_limit.
        ctl.energy_limit = params.energy_growth * e + params.energy_floor;
        return;
    }
    // As Model::energy_lower.
    let e0 = (ctl.energy_limit - params.energy_floor) / params.energy_growth;
    let lower = (2.0 - params.energy_growth) * e0 - params.energy_floor;
    // As Model::energy_owed_bound.
    let owed_bound = -((params.energy_growth - 1.0) * e0 + params.energy_floor);
    let outside = e > ctl.energy_limit || e < lower || owed < owed_bound;
    if (outside && atomicLoad(&ctl.fail_step) == NONE) {
        atomicMin(&ctl.fail_step, ctl.step);
        atomicMin(&ctl.fail_code, FAIL_ENERGY_GUARD);
        ctl.dt = 0.0;
    }
}

// Particle probe k (codes: gpu::probes) into this state's ring row.
fn probe_value(k: u32) {
    let pr = probes[k];
    let i = probe_slot[pr.x];
    let b = bodies[pinfo[i].z];
    let mu = r[i].x;
    var h = vec4<f32>(0.0);
    if (HISTORY) {
        h = hist[i];
    }
    let p = pressure_of(b, mu, r[i].y, damage_seen(h));
    let si = s[i];
    var val = 0.0;
    switch pr.y {
        case 0u: { val = position_rel(i).x; }
        case 1u: { val = position_rel(i).y; }
        case 2u: { val = v[i].x; }
        case 3u: { val = v[i].y; }
        case 4u: { val = b.rho0 * (1.0 + mu); }
        case 5u: { val = p; }
        case 6u: { val = si.x - p; }
        case 7u: { val = si.y - p; }
        case 8u: { val = si.z; }
        case 9u: { val = von_mises(si); }
        // The plastic history (gpu::probes adds the room temperature).
        case 11u: { val = h.x; }
        case 12u: { val = h.y; }
        case 13u: { val = h.z; }
        case 14u: { val = h.w; }
        case 15u: { val = si.w - p; }
        default: { val = r[i].y; }
    }
    ring[row_base() + 3u + NSLOTS + k] = val;
}

// End of a step: t += dt as a compensated sum, the step counter.
@compute @workgroup_size(1)
fn end_step() {
    let dt = ctl.dt;
    if (dt > 0.0) {
        let a = ctl.t_hi;
        let sum = a + dt;
        let bb = sum - a;
        let err = (a - (sum - bb)) + (dt - bb);
        let lo = ctl.t_lo + err;
        let hi = sum + lo;
        ctl.t_lo = lo - (hi - sum);
        ctl.t_hi = hi;
        ctl.step = ctl.step + 1u;
    } else {
        ctl.zero_steps = ctl.zero_steps + 1u;
    }
    if (LEAP == 0u) {
        atomicStore(&ctl.fallback_now, 0u);
    }
}
