// Test support: every particle's neighbours within 2 h_ij (all bodies), as
// original particle ids, so the device's cell list can be compared with the
// CPU's pair by pair.

@group(0) @binding(3) var<storage, read> x0: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> u: array<vec2<f32>>;
@group(0) @binding(8) var<storage, read> pinfo: array<vec4<u32>>;
@group(0) @binding(9) var<storage, read> cellc: array<vec2<i32>>;
@group(0) @binding(10) var<storage, read> bstart: array<u32>;
@group(0) @binding(11) var<storage, read> blist: array<u32>;
@group(0) @binding(50) var<storage, read_write> dump: array<u32>;

const MAX_DUMP: u32 = 127u;

@compute @workgroup_size(WG)
fn dump_neighbours(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    let hi = bodies[pinfo[i].z].h;
    let ci = cellc[i];
    let rows = scan_rows();
    let base = pinfo[i].w * (MAX_DUMP + 1u);
    var count = 0u;
    for (var dy = -rows; dy <= rows; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let c = ci + vec2<i32>(dx, dy);
            let b = bucket_of(c);
            let end = bstart[b + 1u];
            for (var k = bstart[b]; k < end; k++) {
                let j = blist[k];
                if (j == i || any(cellc[j] != c)) {
                    continue;
                }
                let hij = 0.5 * (hi + bodies[pinfo[j].z].h);
                let d = pair_d(i, j);
                if (length(d) < 2.0 * hij && count < MAX_DUMP) {
                    count += 1u;
                    dump[base + count] = pinfo[j].w;
                }
            }
        }
    }
    dump[base] = count;
}

// x0 holds each particle's reference cell (integral, exact in f32) and its
// offset in that cell at the start; u the displacement since. A pair's
// difference is formed from the three parts, so its round-off scales with
// the pair distance, not with the distance from the origin.
fn pair_d(i: u32, j: u32) -> vec2<f32> {
    let a = x0[i];
    let b = x0[j];
    return (a.xy - b.xy) * params.cell + (a.zw - b.zw) + (u[i] - u[j]);
}

// The cell a particle is in now: its reference cell plus whole cells moved.
fn current_cell(i: u32) -> vec2<i32> {
    let a = x0[i];
    return vec2<i32>(a.xy) + vec2<i32>(floor((a.zw + u[i]) * params.inv_cell));
}

// Absolute position (output only).
fn position(i: u32) -> vec2<f32> {
    let a = x0[i];
    return vec2<f32>(params.origin_x, params.origin_y) + a.xy * params.cell + (a.zw + u[i]);
}
