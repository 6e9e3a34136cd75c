// The forces pass (docs/method.md §4): momentum and energy sums with the pair-symmetric
// corrected gradient G_ij = (L_i + L_j)/2 grad_i W_ij, Monaghan viscosity
// and, when the scene switches it on, artificial stress. With contact on it
// also measures each boundary particle's contact area (docs/method.md §8.4), and
// its contact normal from the colour gradient with reference volumes,
// g = -sum_j V0_j grad W, with how fast that normal turns at the walk's
// velocities (`cn`, for contact.wgsl).
// CPU twins: cpu::forces::momentum_energy, cpu::forces::boundary,
// cpu::contact::normal_rates.
//
// dv and dr.y take the rates at the base state (into the midpoint buffers)
// and dt x rate added in place to the base state at the midpoint
// (common.wgsl, MID). The leapfrog (common.wgsl, LEAP) runs it twice a
// step: at n+1 for the momentum alone (LEAP = 2; `v` is then the predicted
// velocity, `dv` the carried a_{n+1}), then, after the kick, for the energy
// alone (LEAP = 3): the same pair terms, the viscosity at the predicted
// velocity `vstar`, their work on v_{n+1} (`v`), into dr.y, to which the
// contact's booking then adds its heat (CPU twins:
// cpu::sweep::momentum_keeping and energy_replay, which keeps the pair
// terms instead of walking again).

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(12) var<storage, read> lmat: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read> nbo: array<vec4<f32>>;
@group(0) @binding(14) var<storage, read> sr2c: array<vec4<f32>>;
// The close-pair gate's spacing scales kappa^2, by original index (constant).
@group(0) @binding(15) var<storage, read> kappa: array<f32>;
@group(0) @binding(16) var<storage, read_write> dr: array<vec2<f32>>;
@group(0) @binding(18) var<storage, read_write> dv: array<vec2<f32>>;
@group(0) @binding(19) var<storage, read_write> area: array<f32>;
@group(0) @binding(36) var<storage, read> gradv: array<vec4<f32>>;
@group(0) @binding(53) var<storage, read> vstar: array<vec2<f32>>;
// The plastic history, for the damage (common.wgsl, FAILURE).
@group(0) @binding(76) var<storage, read> hist: array<vec4<f32>>;
// The neighbour mask the kinematics pass left (walk.wgsl; the leapfrog's).
@group(0) @binding(9) var<storage, read> nmask: array<vec2<u32>>;
// The momentum walk of a leapfrog step (LEAP = 2) kicks the state's
// velocity to v_{n+1} where a_{n+1} is whole, every particle the contact
// adds nothing to (contact.wgsl kicks the rest), and sizes the contact's
// dispatch over the list of boundary particles the kinematics pass made.
@group(0) @binding(57) var<storage, read_write> vkick: array<vec2<f32>>;
@group(0) @binding(65) var<storage, read_write> surf_args: array<u32>;
// Per boundary particle (contact), at its place on the list
// (kinematics.wgsl, list_surface): (n, |g|, omega), the contact normal
// n = g/|g| and its turning rate, dn/dt = omega perp(n).
@group(0) @binding(66) var<storage, read_write> cn: array<vec4<f32>>;
// Entry overlaps (contact.wgsl): a particle off the boundary at a base
// state has none.
@group(0) @binding(74) var<storage, read_write> centry: array<f32>;
// Bodies of revolution: the hoop stress's acceleration (kinematics.wgsl),
// and each particle's area as placed by original index (the contact
// normal's reference volumes).
@group(0) @binding(80) var<storage, read> hoop: array<f32>;
@group(0) @binding(81) var<storage, read> area0: array<f32>;
// The leapfrog step with the hourglass control: the velocity v_{n+1/2}
// the control sees and its gradient (kinematics.wgsl, kinematics_leap).
@group(0) @binding(87) var<storage, read> vhalf: array<vec2<f32>>;
@group(0) @binding(88) var<storage, read> gradh: array<vec4<f32>>;
// The artificial dissipation (DISS), per workgroup of particles: the
// work booked into the internal energies, a compensated sum (x + y), and
// in the leapfrog the rate of its last energy pass (z), whose second half
// the next step's energy pass books. A fixed-order tree per workgroup, no
// atomics; the host sums the workgroups in f64. CPU twin: State::dissipation.
@group(0) @binding(89) var<storage, read_write> dheat: array<vec4<f32>>;
var<workgroup> shd: array<f32, 256>;
// Whether this pass sums it: those that book energies (the midpoint's
// second evaluation, the leapfrog's energy walk) and the leapfrog's first
// evaluation, which keeps the rate for the first half kick.
override DISS_SUMS: bool = DISS && (MID || LEAP == 1u || LEAP == 3u);

