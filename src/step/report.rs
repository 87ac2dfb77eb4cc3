//! What the passes of one step hand on to each other, and what the step reports.
//!
//! [`BodyStep`] is the step's own state, one per body, made fresh at the start of each step:
//! whether walls or contacts changed the body's grid (the gather then caps its FLIP share,
//! [`super::transfer::Transfer::at_constraints`]), the momentum it received through contact,
//! and what its stress update measured. At the end [`Step::finish_step`] sums the reports
//! into the diagnostics and keeps what the next step needs (each body's fastest compression
//! and largest volume, for the time step); the simulation records the rest ([`Finished`]).

use super::sleep::Sleeping;
use super::state::Step;
use crate::math::{Dim, Real};
use crate::sim::body::max_signal_speed;
use crate::sim::stats::Measure;

/// One body's part of the step's state (see the module documentation).
#[derive(Clone, Copy, Debug, Default)]
pub struct BodyStep {
    /// Whether a wall or a contact changed a velocity of this body's grid.
    pub constrained: bool,
    /// Momentum received through contact.
    pub contact_impulse: [f64; 3],
    /// What the stress update measured.
    pub stress: StressReport,
    /// The grid's kinetic energies at v_i^n and after the walls, and gravity's work
    /// ([`super::grid_update::kinetic_energies`]; zero for a kinematic body).
    pub grid: super::grid_update::GridEnergies,
    /// The energy the walls and contacts booked as removed from this body's grid in the step
    /// (a contact's from both bodies, on one that is not kinematic).
    pub constraints: f64,
    /// The work of the external forces other than gravity on this body's grid in the step
    /// (a traction's, [`super::traction`]), booked as energy brought in.
    pub external: f64,
}

impl<D: Dim> Step<'_, D> {
    /// Sums the step's reports into the diagnostics and the bodies' figures, with the
    /// sleeping particles' frozen figures (`sleeping`) beside the stepped ones'.
    pub(super) fn finish_step(
        &mut self,
        dt: f64,
        steps: &[BodyStep],
        gathered: &[GatherReport<D>],
        sleeping: &Sleeping<D>,
    ) -> Finished<D> {
        for (body, step) in self.bodies.iter_mut().zip(steps) {
            body.max_compression = step.stress.max_compression;
        }
        let c = max_signal_speed(self.bodies.iter());
        let d = &mut *self.diagnostics;
        d.nonfinite = steps.iter().map(|s| s.stress.bad).sum::<usize>()
            + gathered.iter().map(|g| g.bad).sum::<usize>();
        for ((body, step), g) in self.bodies.iter_mut().zip(steps).zip(gathered) {
            let s = &step.stress;
            if s.bad == 0 && s.max_volume > 0.0 {
                body.max_volume = s.max_volume; // a kinematic body's report has none
            }
            d.dissipated_plastic += s.dissipated;
            d.dissipated_viscous += s.viscous;

            d.dissipated_boundary += g.dissipated_walls;
            body.stats.dissipated_plastic += s.dissipated;
            body.stats.contact_force = step
                .contact_impulse
                .map(|j| if dt > 0.0 { j / dt } else { 0.0 });
        }
        // the sleeping particles' figures, frozen, beside the stepped ones'
        let mut measures: Vec<_> = gathered.iter().map(|g| g.measure).collect();
        let mut elastic: Vec<f64> = steps.iter().map(|s| s.stress.elastic).collect();
        for (i, body) in self.bodies.iter_mut().enumerate() {
            if body.asleep > 0 {
                let sleep = sleeping.body(i);
                measures[i].add_finished(&sleep.measure);
                elastic[i] += sleep.elastic;
                body.max_volume = body.max_volume.max(sleep.max_volume);
            }
        }
        // what the transfers removed: the particles' kinetic energy before the scatter (as
        // the last step, or an edit, left it) less the grid's, and the grid's after the walls
        // less the particles' after the gather and the particle-side walls
        // A kinematic body's energy changes, and the work it does through contact, come from
        // outside: booked as energy brought in.
        for (i, body) in self.bodies.iter().enumerate() {
            if !body.kinematic {
                let step = &steps[i];
                let [before, after] = step.grid.kinetic;
                self.diagnostics.dissipated_numerical += body.stats.kinetic - before + after
                    - measures[i].kinetic
                    - gathered[i].dissipated_walls;
                // the stress update's integration error: the work the internal forces did on
                // the grid (its kinetic energy gained, less gravity's and a traction's work,
                // plus what the constraints removed) against the energy the update stored and removed
                let force_work =
                    after - before - step.grid.gravity_work - step.external + step.constraints;
                let s = &step.stress;
                let stored = elastic[i] - body.stats.elastic;
                self.diagnostics.dissipated_integration -=
                    force_work + stored + s.dissipated + s.viscous;
            } else {
                let s = &body.stats;
                let m = &measures[i];
                let j = steps[i].contact_impulse;
                let work = if s.mass > 0.0 {
                    -(0..3).map(|a| j[a] * s.momentum[a]).sum::<f64>() / s.mass
                } else {
                    0.0
                };
                self.diagnostics.energy_in +=
                    m.kinetic + m.gravitational - s.kinetic - s.gravitational + work;
            }
        }
        let bad = (0..self.bodies.len()).find_map(|i| {
            let bad = steps[i].stress.first_bad.or_else(|| {
                gathered[i]
                    .first_bad
                    .map(|p| (p, Bad::NonFinite("velocity or position")))
            });
            bad.map(|(particle, bad)| (i, particle, bad))
        });
        Finished {
            signal_speed: c,
            measures,
            elastic,
            bad,
        }
    }
}

