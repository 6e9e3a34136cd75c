//! The penalty spring's gap and the exact gradient of its stored energy
//! (docs/method.md §8.3, "Gap, penalty pressure, force", and "The spring as the gradient of its stored energy").
//!
//! One pass of boundary particle P against one partner body sees that body
//! through kernel-weighted sums over its candidates q ([`Sums`]). The gap is
//! a function of those sums and of P's normal; the stored energy of the pass
//! is `Φ = ¼ k δ² A` with `δ = max(−g, 0)`. This module gives the gap and,
//! by reverse differentiation, `∂Φ/∂` every sum and `∂Φ/∂n_P`
//! ([`SumsBar`]), and from those each candidate's share ([`candidate`]):
//! the derivatives with respect to its position, its normal and its weight.
//! The solvers turn the normals' derivatives into forces through the
//! colour gradient the normals are made from. The spring's stiffness from
//! the two surface layers, the touching and yield overlaps and the entry
//! rule are here too ([`spring_stiffness`], [`entry_rule`]).

use glam::DVec2;

/// Kernel-weighted sums of P over its candidates q in one partner body,
/// with `S_P = x_P + o_P n_P` and `s_q = x_q + o_q n_q` the surface points.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Sums {
    /// `ΣW`
    pub sw: f64,
    /// `ΣW (s_q − S_P)`
    pub sws: DVec2,
    /// `ΣW n_q`
    pub swn: DVec2,
    /// `ΣW n_q·(S_P − s_q)`
    pub swt: f64,
    /// `ΣW o_q`
    pub swo: f64,
}

impl Sums {
    /// Adds candidate q of weight `w` (P's surface point `sp`).
    #[inline]
    pub fn add(&mut self, w: f64, sp: DVec2, sq: DVec2, nq: DVec2, oq: f64) {
        self.sw += w;
        self.sws += (sq - sp) * w;
        self.swn += nq * w;
        self.swt += nq.dot(sp - sq) * w;
        self.swo += oq * w;
    }
}

/// Which direction serves as the contact normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Normal {
    /// P's own normal `n_P`.
    Own,
    /// The partners' mean normal reversed, `−n̄`.
    Partner,
    /// The bisector `(n_P − n̄)/|n_P − n̄|`.
    Bisector,
}

/// The gap of one pass and what its derivative needs.
#[derive(Debug, Clone, Copy)]
pub struct Gap {
    /// `g = ½ (n·r + t)`, negative in overlap.
    pub gap: f64,
    /// The contact normal (unit, P's outward sense).
    pub n: DVec2,
    pub choice: Normal,
    /// `n̄ = ΣW n_q / |ΣW n_q|`.
    nbar: DVec2,
    /// `r = ΣW (s_q − S_P) / ΣW`.
    r: DVec2,
    /// `t = ΣW n_q·(S_P − s_q) / ΣW`.
    t: f64,
}

/// The gap of P (normal `np`) against the interpolated partner surface.
///
/// The weighted mean of the partners' surface points lies on chords, behind
/// a curved surface by ≈ Rφ²/2 (φ the angle the partners span); the weighted
/// distance to the partners' tangent lines errs by the same amount the other
/// way; their mean is exact to second order in φ. The contact normal is, of
/// `n_P`, `−n̄` and their bisector, the one with the largest projected
/// distance (least penetration). `None` without weight or partner normal.
pub fn gap(np: DVec2, s: &Sums) -> Option<Gap> {
    if s.sw <= 0.0 {
        return None;
    }
    let nbar = s.swn.normalize_or_zero();
    if nbar == DVec2::ZERO {
        return None;
    }
    let r = s.sws / s.sw;
    let t = s.swt / s.sw;
    let mut best = (np, np.dot(r), Normal::Own);
    for (cand, choice) in [
        (-nbar, Normal::Partner),
        ((np - nbar).normalize_or_zero(), Normal::Bisector),
    ] {
        if cand != DVec2::ZERO {
            let d = cand.dot(r);
            if d > best.1 {
                best = (cand, d, choice);
            }
        }
    }
    let (n, chord, choice) = best;
    Some(Gap {
        gap: 0.5 * (chord + t),
        n,
        choice,
        nbar,
        r,
        t,
    })
}

