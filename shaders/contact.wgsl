// Penalty contact (docs/method.md §8), two gathers (four with friction:
// the rub pass and its gather, at the end of this file), no atomics.
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
// The leapfrog (common.wgsl, LEAP) runs the passes twice a step: for the
// forces at the predicted velocity (LEAP = 2: `v` is vstar, `dv` the carried
// a_{n+1}; pass 2 then kicks its particles to v_{n+1}), then for the
// booking (LEAP = 3), after the energy walk: the same forces, their
// dashpot heat and spring power at v_{n+1} (`vbook`), the heat added to
// dr.y and the ledger advanced by half a step (CPU twin:
// cpu::contact::penalty_booked); only the booking stores the spring
// energy, since the energy walk before it still reads sr2c
// (store_energy). Without a rigid body the booking's pass 1 books alone.
//
// Where pass 1 leaves a particle's entries: what only boundary particles
// carry (the normals, the spring's derivative, dPhi/dg for the spread) at
// the particle's place on the list of boundary particles that the
// kinematics pass made (kinematics.wgsl, list_surface; `place`); the
// nominal force and the dashpot shares (`cown`, `cshare`) in the midpoint
// rule and the leapfrog's first evaluation and booking at the particle, in
// pass scratch no later pass of the evaluation reads (gpu::contact_homes),
// and in the leapfrog's force passes (LEAP = 2), before the energy walk has
// read that scratch, and in the midpoint's second evaluation where the
// supports' gradient is kept in it, on the list too (`on_list`).

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(13) var<storage, read_write> nbo: array<vec4<f32>>;
@group(0) @binding(16) var<storage, read_write> dr: array<vec2<f32>>;
@group(0) @binding(18) var<storage, read_write> dv: array<vec2<f32>>;
@group(0) @binding(19) var<storage, read> area: array<f32>;
@group(0) @binding(20) var<storage, read_write> cown: array<vec4<f32>>;
@group(0) @binding(21) var<storage, read_write> cshare: array<vec4<f32>>;
// `x`: the spring energy each particle's pass stores (observations,
// store_energy). The kinematics pass writes sr2c and the forces pass (the
// leapfrog's energy walk) reads it, last; the reductions after this
// evaluation read only its `w` (sound speed) and this `x`; no other thread
// touches a particle's entry in these passes.
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
// The list of boundary particles (kinematics.wgsl, list_surface) and its
// (count, the indirect dispatch's workgroups x, y, z).
@group(0) @binding(64) var<storage, read> surf: array<u32>;
@group(0) @binding(65) var<storage, read> surf_args: array<u32>;
// The contact normals and their turning rates (forces.wgsl), on the list.
@group(0) @binding(66) var<storage, read> cn: array<vec4<f32>>;
// Pass 1 -> pass 2, on the list (Entries).
@group(0) @binding(67) var<storage, read_write> cbar0: array<vec4<f32>>;
@group(0) @binding(68) var<storage, read_write> cbar1: array<vec4<f32>>;
@group(0) @binding(69) var<storage, read_write> ckeep: array<vec4<f32>>;
// Pass 2 -> the spread (spread.wgsl): each boundary particle's dPhi/dg, the
// derivative through its colour gradient, as beta perp(n) (pass2_at), on
// the list; and a bit a particle, set where the spread has a force to
// gather.
@group(0) @binding(70) var<storage, read_write> bt: array<f32>;
@group(0) @binding(72) var<storage, read_write> claim: array<atomic<u32>>;
// Each particle's entry overlap (State::entry; -1: off the boundary at the
// last base state): the overlap it had when it joined the surface, which
// its spring does not push against. Written at the base evaluations (the
// midpoint rule's first, the leapfrog's force passes; the forces pass
// marks the particles off the boundary).
@group(0) @binding(74) var<storage, read_write> centry: array<f32>;

