// The kernel and the supports shared by every stage (the host appends this
// file to common.wgsl): the cubic B-spline, its gradient and Hessian, the
// artificial stress's weight and close-pair gate, and the adaptive
// supports' metrics (on the CPU: crate::physics::kernel, crate::physics::support).

// Cubic B-spline (docs/method.md §3).
fn kernel_alpha(h: f32) -> f32 {
    if (DIM == 1u) {
        return 2.0 / (3.0 * h);
    }
    return 10.0 / (7.0 * PI * h * h);
}

// The 2-D kernel's integral along a line through its centre, 15/(7 pi h)
// (CPU twin: physics::kernel::line_integral_2d).
fn line_integral(h: f32) -> f32 {
    return 15.0 / (7.0 * PI * h);
}

fn kernel_w(r: f32, h: f32) -> f32 {
    let q = r / h;
    var f = 0.0;
    if (q < 1.0) {
        f = 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    } else if (q < 2.0) {
        let t = 2.0 - q;
        f = 0.25 * t * t * t;
    }
    return kernel_alpha(h) * f;
}

// The cubic spline's shape inside the support (W = alpha f).
fn kernel_shape(q: f32) -> f32 {
    if (q < 1.0) {
        return 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    }
    let t = max(2.0 - q, 0.0);
    return 0.25 * t * t * t;
}

// The artificial stress's pair weight f^n, f = W(r)/W(dp) at h (the
// normalisation cancels); n = 4, the usual choice, by two squarings
// (pow is exp2(n log2 f), undefined at f = 0).
fn art_weight(r: f32, dp: f32, h: f32) -> f32 {
    let f = kernel_shape(r / h) / kernel_shape(dp / h);
    if (params.as_n == 4.0) {
        let f2 = f * f;
        return f2 * f2;
    }
    return pow(f, params.as_n);
}

// The artificial stress R from t = sigma/rho^2 (xyz): -eps times the
// tensile principal part of t, which is sigma's over rho^2. Without the
// angle: both tensile, -eps t; one (a > 0 >= b), -eps a (t - b I)/(a - b);
// none, zero (the CPU's forces::artificial_stress).
fn art_of(t: vec4<f32>) -> vec4<f32> {
    let m = 0.5 * (t.x + t.y);
    let d = 0.5 * (t.x - t.y);
    let rad = sqrt(d * d + t.z * t.z);
    let a = m + rad;
    let b = m - rad;
    if (b > 0.0) {
        return vec4<f32>(-params.as_eps * t.xyz, 0.0);
    }
    if (a > 0.0) {
        let s = -params.as_eps * a / (a - b);
        return vec4<f32>(s * (t.x - b), s * (t.y - b), s * t.z, 0.0);
    }
    return vec4<f32>(0.0);
}

// The close-pair gate (forces::close_gate): 0 at or beyond the local
// spacing s = kappa vol^(1/d), 1 from CLOSE_FULL s in, linear in (r/s)^2.
const CLOSE_FULL: f32 = 0.95;
fn close_gate(r2: f32, vol: f32, k2: f32) -> f32 {
    var s2 = vol * k2;
    if (DIM == 1u) {
        s2 = vol * vol * k2;
    }
    return clamp((1.0 - r2 / s2) / (1.0 - CLOSE_FULL * CLOSE_FULL), 0.0, 1.0);
}

fn kernel_dw(r: f32, h: f32) -> f32 {
    let q = r / h;
    var f = 0.0;
    if (q < 1.0) {
        f = -3.0 * q + 2.25 * q * q;
    } else if (q < 2.0) {
        let t = 2.0 - q;
        f = -0.75 * t * t;
    }
    return kernel_alpha(h) * f / h;
}

// The Hessian of W at distance r as (s, t), grad grad W = s I + t d d^T for
// the separation d: s = (dW/dr)/r, t = (ds/dr)/r (zero at r = 0 and beyond
// the support). CPU twin: physics::kernel::hessian.
fn kernel_hess(r: f32, h: f32) -> vec2<f32> {
    let q = r / h;
    if (q <= 0.0 || q >= 2.0) {
        return vec2<f32>(0.0);
    }
    let a = kernel_alpha(h) / (h * h);
    if (q < 1.0) {
        return vec2<f32>(a * (-3.0 + 2.25 * q), a * 2.25 / (q * h * h));
    }
    let t = 2.0 - q;
    return vec2<f32>(a * (-0.75 * t * t / q), a * 0.75 * t * (2.0 + q) / (q * q * q * h * h));
}

// grad grad W of separation d, distance r, applied to b.
fn hess_times(d: vec2<f32>, r: f32, h: f32, b: vec2<f32>) -> vec2<f32> {
    let st = kernel_hess(r, h);
    return b * st.x + d * (st.y * dot(d, b));
}

// Support metrics (physics::support::Metric) are vec4 (xx, xy, yy, 0).
fn metric_apply(q: vec4<f32>, d: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(q.x * d.x + q.y * d.y, q.y * d.x + q.z * d.y);
}

// The kernel's normalisation factor sqrt(det Q) (sqrt(Q_xx) in 1-D).
fn metric_scale(q: vec4<f32>) -> f32 {
    if (DIM == 1u) {
        return sqrt(q.x);
    }
    return sqrt(q.x * q.z - q.y * q.y);
}

// The eigenvalues (large, small) of a metric and the unit eigenvector of
// the large one (Metric::eigen).
struct Eigen {
    a: f32,
    b: f32,
    e: vec2<f32>,
}

