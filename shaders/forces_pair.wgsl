// The forces stage's pair terms (the host appends them to the forces
// stage's module, forces.wgsl, which declares the buffers they read): a
// pair's momentum and energy terms with the viscosity, the artificial
// stress and the hourglass control, and the boundary's sums.

// The velocity jump the viscosity sees: v_ij less each side's linear
// reconstruction to the pair midpoint, van Leer limited (xij = x_i - x_j).
// CPU twin: physics::viscosity::reconstructed_jump.
fn reconstructed_jump(vij: vec2<f32>, xij: vec2<f32>, gi: vec4<f32>, gj: vec4<f32>) -> vec2<f32> {
    let di = mat_mul(gi, xij);
    let dj = mat_mul(gj, xij);
    let si = dot(xij, di);
    let sj = dot(xij, dj);
    if (si * sj <= 0.0) {
        return vij;
    }
    let q = si / sj;
    let phi = min(4.0 * q / ((1.0 + q) * (1.0 + q)), 1.0);
    return vij - (di + dj) * (0.5 * phi);
}

// What particle i's pair terms read of it, read once before its walk.
struct Own {
    body: Body,
    hi: f32,
    rigid: bool,
    boundary: bool,
    surface: bool,
    l: vec4<f32>,
    t: vec4<f32>,
    v: vec2<f32>,
    vs: vec2<f32>,
    g: vec4<f32>,
    // The velocity and gradient the hourglass control sees (`hg_seen`).
    vh: vec2<f32>,
    gh: vec4<f32>,
    rho: f32,
    // m_i / rho_i and kappa_i^2, for the close-pair gate.
    vol: f32,
    k2: f32,
    // R_i (art_of), zero without the artificial stress.
    art: vec4<f32>,
    // Not failed: a failed particle takes no part in the artificial stress.
    intact: bool,
    // Flows plastically (ART_FLOW; `t.w` holds the sound speed itself).
    flows: bool,
    alpha: f32,
    beta: f32,
    // Its share of itself on the modelled side of a symmetry plane
    // (`plane_share`).
    share: f32,
}

// The sums of the walk.
struct Sums {
    acc: vec2<f32>,
    de: f32,
    // The boundary's kernel sum over boundary neighbours (contact area).
    sw: f32,
    // The colour gradient with reference volumes, and its rate.
    g0: vec2<f32>,
    gdot: vec2<f32>,
    // The artificial terms' share of `de` (DISS).
    dd: f32,
}

// Add the SPH pair (i, j) (inside the support) to the sums; `img`: 0 for
// j itself, else the coordinates the mirror image of j the pair is with
// reverses (`image_flip`), which has j's values mirrored; j at radius `rj`
// (bodies of revolution).
fn add_pair(o: Own, j: u32, mj: vec4<u32>, pr: Pair, img: u32, rj: f32, sums: ptr<function, Sums>) {
    add_boundary(o, j, mj, pr, img, sums);
    add_sph(o, j, mj, pr, img, rj, sums);
}

// A boundary particle's contact area and normal terms of a pair with the
// round supports of the bodies' h (`add_pair`).
fn add_boundary(o: Own, j: u32, mj: vec4<u32>, pr: Pair, img: u32, sums: ptr<function, Sums>) {
    let hij = pr.hij;
    let dist = pr.dist;
    if (o.boundary && nbo[j].z > 0.0 && LEAP != 3u) {
        // A particle on a symmetry plane counts for its share, its image
        // for the rest.
        if (ONPLANE) {
            (*sums).sw += plane_share(j) * kernel_w(dist, hij);
        } else {
            (*sums).sw += kernel_w(dist, hij);
        }
    }
    if (o.boundary && dist > 0.0) {
        var vj = v[j];
        if (img != 0u) {
            vj = mirror_vec(img, vj);
        }
        // With contact on, j is of i's body.
        let v0 = reference_volume(mj, o.body.rho0);
        (*sums).g0 -= pr.gw * v0;
        (*sums).gdot -= hess_times(pr.d, dist, hij, o.v - vj) * v0;
    }
}

