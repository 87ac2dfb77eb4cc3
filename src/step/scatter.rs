//! Step 1: rasterise the particles' mass and momentum to their body's grid,
//!
//! m_i = Σ_p w_ip m_p,   (mv)_i = Σ_p w_ip m_p (v_p + C_p (x_i − x_p)),   v_i^n = (mv)_i / m_i,
//!
//! with C_p the APIC affine velocity (zero without APIC; see [`super::transfer`]). Bodies that
//! may touch another body also scatter the mass gradient ∇m_i = Σ_p m_p ∇w_ip, the contact
//! normal of Eq. 20.

use super::transfer::Transfer;
use super::{first_node, grid_coords, layout, third_axis, third_axis_nodes, with_kernel};
use crate::grid::{Grid, Node, stencil_span};
use crate::kernel::{Kernel, Stencil};
use crate::math::{Dim, Real, VectorOps};
use crate::sim::Simulation;

impl<D: Dim> Simulation<D> {
    /// Step 1 for every body: mass and momentum to its grid, then grid velocities.
    pub(super) fn scatter_to_grid(&mut self) {
        let p = &self.particles;
        let inv_h = self.world.inv_h;
        for body in &mut self.bodies {
            let r = body.range.clone();
            let affine = body.transfer.apic.then(|| &p.affine[r.clone()]);
            let (x, v, m) = (&p.x[r.clone()], &p.v[r.clone()], &p.mass[r]);
            let lp = body.radius * inv_h;
            with_kernel!(self.world.kernel, K, S => scatter::<D, K, S>(&mut body.grid, x, v, m, affine, inv_h, lp));
            grid_velocities(&mut body.grid);
        }
    }
}

/// Step 1 for one body: every particle's mass and momentum (and mass gradient, when the grid
/// keeps one) added to its stencil's nodes; then the halo nodes added to their owners.
pub fn scatter<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &mut Grid<D>,
    x: &[D::Vector],
    v: &[D::Vector],
    mass: &[Real],
    affine: Option<&[D::Grad]>,
    inv_h: Real,
    lp: Real,
) {
    let (p, span) = layout::<D, S>(grid);
    let Grid {
        layout,
        nodes,
        mass_grad,
        particle_node,
        ..
    } = &mut *grid;
    let with_gradient = !mass_grad.is_empty();
    let h = 1.0 / inv_h;
    for q in 0..x.len() {
        let st = K::stencil(grid_coords::<D>(x[q], inv_h), D::DIM, inv_h, lp);
        let origin = first_node(layout, particle_node[q], &st);
        let grad = if with_gradient {
            Some(&mut mass_grad[origin..origin + span])
        } else {
            None
        };
        scatter_particle::<D, S>(
            &mut nodes[origin..origin + span],
            grad,
            p,
            &st,
            mass[q],
            v[q] * mass[q],
            affine.map(|c| Transfer::affine_momentum::<D>(c[q], mass[q], h)),
        );
    }
    grid.reduce_nodes(|o, h| o.vm += h.vm);
    if with_gradient {
        grid.reduce_mass_gradient();
    }
}

/// One particle's share of step 1: m_i += w m and (mv)_i += w (mv + A d_i), with the APIC term
/// A = m C h (d_i: the node's offset from the particle in cells); with `grad`, also
/// ∇m_i += m ∇w. `nodes` starts at the stencil's first node, whose row length is `p`: node
/// (i, j, k) is `nodes[i + j p + k p²]`.
#[inline(always)]
pub fn scatter_particle<D: Dim, const S: usize>(
    nodes: &mut [Node<D::Vector>],
    mut grad: Option<&mut [D::Vector]>,
    p: usize,
    st: &Stencil<S>,
    m: Real,
    mv: D::Vector,
    affine: Option<D::Grad>,
) {
    let nodes = &mut nodes[..stencil_span(D::DIM, p, S)];
    let pm = mv.with_mass(m);
    let ax = affine
        .map(|a| D::column(&a, 0).with_mass(0.0))
        .unwrap_or_default();
    for k in 0..third_axis_nodes::<D, S>() {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        for j in 0..S {
            let base = j * p + k * p * p;
            let wjk = st.w[j][1] * wk;
            let row = &mut nodes[base..base + S];
            match affine {
                None => {
                    for i in 0..S {
                        row[i].vm += pm * (st.w[i][0] * wjk);
                    }
                }
                Some(a) => {
                    let mut r = mv + D::column(&a, 1) * st.d[j][1];
                    if D::DIM == 3 {
                        r += D::column(&a, 2) * st.d[k][2];
                    }
                    let r = r.with_mass(m);
                    for i in 0..S {
                        row[i].vm += (r + ax * st.d[i][0]) * (st.w[i][0] * wjk);
                    }
                }
            }
            if let Some(g) = grad.as_deref_mut() {
                let (djk, wdjk) = (st.dw[j][1] * wk, st.w[j][1] * dwk);
                for i in 0..S {
                    g[base + i] +=
                        D::vector([st.dw[i][0] * wjk, st.w[i][0] * djk, st.w[i][0] * wdjk]) * m;
                }
            }
        }
    }
}

/// Grid velocities v_i^n = (mv)_i / m_i, on every node, halos included (they are then
/// overwritten from their owners).
pub fn grid_velocities<D: Dim>(grid: &mut Grid<D>) {
    for node in &mut grid.nodes {
        let m = node.mass();
        if m > 0.0 {
            node.vm = (node.vel() / m).with_mass(m);
        }
    }
    grid.fill_nodes(|h, o| h.vm = o.vm);
}
