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

// Pass 1 at particle p: its entries (a particle off the boundary: no
// partner, nothing else). `count`: whether a particle that meets two partner
// bodies is counted (once an evaluation).
fn entries(p: u32, count: bool) -> Entries {
    // w: the partner body as a float (exact for any realistic count), -1: none.
    var e = Entries(vec4<f32>(0.0, 0.0, 0.0, -1.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), 0.0, 0.0);
    let np4 = nbo[p];
    if (np4.z <= 0.0) {
        return e;
    }
    let mp = pinfo[p];
    let bp = mp.z;
    let bodyp = bodies[bp];
    let op = bitcast<f32>(mp.y);
    let cnp = cn[place(p)];
    let np = cnp.xy;

    var partner = NONE;
    var multi = false;
    var sw = 0.0;
    var sws = vec2<f32>(0.0);
    var swn = vec2<f32>(0.0);
    var swv = vec2<f32>(0.0);
    var swt = 0.0;
    var swo = 0.0;
    var swb = vec2<f32>(0.0);
    let cs = consts();
    let wk = walker(p);
    let hp = bodyp.h;
    for (var row = 0u; row < scan_rows(); row++) {
        let span = row_span(wk.hm, row);
        for (var k = span.start; k < span.end; k++) {
            let cd = cand(wk, k, cs);
            let q = cd.j;
            if (!in_row(cd.cell, span)) {
                continue;
            }
            let mq = pinfo[q];
            let nq4 = nbo[q];
            if (mq.z == bp || nq4.z <= 0.0) {
                continue;
            }
            let oq = bitcast<f32>(mq.y);
            // x_q - x_p.
            let d = -cd.d;
            let cq = cn[place(q)];
            let nq = cq.xy;
            let hq = bodies[mq.z].h;
            let w = candidate(np, nq, d, op, oq, hp, hq, ramp_measure(p, hp, cnp), ramp_measure(q, hq, cq)).x;
            if (w < 0.0) {
                continue;
            }
            if (partner == NONE) {
                partner = mq.z;
            } else if (mq.z != partner) {
                multi = true;
                continue;
            }
            // s_q - S_P, formed from the precise centre difference.
            let rel = d + nq * oq - np * op;
            sw += w;
            sws += rel * w;
            swn += nq * w;
            swv += v[q] * w;
            if (LEAP == 3u) {
                swb += vbook[q] * w;
            }
            swt += dot(nq, -rel) * w;
            swo += oq * w;
        }
    }
    if (multi && count) {
        atomicAdd(&ctl.multi_partner, 1u);
    }
    if (partner == NONE || sw <= 0.0) {
        return e;
    }
    let nlen = length(swn);
    if (nlen <= 0.0) {
        return e;
    }
    let nbar = swn / nlen;
    let rr = sws / sw;
    let tg = swt / sw;
    let vrel = v[p] - swv / sw;
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
    let gap = 0.5 * (chord + tg);
    // Round-off counts as touching (CPU twin: physics::penalty::touching).
    if (gap > 1e-5 * bodyp.spacing) {
        e.own.w = f32(partner);
        return e;
    }
    // The spring measures the overlap beyond the one the particle joined
    // the surface with; that one only shrinks, but follows an overlap more
    // than a quarter spacing beyond it, where the spring yields (CPU twin:
    // the entry rule of cpu::contact::penalty_booked,
    // physics::penalty::yield_overlap).
    let raw = max(-gap, 0.0);
    let e_in = centry[p];
    var yielded = false;
    e.entry = raw;
    if (e_in >= 0.0) {
        e.entry = min(e_in, raw);
        let cap = 0.25 * bodyp.spacing;
        if (raw - e.entry > cap) {
            yielded = true;
            e.entry = raw - cap;
        }
    }
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
    let ob = swo / sw;
    let stiffness = 1.0 / (layer(op, bodyp) + layer(ob, bodyq));
    let push = z * w_rate + stiffness * delta;
    let pres = max(push, 0.0);
    // The dashpot would pull harder than the spring pushes: the pass lets go.
    let clipped = push < 0.0;
    let a = area[area_index(p, nbo[p].w)];
    // The spring's derivative (physics::penalty::gap_bar) and, through the
    // same derivative, dPhi/dt at the booking velocities.
    var keep = vec2<f32>(0.0);
    var np_bar = vec2<f32>(0.0);
    var phi_dot = 0.0;
    var bar0 = vec4<f32>(0.0);
    var bar1 = vec4<f32>(0.0);
    // The pass fades out as its candidates' weight falls below a quarter of
    // a flat surface's (physics::penalty::fade, cpu::contact::
    // weight_reference).
    let phi0 = 0.25 * stiffness * delta * delta * a;
    var fade = 1.0;
    var fade_slope = 0.0;
    var w_ref = 1.0;
    if (DIM == 2u) {
        w_ref = 0.25 * line_integral(hp) / bodyq.spacing;
        let fs = sw / w_ref;
        if (fs < 1.0) {
            fade = fs * fs * (3.0 - 2.0 * fs);
            fade_slope = 6.0 * fs * (1.0 - fs);
        }
    }
    if (delta > 0.0) {
        var slope = 0.0;
        if (!qr && ob > 0.25 * bodyq.spacing) {
            slope = -stiffness * stiffness / bodyq.modulus;
        }
        let gbar = -0.5 * stiffness * delta * a * fade;
        let obar = 0.25 * delta * delta * a * slope * fade;
        let half = 0.5 * gbar;
        let n_bar = rr * half;
        let r_bar = n * half;
        let b_sws = r_bar / sw;
        let b_swt = half / sw;
        let b_swo = obar / sw;
        let b_sw = -(dot(r_bar, rr) + half * tg + obar * ob) / sw + phi0 * fade_slope / w_ref;
        var nbar_bar = vec2<f32>(0.0);
        if (choice == 0u) {
            np_bar = n_bar;
        } else if (choice == 1u) {
            nbar_bar = -n_bar;
        } else {
            let u_bar = (n_bar - n * dot(n, n_bar)) / bl;
            np_bar = u_bar;
            nbar_bar = -u_bar;
        }
        let b_swn = (nbar_bar - nbar * dot(nbar, nbar_bar)) / nlen;
        let b_sp = -b_sws * sw + swn * b_swt;
        bar0 = vec4<f32>(b_sws, b_swn);
        bar1 = vec4<f32>(b_sw, b_swt, b_swo, 0.0);
        var xp_bar = b_sp;
        // The candidates again: each one's share, as its pass 2 makes it.
        for (var row = 0u; row < scan_rows(); row++) {
            let span = row_span(wk.hm, row);
            for (var k = span.start; k < span.end; k++) {
                let cd = cand(wk, k, cs);
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
                let wg = candidate(np, nq, d, op, oq, hp, hq, ramp_measure(p, hp, cnp), ramp_measure(q, hq, cnq));
                if (wg.x < 0.0) {
                    continue;
                }
                let rel = d + nq * oq - np * op;
                let cb = cand_bar(bar0, bar1, wg.x, rel, nq, oq);
                let gw = -d * wg.y;
                xp_bar += gw * cb.w;
                phi_dot += dot(cb.x - gw * cb.w, v_book(q)) + dot(cb.n, perp(nq) * cnq.w);
            }
        }
        np_bar += b_sp * op;
        phi_dot += dot(xp_bar, v_book(p)) + dot(np_bar, perp(np) * cnp.w);
        if (!clipped) {
            keep = -xp_bar;
            bar1.w = 1.0;
        } else {
            np_bar = vec2<f32>(0.0);
        }
    }
    // The rate the heat is booked at: the forces' own, or the leapfrog's
    // v_{n+1}.
    var w_book = w_rate;
    if (LEAP == 3u) {
        w_book = dot(vbook[p] - swb / sw, n);
    }
    // Dashpot heat 1/2 z w A w; where the pass lets go, the spring's energy
    // released.
    var heat = -phi_dot;
    var dash = 0.0;
    if (!clipped) {
        dash = 0.5 * z * w_rate * a;
        heat = dash * w_book;
        // A yielded spring pressed further stores nothing more: the work it
        // takes is heat.
        if (yielded && phi_dot > 0.0) {
            heat += phi_dot;
            phi_dot = 0.0;
        }
    }
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
    e.share = vec4<f32>(n * (dash / sw), eta, phi_dot);
    e.bar0 = bar0;
    e.bar1 = bar1;
    e.keep = vec4<f32>(keep, np_bar);
    e.stored = phi0 * fade;
    return e;
}
