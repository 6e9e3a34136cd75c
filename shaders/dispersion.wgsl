// The dispersion correction (docs/method.md, "The dispersion correction";
// CPU twin: cpu::dispersion), part of the kinematics module: an
// evaluation's two extra walks, and the leapfrog step's four, where a
// scene sets DISP (theta).
// With a_ij = V_j L_i grad_i W_ij the corrected gradient's weights and
// d_ij = x_j - x_i:
//
// * `disperse`, after the kinematic walk: C_i = -theta/2 sum_j ((grad v_j -
//   grad v_i) d_ij) (x) a_ij, and the density and stress rates at grad v_i
//   + C_i (which the kinematic walk left to it); the extra stress S_i =
//   theta/(2 V_i) sum_j (V_i sig_i a_ij + V_j sig_j a_ji) (x) d_ij;
// * `disperse_forces`, after the forces walk: S's forces m_i a_i = sum_j
//   (V_i S_i a_ij - V_j S_j a_ji), and its work S_i : grad v_i / rho_i,
//   a kick of their own (booked as the forces pass books its own).
//
// The leapfrog's step takes them apart as its CPU twin does
// (cpu::leapfrog): C at x_{n+1} and v_{n+1/2} before the update to n+1
// (`disperse_leap`), S from the stresses at n+1 (`disperse_stress`), its
// forces after the forces walk (`disperse_forces_leap`), and its work at
// the gradient of v_{n+1} after the energy walk (`disperse_work`). Its
// first evaluation runs `disperse` and `disperse_forces` for a_0 and de_0.
//
// Across the symmetry planes and a body of revolution's axis each walk
// meets its neighbours' images and its own, as the kinematic walk does
// (cpu::dispersion, `image_pairs`). In a body of revolution (AXI) V is the
// ring's volume m/rho that weighs the power, the gradient's weights (the
// forces', and the leapfrog's work's) are m_j/eta_i as the kinematic
// walk's, and C's and S's the areas m_j/eta_j (cpu::dispersion, `Weigh`);
// the hoop rate takes no correction.

// The plain velocity gradient of the kinematic walk (zero on a rigid
// particle).
@group(0) @binding(102) var<storage, read_write> gdisp: array<vec4<f32>>;
// S_i (a general 2x2 matrix: xx, xy, yx, yy). Between the kinematic walk
// and `disperse` its x holds 1 where particle i's correction fell back.
@group(0) @binding(103) var<storage, read_write> sdisp: array<vec4<f32>>;
@group(0) @binding(18) var<storage, read_write> dv: array<vec2<f32>>;
// The leapfrog step's velocity, kicked (forces.wgsl).
@group(0) @binding(57) var<storage, read_write> vkick: array<vec2<f32>>;

// sigma a of an in-plane stress (xx, yy, xy) and a vector.
fn sym_apply(t: vec4<f32>, a: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(t.x * a.x + t.z * a.y, t.z * a.x + t.y * a.y);
}

// A : B of two general matrices.
fn ddot2(a: vec4<f32>, b: vec4<f32>) -> f32 {
    return dot(a, b);
}

// What the kinematic walk hands `disperse`: particle i's plain gradient,
// and whether its correction fell back (its deviatoric rate then takes
// no shear modulus, as the walk's own would).
fn hand_over(i: u32, gv: vec4<f32>, fell_back: bool) {
    gdisp[i] = gv;
    sdisp[i] = vec4<f32>(select(0.0, 1.0, fell_back), 0.0, 0.0, 0.0);
}

// What a walk sums (`disp_walk`): C and Q (the midpoint rule's
// `disperse`), C alone (the leapfrog's, at x_{n+1} and v_{n+1/2}), Q alone
// (the leapfrog's S at n+1), the force of S, or the gradient of the
// velocities v (the leapfrog's work at v_{n+1}).
const D_CQ: u32 = 0u;
const D_C: u32 = 1u;
const D_Q: u32 = 2u;
const D_FORCE: u32 = 3u;
const D_GRAD: u32 = 4u;

// One walk's sums: C_i (or the velocity gradient; in c) and Q_i (in q)
// unscaled, or the force of S on particle i (in c.xy). The kinematic
// walk's pairs: round, or in the pair's mean metric where supports adapt;
// one body's where contact is on. `next`: the volumes at n+1 (the
// leapfrog's density there, rdt.x), else the state's.
struct DispSums {
    c: vec4<f32>,
    q: vec4<f32>,
}

