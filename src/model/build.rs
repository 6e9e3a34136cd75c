//! Building the model and the initial state from a scene.

use super::*;

impl Model {
    /// Whether supports adapt within a band (`Model::band` not none): the
    /// state then carries each particle's ellipse besides its support
    /// ([`State::carried`]).
    #[inline]
    pub fn carries_band(&self) -> bool {
        self.adaptive && !self.band.is_none()
    }

    /// The supports the carried ellipses `carried` give within the band
    /// ([`Metric::banded`]), or none (round supports, [`State::metric`])
    /// while every one of them is round: a scene whose supports stay
    /// inside the band runs the round kernel's code.
    pub fn supports_of(&self, carried: &[Metric], out: &mut Vec<Metric>) {
        use rayon::prelude::*;
        out.clear();
        out.par_extend(
            carried
                .par_iter()
                .enumerate()
                .map(|(i, c)| c.banded(self.h[i], self.band, self.dim)),
        );
        let all_round = out
            .par_iter()
            .enumerate()
            .all(|(i, q)| *q == Metric::round(self.h[i]));
        if all_round {
            out.clear();
        }
    }

    /// Build the model and the initial state of a validated scene.
    pub fn new(scene: &Scene) -> (Model, State) {
        let placed = place_bodies(scene);
        let n: usize = placed.iter().map(|p| p.positions.len()).sum();
        let mut model = Model::blank(scene, n, placed.len());
        let mut state = State::blank(n);
        for (bi, (b, p)) in scene.bodies.iter().zip(&placed).enumerate() {
            model.add_body(&mut state, scene, bi, b, p);
        }
        model.hourglass = model.bodies.iter().map(|b| b.hourglass).fold(0.0, f64::max);
        if model.bodies.iter().all(|b| !b.art) {
            model.artificial_stress = None;
        }
        if model.carries_band() {
            state.carried = model.h.iter().map(|&h| Metric::round(h)).collect();
        } else if model.adaptive {
            state.metric = model.h.iter().map(|&h| Metric::round(h)).collect();
        }
        if model.share.iter().all(|&s| s == 1.0) {
            model.share.clear();
            model.on_plane.clear();
        }
        // A particle on the plane is its own mirror image: it moves along it.
        for (i, v) in state.v.iter_mut().enumerate() {
            *v = model.along_plane(i, *v);
        }
        model.finish_held(&mut state);
        model.read_placement(scene, &state);
        model.domain = Model::domain_of(&model, &state, scene.simulation.end_time);
        model.gravity_ref = (0..model.len())
            .filter(|&i| !model.rigid(i))
            .map(|i| state.x[i] * model.mass[i])
            .sum();
        model.energy_guard = Model::guards_energy(&model);
        model.energy_floor = ENERGY_FLOOR
            * (0..model.len())
                .filter(|&i| !model.rigid(i))
                .map(|i| model.mass[i] * model.material(i).c_l.powi(2))
                .sum::<f64>();
        if model.history {
            state.eps_p = vec![0.0; model.len()];
            state.damage = vec![0.0; model.len()];
            state.failed_at = vec![-1.0; model.len()];
            state.temperature = (0..model.len())
                .map(|i| model.material(i).initial_temperature())
                .collect();
        }
        if model.contact {
            // Bodies that start overlapping are pushed apart (entry 0).
            state.entry = vec![0.0; model.len()];
            // The static coefficient is never below the sliding one.
            model.rubs = model.friction.sticking > 0.0
                || model.friction_pairs.iter().any(|p| p.2.sticking > 0.0);
            if model.rubs {
                state.slip = vec![0.0; model.len()];
                state.sliding = vec![false; model.len()];
                state.slip_stiffness = vec![0.0; model.len()];
            }
        }
        (model, state)
    }

