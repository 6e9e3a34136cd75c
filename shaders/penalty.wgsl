// One pass of the penalty law at a boundary particle P (pass 1 of the
// contact stage): P's sums over its candidates in the partner body, the
// gap, the spring's stored energy and its derivatives, the dashpot, and
// what P keeps and leaves its partners. Assembled with contact.wgsl
// (src/gpu/shaders.rs); CPU twins: physics::penalty (the law) and
// cpu::contact::penalty_booked (the pass).

// Pass 1's entries of a particle: the pass's nominal force -p A n / 2 (the
// observations' contact force), its booked heat and its partner body
// (`own`); the dashpot force per unit weight it leaves its partners, the
// dashpot heat per unit weight of a rigid particle and dPhi/dt of its pass
// (`share`); the spring's derivative with respect to the sums, for the
// partners (`bar0`: sws, swn; `bar1`: sw, swt, swo, whether the spring
// acts); the force the particle keeps and dPhi/dn_P (`keep`); and the
// spring energy it stores. CPU twins: cpu::contact::penalty_booked pass 1,
// physics::penalty::{gap, gap_bar, candidate}.
struct Entries {
    own: vec4<f32>,
    share: vec4<f32>,
    bar0: vec4<f32>,
    bar1: vec4<f32>,
    keep: vec4<f32>,
    stored: f32,
    // The particle's entry overlap after this evaluation.
    entry: f32,
    // With friction (RUB), what the rub pass reads (contact.wgsl, rub_at):
    // the contact normal, the partners' mean offset and the sum of the
    // weights (`rub0`); the relative tangential velocity along perp(n) at
    // the forces' and the booking's velocities, the normal force the pass
    // applies, and that force per unit weight for the partners (`rub1`).
    rub0: vec4<f32>,
    rub1: vec4<f32>,
}

// One candidate's share of the spring's derivative (physics::penalty::
// candidate): d Phi / d x_q through s_q (`x`), d Phi / d n_q (`n`) and
// d Phi / d W_q (`w`). `rel` = s_q - S_P.
struct CandBar {
    x: vec2<f32>,
    n: vec2<f32>,
    w: f32,
}

fn cand_bar(bar0: vec4<f32>, bar1: vec4<f32>, w: f32, rel: vec2<f32>, nq: vec2<f32>, oq: f32) -> CandBar {
    let x = (bar0.xy - nq * bar1.y) * w;
    let n = (bar0.zw - rel * bar1.y) * w + x * oq;
    let wb = bar1.x + dot(bar0.xy, rel) + dot(bar0.zw, nq) - bar1.y * dot(nq, rel) + bar1.z * oq;
    return CandBar(x, n, wb);
}

// What pass 1 reads of particle P throughout: its body, surface offset,
// normal (`cnp.xy`; `cnp.w` its turning rate), smoothing length and
// walker.
struct PassAt {
    p: u32,
    bp: u32,
    op: f32,
    np: vec2<f32>,
    cnp: vec4<f32>,
    hp: f32,
    wk: Walker,
}

// P's sums over its candidates in the first partner body it meets, and
// whether it meets another (CPU twins: cpu::contact::Booking::partners,
// physics::penalty::Sums::add).
struct PassSums {
    partner: u32,
    multi: bool,
    sw: f32,
    sws: vec2<f32>,
    swn: vec2<f32>,
    swv: vec2<f32>,
    swt: f32,
    swo: f32,
    swb: vec2<f32>,
}

