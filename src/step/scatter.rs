//! Step 1: rasterise the particles' mass and momentum to their body's grid,
//!
//! m_i = Σ_p w_ip m_p,   (mv)_i = Σ_p w_ip m_p (v_p + C_p (x_i − x_p)),
//!
//! with C_p the APIC affine velocity (zero without APIC; see [`super::transfer`]). For bodies
//! whose stress is updated last ([`super::StressOrder`]) the same walk also scatters the internal
//! forces of step 4, f_i = −Σ_p V_p (σ_p − q_p I) ∇w_ip, from the stress, volume and bulk
//! viscosity q_p ([`super::stress`]) the previous step's gather left. Bodies that may touch
//! another body also scatter the mass gradient ∇m_i = Σ_p m_p ∇w_ip, the contact normal of
//! Eq. 20.

use super::transfer::Transfer;
use super::{
    Stencils, first_axis_nodes, first_node, layout, second_axis_nodes, third_axis,
    third_axis_nodes, with_kernel,
};
use crate::grid::{Grid, Node, stencil_span};
use crate::kernel::{Kernel, Stencil};
use crate::math::{Dim, Real, SymTensor, Vec4, VectorOps};
use crate::sim::Simulation;

impl<D: Dim> Simulation<D> {
    /// Step 1 (and the forces of step 4, stress updated last) for every body.
    pub(super) fn scatter_to_grid(&mut self) {
        let p = &self.particles;
        let inv_h = self.world.inv_h;
        for body in &mut self.bodies {
            let last = body.recipe.stress_order == super::StressOrder::Last;
            let r = body.range.clone();
            let state = ScatterState {
                x: &p.x[r.clone()],
                v: &p.v[r.clone()],
                mass: &p.mass[r.clone()],
                // A kinematic body carries no stress.
                stress: (last && !body.kinematic).then(|| {
                    (
                        &p.stress[r.clone()],
                        &p.volume[r.clone()],
                        &p.viscous_pressure[r.clone()],
                    )
                }),
                affine: body.recipe.apic.then(|| &p.affine[r]),
            };
            let lp = body.radius * inv_h;
            with_kernel!(self.world.kernel, K, S => scatter::<D, K, S>(&mut body.grid, state, inv_h, lp));
        }
    }
}

/// The particles' stress, volume and bulk viscosity's pressure, which make their forces.
pub type ForceState<'a, D> = (&'a [<D as Dim>::Sym], &'a [Real], &'a [Real]);

/// The particle state the scatter reads.
pub struct ScatterState<'a, D: Dim> {
    pub x: &'a [D::Vector],
    pub v: &'a [D::Vector],
    pub mass: &'a [Real],
    /// Stress, volume and bulk viscosity's pressure q, for the forces of bodies that carry
    /// stress (stress updated last).
    pub stress: Option<ForceState<'a, D>>,
    /// The APIC affine velocities, for APIC bodies.
    pub affine: Option<&'a [D::Grad]>,
}