// The velocity jumps a pair's artificial terms see: the viscosity's
// (`vis`, reconstructed where it applies), the momentum's (`vm`, the
// predicted velocities in a leapfrog step; the artificial stress's heat
// gate reads these in both passes) and the hourglass control's (`vf`: the
// forces' in an evaluation, v_{n+1/2} in a leapfrog step, `hg_seen`). The
// energy sum keeps the true v_ij.
struct Jumps {
    vis: vec2<f32>,
    vm: vec2<f32>,
    vf: vec2<f32>,
}

fn seen_jumps(o: Own, j: u32, img: u32, vij: vec2<f32>, d: vec2<f32>) -> Jumps {
    var vis = vij;
    if (LEAP == 3u) {
        var vsj = vstar[j];
        if (img != 0u) {
            vsj = mirror_vec(img, vsj);
        }
        vis = o.vs - vsj;
    }
    let vm = vis;
    var vf = vis;
    if (HG_HALF) {
        var vhj = vhalf[j];
        if (img != 0u) {
            vhj = mirror_vec(img, vhj);
        }
        vf = o.vh - vhj;
    }
    // Not at a surface (h |grad psi| above the threshold) unless the scene
    // asks: there grad v is one-sided and a contact loads the face
    // impulsively.
    if (RECON && (RECON_SURF || (!o.surface && nbo[j].z <= 0.0))) {
        var gj = gradv[j];
        if (img != 0u) {
            gj = mirror_mat(img, gj);
        }
        vis = reconstructed_jump(vis, d, o.g, gj);
    }
    return Jumps(vis, vm, vf);
}

// The viscosity's Pi (Monaghan's, or with RELEASE the Riemann form) on
// approaching pairs; with RELEASE receding ones too, on the linear term,
// unless a failed particle or an open void is in the pair (an opening
// crack carries no traction). `cj` is j's sound speed. CPU twin:
// physics::viscosity::viscosity_pi.
fn pair_pi(o: Own, jumps: Jumps, d: vec2<f32>, hij: f32, cj: f32, bj: Body, j: u32, rj: f32) -> f32 {
    var vx = dot(jumps.vis, d);
    var on = vx < 0.0;
    if (RELEASE) {
        // The smaller of the seen and the true jump where they agree in
        // sign: heat, and continuous where either passes zero.
        let tx = dot(jumps.vm, d);
        on = vx * tx > 0.0 && (tx < 0.0 || (o.intact && intact(j)));
        if (tx * tx < vx * vx) {
            vx = tx;
        }
    }
    if (!on) {
        return 0.0;
    }
    let muv = hij * vx / (dot(d, d) + 0.01 * hij * hij);
    let cm = 0.5 * (o.t.w + cj);
    let rhom = 0.5 * (o.rho + sum_density(bj, j, rj));
    var beta = o.beta;
    if (vx >= 0.0) {
        beta = 0.0;
    }
    return (-o.alpha * cm * muv + beta * muv * muv) / rhom;
}

// The artificial stress (R_i + R_j) f^n of a pair, where it acts (`on`):
// where one of its particles is in tension (the trace of R_i + R_j, R
// negative semi-definite, below zero) and, in the close-pair form, where
// its gate is open; R_j comes from t_j. It holds intact material together
// against the tensile instability; a failed particle is bonded to
// nothing. CPU twin: cpu::forces::art_stress.
struct ArtPair {
    on: bool,
    rf: vec4<f32>,
}