// Coulomb friction (RUB; docs/method.md §8.6). Each particle's elastic
// slip, by original index (never permuted): (u at the state, the spring
// f A k_t of the pass that last held it (negative while that pass slid),
// u at the midpoint (MID), the frictional heat booked so far). The
// advance passes move it, return it and book the heat (advance.wgsl).
// In a leapfrog step the state's u is u_{n+1/2}, which its passes at n+1
// look half a step ahead from.
@group(0) @binding(96) var<storage, read> slip: array<vec4<f32>>;
// Each particle's friction in this evaluation, by original index: the
// spring c = f A k_t (negative where the pass slides), the largest elastic
// slip the limit allows, the slip rate and the frictional heat rate; what
// the advance passes move and return the slip with (the leapfrog carries
// its booking's to the next step's first half). Written at boundary
// particles; its readers look at the boundary flag first.
@group(0) @binding(97) var<storage, read_write> frub: array<vec4<f32>>;
// Pass 1 -> the rub pass, on the list (Entries::rub0, rub1).
@group(0) @binding(98) var<storage, read_write> crub0: array<vec4<f32>>;
@group(0) @binding(99) var<storage, read_write> crub1: array<vec4<f32>>;
// The rub pass -> its gather and the reductions, by original index (the
// leapfrog's next step's reductions read its booking's): the force per
// unit weight a particle hands its partner's candidates, its friction
// force f tau A and A |slip rate|.
@group(0) @binding(100) var<storage, read_write> crubo: array<vec4<f32>>;
// The Coulomb coefficients (sliding, static) of each pair of bodies, a row
// a body (Model::friction_between).
@group(0) @binding(101) var<storage, read> coulomb: array<vec2<f32>>;

fn kick(q: u32, rigid: bool) {
    if (!rigid) {
        vkick[q] = hold(q, vkick[q] + dv[q] * (0.5 * ctl.dt));
    }
}

// The spring energy a particle's pass stores, for the observations, in
// sr2c.x, which no later pass of the evaluation reads (the leapfrog's
// force passes store none: the energy walk after them reads sr2c; its
// booking stores the same energy they would).
fn store_energy(p: u32, e: f32) {
    if (LEAP != 2u) {
        sr2c[p].x = e;
    }
}

// Boundary particle p's place on the list (kinematics.wgsl, list_surface).
fn place(p: u32) -> u32 {
    return u32(nbo[p].w);
}

// Whether the `own` and `share` entries go on the list: in the leapfrog's
// force passes, and in the midpoint's second evaluation where its pass
// scratch (`gradv`) carries the supports' gradient on to the step's end
// (`LGRAD` off).
fn on_list() -> bool {
    return LEAP == 2u || (MID && ADAPT && !LGRAD);
}

// Where boundary particle p's `own` and `share` entries are (the header).
fn own_at(p: u32) -> u32 {
    if (on_list()) {
        return place(p);
    }
    return p;
}

// Kernel weight W of the candidate pair (p, q) with normals np, nq and
// d = x_q - x_p, with (dW/dr)/r (so grad_P W = -d times it), or a negative
// weight when q is not a contact candidate of p (docs/method.md §8.2). Both
// passes call it with the same arguments in the same order, so both see
// the same weight.
// gp, gq are the two particles' ramp_measure: the weight is ramped by how
// far each stands above the boundary threshold; sq is q's plane_share.
// CPU twin: cpu::contact::is_candidate, surface_ramp.
fn candidate(np: vec2<f32>, nq: vec2<f32>, d: vec2<f32>, op: f32, oq: f32, hp: f32, hq: f32, gp: f32, gq: f32, sq: f32) -> vec2<f32> {
    let hpq = 0.5 * (hp + hq);
    let dist = length(d);
    if (dist >= 2.0 * hpq || dot(np, nq) >= 0.0 || max(dot(np, d), -dot(nq, d)) > op + oq + hpq) {
        return vec2<f32>(-1.0, 0.0);
    }
    var r = 1.0;
    if (DIM != 1u) {
        r = surface_ramp(gp) * surface_ramp(gq);
        if (ONPLANE) {
            // A candidate on a symmetry plane weighs its share; its image,
            // met as a candidate too, the rest.
            r *= sq;
        }
        if (r <= 0.0) {
            return vec2<f32>(-1.0, 0.0);
        }
    }
    return vec2<f32>(kernel_w(dist, hpq), kernel_dw(dist, hpq) / dist) * r;
}

