// The kinematics pass (docs/method.md §5, §6, §8.1): per particle, one neighbour loop gathers
// the correction matrix M_i, the colour gradient and the uncorrected velocity
// gradient sum; then L_i = M_i^-1, the equation of state, sigma/rho^2 and the
// sound speed, and the corrected velocity gradient
// grad v_i = [sum_j V_j (v_j - v_i) (x) grad_i W_ij] L_i^T (L_i is particle
// i's own, so it factors out of the sum), giving the continuity rate and the
// Jaumann stress rate. CPU twins: cpu::kinematics::kinematics,
// cpu::eos_and_stress.
//
// Two entry points share the walk and the per-particle algebra:
// * `kinematics`, an evaluation of the rates at a state: of the midpoint rule
//   (dr and ds are where the rates go, common.wgsl MID: at the base state
//   the midpoint buffers, which receive the rates themselves; at the
//   midpoint the base state, which receives dt x rate in place), or the
//   leapfrog's first evaluation (LEAP = 1: no density or stress rates, the
//   state's own EOS for the momentum pass).
// * `kinematics_leap`, the leapfrog step's kinematic pass (LEAP = 2) at
//   (x_{n+1}, v_{n+1/2}): it takes the particle's own density and stress to
//   n+1 (the density into rdt.x, whose de_n it has used: the neighbours
//   read density n for their volumes, and the passes after it read n+1
//   there until the step's end commits it), the EOS at n+1 with the predicted
//   energy e_{n+1/2} + dt/2 de_n, the predicted velocity v_n + c dt a_n
//   (vstar, c = predictor_weight) the viscosity and the contact see, and with the reconstructed
//   viscosity the velocity gradient of vstar, summed in the same walk. CPU
//   twin: cpu::CpuSolver::leapfrog, steps 2 and 3.

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read> s: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read_write> lmat: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read_write> nbo: array<vec4<f32>>;
@group(0) @binding(14) var<storage, read_write> sr2c: array<vec4<f32>>;
@group(0) @binding(16) var<storage, read_write> dr: array<vec2<f32>>;
@group(0) @binding(17) var<storage, read_write> ds: array<vec4<f32>>;
@group(0) @binding(36) var<storage, read_write> gradv: array<vec4<f32>>;
// The leapfrog's carried rates a_n and (_, de_n/dt) and the predicted
// velocity.
@group(0) @binding(51) var<storage, read> acc: array<vec2<f32>>;
@group(0) @binding(52) var<storage, read_write> rdt: array<vec2<f32>>;
@group(0) @binding(53) var<storage, read_write> vstar: array<vec2<f32>>;
// The plastic history (common.wgsl, HISTORY): read for the damage of the
// state evaluated, updated in place by the leapfrog's step. The equivalent
// strain rate of the evaluation, for the midpoint rule's advance passes
// (common.wgsl, STRAIN_RATE).
@group(0) @binding(77) var<storage, read_write> hist_w: array<vec4<f32>>;
@group(0) @binding(78) var<storage, read_write> srate: array<f32>;
// The neighbour mask (common.wgsl), for the forces pass.
@group(0) @binding(9) var<storage, read_write> nmask: array<vec2<u32>>;
// Bodies of revolution: the hoop stress's acceleration sigma_tt / (r rho)
// of the evaluation, for the forces pass.
@group(0) @binding(80) var<storage, read_write> hoop: array<f32>;
// Supports that adapt: the state's velocity gradient, which the step's
// end carries the supports with (advance.wgsl), as dt l in f16
// (common.wgsl, pack_step_gradient).
@group(0) @binding(84) var<storage, read_write> lgrad: array<vec2<u32>>;
// The base pass's debris, a bit a particle (`walk_and_correct`).
@group(0) @binding(86) var<storage, read_write> debris_bits: array<atomic<u32>>;
// The leapfrog step with the hourglass control: the velocity v_{n+1/2}
// the control sees and its gradient (the fit where the correction falls
// back), for the force passes (the state's `v` is kicked in place there).
@group(0) @binding(87) var<storage, read_write> vhalf: array<vec2<f32>>;
@group(0) @binding(88) var<storage, read_write> gradh: array<vec4<f32>>;
// The contact's list of boundary particles and its length (contact.wgsl,
// which says how they are used).
@group(0) @binding(64) var<storage, read_write> surf: array<u32>;
@group(0) @binding(65) var<storage, read_write> surf_args: array<atomic<u32>>;