// Workgroups of the contact's indirect dispatch (surf_args[1..4]): one a
// `WG` listed particles.
fn size_contact() {
    let walkers = min(surf_args[0], params.surf_cap);
    surf_args[1] = min((walkers + WG - 1u) / WG, params.surf_groups);
}

// mu = rho/rho0 - 1 of particle j: in a leapfrog step the n+1 value its
// kinematic pass left in the carried rates' free slot (dr.x).
fn mu_of(j: u32) -> f32 {
    if (LEAP >= 2u) {
        return dr[j].x;
    }
    return r[j].x;
}

// The density of the kernel sums of a particle of body `b` at radius `rj`:
// rho, or eta = 2 pi r rho in a body of revolution.
fn sum_density(b: Body, j: u32, rj: f32) -> f32 {
    let rho = b.rho0 * (1.0 + mu_of(j));
    if (AXI) {
        return circumference(rj) * rho;
    }
    return rho;
}

// V0_j of the contact normal's colour gradient: m_j / rho0, its area as
// placed in a body of revolution (Model::reference_volume).
fn reference_volume(mj: vec4<u32>, rho0: f32) -> f32 {
    if (AXI) {
        return area0[mj.w];
    }
    return bitcast<f32>(mj.x) / rho0;
}

// Whether particle j has not failed and has no void open.
fn intact(j: u32) -> bool {
    // The guard keeps scenes that cannot fail from reading the history.
    return !(FAILURE || CAVITATION) || !failed(damage_seen(hist[j]));
}

// The pairs of i and the mirror images of its partner j (pair `pr`, j at
// radius `rj` and offsets `oj`) across the axis of a body of revolution
// and a symmetry plane, where they are within reach.
fn add_images(o: Own, wk: Walker, j: u32, mj: vec4<u32>, pr: Pair, rj: f32, oj: vec2<f32>, sums: ptr<function, Sums>) {
    for (var m = 0u; m < image_count(); m++) {
        let im = image_pair(wk, m, oj, pr.d, pr.hij);
        if (im.inside) {
            add_pair(o, j, mj, im, image_flip(m), rj, sums);
        }
    }
}

