//! What `check` and `run` warn about in a scene that is valid but will not do what it seems
//! to say: nothing to simulate, a body that never enters, bodies that overlap, a body its
//! own weight crushes.

use super::{AnySimulation, Simulation};
use crate::math::{Dim, VectorOps};

impl<D: Dim> Simulation<D> {
    /// The warnings for this scene, for a run ending at `end` seconds when known.
    pub fn warnings(&self, end: Option<f64>) -> Vec<String> {
        let mut out = Vec::new();
        let scene = &self.scene;
        if scene.bodies.is_empty() {
            out.push("the scene has no bodies (`bodies` is empty): nothing moves".to_string());
        }
        if let Some(end) = end {
            for (i, b) in scene.bodies.iter().enumerate().skip(self.bodies.len()) {
                if b.appear_time() > end {
                    out.push(format!(
                        "bodies[{i}] {:?} enters at appear_at = {} s, after the run's end at {end} s: it never appears",
                        b.name,
                        b.appear_time()
                    ));
                }
            }
        }
        // bodies present whose particles lie inside another body's shape
        let dim = D::DIM;
        let inside = |shape: usize, body: usize| {
            let test = scene.bodies[shape].shape.inside_test(dim);
            let r = self.bodies[body].range.clone();
            let step = (r.len() / 4000).max(1);
            r.step_by(step)
                .filter(|&q| {
                    let x = self.particles.x[q];
                    test.contains(std::array::from_fn(
                        |k| {
                            if k < dim { x[k] as f64 } else { 0.0 }
                        },
                    ))
                })
                .count()
                * step
        };
        for i in 0..self.bodies.len() {
            for j in i + 1..self.bodies.len() {
                let n = inside(i, j) + inside(j, i);
                if n > 0 {
                    out.push(format!(
                        "bodies[{i}] {:?} and bodies[{j}] {:?} overlap (about {n} particles lie inside the other body's shape): both are simulated where they overlap, and their stresses push them apart in the first steps",
                        scene.bodies[i].name, scene.bodies[j].name
                    ));
                }
            }
        }
        // bodies their own weight crushes: the weight at the base ρ |g| H against the
        // constrained modulus K + 4G/3 that the log-strain pressure resists with
        let g = self.world.gravity.length() as f64;
        for (i, b) in self.bodies.iter().enumerate() {
            if b.kinematic || b.range.is_empty() || g == 0.0 {
                continue;
            }
            let config = &scene.bodies[i];
            let e = config.material.elastic_params();
            let modulus = e.bulk_modulus() + 4.0 / 3.0 * e.shear_modulus();
            let gravity = self.world.gravity;
            let height = (0..dim)
                .map(|a| {
                    let s = &b.stats;
                    (s.bbox_max[a] - s.bbox_min[a]) * (gravity[a] as f64 / g).abs()
                })
                .sum::<f64>();
            let weight = e.density * g * height;
            if weight > modulus {
                out.push(format!(
                    "bodies[{i}] {:?}: its weight presses {weight:.3e} Pa on its base (density × gravity × height), more than its material resists (K + 4G/3 = {modulus:.3e} Pa): it will be crushed flat (raise youngs_modulus)",
                    config.name
                ));
            }
        }
        out
    }
}

impl AnySimulation {
    /// See [`Simulation::warnings`].
    pub fn warnings(&self, end: Option<f64>) -> Vec<String> {
        match self {
            AnySimulation::D2(s) => s.warnings(end),
            AnySimulation::D3(s) => s.warnings(end),
        }
    }
}