    /// The model's scene-wide constants, with room for `n` particles in
    /// `bodies` bodies and nothing placed yet.
    fn blank(scene: &Scene, n: usize, bodies: usize) -> Model {
        let sim = &scene.simulation;
        let av = scene.viscosity();
        let cs = scene.contact_settings();
        let art = scene.artificial_stress.unwrap_or(ArtificialStress::DEFAULT);
        let planes: Vec<_> = scene.symmetry.iter().map(|s| s.mirror()).collect();
        Model {
            dim: scene.dim(),
            interaction: sim.interaction,
            correction: sim.correction,
            cfl: sim.cfl,
            fixed_dt: sim.dt,
            integrator: sim.integrator,
            alpha: av.alpha,
            beta: av.beta,
            av_reconstruct: av.reconstruct,
            av_release: av.form == ViscosityForm::Riemann,
            av_recon_surface: av.reconstruct_surfaces,
            // The bodies' largest, once they are known.
            hourglass: 0.0,
            dispersion: sim.dispersion_correction,
            artificial_stress: Some(art).filter(|a| a.epsilon > 0.0),
            close_scale: Vec::new(),
            boundary_threshold: cs.boundary_threshold,
            bodies: Vec::with_capacity(bodies),
            mass: Vec::with_capacity(n),
            h: Vec::with_capacity(n),
            body: Vec::with_capacity(n),
            offset: Vec::with_capacity(n),
            contact: sim.interaction == Interaction::Penalty && scene.bodies.len() > 1,
            friction: Coulomb {
                sliding: cs.friction,
                sticking: cs.static_friction.unwrap_or(cs.friction),
            },
            friction_pairs: cs
                .pairs
                .iter()
                .map(|p| {
                    let id = |n: &String| {
                        scene
                            .bodies
                            .iter()
                            .position(|b| &b.name == n)
                            .expect("validated: a known body") as u32
                    };
                    let (a, b) = (id(&p.bodies[0]), id(&p.bodies[1]));
                    let mu = Coulomb {
                        sliding: p.friction,
                        sticking: p.static_friction.unwrap_or(p.friction),
                    };
                    (a.min(b), a.max(b), mu)
                })
                .collect(),
            rubs: false,
            contact_dt: f64::INFINITY,
            plastic: false,
            history: false,
            strain_rate: false,
            any_rigid: false,
            domain: [DVec2::ZERO; 2],
            energy_guard: false,
            energy_floor: 0.0,
            axisymmetric: scene.axisymmetric(),
            images: crate::math::Mirror::images(
                scene.axisymmetric().then_some(crate::math::Mirror::AXIS),
                &planes,
            ),
            contact_images: crate::math::Mirror::images(None, &planes),
            planes,
            on_plane: Vec::new(),
            share: Vec::new(),
            adaptive: sim.adaptive(),
            band: sim.band(),
            variational: sim.stress_form == crate::scene::StressForm::Variational,
            area0: Vec::new(),
            gravity: sim
                .gravity
                .as_ref()
                .map(|g| DVec2::new(g[0], g.get(1).copied().unwrap_or(0.0))),
            gravity_ref: DVec2::ZERO,
            held: Vec::new(),
            held_of: Vec::new(),
        }
    }

