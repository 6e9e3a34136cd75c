// Cell-list neighbour search, rebuilt at every evaluation: each particle's
// cell and bucket, a count per bucket, an inclusive prefix sum (two
// passes), a scatter, and a sort of each bucket by slot so that the order
// within a cell is fixed whatever order the scatter's atomics took.
// Integer atomics only; the result is deterministic.
//
// One array per bucket does the counting sort (4 bytes a bucket, 1 to 2
// buckets a particle, gpu::bucket_count): it holds the bucket's count, then after the scan the
// end of the bucket in the sorted list, and the scatter counts that end back
// down to the bucket's start as it hands out the places, so that when the
// scatter is done `bstart[b]` is the start of bucket b and `bstart[b + 1]`
// its end.

// The host binds `bstart_w` and `blist_w` to the buffers the other stages
// read as `bstart` and `blist`. A particle's cell is `current_cell` (no
// buffer), so the cells and the scatter pass read the state of the
// evaluation being built for (the host makes one of each per state).
@group(0) @binding(16) var<storage, read_write> bstart_w: array<atomic<u32>>;
@group(0) @binding(17) var<storage, read_write> bsum: array<u32>;
@group(0) @binding(18) var<storage, read_write> blist_w: array<u32>;
// The length of the contact's list of boundary particles, which the
// evaluation's kinematics pass fills (kinematics.wgsl, list_surface).
@group(0) @binding(65) var<storage, read_write> surf_args: array<u32>;

const SCAN: u32 = 256u;
var<workgroup> sh: array<u32, 256>;

@compute @workgroup_size(WG)
fn grid_clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let b = flat_index(gid, nwg);
    if (CONTACT && b == 0u) {
        surf_args[0] = 0u;
    }
    if (b >= params.buckets) {
        return;
    }
    atomicStore(&bstart_w[b], 0u);
}

@compute @workgroup_size(WG)
fn grid_cells(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    atomicAdd(&bstart_w[bucket_of(current_cell(i))], 1u);
}

// Hillis-Steele inclusive scan of `sh` by the 256 threads of a workgroup.
fn scan_shared(lid: u32) {
    for (var off = 1u; off < SCAN; off = off * 2u) {
        workgroupBarrier();
        var add = 0u;
        if (lid >= off) {
            add = sh[lid - off];
        }
        workgroupBarrier();
        sh[lid] = sh[lid] + add;
    }
    workgroupBarrier();
}

// The scan of the bucket counts in two dispatches over the whole device:
// each workgroup scans a block of BLOCK buckets (four a thread) and leaves
// the block's total in `bsum`; then each workgroup adds the totals of the
// blocks before its own (a sum of at most buckets / BLOCK values, spread
// over its threads) to its block. Integer sums: any order gives the same.
const BLOCK: u32 = 1024u;

@compute @workgroup_size(256)
fn scan_local(@builtin(local_invocation_id) lid3: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let lid = lid3.x;
    let block = wid.x + wid.y * nwg.x;
    // A wrapped 2-D dispatch has a few whole workgroups past the end.
    if (block * BLOCK >= params.buckets) {
        return;
    }
    let base = block * BLOCK + 4u * lid;
    var part = array<u32, 4>(0u, 0u, 0u, 0u);
    var run = 0u;
    for (var k = 0u; k < 4u; k++) {
        if (base + k < params.buckets) {
            run += atomicLoad(&bstart_w[base + k]);
        }
        part[k] = run;
    }
    sh[lid] = run;
    scan_shared(lid);
    let before = sh[lid] - run;
    for (var k = 0u; k < 4u; k++) {
        if (base + k < params.buckets) {
            atomicStore(&bstart_w[base + k], before + part[k]);
        }
    }
    if (lid == SCAN - 1u) {
        bsum[block] = sh[lid];
    }
}

@compute @workgroup_size(256)
fn scan_add(@builtin(local_invocation_id) lid3: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let lid = lid3.x;
    let block = wid.x + wid.y * nwg.x;
    if (block * BLOCK >= params.buckets) {
        return;
    }
    var acc = 0u;
    for (var k = lid; k < block; k += SCAN) {
        acc += bsum[k];
    }
    sh[lid] = acc;
    scan_shared(lid);
    let offset = sh[SCAN - 1u];
    for (var k = 0u; k < 4u; k++) {
        let b = block * BLOCK + 4u * lid + k;
        if (b < params.buckets) {
            atomicAdd(&bstart_w[b], offset);
        }
    }
    if (block == 0u && lid == 0u) {
        atomicStore(&bstart_w[params.buckets], params.n);
    }
}

@compute @workgroup_size(WG)
fn grid_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if (i >= params.n) {
        return;
    }
    // The bucket again from the cell: recomputing both is cheaper than
    // keeping them (8 bytes a particle for the cell, 4 for the bucket).
    let b = bucket_of(current_cell(i));
    blist_w[atomicSub(&bstart_w[b], 1u) - 1u] = i;
}

// Insertion sort of each bucket by slot: buckets hold a cell's few
// particles (plus the rare hash collision).
@compute @workgroup_size(WG)
fn grid_sort(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let b = flat_index(gid, nwg);
    if (b >= params.buckets) {
        return;
    }
    let lo = atomicLoad(&bstart_w[b]);
    let hi = atomicLoad(&bstart_w[b + 1u]);
    for (var k = lo + 1u; k < hi; k = k + 1u) {
        let key = blist_w[k];
        var m = k;
        while (m > lo && blist_w[m - 1u] > key) {
            blist_w[m] = blist_w[m - 1u];
            m = m - 1u;
        }
        blist_w[m] = key;
    }
}
