//! The walls of the domain box: grid-node constraints (step 5) and the particle-side
//! projection (step 7), with Coulomb friction proportional to the normal velocity removed,
//! which is friction proportional to the contact pressure (the paper's Sec. 5); and the rule
//! between bodies in contact ([`ContactRule`], applied by `crate::step::contact`).
//!
//! The walls lie on grid nodes; nodes on or beyond a wall take the wall rule. On the particle
//! side a particle is treated as the cube of material it stands for (half-width: half the
//! particle spacing), which may touch a wall but not cross it: particles never pile into the
//! cells behind the walls, whichever kernel interpolates.

use crate::config::BoundaryConfig;
use crate::grid::GHOST;
use crate::math::{Dim, Real, VectorOps};

/// What a wall does to a velocity that points into it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WallRule {
    /// Remove the normal component only.
    Slip,
    /// Remove the normal component v_n and reduce the tangential speed by μ|v_n|.
    Friction(Real),
    /// No motion at the wall at all (not even separation).
    Sticky,
}

impl WallRule {
    pub fn from_config(c: &BoundaryConfig) -> Self {
        if c.sticky {
            WallRule::Sticky
        } else if c.friction > 0.0 {
            WallRule::Friction(c.friction as Real)
        } else {
            WallRule::Slip
        }
    }

    /// The velocity after contact with a wall whose inward normal is `inward` (±1) along
    /// `axis`.
    #[inline(always)]
    pub fn apply<V: VectorOps>(self, v: V, axis: usize, inward: Real) -> V {
        let vn = v[axis] * inward;
        match self {
            WallRule::Sticky => V::ZERO,
            _ if vn >= 0.0 => v,
            WallRule::Slip => {
                let mut t = v;
                t[axis] = 0.0;
                t
            }
            WallRule::Friction(mu) => {
                let mut t = v;
                t[axis] = 0.0;
                let speed = t.length();
                let loss = -mu * vn; // μ |v_n|
                if speed <= loss {
                    V::ZERO
                } else {
                    t * (1.0 - loss / speed)
                }
            }
        }
    }
}

/// The six (four in 2D) walls of the domain `[0, size]`.
#[derive(Clone, Copy, Debug)]
pub struct Walls<D: Dim> {
    pub rule: WallRule,
    pub size: D::Vector,
    /// Nodes with grid coordinate `<= GHOST` lie on or beyond the lower walls, those `>= hi`
    /// on or beyond the upper walls.
    pub node_hi: [i32; 3],
}

impl<D: Dim> Walls<D> {
    /// Walls of a domain whose sizes are whole numbers of cells (as validated).
    pub fn new(rule: WallRule, size: D::Vector, cell_size: Real) -> Self {
        let mut node_hi = [i32::MAX; 3];
        for (a, hi) in node_hi.iter_mut().enumerate().take(D::DIM) {
            *hi = GHOST + (size[a] / cell_size).round() as i32;
        }
        Walls {
            rule,
            size,
            node_hi,
        }
    }

    /// Whether any node of the block with first node `origin` (edge `block` nodes) is a wall node.
    #[inline]
    pub fn block_touches(&self, origin: [i32; 3], block: i32) -> bool {
        (0..D::DIM).any(|a| origin[a] <= GHOST || origin[a] + block > self.node_hi[a])
    }

    /// Step 5: the velocity of the grid node with coordinate `node` after the walls.
    #[inline(always)]
    pub fn node_velocity(&self, node: [i32; 3], mut v: D::Vector) -> D::Vector {
        for (a, &n) in node.iter().enumerate().take(D::DIM) {
            if n <= GHOST {
                v = self.rule.apply(v, a, 1.0);
            } else if n >= self.node_hi[a] {
                v = self.rule.apply(v, a, -1.0);
            }
        }
        v
    }