// kernel::FIT_MIN_SINGULAR, squared.
const FIT_MIN_SV2: f32 = 1.0e-6;

// Particle i's surface (normal, boundary flag) into nbo and, with contact,
// a boundary particle's place on the list of boundary particles in nbo.w
// (as a float, exact below 2^24): the contact keeps what a boundary
// particle carries between its passes there, on as many places as the
// boundary has, not one a particle. The places follow the atomic counter,
// so their order varies from run to run; no result depends on it (each
// place is written only by its own particle's threads). A list more than
// three quarters full stops the run's steps after this one (a zero-length
// step, as after a failure, with the peak length in the control block):
// the host lengthens it and goes on (GpuSolver::run_batch). A particle
// past the end gets no place and is not a boundary particle here; the
// host reports that evaluation as a failure.
fn list_surface(i: u32, ks: KinSums, hi: f32) {
    var sf = surface_of(ks.gpsi, ks.psi, hi);
    var place = -1.0;
    if (CONTACT && sf.z > 0.0) {
        let k = atomicAdd(&surf_args[0], 1u);
        let cap = params.surf_cap;
        if (cap < params.n && k + 1u > cap - cap / 4u) {
            atomicMax(&ctl.list_peak, k + 1u);
            if (atomicLoad(&ctl.fail_step) == NONE) {
                atomicMin(&ctl.fail_step, ctl.step);
                atomicMin(&ctl.fail_code, FAIL_LIST_FULL);
            }
        }
        if (k < cap) {
            surf[k] = i;
            place = f32(k);
        } else {
            sf.z = 0.0;
        }
    }
    nbo[i] = vec4<f32>(sf, place);
}

// V_j = m_j / rho_j; `rho0_i` is particle i's body's, j's too when contact
// is on (pairs are then of one body: no body read a pair).
fn volume(j: u32, mj: vec4<u32>, rho0_i: f32) -> f32 {
    var rho0 = rho0_i;
    if (!CONTACT) {
        rho0 = bodies[mj.z].rho0;
    }
    return bitcast<f32>(mj.x) / (rho0 * (1.0 + r[j].x));
}

// The sums of particle i's neighbour walk at velocities `v`, its neighbour
// mask (common.wgsl; leapfrog only), and in a leapfrog step with the
// reconstructed viscosity the velocity gradient sum of the predicted
// velocities v + (c - 1/2) dt a_n (`gseen`; vstar is written in this pass, so each
// side's is formed here); with the walker's radius (bodies of revolution;
// 0 in plane strain), which the stress point and the hoop rate read.
struct KinSums {
    m: vec4<f32>,
    gpsi: vec2<f32>,
    gsum: vec4<f32>,
    mask: vec2<u32>,
    gseen: vec4<f32>,
    rad: f32,
    // Same-body partners in the gradient sums, images included (the debris
    // floor, Body::debris_n).
    n: u32,
    // Bodies of revolution: the colour function sum_j V_j W_ij, the walker
    // itself included (surface_of).
    psi: f32,
}

// The predicted velocity of particle j, v_n + c dt a_n (a rigid one's a_n
// is zero; c = predictor_weight).
fn predicted(j: u32) -> vec2<f32> {
    let b = bodies[pinfo[j].z];
    let c = predictor_weight(sqrt(b.modulus / b.rho0), b.h, ctl.dt);
    var a = acc[j];
    if (GRAVITY && b.rigid == 0u) {
        a += gravity();
    }
    return hold(j, v[j] + a * ((c - 0.5) * ctl.dt));
}