/// `∂Φ/∂` the sums of a pass, P's surface point and P's normal.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SumsBar {
    pub sw: f64,
    pub sws: DVec2,
    pub swn: DVec2,
    pub swt: f64,
    pub swo: f64,
    /// `∂Φ/∂S_P` through the sums (the weights aside).
    pub sp: DVec2,
    /// `∂Φ/∂n_P` through the choice of the contact normal (the surface point
    /// aside: that is `o_P` times [`SumsBar::sp`]).
    pub np: DVec2,
}

/// Reverse derivative of the gap: `gbar = ∂Φ/∂g` and `obar = ∂Φ/∂ō`, with
/// `ō = ΣW o_q / ΣW` the partners' mean offset (the stiffness's far layer).
pub fn gap_bar(np: DVec2, s: &Sums, g: &Gap, gbar: f64, obar: f64) -> SumsBar {
    let chord_bar = 0.5 * gbar;
    let t_bar = 0.5 * gbar;
    // chord = n·r
    let n_bar = g.r * chord_bar;
    let r_bar = g.n * chord_bar;
    let sws = r_bar / s.sw;
    let swt = t_bar / s.sw;
    let swo = obar / s.sw;
    let sw = -(r_bar.dot(g.r) + t_bar * g.t + obar * s.swo / s.sw) / s.sw;
    let (np_bar, nbar_bar) = match g.choice {
        Normal::Own => (n_bar, DVec2::ZERO),
        Normal::Partner => (DVec2::ZERO, -n_bar),
        Normal::Bisector => {
            let u = np - g.nbar;
            let u_bar = (n_bar - g.n * g.n.dot(n_bar)) / u.length();
            (u_bar, -u_bar)
        }
    };
    let swn = (nbar_bar - g.nbar * g.nbar.dot(nbar_bar)) / s.swn.length();
    SumsBar {
        sw,
        sws,
        swn,
        swt,
        swo,
        sp: -sws * s.sw + s.swn * swt,
        np: np_bar,
    }
}

/// The fade of a pass whose candidates' total weight is `s` times the
/// reference (`smoothstep`, 1 from `s = 1`), and its slope.
///
/// The gap is a weighted mean, so it stays finite as the last candidate's
/// weight goes to zero, then the pass vanishes: a jump of the stored
/// energy; and the mean's derivative with respect to a weight carries
/// `1/ΣW`, which with a few grazing candidates at a crater lip makes
/// forces many times the spring's own. Scaling the pass's energy by the
/// fade makes it vanish continuously, and the weights' derivative bounded
/// (`∝ ΣW`) where it would blow up. Flat surfaces touching give `s ≈ 1.5`.
#[inline]
pub fn fade(s: f64) -> (f64, f64) {
    if s >= 1.0 || s.is_nan() {
        (1.0, 0.0)
    } else if s <= 0.0 {
        (0.0, 0.0)
    } else {
        (s * s * (3.0 - 2.0 * s), 6.0 * s * (1.0 - s))
    }
}

/// One candidate's share of a pass's derivative.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Candidate {
    /// `∂Φ/∂x_q` through its surface point (the weight aside).
    pub x: DVec2,
    /// `∂Φ/∂n_q` (not yet projected on the tangent).
    pub n: DVec2,
    /// `∂Φ/∂W_q`: the weight's derivative, applied along `∇W`.
    pub w: f64,
}

/// Candidate q (weight `w`, surface point `sq`, normal `nq`, offset `oq`) of
/// a pass with derivative `bar` and P's surface point `sp`.
#[inline]
pub fn candidate(bar: &SumsBar, sp: DVec2, w: f64, sq: DVec2, nq: DVec2, oq: f64) -> Candidate {
    let x = (bar.sws - nq * bar.swt) * w;
    Candidate {
        x,
        n: (bar.swn + (sp - sq) * bar.swt) * w + x * oq,
        w: bar.sw
            + bar.sws.dot(sq - sp)
            + bar.swn.dot(nq)
            + bar.swt * nq.dot(sp - sq)
            + bar.swo * oq,
    }
}

// The spring's constants and the entry rule: functions of the two
// surfaces' layers and overlaps alone.