fn pass_sums(at: PassAt) -> PassSums {
    var s = PassSums(NONE, false, 0.0, vec2<f32>(0.0), vec2<f32>(0.0), vec2<f32>(0.0), 0.0, 0.0, vec2<f32>(0.0));
    let cs = consts();
    let gp = ramp_measure(at.p, at.hp, at.cnp);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(at.wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(at.wk, k, cs);
            let q = cd.j;
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let mq = pinfo[q];
            let nq4 = nbo[q];
            if (mq.z == at.bp || nq4.z <= 0.0) {
                continue;
            }
            let oq = bitcast<f32>(mq.y);
            let cq = cn[place(q)];
            let hq = bodies[mq.z].h;
            let gq = ramp_measure(q, hq, cq);
            let sq = plane_share(q);
            var vb = vec2<f32>(0.0);
            if (LEAP == 3u) {
                vb = vbook[q];
            }
            // x_q - x_p.
            let d = -cd.d;
            let w = candidate(at.np, cq.xy, d, at.op, oq, at.hp, hq, gp, gq, sq).x;
            if (w >= 0.0) {
                sum_candidate(at, &s, mq.z, w, d, cq.xy, oq, v[q], vb);
            }
            for (var m = 0u; m < contact_images(); m++) {
                // Across the symmetry planes: q's image, at the mirror
                // point with its normal and velocities mirrored.
                let f = contact_flip(m);
                let di = image_sep(at.wk, f, cd.off, cd.d);
                let nqi = mirror_vec(f, cq.xy);
                let wi = candidate(at.np, nqi, di, at.op, oq, at.hp, hq, gp, gq, sq).x;
                if (wi >= 0.0) {
                    sum_candidate(at, &s, mq.z, wi, di, nqi, oq, mirror_vec(f, v[q]), mirror_vec(f, vb));
                }
            }
        }
    }
    return s;
}

// x_q - x_p of the image under `flip` of candidate q (offsets `oq`, `cd_d`
// = x_p - x_q) across the symmetry planes, from walker P: along a reversed
// coordinate -(off_p + off_q), along the other -cd_d. Pass 2 forms the
// same bits from q's side (contact.wgsl, image_sep_of_walker).
fn image_sep(wk: Walker, flip: u32, oq: vec2<f32>, cd_d: vec2<f32>) -> vec2<f32> {
    return -image_d(wk, flip, oq, cd_d);
}

// Candidate q of body `bq` (or its image) of weight `w`, x_q - x_p `d`,
// normal `nq`, offset `oq`, velocity `vq` and booking velocity `vb`, in
// P's sums: the first partner body P meets, others counted.
fn sum_candidate(at: PassAt, s: ptr<function, PassSums>, bq: u32, w: f32, d: vec2<f32>, nq: vec2<f32>, oq: f32, vq: vec2<f32>, vb: vec2<f32>) {
    if ((*s).partner == NONE) {
        (*s).partner = bq;
    } else if (bq != (*s).partner) {
        (*s).multi = true;
        return;
    }
    // s_q - S_P, formed from the precise centre difference.
    let rel = d + nq * oq - at.np * at.op;
    (*s).sw += w;
    (*s).sws += rel * w;
    (*s).swn += nq * w;
    (*s).swv += vq * w;
    if (LEAP == 3u) {
        (*s).swb += vb * w;
    }
    (*s).swt += dot(nq, -rel) * w;
    (*s).swo += oq * w;
}

// The gap of P against the interpolated partner surface, its normal and
// what the gap's derivative reads: `nbar` (the partners' mean normal, of
// length `nlen` before normalising), `rr` (the mean of s_q - S_P), `tg`,
// which normal was chosen (0 n_P, 1 -nbar, 2 their bisector, of length
// `bl` before normalising). CPU twin: physics::penalty::gap.
struct Gap {
    gap: f32,
    n: vec2<f32>,
    choice: u32,
    nbar: vec2<f32>,
    nlen: f32,
    rr: vec2<f32>,
    tg: f32,
    bl: f32,
}

// Needs s.sw > 0 and nlen = |s.swn| > 0.
fn gap_of(np: vec2<f32>, s: PassSums, nlen: f32) -> Gap {
    let nbar = s.swn / nlen;
    let rr = s.sws / s.sw;
    let tg = s.swt / s.sw;
    // Contact normal: of n_P, -nbar and their bisector, the one with the
    // largest projected distance (least penetration; docs/method.md §8.2).
    var n = np;
    var chord = dot(np, rr);
    var choice = 0u;
    let c1 = -nbar;
    if (dot(c1, rr) > chord) {
        n = c1;
        chord = dot(c1, rr);
        choice = 1u;
    }
    let bis = np - nbar;
    let bl = length(bis);
    if (bl > 0.0) {
        let c2 = bis / bl;
        if (dot(c2, rr) > chord) {
            n = c2;
            chord = dot(c2, rr);
            choice = 2u;
        }
    }
    return Gap(0.5 * (chord + tg), n, choice, nbar, nlen, rr, tg, bl);
}

