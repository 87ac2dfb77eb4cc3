//! The soil-mechanics lab: what a biaxial test reads from the forces the solver computes, and
//! the Mohr–Coulomb envelope fitted to the failures of several runs.
//!
//! **The biaxial test** (plane strain): a sample under a confining pressure σ3 on its free
//! faces ([`crate::config::TractionConfig`]), standing on the floor, compressed by a kinematic
//! platen at a constant speed. Its readings come from the solver's state, not the material's
//! parameters: the axial stress σ1 = F/w from the force F the sample exerts on the platen
//! (its `contact_force`, averaged over each interval between readings) over the sample's
//! current width w (σ3 + F/w where the traction also presses the top), σ3 as the traction
//! applies it at the reading (rising over its rise time); the deviator q = σ1 − σ3; the axial strain ε_a = 1 − H/H0 from the
//! height H between the centres of its top and bottom particles; the volumetric strain ε_v = ΣV/ΣV0 − 1 from the particles' volumes
//! (compression negative).
//!
//! **The direct shear box** (plane strain): a sample in a split box, the lower half fixed, the
//! upper half (a kinematic body) driven sideways at a constant speed, a loaded lid (a solid
//! body) on top. Both readings come from the statics of what lies above the shear plane (the
//! sample's upper part and the lid), the plane lying midway between the halves: τ = F_x/L
//! from the force F the sample and the lid exert on the upper half along its motion, over the
//! box's length L; σ_n = (W + F_y)/L from the weight W of the lid and of the sand above the
//! plane and the vertical force F_y the upper half exerts on them. The upper half is held
//! vertically, as the kinematic body it is, so it carries part of the load or presses the
//! sample down (with ψ = 0 it presses: its rims hold down the sand that the trailing wall
//! pushes), and the plane's normal stress is not the lid's alone; a box whose upper half is
//! held reads it the same way, from the vertical force on the half or below the sample. The
//! lid's rise comes from its centre of mass; the vertical force the sample exerts on the lid
//! checks the lid's load against statics.
//!
//! **The envelope**: failure points (σ_n, τ) of shear tests are fitted by least squares with
//! τ = c + σ_n tan φ; failure circles (σ1, σ3) of biaxial tests with the line
//! t = c cos φ + s sin φ through their tops (s, t) = ((σ1 + σ3)/2, (σ1 − σ3)/2), which every
//! circle of a Mohr–Coulomb material touches. [`davis`] gives what a plane-strain shear box
//! reads for a material of friction angle φ and dilatancy ψ.

use crate::config::SceneConfig;
use crate::error::{Error, Result};
use crate::math::D2;
use crate::sim::Simulation;
use serde::Serialize;

/// A Mohr–Coulomb envelope τ = c + σ_n tan φ.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Envelope {
    /// φ (degrees).
    pub friction_angle: f64,
    /// c (Pa).
    pub cohesion: f64,
}

/// The least-squares line y = a + b x through `points`; `None` for fewer than two distinct x.
fn line(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (sxx, sxy) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (x - mx), b + (x - mx) * (y - my))
    });
    if sxx.is_nan() || sxx <= 1e-12 * (mx * mx).max(1e-300) {
        return None;
    }
    let b = sxy / sxx;
    Some((my - b * mx, b))
}

/// The envelope τ = c + σ_n tan φ fitted by least squares to failure points (σ_n, τ) (Pa,
/// compression positive); `None` for fewer than two distinct σ_n. A fitted negative slope or
/// intercept is kept (the reading says what the points say).
pub fn fit_points(points: &[(f64, f64)]) -> Option<Envelope> {
    let (c, tan_phi) = line(points)?;
    Some(Envelope {
        friction_angle: tan_phi.atan().to_degrees(),
        cohesion: c,
    })
}