/// Stiffness of the penalty spring, Pa/m (docs/method.md §8.3, derived here).
///
/// The spring stands for the two surface layers between the particle
/// centres and the surfaces they meet: thickness `o_a` of body A and `o_b`
/// of body B, each squeezed in uniaxial strain (the layer is thin against
/// the body, so the constrained modulus `M = K + 4G/3 = ρ0 c_L²` holds).
/// In series their compliance is `o_a/M_a + o_b/M_b`. On a conforming
/// lattice (`o = Δx/2`) between equal bodies this is `M/Δx`, where the
/// paper's `E*/h0` gives `E/(2Δx)`: for steel 2.7 times more compliant than
/// the material it stands for, which made contacts soft and long.
///
/// A layer is taken at least `Δx/4` thick: on a square lattice around a curve
/// a particle centre can sit almost on the surface, and a zero-thickness
/// layer would be an infinitely stiff spring. At the floor the spring's
/// frequency is `√2 c_L/Δx` between equal bodies (`2 c_L/Δx` against a
/// rigid one), so `ω Δt ≈ 0.5` (0.72) at the default CFL step; the step
/// is held below [`CONTACT_STEP`]` / ω` ([`contact_step`]).
/// A rigid side (`M = ∞`) adds no compliance.
pub fn spring_stiffness(o_a: f64, dx_a: f64, m_a: f64, o_b: f64, dx_b: f64, m_b: f64) -> f64 {
    let layer = |o: f64, dx: f64, m: f64| {
        if m.is_infinite() {
            0.0
        } else {
            o.max(0.25 * dx) / m
        }
    };
    1.0 / (layer(o_a, dx_a, m_a) + layer(o_b, dx_b, m_b))
}

/// The most `ω Δt` the step gives the stiffest penalty spring
/// ([`contact_step`]). Alone the spring is stable to `ω Δt = 2` on the
/// leapfrog, but it acts on particles the body's own stresses load too:
/// at CFL 0.9 the spring of two coarse steel disks at `ω Δt ≈ 1.5` (its
/// floor) makes the contact chatter, opening and closing every 15 steps,
/// at twice the Hertz force; at 1.27 (CFL 0.75) the contact holds the
/// quasi-static force (docs/method.md §9).
pub const CONTACT_STEP: f64 = 1.0;

/// The longest step the penalty spring between bodies a and b allows on
/// body a (spacing `dx_a`, reference density `rho_a`, constrained modulus
/// `m_a`), `CONTACT_STEP / ω` with `ω² = k / (ρ_a Δx_a)`: the spring
/// of [`spring_stiffness`] at its floor (both layers `Δx/4`), pressing on
/// a particle of mass `ρ Δx^d` through its area `Δx^(d−1)` (the same
/// ratio in 1-D, plane strain and bodies of revolution). Infinite for a
/// rigid body a (`m_a = ∞`: its particles move as prescribed).
pub fn contact_step(dx_a: f64, rho_a: f64, m_a: f64, dx_b: f64, m_b: f64) -> f64 {
    if m_a.is_infinite() {
        return f64::INFINITY;
    }
    let k = spring_stiffness(0.0, dx_a, m_a, 0.0, dx_b, m_b);
    CONTACT_STEP * (rho_a * dx_a / k).sqrt()
}

/// The surface offset a particle carries (`Model::offset`), from the one
/// its placement gives (`placed`: the distance from its centre to its
/// shape's boundary), its body's spacing and its placement jitter (a
/// fraction of the spacing, 0 without) in `dim` dimensions, and whether
/// it is on the boundary as placed.
///
/// A particle off the boundary and placed deeper than [`FRESH_DEPTH`]
/// spacings, or than one spacing plus the most the jitter can move it
/// inward (`jitter √d`), is interior on every lattice (the outer layer of a
/// lattice lies within one spacing of the boundary: a neighbour one
/// spacing away is outside), and its distance to the shape as placed says
/// nothing of a surface: if the flow exposes it (a crater's wall, a crack)
/// its surface is a fresh one, half a spacing out as on a conforming face.
/// A particle on the boundary keeps its offset however deep (a heavily
/// jittered body's surface has gaps that put deeper particles on it). Left at its depth, a crater wall's surface points sat
/// up to 5.5 spacings in front of its particles (Δx = 0.2 mm, 1,200 m/s,
/// 5 µs): the interpolated surface ran ahead of the wall, and the weights'
/// derivatives, which carry the offsets, made the springs' forces on it
/// many times the rest.
#[inline]
pub fn surface_offset(placed: f64, spacing: f64, jitter: f64, dim: usize, boundary: bool) -> f64 {
    let outer = FRESH_DEPTH.max(1.0 + jitter * (dim as f64).sqrt());
    if !boundary && placed > outer * spacing {
        0.5 * spacing
    } else {
        placed
    }
}