// What particle i's kinematic walk reads of itself.
struct KinOwn {
    vi: vec2<f32>,
    vsi: vec2<f32>,
    seen: bool,
    rigid: bool,
    // Bodies of revolution: 1 / eta_i, the kinematic sums' weight m_j / eta_i.
    inv_eta: f32,
}

// Add the pair of gradient `gw` and separation `d` with a neighbour of mass
// `mass`, volume `vol` (an area in a body of revolution) and velocities
// `vj`, `vsj` (the state's and the predicted) to the sums.
fn add_kin(o: KinOwn, gw: vec2<f32>, d: vec2<f32>, mass: f32, vol: f32, vj: vec2<f32>, vsj: vec2<f32>, ks: ptr<function, KinSums>) {
    let gj = gw * vol;
    // A body of revolution weighs the gradient sums by mass (docs/method.md
    // §12): with areas a mode of the particles nearest the axis grows.
    var gm = gj;
    if (AXI) {
        gm = gw * (mass * o.inv_eta);
    }
    (*ks).m += outer(gm, -d);
    (*ks).n += select(0u, 1u, dot(d, d) > 0.0);
    (*ks).gpsi -= gj;
    // Rigid particles have no velocity gradient: their loop skips
    // the velocity reads (a branch uniform over the whole loop).
    if (!o.rigid) {
        (*ks).gsum += outer(vj - o.vi, gm);
        if (o.seen) {
            (*ks).gseen += outer(vsj - o.vsi, gm);
        }
    }
}

// The mirror images of particle j (radius rj, offsets oj, mass and volume
// as `add_kin`) in walker `wk`'s sums, where they are within reach.
fn add_kin_images(o: KinOwn, wk: Walker, j: u32, rj: f32, oj: vec2<f32>, d: vec2<f32>, hij: f32, mass: f32, vol: f32, ks: ptr<function, KinSums>) {
    for (var m = 0u; m < image_count(); m++) {
        let im = image_pair(wk, m, oj, d, hij);
        if (!im.inside) {
            continue;
        }
        let f = image_flip(m);
        var vsj = vec2<f32>(0.0);
        if (o.seen) {
            vsj = mirror_vec(f, predicted(j));
        }
        var area = vol;
        if (AXI) {
            area = vol / circumference(rj);
        }
        add_kin(o, im.gw, im.d, mass, area, mirror_vec(f, v[j]), vsj, ks);
        if (AXI) {
            (*ks).psi += kernel_w(im.dist, im.hij) * area;
        }
    }
}

fn kinematic_walk(i: u32, hi: f32, bi: u32, rigid: bool, rho0: f32) -> KinSums {
    if (adapting()) {
        return adaptive_walk(i, hi, bi, rigid, rho0);
    }
    let cs = consts();
    let wk = walker(i);
    let seen = LEAP == 2u && RECON;
    var o = KinOwn(v[i], vec2<f32>(0.0), seen, rigid, 0.0);
    if (seen) {
        o.vsi = predicted(i);
    }
    if (AXI) {
        o.inv_eta = 1.0 / (circumference(wk.rad) * rho0 * (1.0 + r[i].x));
    }
    var ks = KinSums(vec4<f32>(0.0), vec2<f32>(0.0), vec4<f32>(0.0), vec2<u32>(0u), vec4<f32>(0.0), wk.rad, 0u, 0.0);
    var mask = vec2<u32>(0u);
    // The ordinal of the row's first candidate.
    var first = 0u;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        let off = first - span.start;
        first += span.end - span.start;
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let j = cd.j;
            let mj = pinfo[j];
            let pr = body_pair(wk, cd, mj.z, span, hi, bi);
            if (LEAP != 0u && pr.inside && k + off < MASK_BITS) {
                mask = mask_set(mask, k + off);
            }
            if (!pr.inside || pr.dist <= 0.0) {
                continue;
            }
            let mass = bitcast<f32>(mj.x);
            let vol = volume(j, mj, rho0);
            var vsj = vec2<f32>(0.0);
            if (seen && !rigid) {
                vsj = predicted(j);
            }
            var vj = vec2<f32>(0.0);
            if (!rigid) {
                vj = v[j];
            }
            if (AXI) {
                // The area m_j / eta_j of j, and its image.
                let area = vol / circumference(cd.rad);
                add_kin(o, pr.gw, pr.d, mass, area, vj, vsj, &ks);
                ks.psi += kernel_w(pr.dist, pr.hij) * area;
            } else {
                add_kin(o, pr.gw, pr.d, mass, vol, vj, vsj, &ks);
            }
            add_kin_images(o, wk, j, cd.rad, cd.off, pr.d, pr.hij, mass, vol, &ks);
        }
    }
    if (image_count() > 0u) {
        // The walker's own images, and itself in the colour function.
        let mi = pinfo[i];
        let vi = volume(i, mi, rho0);
        add_kin_images(o, wk, i, wk.rad, wk.off, vec2<f32>(0.0), hi, bitcast<f32>(mi.x), vi, &ks);
        if (AXI) {
            ks.psi += kernel_w(0.0, hi) * vi / circumference(wk.rad);
        }
    }
    if (first > MASK_BITS) {
        mask.y |= MASK_FULL;
    }
    ks.mask = mask;
    return ks;
}