// What the surface ramp reads of boundary particle p, of support h and
// normal entry c (cn): h |grad psi0|, in a body of revolution the boundary
// test's own measure (nbo.z, kinematics.wgsl surface_of).
// CPU twin: cpu::contact::ramp_measure.
fn ramp_measure(p: u32, h: f32, c: vec4<f32>) -> f32 {
    if (AXI) {
        return nbo[p].z;
    }
    return h * c.z;
}

// 0 at the boundary threshold, 1 from 1.5 times it (cpu::contact::surface_ramp).
fn surface_ramp(hg: f32) -> f32 {
    let t = params.boundary_threshold;
    return clamp((hg - t) / (0.5 * t), 0.0, 1.0);
}

// Penalty spring stiffness: the two surface layers (thickness o, at least
// spacing/4) in series, a rigid side adding no compliance.
// CPU twin: physics::penalty::spring_stiffness.
fn layer(o: f32, b: Body) -> f32 {
    if (b.rigid != 0u) {
        return 0.0;
    }
    return max(o, 0.25 * b.spacing) / b.modulus;
}

// Series combination, a rigid side counting as infinite (docs/method.md §8.5).
fn series(a: f32, ra: bool, b: f32, rb: bool) -> f32 {
    if (ra) {
        return b;
    }
    if (rb) {
        return a;
    }
    return a * b / (a + b);
}

// The entries (first, end, stride) a thread of a contact pass handles, each
// the particle `walked` names: in a leapfrog step (LEAP >= 2) the boundary
// particles the kinematics pass listed (`surf`), one a thread and a
// workgroup a `WG` of them (the forces pass sized the indirect dispatch);
// otherwise one particle a thread, every particle. A thread strides past
// the most workgroups a dispatch may have. Only
// boundary particles (nbo.z > 0) take part: the others' entries are left
// as they are, and their readers look at the boundary flag first
// (reduce.wgsl; advance.wgsl for qrate).
fn contact_walkers(gid: vec3<u32>, nwg: vec3<u32>) -> vec3<u32> {
    if (zero_length_pass()) {
        return vec3<u32>(0u, 0u, 1u);
    }
    if (LEAP >= 2u) {
        return vec3<u32>(gid.x, min(surf_args[0], params.surf_cap), nwg.x * WG);
    }
    let p = flat_index(gid, nwg);
    return vec3<u32>(p, min(p + 1u, params.n), 1u);
}

// The particle of entry k of a range of `contact_walkers`.
fn walked(k: u32) -> u32 {
    if (LEAP >= 2u) {
        return surf[k];
    }
    return k;
}

// Each pass its own entry point, so that each binds only the buffers it
// reads (the union would pass a software adapter's 32).
@compute @workgroup_size(WG)
fn contact_pass1(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let r = contact_walkers(gid, nwg);
    for (var k = r.x; k < r.y; k += r.z) {
        pass1_at(walked(k));
    }
}

@compute @workgroup_size(WG)
fn contact_pass2(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let r = contact_walkers(gid, nwg);
    for (var k = r.x; k < r.y; k += r.z) {
        pass2_at(walked(k));
    }
}

// With friction (RUB): the rub pass, then its gather, after pass 2.
@compute @workgroup_size(WG)
fn contact_rub(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let r = contact_walkers(gid, nwg);
    for (var k = r.x; k < r.y; k += r.z) {
        rub_at(walked(k));
    }
}

@compute @workgroup_size(WG)
fn contact_rub_gather(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let r = contact_walkers(gid, nwg);
    for (var k = r.x; k < r.y; k += r.z) {
        rub_gather_at(walked(k));
    }
}

// The leapfrog's booking of particle q's (dashpot heat, spring power): the
// heat after the energy walk's pair work (forces.wgsl), the ledger's second
// half step, and the rates its next step's first half step takes.
fn book(q: u32, rates: vec2<f32>) {
    dr[q].y = dr[q].y + rates.x / bitcast<f32>(pinfo[q].x);
    qheat_w[q] = qheat_w[q] + rates * (0.5 * ctl.dt);
    qrate[q] = rates;
}

