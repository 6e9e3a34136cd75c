// Johnson–Cook strength (CPU twin: physics::laws::johnson_cook):
// sigma_y = (A + B eps^n)(1 + C ln rate*)(1 - T*^m). Constants (Plastic.k):
// A, B, n, C, m, the reference rate.

// 1 + C ln(rate / rate0), rates below the reference counting as it.
fn johnson_cook_rate(p: Plastic, rate: f32) -> f32 {
    let star = rate / p.k[5];
    if (star > 1.0) {
        return 1.0 + p.k[3] * log(star);
    }
    return 1.0;
}

// 1 - T*^m.
fn johnson_cook_thermal(p: Plastic, rise: f32) -> f32 {
    let t = homologous(p, rise);
    if (t <= 0.0) {
        return 1.0;
    }
    return 1.0 - pow(t, p.k[4]);
}

// A + B eps^n and its slope (BIG at zero strain for n < 1: the return
// brackets its root and never divides by it).
fn johnson_cook_hardening(p: Plastic, eps: f32) -> vec2<f32> {
    if (eps <= 0.0) {
        var slope = 0.0;
        if (p.k[2] < 1.0) {
            slope = BIG;
        } else if (p.k[2] == 1.0) {
            slope = p.k[1];
        }
        return vec2<f32>(p.k[0], slope);
    }
    let pw = pow(eps, p.k[2]);
    return vec2<f32>(p.k[0] + p.k[1] * pw, p.k[1] * p.k[2] * pw / eps);
}

fn johnson_cook_factor(p: Plastic, rate: f32, rise: f32) -> f32 {
    return johnson_cook_rate(p, rate) * johnson_cook_thermal(p, rise);
}

fn johnson_cook_curve(p: Plastic, f: f32, eps: f32) -> vec2<f32> {
    return f * johnson_cook_hardening(p, eps);
}