    /// Step 7: the velocity of a particle at `x` whose material (a cube of half-width
    /// `radius` about it) would cross a wall within `dt`. Particles therefore never pile into
    /// the cells behind the walls, whatever the kernel.
    #[inline(always)]
    pub fn particle_velocity(
        &self,
        x: D::Vector,
        mut v: D::Vector,
        dt: Real,
        radius: Real,
    ) -> D::Vector {
        let next = x + v * dt;
        if self.inside(next, radius) {
            return v; // stays inside: the common case
        }
        for a in 0..D::DIM {
            let next = next[a];
            if next < radius {
                v = self.rule.apply(v, a, 1.0);
            } else if next > self.size[a] - radius {
                v = self.rule.apply(v, a, -1.0);
            }
        }
        v
    }

    /// Whether a particle of half-width `radius` at `x` is clear of every wall.
    #[inline(always)]
    pub fn inside(&self, x: D::Vector, radius: Real) -> bool {
        let r = D::Vector::splat(radius);
        x.max(r).min(self.size - r) == x
    }

    /// Keeps a particle of half-width `radius` inside the domain (a last resort after step 7).
    #[inline(always)]
    pub fn clamp(&self, x: D::Vector, radius: Real) -> D::Vector {
        let r = D::Vector::splat(radius);
        x.max(r).min(self.size - r)
    }
}

/// How approaching bodies interact at shared nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactRule {
    /// The paper's Eq. 21: both take the centre-of-mass velocity (perfectly inelastic, no slip).
    Stick,
    /// Bardenhagen et al. (2001): remove the approaching normal velocity; the tangential slip is
    /// resisted by Coulomb friction with coefficient μ.
    Friction(Real),
}

/// The largest CFL number, over the signal speeds of the bodies held together, of a step in
/// which two solids that update their stress last
/// (elastic and von Mises bodies with the C¹ kernels, [`crate::recipe::StressOrder`]) share grid
/// nodes under a contact rule that sticks ([`ContactRule::sticks`]). Such a solid takes its
/// strain from grid velocities the contact has just set to the pair's common velocity; at the
/// paper's 0.4 that pumped energy into bodies held together in three of 40 long random
/// sweeps (a replayed case gained 54 times its energy scale), at 0.3 into one of four
/// replays, at 0.2 into none (docs/stability.md, "Energy rises between bodies in contact").
/// Bodies not held keep the scene's CFL number ([`crate::Simulation::stable_dt`]).
pub const STICKING_CFL: f64 = 0.2;

impl ContactRule {
    /// Whether the rule can hold two bodies together tangentially: the paper's rule, or
    /// Coulomb friction with μ > 0 ([`STICKING_CFL`] applies under such a rule). In replays of
    /// four random scenes whose energy rose under the paper's rule at CFL 0.4, frictionless
    /// contact kept the energy in all four; Coulomb friction did not in one at μ = 0.5 and
    /// 0.86, and in the others from μ = 2 or 5 on (docs/stability.md).
    pub fn sticks(self) -> bool {
        match self {
            ContactRule::Stick => true,
            ContactRule::Friction(mu) => mu > 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;

    #[test]
    fn coulomb_friction_removes_mu_times_the_normal_velocity() {
        let v = Vec2::new(3.0, -2.0); // hitting the floor (inward normal +y)
        assert_eq!(WallRule::Slip.apply(v, 1, 1.0), Vec2::new(3.0, 0.0));
        let f = WallRule::Friction(0.5).apply(v, 1, 1.0);
        assert!((f - Vec2::new(2.0, 0.0)).length() < 1e-6);
        // enough friction stops the sliding entirely
        assert_eq!(WallRule::Friction(2.0).apply(v, 1, 1.0), Vec2::ZERO);
        // separating velocities are untouched except by sticky walls
        let up = Vec2::new(1.0, 1.0);
        assert_eq!(WallRule::Friction(0.5).apply(up, 1, 1.0), up);
        assert_eq!(WallRule::Sticky.apply(up, 1, 1.0), Vec2::ZERO);
    }
}
