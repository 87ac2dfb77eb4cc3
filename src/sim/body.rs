//! A body of the simulation, and the world settings every body sees.

use super::pour::Spout;
use super::stats::BodyStats;
use crate::boundary::{ContactRule, WallRule, Walls};
use crate::config::SceneConfig;
use crate::grid::Grid;
use crate::kernel::KernelKind;
use crate::material::{LOOSEST, Model};
use crate::math::{Dim, Real, VectorOps};
use crate::recipe::{BULK_VISCOSITY, Recipe};
use std::ops::Range;

/// Runtime constants derived from the scene's world settings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct World<D: Dim> {
    pub(crate) h: Real,
    pub(crate) inv_h: Real,
    pub(crate) gravity: D::Vector,
    pub(crate) cfl: f64,
    pub(crate) max_dt: f64,
    pub(crate) walls: Walls<D>,
    pub(crate) kernel: KernelKind,
    pub(crate) contact: ContactRule,
}

impl<D: Dim> World<D> {
    pub(crate) fn new(scene: &SceneConfig) -> Self {
        let h = scene.cell_size as Real;
        let g = scene.gravity_vector();
        let size = D::Vector::from_fn(|a| scene.domain.size[a] as Real);
        World {
            h,
            inv_h: 1.0 / h,
            gravity: D::Vector::from_fn(|a| g[a] as Real),
            cfl: scene.cfl,
            max_dt: scene.max_dt,
            walls: Walls::new(WallRule::from_config(&scene.boundary), size, h),
            kernel: scene.kernel,
            contact: match scene.contact.friction {
                None => ContactRule::Stick,
                Some(mu) => ContactRule::Friction(mu as Real),
            },
        }
    }
}

/// One body: a contiguous range of particles, its material and its own grid.
#[derive(Clone, Debug)]
pub struct Body<D: Dim> {
    pub(crate) model: Model,
    /// How the step treats it: transfer, FLIP share, stress order, volumetric rate, bulk
    /// viscosity.
    pub(crate) recipe: Recipe,
    pub(crate) range: Range<usize>,
    pub(crate) grid: Grid<D>,
    pub(crate) stats: BodyStats,
    /// The largest particle volume and the smallest particle mass, which bound the lowest
    /// density (for the wave speed).
    pub(crate) max_volume: Real,
    pub(crate) min_mass: Real,
    /// Half the particle spacing: how far a particle's material reaches (for the walls).
    pub(crate) radius: Real,
    /// Moves at its initial velocity whatever acts on it (see [`crate::config::BodyConfig::kinematic`]).
    pub(crate) kinematic: bool,
    /// The fastest compression |tr ε̇| of the latest stress update (for the bulk viscosity's
    /// share of the signal speed).
    pub(crate) max_compression: Real,
    /// Whether the latest contact pass held it to another solid that updates its stress last
    /// under a rule that sticks: its signal speed then bounds the next step at
    /// [`crate::boundary::STICKING_CFL`] ([`crate::Simulation::stable_dt`]).
    pub(crate) stuck: bool,
    /// How many of its particles, the last of its range, sleep: the step leaves them out
    /// (its sleeping state, [`crate::step::sleep`], keeps what they give the grid).
    pub(crate) asleep: usize,
    /// The pressure on its traction faces (Pa; zero without a traction): the force on a
    /// surface particle is −p n da ([`crate::step::traction`]).
    pub(crate) traction: Real,
    /// The spout that pours its particles, for a poured body ([`super::pour`]): the
    /// simulation adds its layers between steps; the step never reads it.
    pub(crate) spout: Option<Spout>,
}

impl<D: Dim> Body<D> {
    /// The particle indices of this body.
    pub fn range(&self) -> Range<usize> {
        self.range.clone()
    }
    /// The particle indices of this body that are stepped: all but the sleeping ones, which
    /// come last in [`Body::range`] ([`crate::step::sleep`]).
    pub fn active(&self) -> Range<usize> {
        self.range.start..self.range.end - self.asleep
    }
    /// Figures after the latest step.
    pub fn stats(&self) -> &BodyStats {
        &self.stats
    }
    /// The body's grid (blocks allocated in the latest step).
    pub fn grid(&self) -> &Grid<D> {
        &self.grid
    }
    /// The dilatational wave speed √((K + 4G/3)/ρ) at the body's lowest density (m/s); zero for
    /// a kinematic body, which carries no stress. When its parted grains close again
    /// ([`Recipe::closing`]) a granular body's density counts down to ρ/[`LOOSEST`]: looser
    /// grains have parted and carry no stress, and so no waves.
    pub fn wave_speed(&self) -> f64 {
        if self.kinematic {
            return 0.0;
        }
        let mut lowest_density = self.min_mass as f64 / self.max_volume as f64;
        if let (Some(packed), true) = (self.model.packed_specific_volume(), self.recipe.closing) {
            lowest_density = lowest_density.max(1.0 / (LOOSEST * packed as f64));
        }
        self.model.elastic().wave_speed(lowest_density)
    }

    /// The speed the time step must resolve (m/s): the wave speed c, raised by the bulk
    /// viscosity to Q + √(Q² + c²) with Q = C² h |tr ε̇|max (the explicit limit of a
    /// von Neumann–Richtmyer viscosity, as in the hydrocodes: a lone particle squeezed fast
    /// has a viscous pressure ρ (C h tr ε̇)² that grows without bound).
    pub fn signal_speed(&self) -> f64 {
        let c = self.wave_speed();
        // the fastest compression of the latest stress update
        let fastest = self.max_compression;
        let q = (BULK_VISCOSITY * self.recipe.bulk_length * fastest) as f64;
        q + (q * q + c * c).sqrt()
    }

    /// How the step treats this body.
    pub fn recipe(&self) -> &Recipe {
        &self.recipe
    }

    /// Whether its waves bound the time step: not when it is wholly asleep, since it then
    /// updates no stress (a body without particles keeps its bound).
    pub fn bounds_step(&self) -> bool {
        self.asleep < self.range.len() || self.range.is_empty()
    }

    /// The spout that pours it, for a poured body.
    pub fn spout(&self) -> Option<&Spout> {
        self.spout.as_ref()
    }
}

/// The largest signal speed of `bodies` (m/s) whose waves bound the step, see
/// [`Body::signal_speed`] and [`Body::bounds_step`].
pub(crate) fn max_signal_speed<'a, D: Dim + 'a>(
    bodies: impl IntoIterator<Item = &'a Body<D>>,
) -> f64 {
    bodies
        .into_iter()
        .filter(|b| b.bounds_step())
        .map(|b| b.signal_speed())
        .fold(0.0, f64::max)
}
