// Particles reordered by cell for memory locality: gather every
// per-particle array into scratch in the order of the cell list (the host
// copies it back), then refresh the id -> slot map the probes use.
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
@group(0) @binding(29) var<storage, read_write> slot_of: array<u32>;
@group(0) @binding(40) var<storage, read_write> t_x0: array<vec4<f32>>;
@group(0) @binding(41) var<storage, read_write> t_u: array<vec2<f32>>;
@group(0) @binding(42) var<storage, read_write> t_v: array<vec2<f32>>;
@group(0) @binding(43) var<storage, read_write> t_r: array<vec2<f32>>;
@group(0) @binding(44) var<storage, read_write> t_s: array<vec4<f32>>;
@group(0) @binding(45) var<storage, read_write> t_pinfo: array<vec4<u32>>;
@group(0) @binding(46) var<storage, read_write> t_qheat: array<vec2<f32>>;

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
    }
}

@compute @workgroup_size(WG)
fn map_slots(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = flat_index(gid, nwg);
    if (k >= params.n) {
        return;
    }
    slot_of[pinfo[k].w] = k;
}