fn art_pair(o: Own, bj: Body, j: u32, mj: vec4<u32>, rj: f32, pr: Pair, tj: vec4<f32>, flows_j: bool, g: vec2<f32>, vm: vec2<f32>) -> ArtPair {
    var out = ArtPair(false, vec4<f32>(0.0));
    let dist = pr.dist;
    var gate = 1.0;
    if (ART_CLOSE) {
        let rho_j = sum_density(bj, j, rj);
        var vol = 0.5 * (o.vol + bitcast<f32>(mj.x) / rho_j);
        if (ONPLANE) {
            // The whole particles' volumes, on a symmetry plane too.
            vol = 0.5 * (o.vol / o.share + bitcast<f32>(mj.x) / (rho_j * plane_share(j)));
        }
        // kappa^2 <= 1 only shrinks the spacing: a gate shut at 1 is
        // shut, and most pairs read no kappa. Where supports adapt, in
        // the pair's metric.
        var u2 = dist * dist;
        var vs = vol;
        if (ADAPT && pr.scale > 0.0) {
            u2 = pr.q2;
            vs = vol * pr.scale;
        }
        gate = close_gate(u2, vs, 1.0);
        if (ART_KAPPA && gate > 0.0) {
            gate = close_gate(u2, vs, min(o.k2, kappa[mj.w]));
        }
    }
    if (gate <= 0.0) {
        return out;
    }
    var rs = o.art;
    if (bj.art != 0u) {
        rs += art_of(tj);
    }
    if (!(rs.x + rs.y < 0.0 && intact(j))) {
        return out;
    }
    let dp = 0.5 * (o.body.spacing + bj.spacing);
    var aw = 0.0;
    if (ADAPT && pr.scale > 0.0) {
        aw = art_weight(sqrt(pr.q2), dp / (0.5 * (o.hi + bj.h)), 1.0);
    } else {
        aw = art_weight(dist, dp, pr.hij);
    }
    var rf = rs * (aw * gate);
    // Where its work may only be heat (everywhere, or at a pair that flows
    // plastically), the share of it that is, read at the momentum's
    // velocities (tension::heat_share).
    if (ART_HEAT || (ART_FLOW && (o.flows || flows_j))) {
        let rg = sym_mul(rf, g);
        let scale = HEAT_SPEED * 0.5 * (o.t.w + tj.w) * length(rg);
        var share = 0.0;
        if (scale > 0.0) {
            share = clamp(-dot(vm, rg) / scale, 0.0, 1.0);
        }
        rf *= share;
    }
    out.on = true;
    out.rf = rf;
    return out;
}