// The velocity the ledger books at.
fn v_book(q: u32) -> vec2<f32> {
    if (LEAP == 3u) {
        return vbook[q];
    }
    return v[q];
}

// Pass 1 at particle p: its entries stored. A leapfrog step counts
// particles with two partners at its booking alone.
fn pass1_at(p: u32) {
    let e = entries(p, LEAP != 2u);
    if (!MID && LEAP != 3u && nbo[p].z > 0.0) {
        centry[p] = e.entry;
    }
    if (RUB && nbo[p].z > 0.0) {
        let k = place(p);
        crub0[k] = e.rub0;
        crub1[k] = e.rub1;
    }
    if (LEAP == 3u && !RIGID) {
        // The booking without rigid bodies: no partner hands this particle
        // heat, so its own pass books everything pass 2 would.
        if (nbo[p].z > 0.0) {
            book(p, vec2<f32>(e.own.z, e.share.w));
        }
        // The observations read the pass's nominal force.
        cown[p] = e.own;
        store_energy(p, e.stored);
        return;
    }
    // Only boundary particles have a place on the list, and only their
    // entries are read (pass2_at).
    if (!on_list() || nbo[p].z > 0.0) {
        cown[own_at(p)] = e.own;
        cshare[own_at(p)] = e.share;
    }
    if (nbo[p].z > 0.0) {
        let k = place(p);
        cbar0[k] = e.bar0;
        cbar1[k] = e.bar1;
        ckeep[k] = e.keep;
    }
    store_energy(p, e.stored);
}

// Boundary particle p's entries for pass 2, as pass 1 stored them.
fn entries_of(p: u32) -> Entries {
    let k = place(p);
    let o = own_at(p);
    return Entries(cown[o], cshare[o], cbar0[k], cbar1[k], ckeep[k], 0.0, 0.0, vec4<f32>(0.0), vec4<f32>(0.0));
}

// The weight (W, (dW/dr)/r) of the candidate pair of walker q (its
// meta `mq`, normal entry `cnq`) and the particle p its walk meets (`cd`,
// cd.d = x_q - x_p), where p is a boundary particle of body `partner` (NONE:
// of any body but q's) whose passes point at q's body; x < 0: no such
// pair. What every gather over a partner's candidate sets reads (pass 2,
// the rub's normal force and its gather).
fn partner_weight(q: u32, mq: vec4<u32>, cnq: vec4<f32>, cd: Cand, partner: u32) -> vec2<f32> {
    return pair_weight(q, mq, cnq, cnq.xy, cd.d, cd.j, partner);
}

// `partner_weight` of walker q, as p's pass saw it (q's normal `nq` and
// x_q - x_p `d`: its own, or its image's across a symmetry plane).
fn pair_weight(q: u32, mq: vec4<u32>, cnq: vec4<f32>, nq: vec2<f32>, d: vec2<f32>, p: u32, partner: u32) -> vec2<f32> {
    let mp = pinfo[p];
    if (mp.z == mq.z || (partner != NONE && mp.z != partner) || nbo[p].z <= 0.0) {
        return vec2<f32>(-1.0, 0.0);
    }
    let cp = cn[place(p)];
    let hp = bodies[mp.z].h;
    let hq = bodies[mq.z].h;
    let wg = candidate(cp.xy, nq, d, bitcast<f32>(mp.y), bitcast<f32>(mq.y), hp, hq, ramp_measure(p, hp, cp), ramp_measure(q, hq, cnq), plane_share(q));
    if (wg.x < 0.0 || cown[own_at(p)].w != f32(mq.z)) {
        return vec2<f32>(-1.0, 0.0);
    }
    return wg;
}

// x_q - x_p of the image under `flip` of walker q across the symmetry
// planes and candidate p at offsets `op` (`cd_d` = x_q - x_p): the same
// bits as p's pass forms (`image_sep`).
fn image_sep_of_walker(wk: Walker, flip: u32, op: vec2<f32>, cd_d: vec2<f32>) -> vec2<f32> {
    return mirror_vec(flip, image_d(wk, flip, op, cd_d));
}

