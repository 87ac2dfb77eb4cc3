//! What the passes of one step hand on to each other, and what the step reports.
//!
//! [`BodyStep`] is the step's own state, one per body, made fresh at the start of each step:
//! whether walls or contacts changed the body's grid (the gather then caps its FLIP share,
//! [`super::transfer::Transfer::at_constraints`]), the momentum it received through contact,
//! and what its stress update measured. At the end [`Simulation::finish_step`] sums the
//! reports into the diagnostics and keeps what the next step needs (each body's fastest
//! compression and largest volume, for the time step).

use super::gather::GatherReport;
use super::stress::{Bad, StressReport};
use crate::error::{Error, Result};
use crate::math::Dim;
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
        let measures: Vec<_> = gathered.iter().map(|g| g.measure).collect();
        let elastic: Vec<f64> = steps.iter().map(|s| s.stress.elastic).collect();
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
        Ok(())
    }
}
