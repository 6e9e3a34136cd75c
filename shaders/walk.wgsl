// The neighbour walk every stage shares: a particle's cell and its place
// in it, the rows of its stencil and the ranges of the sorted particle list
// they cover, the candidates and the pairs within reach, and the neighbour
// masks of the leapfrog. Assembled after common.wgsl (src/gpu/shaders.rs);
// the CPU's twin is src/cpu/neighbours.rs with src/math/cells.rs.

// Bucket of a cell in the hashed cell table: row-major keys modulo a power
// of two, so neighbouring cells of a row are neighbouring buckets and
// far-apart bodies need no large grid.
fn bucket_of(c: vec2<i32>) -> u32 {
    return (bitcast<u32>(c.x) + bitcast<u32>(c.y) * params.row_stride) & (params.buckets - 1u);
}

// Cells are a hair larger than the largest h, so a pair within 2 h_ij is at
// most REACH = 2 cells apart along each axis: a particle's candidates lie in
// the 5 x 5 cells around its own (5 cells in 1-D). Where supports adapt
// (ADAPT) a walk's stencil reaches ADAPT_ROWS cells either side, each
// walker's rows and columns clipped to its own reach (`Walker::reach`).
const REACH: i32 = 2;

// Supports that adapt: each particle's metric (common.wgsl).
@group(0) @binding(82) var<storage, read> metric: array<vec4<f32>>;

// The cells either side a walk's stencil spans: while every support is
// round (`adapting`), a round walk's, which the leapfrog's neighbour masks
// can then map (`row_map`).
fn stencil() -> i32 {
    if (adapting()) {
        return i32(ADAPT_ROWS);
    }
    return REACH;
}

// Where a particle is in the grid: its cell, and its place inside the cell
// in units of the cell, in [0, 1) along each axis. The cell list and every
// neighbour loop call this one function on the same state, so they agree
// on every particle's cell bit for bit (an add, a multiply and a floor:
// nothing a compiler may contract).
struct Home {
    cell: vec2<i32>,
    frac: vec2<f32>,
}

// `home` of a particle with reference `a` (its x0) and displacement `un`.
fn home_at(a: vec4<f32>, un: vec2<f32>) -> Home {
    return home_in(a, un, params.inv_cell);
}

fn home_in(a: vec4<f32>, un: vec2<f32>, inv_cell: f32) -> Home {
    let p = (a.zw + un) * inv_cell;
    let f = floor(p);
    return Home(vec2<i32>(a.xy) + vec2<i32>(f), p - f);
}

// The cell a particle is in now: its reference cell plus whole cells moved.
fn current_cell(i: u32) -> vec2<i32> {
    return home_at(x0[i], u[i]).cell;
}

// Rows of the stencil, bottom to top, always in this order (the order of
// every neighbour sum is fixed).
fn scan_rows() -> u32 {
    if (DIM == 1u) {
        return 1u;
    }
    return u32(2 * stencil() + 1);
}

// One row of a particle's stencil: the row `cy`, its columns `lo..=hi` (the
// cells its support reaches), and the range of the sorted particle list
// that holds their buckets. Row-major keys make a row's cells consecutive
// buckets, so the row is one contiguous range: a warp's lanes run five
// loops a walk, not nine or twenty-five. When the buckets wrap past the
// last, the range runs on past `n` into the list's start (`cand`).
// A bucket may also hold cells of other rows: callers keep only particles
// whose cell is in the span (`in_row`).
struct RowSpan {
    cy: i32,
    lo: i32,
    hi: i32,
    start: u32,
    end: u32,
}

fn row_span(hm: Home, row: u32) -> RowSpan {
    return row_span_in(hm, row, params.reach);
}

// `row_span` of a support `reach` cells in radius.
fn row_span_in(hm: Home, row: u32, reach: f32) -> RowSpan {
    let rows = stencil();
    var dy = i32(row) - rows;
    // The distance in cells from the particle to the row's band.
    var gap = 0.0;
    if (DIM == 1u) {
        dy = 0;
    } else if (dy > 0) {
        gap = f32(dy) - hm.frac.y;
    } else if (dy < 0) {
        gap = hm.frac.y - f32(dy + 1);
    }
    let cy = hm.cell.y + dy;
    if (gap >= reach) {
        return RowSpan(cy, 1, 0, 0u, 0u);
    }
    // The columns a disk of radius `reach` reaches in this row.
    let w = sqrt(reach * reach - gap * gap);
    let lo = max(-rows, i32(floor(hm.frac.x - w)));
    let hi = min(rows, i32(floor(hm.frac.x + w)));
    let b = bucket_of(vec2<i32>(hm.cell.x + lo, cy));
    let e = b + u32(hi - lo + 1);
    var end = 0u;
    if (e <= params.buckets) {
        end = bstart[e];
    } else {
        end = bstart[e - params.buckets] + params.n;
    }
    return RowSpan(cy, hm.cell.x + lo, hm.cell.x + hi, bstart[b], end);
}

