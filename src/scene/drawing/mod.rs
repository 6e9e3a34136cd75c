//! Sections drawn in CAD: a `polygon` shape's outline and holes read from
//! an SVG or a DXF file (docs/scenes.md, "Drawn sections").
//!
//! Each reader turns the drawing's elements into closed loops in drawing
//! units, its curves cut into chords no farther than the tolerance from
//! them. This module scales the loops to metres, sorts them into the
//! outline and its holes by the fill rule, and checks them, naming the
//! element at fault.

mod dxf;
mod svg;

use glam::DVec2;
use std::path::Path;

use super::outline;

/// What a scene asks of a drawing.
pub struct Request<'a> {
    pub file: &'a Path,
    /// Metres per drawing unit, overriding the unit the drawing states.
    pub scale: Option<f64>,
    /// The part to read (an SVG id or label, a DXF layer); `None`: all.
    pub layer: Option<&'a str>,
    /// Largest distance between a curve and its chords, m.
    pub tolerance: f64,
    /// Added to every point after scaling, m.
    pub offset: DVec2,
}

/// A section read from a drawing, in metres: one outline and its holes.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    pub outline: Vec<DVec2>,
    pub holes: Vec<Vec<DVec2>>,
}

/// How a drawing decides which side of its loops is filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FillRule {
    /// Filled where the loops wind around a point a non-zero number of
    /// times (SVG's default).
    NonZero,
    /// Filled where a ray from a point crosses the loops an odd number of
    /// times (SVG's `evenodd`; a DXF drawing's nesting).
    EvenOdd,
}

/// A closed loop in drawing units, as one element draws it. Loops of one
/// `group` (one SVG element; a whole DXF drawing) are filled together.
struct Loop {
    element: String,
    group: usize,
    rule: FillRule,
    points: Vec<DVec2>,
}

/// Metres per drawing unit. A power of ten moves the decimal point of
/// each coordinate's shortest decimal form, so that a figure drawn in
/// millimetres gives the very double the same figure typed in metres
/// gives (a product by 0.001 differs in the last bit about one time in
/// six).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Unit {
    Decade(i32),
    Times(f64),
}

impl Unit {
    /// The unit `scale` metres long.
    fn of(scale: f64) -> Unit {
        let shortest = format!("{scale:e}");
        match shortest.strip_prefix("1e").map(str::parse::<i32>) {
            Some(Ok(k)) => Unit::Decade(k),
            _ => Unit::Times(scale),
        }
    }

    fn metres(self) -> f64 {
        match self {
            Unit::Decade(k) => 10f64.powi(k),
            Unit::Times(f) => f,
        }
    }

    /// This unit `ratio` times longer.
    fn times(self, ratio: f64) -> Unit {
        if ratio == 1.0 {
            self
        } else {
            Unit::Times(self.metres() * ratio)
        }
    }

    /// `x` drawing units in metres.
    fn apply(self, x: f64) -> f64 {
        match self {
            Unit::Decade(0) => x,
            Unit::Decade(k) => {
                let shortest = format!("{x:e}");
                let (mantissa, exponent) = shortest
                    .split_once('e')
                    .expect("the exponent form has an exponent");
                let e: i32 = exponent.parse().expect("an integer exponent");
                format!("{mantissa}e{}", e + k)
                    .parse()
                    .expect("a mantissa and an exponent")
            }
            Unit::Times(f) => x * f,
        }
    }
}

/// The unit to read a drawing in: the scene's `scale` when given, else
/// the one the drawing states (or why it states none).
fn unit(req: &Request, stated: Result<Unit, String>) -> Result<Unit, String> {
    match req.scale {
        Some(s) => Ok(Unit::of(s)),
        None => stated.map_err(|why| format!("{why}: give `scale`, metres per drawing unit")),
    }
}

/// Read a drawn section: `.svg` or `.dxf` by the file's extension.
pub fn read(req: &Request) -> Result<Section, String> {
    let ext = req
        .file
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let (unit, loops) = match ext.as_deref() {
        Some("svg") => {
            let text = std::fs::read_to_string(req.file)
                .map_err(|e| format!("cannot read {}: {e}", req.file.display()))?;
            svg::read(&text, req)?
        }
        Some("dxf") => dxf::read(req.file, req)?,
        _ => {
            return Err(format!(
                "{}: a drawn section is an .svg or a .dxf file",
                req.file.display()
            ))
        }
    };
    section(loops, unit, req)
}