// The density of particle j (meta `mj`) whose walker's body has rho0
// `rho0` (`volume`'s), at n+1 where `next` (the leapfrog's, rdt.x).
fn disp_density(j: u32, mj: vec4<u32>, rho0: f32, next: bool) -> f32 {
    var r0 = rho0;
    if (!CONTACT) {
        r0 = bodies[mj.z].rho0;
    }
    if (next) {
        return r0 * (1.0 + rdt[j].x);
    }
    return r0 * (1.0 + r[j].x);
}

// What walker i's sums take of its pair with particle j, or with j's
// mirror image under `f` across the symmetry planes (f = 0: j itself):
// the pair's gradient `gw` (grad_i W), d_ij = x_j - x_i, and j's volume
// `vj` and density `rho_j`; j's gradient, L, S, stress and velocity
// mirrored by `f`; in a body of revolution j's mass and radius `rad_j`
// too. `wi` is what the walk keeps of i: its own gradient or S (`own`),
// V sigma, velocity, volume, L, and in a body of revolution its mass,
// area and 1/eta.
struct DispOwn {
    own: vec4<f32>,
    vs: vec4<f32>,
    vel: vec2<f32>,
    vol: f32,
    l: vec4<f32>,
    mass: f32,
    area: f32,
    inv_eta: f32,
}

// The walker's own part of DispOwn in a body of revolution: its mass
// `mass`, volume `vol` and density `rho` at radius `rad`.
fn disp_own_axi(wi: ptr<function, DispOwn>, mass: f32, rad: f32, rho: f32) {
    if (AXI) {
        let c = circumference(rad);
        (*wi).mass = mass;
        (*wi).area = (*wi).vol / c;
        (*wi).inv_eta = 1.0 / (c * rho);
    }
}

fn disp_terms(out: ptr<function, DispSums>, mode: u32, wi: DispOwn, gw: vec2<f32>, dij: vec2<f32>, f: u32, j: u32, bj: u32, vj: f32, rho_j: f32, mass_j: f32, rad_j: f32) {
    // The pair's weights: areas in C and S, the gradient's in the forces
    // and the gradient (the same in the plane).
    var cj = 1.0;
    var wj = vj;
    var wi_ = wi.vol;
    if (AXI) {
        cj = circumference(rad_j);
        if (mode == D_GRAD || mode == D_FORCE) {
            wj = mass_j * wi.inv_eta;
            wi_ = wi.mass / (cj * rho_j);
        } else {
            wj = vj / cj;
            wi_ = wi.area;
        }
    }
    let aij = mat_mul(wi.l, gw * wj);
    if (mode == D_GRAD) {
        (*out).c += outer(mirror_vec(f, v[j]) - wi.vel, aij);
        return;
    }
    if (mode == D_C || mode == D_CQ) {
        (*out).c += outer(mat_mul(mirror_mat(f, gdisp[j]) - wi.own, dij), aij);
    }
    if (mode == D_C) {
        return;
    }
    // A rigid particle has no correction of its own (the CPU's L is zero
    // there).
    var aji = vec2<f32>(0.0);
    if (bodies[bj].rigid == 0u) {
        aji = mat_mul(mirror_mat(f, lmat[j]), -gw * wi_);
    }
    if (mode == D_FORCE) {
        let p = mat_mul(wi.own, aij) * wi.vol - mat_mul(mirror_mat(f, sdisp[j]), aji) * vj;
        (*out).c += vec4<f32>(p, 0.0, 0.0);
    } else {
        // V sigma: sr2c is sigma / rho^2 (sigma / (rho eta) in a body of
        // revolution).
        let w = sym_apply(wi.vs, aij) + sym_apply(mirror_sym(f, sr2c[j]) * (vj * rho_j * rho_j * cj), aji);
        (*out).q += outer(w, dij);
    }
}

// The pair of walker `wk` with image `m` of a particle at offsets `oj`,
// separation `d` and support `qj` (where supports adapt; `hij` the round
// pair's smoothing length otherwise): the kinematic walk's image pairs.
fn disp_image(wk: Walker, adapt: bool, m: u32, oj: vec2<f32>, d: vec2<f32>, qj: vec4<f32>, hij: f32, hi: f32) -> Pair {
    if (adapt) {
        return image_pair_metric(wk, m, oj, d, qj, hi);
    }
    return image_pair(wk, m, oj, d, hij);
}