// Whether cell `c` is one of the span's.
fn in_row(c: vec2<i32>, span: RowSpan) -> bool {
    return c.y == span.cy && c.x >= span.lo && c.x <= span.hi;
}

// A neighbour walk reads everything it can before its loop: on a software
// adapter (lavapipe) every read inside the loop, a uniform's too, is a
// scalar load for each lane, and these reads were most of a walk's cost.
//
// The run constants a walk's loop uses.
struct Consts {
    n: u32,
    cell: f32,
    inv_cell: f32,
}

fn consts() -> Consts {
    return Consts(params.n, params.cell, params.inv_cell);
}

// The walking particle: its index, reference, displacement, grid home,
// (bodies of revolution; else 0) radius and offsets from the image lines
// (`offsets_at`); where supports adapt its metric and the radius in cells
// its walk reaches (else the round support's).
struct Walker {
    i: u32,
    a: vec4<f32>,
    un: vec2<f32>,
    hm: Home,
    rad: f32,
    q: vec4<f32>,
    reach: f32,
    off: vec2<f32>,
}

fn walker(i: u32) -> Walker {
    let a = x0[i];
    let un = u[i];
    let rad = radius_at(a, un);
    return Walker(i, a, un, home_at(a, un), rad, vec4<f32>(0.0), params.reach, offsets_at(a, un, rad));
}

// The walker of the SPH sums where supports adapt: its metric, and the
// reach of the pairs in their mean metric (the round walks of the contact
// keep `walker`'s).
fn adaptive_walker(i: u32) -> Walker {
    var w = walker(i);
    w.q = support_of(i, bodies[pinfo[i].z].h);
    w.reach = max(adaptive_reach(w.q) * params.inv_cell + params.reach_margin, params.reach);
    return w;
}

// The walker of the SPH sums: `adaptive_walker`'s while some support
// adapts (`adapting`), else `walker`'s.
fn sph_walker(i: u32) -> Walker {
    if (adapting()) {
        return adaptive_walker(i);
    }
    return walker(i);
}

// How far apart a particle of metric `q` and any other can be and lie in
// their mean metric's support, dᵀ (Q_i + Q_j) d < 8, when no major
// semi-axis exceeds the step's largest (`step_h_top`): sqrt(8 / (1/a_i^2 +
// 1/top^2)), a_i the particle's own (cpu::neighbours, near_adaptive).
fn adaptive_reach(q: vec4<f32>) -> f32 {
    let a = metric_axes(q).y;
    let top = max(step_h_top(), a);
    return sqrt(8.0 / (1.0 / (a * a) + 1.0 / (top * top)));
}

// The radius of a particle of a body of revolution with reference `a` and
// displacement `un`: its whole cells from the axis (exact) and its place in
// the cell (0 in plane strain).
fn radius_at(a: vec4<f32>, un: vec2<f32>) -> f32 {
    if (!AXI) {
        return 0.0;
    }
    return (a.x - params.axis_cell) * params.cell + (a.z + un.x);
}

fn radius_of(j: u32) -> f32 {
    return radius_at(x0[j], u[j]);
}

// A particle's offsets from the lines its images are mirrored across,
// along the coordinate each reverses (0 along one none reverses): the
// radius `rad` from the axis (AXI), and from the symmetry planes (PLANE),
// each its whole cells from the line (exact) and its place in the cell.
fn offsets_at(a: vec4<f32>, un: vec2<f32>, rad: f32) -> vec2<f32> {
    var o = vec2<f32>(rad, 0.0);
    if ((PLANE & 1u) != 0u) {
        o.x = (a.x - params.plane_x) * params.cell + (a.z + un.x);
    }
    if ((PLANE & 2u) != 0u) {
        o.y = (a.y - params.plane_y) * params.cell + (a.w + un.y);
    }
    return o;
}