// `kinematic_walk` where supports adapt (docs/method.md, "Supports that
// follow the deformation"): the gradient sums take the pairs in their mean
// metric, the colour gradient the round pairs of the bodies' h, and in a
// body of revolution each candidate's image either way (a metric's image
// is its particle's mirrored). A candidate goes into the mask when any of
// the three is a pair. CPU twins: cpu::kinematics::kinematics and
// round_colour.
fn adaptive_walk(i: u32, hi: f32, bi: u32, rigid: bool, rho0: f32) -> KinSums {
    let cs = consts();
    let wk = adaptive_walker(i);
    let seen = LEAP == 2u && RECON;
    var o = KinOwn(v[i], vec2<f32>(0.0), seen, rigid, 0.0);
    if (seen) {
        o.vsi = predicted(i);
    }
    if (AXI) {
        o.inv_eta = 1.0 / (circumference(wk.rad) * rho0 * (1.0 + r[i].x));
    }
    var ks = KinSums(vec4<f32>(0.0), vec2<f32>(0.0), vec4<f32>(0.0), vec2<u32>(0u), vec4<f32>(0.0), wk.rad, 0u, 0.0);
    var mask = vec2<u32>(0u);
    var first = 0u;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span_in(wk.hm, row, wk.reach);
        let off = first - span.start;
        first += span.end - span.start;
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let j = cd.j;
            let mj = pinfo[j];
            let pr = sph_pair(wk, cd, mj.z, span, hi, bi);
            let round = body_pair(wk, cd, mj.z, span, hi, bi);
            let valid = j != i && in_row(cd.cell, span) && !(CONTACT && mj.z != bi);
            var qj = vec4<f32>(0.0);
            var hit = 0u;
            if (image_count() > 0u && valid) {
                qj = support_of(j, body_h(hi, mj.z));
                hit = metric_images(wk, cd.off, cd.d, qj, hi);
            }
            let any = pr.inside || round.inside || hit != 0u;
            if (LEAP != 0u && any && k + off < MASK_BITS) {
                mask = mask_set(mask, k + off);
            }
            if (!any) {
                continue;
            }
            let mass = bitcast<f32>(mj.x);
            let vol = volume(j, mj, rho0);
            add_adaptive(o, wk, Mirrored(j, cd.rad, cd.off, cd.d, qj, hi, hit), mass, vol, pr, round, &ks);
        }
    }
    if (image_count() > 0u) {
        // The walker's own images, both ways.
        let mi = pinfo[i];
        let own = Pair(vec2<f32>(0.0), 0.0, hi, vec2<f32>(0.0), true, 0.0, 0.0);
        let hit = metric_images(wk, wk.off, vec2<f32>(0.0), wk.q, hi);
        let vi = volume(i, mi, rho0);
        add_adaptive(o, wk, Mirrored(i, wk.rad, wk.off, vec2<f32>(0.0), wk.q, hi, hit), bitcast<f32>(mi.x), vi, Pair(vec2<f32>(0.0), 0.0, 0.0, vec2<f32>(0.0), false, 0.0, 0.0), own, &ks);
        if (AXI) {
            ks.psi += kernel_w(0.0, hi) * vi / circumference(wk.rad);
        }
    }
    if (first > MASK_BITS) {
        mask.y |= MASK_FULL;
    }
    ks.mask = mask;
    return ks;
}