/// The envelope tangent to failure circles given by their principal stresses (σ1, σ3) (Pa,
/// compression positive): the least-squares line t = c cos φ + s sin φ through the circles'
/// tops; `None` for fewer than two distinct centres or a slope outside [0, 1).
pub fn fit_circles(circles: &[(f64, f64)]) -> Option<Envelope> {
    let tops: Vec<(f64, f64)> = circles
        .iter()
        .map(|&(s1, s3)| (0.5 * (s1 + s3), 0.5 * (s1 - s3)))
        .collect();
    let (a, sin_phi) = line(&tops)?;
    if !(0.0..1.0).contains(&sin_phi) {
        return None;
    }
    let phi = sin_phi.asin();
    Some(Envelope {
        friction_angle: phi.to_degrees(),
        cohesion: a / phi.cos(),
    })
}

/// The envelope a plane-strain direct shear test reads on a material of friction angle φ,
/// dilatancy ψ (degrees) and cohesion c (Pa): Davis's ([`crate::material::davis`]).
pub fn davis(friction_angle: f64, dilatancy_angle: f64, cohesion: f64) -> Envelope {
    let (friction_angle, cohesion) =
        crate::material::davis(friction_angle, dilatancy_angle, cohesion);
    Envelope {
        friction_angle,
        cohesion,
    }
}

/// Whether `scene` is a biaxial test (a body under a traction, [`Biaxial`]) rather than a
/// shear box ([`ShearBox`]): the one place the two soil tests are told apart.
pub fn is_biaxial(scene: &SceneConfig) -> bool {
    scene.bodies.iter().any(|b| b.traction.is_some())
}

/// One reading of a biaxial test.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BiaxialReading {
    /// Simulated time (s).
    pub time: f64,
    /// ε_a = 1 − H/H0 (shortening positive).
    pub axial_strain: f64,
    /// ε_v = ΣV/ΣV0 − 1 (dilation positive).
    pub volumetric_strain: f64,
    /// σ3, the confining pressure as the traction applies it then (Pa, compression positive).
    pub sigma3: f64,
    /// σ1 = F/w, or σ3 + F/w with the top under the traction too (Pa, compression positive).
    pub sigma1: f64,
    /// q = σ1 − σ3 (Pa).
    pub deviator: f64,
}

/// A biaxial test on a plane-strain simulation: which body is the sample (the one under a
/// traction) and which the platen (the moving kinematic body), the sample's initial height and
/// volume, and the platen's impulse summed since the last reading.
#[derive(Clone, Debug)]
pub struct Biaxial {
    pub sample: usize,
    pub platen: usize,
    /// The confining traction: σ3 (Pa) as it rises ([`crate::config::TractionConfig::ramp`]),
    /// and whether it also presses on the sample's top (then σ1 = σ3 + F/w).
    traction: crate::config::TractionConfig,
    top_loaded: bool,
    spacing: f64,
    height0: f64,
    volume0: f64,
    impulse: f64,
    elapsed: f64,
    /// The readings so far.
    pub readings: Vec<BiaxialReading>,
}

impl Biaxial {
    /// Finds the sample (the one body under a traction) and the platen (a kinematic body
    /// moving along y) of `sim`, at its start; an error names what is missing.
    pub fn new(sim: &Simulation<D2>) -> Result<Self> {
        let scene = sim.scene();
        let present = sim.bodies().len();
        let sample = (0..present)
            .find(|&i| scene.bodies[i].traction.is_some())
            .ok_or_else(|| {
                Error::invalid(
                    "bodies",
                    "no body with a traction",
                    "a biaxial test needs a sample under a confining pressure (bodies[].traction)",
                )
            })?;
        let platen = (0..present)
            .find(|&i| {
                let b = &scene.bodies[i];
                b.kinematic && b.velocity.as_ref().is_some_and(|v| v[1] != 0.0)
            })
            .ok_or_else(|| {
                Error::invalid(
                    "bodies",
                    "no moving kinematic body",
                    "a biaxial test needs a platen: a kinematic body with a velocity along y",
                )
            })?;
        let config = &scene.bodies[sample];
        let traction = config.traction.as_ref().expect("found by its traction");
        let spacing = scene.cell_size / config.particles_per_cell as f64;
        let r = sim.bodies()[sample].range();
        let volume0 = sim.particles().volume[r].iter().map(|&v| v as f64).sum();
        let s = sim.bodies()[sample].stats();
        Ok(Biaxial {
            sample,
            platen,
            traction: traction.clone(),
            top_loaded: traction.faces.contains(&crate::config::Face::Top),
            spacing,
            height0: s.bbox_max[1] - s.bbox_min[1],
            volume0,
            impulse: 0.0,
            elapsed: 0.0,
            readings: Vec::new(),
        })
    }

