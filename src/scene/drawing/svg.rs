//! SVG sections: `path`, `polygon`, `polyline`, `rect`, `circle` and
//! `ellipse` elements, in groups and under transforms, read with roxmltree
//! and svgtypes. The page's y axis points down; the scene's points up, so
//! y is negated and the section stands as drawn.

use glam::DVec2;
use roxmltree::{Document, Node, ParsingOptions};
use svgtypes::{Length, LengthUnit, SimplePathSegment, SimplifyingPathParser, ViewBox};

use super::{cubic, ellipse, elliptic, list, push, quadratic, unit, FillRule, Loop, Request, Unit};

const SVG: &str = "http://www.w3.org/2000/svg";
const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";

/// Elements that draw nothing themselves and whose content is drawn
/// only where referenced.
const UNDRAWN: [&str; 14] = [
    "defs",
    "clipPath",
    "mask",
    "symbol",
    "marker",
    "pattern",
    "linearGradient",
    "radialGradient",
    "filter",
    "style",
    "script",
    "title",
    "desc",
    "metadata",
];

/// Elements that draw no outline: annotations and pictures.
const NOT_OUTLINES: [&str; 5] = ["text", "image", "foreignObject", "tspan", "textPath"];

/// An affine map `(a x + c y + e, b x + d y + f)`; `None` is the
/// identity, kept apart so that untransformed figures pass unchanged.
type Affine = Option<svgtypes::Transform>;

fn then(outer: Affine, inner: svgtypes::Transform) -> Affine {
    Some(match outer {
        None => inner,
        Some(o) => svgtypes::Transform::new(
            o.a * inner.a + o.c * inner.b,
            o.b * inner.a + o.d * inner.b,
            o.a * inner.c + o.c * inner.d,
            o.b * inner.c + o.d * inner.d,
            o.a * inner.e + o.c * inner.f + o.e,
            o.b * inner.e + o.d * inner.f + o.f,
        ),
    })
}

fn map(t: Affine, p: DVec2) -> DVec2 {
    match t {
        None => p,
        Some(t) => DVec2::new(t.a * p.x + t.c * p.y + t.e, t.b * p.x + t.d * p.y + t.f),
    }
}

/// An upper bound of how much `t` stretches a length.
fn stretch(t: Affine) -> f64 {
    t.map_or(1.0, |t| {
        (t.a * t.a + t.b * t.b + t.c * t.c + t.d * t.d).sqrt()
    })
}

struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    /// The tolerance in the page's user units.
    tolerance: f64,
    layer: Option<&'a str>,
    found_layer: bool,
    loops: Vec<Loop>,
    groups: usize,
}

pub(super) fn read(text: &str, req: &Request) -> Result<(Unit, Vec<Loop>), String> {
    let options = ParsingOptions {
        allow_dtd: true,
        ..ParsingOptions::default()
    };
    let doc = Document::parse_with_options(text, options)
        .map_err(|e| format!("{} is not readable XML: {e}", req.file.display()))?;
    let root = doc.root_element();
    if !root.has_tag_name((SVG, "svg")) {
        return Err(format!(
            "{} is not an SVG drawing: its root element is <{}>",
            req.file.display(),
            root.tag_name().name()
        ));
    }
    let unit = unit(req, page_unit(root))?;
    let mut r = Reader {
        doc: &doc,
        tolerance: req.tolerance / unit.metres(),
        layer: req.layer,
        found_layer: false,
        loops: Vec::new(),
        groups: 0,
    };
    r.children(root, None, FillRule::NonZero, req.layer.is_none())?;
    if let Some(layer) = req.layer {
        if !r.found_layer {
            let names = doc
                .descendants()
                .filter(|n| n.is_element())
                .flat_map(|n| [n.attribute("id"), n.attribute((INKSCAPE, "label"))])
                .flatten()
                .map(|s| format!("'{s}'"));
            return Err(format!(
                "no element with id or label '{layer}' in {} (it has {})",
                req.file.display(),
                list(names)
            ));
        }
    }
    // The page's y runs down the page.
    for l in &mut r.loops {
        for p in &mut l.points {
            p.y = -p.y;
        }
    }
    Ok((unit, r.loops))
}

