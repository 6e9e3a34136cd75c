//! DXF sections: closed LWPOLYLINEs and POLYLINEs (straight or bulged
//! segments), CIRCLEs, and chains of LINEs, ARCs and open polylines that
//! meet end to end, read with the `dxf` crate. Loops nest: the region
//! inside an odd number of them is the section.

use dxf::entities::{Entity, EntityType};
use dxf::enums::Units;
use dxf::Drawing;
use glam::DVec2;
use std::path::Path;

use super::{ellipse, list, pieces, push, unit, FillRule, Loop, Request, Unit};

pub(super) fn read(file: &Path, req: &Request) -> Result<(Unit, Vec<Loop>), String> {
    let drawing = Drawing::load_file(file)
        .map_err(|e| format!("{} is not a readable DXF drawing: {e}", file.display()))?;
    let unit = unit(req, stated(drawing.header.default_drawing_units))?;
    let tol = req.tolerance / unit.metres();
    let mut loops = Vec::new();
    let mut open: Vec<Piece> = Vec::new();
    let mut layers: Vec<String> = Vec::new();
    for e in drawing.entities() {
        if e.common.is_in_paper_space {
            continue;
        }
        if !layers.contains(&e.common.layer) {
            layers.push(e.common.layer.clone());
        }
        if req.layer.is_some_and(|l| l != e.common.layer) {
            continue;
        }
        // Annotations draw no outline.
        if matches!(
            e.specific,
            EntityType::Text(_)
                | EntityType::MText(_)
                | EntityType::RotatedDimension(_)
                | EntityType::RadialDimension(_)
                | EntityType::DiameterDimension(_)
                | EntityType::AngularThreePointDimension(_)
                | EntityType::OrdinateDimension(_)
                | EntityType::Leader(_)
                | EntityType::ModelPoint(_)
        ) {
            continue;
        }
        let name = name(e);
        let mut closed = |points: Vec<DVec2>| {
            loops.push(Loop {
                element: name.clone(),
                group: 0,
                rule: FillRule::EvenOdd,
                points,
            })
        };
        match &e.specific {
            EntityType::LwPolyline(p) => {
                let v: Vec<(DVec2, f64)> = p
                    .vertices
                    .iter()
                    .map(|v| (DVec2::new(v.x, v.y), v.bulge))
                    .collect();
                let points = bulged(&v, p.is_closed(), tol);
                let points = mirrored(points, p.extrusion_direction.z);
                if p.is_closed() {
                    closed(points);
                } else {
                    open.push(Piece { name, points });
                }
            }
            EntityType::Polyline(p) => {
                if p.is_3d_polygon_mesh() || p.is_polyface_mesh() {
                    return Err(format!("{name}: a mesh is no outline"));
                }
                let v: Vec<(DVec2, f64)> = p
                    .vertices()
                    .map(|v| (DVec2::new(v.location.x, v.location.y), v.bulge))
                    .collect();
                let points = mirrored(bulged(&v, p.is_closed(), tol), p.normal.z);
                if p.is_closed() {
                    closed(points);
                } else {
                    open.push(Piece { name, points });
                }
            }
            EntityType::Circle(c) => {
                let centre = DVec2::new(c.center.x, c.center.y);
                let points = ellipse(centre, DVec2::splat(c.radius), tol, |p| p);
                closed(mirrored(points, c.normal.z));
            }
            EntityType::Line(l) => open.push(Piece {
                name,
                points: vec![DVec2::new(l.p1.x, l.p1.y), DVec2::new(l.p2.x, l.p2.y)],
            }),
            EntityType::Arc(a) => {
                let centre = DVec2::new(a.center.x, a.center.y);
                let (from, to) = (a.start_angle.to_radians(), a.end_angle.to_radians());
                let mut sweep = to - from;
                if sweep <= 0.0 {
                    sweep += std::f64::consts::TAU;
                }
                let at = |t: f64| centre + a.radius * DVec2::new(t.cos(), t.sin());
                let mut points = vec![at(from)];
                let n = pieces(sweep, a.radius, tol);
                for k in 1..=n {
                    push(&mut points, at(from + sweep * k as f64 / n as f64));
                }
                open.push(Piece {
                    name,
                    points: mirrored(points, a.normal.z),
                });
            }
            EntityType::Insert(_) => {
                return Err(format!(
                    "{name}: a block reference is not read; explode it into its entities"
                ))
            }
            _ => {
                return Err(format!(
                    "{name} is not read as an outline; draw the outline with LWPOLYLINE, POLYLINE, LINE, ARC and CIRCLE (a spline or an ellipse converted to a polyline)"
                ))
            }
        }
    }
    if let Some(l) = req.layer {
        if !layers.iter().any(|x| x == l) {
            return Err(format!(
                "no layer '{l}' in {} (it has {})",
                file.display(),
                list(layers.iter().map(|x| format!("'{x}'")))
            ));
        }
    }
    loops.extend(chains(open, tol / 100.0)?);
    Ok((unit, loops))
}