    /// Adds the platen's impulse of the step just taken (call after every step).
    pub fn after_step(&mut self, sim: &Simulation<D2>) {
        let dt = sim.diagnostics().dt;
        self.impulse += sim.bodies()[self.platen].stats().contact_force[1] * dt;
        self.elapsed += dt;
    }

    /// A reading now, with the platen's force averaged since the last one; recorded in
    /// [`Biaxial::readings`] and returned.
    pub fn read(&mut self, sim: &Simulation<D2>) -> BiaxialReading {
        let s = sim.bodies()[self.sample].stats();
        let width = s.bbox_max[0] - s.bbox_min[0] + self.spacing;
        let height = s.bbox_max[1] - s.bbox_min[1];
        let force = if self.elapsed > 0.0 {
            self.impulse / self.elapsed
        } else {
            0.0
        };
        self.impulse = 0.0;
        self.elapsed = 0.0;
        let r = sim.bodies()[self.sample].range();
        let volume: f64 = sim.particles().volume[r].iter().map(|&v| v as f64).sum();
        let from_platen = force / width;
        // σ3 as the traction applies it now: rising from 0 over its rise time, as a cell is
        // pressurised, so that an unloaded sample reads q = 0, not −σ3
        let sigma3 = self.traction.pressure * self.traction.ramp(sim.time());
        let sigma1 = if self.top_loaded {
            sigma3 + from_platen
        } else {
            from_platen
        };
        let reading = BiaxialReading {
            time: sim.time(),
            axial_strain: 1.0 - height / self.height0,
            volumetric_strain: volume / self.volume0 - 1.0,
            sigma3,
            sigma1,
            deviator: sigma1 - sigma3,
        };
        self.readings.push(reading);
        reading
    }

    /// Runs `sim` for `span` seconds, reading every `every` seconds.
    pub fn run(&mut self, sim: &mut Simulation<D2>, span: f64, every: f64) -> Result<()> {
        run_test(sim, span, every, |sim, read| {
            self.after_step(sim);
            if read {
                self.read(sim);
            }
        })
    }

    /// The failure circle (σ1, σ3) at the peak deviator of the readings.
    pub fn failure(&self) -> Option<(f64, f64)> {
        self.readings
            .iter()
            .max_by(|a, b| a.deviator.total_cmp(&b.deviator))
            .map(|r| (r.sigma1, r.sigma3))
    }

    /// The readings as CSV: a header, then one row per reading.
    pub fn csv(&self) -> String {
        let mut out =
            String::from("time_s,axial_strain,volumetric_strain,sigma3_pa,sigma1_pa,deviator_pa\n");
        for r in &self.readings {
            out += &format!(
                "{},{},{},{},{},{}\n",
                r.time, r.axial_strain, r.volumetric_strain, r.sigma3, r.sigma1, r.deviator
            );
        }
        out
    }
}

