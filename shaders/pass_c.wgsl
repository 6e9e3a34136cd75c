// Pass C (METHOD.md §4): momentum and energy sums with the pair-symmetric
// corrected gradient G_ij = (L_i + L_j)/2 grad_i W_ij, Monaghan viscosity
// and, when the scene switches it on, artificial stress. With contact on it
// also measures each boundary particle's contact area (METHOD.md §8.4).
// CPU twins: cpu::forces::momentum_energy, cpu::kinematics::boundary.
//
// dv and dr.y take the rates at the base state (into the midpoint buffers)
// and dt x rate added in place to the base state at the midpoint
// (common.wgsl, MID). The leapfrog (common.wgsl, LEAP) runs it twice a
// step: at n+1 for the momentum alone (LEAP = 2; `v` is then the predicted
// velocity, `dv` the carried a_{n+1}), then, after the kick, for the energy
// alone (LEAP = 3): the same pair terms, the viscosity at the predicted
// velocity `vstar`, their work on v_{n+1} (`v`), added to the contact heat
// the booking left in dr.y (CPU twins: cpu::forces::momentum_keeping and
// energy_replay, which keeps the pair terms instead of walking again).

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(12) var<storage, read> lmat: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read> nbo: array<vec4<f32>>;
@group(0) @binding(14) var<storage, read> sr2c: array<vec4<f32>>;
@group(0) @binding(15) var<storage, read> art: array<vec4<f32>>;
@group(0) @binding(16) var<storage, read_write> dr: array<vec2<f32>>;
@group(0) @binding(18) var<storage, read_write> dv: array<vec2<f32>>;
@group(0) @binding(19) var<storage, read_write> area: array<f32>;
@group(0) @binding(36) var<storage, read> gradv: array<vec4<f32>>;
@group(0) @binding(53) var<storage, read> vstar: array<vec2<f32>>;

// mu = rho/rho0 - 1 of particle j: in a leapfrog step the n+1 value its
// kinematic pass left in the carried rates' free slot (dr.x).
fn mu_of(j: u32) -> f32 {
    if (LEAP >= 2u) {
        return dr[j].x;
    }
    return r[j].x;
}

// The velocity jump the viscosity sees: v_ij less each side's linear
// reconstruction to the pair midpoint, van Leer limited (xij = x_i - x_j).
// CPU twin: cpu::forces::reconstructed_jump.
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

@compute @workgroup_size(WG)
fn pass_c(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    // A leapfrog step of zero length leaves the carried rates as they are.
    if (i >= params.n || (LEAP >= 2u && ctl.dt == 0.0)) {
        return;
    }
    let mi = pinfo[i];
    let bi = mi.z;
    let body = bodies[bi];
    let hi = body.h;
    let rigid = body.rigid != 0u;
    let boundary = CONTACT && nbo[i].z > 0.0;
    if (rigid && !boundary) {
        if (LEAP == 3u) {
            return;
        }
        if (!MID) {
            dv[i] = vec2<f32>(0.0);
            dr[i].y = 0.0;
        }
        if (CONTACT) {
            area[i] = 0.0;
        }
        return;
    }
    let cs = consts();
    let wk = walker(i);
    let li = lmat[i];
    let ti = sr2c[i];
    let vi = v[i];
    var gi = vec4<f32>(0.0);
    if (RECON) {
        gi = gradv[i];
    }
    let rhoi = body.rho0 * (1.0 + mu_of(i));
    var ri = vec4<f32>(0.0);
    if (ART_STRESS) {
        ri = art[i];
    }

    var vsi = vec2<f32>(0.0);
    if (LEAP == 3u) {
        vsi = vstar[i];
    }
    let surface_i = nbo[i].z > 0.0;
    let alpha = params.alpha;
    let beta = params.beta;

    var acc = vec2<f32>(0.0);
    var de = 0.0;
    var sw = kernel_w(0.0, hi);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let j = cd.j;
            let mj = pinfo[j];
            let pr = body_pair(wk, cd, mj.z, span, hi, bi);
            if (!pr.inside) {
                continue;
            }
            let hij = pr.hij;
            let dist = pr.dist;
            if (boundary && nbo[j].z > 0.0 && LEAP != 3u) {
                sw += kernel_w(dist, hij);
            }
            if (rigid || dist <= 0.0) {
                continue;
            }
            // With contact on, j is of i's body (`body_pair`).
            var bj = body;
            if (!CONTACT) {
                bj = bodies[mj.z];
            }
            let d = pr.d;
            let gw = pr.gw;
            let g = mat_mul(0.5 * (li + lmat[j]), gw);
            let tj = sr2c[j];
            let vij = vi - v[j];
            // Monaghan viscosity, zero for receding pairs; it sees the
            // reconstructed jump, the energy sum keeps the true v_ij.
            var vis = vij;
            if (LEAP == 3u) {
                vis = vsi - vstar[j];
            }
            // Not at a surface (h |grad psi| above the threshold): there
            // grad v is one-sided and a contact loads the face impulsively.
            if (RECON && !surface_i && nbo[j].z <= 0.0) {
                vis = reconstructed_jump(vis, d, gi, gradv[j]);
            }
            var pi = 0.0;
            let vx = dot(vis, d);
            if (vx < 0.0) {
                let muv = hij * vx / (dot(d, d) + 0.01 * hij * hij);
                let cm = 0.5 * (ti.w + tj.w);
                let rhom = 0.5 * (rhoi + bj.rho0 * (1.0 + mu_of(j)));
                pi = (-alpha * cm * muv + beta * muv * muv) / rhom;
            }
            var t = vec4<f32>(ti.xyz + tj.xyz, 0.0);
            t.x -= pi;
            t.y -= pi;
            // The artificial stress's work, half to each particle of the
            // pair, is booked as heat so total energy stays conserved.
            var art_work = 0.0;
            if (ART_STRESS) {
                let dp = 0.5 * (body.spacing + bj.spacing);
                let f = kernel_w(dist, hij) / kernel_w(dp, hij);
                let rf = (ri + art[j]) * pow(f, params.as_n);
                t += rf;
                art_work = 0.5 * dot(vij, sym_mul(rf, g));
            }
            let mass_j = bitcast<f32>(mj.x);
            if (LEAP != 3u) {
                acc += sym_mul(t, g) * mass_j;
            }
            if (LEAP != 2u) {
                de -= mass_j * (dot(vij, sym_mul(ti, g)) - 0.5 * pi * dot(vij, g) + art_work);
            }
        }
    }
    if (LEAP == 3u) {
        if (!rigid) {
            dr[i].y = de + dr[i].y;
        }
        return;
    }
    if (!MID) {
        if (rigid) {
            dv[i] = vec2<f32>(0.0);
            dr[i].y = 0.0;
        } else {
            dv[i] = acc;
            dr[i].y = de;
        }
    } else if (!rigid && ctl.dt != 0.0) {
        dv[i] = dv[i] + acc * ctl.dt;
        dr[i].y = dr[i].y + de * ctl.dt;
    }
    if (CONTACT) {
        var a = 0.0;
        if (boundary) {
            if (DIM == 1u) {
                a = 1.0;
            } else {
                a = 15.0 / (7.0 * PI * hi) / sw;
            }
        }
        area[i] = a;
    }
}
