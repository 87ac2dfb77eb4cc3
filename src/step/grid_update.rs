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

/// The grid's kinetic energies Σ ½ m_i |v_i|² over the nodes it owns, at v_i^n (as the
/// particles brought it) and at v_i^{n+1}, the velocities the particles will gather (after
/// forces, contacts and walls), and the work gravity did on them, Σ Δt m_i g·(v_i^n +
/// v_i^{n+1})/2. With the particles' kinetic energies before the scatter and after the gather
/// they measure what the transfers remove ([`crate::Diagnostics::dissipated_numerical`]);
/// with gravity's work and the constraints' the work the internal forces did
/// ([`crate::Diagnostics::dissipated_integration`]). Only the awake particles' share of a
/// node's mass counts: `frozen` gives the sleeping particles' mass on each owned node of a
/// block ([`super::sleep::Sleeping::frozen_mass`]), which no step moves.
pub fn kinetic_energies<'a, D: Dim>(
    grid: &Grid<D>,
    frozen: impl Fn(&[i32; 3]) -> Option<&'a [Real]>,
    gravity: D::Vector,
    dt: f64,
) -> GridEnergies {
    let mut k = [0.0f64; 3];
    for_each_awake(grid, frozen, |node, awake| {
        let (v0, v1) = (node.vel(), node.new_vel);
        k[0] += (awake * v0.length_squared()) as f64;
        k[1] += (awake * v1.length_squared()) as f64;
        k[2] += (awake * gravity.dot(v0 + v1)) as f64;
    });
    GridEnergies {
        kinetic: [0.5 * k[0], 0.5 * k[1]],
        gravity_work: 0.5 * dt * k[2],
    }
}

/// What [`kinetic_energies`] measures.
#[derive(Clone, Copy, Debug, Default)]
pub struct GridEnergies {
    /// Σ ½ m_i |v_i|² at v_i^n and at v_i^{n+1}.
    pub kinetic: [f64; 2],
    /// Σ Δt m_i g·(v_i^n + v_i^{n+1})/2.
    pub gravity_work: f64,
}

/// Calls `f` with each owned node that has mass and the awake particles' share of its mass
/// (all of it, but for the sleeping particles' mass `frozen` gives).
fn for_each_awake<'a, D: Dim>(
    grid: &Grid<D>,
    frozen: impl Fn(&[i32; 3]) -> Option<&'a [Real]>,
    mut f: impl FnMut(&crate::grid::Node<D::Vector>, Real),
) {
    for slot in 0..grid.index.block_count() {
        let asleep = frozen(&grid.index.blocks()[slot]);
        let mut k = 0;
        grid.layout.for_each_owned(&grid.index, slot, |_, n| {
            let node = &grid.nodes[n];
            let m = node.mass();
            let awake = match asleep {
                Some(mass) => (m - mass[k]).max(0.0),
                None => m,
            };
            k += 1;
            if m > 0.0 {
                f(node, awake);
            }
        });
    }
}
