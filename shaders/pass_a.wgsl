// Pass A (METHOD.md §5, §6, §8.1): per particle, one neighbour loop gathers
// the correction matrix M_i, the colour gradient and the uncorrected velocity
// gradient sum; then L_i = M_i^-1, the equation of state, sigma/rho^2 and the
// sound speed, and the corrected velocity gradient
// grad v_i = [sum_j V_j (v_j - v_i) (x) grad_i W_ij] L_i^T (L_i is particle
// i's own, so it factors out of the sum), giving the continuity rate and the
// Jaumann stress rate. CPU twins: cpu::kinematics::kinematics,
// cpu::eos_and_stress.
//
// dr and ds are where the rates go (common.wgsl, MID): at the base state
// the midpoint buffers (rm, sm), which receive the rates themselves; at the
// midpoint the base state (r, s), which receives dt x rate in place.

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read> s: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read_write> lmat: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read_write> nbo: array<vec4<f32>>;
@group(0) @binding(14) var<storage, read_write> sr2c: array<vec4<f32>>;
@group(0) @binding(15) var<storage, read_write> art: array<vec4<f32>>;
@group(0) @binding(16) var<storage, read_write> dr: array<vec2<f32>>;
@group(0) @binding(17) var<storage, read_write> ds: array<vec4<f32>>;
@group(0) @binding(36) var<storage, read_write> gradv: array<vec4<f32>>;

// Artificial stress (METHOD.md §4): -eps sigma/rho^2 of each tensile
// principal value, rotated back.
fn artificial_stress(sig: vec4<f32>, rho: f32) -> vec4<f32> {
    let m = 0.5 * (sig.x + sig.y);
    let rad = sqrt(0.25 * (sig.x - sig.y) * (sig.x - sig.y) + sig.z * sig.z);
    let th = 0.5 * atan2(2.0 * sig.z, sig.x - sig.y);
    let a = m + rad;
    let b = m - rad;
    let r2 = rho * rho;
    var ra = 0.0;
    var rb = 0.0;
    if (a > 0.0) {
        ra = -params.as_eps * a / r2;
    }
    if (b > 0.0) {
        rb = -params.as_eps * b / r2;
    }
    let sn = sin(th);
    let cs = cos(th);
    return vec4<f32>(ra * cs * cs + rb * sn * sn, ra * sn * sn + rb * cs * cs, (ra - rb) * sn * cs, 0.0);
}

// V_j = m_j / rho_j.
fn volume(j: u32, mj: vec4<u32>) -> f32 {
    return bitcast<f32>(mj.x) / (bodies[mj.z].rho0 * (1.0 + r[j].x));
}

@compute @workgroup_size(WG)
fn pass_a(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    let mi = pinfo[i];
    let bi = mi.z;
    let body = bodies[bi];
    let hi = body.h;
    let hm = home(i);

    // Rigid particles have no velocity gradient: their loop skips the
    // velocity reads (a branch uniform over the particle's whole loop).
    let rigid = body.rigid != 0u;
    let vi = v[i];
    var m = vec4<f32>(0.0);
    var gpsi = vec2<f32>(0.0);
    var gsum = vec4<f32>(0.0);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(hm, row);
        for (var k = span.start; k < span.end; k++) {
            let j = row_particle(k);
            let pr = body_pair(i, j, span, hi, bi);
            if (!pr.inside || pr.dist <= 0.0) {
                continue;
            }
            let gj = pr.gw * volume(j, pinfo[j]);
            m += outer(gj, -pr.d);
            gpsi -= gj;
            if (!rigid) {
                gsum += outer(v[j] - vi, gj);
            }
        }
    }

    var l = vec4<f32>(1.0, 0.0, 0.0, 1.0);
    if (CORRECTED) {
        if (DIM == 1u) {
            m.w = 1.0;
        }
        let det = m.x * m.w - m.y * m.z;
        if (abs(det) > params.min_det) {
            let q = 1.0 / det;
            l = vec4<f32>(m.w * q, -m.y * q, -m.z * q, m.x * q);
        } else {
            atomicAdd(&ctl.fallback_now, 1u);
        }
    }
    lmat[i] = l;

    var normal = vec2<f32>(0.0);
    let glen = length(gpsi);
    if (glen > 0.0) {
        normal = gpsi / glen;
    }
    var boundary = 0.0;
    if (hi * glen > params.boundary_threshold) {
        boundary = 1.0;
    }
    nbo[i] = vec4<f32>(normal, boundary, 0.0);

    // Equation of state and sigma/rho^2 (tension positive), sound speed in w.
    let mu = r[i].x;
    let e = r[i].y;
    let p = eos_pressure(body, mu, e);
    let c = eos_sound_speed(body, mu, e);
    let si = s[i];
    let sig = vec4<f32>(si.x - p, si.y - p, si.z, si.w - p);
    let rho = body.rho0 * (1.0 + mu);
    sr2c[i] = vec4<f32>(sig.xyz / (rho * rho), c);
    if (ART_STRESS) {
        art[i] = artificial_stress(sig, rho);
    }

    if (rigid) {
        if (!MID) {
            dr[i] = vec2<f32>(0.0);
            ds[i] = vec4<f32>(0.0);
        }
        if (RECON) {
            gradv[i] = vec4<f32>(0.0);
        }
        return;
    }

    // Velocity gradient with the corrected kernel gradient (METHOD.md §6):
    // gsum L^T, in the order of math::Mat2::mul_transpose.
    let gv = vec4<f32>(
        gsum.x * l.x + gsum.y * l.y,
        gsum.x * l.z + gsum.y * l.w,
        gsum.z * l.x + gsum.w * l.y,
        gsum.z * l.z + gsum.w * l.w,
    );
    if (RECON) {
        gradv[i] = gv;
    }
    let tr = gv.x + gv.w;
    let dmu = -(1.0 + mu) * tr;

    // Jaumann-rate hypoelastic deviatoric stress rate, plane strain.
    let g = body.g;
    let exy = 0.5 * (gv.y + gv.z);
    let w = 0.5 * (gv.y - gv.z);
    let tr3 = tr / 3.0;
    let rate = vec4<f32>(
        2.0 * g * (gv.x - tr3) + 2.0 * w * si.z,
        2.0 * g * (gv.w - tr3) - 2.0 * w * si.z,
        2.0 * g * exy + w * (si.y - si.x),
        -2.0 * g * tr3,
    );
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