// Which of the images of a particle of metric `qj` (offsets `oj`,
// separation `d` from the walker) are metric pairs of the walker, a bit
// each.
fn metric_images(wk: Walker, oj: vec2<f32>, d: vec2<f32>, qj: vec4<f32>, h0: f32) -> u32 {
    var hit = 0u;
    for (var m = 0u; m < image_count(); m++) {
        if (image_pair_metric(wk, m, oj, d, qj, h0).inside) {
            hit |= 1u << m;
        }
    }
    return hit;
}

// A particle j as its images are met: its radius, offsets, separation
// from the walker, metric, and which images are metric pairs
// (`metric_images`).
struct Mirrored {
    j: u32,
    rj: f32,
    oj: vec2<f32>,
    d: vec2<f32>,
    qj: vec4<f32>,
    h0: f32,
    hit: u32,
}

// A candidate's terms in an adaptive walk: the metric pair `pr` and the
// metric pairs with its images (mirrored metrics) to the gradient sums;
// the round pair `round` and its round images to the colour gradient.
// `round` with zero distance stands for the walker's own images.
fn add_adaptive(o: KinOwn, wk: Walker, c: Mirrored, mass: f32, vol: f32, pr: Pair, round: Pair, ks: ptr<function, KinSums>) {
    let j = c.j;
    var area = vol;
    if (AXI) {
        area = vol / circumference(c.rj);
    }
    if (round.inside) {
        if (round.dist > 0.0) {
            (*ks).gpsi -= round.gw * area;
            if (AXI) {
                (*ks).psi += kernel_w(round.dist, round.hij) * area;
            }
        }
        for (var m = 0u; m < image_count(); m++) {
            let ri = image_pair(wk, m, c.oj, round.d, round.hij);
            if (ri.inside) {
                (*ks).gpsi -= ri.gw * area;
                if (AXI) {
                    (*ks).psi += kernel_w(ri.dist, ri.hij) * area;
                }
            }
        }
    }
    var vsj = vec2<f32>(0.0);
    var vj = vec2<f32>(0.0);
    if (!o.rigid) {
        vj = v[j];
        if (o.seen) {
            vsj = predicted(j);
        }
    }
    if (pr.inside && pr.dist > 0.0) {
        add_grad(o, pr.gw, pr.d, mass, area, vj, vsj, ks);
    }
    for (var m = 0u; m < image_count(); m++) {
        if ((c.hit & (1u << m)) != 0u) {
            let f = image_flip(m);
            let img = image_pair_metric(wk, m, c.oj, c.d, c.qj, c.h0);
            add_grad(o, img.gw, img.d, mass, area, mirror_vec(f, vj), mirror_vec(f, vsj), ks);
        }
    }
}

// `add_kin` without the colour gradient.
fn add_grad(o: KinOwn, gw: vec2<f32>, d: vec2<f32>, mass: f32, vol: f32, vj: vec2<f32>, vsj: vec2<f32>, ks: ptr<function, KinSums>) {
    var gm = gw * vol;
    if (AXI) {
        gm = gw * (mass * o.inv_eta);
    }
    (*ks).m += outer(gm, -d);
    (*ks).n += select(0u, 1u, dot(d, d) > 0.0);
    if (!o.rigid) {
        (*ks).gsum += outer(vj - o.vi, gm);
        if (o.seen) {
            (*ks).gseen += outer(vsj - o.vsi, gm);
        }
    }
}

// The start of both entries: particle i's body, its walk, and its
// correction matrix (stored).
struct Walked {
    body: Body,
    rigid: bool,
    ks: KinSums,
    l: vec4<f32>,
    // The correction fell back (`shear_of`).
    fell_back: bool,
    // Debris (`stress_point`): at the midpoint the base state's, so that
    // no particle turns to or from debris inside a step (CPU twin:
    // cpu::Rates::debris).
    debris: bool,
}

