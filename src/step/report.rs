//! What the passes of one step hand on to each other, and what the step reports.
//!
//! [`BodyStep`] is the step's own state, one per body, made fresh at the start of each step:
//! whether walls or contacts changed the body's grid (the gather then caps its FLIP share,
//! [`super::transfer::Transfer::at_constraints`]), the momentum it received through contact,
//! and what its stress update measured. At the end `Simulation::finish_step` sums the
//! reports into the diagnostics and keeps what the next step needs (each body's fastest
//! compression and largest volume, for the time step).

use super::gather::GatherReport;
use crate::error::{Error, Result};
use crate::math::{Dim, Real};
use crate::sim::Simulation;

/// One body's part of the step's state (see the module documentation).
#[derive(Clone, Copy, Debug, Default)]
pub struct BodyStep {
    /// Whether a wall or a contact changed a velocity of this body's grid.
    pub constrained: bool,
    /// Momentum received through contact.
    pub contact_impulse: [f64; 3],
    /// What the stress update measured.
    pub stress: StressReport,
    /// The grid's kinetic energy at v_i^n and after the walls
    /// ([`super::grid_update::kinetic_energies`]; zero for a kinematic body).
    pub grid_kinetic: [f64; 2],
}

impl<D: Dim> Simulation<D> {
    /// Sums the step's reports into the diagnostics; fails on the first non-finite particle.
    pub(super) fn finish_step(
        &mut self,
        dt: f64,
        steps: &[BodyStep],
        gathered: &[GatherReport<D>],
    ) -> Result<()> {
        for (body, step) in self.bodies.iter_mut().zip(steps) {
            body.max_compression = step.stress.max_compression;
        }
        let c = self.max_wave_speed();
        let d = &mut self.diagnostics;
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
            if body.sleep.any() {
                measures[i].add_finished(&body.sleep.measure);
                elastic[i] += body.sleep.elastic;
                body.max_volume = body.max_volume.max(body.sleep.max_volume);
            }
        }
        // what the transfers removed: the particles' kinetic energy before the scatter (as
        // the last step, or an edit, left it) less the grid's, and the grid's after the walls
        // less the particles' after the gather and the particle-side walls
        // A kinematic body's energy changes, and the work it does through contact, come from
        // outside: booked as energy brought in.
        for (i, body) in self.bodies.iter().enumerate() {
            if !body.kinematic {
                let [before, after] = steps[i].grid_kinetic;
                self.diagnostics.dissipated_numerical += body.stats.kinetic - before + after
                    - measures[i].kinetic
                    - gathered[i].dissipated_walls;
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
        self.record_measures(dt, c, &measures, &elastic);
        for i in 0..self.bodies.len() {
            let bad = steps[i].stress.first_bad.or_else(|| {
                gathered[i]
                    .first_bad
                    .map(|p| (p, Bad::NonFinite("velocity or position")))
            });
            if let Some((particle, bad)) = bad {
                let body = self.scene.bodies[i].name.clone();
                let step = self.steps;
                let e = match bad {
                    Bad::Crushed => Error::Crushed {
                        body,
                        particle,
                        step,
                    },
                    Bad::NonFinite(quantity) => Error::NonFinite {
                        body,
                        particle,
                        quantity,
                        step,
                    },
                };
                self.failed = Some(e.clone());
                return Err(e);
            }
        }
        if let Some(e) = self.energy_guard() {
            self.failed = Some(e.clone());
            return Err(e);
        }
        Ok(())
    }
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