// The entry overlap after an evaluation whose raw overlap is `raw`, from
// the stored one `e_in` (negative: P was off the boundary), with the yield
// overlap `cap`; and whether the spring has yielded. The entry only
// shrinks, but follows an overlap more than `cap` beyond it. CPU twin:
// physics::penalty::entry_rule.
struct Entry {
    entry: f32,
    yielded: bool,
}

fn entry_rule(e_in: f32, raw: f32, cap: f32) -> Entry {
    var en = Entry(raw, false);
    if (e_in >= 0.0) {
        en.entry = min(e_in, raw);
        if (raw - en.entry > cap) {
            en.yielded = true;
            en.entry = raw - cap;
        }
    }
    return en;
}

// dPhi/d the sums of a pass (`bar0`: sws, swn; `bar1`: sw, swt, swo, 0),
// dPhi/dS_P through them (`sp`) and dPhi/dn_P through the choice of the
// normal (`np`), from gbar = dPhi/dg and obar = dPhi/d(mean offset `ob`);
// `fade_sw` is the fade's own part of dPhi/dsw. CPU twin:
// physics::penalty::gap_bar.
struct SumsBar {
    bar0: vec4<f32>,
    bar1: vec4<f32>,
    sp: vec2<f32>,
    np: vec2<f32>,
}

fn gap_bar(s: PassSums, g: Gap, gbar: f32, obar: f32, ob: f32, fade_sw: f32) -> SumsBar {
    let half = 0.5 * gbar;
    let n_bar = g.rr * half;
    let r_bar = g.n * half;
    let b_sws = r_bar / s.sw;
    let b_swt = half / s.sw;
    let b_swo = obar / s.sw;
    let b_sw = -(dot(r_bar, g.rr) + half * g.tg + obar * ob) / s.sw + fade_sw;
    var np_bar = vec2<f32>(0.0);
    var nbar_bar = vec2<f32>(0.0);
    if (g.choice == 0u) {
        np_bar = n_bar;
    } else if (g.choice == 1u) {
        nbar_bar = -n_bar;
    } else {
        let u_bar = (n_bar - g.n * dot(g.n, n_bar)) / g.bl;
        np_bar = u_bar;
        nbar_bar = -u_bar;
    }
    let b_swn = (nbar_bar - g.nbar * dot(g.nbar, nbar_bar)) / g.nlen;
    let b_sp = -b_sws * s.sw + s.swn * b_swt;
    return SumsBar(vec4<f32>(b_sws, b_swn), vec4<f32>(b_sw, b_swt, b_swo, 0.0), b_sp, np_bar);
}

// The candidates again, each one's share as its pass 2 makes it: dPhi/dx_P
// (`xp`, from the sums' part `b.sp`) and dPhi/dt over the candidates at
// their booking velocities. CPU twin: physics::penalty::candidate.
struct CandSum {
    xp: vec2<f32>,
    phi_dot: f32,
}

fn candidates_bar(at: PassAt, partner: u32, b: SumsBar) -> CandSum {
    var cs_ = CandSum(b.sp, 0.0);
    let cs = consts();
    let gp = ramp_measure(at.p, at.hp, at.cnp);
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(at.wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(at.wk, k, cs);
            let q = cd.j;
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let mq = pinfo[q];
            if (mq.z != partner || nbo[q].z <= 0.0) {
                continue;
            }
            let oq = bitcast<f32>(mq.y);
            let d = -cd.d;
            let cnq = cn[place(q)];
            let nq = cnq.xy;
            let hq = bodies[mq.z].h;
            let gq = ramp_measure(q, hq, cnq);
            let sq = plane_share(q);
            let wg = candidate(at.np, nq, d, at.op, oq, at.hp, hq, gp, gq, sq);
            if (wg.x >= 0.0) {
                bar_candidate(at, b, &cs_, wg, d, nq, oq, v_book(q), cnq.w);
            }
            for (var m = 0u; m < contact_images(); m++) {
                // q's images (pass_sums): across one plane its normal
                // turns the other way, across both (a half turn) the same.
                let f = contact_flip(m);
                let di = image_sep(at.wk, f, cd.off, cd.d);
                let nqi = mirror_vec(f, nq);
                let wi = candidate(at.np, nqi, di, at.op, oq, at.hp, hq, gp, gq, sq);
                if (wi.x >= 0.0) {
                    bar_candidate(at, b, &cs_, wi, di, nqi, oq, mirror_vec(f, v_book(q)), select(cnq.w, -cnq.w, shears(f)));
                }
            }
        }
    }
    return cs_;
}