fn disp_walk(i: u32, bi: u32, hi: f32, rho0: f32, mode: u32, next: bool) -> DispSums {
    let cs = consts();
    let adapt = adapting();
    let wk = sph_walker(i);
    let mi = pinfo[i];
    let rho_i = disp_density(i, mi, rho0, next);
    var wi = DispOwn(vec4<f32>(0.0), vec4<f32>(0.0), vec2<f32>(0.0), bitcast<f32>(mi.x) / rho_i, lmat[i], 0.0, 0.0, 0.0);
    disp_own_axi(&wi, bitcast<f32>(mi.x), wk.rad, rho_i);
    if (mode == D_FORCE) {
        wi.own = sdisp[i];
    } else if (mode == D_CQ || mode == D_C) {
        wi.own = gdisp[i];
    }
    if (mode == D_CQ || mode == D_Q) {
        // V sigma = V rho^2 (sigma / rho^2); V rho eta (sigma / (rho eta))
        // in a body of revolution.
        var ci = 1.0;
        if (AXI) {
            ci = circumference(wk.rad);
        }
        wi.vs = sr2c[i] * (wi.vol * rho_i * rho_i * ci);
    }
    if (mode == D_GRAD) {
        wi.vel = v[i];
    }
    var out = DispSums(vec4<f32>(0.0), vec4<f32>(0.0));
    let images = image_count();
    for (var row = 0u; row < scan_rows(); row++) {
        // A round walker's reach is `row_span`'s.
        let span = row_span_in(wk.hm, row, wk.reach);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let j = cd.j;
            let mj = pinfo[j];
            var pr = body_pair(wk, cd, mj.z, span, hi, bi);
            if (adapt) {
                pr = sph_pair(wk, cd, mj.z, span, hi, bi);
            }
            let paired = pr.inside && pr.dist > 0.0;
            // Which of j's images across the symmetry planes may be pairs
            // (none without a plane): where supports adapt, those in the
            // mean metric whether or not j itself is; else, an image being
            // never nearer than its particle, those of j's pair.
            var hit = 0u;
            var qj = vec4<f32>(0.0);
            if (images > 0u) {
                if (adapt) {
                    if (j != i && in_row(cd.cell, span) && !(CONTACT && mj.z != bi)) {
                        qj = support_of(j, body_h(hi, mj.z));
                        hit = metric_images(wk, cd.off, cd.d, qj, hi);
                    }
                } else if (paired) {
                    hit = (1u << images) - 1u;
                }
            }
            if (!paired && hit == 0u) {
                continue;
            }
            let rho_j = disp_density(j, mj, rho0, next);
            let vj = bitcast<f32>(mj.x) / rho_j;
            if (paired) {
                // d_ij = x_j - x_i.
                disp_terms(&out, mode, wi, pr.gw, -pr.d, 0u, j, mj.z, vj, rho_j, bitcast<f32>(mj.x), cd.rad);
            }
            for (var m = 0u; m < images; m++) {
                if ((hit & (1u << m)) == 0u) {
                    continue;
                }
                let im = disp_image(wk, adapt, m, cd.off, cd.d, qj, pr.hij, hi);
                if (im.inside) {
                    disp_terms(&out, mode, wi, im.gw, -im.d, image_flip(m), j, mj.z, vj, rho_j, bitcast<f32>(mj.x), cd.rad);
                }
            }
        }
    }
    for (var m = 0u; m < images; m++) {
        // The walker's own images (none on a plane it lies on, at zero
        // distance).
        let im = disp_image(wk, adapt, m, wk.off, vec2<f32>(0.0), wk.q, hi, hi);
        if (im.inside && im.dist > 0.0) {
            disp_terms(&out, mode, wi, im.gw, -im.d, image_flip(m), i, bi, wi.vol, rho_i, bitcast<f32>(mi.x), wk.rad);
        }
    }
    return out;
}