    /// Place body `bi` (scene body `b`, placed as `p`): its particles'
    /// constants and initial state, and its [`BodyInfo`].
    fn add_body(
        &mut self,
        state: &mut State,
        scene: &Scene,
        bi: usize,
        b: &crate::scene::Body,
        p: &crate::scene::PlacedBody,
    ) {
        let av = scene.viscosity();
        let art = scene.artificial_stress.unwrap_or(ArtificialStress::DEFAULT);
        let material = MaterialModel::new(&scene.materials[&b.material]);
        let mut v0 = DVec2::ZERO;
        if let Some(v) = &b.velocity {
            v0.x = v[0];
            if v.len() > 1 {
                v0.y = v[1];
            }
        }
        let start = self.mass.len();
        let h = scene.simulation.smoothing_ratio * p.spacing;
        for k in 0..p.positions.len() {
            self.mass.push(p.masses[k]);
            self.h.push(h);
            self.body.push(bi as u32);
            // As placed; deep particles off the boundary get a fresh
            // surface's below, once the boundary is known.
            self.offset.push(p.offsets[k]);
            state.x.push(p.positions[k]);
            state.v.push(p.velocities.get(k).copied().unwrap_or(v0));
            state
                .rho
                .push(self.state_rho(material.rho0, p.positions[k]));
            if self.axisymmetric {
                self.area0
                    .push(p.masses[k] / state.rho[state.rho.len() - 1]);
            }
            if !self.planes.is_empty() {
                // Its own image: on a plane, placed with half its mass
                // (on two, a quarter).
                let x = p.positions[k];
                let on = self
                    .planes
                    .iter()
                    .filter(|m| m.point(x) == x)
                    .fold(0u8, |b, m| {
                        b | u8::from(m.flip[0]) | u8::from(m.flip[1]) << 1
                    });
                self.on_plane.push(on);
                self.share.push(0.5f64.powi(on.count_ones() as i32));
            }
        }
        let yields = !b.rigid && material.y0.is_finite();
        self.plastic |= yields;
        self.history |= !b.rigid && material.has_history();
        self.strain_rate |= !b.rigid && (material.strength.is_some() || material.failure.is_some());
        self.any_rigid |= b.rigid;
        // A body that can yield takes the hourglass control in place of
        // the artificial stress where the scene says so.
        let keyed = yields && art.plastic == ArtPlastic::Hourglass;
        let range = start..self.mass.len();
        let mass: f64 = self.mass[range.clone()].iter().sum();
        let moment: DVec2 = range.clone().map(|i| state.x[i] * self.mass[i]).sum();
        self.bodies.push(BodyInfo {
            name: b.name.clone(),
            material,
            rigid: b.rigid,
            spacing: p.spacing,
            range: range.clone(),
            velocity0: v0,
            debris_neighbours: 0,
            art: !keyed,
            hourglass: if keyed {
                art.plastic_hourglass
            } else {
                av.hourglass
            },
            centre0: if mass > 0.0 {
                moment / mass
            } else {
                DVec2::ZERO
            },
        });
        self.add_held(b, range, &state.x);
    }

    /// What the particles as placed in `state` set: the contact's step and
    /// surface offsets, the debris floor, the close-pair gate's scales.
    fn read_placement(&mut self, scene: &Scene, state: &State) {
        let floor = match scene.simulation.correction {
            Correction::Gradient => crate::physics::kernel::debris_neighbours(
                self.dim,
                scene.simulation.smoothing_ratio,
            ),
            _ => 0,
        };
        let close = self
            .artificial_stress
            .is_some_and(|a| a.pairs == ArtPairs::Close);
        // One walk of the placed particles serves the debris floor, the
        // close-pair gate's scales and the contact's surface offsets.
        let hoods = if floor > 0 || close || self.contact {
            self.placed_neighbourhoods(&state.x)
        } else {
            Vec::new()
        };
        if self.contact {
            self.contact_dt = self.contact_step();
            for (i, n) in hoods.iter().enumerate() {
                let b = self.body[i] as usize;
                self.offset[i] = crate::physics::penalty::surface_offset(
                    self.offset[i],
                    self.bodies[b].spacing,
                    scene.bodies[b].jitter.unwrap_or(0.0),
                    self.dim,
                    n.hg > self.boundary_threshold,
                );
            }
        }
        if floor > 0 {
            let fewest = self.fewest_neighbours(&hoods);
            for (b, n) in self.bodies.iter_mut().zip(fewest) {
                b.debris_neighbours = if b.rigid { 0 } else { floor.min(n) };
            }
        }
        if close {
            let k2 = self.close_scales_of(&hoods);
            // All 1 (a square lattice): the gate needs none of them.
            if k2.iter().any(|&k| k < 1.0) {
                self.close_scale = k2;
            }
        }
    }

    /// The longest step the penalty spring allows over every pair of
    /// bodies and both sides ([`Model::contact_dt`]).
    fn contact_step(&self) -> f64 {
        let m = |b: &BodyInfo| {
            if b.rigid {
                f64::INFINITY
            } else {
                b.material.m
            }
        };
        let mut dt = f64::INFINITY;
        for (i, a) in self.bodies.iter().enumerate() {
            for (j, b) in self.bodies.iter().enumerate() {
                if i != j {
                    dt = dt.min(crate::physics::penalty::contact_step(
                        a.spacing,
                        a.material.rho0,
                        m(a),
                        b.spacing,
                        m(b),
                    ));
                }
            }
        }
        dt
    }

