//! What the solver reports after every step.

use crate::math::{Dim, Real, VectorOps, max};
use serde::Serialize;

/// How far the energy account may be from closing ([`Diagnostics::energy_error`]) for a run
/// to count as closing it: 2 % of the energy in play.
pub const ACCOUNT_TOLERANCE: f64 = 0.02;

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
    /// Cumulative kinetic energy of the particles brought to rest as they fell asleep
    /// (slower than the sleep speed; see [`crate::step::sleep`]).
    pub dissipated_sleep: f64,
    /// Cumulative kinetic energy the transfers between particles and grid removed (the
    /// numerical damping of PIC's share; negative where FLIP's share added energy): in each
    /// step the particles' kinetic energy before the scatter minus the grid's, plus the grid's
    /// after the walls minus the particles' after the gather (less what the particle-side
    /// walls booked as boundary dissipation).
    pub dissipated_numerical: f64,
    /// Cumulative integration error of the stress update (signed; negative where the update
    /// created energy): in each step the kinetic energy the internal forces took from the
    /// grid, Σ −Δt f_i·(v_i^n + v*_i)/2, less the elastic energy the update stored and the
    /// plastic and viscous work it removed.
    pub dissipated_integration: f64,
    /// The energy the bodies brought as they entered (kinetic, gravitational and elastic at
    /// their entry) and the particles a spout poured as they entered (kinetic and
    /// gravitational, [`crate::sim::pour`]), less what removed bodies took with them: what the
    /// account must close on.
    pub energy_in: f64,
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
            + self.dissipated_sleep
            + self.dissipated_numerical
            + self.dissipated_integration
    }
    /// How far the account is from closing: (total + dissipated − energy in) as a share of
    /// the largest of the energy in, the total and the dissipated (zero when none is in
    /// play). Positive when the account created energy.
    pub fn energy_error(&self) -> f64 {
        let total = self.total_energy();
        let dissipated = self.dissipated();
        let scale = self.energy_in.abs().max(total.abs()).max(dissipated.abs());
        if scale > 0.0 {
            (total + dissipated - self.energy_in) / scale
        } else {
            0.0
        }
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

/// The figures of one body's particle state, summed particle by particle: mass, kinetic and
/// gravitational energy, momentum, first moment, bounds, the largest speed and plastic
/// strain. The gather records each particle after it moved; [`super::Simulation::refresh_diagnostics`]
/// records them as they stand.
#[derive(Clone, Copy, Debug)]
pub struct Measure<D: Dim> {
    pub mass: f64,
    pub kinetic: f64,
    pub gravitational: f64,
    pub momentum: [f64; 3],
    /// Σ m x.
    pub first_moment: [f64; 3],
    pub min: D::Vector,
    pub max: D::Vector,
    pub max_speed: Real,
    pub max_plastic_strain: Real,
    /// Σ m, Σ ½ m v², Σ m v and Σ m x while recording, side by side so that the f64 sums go
    /// through SIMD registers two at a time ([`Self::finish`] hands them out).
    sums: [f64; 8],
}

impl<D: Dim> Measure<D> {
    /// Nothing recorded yet.
    pub fn empty() -> Self {
        Measure {
            mass: 0.0,
            kinetic: 0.0,
            gravitational: 0.0,
            momentum: [0.0; 3],
            first_moment: [0.0; 3],
            min: D::Vector::splat(Real::INFINITY),
            max: D::Vector::splat(Real::NEG_INFINITY),
            max_speed: 0.0,
            max_plastic_strain: 0.0,
            sums: [0.0; 8],
        }
    }

    /// After the last particle: the speed from its square, and the gravitational energy
    /// −Σ m g·x = −g·Σ m x from the first moment (one accumulator fewer per particle).
    #[inline(always)]
    pub fn finish(&mut self, gravity: D::Vector) {
        let (s, d) = (self.sums, D::DIM);
        (self.mass, self.kinetic) = (s[0], s[1]);
        for a in 0..d {
            (self.momentum[a], self.first_moment[a]) = (s[2 + a], s[2 + d + a]);
        }
        self.max_speed = self.max_speed.sqrt();
        self.gravitational = -(0..D::DIM)
            .map(|a| gravity[a] as f64 * self.first_moment[a])
            .sum::<f64>();
    }

    /// Adds one particle (`max_speed` holds the squared speed until [`Self::finish`]).
    #[inline(always)]
    pub fn record(&mut self, m: Real, x: D::Vector, v: D::Vector) {
        let (md, v2) = (m as f64, v.length_squared());
        // m · (1, ½ v², v, x); ½ m v² as md (½ v²) is (½ md) v² exactly (a power of two).
        let d = D::DIM;
        let mut per_mass = [1.0, 0.5 * v2 as f64, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        for a in 0..d {
            (per_mass[2 + a], per_mass[2 + d + a]) = (v[a] as f64, x[a] as f64);
        }
        for i in 0..2 + 2 * d {
            self.sums[i] += md * per_mass[i];
        }
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.max_speed = max(self.max_speed, v2);
    }

    /// Adds the figures of another finished measure (of other particles) to this finished one.
    pub fn add_finished(&mut self, o: &Measure<D>) {
        self.mass += o.mass;
        self.kinetic += o.kinetic;
        self.gravitational += o.gravitational;
        for a in 0..3 {
            self.momentum[a] += o.momentum[a];
            self.first_moment[a] += o.first_moment[a];
        }
        self.min = self.min.min(o.min);
        self.max = self.max.max(o.max);
        self.max_speed = max(self.max_speed, o.max_speed);
        self.max_plastic_strain = max(self.max_plastic_strain, o.max_plastic_strain);
    }

    /// With the largest plastic strain of the particles.
    pub fn with_plastic_strain(mut self, plastic_strain: &[Real]) -> Self {
        for &e in plastic_strain {
            self.max_plastic_strain = max(self.max_plastic_strain, e);
        }
        self
    }

    /// Writes the figures of a body of `particles` particles into its `stats`.
    pub fn write(&self, stats: &mut BodyStats, particles: usize) {
        stats.particles = particles;
        stats.mass = self.mass;
        stats.kinetic = self.kinetic;
        stats.gravitational = self.gravitational;
        stats.momentum = self.momentum;
        stats.max_speed = self.max_speed as f64;
        stats.max_plastic_strain = self.max_plastic_strain as f64;
        for a in 0..3 {
            stats.center_of_mass[a] = if self.mass > 0.0 {
                self.first_moment[a] / self.mass
            } else {
                0.0
            };
            stats.bbox_min[a] = if a < D::DIM && particles > 0 {
                self.min[a] as f64
            } else {
                0.0
            };
            stats.bbox_max[a] = if a < D::DIM && particles > 0 {
                self.max[a] as f64
            } else {
                0.0
            };
        }
    }
}

/// Cumulative wall-clock seconds spent in each pass of the step (see
/// [`crate::Simulation::timings`]); always zero in WebAssembly, which has no clock here.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PassTimings {
    pub steps: u64,
    /// Grid blocks where the particles are, particle sorting, contact pair search.
    pub allocate: f64,
    /// Step 1: mass and momentum to the grid (and, stress updated last, the internal forces).
    pub scatter: f64,
    /// Steps 2–3 and the particle side of 4 with the stress updated first (the linear kernel);
    /// with the stress updated last they run in the gather and count there.
    pub stress: f64,
    /// Grid velocities, and step 4 on the grid: forces and gravity.
    pub grid: f64,
    /// Step 5 between bodies (Eq. 20–21).
    pub contact: f64,
    /// Step 5 at the walls.
    pub walls: f64,
    /// Steps 6–8: PIC/FLIP gather, particle collisions, advection, diagnostics (and, stress
    /// updated last, the velocity gradient and steps 2–3).
    pub gather: f64,
}