// `partner_weight` of walker q's image under `flip` across the symmetry
// planes and the particle p its walk meets (`cd`), as p's pass saw that
// image: what the friction's gathers read of the passes that met it.
fn image_weight(q: u32, mq: vec4<u32>, cnq: vec4<f32>, wk: Walker, cd: Cand, flip: u32, partner: u32) -> vec2<f32> {
    let d = image_sep_of_walker(wk, flip, cd.off, cd.d);
    return pair_weight(q, mq, cnq, mirror_vec(flip, cnq.xy), d, cd.j, partner);
}

// What pass 2 gathers at particle q from the partners' passes over the
// candidate pairs they used: the dashpot shares and the spring's pull
// (`f`), the heat, and dPhi/dn_q through the partners' sums (`n_bar`).
// CPU twin: cpu::contact::Booking::pass2.
struct Gathered {
    f: vec2<f32>,
    heat: f32,
    n_bar: vec2<f32>,
}

fn gathered(q: u32, mq: vec4<u32>, wk: Walker, cnq: vec4<f32>) -> Gathered {
    var gt = Gathered(vec2<f32>(0.0), 0.0, vec2<f32>(0.0));
    let oq = bitcast<f32>(mq.y);
    let cs = consts();
    let nq = cnq.xy;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let wg = partner_weight(q, mq, cnq, cd, NONE);
            if (wg.x >= 0.0) {
                gather_from(&gt, 0u, cd.j, wg, cd.d, nq, oq);
            }
            for (var m = 0u; m < contact_images(); m++) {
                // Across the symmetry planes: p's pass as it saw q's
                // image, its force and the derivative by q's normal
                // mirrored back.
                let f = contact_flip(m);
                let d = image_sep_of_walker(wk, f, cd.off, cd.d);
                let nqi = mirror_vec(f, nq);
                let wi = pair_weight(q, mq, cnq, nqi, d, cd.j, NONE);
                if (wi.x >= 0.0) {
                    gather_from(&gt, f, cd.j, wi, d, nqi, oq);
                }
            }
        }
    }
    return gt;
}

// What q gathers from partner p's pass over their candidate pair of weight
// `wg` (W, (dW/dr)/r), as the pass saw q (x_q - x_p `d`, normal `nq`),
// mirrored back by `flip` where it saw q's image.
fn gather_from(gt: ptr<function, Gathered>, flip: u32, p: u32, wg: vec2<f32>, d: vec2<f32>, nq: vec2<f32>, oq: f32) {
    let w = wg.x;
    let np = cn[place(p)].xy;
    let op = bitcast<f32>(pinfo[p].y);
    let ep = entries_of(p);
    let sh = ep.share;
    (*gt).f += mirror_vec(flip, sh.xy * w);
    (*gt).heat += sh.z * w;
    if (ep.bar1.w > 0.0) {
        // s_q - S_P.
        let rel = d + nq * oq - np * op;
        let cb = cand_bar(ep.bar0, ep.bar1, w, rel, nq, oq);
        (*gt).f += mirror_vec(flip, -d * (wg.y * cb.w) - cb.x);
        (*gt).n_bar += mirror_vec(flip, cb.n);
    }
}

// `f0` plus the force on q of dPhi/dn_q (as `b` = beta perp(n_q)), in
// that order of summation: g_q moves with q
// against each neighbour j by V0_j grad grad W (and against j's image and
// its own in a body of revolution); q claims the neighbours, which gather
// the opposite pull in the spread (spread.wgsl). CPU twin: the spread of
// cpu::contact::Booking::pass2.
fn normal_pull(q: u32, mq: vec4<u32>, wk: Walker, b: vec2<f32>, f0: vec2<f32>) -> vec2<f32> {
    var f = f0;
    let bq = mq.z;
    let bodyq = bodies[bq];
    let hq = bodyq.h;
    let rho0 = bodyq.rho0;
    let cs = consts();
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let mj = pinfo[cd.j];
            let pr = body_pair(wk, cd, mj.z, span, hq, bq);
            if (!pr.inside || pr.dist <= 0.0) {
                continue;
            }
            let vol = spread_volume(mj, rho0);
            f += hess_times(pr.d, pr.dist, pr.hij, b) * vol;
            // And against j's images, which j moves the mirror way
            // (spread.wgsl).
            for (var m = 0u; m < image_count(); m++) {
                let im = image_pair(wk, m, cd.off, pr.d, pr.hij);
                if (im.inside) {
                    f += hess_times(im.d, im.dist, im.hij, b) * vol;
                }
            }
            claim_spread(cd.j);
        }
    }
    // Against its own images.
    for (var m = 0u; m < image_count(); m++) {
        let im = image_pair(wk, m, wk.off, vec2<f32>(0.0), hq);
        if (im.inside) {
            f += hess_times(im.d, im.dist, im.hij, b) * spread_volume(mq, rho0);
            claim_spread(q);
        }
    }
    return f;
}