/// One reading of a direct shear test.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShearReading {
    /// Simulated time (s).
    pub time: f64,
    /// δ, how far the upper half has moved (m).
    pub displacement: f64,
    /// τ = F_x/L, the force the sample and the lid exert on the upper half along its motion
    /// over the box's length (Pa).
    pub shear_stress: f64,
    /// σ_n = (W + F_y)/L on the shear plane: the weight of the lid and of the sand above the
    /// plane and the vertical force of the upper half on them, over the box's length (Pa).
    pub normal_stress: f64,
    /// F_y/L, the vertical force the upper half exerts on the sand and the lid, over the
    /// box's length (Pa; pressing down positive).
    pub frame_load: f64,
    /// The vertical force the sample exerts on the lid over the box's length (Pa): σ_n by
    /// statics once the lid rests.
    pub lid_support: f64,
    /// How far the lid has risen (m; sinking negative).
    pub lid_rise: f64,
}

/// A plane-strain direct shear test on a simulation: the sample (the first granular body),
/// the upper half (a kinematic body moving along x), the lower half (a kinematic body at
/// rest), the lid (a solid body that is not kinematic), the box's inner length L (the
/// sample's initial width) and the shear plane, midway between the lower half's top and the
/// upper half's bottom.
#[derive(Clone, Debug)]
pub struct ShearBox {
    pub sample: usize,
    pub upper: usize,
    pub lid: usize,
    length: f64,
    /// The shear plane's height (m).
    pub plane: f64,
    speed: f64,
    start: f64,
    lid0: f64,
    weight: f64,
    lid_weight: f64,
    impulse: [f64; 3],
    elapsed: f64,
    /// The readings so far.
    pub readings: Vec<ShearReading>,
}

/// The lid of a shear-box scene and the density that gives it `load` (Pa), its weight over
/// the box's length (the sample's width), as [`ShearBox::lid_pressure`] reads it: the sample
/// is the first sand body and the lid the first solid body, neither kinematic, as
/// [`ShearBox::new`] finds them. The lid's load sets the test; σ_n on the shear plane is read
/// ([`ShearReading::normal_stress`]). An error names what is missing.
pub fn lid_density(scene: &SceneConfig, load: f64) -> Result<(usize, f64)> {
    let find = |sand: bool, what: &str| {
        scene
            .bodies
            .iter()
            .position(|b| !b.kinematic && b.material.behaviour().friction().is_some() == sand)
            .ok_or_else(|| {
                Error::invalid(
                    "bodies",
                    format!("no {what}"),
                    "a shear box needs a sand sample and a solid lid",
                )
            })
    };
    let (sample, lid) = (find(true, "sand")?, find(false, "lid")?);
    let g = scene.gravity_vector()[1].abs();
    let (s, l) = (
        scene.bodies[sample].shape.bounds(scene.dim),
        scene.bodies[lid].shape.bounds(scene.dim),
    );
    let area = (l.max[0] - l.min[0]) * (l.max[1] - l.min[1]);
    Ok((lid, load * (s.max[0] - s.min[0]) / (g * area)))
}