/// The length a DXF drawing's $INSUNITS names.
fn stated(units: Units) -> Result<Unit, String> {
    use Unit::{Decade, Times};
    Ok(match units {
        Units::Unitless => {
            return Err("the drawing states no unit ($INSUNITS is 0, unitless)".into());
        }
        Units::Inches => Times(0.0254),
        Units::Feet => Times(0.3048),
        Units::Miles => Times(1609.344),
        Units::Millimeters => Decade(-3),
        Units::Centimeters => Decade(-2),
        Units::Meters => Decade(0),
        Units::Kilometers => Decade(3),
        Units::Microinches => Times(0.0254e-6),
        Units::Mils => Times(0.0254e-3),
        Units::Yards => Times(0.9144),
        Units::Angstroms => Decade(-10),
        Units::Nanometers => Decade(-9),
        Units::Microns => Decade(-6),
        Units::Decimeters => Decade(-1),
        Units::Decameters => Decade(1),
        Units::Hectometers => Decade(2),
        Units::Gigameters => Decade(9),
        Units::USSurveyFeet => Times(1200.0 / 3937.0),
        Units::USSurveyInch => Times(100.0 / 3937.0),
        Units::USSurveyYard => Times(3600.0 / 3937.0),
        Units::USSurveyMile => Times(6_336_000.0 / 3937.0),
        other => {
            return Err(format!(
                "the drawing's unit ({other:?}) is no length for a solid"
            ))
        }
    })
}

/// "LWPOLYLINE (handle 2F, layer 'plate')".
fn name(e: &Entity) -> String {
    let kind = match &e.specific {
        EntityType::LwPolyline(_) => "LWPOLYLINE".to_string(),
        EntityType::Polyline(_) => "POLYLINE".to_string(),
        EntityType::Line(_) => "LINE".to_string(),
        EntityType::Arc(_) => "ARC".to_string(),
        EntityType::Circle(_) => "CIRCLE".to_string(),
        // Any other kind is named only in its error: its variant's name.
        other => format!("{other:?}")
            .split(['(', ' ', '{'])
            .next()
            .unwrap_or("entity")
            .to_ascii_uppercase(),
    };
    format!(
        "{kind} (handle {}, layer '{}')",
        e.common.handle.as_string(),
        e.common.layer
    )
}

/// An entity drawn with its extrusion along −z lies in a mirrored plane:
/// its x runs the other way (the DXF arbitrary-axis rule).
fn mirrored(mut points: Vec<DVec2>, z: f64) -> Vec<DVec2> {
    if z < 0.0 {
        points.iter_mut().for_each(|p| p.x = -p.x);
    }
    points
}

/// A polyline's points, each bulged segment (bulge = tan of a quarter of
/// the arc's angle, positive counter-clockwise) cut into chords. The
/// vertices themselves are kept exactly.
fn bulged(v: &[(DVec2, f64)], closed: bool, tol: f64) -> Vec<DVec2> {
    let mut out = Vec::with_capacity(v.len());
    let segments = if closed {
        v.len()
    } else {
        v.len().saturating_sub(1)
    };
    if let Some(&(p, _)) = v.first() {
        out.push(p);
    }
    for k in 0..segments {
        let ((a, bulge), (b, _)) = (v[k], v[(k + 1) % v.len()]);
        if bulge != 0.0 && a != b {
            let chord = b - a;
            let len = chord.length();
            let angle = 4.0 * bulge.atan();
            let radius = len / (2.0 * (angle / 2.0).sin()).abs();
            // From the chord's middle to the centre, on the left of the
            // chord for a counter-clockwise arc less than half a turn.
            let sagitta = bulge.abs() * len / 2.0;
            let left = DVec2::new(-chord.y, chord.x) / len;
            let centre = 0.5 * (a + b) + left * (radius - sagitta) * bulge.signum();
            let from = (a - centre).y.atan2((a - centre).x);
            let n = pieces(angle.abs(), radius, tol);
            for i in 1..n {
                let t = from + angle * i as f64 / n as f64;
                push(&mut out, centre + radius * DVec2::new(t.cos(), t.sin()));
            }
        }
        push(&mut out, b);
    }
    out
}

/// An open entity, to be joined end to end with others.
struct Piece {
    name: String,
    points: Vec<DVec2>,
}

/// Join open pieces whose ends lie within `join` of each other into
/// closed loops, in the file's order; a piece nothing continues is an
/// open outline.
fn chains(mut open: Vec<Piece>, join: f64) -> Result<Vec<Loop>, String> {
    let mut loops = Vec::new();
    open.reverse();
    while let Some(first) = open.pop() {
        let mut points = first.points;
        let mut names = vec![first.name];
        loop {
            let (start, end) = (points[0], *points.last().expect("a piece has points"));
            if points.len() > 2 && start.distance(end) <= join {
                points.pop();
                break;
            }
            let next = open.iter().rposition(|p| {
                p.points[0].distance(end) <= join
                    || p.points.last().expect("a piece has points").distance(end) <= join
            });
            let Some(k) = next else {
                return Err(format!(
                    "{}: the outline is open: it ends at ({}, {}) where nothing continues it",
                    joined(names),
                    end.x,
                    end.y
                ));
            };
            let mut p = open.remove(k);
            if p.points[0].distance(end) > join {
                p.points.reverse();
            }
            points.extend_from_slice(&p.points[1..]);
            names.push(p.name);
        }
        loops.push(Loop {
            element: joined(names),
            group: 0,
            rule: FillRule::EvenOdd,
            points,
        });
    }
    Ok(loops)
}

/// A chain's name: its first piece's, and how many follow.
fn joined(mut names: Vec<String>) -> String {
    match names.len() {
        1 => names.remove(0),
        n => format!("{} and {} more joined to it", names[0], n - 1),
    }
}
