// Test support: every particle's neighbours within 2 h_ij (all bodies), as
// original particle ids, so the device's cell list can be compared with the
// CPU's pair by pair; and the candidates its walk visits (the last entry of
// its record), to check the host's count of the walks' work (gpu::work).

@group(0) @binding(50) var<storage, read_write> dump: array<u32>;

// A particle's record: the count, up to MAX_DUMP ids, the visits.
const STRIDE: u32 = 128u;
const MAX_DUMP: u32 = 126u;

@compute @workgroup_size(WG)
fn dump_neighbours(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    let hi = bodies[pinfo[i].z].h;
    let cs = consts();
    let wk = walker(i);
    let base = pinfo[i].w * STRIDE;
    var count = 0u;
    var visits = 0u;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            visits += 1u;
            let cd = cand(wk, k, cs);
            let j = cd.j;
            if (j == i || !in_row(cd.cell, span)) {
                continue;
            }
            let hij = 0.5 * (hi + bodies[pinfo[j].z].h);
            if (length(cd.d) < 2.0 * hij && count < MAX_DUMP) {
                count += 1u;
                dump[base + count] = pinfo[j].w;
            }
        }
    }
    dump[base] = count;
    dump[base + STRIDE - 1u] = visits;
}

// Test support: the equation of state of body `q.w` at given states `q`
// = (mu, e, damage, body), as (pressure, sound speed), for the tests that
// hold it to its formula (CPU twin: MaterialModel::pressure_of).
@group(0) @binding(90) var<storage, read> eos_in: array<vec4<f32>>;
@group(0) @binding(91) var<storage, read_write> eos_out: array<vec2<f32>>;

@compute @workgroup_size(WG)
fn eos_table(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= arrayLength(&eos_in)) {
        return;
    }
    let q = eos_in[i];
    let b = bodies[u32(q.w)];
    eos_out[i] = vec2<f32>(pressure_of(b, q.x, q.y, q.z), sound_speed_of(b, q.x, q.y, q.z));
}

// Test support: the strength law of a body at given rows, each two vec4s:
// (eps_p, rate, T - T_room, q_trial) and (body, 0, 0, 0); out, in the first
// of two vec4s a row: (the law's factor, flow stress, its slope, the
// return's plastic strain increment from q_trial with the body's shear
// modulus), for the tests that hold each law to its formula (CPU twin:
// physics::laws::return_increment).
@group(0) @binding(92) var<storage, read> law_in: array<vec4<f32>>;
@group(0) @binding(93) var<storage, read_write> law_out: array<vec4<f32>>;

@compute @workgroup_size(WG)
fn law_table(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = 2u * gid.x;
    if (i >= arrayLength(&law_in)) {
        return;
    }
    let q = law_in[i];
    let bi = u32(law_in[i + 1u].x);
    let p = plastic[bi];
    let f = law_factor(p, q.y, q.z);
    let c = law_curve(p, f, q.x);
    law_out[i] = vec4<f32>(f, c.x, c.y, return_increment(p, q.w, bodies[bi].g, q.x, f));
}