/// Scale the loops, check them, and sort them into one outline and its
/// holes.
fn section(loops: Vec<Loop>, unit: Unit, req: &Request) -> Result<Section, String> {
    let mut rings: Vec<Loop> = Vec::with_capacity(loops.len());
    for mut l in loops {
        for p in &mut l.points {
            *p = DVec2::new(unit.apply(p.x), unit.apply(p.y)) + req.offset;
        }
        l.points.dedup();
        if l.points.len() > 1 && l.points.first() == l.points.last() {
            l.points.pop();
        }
        if l.points.len() < 3 {
            return Err(format!("{}: encloses no area", l.element));
        }
        if let Some((a, b)) = outline::self_intersection(&l.points) {
            let at = |k: usize| l.points[k];
            return Err(format!(
                "{}: the outline crosses itself (its edge from ({}) meets its edge from ({}))",
                l.element,
                metres(at(a)),
                metres(at(b))
            ));
        }
        if outline::signed_area(&l.points) == 0.0 {
            return Err(format!("{}: encloses no area", l.element));
        }
        // Loops of one group bound one region; those of different groups
        // are filled apart (and two outlines are refused below).
        if let Some(o) = rings
            .iter()
            .find(|o| o.group == l.group && outline::rings_meet(&o.points, &l.points))
        {
            return Err(format!(
                "{} and {} cross or touch: a hole must lie inside its outline, touching nowhere",
                o.element, l.element
            ));
        }
        rings.push(l);
    }
    let (mut outer, mut holes) = (Vec::new(), Vec::new());
    for (i, r) in rings.iter().enumerate() {
        // The winding number just outside r: the loops of its group that
        // enclose it (they cannot cross it).
        let p = r.points[0];
        let around: i32 = rings
            .iter()
            .enumerate()
            .filter(|&(j, o)| j != i && o.group == r.group && outline::contains(&o.points, p))
            .map(|(_, o)| winding(&o.points))
            .sum();
        let filled = |w: i32| match r.rule {
            FillRule::NonZero => w != 0,
            FillRule::EvenOdd => w % 2 != 0,
        };
        match (filled(around + winding(&r.points)), filled(around)) {
            (true, false) => outer.push(r),
            (false, true) => holes.push(r),
            // The same fill on both sides: a loop that bounds nothing.
            _ => {}
        }
    }
    let scope = match req.layer {
        Some(l) => format!("'{l}' in {}", req.file.display()),
        None => req.file.display().to_string(),
    };
    match outer.as_slice() {
        [] => Err(format!("no closed outline found in {scope}")),
        [one] => Ok(Section {
            outline: one.points.clone(),
            holes: holes.iter().map(|h| h.points.clone()).collect(),
        }),
        many => Err(format!(
            "{scope} holds {} separate outlines ({}); a polygon is one outline with its holes: pick one with `layer`",
            many.len(),
            list(many.iter().map(|l| l.element.clone()))
        )),
    }
}

/// +1 for a counter-clockwise loop, −1 for a clockwise one.
fn winding(points: &[DVec2]) -> i32 {
    if outline::signed_area(points) > 0.0 {
        1
    } else {
        -1
    }
}

fn metres(p: DVec2) -> String {
    format!("{} m, {} m", p.x, p.y)
}

/// The first few of `names`, comma-separated.
fn list(names: impl Iterator<Item = String>) -> String {
    let names: Vec<String> = names.collect();
    const SHOWN: usize = 12;
    let mut s = names[..names.len().min(SHOWN)].join(", ");
    if names.len() > SHOWN {
        s.push_str(&format!(" and {} more", names.len() - SHOWN));
    }
    s
}

