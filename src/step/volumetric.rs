//! Sand's cell-averaged volumetric rate (an option, `"volumetric_rate": "cell_average"`, off
//! by default): the stress update ([`super::stress`]) takes ∇v_p with its volumetric part
//! replaced by the volume-weighted mean over the body's particles in the particle's grid
//! cell c,
//!
//! ∇v̄_p = ∇v_p + (⟨tr ε̇⟩_c − tr ε̇_p)/d I,   ⟨tr ε̇⟩_c = Σ_{q∈c} V_q tr ε̇_q / Σ_{q∈c} V_q,
//!
//! keeping each particle's deviatoric rate and spin. With ψ = 0 sand flows at constant volume,
//! and a coarse grid's velocity field, sampled at several particles per cell, cannot shear
//! without spurious volume changes that the bulk modulus resists: the sand grows stronger with
//! more particles per cell (volumetric locking). One volume rate per cell leaves it as many
//! volume constraints as cells, as Coombs et al. (2018, *Overcoming volumetric locking in
//! material point methods*, CMAME 333) do with a cell-averaged dilatation. It costs one more
//! walk over the particles ([`sum_cell_dilatation`]) and an array laid out like the nodes.

use super::walk::{self, Walker};
use crate::grid::Grid;
use crate::kernel::Kernel;
use crate::math::{Dim, Real};

/// The first walk of sand's cell-averaged volumetric rate: for each cell holding particles of
/// the body, Σ_p V_p tr ε̇_p and Σ_p V_p over them (tr ε̇_p = tr ∇v_p from the grid velocities
/// v_i^n, V_p at the start of the step), into `grid.cell_dilatation` at the cell's lowest node,
/// whose halo copies are then added into their owners and copied back, so that every particle
/// of a cell reads the same sums whichever block it is handled by.
#[inline(never)]
pub fn sum_cell_dilatation<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &mut Grid<D>,
    x: &[D::Vector],
    volume: &[Real],
    inv_h: Real,
    lp: Real,
) {
    let Grid {
        index,
        layout,
        nodes,
        particle_node,
        cell_dilatation: sums,
        ..
    } = &mut *grid;
    sums.clear();
    sums.resize(nodes.len(), [0.0; 2]);
    let mut walker = Walker::<D, K, S>::new(layout, particle_node, inv_h, lp);
    for q in 0..x.len() {
        let at = walker.at(x, q);
        let grad = walk::gradient::<D, K, S>(nodes, &at, |n| n.vel());
        let v = volume[q];
        let s = &mut sums[walk::cell_node::<D, S>(x[q], inv_h, &at)];
        s[0] += v * divergence::<D>(&grad);
        s[1] += v;
    }
    layout.reduce_halo(index, sums, |o, h| {
        o[0] += h[0];
        o[1] += h[1];
    });
    layout.fill_halo(index, sums, |h, o| *h = *o);
}

/// tr ∇v = ∇·v.
#[inline(always)]
pub fn divergence<D: Dim>(grad: &D::Grad) -> Real {
    (0..D::DIM).map(|a| D::grad_entry(grad, a, a)).sum()
}

/// ∇v with its volumetric part tr ∇v / d replaced by `rate` / d: ∇v + (rate − tr ∇v)/d I
/// (I in the plane in 2D, where plane strain has no zz rate).
#[inline(always)]
pub fn with_volumetric_rate<D: Dim>(grad: D::Grad, rate: Real) -> D::Grad {
    let d = D::DIM as Real;
    let mut g = grad;
    g += D::from_columns([0, 1, 2].map(|a| {
        let mut e = [0.0; 3];
        e[a] = 1.0;
        D::vector(e)
    })) * ((rate - divergence::<D>(&grad)) / d);
    g
}
