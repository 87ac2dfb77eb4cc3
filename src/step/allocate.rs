//! Before step 1: each body's sparse grid, the blocks of nodes its particles' stencils reach
//! (the paper's grid is dense; here cost and memory follow the particles, never the domain).
//! Every few steps the particles are reordered by grid block, so that consecutive particles
//! touch the same nodes and the transfers stay in cache. Then the pairs of bodies whose grids
//! share blocks are found, for the contact of step 5.

use super::Step;
use super::contact::ContactPair;
use super::walk::grid_coords;
use crate::grid::GridIndex;
use crate::kernel::{Kernel, with_kernel};
use crate::math::Dim;

impl<D: Dim> Step<'_, D> {
    /// Allocates each body's grid blocks where its particles are, reorders particles by block
    /// now and then, and finds the bodies whose grids overlap (into `contacts`).
    pub(super) fn allocate_grids(&mut self, contacts: &mut Vec<ContactPair>) {
        let (kernel, inv_h) = (self.world.kernel, self.world.inv_h);
        let sort = self.sort_interval > 0 && self.steps.is_multiple_of(self.sort_interval);
        for body in self.bodies.iter_mut() {
            let x = &self.particles.x[body.range.clone()];
            let lp = body.radius * inv_h;
            with_kernel!(kernel, K, S => body.grid.rebuild(x.len(), S, |p| {
                K::base(grid_coords::<D>(x[p], inv_h), D::DIM, lp)
            }));
            if sort {
                let active = body.active();
                let grid = &mut body.grid;
                let padded = grid.layout.padded_nodes() as u32;
                let blocks: Vec<u32> = grid.particle_node.iter().map(|&n| n / padded).collect();
                // the sleeping particles stay last, unsorted (no pass walks them)
                let awake = &blocks[..active.len()];
                if awake.windows(2).any(|w| w[0] > w[1]) {
                    let order = counting_sort(awake, grid.index.block_count());
                    self.particles.permute(active, &order);
                    let nodes = &grid.particle_node;
                    let sorted = order.iter().map(|&o| nodes[o as usize]);
                    let asleep = nodes[awake.len()..].iter().copied();
                    grid.particle_node = sorted.chain(asleep).collect();
                }
            }
        }
        let indices: Vec<&GridIndex<D>> = self.bodies.iter().map(|b| &b.grid.index).collect();
        super::contact::find_pairs(&indices, contacts);
        for pair in contacts.iter() {
            for i in [pair.a, pair.b] {
                if self.bodies[i].grid.mass_grad.is_empty() {
                    self.bodies[i].grid.enable_mass_gradient();
                }
            }
        }
    }
}

/// The permutation that sorts `keys` (all below `n`) stably.
fn counting_sort(keys: &[u32], n: usize) -> Vec<u32> {
    let mut start = vec![0u32; n + 1];
    for &k in keys {
        start[k as usize + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut order = vec![0u32; keys.len()];
    for (p, &k) in keys.iter().enumerate() {
        order[start[k as usize] as usize] = p as u32;
        start[k as usize] += 1;
    }
    order
}