// Pass 2 at particle q: the dashpot shares and the spring's derivative its
// partners left, over the candidate pairs they used; then dPhi/dn_q whole,
// which turns into forces through the colour gradient the normal is made
// from: on q here, on its neighbours through the spread (bt: dPhi/dn_q as
// beta perp(n_q) / |g_q|; q claims its neighbours, spread.wgsl).
fn pass2_at(q: u32) {
    // A particle off the boundary has no contact rates: the ledger reads
    // qrate (which holds the neighbour masks for part of a step;
    // gpu::mask_home) only behind the boundary flag (advance.wgsl).
    if (nbo[q].z <= 0.0) {
        return;
    }
    let mq = pinfo[q];
    let bodyq = bodies[mq.z];
    let wk = walker(q);
    let cnq = cn[place(q)];
    let nq = cnq.xy;
    let gt = gathered(q, mq, wk, cnq);
    var f = gt.f;
    let eq = entries_of(q);
    let own = eq.own;
    let n_bar = gt.n_bar + eq.keep.zw;
    var beta = 0.0;
    if (DIM == 2u && LEAP != 3u && bodyq.rigid == 0u && cnq.z > 0.0) {
        beta = dot(perp(nq), n_bar) / cnq.z;
    }
    if (LEAP != 3u) {
        bt[place(q)] = beta;
    }
    if (beta != 0.0) {
        f = normal_pull(q, mq, wk, perp(nq) * beta, f);
    }
    let total = eq.keep.xy + f;
    let booked = own.z + gt.heat;
    let m = bitcast<f32>(mq.x);
    // (dashpot heat, spring power) of the particle's passes; a rigid
    // particle books no heat.
    let rates = vec2<f32>(select(booked, 0.0, bodyq.rigid != 0u), eq.share.w);
    if (LEAP >= 2u) {
        if (LEAP == 2u) {
            if (bodyq.rigid == 0u) {
                dv[q] += total / m;
            }
            // With friction the rub's gather kicks, once the particle's
            // acceleration is whole.
            if (!RUB) {
                kick(q, bodyq.rigid != 0u);
            }
        } else {
            book(q, rates);
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
            let w0 = dv[q];
            let w1 = w0 + total * (ctl.dt / m);
            dv[q] = w1;
            dr[q].y += booked * (ctl.dt / m) + compatible_energy(w0, w1, v[q]);
        }
    }
    if (MID && ctl.dt != 0.0) {
        // A rigid particle books no heat (rates.x is 0) but its passes'
        // springs still do work.
        qheat_w[q] = qheat_w[q] + rates * ctl.dt;
    }
}

// The spread pass, where it is a pass of its own (the leapfrog, and the
// midpoint rule's base evaluation as a stage alone): each particle pass 2
// claimed gathers the spring's pull through its boundary neighbours'
// normals (spread.wgsl). The midpoint rule's steps gather it in their
// advance passes instead (advance.wgsl), so no variant at the midpoint.
@compute @workgroup_size(WG)
fn contact_spread(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let j = flat_index(gid, nwg);
    if (j >= params.n) {
        return;
    }
    let f = spread_force(j);
    if (all(f == vec2<f32>(0.0)) || (LEAP >= 2u && ctl.dt == 0.0)) {
        return;
    }
    let m = bitcast<f32>(pinfo[j].x);
    dv[j] += f / m;
    if (LEAP == 2u) {
        vkick[j] = hold(j, vkick[j] + f * (0.5 * ctl.dt / m));
    }
}

