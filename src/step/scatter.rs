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

use super::Step;
use super::transfer::Transfer;
use super::walk::{Walker, Weights, scatter as spread, scatter_pair};
use crate::grid::Grid;
use crate::grid::Node;
use crate::kernel::{Kernel, with_kernel};
use crate::math::{Dim, Real, SymTensor, VectorOps};

impl<D: Dim> Step<'_, D> {
    /// Step 1 (and the forces of step 4, stress updated last) for every body.
    pub(super) fn scatter_to_grid(&mut self) {
        let p = &*self.particles;
        let inv_h = self.world.inv_h;
        for body in self.bodies.iter_mut() {
            let last = body.recipe.stress_order == super::StressOrder::Last;
            let r = body.active();
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

/// Step 4's internal force at the nodes is f_i = Σ_p F_p ∇w_ip with, for each particle,
///
/// F_p = −V_p (σ_p − q_p I),
///
/// its stress less the bulk viscosity's pressure q_p (`viscous`; none for sand) times minus
/// its volume. Both stress orders scatter it: [`scatter`] the next step's with the stress
/// updated last, [`super::stress::update_stress_first`] its own.
#[inline(always)]
pub fn internal_force<D: Dim>(stress: D::Sym, volume: Real, viscous: Option<Real>) -> D::Sym {
    let sigma = match viscous {
        Some(q) => stress - D::Sym::iso(q),
        None => stress,
    };
    sigma * -volume
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
    let Grid {
        layout,
        nodes,
        mass_grad,
        particle_node,
        ..
    } = &mut *grid;
    let with_gradient = !mass_grad.is_empty();
    let h = 1.0 / inv_h;
    // F_p ([`internal_force`]): the viscous pressure of the latest update acts with the stress.
    let force = |i: usize| {
        ps.stress
            .map(|(s, v, q)| internal_force::<D>(s[i], v[i], Some(q[i])))
    };
    let mut walker = Walker::<D, K, S>::new(layout, particle_node, inv_h, lp);
    // One loop per combination of the force, APIC and contact (mass gradient) terms, each
    // compiled in or out.
    macro_rules! walk {
        ($force:expr, $affine:expr, $gradient:expr) => {
            for q in 0..ps.x.len() {
                let at = walker.at(ps.x, q);
                let m = ps.mass[q];
                let (mv, affine, force) = (ps.v[q] * m, $affine(q), $force(q));
                // A_p's columns with mass 0, to add to the momentum with mass m_p.
                let columns = affine.map(|a: D::Grad| {
                    [0, 1, 2].map(|c| {
                        let column = if c < D::DIM {
                            D::column(&a, c)
                        } else {
                            D::Vector::ZERO
                        };
                        column.with_mass(0.0)
                    })
                });
                let pm = mv.with_mass(m);
                // m_i += w_ip m_p, (mv)_i += w_ip (m_p v_p + A_p d_i), f_i += F_p ∇w_ip.
                let term = |n: &mut Node<D::Vector>, w: &Weights<D>| {
                    let p = match columns {
                        None => pm,
                        Some(c) => w.plus_offset(pm, c),
                    };
                    n.vm += p * w.value();
                    if let Some(f) = force {
                        n.new_vel += w.gradient_times(f);
                    }
                };
                // ∇m_i += m_p ∇w_ip.
                let gradient = |g: &mut D::Vector, w: &Weights<D>| *g += w.gradient() * m;
                if $gradient && D::DIM == 3 {
                    // Both in one walk in 3D (in 2D two walks take fewer instructions).
                    scatter_pair::<D, K, S, _, _>(nodes, mass_grad, &at, |n, g, w| {
                        term(n, &w);
                        gradient(g, &w);
                    });
                } else {
                    spread::<D, K, S, _>(nodes, &at, |n, w| term(n, &w));
                    if $gradient {
                        spread::<D, K, S, _>(mass_grad, &at, |g, w| gradient(g, &w));
                    }
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