/// What the step leaves the simulation to record: the largest signal speed after it (for its
/// CFL number), each body's measure and stored elastic energy, and the first body with an
/// unusable particle (body, particle, why).
pub struct Finished<D: Dim> {
    pub signal_speed: f64,
    pub measures: Vec<Measure<D>>,
    pub elastic: Vec<f64>,
    pub bad: Option<(usize, usize, Bad)>,
}

/// Why a particle's state is unusable after its update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bad {
    /// A quantity went non-finite: [`crate::Error::NonFinite`].
    NonFinite(&'static str),
    /// A finite stress with a volume of zero: the body was compressed further than its law
    /// can resist (the log-strain pressure stores at most about the constrained modulus per
    /// unit volume), so J fell each step until it underflowed: [`crate::Error::Crushed`].
    Crushed,
}

/// What the stress update measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct StressReport {
    /// Stored elastic energy Σ V W(σ) after the update.
    pub elastic: f64,
    /// Energy removed by plastic correction in this step.
    pub dissipated: f64,
    /// The largest particle volume (with the body's smallest particle mass it bounds the
    /// lowest density, for the wave speed).
    pub max_volume: Real,
    /// The fastest compression −tr ε̇ of the update (1/s; solids only, for the time step of the
    /// bulk viscosity), and the viscosity's work in the step.
    pub max_compression: Real,
    pub viscous: f64,
    /// Number of particles whose stress or volume went non-finite, and the first of them.
    pub bad: usize,
    pub first_bad: Option<(usize, Bad)>,
}

impl StressReport {
    /// Counts particle `q` as bad (its stress or, with a finite stress, its volume `v`: zero
    /// when the body was crushed flat).
    pub(super) fn bad(&mut self, q: usize, stress_finite: bool, v: Real) {
        self.bad += 1;
        let what = match (stress_finite, v.is_finite()) {
            (false, _) => Bad::NonFinite("stress"),
            (true, true) => Bad::Crushed,
            (true, false) => Bad::NonFinite("volume"),
        };
        self.first_bad.get_or_insert((q, what));
    }
}

/// What the gather pass measured (after the step): the figures of the particle state it
/// recorded ([`Measure`], which it dereferences to) and what it did itself.
#[derive(Clone, Copy, Debug)]
pub struct GatherReport<D: Dim> {
    pub measure: Measure<D>,
    /// Kinetic energy removed by the particle-side wall projection.
    pub dissipated_walls: f64,
    pub bad: usize,
    pub first_bad: Option<usize>,
}

impl<D: Dim> GatherReport<D> {
    /// Nothing recorded yet.
    pub fn empty() -> Self {
        GatherReport {
            measure: Measure::empty(),
            dissipated_walls: 0.0,
            bad: 0,
            first_bad: None,
        }
    }

    /// With the largest plastic strain of the particles.
    pub fn with_plastic_strain(mut self, plastic_strain: &[Real]) -> Self {
        self.measure = self.measure.with_plastic_strain(plastic_strain);
        self
    }
}

impl<D: Dim> std::ops::Deref for GatherReport<D> {
    type Target = Measure<D>;
    fn deref(&self) -> &Measure<D> {
        &self.measure
    }
}

impl<D: Dim> std::ops::DerefMut for GatherReport<D> {
    fn deref_mut(&mut self) -> &mut Measure<D> {
        &mut self.measure
    }
}
