// Explicit midpoint (RK2) updates (docs/method.md §9) with the radial return of
// perfect plasticity (docs/method.md §6). The evaluation at the base state left
// its rates k1 in the midpoint buffers; advance_half turns them into the
// midpoint state in place, mid = base + dt/2 k1. The evaluation at the
// midpoint adds dt k2 to the base state itself (common.wgsl, MID) and the
// contact's second pass books its energy ledger, so advance_full only moves
// the positions with the midpoint velocity and checks the new state. With
// contact both also gather the spread of the evaluation before them
// (spread.wgsl) into their particle's rates first: a pass the step does
// not need. CPU twin: cpu::advance.

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read> s: array<vec4<f32>>;
@group(0) @binding(30) var<storage, read_write> u_w: array<vec2<f32>>;
@group(0) @binding(31) var<storage, read_write> v_w: array<vec2<f32>>;
@group(0) @binding(32) var<storage, read_write> r_w: array<vec2<f32>>;
@group(0) @binding(33) var<storage, read_write> s_w: array<vec4<f32>>;
@group(0) @binding(35) var<storage, read> vm: array<vec2<f32>>;
// The contact's spread (spread.wgsl): normals and dPhi/dg on the list of
// boundary particles, and the particles pass 2 claimed.
@group(0) @binding(66) var<storage, read> cn: array<vec4<f32>>;
@group(0) @binding(70) var<storage, read> bt: array<f32>;
@group(0) @binding(72) var<storage, read_write> claim: array<atomic<u32>>;
// The plastic history (common.wgsl, HISTORY): the base state's, and the
// one written (advance_half: the midpoint's; advance_full: the base
// state's, in place); the strain rates of the evaluation before
// (kinematics.wgsl).
@group(0) @binding(76) var<storage, read> hist: array<vec4<f32>>;
@group(0) @binding(77) var<storage, read_write> hist_w: array<vec4<f32>>;
@group(0) @binding(78) var<storage, read> srate: array<f32>;
// Supports that adapt: each particle's metric, carried at a step's end
// with the velocity gradient of the evaluation that moved the positions
// (kinematics.wgsl).
@group(0) @binding(83) var<storage, read_write> metric_w: array<vec4<f32>>;
// With LGRAD the kinematics' packed dt l (common.wgsl), else the
// viscosity's kept gradient (`gradv`, a vec4<f32> a particle) bound here.
@group(0) @binding(84) var<storage, read> lgrad: array<vec2<u32>>;
// The impulse the regions gave each held particle (common.wgsl, HELD), by
// original index: (hi x, hi y, lo x, lo y).
@group(0) @binding(95) var<storage, read_write> held_w: array<vec4<f32>>;

// Coulomb friction (RUB; contact.wgsl): each particle's elastic slip, and
// its friction in the evaluation before, by original index.
@group(0) @binding(96) var<storage, read_write> slip: array<vec4<f32>>;
@group(0) @binding(97) var<storage, read_write> frub: array<vec4<f32>>;

// Particle i's friction in the evaluation before: its rub pass's where it
// was on the boundary, else none.
fn friction_of(i: u32) -> vec4<f32> {
    if (nbo[i].z > 0.0) {
        return frub[pinfo[i].w];
    }
    return vec4<f32>(0.0);
}

// The Coulomb return at the step's end (CPU twin: cpu::contact::
// return_slip, after advance_slip) of particle i, its slip advanced to
// `u` by the rate of its friction `fr`, the frictional heat by `heat`:
// the slip clipped to the limit of the step's evaluation, with its spring
// and whether it slid; a particle without a frictional pass lets its
// slip go. The spring energy released is heat in the particle (returned,
// specific), in the contact's ledger (taken from the springs' work) and in
// the frictional heat.
fn return_slip(i: u32, u: f32, fr: vec4<f32>, heat: f32) -> f32 {
    let id = pinfo[i].w;
    var sl = slip[id];
    var released = 0.0;
    if (fr.x != 0.0) {
        let c = abs(fr.x);
        let uc = clamp(u, -fr.y, fr.y);
        released = 0.5 * c * (u * u - uc * uc);
        sl = vec4<f32>(uc, fr.x, uc, sl.w + heat + released);
    } else {
        released = 0.5 * abs(sl.y) * u * u;
        sl = vec4<f32>(0.0, 0.0, 0.0, sl.w + heat + released);
    }
    slip[id] = sl;
    if (released != 0.0) {
        qheat_w[i] = qheat_w[i] + vec2<f32>(released, -released);
    }
    return released / bitcast<f32>(pinfo[i].x);
}

