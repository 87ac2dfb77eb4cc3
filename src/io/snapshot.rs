//! The particles of a simulation of either dimension, as plain arrays with three components
//! per vector (the third is zero in 2D).

use crate::math::{Dim, SymTensor};
use crate::sim::{AnySimulation, Simulation};

/// Particle state copied out of a simulation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    pub dim: usize,
    pub time: f64,
    /// The domain `[0, size]` (m; the third component is zero in 2D).
    pub domain: [f64; 3],
    pub position: Vec<[f32; 3]>,
    pub velocity: Vec<[f32; 3]>,
    /// The index of each particle's body.
    pub body: Vec<u32>,
    /// Accumulated equivalent plastic strain.
    pub plastic_strain: Vec<f32>,
    /// Pressure −tr(σ)/3 (Pa): for sand, of the stress recovered on the grid
    /// ([`crate::recovery`]).
    pub pressure: Vec<f32>,
    /// Volume (m³; m² in 2D).
    pub volume: Vec<f32>,
    /// Body names, by index.
    pub body_names: Vec<String>,
}

impl Snapshot {
    pub fn of(sim: &AnySimulation) -> Self {
        match sim {
            AnySimulation::D2(s) => Self::of_sim(s),
            AnySimulation::D3(s) => Self::of_sim(s),
        }
    }

    // `Real` is f32 or f64 (feature `f64`): the casts are needed in one of the builds
    #[allow(clippy::unnecessary_cast)]
    pub fn of_sim<D: Dim>(sim: &Simulation<D>) -> Self {
        let p = sim.particles();
        let n = p.len();
        let v3 = |v: D::Vector| -> [f32; 3] {
            std::array::from_fn(|a| if a < D::DIM { v[a] as f32 } else { 0.0 })
        };
        let mut body = vec![0u32; n];
        for (b, body_data) in sim.bodies().iter().enumerate() {
            for i in body_data.range() {
                body[i] = b as u32;
            }
        }
        let scene = sim.scene();
        Snapshot {
            dim: D::DIM,
            time: sim.time(),
            domain: std::array::from_fn(|a| scene.domain.size.get(a).copied().unwrap_or(0.0)),
            position: p.x.iter().map(|&x| v3(x)).collect(),
            velocity: p.v.iter().map(|&v| v3(v)).collect(),
            body,
            plastic_strain: p.plastic_strain.iter().map(|&e| e as f32).collect(),
            pressure: crate::recovery::shown_stress(sim)
                .iter()
                .map(|s| -s.trace() as f32 / 3.0)
                .collect(),
            volume: p.volume.iter().map(|&v| v as f32).collect(),
            body_names: scene.bodies.iter().map(|b| b.name.clone()).collect(),
        }
    }

    pub fn len(&self) -> usize {
        self.position.len()
    }
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Particles with a non-finite position, velocity or pressure.
    pub fn nonfinite(&self) -> usize {
        (0..self.len())
            .filter(|&i| {
                !(self.position[i].iter().all(|x| x.is_finite())
                    && self.velocity[i].iter().all(|x| x.is_finite())
                    && self.pressure[i].is_finite())
            })
            .count()
    }

    /// Particles outside the domain (or with a non-finite position).
    pub fn escaped(&self) -> usize {
        self.position
            .iter()
            .filter(|x| !(0..self.dim).all(|a| x[a] >= 0.0 && (x[a] as f64) <= self.domain[a]))
            .count()
    }
}