fn walk_and_correct(i: u32) -> Walked {
    let bi = pinfo[i].z;
    let body = bodies[bi];
    let rigid = body.rigid != 0u;
    let ks = kinematic_walk(i, body.h, bi, rigid, body.rho0);
    // Too few neighbours is debris however well M looks (CPU twin:
    // cpu::kinematics::finish).
    let ok = !CORRECTED || (conditioned(dim_fixed(ks.m), params.min_sv2) && ks.n >= body.debris_n);
    let l = correction(ks.m, ok);
    lmat[i] = l;
    if (LEAP != 0u) {
        nmask[i] = ks.mask;
    }
    let fell_back = !ok && !rigid;
    var debris = fell_back;
    if (CORRECTED && LEAP == 0u) {
        let w = i / 32u;
        let bit = 1u << (i % 32u);
        if (MID) {
            debris = (atomicLoad(&debris_bits[w]) & bit) != 0u;
        } else if (fell_back) {
            atomicOr(&debris_bits[w], bit);
        } else {
            atomicAnd(&debris_bits[w], ~bit);
        }
    }
    return Walked(body, rigid, ks, l, fell_back, debris);
}

// The shear modulus of the deviatoric stress rate: 0 for debris, whose
// deviatoric stress only turns with the spin while it is so.
fn shear_of(wk: Walked) -> f32 {
    if (wk.fell_back) {
        return 0.0;
    }
    return wk.body.g;
}

@compute @workgroup_size(WG)
fn kinematics(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let wk = walk_and_correct(i);
    let body = wk.body;
    let rigid = wk.rigid;
    let ks = wk.ks;
    let l = wk.l;
    list_surface(i, ks, body.h);
    let mu = r[i].x;
    let si = s[i];
    stress_point(i, ks.rad, body, mu, r[i].y, si, damage_of(i), wk.debris);

    if (rigid) {
        if (!MID && LEAP == 0u) {
            dr[i] = vec2<f32>(0.0);
            ds[i] = vec4<f32>(0.0);
        }
        if (RECON || HG > 0.0) {
            gradv[i] = vec4<f32>(0.0);
        }
        if (DISP > 0.0) {
            hand_over(i, vec4<f32>(0.0), false);
        }
        return;
    }
    let gv = velocity_gradient(ks.gsum, l);
    if (RECON || HG > 0.0) {
        gradv[i] = velocity_gradient(ks.gsum, fit_of(ks.m, l));
    }
    if (ADAPT && LGRAD) {
        lgrad[i] = pack_step_gradient(gv, ctl.dt);
    }
    if (DISP > 0.0) {
        // The rates wait for the dispersion correction (dispersion.wgsl).
        hand_over(i, gv, wk.fell_back);
        return;
    }
    if (LEAP != 0u) {
        return;
    }
    midpoint_rates(i, body, mu, si, gv, hoop_rate(ks.rad, v[i]), shear_of(wk));
}

// The midpoint rule's rates of particle i (body `body`, density `mu`,
// deviatoric stress `si`) at velocity gradient `gv` and hoop rate `d_tt`
// with shear modulus `g`: at the base state into the rates, at the
// midpoint a step of them into the state.
fn midpoint_rates(i: u32, body: Body, mu: f32, si: vec4<f32>, gv: vec4<f32>, d_tt: f32, g: f32) {
    if (STRAIN_RATE) {
        srate[i] = equivalent_rate(gv, d_tt);
    }
    let dmu = density_rate(mu, gv, d_tt);
    let rate = deviator_rate(g, si, gv, d_tt);
    if (!MID) {
        dr[i].x = dmu;
        ds[i] = rate;
    } else if (ctl.dt != 0.0) {
        // A zero-length step leaves the state as it is.
        let dt = ctl.dt;
        dr[i].x = dr[i].x + dmu * dt;
        ds[i] = plastic_return(ds[i] + rate * dt, body);
    }
}