// The walk of `forces` where supports adapt: each candidate's pair in its
// mean metric (and in a body of revolution the pair with its image, whose
// metric is mirrored) to the momentum and energy sums, its round pair and
// round image to the boundary's sums; then the walker's own images. CPU
// twins: cpu::forces::momentum_energy, cpu::forces::boundary.
fn adaptive_forces(own: Own, wk: Walker, i: u32, mi: vec4<u32>, cs: Consts, sums: ptr<function, Sums>) {
    let bi = mi.z;
    let hi = own.hi;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span_in(wk.hm, row, wk.reach);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let j = cd.j;
            let mj = pinfo[j];
            if (j == i || !in_row(cd.cell, span) || (CONTACT && mj.z != bi)) {
                continue;
            }
            let round = body_pair(wk, cd, mj.z, span, hi, bi);
            if (round.inside) {
                add_boundary(own, j, mj, round, 0u, sums);
                for (var m = 0u; m < image_count(); m++) {
                    let ri = image_pair(wk, m, cd.off, round.d, round.hij);
                    if (ri.inside) {
                        add_boundary(own, j, mj, ri, image_flip(m), sums);
                    }
                }
            }
            let pr = sph_pair(wk, cd, mj.z, span, hi, bi);
            if (pr.inside) {
                add_sph(own, j, mj, pr, 0u, cd.rad, sums);
            }
            if (image_count() > 0u) {
                let qj = support_of(j, body_h(hi, mj.z));
                for (var m = 0u; m < image_count(); m++) {
                    let img = image_pair_metric(wk, m, cd.off, cd.d, qj, hi);
                    if (img.inside) {
                        add_sph(own, j, mj, img, image_flip(m), cd.rad, sums);
                    }
                }
            }
        }
    }
    for (var m = 0u; m < image_count(); m++) {
        let own_round = image_pair(wk, m, wk.off, vec2<f32>(0.0), hi);
        if (own_round.inside) {
            add_boundary(own, i, mi, own_round, image_flip(m), sums);
        }
    }
    for (var m = 0u; m < image_count(); m++) {
        let own_img = image_pair_metric(wk, m, wk.off, vec2<f32>(0.0), wk.q, hi);
        if (own_img.inside) {
            add_sph(own, i, mi, own_img, image_flip(m), wk.rad, sums);
        }
    }
}

@compute @workgroup_size(WG)
fn forces(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let d = forces_of(flat_index(gid, nwg));
    if (DISS_SUMS) {
        book_dissipation(lid.x, wid.x + wid.y * nwg.x, d);
    }
}

// The workgroup's artificial dissipation rate (particle i's `d`, summed in
// a fixed tree), booked as the step books the internal energies: the
// midpoint rule's second evaluation for dt; the leapfrog's energy pass
// for its half step, with the half step of the last pass's rate that
// this step's first kick booked; its first evaluation only keeps the rate.
fn book_dissipation(lid: u32, w: u32, d: f32) {
    shd[lid] = d;
    workgroupBarrier();
    for (var s = WG / 2u; s > 0u; s = s / 2u) {
        if (lid < s) {
            shd[lid] += shd[lid + s];
        }
        workgroupBarrier();
    }
    if (lid != 0u || w * WG >= params.n || zero_length_pass()) {
        return;
    }
    let rate = shd[0];
    var b = dheat[w];
    if (MID) {
        b = vec4<f32>(two_sum(b.xy, rate * ctl.dt), b.zw);
    } else if (LEAP == 3u) {
        b = vec4<f32>(two_sum(b.xy, (b.z + rate) * (0.5 * ctl.dt)), rate, 0.0);
    } else if (LEAP == 1u) {
        b.z = rate;
    }
    dheat[w] = b;
}

// What particle i's pair terms read of it (`Own`), its density rho_i (eta_i
// in a body of revolution, `sum_density`) among them. CPU twin:
// cpu::forces::Side::of.
fn own_of(i: u32, mi: vec4<u32>, body: Body, boundary: bool, surface: bool, rad: f32) -> Own {
    var gi = vec4<f32>(0.0);
    if (RECON || HG > 0.0) {
        gi = gradv[i];
    }
    let rho_i = sum_density(body, i, rad);
    var ti = sr2c[i];
    var flows_i = false;
    if (ART_FLOW) {
        flows_i = ti.w < 0.0;
        ti.w = abs(ti.w);
    }
    var ri = vec4<f32>(0.0);
    if (ART_STRESS && body.art != 0u) {
        ri = art_of(ti);
    }
    var k2i = 1.0;
    if (ART_KAPPA) {
        k2i = kappa[mi.w];
    }
    var vsi = vec2<f32>(0.0);
    if (LEAP == 3u) {
        vsi = vstar[i];
    }
    var vhi = v[i];
    var ghi = gi;
    if (HG_HALF) {
        vhi = vhalf[i];
        ghi = gradh[i];
    }
    return Own(
        body,
        body.h,
        body.rigid != 0u,
        boundary,
        surface,
        lmat[i],
        ti,
        v[i],
        vsi,
        gi,
        vhi,
        ghi,
        rho_i,
        bitcast<f32>(mi.x) / rho_i,
        k2i,
        ri,
        intact(i),
        flows_i,
        params.alpha,
        params.beta,
        plane_share(i),
    );
}