@compute @workgroup_size(WG)
fn disperse(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let bi = pinfo[i].z;
    let body = bodies[bi];
    if (body.rigid != 0u) {
        sdisp[i] = vec4<f32>(0.0);
        return;
    }
    let fell_back = sdisp[i].x != 0.0;
    let sums = disp_walk(i, bi, body.h, body.rho0, D_CQ, false);
    let vi = volume(i, pinfo[i], body.rho0);
    sdisp[i] = sums.q * (0.5 * DISP / vi);
    if (LEAP != 0u) {
        // The leapfrog's first evaluation takes no density or stress
        // rates (its kinematic walk's none either).
        return;
    }
    let gc = gdisp[i] + sums.c * (-0.5 * DISP);
    // The kinematic walk's rates (kinematics.wgsl) at grad v + C.
    midpoint_rates(i, body, r[i].x, s[i], gc, hoop_rate(radius_of(i), v[i]), select(body.g, 0.0, fell_back));
}

@compute @workgroup_size(WG)
fn disperse_forces(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let mi = pinfo[i];
    let body = bodies[mi.z];
    if (body.rigid != 0u) {
        return;
    }
    let a = disp_walk(i, mi.z, body.h, body.rho0, D_FORCE, false).c.xy / bitcast<f32>(mi.x);
    let de = ddot2(sdisp[i], gdisp[i]) / (body.rho0 * (1.0 + r[i].x));
    if (!MID) {
        dv[i] = dv[i] + a;
        dr[i].y = dr[i].y + de;
    } else if (ctl.dt != 0.0) {
        // A kick of the velocity the step updates, booked as the forces
        // pass books its own (common.wgsl, compatible_energy).
        let w0 = dv[i];
        let w1 = w0 + a * ctl.dt;
        dv[i] = w1;
        dr[i].y = dr[i].y + de * ctl.dt + compatible_energy(w0, w1, v[i]);
    }
}

// The leapfrog step (LEAP = 2, after kinematics_leap, which leaves the
// update to n+1 to it): C at x_{n+1} and v_{n+1/2}, then particle i's
// density, stress and energy at n+1 at grad v + C (kinematics.wgsl,
// to_next). A rigid particle's pass is the kinematic walk's.
@compute @workgroup_size(WG)
fn disperse_leap(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let bi = pinfo[i].z;
    let body = bodies[bi];
    if (body.rigid != 0u) {
        return;
    }
    let fell_back = sdisp[i].x != 0.0;
    let c = disp_walk(i, bi, body.h, body.rho0, D_C, false).c * (-0.5 * DISP);
    to_next(i, body, radius_of(i), gdisp[i] + c, select(body.g, 0.0, fell_back), fell_back);
}

// The leapfrog step's S at n+1 (after disperse_leap): the stresses and
// densities there.
@compute @workgroup_size(WG)
fn disperse_stress(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let mi = pinfo[i];
    let body = bodies[mi.z];
    if (body.rigid != 0u) {
        sdisp[i] = vec4<f32>(0.0);
        return;
    }
    let q = disp_walk(i, mi.z, body.h, body.rho0, D_Q, true).q;
    let vi = bitcast<f32>(mi.x) / disp_density(i, mi, body.rho0, true);
    sdisp[i] = q * (0.5 * DISP / vi);
}

// The leapfrog step's forces of S at n+1, after the forces walk: into the
// carried acceleration, and the second half kick where the forces walk
// gave it (a boundary particle's comes in the contact's pass, from the
// whole acceleration).
@compute @workgroup_size(WG)
fn disperse_forces_leap(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let mi = pinfo[i];
    let body = bodies[mi.z];
    if (body.rigid != 0u) {
        return;
    }
    let a = disp_walk(i, mi.z, body.h, body.rho0, D_FORCE, true).c.xy / bitcast<f32>(mi.x);
    dv[i] = dv[i] + a;
    if (!(CONTACT && nbo[i].z > 0.0)) {
        vkick[i] = hold(i, vkick[i] + a * (0.5 * ctl.dt));
    }
}

// The leapfrog's booking (LEAP = 3, after the energy walk): S's work at
// the velocity gradient of v_{n+1}, into the carried de/dt.
@compute @workgroup_size(WG)
fn disperse_work(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let mi = pinfo[i];
    let body = bodies[mi.z];
    if (body.rigid != 0u) {
        return;
    }
    let g = disp_walk(i, mi.z, body.h, body.rho0, D_GRAD, true).c;
    rdt[i].y = rdt[i].y + ddot2(sdisp[i], g) / disp_density(i, mi, body.rho0, true);
}