impl ShearBox {
    /// Finds the sample, the upper half and the lid of `sim` at its start; an error names
    /// what is missing.
    pub fn new(sim: &Simulation<D2>) -> Result<Self> {
        let scene = sim.scene();
        let present = sim.bodies().len();
        let missing =
            |what: &str, need: &str| Error::invalid("bodies", what.to_string(), need.to_string());
        let sample = (0..present)
            .find(|&i| {
                scene.bodies[i].material.behaviour().friction().is_some()
                    && !scene.bodies[i].kinematic
            })
            .ok_or_else(|| missing("no sand", "a shear box needs a sample of sand"))?;
        let upper = (0..present)
            .find(|&i| {
                let b = &scene.bodies[i];
                b.kinematic && b.velocity.as_ref().is_some_and(|v| v[0] != 0.0)
            })
            .ok_or_else(|| {
                missing(
                    "no kinematic body moving along x",
                    "a shear box needs an upper half driven sideways",
                )
            })?;
        let lower = (0..present)
            .find(|&i| {
                let b = &scene.bodies[i];
                b.kinematic
                    && b.velocity
                        .as_ref()
                        .is_none_or(|v| v.iter().all(|&x| x == 0.0))
            })
            .ok_or_else(|| {
                missing(
                    "no kinematic body at rest",
                    "a shear box needs a fixed lower half",
                )
            })?;
        let lid = (0..present)
            .find(|&i| {
                let b = &scene.bodies[i];
                !b.kinematic && b.material.behaviour().friction().is_none()
            })
            .ok_or_else(|| {
                missing(
                    "no solid body",
                    "a shear box needs a lid: a solid body on the sample",
                )
            })?;
        let s = sim.bodies()[sample].stats();
        let spacing = scene.cell_size / scene.bodies[sample].particles_per_cell as f64;
        let g = scene.gravity_vector()[1].abs();
        let b = sim.bodies();
        let plane = 0.5 * (b[lower].stats().bbox_max[1] + b[upper].stats().bbox_min[1]);
        let p = sim.particles();
        let sand_above: f64 = b[sample]
            .range()
            .filter(|&i| p.x[i][1] as f64 > plane)
            .map(|i| p.mass[i] as f64)
            .sum();
        let above = sand_above + b[lid].stats().mass;
        Ok(ShearBox {
            sample,
            upper,
            lid,
            length: s.bbox_max[0] - s.bbox_min[0] + spacing,
            plane,
            speed: scene.bodies[upper]
                .velocity
                .as_ref()
                .expect("found by its velocity")[0],
            start: sim.time(),
            lid0: sim.bodies()[lid].stats().center_of_mass[1],
            weight: above * g,
            lid_weight: sim.bodies()[lid].stats().mass * g,
            impulse: [0.0; 3],
            elapsed: 0.0,
            readings: Vec::new(),
        })
    }

    /// Adds the forces of the step just taken (call after every step).
    pub fn after_step(&mut self, sim: &Simulation<D2>) {
        let dt = sim.diagnostics().dt;
        let b = sim.bodies();
        let upper = b[self.upper].stats().contact_force;
        self.impulse[0] += upper[0] * dt;
        self.impulse[1] += b[self.lid].stats().contact_force[1] * dt;
        self.impulse[2] += upper[1] * dt;
        self.elapsed += dt;
    }

    /// A reading now, with the forces averaged since the last one; recorded and returned.
    pub fn read(&mut self, sim: &Simulation<D2>) -> ShearReading {
        let mean = |j: f64| {
            if self.elapsed > 0.0 {
                j / self.elapsed
            } else {
                0.0
            }
        };
        let (fx, fy) = (mean(self.impulse[0]), mean(self.impulse[1]));
        // the sand and the lid push the upper half up by what it presses them down with
        let frame = mean(self.impulse[2]);
        self.impulse = [0.0; 3];
        self.elapsed = 0.0;
        let sign = self.speed.signum();
        let reading = ShearReading {
            time: sim.time(),
            displacement: (sim.time() - self.start) * self.speed.abs(),
            // the sample resists the motion: its force on the upper half opposes it
            shear_stress: -sign * fx / self.length,
            normal_stress: (self.weight + frame) / self.length,
            frame_load: frame / self.length,
            lid_support: fy / self.length,
            lid_rise: sim.bodies()[self.lid].stats().center_of_mass[1] - self.lid0,
        };
        self.readings.push(reading);
        reading
    }

    /// Runs `sim` for `span` seconds, reading every `every` seconds.
    pub fn run(&mut self, sim: &mut Simulation<D2>, span: f64, every: f64) -> Result<()> {
        run_test(sim, span, every, |sim, read| {
            self.after_step(sim);
            if read {
                self.read(sim);
            }
        })
    }

    /// The lid's weight over the box's length (Pa), for the statics check of
    /// [`ShearReading::lid_support`].
    pub fn lid_pressure(&self) -> f64 {
        self.lid_weight / self.length
    }

