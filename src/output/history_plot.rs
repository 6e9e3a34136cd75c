//! `history.png`: each probe of `history.csv` against time, one panel a
//! probe with its unit, so that a run ends in a picture.

use std::path::Path;

use crate::output::History;
use crate::plot::{panel_plot, Figure, PlotError, Series, Style};
use crate::scene::{BodyQuantity, ContactQuantity, EnergyQuantity, ParticleQuantity, Probe, Scene};

/// At most this many panels (the first probes): a taller picture is not
/// read.
pub const MAX_PANELS: usize = 12;

/// The unit of a probe's values in a scene of `dim` dimensions (bodies of
/// a 2-D scene are per metre of depth, of a 1-D one per square metre of
/// cross-section).
pub fn unit(probe: &Probe, dim: u32) -> &'static str {
    let per = |two: &'static str, one: &'static str| if dim == 1 { one } else { two };
    match probe {
        Probe::Particle { quantity, .. } => match quantity {
            ParticleQuantity::PositionX | ParticleQuantity::PositionY => "m",
            ParticleQuantity::VelocityX | ParticleQuantity::VelocityY => "m/s",
            ParticleQuantity::Density => "kg/m³",
            ParticleQuantity::Pressure
            | ParticleQuantity::StressXx
            | ParticleQuantity::StressYy
            | ParticleQuantity::StressXy
            | ParticleQuantity::StressZz
            | ParticleQuantity::VonMises => "Pa",
            ParticleQuantity::InternalEnergy => "J/kg",
            ParticleQuantity::PlasticStrain | ParticleQuantity::Damage => "1",
            ParticleQuantity::Temperature => "K",
            ParticleQuantity::FailureTime => "s",
        },
        Probe::Body { quantity, .. } => match quantity {
            BodyQuantity::VelocityX | BodyQuantity::VelocityY => "m/s",
            BodyQuantity::PositionX | BodyQuantity::PositionY => "m",
            BodyQuantity::KineticEnergy => per("J/m", "J/m²"),
            BodyQuantity::MomentumX | BodyQuantity::MomentumY => per("kg/s", "kg/(m s)"),
            BodyQuantity::AngularVelocity => "rad/s",
        },
        Probe::Contact { quantity, .. } => match quantity {
            ContactQuantity::Force => per("N/m", "N/m²"),
            ContactQuantity::PressureMax => "Pa",
            ContactQuantity::TangentialForce => per("N/m", "N/m²"),
            ContactQuantity::SlipRate => "m/s",
        },
        Probe::Energy { quantity, .. } => match quantity {
            EnergyQuantity::Kinetic
            | EnergyQuantity::Internal
            | EnergyQuantity::ContactHeat
            | EnergyQuantity::FrictionHeat
            | EnergyQuantity::ArtificialDissipation
            | EnergyQuantity::Potential
            | EnergyQuantity::Total => per("J/m", "J/m²"),
        },
        Probe::Constraint { .. } => per("N/m", "N/m²"),
    }
}

/// The time axis's unit for a run ending at `end` s: its label and scale.
fn time_axis(end: f64) -> (&'static str, f64) {
    if end < 1e-3 {
        ("time (µs)", 1e6)
    } else if end < 1.0 {
        ("time (ms)", 1e3)
    } else {
        ("time (s)", 1.0)
    }
}

/// The panels of `history`'s probes (at most [`MAX_PANELS`]).
pub fn panels(scene: &Scene, history: &History) -> Vec<Figure> {
    let (x_label, scale) = time_axis(scene.simulation.end_time);
    scene
        .probes
        .iter()
        .take(MAX_PANELS)
        .filter_map(|p| {
            let values = history.column(p.name())?;
            let mut fig = Figure::new(
                "",
                x_label,
                &format!("{} ({})", p.name(), unit(p, scene.simulation.dimension)),
            );
            fig.height = 300;
            fig.series.push(Series {
                label: p.name().to_string(),
                points: history
                    .times
                    .iter()
                    .zip(values)
                    .map(|(t, v)| (t * scale, v))
                    .collect(),
                style: Style::Solid,
                color: None,
                exact: false,
            });
            Some(fig)
        })
        .collect()
}

/// Draws `history.png` in `dir` (nothing for a scene without probes or a
/// history without rows).
pub fn write(dir: &Path, scene: &Scene, history: &History) -> Result<(), PlotError> {
    let figs = panels(scene, history);
    if figs.is_empty() || history.times.is_empty() {
        return Ok(());
    }
    panel_plot(&dir.join("history.png"), &figs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Forces and energies of a body are per metre of depth in 2-D and per
    /// square metre of section in 1-D; particle quantities have their own.
    #[test]
    fn units_follow_the_dimension() {
        let force = Probe::Contact {
            name: "f".into(),
            bodies: ["a".into(), "b".into()],
            quantity: ContactQuantity::Force,
        };
        assert_eq!((unit(&force, 2), unit(&force, 1)), ("N/m", "N/m²"));
        let energy = Probe::Energy {
            name: "e".into(),
            quantity: EnergyQuantity::Total,
        };
        assert_eq!((unit(&energy, 2), unit(&energy, 1)), ("J/m", "J/m²"));
        let t = Probe::Particle {
            name: "t".into(),
            body: "a".into(),
            at: vec![0.0, 0.0],
            quantity: ParticleQuantity::Temperature,
        };
        assert_eq!(unit(&t, 2), "K");
        assert_eq!(time_axis(2e-5), ("time (µs)", 1e6));
        assert_eq!(time_axis(0.02), ("time (ms)", 1e3));
    }
}
