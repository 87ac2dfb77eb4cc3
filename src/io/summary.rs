//! The JSON summary of a run: world figures, energies and per-body statistics.

use super::Snapshot;
use crate::measure::{Deposit, Footprints, deposits_any};
use crate::sim::AnySimulation;
use serde::{Deserialize, Serialize};

/// What `mpm run --summary` writes. Vectors have the scene's dimension; energies are in J
/// (J/m in 2D), momentum in kg·m/s (kg·m/s per metre in 2D).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub scene: String,
    pub dim: usize,
    /// Simulated time (s).
    pub time: f64,
    pub steps: u64,
    pub wall_seconds: f64,
    pub particles: usize,
    pub nonfinite_particles: usize,
    /// Particles outside the domain.
    pub escaped_particles: usize,
    /// Particles asleep at the end (zero unless the run let material at rest sleep).
    #[serde(default)]
    pub asleep_particles: usize,
    pub energy: Energy,
    pub bodies: Vec<BodySummary>,
    /// The measures of each sand body ([`crate::measure::deposits`]): its height, its flank
    /// angles (in 3D on the radial profile) and its run-out from its initial footprint.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub deposits: Vec<Deposit>,
    /// The error that stopped the run, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    pub kinetic: f64,
    /// −Σ m g·x (zero at the origin).
    pub gravitational: f64,
    /// Stored elastic energy.
    pub elastic: f64,
    /// Cumulative energy removed by plasticity, by the solids' bulk viscosity, by the walls,
    /// by contact, by bringing particles to rest as they fell asleep and by the transfers.
    pub dissipated_plastic: f64,
    #[serde(default)]
    pub dissipated_viscous: f64,
    pub dissipated_boundary: f64,
    pub dissipated_contact: f64,
    #[serde(default)]
    pub dissipated_sleep: f64,
    /// Cumulative kinetic energy removed by the transfers between particles and grid
    /// ([`crate::Diagnostics::dissipated_numerical`]).
    #[serde(default)]
    pub dissipated_numerical: f64,
    /// The stress update's integration error, signed
    /// ([`crate::Diagnostics::dissipated_integration`]).
    #[serde(default)]
    pub dissipated_integration: f64,
    /// The energy the bodies brought as they entered ([`crate::Diagnostics::energy_in`]).
    #[serde(default)]
    pub energy_in: f64,
    /// (kinetic + gravitational + elastic + dissipated − energy in) over the energy in play
    /// ([`crate::Diagnostics::energy_error`]), and whether it is within
    /// [`crate::sim::ACCOUNT_TOLERANCE`]: whether the account closes.
    #[serde(default)]
    pub account_error: f64,
    #[serde(default = "closes")]
    pub account_closes: bool,
}

fn closes() -> bool {
    true
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodySummary {
    pub name: String,
    pub material: String,
    pub particles: usize,
    pub mass: f64,
    pub center_of_mass: Vec<f64>,
    pub bbox_min: Vec<f64>,
    pub bbox_max: Vec<f64>,
    pub kinetic_energy: f64,
    pub momentum: Vec<f64>,
    pub max_plastic_strain: f64,
}

impl Summary {
    /// The summary of a simulation as it stands; `footprints` holds where its particles
    /// started (for the run-outs).
    pub fn of(sim: &AnySimulation, wall_seconds: f64, footprints: &Footprints) -> Self {
        let snap = Snapshot::of(sim);
        let d = sim.diagnostics();
        let dim = sim.dim();
        let cut = |v: [f64; 3]| v[..dim].to_vec();
        let scene = sim.scene();
        Summary {
            scene: scene.name.clone(),
            dim,
            time: sim.time(),
            steps: sim.steps(),
            wall_seconds,
            particles: snap.len(),
            nonfinite_particles: snap.nonfinite(),
            escaped_particles: snap.escaped(),
            asleep_particles: sim.asleep(),
            energy: Energy {
                kinetic: d.kinetic,
                gravitational: d.gravitational,
                elastic: d.elastic,
                dissipated_plastic: d.dissipated_plastic,
                dissipated_viscous: d.dissipated_viscous,
                dissipated_boundary: d.dissipated_boundary,
                dissipated_contact: d.dissipated_contact,
                dissipated_sleep: d.dissipated_sleep,
                dissipated_numerical: d.dissipated_numerical,
                dissipated_integration: d.dissipated_integration,
                energy_in: d.energy_in,
                account_error: d.energy_error(),
                account_closes: d.energy_error().abs() <= crate::sim::ACCOUNT_TOLERANCE,
            },
            bodies: sim
                .body_stats()
                .into_iter()
                .zip(&scene.bodies)
                .map(|(s, b)| BodySummary {
                    name: b.name.clone(),
                    material: b.material.kind().to_string(),
                    particles: s.particles,
                    mass: s.mass,
                    center_of_mass: cut(s.center_of_mass),
                    bbox_min: cut(s.bbox_min),
                    bbox_max: cut(s.bbox_max),
                    kinetic_energy: s.kinetic,
                    momentum: cut(s.momentum),
                    max_plastic_strain: s.max_plastic_strain,
                })
                .collect(),
            deposits: deposits_any(sim, footprints),
            error: sim.failure().map(|e| e.to_string()),
        }
    }
}