// How many mirror images a particle has: across each line (the axis of a
// body of revolution, each symmetry plane), and across both where there
// are two.
fn image_count() -> u32 {
    return (1u << (select(0u, 1u, AXI) + countOneBits(PLANE))) - 1u;
}

// The coordinates image `m` reverses (mirror_vec): with two lines, x's
// (the axis's or a plane's), y's, then both.
fn image_flip(m: u32) -> u32 {
    if (image_count() == 3u) {
        return m + 1u;
    }
    return select(PLANE, 1u, AXI);
}

// How many images the contact meets: each symmetry plane's and, across
// two, the corner's (the axis's are not a body's partners).
fn contact_images() -> u32 {
    return (1u << countOneBits(PLANE)) - 1u;
}

// The coordinates the contact's image `m` reverses.
fn contact_flip(m: u32) -> u32 {
    return select(PLANE, m + 1u, PLANE == 3u);
}

// The separation from walker `w` of the image under `flip` of a particle at
// offsets `oj` whose own separation from w is `d`: each reversed
// coordinate's is the sum of their offsets (x_i - (2 l - x_j)).
fn image_d(w: Walker, flip: u32, oj: vec2<f32>, d: vec2<f32>) -> vec2<f32> {
    let s = w.off + oj;
    return vec2<f32>(select(d.x, s.x, (flip & 1u) != 0u), select(d.y, s.y, (flip & 2u) != 0u));
}

// The pair of walker `w` and image `m` of a particle at offsets `oj` whose
// pair with w has separation `d`, at smoothing length `hij`; not inside
// where the image lies beyond the support along a reversed coordinate
// (most pairs: the test needs no square root). An image is never nearer
// than its particle, so the images within reach are those of the pairs
// within reach, and of the walker itself (d = 0, oj = w.off).
fn image_pair(w: Walker, m: u32, oj: vec2<f32>, d: vec2<f32>, hij: f32) -> Pair {
    let f = image_flip(m);
    let di = image_d(w, f, oj, d);
    if (((f & 1u) != 0u && abs(di.x) >= 2.0 * hij) || ((f & 2u) != 0u && abs(di.y) >= 2.0 * hij)) {
        return Pair(vec2<f32>(0.0), 0.0, 0.0, vec2<f32>(0.0), false, 0.0, 0.0);
    }
    return pair_at(di, hij);
}

// `image_pair` where supports adapt: the pair of the walker and image `m`
// of a particle of metric `qj`, whose own metric is `qj` mirrored; `h0`
// the round support's h.
fn image_pair_metric(w: Walker, m: u32, oj: vec2<f32>, d: vec2<f32>, qj: vec4<f32>, h0: f32) -> Pair {
    let f = image_flip(m);
    let qm = vec4<f32>(qj.x, select(qj.y, -qj.y, shears(f)), qj.z, 0.0);
    return pair_metric(image_d(w, f, oj, d), w.q, qm, h0);
}

// Candidate j at place k of a row's range (a range that wraps past the
// last bucket runs on past `n`): its cell, and the pair difference
// d = x_i - x_j from one read of its position. x0 holds each particle's
// reference cell (integral, exact in f32) and its offset in that cell at
// the start, u the displacement since; the difference is formed part by
// part, so its round-off scales with the pair distance, not with the
// distance from the origin. (x_j - x_i is exactly -d: each part negates.)
struct Cand {
    j: u32,
    cell: vec2<i32>,
    d: vec2<f32>,
    // Its radius in a body of revolution (0 in plane strain), and its
    // offsets from the image lines (`offsets_at`).
    rad: f32,
    off: vec2<f32>,
}

fn cand(w: Walker, k: u32, c: Consts) -> Cand {
    let j = sorted_at(k, c);
    let b = x0[j];
    let uj = u[j];
    let cell = home_in(b, uj, c.inv_cell).cell;
    let rad = radius_at(b, uj);
    return Cand(j, cell, pair_diff(w, b, uj, c), rad, offsets_at(b, uj, rad));
}

// Particle j's offsets from the image lines.
fn offsets_of(j: u32) -> vec2<f32> {
    let b = x0[j];
    let uj = u[j];
    return offsets_at(b, uj, radius_at(b, uj));
}

