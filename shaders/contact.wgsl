// Penalty contact (METHOD.md §8), two gathers, no atomics.
// Pass 1: each boundary particle P interpolates the partner body's surface
// points s_q = x_q + o_q n_q with kernel weights, takes the gap as the mean
// of the chord and tangent-line estimates, and the pressure
// p = max(0, Z* w + k delta), k from the two surface layers
// (cpu::contact::spring_stiffness); it keeps -p A n / 2 and leaves +p A n / 2
// per unit weight for its partners. Pass 2: each boundary particle gathers
// those shares over the same candidate pairs, and adds the contact force and
// the dashpot heat to its rates.
// CPU twin: cpu::contact::penalty (which also allows several partner bodies
// at one particle; here each particle pairs with the first partner body its
// neighbour scan meets, and such particles are counted).
//
// The leapfrog (common.wgsl, LEAP) runs both passes twice a step: for the
// forces at the predicted velocity (LEAP = 2: `v` is vstar, `dv` the carried
// a_{n+1}; pass 2 then kicks its particles to v_{n+1}), then for the
// booking (LEAP = 3), after the energy walk: the same forces,
// their dashpot heat and spring power at v_{n+1} (`vbook`), the heat added
// to dr.y and the ledger advanced by half a step (CPU twin:
// cpu::contact::penalty_booked). The stored spring energy goes to nbo.w
// there, since the energy walk after the contact still reads sr2c.
//
// Where pass 1 leaves a particle's entries (`cown`, `cshare`): in the
// midpoint rule and the leapfrog's first evaluation and booking, at the
// particle, in pass scratch no later pass of the evaluation reads
// (gpu::contact_homes); in the leapfrog's force passes (LEAP = 2), before the
// energy walk has read that scratch, at the particle's place on the list of
// boundary particles, which the kinematics pass wrote to nbo.w (`slot`). Where that list
// overflowed, pass 1 stores nothing and pass 2 makes each entry it needs
// again (`entries`: the same arithmetic, so the same bits, at a walk per
// partner).

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(13) var<storage, read_write> nbo: array<vec4<f32>>;
@group(0) @binding(16) var<storage, read_write> dr: array<vec2<f32>>;
@group(0) @binding(18) var<storage, read_write> dv: array<vec2<f32>>;
@group(0) @binding(19) var<storage, read> area: array<f32>;
@group(0) @binding(20) var<storage, read_write> cown: array<vec4<f32>>;
@group(0) @binding(21) var<storage, read_write> cshare: array<vec4<f32>>;
// `x`: the spring energy each particle's pass stores (observations). The
// kinematics pass writes sr2c and the forces pass reads it, last; the reductions after this
// evaluation read only its `w` (sound speed) and this `x`; no other thread
// touches a particle's entry in these passes (gpu::contact_homes).
@group(0) @binding(14) var<storage, read_write> sr2c: array<vec4<f32>>;
// Per particle: (dashpot heat booked, spring work of its own passes), the
// contact's energy ledger, booked at the midpoint (MID) with the step.
@group(0) @binding(34) var<storage, read_write> qheat_w: array<vec2<f32>>;
// The leapfrog's: the contact's (heat, spring power) rates per particle at
// the state (the ledger's other half step), and the velocities the booking
// books at.
@group(0) @binding(55) var<storage, read_write> qrate: array<vec2<f32>>;
@group(0) @binding(56) var<storage, read> vbook: array<vec2<f32>>;
// The state's velocity, which the leapfrog's force pass 2 (LEAP = 2) kicks
// to v_{n+1} once a boundary particle's acceleration is whole (the forces pass kicks
// the others).
@group(0) @binding(57) var<storage, read_write> vkick: array<vec2<f32>>;
// The leapfrog step's boundary particles (kinematics.wgsl, leap_surface) and
// (count, the indirect dispatch's workgroups x, y, z).
@group(0) @binding(64) var<storage, read> surf: array<u32>;
@group(0) @binding(65) var<storage, read> surf_args: array<u32>;

fn kick(q: u32, rigid: bool) {
    if (!rigid) {
        vkick[q] = vkick[q] + dv[q] * (0.5 * ctl.dt);
    }
}

