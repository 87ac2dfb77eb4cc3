//! What the solver reports after every step.

use serde::Serialize;

/// Whole-simulation diagnostics after the latest step. Energies in J (J/m in 2D),
/// momentum in kg·m/s.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Diagnostics {
    pub time: f64,
    pub step: u64,
    /// The time step just taken (s).
    pub dt: f64,
    /// The CFL number of that step: dt (c + |v|max) / h.
    pub cfl: f64,
    pub particles: usize,
    pub kinetic: f64,
    /// −Σ m g·x (zero at the origin).
    pub gravitational: f64,
    /// Σ V (s:s/(4G) + P²/(2K)).
    pub elastic: f64,
    /// Cumulative energy removed by plastic return mapping.
    pub dissipated_plastic: f64,
    /// Cumulative energy removed by the solids' artificial bulk viscosity.
    pub dissipated_viscous: f64,
    /// Cumulative energy removed by the walls (impact and friction), on the grid and particles.
    pub dissipated_boundary: f64,
    /// Cumulative energy removed by contact between bodies.
    pub dissipated_contact: f64,
    pub momentum: [f64; 3],
    pub max_speed: f64,
    /// Particles whose state went non-finite in this step (the step then fails).
    pub nonfinite: usize,
    /// Grid blocks allocated over all bodies in this step.
    pub grid_blocks: usize,
}

impl Diagnostics {
    /// Kinetic + gravitational + elastic energy.
    pub fn total_energy(&self) -> f64 {
        self.kinetic + self.gravitational + self.elastic
    }
    /// All energy removed by the accounted dissipation mechanisms.
    pub fn dissipated(&self) -> f64 {
        self.dissipated_plastic
            + self.dissipated_viscous
            + self.dissipated_boundary
            + self.dissipated_contact
    }
}

/// Per-body figures after the latest step.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct BodyStats {
    pub particles: usize,
    pub mass: f64,
    pub kinetic: f64,
    pub gravitational: f64,
    pub elastic: f64,
    pub momentum: [f64; 3],
    pub center_of_mass: [f64; 3],
    pub bbox_min: [f64; 3],
    pub bbox_max: [f64; 3],
    pub max_speed: f64,
    pub max_plastic_strain: f64,
    /// The force other bodies exerted on this one through contact in the latest step (N; N/m
    /// in 2D): the momentum exchanged at shared nodes divided by the step.
    pub contact_force: [f64; 3],
    /// Cumulative plastic dissipation of this body.
    pub dissipated_plastic: f64,
}