/// Step 1 for one body: every particle's mass, momentum, force (with `ps.stress`) and mass
/// gradient (when the grid keeps one) added to its stencil's nodes; then the halo nodes added
/// to their owners.
pub fn scatter<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &mut Grid<D>,
    ps: ScatterState<'_, D>,
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
    // F = −V (σ − q I): the viscous pressure of the latest update acts with the stress.
    let force = |i: usize| {
        ps.stress
            .map(|(s, v, q)| (s[i] - D::Sym::iso(q[i])) * -v[i])
    };
    let mut stencils = Stencils::<D, K, S>::new(inv_h, lp);
    // One loop per combination of the force, APIC and contact (mass gradient) terms, each
    // compiled in or out.
    macro_rules! walk {
        ($force:expr, $affine:expr, $gradient:expr) => {
            for q in 0..ps.x.len() {
                let st = stencils.at(ps.x, q);
                let origin = first_node(layout, particle_node[q], &st);
                let cell = &mut nodes[origin..origin + span];
                let (m, f, a) = (ps.mass[q], $force(q), $affine(q));
                if D::DIM == 2 && a.is_none() && !$gradient {
                    scatter_2d_packed::<D, K, S>(cell, p, &st, m, ps.v[q] * m, f);
                } else {
                    let g = $gradient.then(|| &mut mass_grad[origin..origin + span]);
                    scatter_particle::<D, K, S>(cell, g, p, &st, m, ps.v[q] * m, a, f);
                }
            }
        };
    }
    macro_rules! with_affine {
        ($force:expr, $gradient:expr) => {
            match ps.affine {
                None => walk!($force, |_| None, $gradient),
                Some(c) => {
                    let m = ps.mass;
                    walk!(
                        $force,
                        |q: usize| Some(Transfer::affine_momentum::<D>(c[q], m[q], h)),
                        $gradient
                    )
                }
            }
        };
    }
    match (ps.stress.is_some(), with_gradient) {
        (true, false) => with_affine!(force, false),
        (false, false) => with_affine!(|_| None, false),
        (true, true) => with_affine!(force, true),
        (false, true) => with_affine!(|_| None, true),
    }
    if ps.stress.is_some() {
        grid.reduce_nodes(|o, h| {
            o.vm += h.vm;
            o.new_vel += h.new_vel;
        });
    } else {
        grid.reduce_nodes(|o, h| o.vm += h.vm);
    }
    if with_gradient {
        grid.reduce_mass_gradient();
    }
}

/// One particle's share: m_i += w m, (mv)_i += w (mv + A d_i) with the APIC term A = m C h
/// (d_i: the node's offset from the particle in cells); with `force` F = −V σ, f_i += F ∇w
/// (into the nodes' `new_vel`); with `grad`, ∇m_i += m ∇w. `nodes` starts at the stencil's
/// first node, whose row length is `p`: node (i, j, k) is `nodes[i + j p + k p²]`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn scatter_particle<D: Dim, K: Kernel<S>, const S: usize>(
    nodes: &mut [Node<D::Vector>],
    mut grad: Option<&mut [D::Vector]>,
    p: usize,
    st: &Stencil<S>,
    m: Real,
    mv: D::Vector,
    affine: Option<D::Grad>,
    force: Option<D::Sym>,
) {
    let nodes = &mut nodes[..stencil_span(D::DIM, p, S)];
    let pm = mv.with_mass(m);
    let ax = affine
        .map(|a| D::column(&a, 0).with_mass(0.0))
        .unwrap_or_default();
    let [f0, f1, f2] = D::sym_columns(force.unwrap_or(D::Sym::ZERO));
    // The first axis's weights as vectors, once.
    let w: [D::Vector; S] = std::array::from_fn(|i| D::Vector::splat(st.w[i][0]));
    let dw: [D::Vector; S] = std::array::from_fn(|i| D::Vector::splat(st.dw[i][0]));
    for k in 0..third_axis_nodes::<D, K, S>(st) {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        for j in 0..second_axis_nodes::<D, K, S>(st) {
            let base = j * p + k * p * p;
            let wjk = st.w[j][1] * wk;
            // F ∇w = F e_x ∂_x w + F e_y ∂_y w (+ F e_z ∂_z w): the row's factors first.
            let fx = f0 * wjk;
            let mut fyz = f1 * (st.dw[j][1] * wk);
            if D::DIM == 3 {
                fyz += f2 * (st.w[j][1] * dwk);
            }
            let row = &mut nodes[base..base + S];
            match affine {
                None => {
                    for i in 0..first_axis_nodes::<D, K, S>(st) {
                        row[i].vm += pm * (st.w[i][0] * wjk);
                        if force.is_some() {
                            row[i].new_vel += fx * dw[i] + fyz * w[i];
                        }
                    }
                }
                Some(a) => {
                    let mut r = mv + D::column(&a, 1) * st.d[j][1];
                    if D::DIM == 3 {
                        r += D::column(&a, 2) * st.d[k][2];
                    }
                    let r = r.with_mass(m);
                    for i in 0..first_axis_nodes::<D, K, S>(st) {
                        row[i].vm += (r + ax * st.d[i][0]) * (st.w[i][0] * wjk);
                        if force.is_some() {
                            row[i].new_vel += fx * dw[i] + fyz * w[i];
                        }
                    }
                }
            }
            if let Some(g) = grad.as_deref_mut() {
                let (djk, wdjk) = (st.dw[j][1] * wk, st.w[j][1] * dwk);
                for i in 0..first_axis_nodes::<D, K, S>(st) {
                    g[base + i] +=
                        D::vector([st.dw[i][0] * wjk, st.w[i][0] * djk, st.w[i][0] * wdjk]) * m;
                }
            }
        }
    }
}

