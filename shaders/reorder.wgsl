// Particles reordered by cell for memory locality: gather every
// per-particle array into scratch in the order of the cell list (the host
// copies it back), then refresh the slots of the probed particles.
//
// A state reached by a zero-length step (the run waiting at a stop: a
// snapshot, a checkpoint or the end) keeps its order. The host schedules a
// reorder every few *real* steps, but how many zero-length steps a batch
// spends at a stop depends on how the host sized it (by wall time); were
// they reordered, the order, hence the sums' order and the result's last
// bits, would depend on the batch sizes. Skipping them makes a run the same
// whatever its batches, which a resumed run relies on.

@group(0) @binding(5) var<storage, read> v: array<vec2<f32>>;
@group(0) @binding(6) var<storage, read> r: array<vec2<f32>>;
@group(0) @binding(7) var<storage, read> s: array<vec4<f32>>;
@group(0) @binding(24) var<storage, read> qheat: array<vec2<f32>>;
// The probed particles' ids, sorted, padded with 0xffffffff to one entry a
// probe (`params.nprobes`), and each entry's slot (gpu::probe_tables).
@group(0) @binding(47) var<storage, read> probe_ids: array<u32>;
@group(0) @binding(48) var<storage, read_write> probe_slot: array<u32>;
@group(0) @binding(40) var<storage, read_write> t_x0: array<vec4<f32>>;
@group(0) @binding(41) var<storage, read_write> t_u: array<vec2<f32>>;
@group(0) @binding(42) var<storage, read_write> t_v: array<vec2<f32>>;
@group(0) @binding(43) var<storage, read_write> t_r: array<vec2<f32>>;
@group(0) @binding(44) var<storage, read_write> t_s: array<vec4<f32>>;
@group(0) @binding(45) var<storage, read_write> t_pinfo: array<vec4<u32>>;
@group(0) @binding(46) var<storage, read_write> t_qheat: array<vec2<f32>>;
@group(0) @binding(74) var<storage, read> centry: array<f32>;
@group(0) @binding(75) var<storage, read_write> t_centry: array<f32>;

@compute @workgroup_size(WG)
fn permute(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = flat_index(gid, nwg);
    if (k >= params.n) {
        return;
    }
    var i = blist[k];
    if (ctl.dt == 0.0 && ctl.step > 0u) {
        i = k;
    }
    t_x0[k] = x0[i];
    t_u[k] = u[i];
    t_v[k] = v[i];
    t_r[k] = r[i];
    t_s[k] = s[i];
    t_pinfo[k] = pinfo[i];
    if (CONTACT) {
        t_qheat[k] = qheat[i];
        t_centry[k] = centry[i];
    }
}

@compute @workgroup_size(WG)
fn map_slots(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = flat_index(gid, nwg);
    if (k >= params.n) {
        return;
    }
    // Binary search of the particle's id among the probed ones: the lowest
    // entry not below it.
    let id = pinfo[k].w;
    var lo = 0u;
    var hi = params.nprobes;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (probe_ids[mid] < id) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    if (lo < params.nprobes && probe_ids[lo] == id) {
        probe_slot[lo] = k;
    }
}

// The leapfrog's reorder: one array at a time gathered into scratch (the
// host copies it back), through views of 16, 8 or 4 bytes an element so
// that every bit is kept. Its arrays are more than the midpoint rule's
// (its carried rates, and what the next step's reductions read), and one
// kernel a width serves them all.
@group(0) @binding(58) var<storage, read> p_src4: array<vec4<u32>>;
@group(0) @binding(59) var<storage, read_write> p_dst4: array<vec4<u32>>;
@group(0) @binding(60) var<storage, read> p_src2: array<vec2<u32>>;
@group(0) @binding(61) var<storage, read_write> p_dst2: array<vec2<u32>>;
@group(0) @binding(62) var<storage, read> p_src1: array<u32>;
@group(0) @binding(63) var<storage, read_write> p_dst1: array<u32>;

// The slot whose particle goes to slot k (as `permute`).
fn source_of(k: u32) -> u32 {
    if (ctl.dt == 0.0 && ctl.step > 0u) {
        return k;
    }
    return blist[k];
}

@compute @workgroup_size(WG)
fn permute4(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = flat_index(gid, nwg);
    if (k < params.n) {
        p_dst4[k] = p_src4[source_of(k)];
    }
}

@compute @workgroup_size(WG)
fn permute2(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = flat_index(gid, nwg);
    if (k < params.n) {
        p_dst2[k] = p_src2[source_of(k)];
    }
}

@compute @workgroup_size(WG)
fn permute1(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = flat_index(gid, nwg);
    if (k < params.n) {
        p_dst1[k] = p_src1[source_of(k)];
    }
}