    /// The failure point (σ_n, τ): the mean of the readings over the last quarter of the
    /// travel so far, where the band flows plastically (τ/σ_n is steady from δ ≈ 0.3 mm on in
    /// the shipped box, while σ_n changes with the upper half's load: every reading there lies
    /// on the envelope, and Davis's angle is that of plastic flow).
    pub fn failure(&self) -> Option<(f64, f64)> {
        let last = self.readings.last()?.displacement;
        let flowing: Vec<_> = self
            .readings
            .iter()
            .filter(|r| r.displacement >= 0.75 * last && r.time > self.start)
            .collect();
        if flowing.is_empty() {
            return None;
        }
        let n = flowing.len() as f64;
        let sum = flowing.iter().fold((0.0, 0.0), |(s, t), r| {
            (s + r.normal_stress, t + r.shear_stress)
        });
        Some((sum.0 / n, sum.1 / n))
    }

    /// The readings as CSV: a header, then one row per reading.
    pub fn csv(&self) -> String {
        let mut out = String::from(
            "time_s,displacement_m,shear_stress_pa,normal_stress_pa,frame_load_pa,lid_support_pa,lid_rise_m\n",
        );
        for r in &self.readings {
            out += &format!(
                "{},{},{},{},{},{},{}\n",
                r.time,
                r.displacement,
                r.shear_stress,
                r.normal_stress,
                r.frame_load,
                r.lid_support,
                r.lid_rise
            );
        }
        out
    }
}

/// A lab test's driver loop: steps `sim` for `span` seconds and calls `each` after every step,
/// with `true` every `every` seconds (when the test takes a reading).
fn run_test(
    sim: &mut Simulation<D2>,
    span: f64,
    every: f64,
    mut each: impl FnMut(&Simulation<D2>, bool),
) -> Result<()> {
    let end = sim.time() + span;
    let mut next = sim.time() + every;
    while sim.time() < end - 1e-12 {
        sim.step()?;
        let read = sim.time() >= next - 1e-12;
        each(sim, read);
        if read {
            next += every;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn davis_reads_26_6_degrees_for_30_and_no_dilatancy_and_phi_when_psi_is_phi() {
        let e = davis(30.0, 0.0, 1000.0);
        assert!(close(e.friction_angle, 26.565, 0.01), "{e:?}");
        assert!(
            close(e.cohesion, 1000.0 * 30f64.to_radians().cos(), 1e-9),
            "{e:?}"
        );
        let same = davis(30.0, 30.0, 1000.0);
        assert!(close(same.friction_angle, 30.0, 1e-9), "{same:?}");
        assert!(close(same.cohesion, 1000.0, 1e-9), "{same:?}");
    }

    #[test]
    fn the_fits_recover_the_envelope_the_failures_were_drawn_from() {
        let (phi, c) = (32f64.to_radians(), 2500.0);
        // shear-box points on τ = c + σ tan φ, with ±1 % scatter that cancels in pairs
        let points: Vec<(f64, f64)> = [10e3, 20e3, 40e3, 80e3]
            .iter()
            .zip([1.01, 0.99, 0.99, 1.01])
            .map(|(&s, k)| (s, (c + s * phi.tan()) * k))
            .collect();
        let e = fit_points(&points).unwrap();
        assert!(close(e.friction_angle, 32.0, 0.5), "{e:?}");
        assert!(close(e.cohesion, c, 0.1 * c), "{e:?}");
        // biaxial circles touching it: σ1 = σ3 Kp + 2 c √Kp
        let kp = (1.0 + phi.sin()) / (1.0 - phi.sin());
        let circles: Vec<(f64, f64)> = [10e3, 20e3, 40e3]
            .iter()
            .map(|&s3| (s3 * kp + 2.0 * c * kp.sqrt(), s3))
            .collect();
        let e = fit_circles(&circles).unwrap();
        assert!(close(e.friction_angle, 32.0, 1e-9), "{e:?}");
        assert!(close(e.cohesion, c, 1e-6 * c), "{e:?}");
        // one point, or one centre, fits nothing
        assert!(fit_points(&points[..1]).is_none());
        assert!(fit_circles(&[circles[0], circles[0]]).is_none());
    }
}