// The shear layer of a body's surface (thickness o, at least spacing/4)
// over its shear modulus, a rigid side adding no compliance (CPU twin:
// physics::penalty::spring_stiffness with cpu::contact::shear_constants).
fn shear_layer(o: f32, b: Body) -> f32 {
    if (b.rigid != 0u) {
        return 0.0;
    }
    return max(o, 0.25 * b.spacing) / b.g;
}

// Rates from a contact pass at particle q (not rigid): the force `f`, the
// heat `heat` and the springs' power `spring`, as pass 2 adds its own:
// the leapfrog's force passes (LEAP = 2) the force alone, its booking
// (LEAP = 3) the heat and the power alone, with the ledger's half step
// and the rates its next step's first half takes (`book`); the leapfrog's
// first evaluation (LEAP = 1) carries those rates too; the midpoint's
// second evaluation books them with the step.
fn add_rates(q: u32, f: vec2<f32>, heat: f32, spring: f32) {
    let m = bitcast<f32>(pinfo[q].x);
    if (LEAP == 3u) {
        let rates = vec2<f32>(heat, spring);
        dr[q].y = dr[q].y + heat / m;
        qheat_w[q] = qheat_w[q] + rates * (0.5 * ctl.dt);
        qrate[q] = qrate[q] + rates;
        return;
    }
    if (LEAP == 2u) {
        dv[q] += f / m;
        return;
    }
    if (LEAP == 1u) {
        qrate[q] = qrate[q] + vec2<f32>(heat, spring);
    }
    if (!MID) {
        dv[q] += f / m;
        dr[q].y += heat / m;
    } else if (ctl.dt != 0.0) {
        let w0 = dv[q];
        let w1 = w0 + f * (ctl.dt / m);
        dv[q] = w1;
        dr[q].y += heat * (ctl.dt / m) + compatible_energy(w0, w1, v[q]);
        qheat_w[q] = qheat_w[q] + vec2<f32>(heat, spring) * ctl.dt;
    }
}

// The normal force the passes of partner body `bq` apply at particle p,
// shared to p by weight over the candidate pairs they used (pass 1's
// rub1.w), as pass 2 gathers their dashpots' (CPU twin:
// cpu::contact::Booking::pass2, `normal`).
fn shared_normal(p: u32, mp: vec4<u32>, wk: Walker, cnp: vec4<f32>, bq: u32) -> f32 {
    var normal = 0.0;
    let cs = consts();
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let w = partner_weight(p, mp, cnp, cd, bq).x;
            if (w >= 0.0) {
                normal += crub1[place(cd.j)].w * w;
            }
            for (var m = 0u; m < contact_images(); m++) {
                // Across the symmetry planes: the passes that met p's
                // image.
                let wi = image_weight(p, mp, cnp, wk, cd, contact_flip(m), bq).x;
                if (wi >= 0.0) {
                    normal += crub1[place(cd.j)].w * wi;
                }
            }
        }
    }
    return normal;
}