// The leapfrog step's kinematic pass (LEAP = 2; header). `ds` is the state's
// own deviatoric stress, updated in place (only particle i reads it here).
@compute @workgroup_size(WG)
fn kinematics_leap(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    // A zero-length step leaves the state and the carried rates as they
    // are.
    if (i >= params.n || zero_length_pass()) {
        return;
    }
    let wk = walk_and_correct(i);
    let body = wk.body;
    let hi = body.h;
    let rigid = wk.rigid;
    let ks = wk.ks;
    let l = wk.l;
    let mu = r[i].x;
    let si = ds[i];
    if (rigid) {
        // A rigid body keeps its velocity and reference state.
        list_surface(i, ks, hi);
        rdt[i].x = mu;
        stress_point(i, ks.rad, body, mu, r[i].y, si, 0.0, false);
        vstar[i] = v[i];
        if (RECON) {
            gradv[i] = vec4<f32>(0.0);
        }
        if (HG > 0.0) {
            vhalf[i] = v[i];
            gradh[i] = vec4<f32>(0.0);
        }
        if (DISP > 0.0) {
            hand_over(i, vec4<f32>(0.0), false);
        }
        return;
    }
    let gv = velocity_gradient(ks.gsum, l);
    if (ADAPT && LGRAD) {
        // The carry (advance.wgsl) takes the gradient with respect to x_n,
        // with which F = I + dt l is the step's motion exactly (CPU twin:
        // cpu::advance::carry_supports at lag dt).
        lgrad[i] = pack_step_gradient(gradient_behind(gv, ctl.dt), ctl.dt);
    }
    list_surface(i, ks, hi);
    vstar[i] = predicted(i);
    // The reconstruction's gradient of the predicted velocities (plain
    // where the correction falls back); the hourglass control's of v_{n+1/2}.
    if (RECON) {
        gradv[i] = velocity_gradient(ks.gseen, l);
    }
    if (HG > 0.0) {
        vhalf[i] = v[i];
        gradh[i] = velocity_gradient(ks.gsum, fit_of(ks.m, l));
    }
    if (DISP > 0.0) {
        // The update waits for the dispersion correction
        // (dispersion.wgsl, disperse_leap).
        hand_over(i, gv, wk.fell_back);
        return;
    }
    to_next(i, body, ks.rad, gv, shear_of(wk), wk.debris);
}

// The leapfrog step's update of particle i (body `body`, radius `rad`) to
// n+1 at velocity gradient `gv`: its density, deviatoric stress (shear
// modulus `g`), plastic history and predicted energy, and its stress point
// there. `ds` is the state's own deviatoric stress, updated in place.
fn to_next(i: u32, body: Body, rad: f32, gv: vec4<f32>, g: f32, debris: bool) {
    let dt = ctl.dt;
    let h = 0.5 * dt;
    let mu = r[i].x;
    let si = ds[i];
    let d_tt = hoop_rate(rad, v[i]);
    var mu1 = density_after(mu, density_log_rate(gv, d_tt) * dt);
    var s1 = plastic_return(si + deviator_rate(g, si, gv, d_tt) * dt, body);
    // The predicted energy takes back the first half kick's compatible
    // term, as the second (to come) is expected to return it
    // (common.wgsl, kick_energy; CPU twin: cpu::leapfrog).
    let e1 = r[i].y + rdt[i].y * h - kick_energy(moving_part(i, acc[i]), h);
    var d1 = 0.0;
    if (HISTORY) {
        var rate = 0.0;
        if (STRAIN_RATE) {
            rate = equivalent_rate(gv, d_tt);
        }
        let up = strength_update(pinfo[i].z, s1, rate, mu1, e1, hist_w[i], ctl.t_hi + ctl.t_lo + dt);
        s1 = up.s;
        mu1 = up.mu;
        hist_w[i] = up.h;
        d1 = damage_seen(up.h);
    }
    rdt[i].x = mu1;
    ds[i] = s1;
    stress_point(i, rad, body, mu1, e1, s1, d1, debris);
}
