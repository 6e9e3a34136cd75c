// Test support: every particle's neighbours within 2 h_ij (all bodies), as
// original particle ids, so the device's cell list can be compared with the
// CPU's pair by pair.

@group(0) @binding(50) var<storage, read_write> dump: array<u32>;

const MAX_DUMP: u32 = 127u;

@compute @workgroup_size(WG)
fn dump_neighbours(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    let hi = bodies[pinfo[i].z].h;
    let ci = current_cell(i);
    let base = pinfo[i].w * (MAX_DUMP + 1u);
    var count = 0u;
    for (var c = 0u; c < scan_cells(); c++) {
        let span = cell_span(ci, c);
        for (var k = span.start; k < span.end; k++) {
            let j = blist[k];
            if (j == i || any(current_cell(j) != span.cell)) {
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
    dump[base] = count;
}