/// The depth, in spacings, below which a particle of an unjittered body
/// keeps the surface offset of its placement ([`surface_offset`]).
pub const FRESH_DEPTH: f64 = 1.25;

/// The gap below which two surfaces count as touching: `1e-5 Δx`.
///
/// Bodies placed touching have a gap of zero up to the round-off of their
/// coordinates (`+2e-19 m` for the paper's bars in f64, a few `1e-7 Δx` on
/// the GPU's f32 offsets). A gap of `+ε` makes the contact start inside the
/// first step instead of at it: the midpoint step then applies the dashpot
/// from its half state, which has not yet felt it, and books 0.3 % too much
/// heat for the bar impact. Counting round-off as touching starts both
/// backends alike; the dashpot engages `1e-5 Δx / w` early at most (a
/// thousandth of a time step), the spring only on a true overlap.
#[inline]
pub fn touching(spacing: f64) -> f64 {
    1e-5 * spacing
}

/// The overlap beyond its entry at which a particle's spring yields:
/// a quarter spacing of its body.
///
/// An overlap that deep is no resolved contact (the physical ones are
/// `p Δx / M`: 1e-3 Δx for the paper's disks, 0.09 Δx for a steel rod
/// into aluminium at 500 m/s); at a crater lip the interpolated partner
/// surface of a particle with a few grazing candidates can jump by
/// several spacings between steps. Beyond it the entry overlap follows
/// (`State::entry`): the pressure holds at `k Δx/4` (a quarter of the
/// constrained modulus on a conforming lattice), the stored energy stays
/// continuous, and the work a further compression does is booked as heat.
#[inline]
pub fn yield_overlap(spacing: f64) -> f64 {
    0.25 * spacing
}

/// The entry overlap after an evaluation whose deepest raw overlap over
/// P's passes is `deepest`, from the stored one `e_in` (negative: P was
/// off the boundary at the last base state), with the yield overlap `cap`
/// ([`yield_overlap`]); and whether the spring has yielded. A particle
/// joins storing nothing; the entry only shrinks, except to follow an
/// overlap more than `cap` beyond it.
#[inline]
pub fn entry_rule(e_in: f64, deepest: f64, cap: f64) -> (f64, bool) {
    if e_in < 0.0 {
        return (deepest, false);
    }
    let e = e_in.min(deepest);
    if deepest - e > cap {
        (deepest - cap, true)
    } else {
        (e, false)
    }
}