// Add `j` to held particle i's impulse (CPU twin: Model::book_held).
fn add_held_impulse(i: u32, j: vec2<f32>) {
    let id = pinfo[i].w;
    let q = held_w[id];
    let x = two_sum(q.xz, j.x);
    let y = two_sum(q.yw, j.y);
    held_w[id] = vec4<f32>(x.x, y.x, x.y, y.y);
}

// The leapfrog's half kick by a (the body force's included) over h of
// held particle i: its region's impulse, -m a h in the held components.
fn book_held_kick(i: u32, a: vec2<f32>, h: f32) {
    if (HELD) {
        let mask = held_mask(i);
        if (any(mask != vec2<f32>(0.0))) {
            add_held_impulse(i, -a * mask * (bitcast<f32>(pinfo[i].x) * h));
        }
    }
}

// Where supports adapt, the slot of the next step's largest major
// semi-axis (common.wgsl), cleared by a pass before the step's end.
fn clear_next_top(i: u32) {
    if (ADAPT && i == 0u) {
        atomicStore(&ctl.h_top[(ctl.step + 1u) & 1u], 0u);
        atomicStore(&ctl.out_of_band[(ctl.step + 1u) & 1u], 0u);
    }
}

// Particle i's support at the step's end (cpu::advance::carry_supports):
// carried with the velocity gradient of the evaluation that moved the
// positions (a rigid one keeps its own), and counted in the next step's
// largest major semi-axis (of the support, where a band maps it) and, where
// it is not round, in whether the next step's supports adapt (`adapting`).
fn carry_support(i: u32, rigid: bool, h0: f32, dt: f32) {
    var q = metric_w[i];
    if (!rigid) {
        if (LGRAD) {
            q = metric_carried(q, unpack_step_gradient(lgrad[i]), 1.0, h0);
        } else {
            let l = vec4<f32>(bitcast<vec2<f32>>(lgrad[2u * i]), bitcast<vec2<f32>>(lgrad[2u * i + 1u]));
            q = metric_carried(q, l, dt, h0);
        }
        metric_w[i] = q;
    }
    let b = metric_banded(q, h0);
    atomicMax(&ctl.h_top[(ctl.step + 1u) & 1u], bitcast<u32>(metric_axes(b).y));
    let round = 1.0 / (h0 * h0);
    if (!no_band() && (b.x != round || b.y != 0.0 || b.z != round)) {
        atomicMax(&ctl.out_of_band[(ctl.step + 1u) & 1u], 1u);
    }
}

fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// Record the first failing step and, within it, the lowest particle id,
// with why (common.wgsl's FAIL_* codes).
fn fail(i: u32, quantity: u32) {
    let fs = atomicLoad(&ctl.fail_step);
    if (fs == NONE || fs == ctl.step) {
        atomicMin(&ctl.fail_step, ctl.step);
        atomicMin(&ctl.fail_code, pinfo[i].w * 8u + quantity);
    }
}

// Stage 1: the midpoint state (u_w, v_w, r_w, s_w are the midpoint buffers;
// v_w, r_w and s_w hold the rates of the evaluation at the base state).
@compute @workgroup_size(WG)
fn advance_half(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    let spread = spread_force(i);
    // A zero-length step (past the stop, or after a failure) leaves the
    // state as it is: non-finite rates times zero would not.
    if (ctl.dt == 0.0) {
        return;
    }
    clear_next_top(i);
    let k = 0.5 * ctl.dt;
    if (RUB) {
        // The slip at the midpoint (cpu::contact::advance_slip).
        let id = pinfo[i].w;
        slip[id].z = slip[id].x + friction_of(i).z * k;
    }
    let mi = pinfo[i];
    let b = bodies[mi.z];
    u_w[i] = u[i] + v[i] * k;
    if (b.rigid != 0u) {
        v_w[i] = v[i];
        r_w[i] = r[i];
        s_w[i] = s[i];
        if (HISTORY) {
            hist_w[i] = hist[i];
        }
        return;
    }
    var a = v_w[i] + spread / bitcast<f32>(mi.x);
    if (GRAVITY) {
        a += gravity();
    }
    v_w[i] = hold(i, v[i] + a * k);
    var rn = r[i] + r_w[i] * k;
    var sn = plastic_return(s[i] + s_w[i] * k, b);
    if (HISTORY) {
        let up = strength_update(mi.z, sn, rate_of(i), rn.x, rn.y, hist[i], ctl.t_hi + ctl.t_lo + k);
        sn = up.s;
        rn.x = up.mu;
        hist_w[i] = up.h;
    }
    r_w[i] = rn;
    s_w[i] = sn;
}

// The equivalent strain rate of particle i's last evaluation (0 where no
// law reads it).
fn rate_of(i: u32) -> f32 {
    if (STRAIN_RATE) {
        return srate[i];
    }
    return 0.0;
}

