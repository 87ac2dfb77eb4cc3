//! Step 5 at the walls of the domain, on the grid: every node on or beyond a wall takes the
//! wall rule ([`crate::boundary::WallRule`]: the normal velocity into the wall removed, and
//! with friction the tangential speed reduced by μ|v_n|, Coulomb friction proportional to the
//! pressure). Then the halo nodes take their owners' values, for the gather.

use super::Step;
use super::sleep::Sleeping;
use super::{BodyStep, constraint_dissipation};
use crate::boundary::Walls;
use crate::grid::Grid;
use crate::math::Dim;

impl<D: Dim> Step<'_, D> {
    /// Step 5 at the walls for every body (noting in `steps` which ones they changed, and the
    /// grid's kinetic energies, on the awake particles' share of the nodes: `sleeping`); then
    /// the halos take their owners' values.
    pub(super) fn apply_walls(&mut self, steps: &mut [BodyStep], sleeping: &Sleeping<D>, dt: f64) {
        for (i, (body, step)) in self.bodies.iter_mut().zip(steps).enumerate() {
            if !body.kinematic {
                let w = grid_walls(&mut body.grid, &self.world.walls);
                self.diagnostics.dissipated_boundary += w.dissipated;
                step.constrained |= w.changed;
                step.constraints += w.dissipated;
                let frozen = |b: &[i32; 3]| sleeping.frozen_mass(i, b);
                let gravity = self.world.gravity;
                step.grid = super::grid_update::kinetic_energies(&body.grid, frozen, gravity, dt);
            }
            body.grid.fill_nodes(|h, o| *h = *o);
        }
    }
}

/// What the walls did to one body's grid.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallsApplied {
    /// Energy removed (see [`constraint_dissipation`]).
    pub dissipated: f64,
    /// Whether any node velocity changed (for [`super::transfer::Transfer::at_constraints`]).
    pub changed: bool,
}

/// Constrains the nodes on or beyond the domain's faces.
pub fn grid_walls<D: Dim>(grid: &mut Grid<D>, walls: &Walls<D>) -> WallsApplied {
    let edge = Grid::<D>::BLOCK as i32;
    let mut dissipated = 0.0;
    let mut changed = false;
    let Grid {
        index,
        layout,
        nodes,
        ..
    } = grid;
    for slot in 0..index.block_count() {
        if !walls.block_touches(index.block_origin(slot), edge) {
            continue;
        }
        layout.for_each_owned(index, slot, |coord, n| {
            let node = &mut nodes[n];
            let m = node.mass();
            if m <= 0.0 {
                return;
            }
            let before = node.new_vel;
            let after = walls.node_velocity(coord, before);
            if after != before {
                dissipated += constraint_dissipation(m, node.vel(), before, after);
                node.new_vel = after;
                changed = true;
            }
        });
    }
    WallsApplied {
        dissipated,
        changed,
    }
}