// One candidate's (or image's) share of dPhi/dx_P and dPhi/dt: weight
// `wg`, x_q - x_p `d`, normal `nq` turning at `rate`, offset `oq`,
// booking velocity `vb`.
fn bar_candidate(at: PassAt, b: SumsBar, c: ptr<function, CandSum>, wg: vec2<f32>, d: vec2<f32>, nq: vec2<f32>, oq: f32, vb: vec2<f32>, rate: f32) {
    let rel = d + nq * oq - at.np * at.op;
    let cb = cand_bar(b.bar0, b.bar1, wg.x, rel, nq, oq);
    let gw = -d * wg.y;
    (*c).xp += gw * cb.w;
    (*c).phi_dot += dot(cb.x - gw * cb.w, vb) + dot(cb.n, perp(nq) * rate);
}

// The fade of a pass whose candidates' weight is `sw`, with the weight of
// a quarter of a flat surface's as its reference `w_ref`: the pass fades
// out below it. CPU twin: cpu::contact::pass_fade (and
// physics::penalty::fade).
struct Fade {
    fade: f32,
    slope: f32,
    w_ref: f32,
}

fn pass_fade(sw: f32, hp: f32, spacing_q: f32) -> Fade {
    var fd = Fade(1.0, 0.0, 1.0);
    if (DIM == 2u) {
        fd.w_ref = 0.25 * line_integral(hp) / spacing_q;
        let fs = sw / fd.w_ref;
        if (fs < 1.0) {
            fd.fade = fs * fs * (3.0 - 2.0 * fs);
            fd.slope = 6.0 * fs * (1.0 - fs);
        }
    }
    return fd;
}

// The heat a pass books and what is left of dPhi/dt: the dashpot's heat
// `dash` w at the booking rate (the forces' own, or the leapfrog's
// v_{n+1}); where the pass lets go, the spring's energy released; a
// yielded spring pressed further stores nothing more, the work it takes
// is heat. CPU twin: cpu::contact::Booking::book_pass.
fn pass_heat(p: u32, s: PassSums, n: vec2<f32>, w_rate: f32, dash: f32, clipped: bool, yielded: bool, phi_dot: f32) -> vec2<f32> {
    var w_book = w_rate;
    if (LEAP == 3u) {
        w_book = dot(vbook[p] - s.swb / s.sw, n);
    }
    if (clipped) {
        return vec2<f32>(-phi_dot, phi_dot);
    }
    var heat = dash * w_book;
    var left = phi_dot;
    if (yielded && phi_dot > 0.0) {
        heat += phi_dot;
        left = 0.0;
    }
    return vec2<f32>(heat, left);
}