// Stage 2: the new positions, in place (u_w is the base buffer), and the
// checks of the new state (velocity, density, energy and stress were
// already advanced by the evaluation at the midpoint, but for the spread,
// added here; v_w is the base velocity and r_w reads the rest). With a
// plastic history the stress update of the new state runs here, where its
// energy is whole: r_w, s_w and hist_w are the base state's buffers.
@compute @workgroup_size(WG)
fn advance_full(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    let spread = spread_force(i);
    // A zero-length step (past the stop, or after a failure) leaves the
    // state as it is.
    if (ctl.dt == 0.0) {
        return;
    }
    let dt = ctl.dt;
    let mi = pinfo[i];
    let b = bodies[mi.z];
    let un = u_w[i] + vm[i] * dt;
    u_w[i] = un;
    if (ADAPT) {
        carry_support(i, b.rigid != 0u, b.h, dt);
    }
    if (b.rigid != 0u) {
        return;
    }
    var vn = v_w[i];
    var rn = r_w[i];
    if (any(spread != vec2<f32>(0.0))) {
        let w0 = vn;
        vn += spread * (dt / bitcast<f32>(mi.x));
        v_w[i] = vn;
        // The compatible energy of this last kick (common.wgsl).
        rn.y += compatible_energy(w0, vn, vm[i]);
        r_w[i] = rn;
    }
    if (HELD || ONPLANE) {
        // The step's kicks (the forces', the contact's, the spread's) left
        // the held components free; they go back to the region's velocity
        // here in one kick whose compatible energy returns what the
        // others booked for them (the sum is the twin's, which books none
        // there), and whose impulse is the region's. A particle on a
        // symmetry plane likewise drops its normal component.
        let w = vn;
        vn = hold(i, w);
        if (HELD && any(vn != w)) {
            add_held_impulse(i, (vn - w) * bitcast<f32>(mi.x));
        }
        if (any(vn != w)) {
            v_w[i] = vn;
            rn.y += compatible_energy(w, vn, vm[i]);
            r_w[i] = rn;
        }
    }
    if (HISTORY) {
        let up = strength_update(mi.z, s_w[i], rate_of(i), rn.x, rn.y, hist_w[i], ctl.t_hi + ctl.t_lo + dt);
        s_w[i] = up.s;
        rn.x = up.mu;
        r_w[i] = rn;
        hist_w[i] = up.h;
    }
    if (RUB) {
        // The step's rates are the midpoint's.
        let fr = friction_of(i);
        rn.y += return_slip(i, slip[pinfo[i].w].x + fr.z * dt, fr, fr.w * dt);
        r_w[i] = rn;
    }
    check(i, un, vn, rn);
}

// The lowest mu a particle's density may reach: -0.9 (0.1 rho0); a failed
// particle's, whose crack opens, -1 (any positive density).
fn low_mu(i: u32) -> f32 {
    if (FAILURE && failed(hist_w[i].z)) {
        return -1.0;
    }
    return -0.9;
}

// The checks of a new state (position `un`, velocity `vn`, density and
// energy `rn`); the first failure is recorded (`fail`).
fn check(i: u32, un: vec2<f32>, vn: vec2<f32>, rn: vec2<f32>) {
    if (bodies[pinfo[i].z].rigid != 0u) {
        return;
    }
    let xn = x0[i].zw + un;
    if (!(finite(xn.x) && finite(xn.y))) {
        fail(i, FAIL_POSITION);
    } else if (!(finite(vn.x) && finite(vn.y))) {
        fail(i, FAIL_VELOCITY);
    } else if (!finite(rn.y)) {
        fail(i, FAIL_ENERGY);
    } else if (!(rn.x > low_mu(i) && rn.x < 9.0)) {
        fail(i, FAIL_DENSITY);
    } else {
        // The domain (Model::domain_of), in the grid origin's frame; f32 is
        // ample for a box this coarse.
        let p = x0[i].xy * params.cell + xn;
        let d = params.domain;
        if (!(all(p >= d.xy) && all(p <= d.zw))) {
            fail(i, FAIL_DOMAIN);
        }
    }
}