/// The length of the page's user unit: the `<svg>` element's width (with
/// a unit of length) over its viewBox's width.
fn page_unit(root: Node) -> Result<Unit, String> {
    let width = root
        .attribute("width")
        .ok_or("the <svg> element has no width, so the drawing states no unit")?;
    let length: Length = width
        .parse()
        .map_err(|_| format!("the <svg> width '{width}' is not a length"))?;
    let unit = match length.unit {
        LengthUnit::Mm => Unit::Decade(-3),
        LengthUnit::Cm => Unit::Decade(-2),
        LengthUnit::In => Unit::Times(0.0254),
        LengthUnit::Pt => Unit::Times(0.0254 / 72.0),
        LengthUnit::Pc => Unit::Times(0.0254 / 6.0),
        LengthUnit::None | LengthUnit::Px => {
            return Err(format!(
                "the <svg> width '{width}' is in pixels, which are no length"
            ))
        }
        LengthUnit::Em | LengthUnit::Ex | LengthUnit::Percent => {
            return Err(format!("unknown unit in the <svg> width '{width}'"))
        }
    };
    Ok(match root.attribute("viewBox") {
        Some(v) => {
            let vb: ViewBox = v
                .parse()
                .map_err(|_| format!("the <svg> viewBox '{v}' is not four numbers"))?;
            unit.times(length.number / vb.w)
        }
        // Without a viewBox a user unit is a CSS pixel, 1/96 in.
        None => Unit::Times(0.0254 / 96.0),
    })
}

/// A presentation property from the attribute or the `style` list.
fn property<'a>(n: Node<'a, '_>, name: &str) -> Option<&'a str> {
    let styled = n.attribute("style").and_then(|s| {
        s.split(';').find_map(|d| {
            let (k, v) = d.split_once(':')?;
            (k.trim() == name).then(|| v.trim())
        })
    });
    styled.or_else(|| n.attribute(name))
}

impl Reader<'_, '_> {
    fn name(&self, n: Node) -> String {
        let tag = n.tag_name().name();
        match n.attribute("id") {
            Some(id) => format!("<{tag} id=\"{id}\">"),
            None => format!(
                "<{tag}> (line {})",
                self.doc.text_pos_at(n.range().start).row
            ),
        }
    }

    fn children(&mut self, n: Node, t: Affine, rule: FillRule, on: bool) -> Result<(), String> {
        for c in n.children().filter(|c| c.is_element()) {
            self.element(c, t, rule, on)?;
        }
        Ok(())
    }

    fn element(&mut self, n: Node, t: Affine, rule: FillRule, on: bool) -> Result<(), String> {
        if n.tag_name().namespace() != Some(SVG)
            || UNDRAWN.contains(&n.tag_name().name())
            || property(n, "display") == Some("none")
        {
            return Ok(());
        }
        let picked = self.layer.is_some_and(|l| {
            n.attribute("id") == Some(l) || n.attribute((INKSCAPE, "label")) == Some(l)
        });
        self.found_layer |= picked;
        let on = on || picked;
        let t = match n.attribute("transform") {
            Some(s) => then(
                t,
                s.parse()
                    .map_err(|_| format!("{}: cannot read its transform '{s}'", self.name(n)))?,
            ),
            None => t,
        };
        let rule = match property(n, "fill-rule") {
            Some("evenodd") => FillRule::EvenOdd,
            Some("nonzero") => FillRule::NonZero,
            _ => rule,
        };
        let tag = n.tag_name().name();
        match tag {
            "g" | "a" | "switch" => return self.children(n, t, rule, on),
            _ if !on || NOT_OUTLINES.contains(&tag) => return Ok(()),
            "svg" => {
                return Err(format!(
                    "{}: a drawing nested in the drawing is not read; ungroup it",
                    self.name(n)
                ))
            }
            "use" => {
                return Err(format!(
                    "{}: a clone is not read; unlink it into a path",
                    self.name(n)
                ))
            }
            "line" => {
                return Err(format!(
                    "{}: a single line encloses nothing; draw the outline as one closed path",
                    self.name(n)
                ))
            }
            _ => {}
        }
        let loops = match tag {
            "path" => self.path(n, t)?,
            "polygon" | "polyline" => self.points(n, t)?,
            "rect" => vec![self.rect(n, t)?],
            "circle" | "ellipse" => vec![self.ellipse(n, t)?],
            other => {
                return Err(format!(
                    "{}: a <{other}> element is not read as an outline",
                    self.name(n)
                ))
            }
        };
        let group = self.groups;
        self.groups += 1;
        let element = self.name(n);
        self.loops
            .extend(loops.into_iter().enumerate().map(|(k, points)| Loop {
                element: if k == 0 {
                    element.clone()
                } else {
                    format!("{element} (subpath {})", k + 1)
                },
                group,
                rule,
                points,
            }));
        Ok(())
    }

    fn open(&self, n: Node, k: usize, points: &[DVec2]) -> String {
        let (a, b) = (points[0], points[points.len() - 1]);
        format!(
            "{}: the outline{} is open: it ends at ({}, {}), not where it starts, ({}, {}); close it (Z)",
            self.name(n),
            if k > 0 { format!(" (subpath {})", k + 1) } else { String::new() },
            b.x,
            b.y,
            a.x,
            a.y
        )
    }