// The momentum and energy terms of a pair (`add_pair`); where supports
// adapt, `pr` is the pair in its mean metric.
fn add_sph(o: Own, j: u32, mj: vec4<u32>, pr: Pair, img: u32, rj: f32, sums: ptr<function, Sums>) {
    var vj = v[j];
    if (img != 0u) {
        vj = mirror_vec(img, vj);
    }
    if (o.rigid || pr.dist <= 0.0) {
        return;
    }
    // With contact on, j is of i's body (`body_pair`).
    var bj = o.body;
    if (!CONTACT) {
        bj = bodies[mj.z];
    }
    let d = pr.d;
    var lj = lmat[j];
    var tj = sr2c[j];
    var flows_j = false;
    if (ART_FLOW) {
        flows_j = tj.w < 0.0;
        tj.w = abs(tj.w);
    }
    if (img != 0u) {
        lj = mirror_mat(img, lj);
        tj = mirror_sym(img, tj);
    }
    let g = mat_mul(0.5 * (o.l + lj), pr.gw);
    let vij = o.v - vj;
    let jumps = seen_jumps(o, j, img, vij, d);
    let pi = pair_pi(o, jumps, d, pr.hij, tj.w, bj, j, rj);
    // Each side's stress vector (cpu::forces::PairTerms::s): the paper's
    // form keeps the stress terms in t on g; the variational one gives
    // each side its own corrected gradient, sigma/(rho_i rho_j) L grad W
    // (sigma/(eta_i rho_i) L grad W in a body of revolution).
    var t = vec4<f32>(o.t.xyz + tj.xyz, 0.0);
    var si = sym_mul(o.t, g);
    var sv = vec2<f32>(0.0);
    if (VARIATIONAL) {
        var fi = 1.0;
        var fj = 1.0;
        if (!AXI) {
            let rho_j = sum_density(bj, j, rj);
            fi = o.rho / rho_j;
            fj = rho_j / o.rho;
        }
        si = sym_mul(o.t, mat_mul(o.l, pr.gw)) * fi;
        sv = si + sym_mul(tj, mat_mul(lj, pr.gw)) * fj;
        t = vec4<f32>(0.0);
    }
    t.x -= pi;
    t.y -= pi;
    // The artificial stress's work, half to each particle of the pair, is
    // booked as heat so total energy stays conserved.
    var art_work = 0.0;
    var rfg = vec2<f32>(0.0);
    if (ART_STRESS && o.intact) {
        let art = art_pair(o, bj, j, mj, rj, pr, tj, flows_j, g, jumps.vm);
        if (art.on) {
            t += art.rf;
            rfg = sym_mul(art.rf, g);
            art_work = 0.5 * dot(vij, rfg);
        }
    }
    var hg = Hourglass(vec2<f32>(0.0), vec2<f32>(0.0));
    if (HG > 0.0) {
        var gj = gradv[j];
        if (HG_HALF) {
            gj = gradh[j];
        }
        if (img != 0u) {
            gj = mirror_mat(img, gj);
        }
        hg = hourglass(o, bj, jumps.vf, d, pr.gw, gj, tj.w, bj.h, sum_density(bj, j, rj));
    }
    let mass_j = bitcast<f32>(mj.x);
    if (LEAP != 3u) {
        (*sums).acc += (sym_mul(t, g) + sv + hg.xi + hg.xj) * mass_j;
    }
    if (LEAP != 2u) {
        (*sums).de -= mass_j * (dot(vij, si + hg.xi) - 0.5 * pi * dot(vij, g) + art_work);
        if (DISS_SUMS) {
            // The artificial part of i's energy vector (PairTerms::a).
            (*sums).dd -= mass_j * dot(vij, 0.5 * (rfg - pi * g) + hg.xi);
        }
    }
}

// A pair's hourglass terms per unit m_i m_j: i's family's force on i
// (`xi`, heat -m_j v_ij.xi to i) and j's family's (`xj`, heat -m_i
// v_ij.xj to j, which j's own walk books).
struct Hourglass {
    xi: vec2<f32>,
    xj: vec2<f32>,
}

// The hourglass control of the pair (i, j) at the velocities the forces
// see, `vf = v_i - v_j`, `d = x_i - x_j`, the kernel gradient `gw`, j's
// velocity gradient, sound speed, h and density (eta in a body of
// revolution). CPU twin: cpu::forces::hourglass.
fn hourglass(o: Own, bj: Body, vf: vec2<f32>, d: vec2<f32>, gw: vec2<f32>, gj: vec4<f32>, cj: f32, hj: f32, rho_j: f32) -> Hourglass {
    let r2 = dot(d, d);
    if (r2 <= 0.0) {
        return Hourglass(vec2<f32>(0.0), vec2<f32>(0.0));
    }
    let w = -dot(gw, d) / r2;
    let di = mat_mul(o.gh, d) - vf;
    let dj = vf - mat_mul(gj, d);
    // Each family at its body's coefficient.
    let ki = o.body.hg * w;
    let kj = bj.hg * w;
    // V_j/m_j: 1/rho_j; in a body of revolution 1/eta_i.
    var vi = rho_j;
    var vj = o.rho;
    if (AXI) {
        vi = o.rho;
        vj = rho_j;
    }
    return Hourglass(di * (ki * o.t.w * o.hi / vi), dj * (-kj * cj * hj / vj));
}