/// Cuts curves into chords, pushing the points after a curve's start.
/// A curve `c(t)` on `t ∈ [0, span]` with `|c''| ≤ bound` strays at most
/// `h² bound / 8` from the chords of `n` equal parameter steps `h`.
fn pieces(span: f64, bound: f64, tolerance: f64) -> usize {
    let n = span * (bound / (8.0 * tolerance)).sqrt();
    (n.ceil() as usize).clamp(1, 100_000)
}

/// Push `p` unless it repeats the last point.
fn push(out: &mut Vec<DVec2>, p: DVec2) {
    if out.last() != Some(&p) {
        out.push(p);
    }
}

/// A cubic Bézier from `out`'s last point through the controls `c1`,
/// `c2` to `to`.
fn cubic(out: &mut Vec<DVec2>, c1: DVec2, c2: DVec2, to: DVec2, tolerance: f64) {
    let p0 = *out.last().expect("a curve starts at a point");
    let bound = 6.0
        * (p0 - 2.0 * c1 + c2)
            .length()
            .max((c1 - 2.0 * c2 + to).length());
    let n = pieces(1.0, bound, tolerance);
    for k in 1..n {
        let t = k as f64 / n as f64;
        let s = 1.0 - t;
        push(
            out,
            s * s * s * p0 + 3.0 * s * s * t * c1 + 3.0 * s * t * t * c2 + t * t * t * to,
        );
    }
    push(out, to);
}

/// A quadratic Bézier from `out`'s last point through `c` to `to`.
fn quadratic(out: &mut Vec<DVec2>, c: DVec2, to: DVec2, tolerance: f64) {
    let p0 = *out.last().expect("a curve starts at a point");
    let n = pieces(1.0, 2.0 * (p0 - 2.0 * c + to).length(), tolerance);
    for k in 1..n {
        let t = k as f64 / n as f64;
        let s = 1.0 - t;
        push(out, s * s * p0 + 2.0 * s * t * c + t * t * to);
    }
    push(out, to);
}

/// The points of the ellipse `centre + (rx cos θ, ry sin θ)` for θ from
/// `from` through `sweep` (radians, negative: clockwise), the start left
/// out; `map` places each point.
fn elliptic(
    out: &mut Vec<DVec2>,
    centre: DVec2,
    radii: DVec2,
    (from, sweep): (f64, f64),
    tolerance: f64,
    map: impl Fn(DVec2) -> DVec2,
) {
    let n = pieces(sweep.abs(), radii.x.max(radii.y), tolerance);
    for k in 1..=n {
        let t = from + sweep * k as f64 / n as f64;
        push(out, map(centre + radii * DVec2::new(t.cos(), t.sin())));
    }
}

