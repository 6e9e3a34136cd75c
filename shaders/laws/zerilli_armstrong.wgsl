// Zerilli–Armstrong strength (CPU twin: physics::laws::zerilli_armstrong):
// sigma_y = C0 + (C1 + C2 eps^1/2) exp(-C3 T + C4 T ln rate) + C5 eps^n,
// T absolute. Constants (Plastic.k): C0, C1, C2, C3, C4, C5, n, the rate
// floor.

fn zerilli_armstrong_factor(p: Plastic, rate: f32, rise: f32) -> f32 {
    let t = p.room + rise;
    return exp(t * (p.k[4] * log(max(rate, p.k[7])) - p.k[3]));
}

fn zerilli_armstrong_curve(p: Plastic, f: f32, eps: f32) -> vec2<f32> {
    let base = p.k[0] + p.k[1] * f;
    if (eps <= 0.0) {
        var slope = 0.0;
        if (p.k[2] * f > 0.0 || (p.k[5] > 0.0 && p.k[6] < 1.0)) {
            slope = BIG;
        } else if (p.k[6] == 1.0) {
            slope = p.k[5];
        }
        return vec2<f32>(base, slope);
    }
    let root = sqrt(eps);
    var s = base + p.k[2] * f * root;
    var slope = 0.5 * p.k[2] * f / root;
    if (p.k[5] != 0.0) {
        let pw = pow(eps, p.k[6]);
        s += p.k[5] * pw;
        slope += p.k[5] * p.k[6] * pw / eps;
    }
    return vec2<f32>(s, slope);
}
