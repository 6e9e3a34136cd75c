// Johnson–Cook strength with the multiplicative rate term (CPU twin:
// physics::laws::modified_johnson_cook): (A + B eps^n)(1 + rate*)^C
// (1 - T*^m). Constants: Johnson–Cook's (johnson_cook.wgsl).

fn modified_johnson_cook_factor(p: Plastic, rate: f32, rise: f32) -> f32 {
    return pow(1.0 + max(rate, 0.0) / p.k[5], p.k[3]) * johnson_cook_thermal(p, rise);
}

fn modified_johnson_cook_curve(p: Plastic, f: f32, eps: f32) -> vec2<f32> {
    return f * johnson_cook_hardening(p, eps);
}