// Pass 1 at particle p: its entries (a particle off the boundary: no
// partner, nothing else). `count`: whether a particle that meets two partner
// bodies is counted (once an evaluation). CPU twin: cpu::contact::
// Booking::book_pass.
fn entries(p: u32, count: bool) -> Entries {
    // w: the partner body as a float (exact for any realistic count), -1: none.
    var e = Entries(vec4<f32>(0.0, 0.0, 0.0, -1.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), 0.0, 0.0, vec4<f32>(0.0), vec4<f32>(0.0));
    if (nbo[p].z <= 0.0) {
        return e;
    }
    let mp = pinfo[p];
    let bodyp = bodies[mp.z];
    let cnp = cn[place(p)];
    let at = PassAt(p, mp.z, bitcast<f32>(mp.y), cnp.xy, cnp, bodyp.h, walker(p));
    let s = pass_sums(at);
    if (s.multi && count) {
        atomicAdd(&ctl.multi_partner, 1u);
    }
    let partner = s.partner;
    let sw = s.sw;
    if (partner == NONE || sw <= 0.0) {
        return e;
    }
    let nlen = length(s.swn);
    if (nlen <= 0.0) {
        return e;
    }
    let g = gap_of(at.np, s, nlen);
    let n = g.n;
    let vrel = v[p] - s.swv / sw;
    if (RUB) {
        // Whether or not the pass presses: the partners' may (CPU twin:
        // cpu::contact::Booking::pass1, `rubs`).
        let t = perp(n);
        var w_book = dot(vrel, t);
        if (LEAP == 3u) {
            w_book = dot(vbook[p] - s.swb / sw, t);
        }
        e.rub0 = vec4<f32>(n, s.swo / sw, sw);
        e.rub1 = vec4<f32>(dot(vrel, t), w_book, 0.0, 0.0);
    }
    // Round-off counts as touching (CPU twin: physics::penalty::touching).
    if (g.gap > 1e-5 * bodyp.spacing) {
        e.own.w = f32(partner);
        return e;
    }
    // The spring measures the overlap beyond the one the particle joined
    // the surface with, yielding a quarter spacing beyond it (CPU twin:
    // physics::penalty::yield_overlap).
    let raw = max(-g.gap, 0.0);
    let en = entry_rule(centry[p], raw, 0.25 * bodyp.spacing);
    e.entry = en.entry;
    let delta = max(raw - e.entry, 0.0);
    let w_rate = dot(vrel, n);
    let bodyq = bodies[partner];
    let pr = bodyp.rigid != 0u;
    let qr = bodyq.rigid != 0u;
    if (pr && qr) {
        // Two rigid bodies move as prescribed: nothing to push.
        e.own.w = f32(partner);
        return e;
    }
    let z = series(bodyp.z, pr, bodyq.z, qr);
    let ob = s.swo / sw;
    let stiffness = 1.0 / (layer(at.op, bodyp) + layer(ob, bodyq));
    let push = z * w_rate + stiffness * delta;
    let pres = max(push, 0.0);
    // The dashpot would pull harder than the spring pushes: the pass lets go.
    let clipped = push < 0.0;
    let a = area[area_index(p, nbo[p].w)];
    // The spring's derivative and, through the same derivative, dPhi/dt at
    // the booking velocities.
    var keep = vec2<f32>(0.0);
    var np_bar = vec2<f32>(0.0);
    var phi_dot = 0.0;
    var bar0 = vec4<f32>(0.0);
    var bar1 = vec4<f32>(0.0);
    let phi0 = 0.25 * stiffness * delta * delta * a;
    let fd = pass_fade(sw, at.hp, bodyq.spacing);
    let fade = fd.fade;
    if (delta > 0.0) {
        var slope = 0.0;
        if (!qr && ob > 0.25 * bodyq.spacing) {
            slope = -stiffness * stiffness / bodyq.modulus;
        }
        let gbar = -0.5 * stiffness * delta * a * fade;
        let obar = 0.25 * delta * delta * a * slope * fade;
        let b = gap_bar(s, g, gbar, obar, ob, phi0 * fd.slope / fd.w_ref);
        bar0 = b.bar0;
        bar1 = b.bar1;
        let cands = candidates_bar(at, partner, b);
        np_bar = b.np + b.sp * at.op;
        phi_dot = cands.phi_dot;
        phi_dot += dot(cands.xp, v_book(p)) + dot(np_bar, perp(at.np) * cnp.w);
        if (!clipped) {
            keep = -cands.xp;
            bar1.w = 1.0;
        } else {
            np_bar = vec2<f32>(0.0);
        }
    }
    var dash = 0.0;
    if (!clipped) {
        dash = 0.5 * z * w_rate * a;
    }
    let ph = pass_heat(p, s, n, w_rate, dash, clipped, en.yielded, phi_dot);
    let heat = ph.x;
    phi_dot = ph.y;
    keep -= n * dash;
    var own_heat = heat;
    var eta = 0.0;
    if (pr) {
        own_heat = 0.0;
        eta = heat / sw;
    }
    // The nominal force the probes report: what the pass applies along its
    // normal, the dashpot and the spring as faded (cpu::contact, PassStat).
    var applied = pres;
    if (fade < 1.0 && !clipped) {
        applied = max(z * w_rate + stiffness * delta * fade, 0.0);
    }
    e.own = vec4<f32>(-n * (0.5 * applied * a), own_heat, f32(partner));
    if (RUB) {
        let normal = 0.5 * applied * a;
        e.rub1.z = normal;
        e.rub1.w = normal / sw;
    }
    e.share = vec4<f32>(n * (dash / sw), eta, phi_dot);
    e.bar0 = bar0;
    e.bar1 = bar1;
    e.keep = vec4<f32>(keep, np_bar);
    e.stored = phi0 * fade;
    return e;
}
