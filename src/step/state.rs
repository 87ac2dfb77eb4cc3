//! What a step works on: the simulation's state, lent to the passes for one step.
//!
//! [`crate::Simulation`] owns the world settings, the particles, the bodies and the
//! diagnostics; for each step it lends them to a [`Step`], whose passes (one file each, see
//! [`super`]) read and write them. What the passes hand on to each other within the step is in
//! [`super::report`]; what the step keeps from one step to the next, sleeping, in
//! [`super::sleep`].

use crate::math::Dim;
use crate::sim::body::{Body, World};
use crate::sim::particles::Particles;
use crate::sim::stats::{Diagnostics, PassTimings};

/// The simulation's state lent to one step.
pub(crate) struct Step<'a, D: Dim> {
    pub world: &'a World<D>,
    pub particles: &'a mut Particles<D>,
    pub bodies: &'a mut [Body<D>],
    pub diagnostics: &'a mut Diagnostics,
    /// Wall-clock time per pass, accumulated while `Some`.
    pub timings: &'a mut Option<PassTimings>,
    /// The steps taken before this one, and every how many steps the particles are reordered
    /// by grid block (0: never).
    pub steps: u64,
    pub sort_interval: u64,
}