// i's sums over its pairs (and their images across the axis): the pairs
// of the kinematics pass's masks where they hold, else the walk's. CPU
// twin: cpu::forces::rates_and_dissipation (one particle's sums).
fn pair_sums(own: Own, wk: Walker, i: u32, mi: vec4<u32>, adapt: bool) -> Sums {
    let cs = consts();
    let hi = own.hi;
    // A particle on a symmetry plane counts for its share here, its image
    // for the rest.
    var sw0 = kernel_w(0.0, hi);
    if (ONPLANE) {
        sw0 *= own.share;
    }
    var sums = Sums(vec2<f32>(0.0), 0.0, sw0, vec2<f32>(0.0), vec2<f32>(0.0), 0.0);
    var mask = vec2<u32>(0u, MASK_FULL);
    // Where supports adapt the walk's rows are the walker's own
    // (`adaptive_forces`), which the masks' row map does not follow; while
    // every support is round the walks and their stencil are round
    // (`adapting`, walk.wgsl `stencil`) and the masks hold.
    if (LEAP != 0u && !adapt) {
        mask = nmask[i];
    }
    if (adapt) {
        adaptive_forces(own, wk, i, mi, cs, &sums);
    } else if ((mask.y & MASK_FULL) == 0u) {
        // The pairs the kinematics pass found, in walk order (walk.wgsl).
        let rm = row_map(wk.hm);
        loop {
            let o = mask_next(&mask);
            if (o >= 64u) {
                break;
            }
            let k = row_place(rm, o);
            let j = sorted_at(k, cs);
            let mj = pinfo[j];
            let pr = pair_at(pair_d(wk, j, cs), pair_h(hi, mj.z));
            var oj = vec2<f32>(0.0);
            if (image_count() > 0u) {
                oj = offsets_of(j);
            }
            // Its radius: the offset from the axis (0 in plane strain).
            var rj = 0.0;
            if (AXI) {
                rj = oj.x;
            }
            add_pair(own, j, mj, pr, 0u, rj, &sums);
            add_images(own, wk, j, mj, pr, rj, oj, &sums);
        }
    } else {
        for (var row = 0u; row < scan_rows(); row++) {
            let span = row_span(wk.hm, row);
            for (var k = span.start; k < span.end; k++) {
                let cd = cand(wk, k, cs);
                let mj = pinfo[cd.j];
                let pr = body_pair(wk, cd, mj.z, span, hi, mi.z);
                if (pr.inside) {
                    add_pair(own, cd.j, mj, pr, 0u, cd.rad, &sums);
                    add_images(own, wk, cd.j, mj, pr, cd.rad, cd.off, &sums);
                }
            }
        }
    }
    if (!adapt) {
        // The walker's own images.
        add_images(own, wk, i, mi, Pair(vec2<f32>(0.0), 0.0, hi, vec2<f32>(0.0), true, 0.0, 0.0), wk.rad, wk.off, &sums);
    }
    return sums;
}