    /// For each particle at positions `x`, from one walk of its own body's
    /// neighbours: the squared distance to the nearest one and how many lie
    /// within `2h` (coincident ones and mirror images excluded), and
    /// `h |∇ψ⁰|`, the colour gradient with the reference volumes that the
    /// boundary test reads (docs/method.md §8.1; in a body of revolution
    /// with the images across the axis, as the solver's test has them, so
    /// that the axis reads as no surface).
    fn placed_neighbourhoods(&self, x: &[DVec2]) -> Vec<Neighbourhood> {
        use rayon::prelude::*;
        let reach = 2.0 * self.h.iter().cloned().fold(0.0, f64::max);
        let cells = crate::math::cells::CellList::build(x, reach);
        (0..self.len())
            .into_par_iter()
            .map(|i| {
                let (mut nearest, mut n) = (f64::INFINITY, 0);
                let mut g = DVec2::ZERO;
                let r2 = 4.0 * self.h[i] * self.h[i];
                cells.for_each_near(x[i], self.dim, |j| {
                    if self.body[j] != self.body[i] {
                        return;
                    }
                    let inv_h = 2.0 / (self.h[i] + self.h[j]);
                    let mut add = |d: DVec2| {
                        let d2 = d.length_squared();
                        if let Some((_, gw)) =
                            crate::physics::kernel::w_grad(self.dim, d, d2, inv_h)
                        {
                            g -= gw * self.reference_volume(j);
                        }
                    };
                    // The images across the axis of a body of revolution
                    // or a symmetry plane fill the neighbourhood as they do in the solver's
                    // boundary test (an image is never nearer than its
                    // particle, so the cells around x_i hold every one
                    // within reach).
                    for m in &self.images {
                        add(x[i] - m.point(x[j]));
                    }
                    if j != i {
                        let d = x[i] - x[j];
                        let d2 = d.length_squared();
                        nearest = nearest.min(d2);
                        n += u32::from(d2 > 0.0 && d2 < r2);
                        add(d);
                    }
                });
                Neighbourhood {
                    nearest2: nearest,
                    count: n,
                    hg: self.h[i] * g.length(),
                }
            })
            .collect()
    }

    /// The fewest same-body neighbours (within `2h`, no mirror images) any
    /// particle of each body has in the walk's `hoods` (0 for an empty
    /// body).
    fn fewest_neighbours(&self, hoods: &[Neighbourhood]) -> Vec<u32> {
        self.bodies
            .iter()
            .map(|b| {
                hoods[b.range.clone()]
                    .iter()
                    .map(|n| n.count)
                    .min()
                    .unwrap_or(0)
            })
            .collect()
    }

    /// The close-pair gate's spacing scale of each particle, squared:
    /// `κ_i² = (d_i / V0_i^(1/d))²`, `d_i` the distance to its nearest
    /// neighbour of its own body as placed and `V0_i = m_i/ρ0` its volume.
    /// 1 on the square lattice; below 1 where placement (a polar lattice,
    /// jitter) puts a neighbour closer than the volume says, so that the
    /// gate, whose spacing is `κ V̄^(1/d)` with the smaller `κ` of a pair,
    /// stays shut on the lattice as placed. Within 1e-9 of 1 or above it
    /// (and alone in its body) is 1.
    pub fn close_scales(&self, x: &[DVec2]) -> Vec<f64> {
        self.close_scales_of(&self.placed_neighbourhoods(x))
    }

    /// [`Model::close_scales`] from the walk's `hoods`.
    fn close_scales_of(&self, hoods: &[Neighbourhood]) -> Vec<f64> {
        hoods
            .iter()
            .enumerate()
            .map(|(i, &Neighbourhood { nearest2: d2, .. })| {
                let v0 = self.reference_volume(i) / self.share(i);
                let s2 = if self.dim == 1 { v0 * v0 } else { v0 };
                // Within round-off of the volume's side is the lattice
                // spacing itself.
                let k2 = d2 / s2;
                if k2 < 1.0 - 1e-9 {
                    k2
                } else {
                    1.0
                }
            })
            .collect()
    }
}

/// A particle's own-body neighbourhood as placed ([`Model::placed_neighbourhoods`]).
#[derive(Debug, Clone, Copy)]
struct Neighbourhood {
    /// Squared distance to the nearest neighbour.
    nearest2: f64,
    /// Neighbours within `2h`, coincident ones excluded.
    count: u32,
    /// `h |∇ψ⁰|`, what the boundary test reads.
    hg: f64,
}
