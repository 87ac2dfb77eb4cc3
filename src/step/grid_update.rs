//! Step 4, grid side: the grid velocities after the internal forces f_i (scattered by the
//! stress pass) and gravity g,
//!
//! v*_i = v_i^n + Δt (f_i / m_i + g),
//!
//! the explicit update of Dv/Dt = −(1/ρ) ∇·σ + g on the nodes. A kinematic body's grid keeps
//! the velocities its particles brought.

use crate::grid::Grid;
use crate::math::{Dim, Real};
use crate::sim::Simulation;

impl<D: Dim> Simulation<D> {
    /// Step 4 on every body's grid.
    pub(super) fn update_grid(&mut self, dt: Real) {
        for body in &mut self.bodies {
            if body.kinematic {
                hold_velocities(&mut body.grid);
            } else {
                grid_forces(&mut body.grid, self.world.gravity, dt);
            }
        }
    }
}

/// v*_i = v_i + Δt (f_i/m_i + g) on every node with mass (halos too: they are refilled before
/// the particles gather).
pub fn grid_forces<D: Dim>(grid: &mut Grid<D>, gravity: D::Vector, dt: Real) {
    for node in &mut grid.nodes {
        let m = node.mass();
        if m > 0.0 {
            node.new_vel = node.vel() + (node.new_vel / m + gravity) * dt;
        }
    }
}

/// A kinematic body's grid: v*_i = v_i.
pub fn hold_velocities<D: Dim>(grid: &mut Grid<D>) {
    for node in &mut grid.nodes {
        node.new_vel = node.vel();
    }
}