// What the pass writes of i: its rates (or, in the midpoint rule's second
// evaluation, the step's velocity and energy) and its contact area.
fn store_rates(i: u32, own: Own, acc: vec2<f32>, de: f32, sw: f32, rad: f32) {
    let rigid = own.rigid;
    if (!MID) {
        if (rigid) {
            dv[i] = vec2<f32>(0.0);
            dr[i].y = 0.0;
        } else {
            dv[i] = acc;
            dr[i].y = de;
            // The second half kick, where a's last part is added (for a
            // boundary particle the contact's); the body force's here.
            if (LEAP == 2u && !own.boundary) {
                var a = acc;
                if (GRAVITY) {
                    a += gravity();
                }
                vkick[i] = hold(i, vkick[i] + a * (0.5 * ctl.dt));
            } else if (LEAP == 2u && GRAVITY) {
                vkick[i] = hold(i, vkick[i] + gravity() * (0.5 * ctl.dt));
            }
        }
    } else if (!rigid && ctl.dt != 0.0) {
        let w0 = dv[i];
        var a = acc;
        if (GRAVITY) {
            a += gravity();
        }
        let w1 = w0 + a * ctl.dt;
        dv[i] = w1;
        dr[i].y = dr[i].y + de * ctl.dt + compatible_energy(w0, w1, own.v);
    }
    if (CONTACT) {
        if (own.boundary) {
            var a = 1.0;
            if (DIM != 1u) {
                a = line_integral(own.hi) / sw;
            }
            if (AXI) {
                // A ring's.
                a *= circumference(rad);
            }
            if (ONPLANE) {
                // On a symmetry plane, its share of the area.
                a *= own.share;
            }
            area[area_index(i, nbo[i].w)] = a;
        } else if (LEAP != 0u) {
            area[i] = 0.0;
        }
    }
}

// Particle i's forces pass (`forces`); returns its artificial dissipation
// rate m_i d_i (0 where it has none).
fn forces_of(i: u32) -> f32 {
    if (LEAP == 2u && CONTACT && i == 0u) {
        size_contact();
    }
    // A zero-length leapfrog step leaves the carried rates as they are.
    if (i >= params.n || zero_length_pass()) {
        return 0.0;
    }
    let mi = pinfo[i];
    let body = bodies[mi.z];
    let rigid = body.rigid != 0u;
    let surface = nbo[i].z > 0.0;
    let boundary = CONTACT && surface;
    // A particle off the boundary at a base state has no entry overlap
    // (contact.wgsl writes the boundary particles').
    if (CONTACT && !boundary && !MID && LEAP != 3u) {
        centry[i] = -1.0;
    }
    if (rigid && !boundary) {
        if (LEAP == 3u) {
            return 0.0;
        }
        if (!MID) {
            dv[i] = vec2<f32>(0.0);
            dr[i].y = 0.0;
        }
        if (CONTACT && LEAP != 0u) {
            area[i] = 0.0;
        }
        return 0.0;
    }
    let adapt = adapting();
    let wk = sph_walker(i);
    let own = own_of(i, mi, body, boundary, surface, wk.rad);
    let sums = pair_sums(own, wk, i, mi, adapt);
    var acc = sums.acc;
    var de = sums.de;
    if (AXI && !rigid) {
        // The hoop stress's acceleration along r and its work, booked as
        // heat (axis::add_momentum): they exchange no energy with the
        // total.
        let hp = hoop[i];
        acc.x -= hp;
        if (LEAP != 2u) {
            de += hp * own.v.x;
        }
    }
    if (boundary) {
        let gl = length(sums.g0);
        var nc = vec2<f32>(0.0);
        var om = 0.0;
        if (gl > 0.0) {
            nc = sums.g0 / gl;
            om = dot(perp(nc), sums.gdot) / gl;
        }
        cn[u32(nbo[i].w)] = vec4<f32>(nc, gl, om);
    }
    // The dissipation the energy sums booked: i's (a rigid particle keeps
    // none).
    var diss = 0.0;
    if (DISS_SUMS && !rigid) {
        diss = sums.dd * bitcast<f32>(mi.x);
    }
    if (LEAP == 3u) {
        if (!rigid) {
            dr[i].y = de + dr[i].y;
        }
        return diss;
    }
    store_rates(i, own, acc, de, sums.sw, wk.rad);
    return diss;
}