// The spring energy a particle's pass stores, for the observations (the
// leapfrog's booking stores the same energy its force passes would).
fn store_energy(p: u32, e: f32) {
    if (LEAP == 0u) {
        sr2c[p].x = e;
    } else if (LEAP != 2u) {
        nbo[p].w = e;
    }
}

// Where boundary particle p's entries are (see the header).
fn slot(p: u32) -> u32 {
    if (LEAP == 2u) {
        return u32(nbo[p].w);
    }
    return p;
}

// Whether this leapfrog step's list of boundary particles overflowed.
fn overflowed() -> bool {
    return LEAP == 2u && surf_args[0] > params.surf_cap;
}

// Kernel weight of the candidate pair (p, q) with normals np, nq and
// d = x_q - x_p, or a negative value when q is not a contact candidate of
// p (METHOD.md §8.2). Both passes call it with the same arguments in the same order, so
// both see the same weight.
fn candidate(np: vec2<f32>, nq: vec2<f32>, d: vec2<f32>, op: f32, oq: f32, hp: f32, hq: f32) -> f32 {
    let hpq = 0.5 * (hp + hq);
    let dist = length(d);
    if (dist >= 2.0 * hpq) {
        return -1.0;
    }
    if (dot(np, nq) >= 0.0) {
        return -1.0;
    }
    if (max(dot(np, d), -dot(nq, d)) > op + oq + hpq) {
        return -1.0;
    }
    return kernel_w(dist, hpq);
}

// Penalty spring stiffness: the two surface layers (thickness o, at least
// spacing/4) in series, a rigid side adding no compliance.
// CPU twin: cpu::contact::spring_stiffness.
fn layer(o: f32, b: Body) -> f32 {
    if (b.rigid != 0u) {
        return 0.0;
    }
    return max(o, 0.25 * b.spacing) / b.modulus;
}

// Series combination, a rigid side counting as infinite (METHOD.md §8.5).
fn series(a: f32, ra: bool, b: f32, rb: bool) -> f32 {
    if (ra) {
        return b;
    }
    if (rb) {
        return a;
    }
    return a * b / (a + b);
}

// The particles a thread of a contact pass handles: in a leapfrog step
// (LEAP >= 2) the boundary particles the kinematics pass listed (`surf`), one a thread
// and a workgroup a `WG` of them (the forces pass sized the indirect dispatch), or,
// where the list overflowed, every particle; otherwise one particle a
// thread, every particle. A thread strides past the most workgroups a
// dispatch may have. Only boundary particles (nbo.z > 0) take part: the
// others' entries are left as they are, and their readers look at the
// boundary flag first (reduce.wgsl; advance.wgsl for qrate).
fn contact_walkers(gid: vec3<u32>, nwg: vec3<u32>, pass2: bool) {
    if (LEAP >= 2u) {
        // A leapfrog step of zero length leaves everything as it is.
        if (ctl.dt == 0.0) {
            return;
        }
        let count = surf_args[0];
        let listed = count <= params.surf_cap;
        // The force passes' pass 1 stores nothing where the list
        // overflowed (pass 2 makes the entries again).
        if (LEAP == 2u && !listed && !pass2) {
            return;
        }
        let end = select(params.n, count, listed);
        for (var k = gid.x; k < end; k += nwg.x * WG) {
            var p = k;
            if (listed) {
                p = surf[k];
            } else if (nbo[p].z <= 0.0) {
                continue;
            }
            if (pass2) {
                pass2_at(p);
            } else {
                pass1_at(p);
            }
        }
        return;
    }
    let p = flat_index(gid, nwg);
    if (p >= params.n) {
        return;
    }
    if (pass2) {
        pass2_at(p);
    } else {
        pass1_at(p);
    }
}

@compute @workgroup_size(WG)
fn contact_pass1(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    contact_walkers(gid, nwg, false);
}

@compute @workgroup_size(WG)
fn contact_pass2(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    contact_walkers(gid, nwg, true);
}