/// [`scatter_particle`] in 2D without APIC or mass gradient, packing specialisation: a
/// node's force from both columns of F in one `Vec4`, (F_xx, F_xy) ∂_x w_i and
/// (F_xy, F_yy) ∂_y w_i side by side.
#[inline(always)]
pub fn scatter_2d_packed<D: Dim, K: Kernel<S>, const S: usize>(
    nodes: &mut [Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
    m: Real,
    mv: D::Vector,
    force: Option<D::Sym>,
) {
    debug_assert_eq!(D::DIM, 2);
    let nodes = &mut nodes[..stencil_span(2, p, S)];
    let pm = mv.with_mass(m);
    let [c0, c1, _] = D::sym_columns(force.unwrap_or(D::Sym::ZERO));
    let f = Vec4::new(c0[0], c0[1], c1[0], c1[1]);
    for j in 0..second_axis_nodes::<D, K, S>(st) {
        let fj = f * Vec4::new(st.w[j][1], st.w[j][1], st.dw[j][1], st.dw[j][1]);
        let row = &mut nodes[j * p..j * p + S];
        for i in 0..first_axis_nodes::<D, K, S>(st) {
            row[i].vm += pm * (st.w[i][0] * st.w[j][1]);
            if force.is_some() {
                let t = fj * Vec4::new(st.dw[i][0], st.dw[i][0], st.w[i][0], st.w[i][0]);
                row[i].new_vel += D::vector([t.x + t.z, t.y + t.w, 0.0]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{Gimp, Linear};
    use crate::math::{D2, Sym2};
    use crate::step::test_util::random_stencils;

    /// The packed 2D scatter adds to the nodes what the generic one adds, up to rounding.
    fn packed_scatter_matches<K: Kernel<S>, const S: usize>() {
        let p = 10;
        let (nodes, stencils) = random_stencils::<D2, K, S>(50, p);
        let f = Sym2 {
            xx: 1.5,
            yy: -0.7,
            zz: 0.2,
            xy: 0.4,
        };
        let mv = crate::math::Vec2::new(0.3, -1.2);
        let (mut a, mut b) = (nodes.clone(), nodes);
        for st in &stencils {
            scatter_particle::<D2, K, S>(&mut a, None, p, st, 2.5, mv, None, Some(f));
            scatter_2d_packed::<D2, K, S>(&mut b, p, st, 2.5, mv, Some(f));
        }
        for (x, y) in a.iter().zip(&b) {
            assert!((x.vm - y.vm).length() <= 1e-5 * (1.0 + x.vm.length()));
            assert!((x.new_vel - y.new_vel).length() <= 1e-5 * (1.0 + x.new_vel.length()));
        }
    }

    #[test]
    fn packed_2d_scatter_matches_the_generic_one() {
        packed_scatter_matches::<Linear, 2>();
        packed_scatter_matches::<Gimp, 3>();
    }
}