// The particle at place k of the sorted list, run on past `n` where a row
// range wraps round the bucket table.
fn sorted_at(k: u32, c: Consts) -> u32 {
    return blist[select(k, k - c.n, k >= c.n)];
}

// x_i - x_j of the walker and a particle at reference cell and offset `b`
// and displacement `uj` (the precision plan: cells and offsets apart).
fn pair_diff(w: Walker, b: vec4<f32>, uj: vec2<f32>, c: Consts) -> vec2<f32> {
    return (w.a.xy - b.xy) * c.cell + (w.a.zw - b.zw) + (w.un - uj);
}

// An SPH pair (i, j), h_ij the mean of the bodies' h: separation x_i - x_j,
// distance, and grad_i W_ij (computed only inside the support, zero at zero
// distance); `inside` when the distance is below 2 h_ij.
struct Pair {
    d: vec2<f32>,
    dist: f32,
    hij: f32,
    gw: vec2<f32>,
    inside: bool,
    // Where supports adapt, q^2 in the pair's metric and its sqrt(det Q);
    // hij is then the smoothing length along the pair, r/q.
    q2: f32,
    scale: f32,
}

// The SPH pair of walker `w` (particle i, body bi, smoothing length hi) and
// candidate `cd` of row `span` (body bj). `inside` is false when j is i,
// lies in a cell outside the span that shares a bucket, or (with contact
// on) belongs to another body: bodies then meet only through the contact
// force. Every SPH sum scans its neighbours through this filter.
fn body_pair(w: Walker, cd: Cand, bj: u32, span: RowSpan, hi: f32, bi: u32) -> Pair {
    if (cd.j == w.i || !in_row(cd.cell, span) || (CONTACT && bj != bi)) {
        return Pair(vec2<f32>(0.0), 0.0, 0.0, vec2<f32>(0.0), false, 0.0, 0.0);
    }
    return pair_at(cd.d, pair_h(hi, bj));
}

// `body_pair` of the SPH sums: where supports adapt, the pair in its mean
// metric (`pair_metric`; the walker from `adaptive_walker`). The surface
// set and the contact keep `body_pair`'s round supports.
fn sph_pair(w: Walker, cd: Cand, bj: u32, span: RowSpan, hi: f32, bi: u32) -> Pair {
    if (!ADAPT) {
        return body_pair(w, cd, bj, span, hi, bi);
    }
    if (cd.j == w.i || !in_row(cd.cell, span) || (CONTACT && bj != bi)) {
        return Pair(vec2<f32>(0.0), 0.0, 0.0, vec2<f32>(0.0), false, 0.0, 0.0);
    }
    return pair_metric(cd.d, w.q, support_of(cd.j, body_h(hi, bj)), pair_h(hi, bj));
}

// Particle j's support (common.wgsl, `metric_banded`), `h0` its body's h.
fn support_of(j: u32, h0: f32) -> vec4<f32> {
    return metric_banded(metric[j], h0);
}

// The h of body `bj` where the walker's is `hi`: with contact on, SPH
// pairs are of one body (`pair_h`).
fn body_h(hi: f32, bj: u32) -> f32 {
    if (!CONTACT) {
        return bodies[bj].h;
    }
    return hi;
}

// h_ij of a pair with i's h `hi` and j of body `bj`. With contact on, SPH
// pairs are of one body: h_ij is h_i, the same bits as the mean, without
// the partner's body read.
fn pair_h(hi: f32, bj: u32) -> f32 {
    if (!CONTACT) {
        return 0.5 * (hi + bodies[bj].h);
    }
    return hi;
}

// The SPH pair of separation `d` and smoothing length `hij`.
fn pair_at(d: vec2<f32>, hij: f32) -> Pair {
    let dist = length(d);
    let inside = dist < 2.0 * hij;
    var gw = vec2<f32>(0.0);
    if (inside && dist > 0.0) {
        gw = d * (kernel_dw(dist, hij) / dist);
    }
    return Pair(d, dist, hij, gw, inside, 0.0, 0.0);
}