// Pass 1's entries of a particle: its own force and booked heat and its
// partner body (`own`), the share per unit weight it leaves its partners and
// its spring power (`share`), and the spring energy it stores.
struct Entries {
    own: vec4<f32>,
    share: vec4<f32>,
    stored: f32,
}

// Pass 1 at particle p: its entries (a particle off the boundary: no
// partner, nothing else). `count`: whether a particle that meets two partner
// bodies is counted (once an evaluation).
fn entries(p: u32, count: bool) -> Entries {
    // w: the partner body as a float (exact for any realistic count), -1: none.
    var e = Entries(vec4<f32>(0.0, 0.0, 0.0, -1.0), vec4<f32>(0.0), 0.0);
    let np4 = nbo[p];
    if (np4.z <= 0.0) {
        return e;
    }
    let mp = pinfo[p];
    let bp = mp.z;
    let bodyp = bodies[bp];
    let op = bitcast<f32>(mp.y);
    let np = np4.xy;

    var partner = NONE;
    var multi = false;
    var sw = 0.0;
    var sws = vec2<f32>(0.0);
    var swn = vec2<f32>(0.0);
    var swv = vec2<f32>(0.0);
    var swt = 0.0;
    var swo = 0.0;
    var swb = vec2<f32>(0.0);
    let cs = consts();
    let wk = walker(p);
    let hp = bodyp.h;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let q = cd.j;
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let mq = pinfo[q];
            let nq4 = nbo[q];
            if (mq.z == bp || nq4.z <= 0.0) {
                continue;
            }
            let oq = bitcast<f32>(mq.y);
            // x_q - x_p.
            let d = -cd.d;
            let nq = nq4.xy;
            let w = candidate(np, nq, d, op, oq, hp, bodies[mq.z].h);
            if (w < 0.0) {
                continue;
            }
            if (partner == NONE) {
                partner = mq.z;
            } else if (mq.z != partner) {
                multi = true;
                continue;
            }
            // s_q - S_P, formed from the precise centre difference.
            let rel = d + nq * oq - np * op;
            sw += w;
            sws += rel * w;
            swn += nq * w;
            swv += v[q] * w;
            if (LEAP == 3u) {
                swb += vbook[q] * w;
            }
            swt += dot(nq, -rel) * w;
            swo += oq * w;
        }
    }
    if (multi && count) {
        atomicAdd(&ctl.multi_partner, 1u);
    }
    if (partner == NONE || sw <= 0.0) {
        return e;
    }
    let nlen = length(swn);
    if (nlen <= 0.0) {
        return e;
    }
    let nbar = swn / nlen;
    let rr = sws / sw;
    let vrel = v[p] - swv / sw;
    // Contact normal: of n_P, -nbar and their bisector, the one with the
    // largest projected distance (least penetration; METHOD.md §8.2).
    var n = np;
    var chord = dot(np, rr);
    let c1 = -nbar;
    if (dot(c1, rr) > chord) {
        n = c1;
        chord = dot(c1, rr);
    }
    let bis = np - nbar;
    let bl = length(bis);
    if (bl > 0.0) {
        let c2 = bis / bl;
        if (dot(c2, rr) > chord) {
            n = c2;
            chord = dot(c2, rr);
        }
    }
    let gap = 0.5 * (chord + swt / sw);
    // Round-off counts as touching (CPU twin: cpu::contact::touching).
    if (gap > 1e-5 * bodyp.spacing) {
        e.own.w = f32(partner);
        return e;
    }
    let delta = max(-gap, 0.0);
    let w_rate = dot(vrel, n);
    let bodyq = bodies[partner];
    let pr = bodyp.rigid != 0u;
    let qr = bodyq.rigid != 0u;
    if (pr && qr) {
        // Two rigid bodies move as prescribed: nothing to push.
        e.own.w = f32(partner);
        return e;
    }
    let z = series(bodyp.z, pr, bodyq.z, qr);
    let stiffness = 1.0 / (layer(op, bodyp) + layer(swo / sw, bodyq));
    let pres = max(z * w_rate + stiffness * delta, 0.0);
    let a = area[p];
    // The rate the heat and the spring power are booked at: the forces'
    // own, or the leapfrog's v_{n+1}.
    var w_book = w_rate;
    if (LEAP == 3u) {
        w_book = dot(vbook[p] - swb / sw, n);
    }
    let heat = 0.5 * (pres - stiffness * delta) * a * w_book;
    let stored = 0.25 * stiffness * delta * delta * a;
    var own_heat = heat;
    var eta = 0.0;
    if (pr) {
        own_heat = 0.0;
        eta = heat / sw;
    }
    e.own = vec4<f32>(-n * (0.5 * pres * a), own_heat, f32(partner));
    // w: the spring power 1/2 k delta A w of this pass (the spring-work ledger).
    e.share = vec4<f32>(n * (0.5 * pres * a / sw), eta, 0.5 * stiffness * delta * a * w_book);
    e.stored = stored;
    return e;
}