// The eigenvalues (large, small) of a metric and half their difference
// (Metric::eigenvalues).
fn metric_eigenvalues(q: vec4<f32>) -> vec3<f32> {
    let m = 0.5 * (q.x + q.z);
    let d = 0.5 * (q.x - q.z);
    let rad = sqrt(d * d + q.y * q.y);
    return vec3<f32>(m + rad, m - rad, rad);
}

fn metric_eigen(q: vec4<f32>) -> Eigen {
    let ev = metric_eigenvalues(q);
    let a = ev.x;
    let b = ev.y;
    let p = vec2<f32>(q.y, a - q.x);
    let w = vec2<f32>(a - q.z, q.y);
    var e = p;
    if (dot(w, w) > dot(p, p)) {
        e = w;
    }
    let len = length(e);
    if (len > 0.0) {
        e = e / len;
    } else {
        e = vec2<f32>(1.0, 0.0);
    }
    return Eigen(a, b, e);
}

// The semi-axes (minor, major) of a support.
fn metric_axes(q: vec4<f32>) -> vec2<f32> {
    let g = metric_eigen(q);
    return vec2<f32>(1.0 / sqrt(g.a), 1.0 / sqrt(max(g.b, 1e-37)));
}

// The bounds of a support's semi-axes around the placed h
// (physics::support::STRETCH_MAX, SQUEEZE_MAX).
const STRETCH_MAX: f32 = 4.0;
const SQUEEZE_MAX: f32 = 2.0;

// The metric held to the bounds widened by the band: unchanged inside
// them, else its eigenvalues clamped along the same axes
// (Metric::bounded_band).
fn metric_bounded(q: vec4<f32>, h0: f32) -> vec4<f32> {
    let lo = 1.0 / ((STRETCH_MAX * BAND * h0) * (STRETCH_MAX * BAND * h0));
    let hi = (SQUEEZE_MAX * BAND_SQ / h0) * (SQUEEZE_MAX * BAND_SQ / h0);
    if (DIM == 1u) {
        return vec4<f32>(clamp(q.x, lo, hi), q.y, q.z, 0.0);
    }
    let g = metric_eigen(q);
    if (g.a <= hi && g.b >= lo) {
        return q;
    }
    let a = clamp(g.a, lo, hi);
    let b = clamp(g.b, lo, hi);
    let k = a - b;
    return vec4<f32>(b + k * g.e.x * g.e.x, k * g.e.x * g.e.y, b + k * g.e.y * g.e.y, 0.0);
}

// An eigenvalue of a carried metric mapped by the band (Metric::banded):
// `round` (1/h0^2) inside it, else moved towards it by the square of the
// drawn-out (`d2`) or squeezed (`s2`) factor.
fn band_map(l: f32, round: f32, d2: f32, s2: f32) -> f32 {
    if (l * d2 < round) {
        return l * d2;
    }
    if (l > round * s2) {
        return l / s2;
    }
    return round;
}

// The support of a carried metric `c` of a particle placed with `h0`
// (Metric::banded): the round kernel while every semi-axis lies within
// the band, beyond it the semi-axes over (or times) the band, as
// alpha I + beta c. With no band, `c` itself.
fn metric_banded(c: vec4<f32>, h0: f32) -> vec4<f32> {
    if (no_band()) {
        return c;
    }
    let round = 1.0 / (h0 * h0);
    let d2 = BAND * BAND;
    let s2 = BAND_SQ * BAND_SQ;
    if (DIM == 1u) {
        let k = band_map(c.x, round, d2, s2);
        if (k == round) {
            return vec4<f32>(round, 0.0, round, 0.0);
        }
        return vec4<f32>(k, c.y, c.z, 0.0);
    }
    let ev = metric_eigenvalues(c);
    let l1 = ev.x;
    let l2 = ev.y;
    let rad = ev.z;
    let k1 = band_map(l1, round, d2, s2);
    let k2 = band_map(l2, round, d2, s2);
    if (k1 == round && k2 == round) {
        return vec4<f32>(round, 0.0, round, 0.0);
    }
    var alpha = 0.0;
    var beta = k1 / l1;
    if (rad > 0.0) {
        beta = (k1 - k2) / (l1 - l2);
        alpha = k1 - beta * l1;
    }
    return vec4<f32>(alpha + beta * c.x, beta * c.y, alpha + beta * c.z, 0.0);
}

// The metric carried over a step of dt with the velocity gradient l
// (xx, xy, yx, yy): (I + dt l)^-T Q (I + dt l)^-1, then bounded
// (Metric::carried).
fn metric_carried(q: vec4<f32>, l: vec4<f32>, dt: f32, h0: f32) -> vec4<f32> {
    let a = vec4<f32>(1.0 + dt * l.x, dt * l.y, dt * l.z, 1.0 + dt * l.w);
    if (DIM == 1u) {
        return metric_bounded(vec4<f32>(q.x / (a.x * a.x), q.y, q.z, 0.0), h0);
    }
    let det = a.x * a.w - a.y * a.z;
    if (det == 0.0) {
        return q;
    }
    let inv = 1.0 / det;
    let b11 = a.w * inv;
    let b12 = -a.y * inv;
    let b21 = -a.z * inv;
    let b22 = a.x * inv;
    let qb11 = q.x * b11 + q.y * b21;
    let qb21 = q.y * b11 + q.z * b21;
    let qb12 = q.x * b12 + q.y * b22;
    let qb22 = q.y * b12 + q.z * b22;
    let c = vec4<f32>(b11 * qb11 + b21 * qb21, b11 * qb12 + b21 * qb22, b12 * qb12 + b22 * qb22, 0.0);
    return metric_bounded(c, h0);
}

// The left-hand perpendicular: a boundary normal's tangent.
fn perp(n: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(-n.y, n.x);
}