// The SPH pair of separation `d` whose particles have metrics `qi`, `qj`
// (supports that adapt): the spline in their mean metric Q, q^2 = d.Qd,
// grad_i W = alpha sqrt(det Q) (f'(q)/q) Q d (physics::kernel::w_grad_pair);
// `h0` the round support's h, the smoothing length along a pair at zero
// distance.
fn pair_metric(d: vec2<f32>, qi: vec4<f32>, qj: vec4<f32>, h0: f32) -> Pair {
    let m = 0.5 * (qi + qj);
    let qd = metric_apply(m, d);
    let q2 = dot(d, qd);
    let dist = length(d);
    if (q2 >= 4.0) {
        return Pair(d, dist, 0.0, vec2<f32>(0.0), false, q2, 0.0);
    }
    let sc = metric_scale(m);
    var hij = h0;
    var gw = vec2<f32>(0.0);
    if (q2 > 0.0) {
        let q = sqrt(q2);
        hij = dist / q;
        var g = 0.0;
        if (q < 1.0) {
            g = -3.0 + 2.25 * q;
        } else {
            let t = 2.0 - q;
            g = -0.75 * t * t / q;
        }
        gw = qd * (kernel_alpha(1.0) * sc * g);
    }
    return Pair(d, dist, hij, gw, true, q2, sc);
}

// The neighbour mask (leapfrog only, LEAP != 0): the kinematic walk
// (kinematics.wgsl) numbers a particle's candidates in walk order, rows bottom
// to top and each row's range in order, and sets bit o of the mask when
// candidate o is an SPH pair (`body_pair` inside); the walks after it at
// the same positions and cell list (forces.wgsl) visit only those, in the
// same order, so every sum keeps its order and its bits. Ordinals 0..62
// fit; a particle with more candidates sets MASK_FULL and is walked in
// full.
const MASK_FULL: u32 = 0x80000000u;
const MASK_BITS: u32 = 63u;

fn mask_set(m: vec2<u32>, o: u32) -> vec2<u32> {
    if (o < 32u) {
        return vec2<u32>(m.x | (1u << o), m.y);
    }
    return vec2<u32>(m.x, m.y | (1u << (o - 32u)));
}

// Where ordinal o of a walk lies in the sorted list: o plus the offset of
// its row (`start` of the row less the ordinals before it); rows past the
// last reached have no ordinals.
struct RowMap {
    // The first ordinal of rows 1..4.
    first: vec4<u32>,
    // Each row's offset (wrapping u32 arithmetic).
    off0: u32,
    off: vec4<u32>,
}

fn row_map(hm: Home) -> RowMap {
    var first = vec4<u32>(0u);
    var off = vec4<u32>(0u);
    let s0 = row_span(hm, 0u);
    var o = s0.end - s0.start;
    for (var row = 1u; row < scan_rows(); row++) {
        let sp = row_span(hm, row);
        first[row - 1u] = o;
        off[row - 1u] = sp.start - o;
        o += sp.end - sp.start;
    }
    if (scan_rows() == 1u) {
        // 1-D: one row, every later row starts past the mask.
        first = vec4<u32>(64u);
    }
    return RowMap(first, s0.start, off);
}

// The place in the sorted list (run on past `n` where a range wraps, as
// `cand`) of ordinal o.
fn row_place(rm: RowMap, o: u32) -> u32 {
    var off = rm.off0;
    if (o >= rm.first.x) {
        off = rm.off.x;
    }
    if (o >= rm.first.y) {
        off = rm.off.y;
    }
    if (o >= rm.first.z) {
        off = rm.off.z;
    }
    if (o >= rm.first.w) {
        off = rm.off.w;
    }
    return o + off;
}

// Take the lowest set bit of the mask: its ordinal (64 when none is left).
fn mask_next(m: ptr<function, vec2<u32>>) -> u32 {
    let x = (*m).x;
    if (x != 0u) {
        (*m).x = x & (x - 1u);
        return countTrailingZeros(x);
    }
    let y = (*m).y;
    if (y != 0u) {
        (*m).y = y & (y - 1u);
        return 32u + countTrailingZeros(y);
    }
    return 64u;
}

// The pair difference d = x_i - x_j of the walker and particle j (as `cand`).
fn pair_d(w: Walker, j: u32, c: Consts) -> vec2<f32> {
    return pair_diff(w, x0[j], u[j], c);
}

// Position relative to the grid origin (output only). The host adds the
// origin in f64 (gpu::probes): far from the coordinate origin an absolute
// f32 position is coarse (7.6e-6 m near 100 m, 0.15 of a typical spacing),
// while this relative one keeps the f32 resolution of the bodies' own size.
fn position_rel(i: u32) -> vec2<f32> {
    let a = x0[i];
    return a.xy * params.cell + (a.zw + u[i]);
}