// The rub pass at boundary particle p (CPU twin: cpu::contact::friction,
// `rub`): a spring on p's elastic slip and a dashpot on the relative
// tangential velocity, their traction held to the Coulomb limit mu N / A,
// N the normal force on p (its own pass's and its partner's shared to
// it). p keeps -f tau A t and hands +f tau A t to its candidates by
// weight (the gather); f is 1/2 against a deformable partner, which rubs
// back with the other half, 1 against a rigid one.
fn rub_at(p: u32) {
    if (nbo[p].z <= 0.0) {
        return;
    }
    let k = place(p);
    var hand = vec4<f32>(0.0);
    var fr = vec4<f32>(0.0);
    let mp = pinfo[p];
    let bodyp = bodies[mp.z];
    let own = cown[own_at(p)];
    let r0 = crub0[k];
    let r1 = crub1[k];
    if (bodyp.rigid == 0u && own.w >= 0.0 && r0.w > 0.0) {
        let bq = u32(own.w);
        let cnp = cn[k];
        let normal = r1.z + shared_normal(p, mp, walker(p), cnp, bq);
        let mu = coulomb[mp.z * arrayLength(&bodies) + bq];
        if (normal > 0.0 && mu.y > 0.0) {
            let bodyq = bodies[bq];
            let qr = bodyq.rigid != 0u;
            let t = perp(r0.xy);
            let a = area[area_index(p, nbo[p].w)];
            let f = select(0.5, 1.0, qr);
            let kt = 1.0 / (shear_layer(bitcast<f32>(mp.y), bodyp) + shear_layer(r0.z, bodyq));
            let zt = series(sqrt(bodyp.rho0 * bodyp.g), false, sqrt(bodyq.rho0 * bodyq.g), qr);
            let w = r1.x;
            let w_book = r1.y;
            let sl = slip[mp.w];
            // The sliding limit, and the limit a sticking pass holds to:
            // the static one unless the particle slid at the last return.
            let limit = mu.x * normal / a;
            var limit_held = mu.y * normal / a;
            if (sl.y < 0.0) {
                limit_held = limit;
            }
            var cap = 0.0;
            var cap_hold = 0.0;
            if (kt > 0.0) {
                cap = limit / kt;
                cap_hold = limit_held / kt;
            }
            var u0 = sl.x;
            if (MID) {
                u0 = sl.z;
            }
            // Sticking, the slip where it will be at n+1 in a leapfrog
            // step (u0 is u_{n+1/2}), where it is otherwise.
            if (LEAP >= 2u) {
                u0 += 0.5 * ctl.dt * w;
            }
            let c = f * a * kt;
            let u_stick = clamp(u0, -cap_hold, cap_hold);
            let trial = kt * u_stick + zt * w;
            let stick = abs(trial) <= limit_held;
            var tau = trial;
            var rate = w_book;
            var heat = 0.0;
            var spring = 0.0;
            if (stick) {
                // Sticking: the spring stores, the dashpot heats.
                let d = f * a * zt * w * w_book;
                heat = max(d, 0.0);
                spring = c * u_stick * w_book + min(d, 0.0);
            } else {
                // Sliding: the traction's work is heat, but where the
                // booking velocity has turned against it, which goes to
                // the spring's ledger so that heat is never negative.
                tau = select(-limit, limit, trial >= 0.0);
                rate = 0.0;
                let d = f * a * tau * w_book;
                heat = max(d, 0.0);
                spring = min(d, 0.0);
            }
            let force = t * (f * a * tau);
            add_rates(p, -force, heat, spring);
            hand = vec4<f32>(force / r0.w, f * a * tau, a * abs(w_book - rate));
            fr = vec4<f32>(select(-c, c, stick), select(cap, cap_hold, stick), rate, heat);
        }
    }
    crubo[mp.w] = hand;
    frub[mp.w] = fr;
}

// The rub's gather at boundary particle q (not rigid): the forces the
// particles rubbing on its body handed it, over exactly their candidate
// sets (CPU twin: cpu::contact::friction, `handed`).
fn rub_gather_at(q: u32) {
    let mq = pinfo[q];
    if (nbo[q].z <= 0.0 || bodies[mq.z].rigid != 0u) {
        return;
    }
    let wk = walker(q);
    let cnq = cn[place(q)];
    let cs = consts();
    var f = vec2<f32>(0.0);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let w = partner_weight(q, mq, cnq, cd, NONE).x;
            if (w >= 0.0) {
                f += crubo[pinfo[cd.j].w].xy * w;
            }
            for (var m = 0u; m < contact_images(); m++) {
                // Across the symmetry planes: what the particles whose
                // images met q's handed q's image, mirrored back.
                let fl = contact_flip(m);
                let wi = image_weight(q, mq, cnq, wk, cd, fl, NONE).x;
                if (wi >= 0.0) {
                    f += mirror_vec(fl, crubo[pinfo[cd.j].w].xy * wi);
                }
            }
        }
    }
    add_rates(q, f, 0.0, 0.0);
    if (LEAP == 2u) {
        kick(q, false);
    }
}
