// Johnson–Cook damage (CPU twin: physics::failure::johnson_cook):
// eps_f = (D1 + D2 exp(D3 sigma*)) (1 + D4 ln rate*) (1 + D5 T*).
// Constants: Plastic.d1 ... d5.

fn johnson_cook_failure_strain(p: Plastic, triax: f32, rate_star: f32, t_star: f32) -> f32 {
    var rf = 1.0;
    if (rate_star > 1.0) {
        rf = 1.0 + p.d4 * log(rate_star);
    }
    return (p.d1 + p.d2 * exp(p.d3 * triax)) * rf * (1.0 + p.d5 * t_star);
}
