//! The grid side of steps 1 and 4: the grid velocities before and after the internal forces
//! f_i and gravity g,
//!
//! v_i^n = (mv)_i / m_i,   v*_i = v_i^n + Δt (f_i / m_i + g),
//!
//! the explicit update of Dv/Dt = −(1/ρ) ∇·σ + g on the nodes. A kinematic body's grid keeps
//! the velocities its particles brought.

use super::Step;
use super::StressOrder;
use crate::grid::Grid;
use crate::math::{Dim, Real, VectorOps};

impl<D: Dim> Step<'_, D> {
    /// v_i^n on every body's grid (for bodies whose stress is updated first, the halos too:
    /// the stress pass reads them).
    pub(super) fn grid_velocities(&mut self) {
        for body in self.bodies.iter_mut() {
            grid_velocities(&mut body.grid);
            if body.recipe.stress_order == StressOrder::First {
                body.grid.fill_nodes(|h, o| h.vm = o.vm);
            }
        }
    }

    /// Step 4 on every body's grid.
    pub(super) fn grid_forces(&mut self, dt: Real) {
        for body in self.bodies.iter_mut() {
            if body.kinematic {
                hold_velocities(&mut body.grid);
            } else {
                grid_forces(&mut body.grid, self.world.gravity, dt);
            }
        }
    }
}

/// v_i^n = (mv)_i / m_i on every node with mass.
pub fn grid_velocities<D: Dim>(grid: &mut Grid<D>) {
    for node in &mut grid.nodes {
        let m = node.mass();
        if m > 0.0 {
            node.vm = (node.vel() / m).with_mass(m);
        }
    }
}

/// v*_i = v_i^n + Δt (f_i/m_i + g) on every node with mass, and zero where no weight reached
/// (a node's gradient weight may be finite where its weight is not; the velocity gradient
/// must read no force there). Halos too: they are refilled before the particles gather.
pub fn grid_forces<D: Dim>(grid: &mut Grid<D>, gravity: D::Vector, dt: Real) {
    for node in &mut grid.nodes {
        let m = node.mass();
        node.new_vel = if m > 0.0 {
            node.vel() + (node.new_vel / m + gravity) * dt
        } else {
            D::Vector::ZERO
        };
    }
}

/// A kinematic body's grid: v*_i = v_i^n.
pub fn hold_velocities<D: Dim>(grid: &mut Grid<D>) {
    for node in &mut grid.nodes {
        node.new_vel = node.vel();
    }
}

/// The grid's kinetic energies Σ ½ m_i |v_i|² over the nodes it owns: at v_i^n (as the
/// particles brought it) and at the velocities the particles will gather (after forces,
/// contacts and walls). With the particles' kinetic energies before the scatter and after the
/// gather they measure what the transfers remove ([`crate::Diagnostics::dissipated_numerical`]).
pub fn kinetic_energies<D: Dim>(grid: &Grid<D>) -> [f64; 2] {
    let mut k = [0.0f64; 2];
    for slot in 0..grid.index.block_count() {
        grid.layout.for_each_owned(&grid.index, slot, |_, n| {
            let node = &grid.nodes[n];
            let m = node.mass() as f64;
            k[0] += m * node.vel().length_squared() as f64;
            k[1] += m * node.new_vel.length_squared() as f64;
        });
    }
    k.map(|x| 0.5 * x)
}