// Pass 1 at particle p: its entries stored. A leapfrog step counts
// particles with two partners at its booking alone.
fn pass1_at(p: u32) {
    let e = entries(p, LEAP != 2u);
    let k = slot(p);
    cown[k] = e.own;
    cshare[k] = e.share;
    store_energy(p, e.stored);
}

// Boundary particle p's entries for pass 2: stored by pass 1, or made again.
fn entries_of(p: u32) -> Entries {
    if (overflowed()) {
        return entries(p, false);
    }
    let k = slot(p);
    return Entries(cown[k], cshare[k], 0.0);
}

// Pass 2 at particle q.
fn pass2_at(q: u32) {
    // A particle off the boundary has no contact rates: the ledger reads
    // qrate (which holds the neighbour masks for part of a step;
    // gpu::mask_home) only behind the boundary flag (advance.wgsl).
    if (nbo[q].z <= 0.0) {
        return;
    }
    let mq = pinfo[q];
    let bq = mq.z;
    let bodyq = bodies[bq];
    let oq = bitcast<f32>(mq.y);
    var f = vec2<f32>(0.0);
    var heat = 0.0;
    let cs = consts();
    let wk = walker(q);
    let nq = nbo[q].xy;
    let hq = bodyq.h;
    let fbq = f32(bq);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let p = cd.j;
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let mp = pinfo[p];
            let np4 = nbo[p];
            if (mp.z == bq || np4.z <= 0.0) {
                continue;
            }
            let w = candidate(np4.xy, nq, cd.d, bitcast<f32>(mp.y), oq, bodies[mp.z].h, hq);
            if (w < 0.0) {
                continue;
            }
            let ep = entries_of(p);
            if (ep.own.w != fbq) {
                continue;
            }
            let sh = ep.share;
            f += sh.xy * w;
            heat += sh.z * w;
        }
    }
    let eq = entries_of(q);
    let own = eq.own;
    let total = own.xy + f;
    let booked = own.z + heat;
    let m = bitcast<f32>(mq.x);
    // (dashpot heat, spring power) of the particle's passes; a rigid
    // particle books no heat.
    let rates = vec2<f32>(select(booked, 0.0, bodyq.rigid != 0u), eq.share.w);
    if (LEAP >= 2u) {
        if (LEAP == 2u) {
            if (bodyq.rigid == 0u) {
                dv[q] += total / m;
            }
            kick(q, bodyq.rigid != 0u);
        } else {
            // The heat after the energy walk's pair work (forces.wgsl).
            dr[q].y = dr[q].y + rates.x / m;
            qheat_w[q] = qheat_w[q] + rates * (0.5 * ctl.dt);
            qrate[q] = rates;
        }
        return;
    }
    if (LEAP == 1u) {
        qrate[q] = rates;
    }
    if (bodyq.rigid == 0u) {
        // Rates at the base state, dt x rate at the midpoint (MID; a
        // zero-length step leaves the state as it is).
        if (!MID) {
            dv[q] += total / m;
            dr[q].y += booked / m;
        } else if (ctl.dt != 0.0) {
            dv[q] += total * (ctl.dt / m);
            dr[q].y += booked * (ctl.dt / m);
        }
    }
    if (MID && ctl.dt != 0.0) {
        // A rigid particle books no heat (rates.x is 0) but its passes'
        // springs still do work.
        qheat_w[q] = qheat_w[q] + rates * ctl.dt;
    }
}
