// The spread of the spring's pull through the contact normals (CPU twin:
// the spread forces of cpu::contact::penalty_booked). A boundary particle
// P's normal is its colour gradient g_P = -sum_j V0_j grad W(x_P - x_j)
// made unit, so the spring's dPhi/dg_P (pass 2 leaves it on the list as
// beta perp(n_P), `bt`) pulls on every neighbour j of P's body by
// -V0_j grad grad W (x_P - x_j) dPhi/dg_P. Pass 2 claims those j (a bit a
// particle, `claim`); each claimed particle gathers its pull here and
// clears its bit. Shared by the contact's own spread pass and the midpoint
// rule's advance passes: the stage that includes it declares nbo, cn, bt
// and claim.

// Bodies of revolution: each particle's area as placed, by original index.
@group(0) @binding(81) var<storage, read> area0: array<f32>;

// V0_j, the volume particle j was made with in the measure of the kernel
// sums: m_j / rho0, its area as placed in a body of revolution
// (Model::reference_volume).
fn spread_volume(mj: vec4<u32>, rho0: f32) -> f32 {
    if (AXI) {
        return area0[mj.w];
    }
    return bitcast<f32>(mj.x) / rho0;
}

// Claim particle j for the spread (contact.wgsl, pass 2).
fn claim_spread(j: u32) {
    let bit = 1u << (j & 31u);
    if ((atomicLoad(&claim[j >> 5u]) & bit) == 0u) {
        atomicOr(&claim[j >> 5u], bit);
    }
}

// The spread's force on particle j (zero without contact, where pass 2 did
// not claim it, or on a rigid body), its claim cleared.
fn spread_force(j: u32) -> vec2<f32> {
    if (!CONTACT) {
        return vec2<f32>(0.0);
    }
    let bit = 1u << (j & 31u);
    if ((atomicLoad(&claim[j >> 5u]) & bit) == 0u) {
        return vec2<f32>(0.0);
    }
    atomicAnd(&claim[j >> 5u], ~bit);
    let mj = pinfo[j];
    let bj = mj.z;
    let body = bodies[bj];
    if (body.rigid != 0u) {
        return vec2<f32>(0.0);
    }
    let cs = consts();
    let wk = walker(j);
    var f = vec2<f32>(0.0);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var kk = span.start; kk < span.end; kk++) {
            let cd = cand(wk, kk, cs);
            let p = cd.j;
            let mp = pinfo[p];
            let pr = body_pair(wk, cd, mp.z, span, body.h, bj);
            if (!pr.inside || pr.dist <= 0.0 || nbo[p].z <= 0.0) {
                continue;
            }
            let k = u32(nbo[p].w);
            let beta = bt[k];
            if (beta != 0.0) {
                let b = perp(cn[k].xy) * beta;
                f -= hess_times(pr.d, pr.dist, pr.hij, b);
                // P's pull on j's images, mirrored: j against P's images
                // with P's pull mirrored.
                for (var m = 0u; m < image_count(); m++) {
                    let im = image_pair(wk, m, cd.off, pr.d, pr.hij);
                    if (im.inside) {
                        f -= hess_times(im.d, im.dist, im.hij, mirror_vec(image_flip(m), b));
                    }
                }
            }
        }
    }
    if (image_count() > 0u && nbo[j].z > 0.0) {
        // j's own normal turns with its own images.
        let k = u32(nbo[j].w);
        let beta = bt[k];
        for (var m = 0u; m < image_count(); m++) {
            let im = image_pair(wk, m, wk.off, vec2<f32>(0.0), body.h);
            if (beta != 0.0 && im.inside) {
                f -= hess_times(im.d, im.dist, im.hij, mirror_vec(image_flip(m), perp(cn[k].xy) * beta));
            }
        }
    }
    return f * spread_volume(mj, body.rho0);
}
