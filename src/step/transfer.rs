//! How a body's velocities travel between its particles and the grid: the choice the scatter
//! (step 1) and the gather (step 6) make for each body, in one place.
//!
//! - **PIC/FLIP blend** (the paper's step 6): v_p ← (1 − α) v_PIC + α v_FLIP with
//!   v_PIC = Σ_i w_ip v_i^{n+1} and v_FLIP = v_p + Σ_i w_ip (v_i^{n+1} − v_i^n). PIC (α = 0)
//!   is stable and smooth but damps; FLIP (α = 1) keeps the energy and the noise.
//! - **APIC** (Jiang et al. 2015): each particle also carries an affine velocity C_p, given
//!   to the nodes as m_p (v_p + C_p (x_i − x_p)) and gathered back as C_p = B_p D_p⁻¹ with
//!   B_p = Σ_i w_ip v_i^{n+1} (x_i − x_p)ᵀ and D_p = Σ_i w_ip (x_i − x_p)(x_i − x_p)ᵀ; it keeps
//!   the angular momentum and the detail PIC smears. The blend above still applies to v_p,
//!   with v_i^n the scattered grid velocity (affine part included): APIC is the base, FLIP
//!   blends on top. Drucker–Prager sand takes APIC by default, solids PIC
//!   ([`crate::recipe::Recipe`]).
//! - **FLIP at constraints**: in a step where a wall or a contact changed a velocity of a
//!   body's grid, that body's α is capped at [`FLIP_AT_CONSTRAINTS`]. The FLIP increment
//!   v_i^{n+1} − v_i^n at a constrained node carries the impact's whole velocity jump, and
//!   carried back in full (α near 1) it re-injects energy at every bounce: an elastic box
//!   thrown at a wall with the GIMP kernel gained 18 % of its energy per impact sequence at
//!   α = 0.9, two boxes colliding with the linear kernel 535 %. With the cap no case of the
//!   impact study gained energy for any α in [0, 1] (docs/stability.md). The cap is per body,
//!   not per particle: Σ_p α m_p (v_p − Σ_i w_ip v_i^n) vanishes only when α is one number
//!   over the body, so a per-particle α would break the conservation of momentum.

use crate::kernel::Stencil;
use crate::math::{Dim, Real, VectorOps};
use crate::recipe::Recipe;

/// One body's transfer scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transfer {
    /// The FLIP share α ∈ [0, 1] of the new particle velocity.
    pub flip: Real,
    /// Whether particles carry an APIC affine velocity.
    pub apic: bool,
}

/// The largest FLIP share α of a body in a step where a wall or a contact changed its grid.
pub const FLIP_AT_CONSTRAINTS: Real = 0.7;

impl Transfer {
    /// The transfer a body's recipe chooses.
    #[inline]
    pub fn of(recipe: &Recipe) -> Self {
        Transfer {
            flip: recipe.flip,
            apic: recipe.apic,
        }
    }

    /// The transfer of a step in which walls or contacts changed the body's grid
    /// (`constrained`) or not: α capped at [`FLIP_AT_CONSTRAINTS`] in the first case.
    #[inline]
    pub fn at_constraints(self, constrained: bool) -> Self {
        Transfer {
            flip: if constrained {
                self.flip.min(FLIP_AT_CONSTRAINTS)
            } else {
                self.flip
            },
            ..self
        }
    }

    /// Step 6: the particle's new velocity from its old one `v_p` and the grid's new and old
    /// velocities interpolated at the particle (`v_new` = v_PIC, `v_old` = Σ_i w_ip v_i^n).
    #[inline(always)]
    pub fn velocity<V: VectorOps>(self, v_p: V, v_new: V, v_old: V) -> V {
        let alpha = self.flip;
        v_new * (1.0 - alpha) + (v_p + v_new - v_old) * alpha
    }

    /// Step 1 with APIC: the matrix A = m_p C_p h whose product with a node's offset d in
    /// cells (x_i − x_p = d h) is the affine part m_p C_p (x_i − x_p) of the node's momentum.
    #[inline(always)]
    pub fn affine_momentum<D: Dim>(c: D::Grad, m: Real, h: Real) -> D::Grad {
        c * (m * h)
    }

    /// Step 6 with APIC: C_p = B_p D_p⁻¹ from B_p (with offsets in cells, as the gather sums
    /// it) and the stencil. The kernels here are products of one-axis weights, so D_p is
    /// diagonal, D_aa = h² Σ_k w_a\[k\] d_a\[k\]² along each axis a.
    #[inline(always)]
    pub fn affine_velocity<D: Dim, const S: usize>(
        b: D::Grad,
        st: &Stencil<S>,
        h: Real,
    ) -> D::Grad {
        let mut c = [D::Vector::ZERO; 3];
        for (a, col) in c.iter_mut().enumerate().take(D::DIM) {
            *col = D::column(&b, a) / inertia(st, a, h);
        }
        D::from_columns(c)
    }
}

/// h Σ_k w[k] d[k]² along axis `a`: the APIC inertia D_aa divided by h (B_p's offsets are in
/// cells, so one h of D_aa's h² is already in it).
#[inline(always)]
fn inertia<const S: usize>(st: &Stencil<S>, a: usize, h: Real) -> Real {
    let mut sum = 0.0;
    for k in 0..S {
        sum += st.w[k][a] * st.d[k][a] * st.d[k][a];
    }
    sum * h
}
