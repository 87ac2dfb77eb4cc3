//! A traction boundary (not in the paper): a pressure p on faces of a body's free surface,
//! the confining pressure σ3 of a soil test.
//!
//! Each surface particle carries the area vector of its share of the loaded faces, marked when
//! the body was sampled as N dA ([`crate::config::TractionConfig`]) and carried with the
//! deformation by Nanson's formula n da = J F⁻ᵀ N dA, whose rate with the velocity gradient
//! L = ∇v is
//!
//! d(n da)/dt = (tr L) n da − Lᵀ n da,
//!
//! integrated over the step from the grid velocities v_i^n of step 1, with
//! L_p = Σ_i v_i ⊗ ∇w_ip. The traction t = −p n acts on the grid as the external force
//!
//! f_i += w_ip (−p n da)_p,
//!
//! added to the nodes' forces of step 4 before the grid velocities are updated. Its work over
//! the step, Σ_i f_i · ½(v_i^n + v*_i) Δt with the velocity v*_i = v_i^n + Δt (F_i/m_i + g)
//! that all the node's forces F_i give it, is energy brought in
//! ([`crate::Diagnostics::energy_in`]). The surface particles are few, so this pass walks
//! their stencils one by one on the nodes that own them ([`super::walk::on_owners`]).

use super::walk::{Stencils, on_owners};
use super::{BodyStep, Step};
use crate::grid::Grid;
use crate::kernel::{Kernel, with_kernel};
use crate::math::{Dim, Real, VectorOps};

impl<D: Dim> Step<'_, D> {
    /// The traction forces of every body under a traction, into its grid's forces.
    pub(super) fn apply_tractions(&mut self, dt: Real, steps: &mut [BodyStep]) {
        if self.particles.area.is_empty() {
            return;
        }
        let inv_h = self.world.inv_h;
        let kernel = self.world.kernel;
        let gravity = self.world.gravity;
        let p = &mut *self.particles;
        for (body, step) in self.bodies.iter_mut().zip(steps.iter_mut()) {
            if body.kinematic || body.traction == 0.0 {
                continue;
            }
            let r = body.active();
            let lp = body.radius * inv_h;
            let x = &p.x[r.clone()];
            let area = &mut p.area[r];
            let pressure = body.traction;
            let work = with_kernel!(kernel, K, S => traction::<D, K, S>(&mut body.grid, x, area, pressure, gravity, dt, inv_h, lp));
            step.external += work;
            self.diagnostics.energy_in += work;
        }
    }
}

/// For one body: each surface particle's area vector carried over the step, and its force
/// −p n da spread to the nodes (whose `new_vel` holds the other forces); returns the force's
/// work over the step (J; J/m in 2D).
#[allow(clippy::too_many_arguments)]
pub fn traction<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &mut Grid<D>,
    x: &[D::Vector],
    area: &mut [D::Vector],
    pressure: Real,
    gravity: D::Vector,
    dt: Real,
    inv_h: Real,
    lp: Real,
) -> f64 {
    // the traction force on each node, in node order
    let mut forces = std::collections::BTreeMap::<usize, D::Vector>::new();
    let mut stencils = Stencils::<D, K, S>::new(inv_h, lp);
    for (q, a) in area.iter_mut().enumerate() {
        if *a == D::Vector::ZERO {
            continue;
        }
        let st = stencils.at(x, q);
        // d(n da)/dt = (tr L) n da − Lᵀ n da = Σ_i [(v_i · ∇w_ip) n da − (v_i · n da) ∇w_ip].
        let mut rate = D::Vector::ZERO;
        on_owners::<D, K, S>(grid, &st, |n, w| {
            let (vi, g) = (grid.nodes[n].vel(), w.gradient());
            rate += *a * vi.dot(g) - g * vi.dot(*a);
        });
        *a += rate * dt;
        // f_i += w_ip (−p n da).
        let f = *a * -pressure;
        on_owners::<D, K, S>(grid, &st, |n, w| {
            *forces.entry(n).or_insert(D::Vector::ZERO) += f * w.value();
        });
    }
    let mut work = 0.0f64;
    for (&n, &f) in &forces {
        let node = &mut grid.nodes[n];
        node.new_vel += f;
        let m = node.mass();
        if m > 0.0 {
            let mean = node.vel() + (node.new_vel / m + gravity) * (0.5 * dt);
            work += (f.dot(mean) * dt) as f64;
        }
    }
    work
}