// The leapfrog (common.wgsl, LEAP; CPU twin: cpu::CpuSolver::leapfrog). A
// step: kick_drift_cells (with the cell list's counts); the rest of the
// cell list; kinematics_leap (density and stress to n+1,
// the EOS, the predicted velocity, the contact's list of boundary
// particles); the momentum and the contact forces at n+1 (LEAP = 2), which
// kick each particle to v_{n+1} once its a_{n+1} is whole; the energy sums
// and the contact's booking at v_{n+1} (LEAP = 3); finish. The rates a_n
// (acc) and de_n (rdt.y) and the contact's heat and spring rates (qrate)
// are carried from the step before. Here u_w, v_w and r_w are the state's own buffers. A
// zero-length step (past the stop, or after a failure) changes nothing.
@group(0) @binding(13) var<storage, read> nbo: array<vec4<f32>>;
@group(0) @binding(34) var<storage, read_write> qheat_w: array<vec2<f32>>;
@group(0) @binding(51) var<storage, read> acc: array<vec2<f32>>;
@group(0) @binding(52) var<storage, read> rdt: array<vec2<f32>>;
@group(0) @binding(55) var<storage, read> qrate: array<vec2<f32>>;

// The cell list's counts (neighbours.wgsl), filled here for the new positions.
@group(0) @binding(16) var<storage, read_write> bstart_w: array<atomic<u32>>;
// The count of the contact's list of boundary particles, which the step's
// the kinematics pass fills (kinematics.wgsl, list_surface).
@group(0) @binding(65) var<storage, read_write> surf_args: array<u32>;

// v_{n+1/2} = v_n + dt/2 a_n, e likewise (less the
// compatible term, kick_energy), x_{n+1} = x_n + dt v_{n+1/2}, the
// contact ledger's first half step, and the first pass of the cell list at
// x_{n+1} (neighbours.wgsl, grid_cells).
@compute @workgroup_size(WG)
fn kick_drift_cells(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (CONTACT && i == 0u) {
        surf_args[0] = 0u;
    }
    if (i >= params.n) {
        return;
    }
    var un = u_w[i];
    let dt = ctl.dt;
    if (dt != 0.0) {
        clear_next_top(i);
        let h = 0.5 * dt;
        // The contact's rates are those of the last step's boundary
        // particles: others hold what the buffer held in between.
        if (CONTACT && nbo[i].z > 0.0) {
            qheat_w[i] = qheat_w[i] + qrate[i] * h;
        }
        var vh = v_w[i];
        if (bodies[pinfo[i].z].rigid == 0u) {
            var a = acc[i];
            if (GRAVITY) {
                a += gravity();
            }
            vh = hold(i, vh + a * h);
            v_w[i] = vh;
            r_w[i].y = r_w[i].y + rdt[i].y * h + kick_energy(moving_part(i, acc[i]), h);
            book_held_kick(i, a, h);
            if (RUB) {
                // The slip at n+1/2 and the frictional heat's first half
                // step, at the rates the last step's booking carried
                // (zero where it found no friction; finish).
                let id = pinfo[i].w;
                let fr = frub[id];
                let sl = slip[id];
                slip[id] = vec4<f32>(sl.x + fr.z * h, sl.y, sl.z, sl.w + fr.w * h);
            }
        }
        un = un + vh * dt;
        u_w[i] = un;
    }
    atomicAdd(&bstart_w[bucket_of(home_at(x0[i], un).cell)], 1u);
}

// The density at n+1 (kinematics_leap left it in rdt.x), e_{n+1} = e_{n+1/2} +
// dt/2 de_{n+1}, and the checks of the new state. The step's last walk is
// done, so it also zeroes the cell list's counts for the next step's
// (kick_drift_cells counts into them): between leapfrog steps the counts
// are zero (gpu::GpuSolver keeps that after the builds outside a step).
@compute @workgroup_size(WG)
fn finish(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    for (var b = i; b < params.buckets; b += params.n) {
        atomicStore(&bstart_w[b], 0u);
    }
    if (ctl.dt == 0.0) {
        return;
    }
    let q = rdt[i];
    var e = r_w[i].y;
    let b = bodies[pinfo[i].z];
    if (b.rigid == 0u) {
        // acc holds a_{n+1}, which kicked the particle to v_{n+1}.
        e = e + q.y * (0.5 * ctl.dt) - kick_energy(moving_part(i, acc[i]), 0.5 * ctl.dt);
        var a = acc[i];
        if (GRAVITY) {
            a += gravity();
        }
        book_held_kick(i, a, 0.5 * ctl.dt);
    }
    if (ADAPT) {
        carry_support(i, b.rigid != 0u, b.h, ctl.dt);
    }
    if (RUB && b.rigid == 0u) {
        // The slip at n+1 from the rate booked at v_{n+1}, returned onto
        // the limit found there; what the booking found carries to the
        // next step's first half, none where it found no friction.
        let h = 0.5 * ctl.dt;
        let fr = friction_of(i);
        e += return_slip(i, slip[pinfo[i].w].x + fr.z * h, fr, fr.w * h);
        frub[pinfo[i].w] = fr;
    }
    r_w[i] = vec2<f32>(q.x, e);
    check(i, u_w[i], v_w[i], vec2<f32>(q.x, e));
}