    fn path(&self, n: Node, t: Affine) -> Result<Vec<Vec<DVec2>>, String> {
        let d = n.attribute("d").unwrap_or("");
        let mut loops: Vec<Vec<DVec2>> = Vec::new();
        let mut current: Vec<DVec2> = Vec::new();
        let mut closed = false;
        let tol = self.tolerance;
        let finish = |loops: &mut Vec<Vec<DVec2>>, current: &mut Vec<DVec2>, closed: bool| {
            if current.len() > 1 && !closed && current.first() != current.last() {
                return Err(self.open(n, loops.len(), current));
            }
            if current.len() > 1 {
                loops.push(std::mem::take(current));
            }
            current.clear();
            Ok(())
        };
        for seg in SimplifyingPathParser::from(d) {
            let seg =
                seg.map_err(|e| format!("{}: cannot read its path data: {e}", self.name(n)))?;
            let p = |x: f64, y: f64| map(t, DVec2::new(x, y));
            match seg {
                SimplePathSegment::MoveTo { x, y } => {
                    finish(&mut loops, &mut current, closed)?;
                    closed = false;
                    current.push(p(x, y));
                }
                SimplePathSegment::LineTo { x, y } => push(&mut current, p(x, y)),
                SimplePathSegment::CurveTo {
                    x1,
                    y1,
                    x2,
                    y2,
                    x,
                    y,
                } => cubic(&mut current, p(x1, y1), p(x2, y2), p(x, y), tol),
                SimplePathSegment::Quadratic { x1, y1, x, y } => {
                    quadratic(&mut current, p(x1, y1), p(x, y), tol)
                }
                SimplePathSegment::ClosePath => closed = true,
            }
        }
        finish(&mut loops, &mut current, closed)?;
        Ok(loops)
    }

    fn points(&self, n: Node, t: Affine) -> Result<Vec<Vec<DVec2>>, String> {
        let points: Vec<DVec2> = svgtypes::PointsParser::from(n.attribute("points").unwrap_or(""))
            .map(|(x, y)| map(t, DVec2::new(x, y)))
            .collect();
        if n.tag_name().name() == "polyline" && points.first() != points.last() {
            return Err(self.open(n, 0, &points));
        }
        Ok(vec![points])
    }

    /// A coordinate attribute in user units (0 when absent).
    fn number(&self, n: Node, key: &str) -> Result<f64, String> {
        let Some(s) = n.attribute(key) else {
            return Ok(0.0);
        };
        match s.parse::<Length>() {
            Ok(l) if matches!(l.unit, LengthUnit::None | LengthUnit::Px) => Ok(l.number),
            _ => Err(format!(
                "{}: its {key} '{s}' is not a number of user units",
                self.name(n)
            )),
        }
    }

    fn rect(&self, n: Node, t: Affine) -> Result<Vec<DVec2>, String> {
        let [x, y, w, h] = ["x", "y", "width", "height"].map(|k| self.number(n, k));
        let (x, y, w, h) = (x?, y?, w?, h?);
        // A radius not given takes the other's (0 when neither is).
        let key = |k: &'static str, other: &'static str| match n.has_attribute(k) {
            true => k,
            false => other,
        };
        let (rx, ry) = (
            self.number(n, key("rx", "ry"))?,
            self.number(n, key("ry", "rx"))?,
        );
        let (rx, ry) = (rx.min(w / 2.0), ry.min(h / 2.0));
        if rx <= 0.0 || ry <= 0.0 {
            return Ok([(x, y), (x + w, y), (x + w, y + h), (x, y + h)]
                .map(|(x, y)| map(t, DVec2::new(x, y)))
                .to_vec());
        }
        use std::f64::consts::{FRAC_PI_2, PI};
        let tol = self.tolerance / stretch(t);
        let radii = DVec2::new(rx, ry);
        // Each corner's quarter arc, joined by the straight sides.
        let mut out = Vec::new();
        for (c, from) in [
            (DVec2::new(x + w - rx, y + ry), -FRAC_PI_2),
            (DVec2::new(x + w - rx, y + h - ry), 0.0),
            (DVec2::new(x + rx, y + h - ry), FRAC_PI_2),
            (DVec2::new(x + rx, y + ry), PI),
        ] {
            push(
                &mut out,
                map(t, c + radii * DVec2::new(from.cos(), from.sin())),
            );
            elliptic(&mut out, c, radii, (from, FRAC_PI_2), tol, |p| map(t, p));
        }
        Ok(out)
    }

    fn ellipse(&self, n: Node, t: Affine) -> Result<Vec<DVec2>, String> {
        let c = DVec2::new(self.number(n, "cx")?, self.number(n, "cy")?);
        let radii = if n.tag_name().name() == "circle" {
            DVec2::splat(self.number(n, "r")?)
        } else {
            DVec2::new(self.number(n, "rx")?, self.number(n, "ry")?)
        };
        if radii.x <= 0.0 || radii.y <= 0.0 {
            return Err(format!("{}: its radius is not positive", self.name(n)));
        }
        Ok(ellipse(c, radii, self.tolerance / stretch(t), |p| {
            map(t, p)
        }))
    }
}