/// The stiffness's slope `∂k/∂o_b` with the far layer's thickness (`k`
/// from [`spring_stiffness`]): zero where the layer sits at its floor or
/// the far side is rigid.
pub fn stiffness_slope(k: f64, o_b: f64, dx_b: f64, m_b: f64) -> f64 {
    if m_b.is_infinite() || o_b <= 0.25 * dx_b {
        0.0
    } else {
        -k * k / m_b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The contact's step limit, exactly: `Δx / (√2 c_L)` between equal
    /// bodies, `Δx / (2 c_L)` against a rigid one (for the deformable
    /// side; a rigid side sets none), where `M = ρ0 c_L²`.
    #[test]
    fn contact_step_between_equal_and_rigid_bodies() {
        let (rho, c, dx) = (7850.0, 5835.66, 5.0e-5);
        let m = rho * c * c;
        let equal = contact_step(dx, rho, m, dx, m);
        assert!((equal / (dx / (2f64.sqrt() * c)) - 1.0).abs() < 1e-14);
        let wall = contact_step(dx, rho, m, dx, f64::INFINITY);
        assert!((wall / (dx / (2.0 * c)) - 1.0).abs() < 1e-14);
        assert_eq!(contact_step(dx, rho, f64::INFINITY, dx, m), f64::INFINITY);
        // A body against a softer one: its spring is softer, its step longer.
        assert!(contact_step(dx, rho, m, dx, 0.1 * m) > equal);
    }

    /// The surface offset: as placed up to 1.25 spacings deep (a
    /// conforming face's half spacing, a square lattice's 0 to 1 around a
    /// curve), half a spacing deeper; a jittered body's outer layer may sit
    /// `jitter √d` spacings further in.
    #[test]
    fn surface_offset_cases() {
        let dx = 2.0e-4;
        for o in [0.0, 0.1 * dx, 0.5 * dx, dx, 1.25 * dx] {
            assert_eq!(surface_offset(o, dx, 0.0, 2, false), o);
            assert_eq!(surface_offset(o, dx, 0.1, 2, false), o);
        }
        for o in [1.25 * dx * (1.0 + 1e-12), 1.5 * dx, 5.5 * dx] {
            assert_eq!(surface_offset(o, dx, 0.0, 2, false), 0.5 * dx);
        }
        // Jitter 0.4 in 2-D: the outer layer reaches 1 + 0.4 √2 = 1.566.
        assert_eq!(surface_offset(1.5 * dx, dx, 0.4, 2, false), 1.5 * dx);
        assert_eq!(surface_offset(1.6 * dx, dx, 0.4, 2, false), 0.5 * dx);
        // On the boundary as placed, kept however deep.
        assert_eq!(surface_offset(5.5 * dx, dx, 0.0, 2, true), 5.5 * dx);
        // In 1-D, 1 + 0.4.
        assert_eq!(surface_offset(1.35 * dx, dx, 0.4, 1, false), 1.35 * dx);
        assert_eq!(surface_offset(1.45 * dx, dx, 0.4, 1, false), 0.5 * dx);
    }

    /// The entry rule's cases, exactly.
    #[test]
    fn entry_rule_cases() {
        // Joining: the overlap is the entry.
        assert_eq!(entry_rule(-1.0, 0.3, 0.25), (0.3, false));
        // Shrinks to a smaller overlap, stays against a larger one.
        assert_eq!(entry_rule(0.2, 0.1, 0.25), (0.1, false));
        assert_eq!(entry_rule(0.1, 0.3, 0.25), (0.1, false));
        // Follows an overlap more than the cap beyond it.
        assert_eq!(entry_rule(0.1, 0.5, 0.25), (0.25, true));
        assert_eq!(entry_rule(0.0, 0.0, 0.25), (0.0, false));
    }

    /// A candidate `(w, s_q, n_q, o_q)`.
    type Cand = (f64, DVec2, DVec2, f64);

    /// A pass from every input `(np, sp, [(w, sq, nq, oq)])`, with a
    /// stiffness that depends on the mean offset as the real one does:
    /// its energy, its derivative and its contact normal's choice.
    fn pass(np: DVec2, sp: DVec2, cands: &[Cand]) -> (f64, SumsBar, Normal) {
        let mut s = Sums::default();
        for &(w, sq, nq, oq) in cands {
            s.add(w, sp, sq, nq, oq);
        }
        let g = gap(np, &s).unwrap();
        let k = 1.0 / (0.3 + s.swo / s.sw);
        let d = (-g.gap).max(0.0);
        let bar = gap_bar(np, &s, &g, -0.5 * k * d, -0.25 * d * d * k * k);
        (0.25 * k * d * d, bar, g.choice)
    }

    fn energy(np: DVec2, sp: DVec2, cands: &[Cand]) -> f64 {
        pass(np, sp, cands).0
    }

    /// The fade: 0 with no weight, 1 from the reference on, continuous with
    /// its slope at both ends, and the slope its derivative.
    #[test]
    fn fade_is_smooth() {
        assert_eq!(fade(0.0), (0.0, 0.0));
        assert_eq!(fade(1.0), (1.0, 0.0));
        assert_eq!(fade(2.5), (1.0, 0.0));
        let (f, df) = fade(1.0 - 1e-9);
        assert!((1.0 - f).abs() < 1e-12 && df.abs() < 1e-8);
        let (f, df) = fade(1e-9);
        assert!(f.abs() < 1e-12 && df.abs() < 1e-8);
        for s in [0.1, 0.37, 0.5, 0.83, 0.99] {
            let fd = (fade(s + 1e-7).0 - fade(s - 1e-7).0) / 2e-7;
            assert!((fd - fade(s).1).abs() < 1e-7, "{s}: {fd} vs {}", fade(s).1);
        }
    }

    /// Every derivative of the pass agrees with central differences, for
    /// each choice of the contact normal.
    #[test]
    fn derivatives_match_differences() {
        let cands = [
            (
                0.8,
                DVec2::new(-0.2, -0.05),
                DVec2::new(0.1, 1.0).normalize(),
                0.4,
            ),
            (
                0.5,
                DVec2::new(0.3, -0.12),
                DVec2::new(-0.2, 1.0).normalize(),
                0.5,
            ),
            (
                0.3,
                DVec2::new(0.7, -0.02),
                DVec2::new(-0.3, 1.0).normalize(),
                0.45,
            ),
        ];
        let sp = DVec2::new(0.1, 0.02);
        let mut seen = Vec::new();
        for np in [
            DVec2::new(0.0, -1.0),
            DVec2::new(0.6, -0.8),
            DVec2::new(-0.3, -1.0).normalize(),
            DVec2::new(0.25, -1.0).normalize(),
        ] {
            let (_, bar, choice) = pass(np, sp, &cands);
            seen.push(choice);
            let eps = 1e-7;
            let tol = |a: f64| 1e-6 * (1.0 + a.abs());
            for e in [DVec2::X, DVec2::Y] {
                // P's normal (free vector) and surface point.
                let fd = (energy(np + e * eps, sp, &cands) - energy(np - e * eps, sp, &cands))
                    / (2.0 * eps);
                assert!(
                    (fd - bar.np.dot(e)).abs() < tol(fd),
                    "np {np}: {fd} vs {}",
                    bar.np.dot(e)
                );
                let fd = (energy(np, sp + e * eps, &cands) - energy(np, sp - e * eps, &cands))
                    / (2.0 * eps);
                assert!(
                    (fd - bar.sp.dot(e)).abs() < tol(fd),
                    "sp: {fd} vs {}",
                    bar.sp.dot(e)
                );
                for k in 0..cands.len() {
                    let (w, sq, nq, oq) = cands[k];
                    let c = candidate(&bar, sp, w, sq, nq, oq);
                    let moved = |f: &dyn Fn(&mut Cand)| {
                        let mut cs = cands;
                        f(&mut cs[k]);
                        energy(np, sp, &cs)
                    };
                    // Surface point s_q with n_q fixed: x_q's direct share.
                    let fd =
                        (moved(&|c| c.1 += e * eps) - moved(&|c| c.1 -= e * eps)) / (2.0 * eps);
                    assert!(
                        (fd - c.x.dot(e)).abs() < tol(fd),
                        "x_q: {fd} vs {}",
                        c.x.dot(e)
                    );
                    // n_q with x_q fixed (s_q moves by o_q δn).
                    let fd = (moved(&|c| {
                        c.2 += e * eps;
                        c.1 += e * (eps * c.3);
                    }) - moved(&|c| {
                        c.2 -= e * eps;
                        c.1 -= e * (eps * c.3);
                    })) / (2.0 * eps);
                    assert!(
                        (fd - c.n.dot(e)).abs() < tol(fd),
                        "n_q: {fd} vs {}",
                        c.n.dot(e)
                    );
                }
            }
            for k in 0..cands.len() {
                let (w, sq, nq, oq) = cands[k];
                let c = candidate(&bar, sp, w, sq, nq, oq);
                let moved = |dw: f64| {
                    let mut cs = cands;
                    cs[k].0 += dw;
                    energy(np, sp, &cs)
                };
                let fd = (moved(1e-7) - moved(-1e-7)) / 2e-7;
                assert!(
                    (fd - c.w).abs() < 1e-6 * (1.0 + fd.abs()),
                    "w: {fd} vs {}",
                    c.w
                );
            }
        }
        // The cases above exercise all three contact normals.
        for choice in [Normal::Own, Normal::Partner, Normal::Bisector] {
            assert!(seen.contains(&choice), "{choice:?} not exercised: {seen:?}");
        }
    }
}