/// A whole ellipse as a closed loop of at least eight chords.
fn ellipse(
    centre: DVec2,
    radii: DVec2,
    tolerance: f64,
    map: impl Fn(DVec2) -> DVec2,
) -> Vec<DVec2> {
    let tau = std::f64::consts::TAU;
    let n = pieces(tau, radii.x.max(radii.y), tolerance).max(8);
    (0..n)
        .map(|k| {
            let t = tau * k as f64 / n as f64;
            map(centre + radii * DVec2::new(t.cos(), t.sin()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_decade_moves_the_decimal_point() {
        // Figures in millimetres give the doubles of the same figures in
        // metres, where a product by 0.001 misses some.
        let mm = Unit::of(0.001);
        assert_eq!(mm, Unit::Decade(-3));
        let mut missed = 0;
        for (drawn, typed) in [
            ("-24.07636664", "-2.407636664e-02"),
            ("4.900857016", "0.004900857016"),
            ("0.3", "0.0003"),
            ("9.975923633", "0.009975923633"),
            ("4.903926402", "0.004903926402"),
            ("-3.888859534", "-0.003888859534"),
            ("1234.5678", "1.2345678"),
        ] {
            let x: f64 = drawn.parse().unwrap();
            let want: f64 = typed.parse().unwrap();
            assert_eq!(mm.apply(x), want, "{drawn}");
            missed += usize::from(x * 0.001 != want);
        }
        assert!(missed > 0, "the test should hold a figure a product misses");
        assert_eq!(Unit::of(0.0254), Unit::Times(0.0254));
        assert_eq!(Unit::of(1.0), Unit::Decade(0));
        assert_eq!(Unit::Decade(0).apply(0.1), 0.1);
    }

    #[test]
    fn chords_stay_within_the_tolerance() {
        // A quarter circle as a cubic (the usual 0.5523 handles) and as an
        // arc: every chord's midpoint within the tolerance of the curve.
        let tol = 1e-3;
        let k = 0.552_284_749_830_793_4;
        let mut c = vec![DVec2::new(1.0, 0.0)];
        cubic(
            &mut c,
            DVec2::new(1.0, k),
            DVec2::new(k, 1.0),
            DVec2::new(0.0, 1.0),
            tol,
        );
        let mut a = vec![DVec2::new(1.0, 0.0)];
        elliptic(
            &mut a,
            DVec2::ZERO,
            DVec2::ONE,
            (0.0, std::f64::consts::FRAC_PI_2),
            tol,
            |p| p,
        );
        for pts in [&c, &a] {
            assert!(pts.len() > 4, "{}", pts.len());
            for w in pts.windows(2) {
                let mid = 0.5 * (w[0] + w[1]);
                // The cubic is within 2.7e-4 of the circle itself.
                assert!(1.0 - mid.length() < tol + 3e-4, "{mid}");
            }
            assert!((pts.last().unwrap().y - 1.0).abs() < 1e-15);
        }
        let loop_ = ellipse(DVec2::ZERO, DVec2::new(2.0, 1.0), tol, |p| p);
        assert!(loop_.len() >= 8);
        assert!(outline::signed_area(&loop_) > 0.0);
    }

    fn square(at: f64, side: f64, ccw: bool, group: usize, rule: FillRule) -> Loop {
        let mut points = vec![
            DVec2::new(at, at),
            DVec2::new(at + side, at),
            DVec2::new(at + side, at + side),
            DVec2::new(at, at + side),
        ];
        if !ccw {
            points.reverse();
        }
        Loop {
            element: format!("square {at}"),
            group,
            rule,
            points,
        }
    }

    fn req() -> Request<'static> {
        Request {
            file: Path::new("part.svg"),
            scale: None,
            layer: None,
            tolerance: 1e-3,
            offset: DVec2::ZERO,
        }
    }

    #[test]
    fn the_fill_rule_makes_holes() {
        use FillRule::*;
        let one = Unit::Decade(0);
        // Even-odd: the inner square is a hole whatever its direction.
        for ccw in [true, false] {
            let s = section(
                vec![
                    square(0.0, 4.0, true, 0, EvenOdd),
                    square(1.0, 1.0, ccw, 0, EvenOdd),
                ],
                one,
                &req(),
            )
            .unwrap();
            assert_eq!(s.holes.len(), 1);
            assert_eq!(s.outline[1], DVec2::new(4.0, 0.0));
        }
        // Non-zero: only a loop turning the other way cuts a hole; one
        // turning the same way bounds nothing.
        let s = section(
            vec![
                square(0.0, 4.0, true, 0, NonZero),
                square(1.0, 1.0, false, 0, NonZero),
            ],
            one,
            &req(),
        )
        .unwrap();
        assert_eq!(s.holes.len(), 1);
        let s = section(
            vec![
                square(0.0, 4.0, true, 0, NonZero),
                square(1.0, 1.0, true, 0, NonZero),
            ],
            one,
            &req(),
        )
        .unwrap();
        assert!(s.holes.is_empty());
        // Loops of two elements fill separately: two outlines.
        let e = section(
            vec![
                square(0.0, 4.0, true, 0, NonZero),
                square(1.0, 1.0, false, 1, NonZero),
            ],
            one,
            &req(),
        )
        .unwrap_err();
        assert!(
            e.contains("2 separate outlines (square 0, square 1)"),
            "{e}"
        );
        // Crossing loops are refused, naming both.
        let e = section(
            vec![
                square(0.0, 4.0, true, 0, EvenOdd),
                square(3.0, 2.0, true, 0, EvenOdd),
            ],
            one,
            &req(),
        )
        .unwrap_err();
        assert!(e.contains("square 0 and square 3 cross"), "{e}");
    }
}
