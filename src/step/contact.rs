//! Step 5 between bodies: contact on the grid (the paper's Sec. 4.3, Eq. 20–21),
//!
//! (v_A − v_B)·n > 0 (approaching):   Δ(m v)_A = (v_B − v_A) m_A m_B / (m_A + m_B) = −Δ(m v)_B.
//!
//! Every body has its own grid. Where two bodies have mass at the same node and approach each
//! other along the contact normal, their node velocities are corrected with equal and opposite
//! momentum changes. The normal is n = (∇m_A − ∇m_B)/|∇m_A − ∇m_B| (A's outward normal, made
//! symmetric in A and B); the approach test (v_A − v_B)·n > 0 is Eq. 20.
//!
//! Only pairs of bodies whose block sets overlap are visited, and only their shared blocks:
//! one body, or bodies apart, cost nothing.

use super::{StressOrder, constraint_dissipation};
use crate::grid::{Grid, GridIndex};
use crate::math::{Dim, Real, VectorOps, min};
use crate::sim::{Body, Simulation};

impl<D: Dim> Simulation<D> {
    /// Step 5 between every pair of bodies whose grids share blocks.
    pub(super) fn resolve_contacts(&mut self) {
        let sticks = self.world.contact.sticks();
        self.solids_stuck = false;
        for body in &mut self.bodies {
            body.contact_impulse = [0.0; 3];
            body.constrained = false; // set again by the contacts and the walls of this step
        }
        for pair in &self.contacts {
            let (left, right) = self.bodies.split_at_mut(pair.b);
            let (a, b) = (&mut left[pair.a], &mut right[0]);
            let r = resolve(
                &mut a.grid,
                &mut b.grid,
                &pair.blocks,
                self.world.contact,
                (a.kinematic, b.kinematic),
            );
            self.diagnostics.dissipated_contact += r.dissipated;
            // (a kinematic body's grid is never changed: both changed means both deform)
            let last = |b: &Body<D>| b.recipe.stress_order == StressOrder::Last;
            self.solids_stuck |= sticks && r.changed_a && r.changed_b && last(a) && last(b);
            a.constrained |= r.changed_a;
            b.constrained |= r.changed_b;
            for k in 0..3 {
                a.contact_impulse[k] += r.impulse_on_a[k];
                b.contact_impulse[k] -= r.impulse_on_a[k];
            }
        }
    }
}

/// The shared blocks of two bodies `a < b`, as (slot in a, slot in b).
#[derive(Clone, Debug, Default)]
pub struct ContactPair {
    pub a: usize,
    pub b: usize,
    pub blocks: Vec<(u32, u32)>,
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

/// The largest CFL number of a step in which two solids that update their stress last
/// (elastic and von Mises bodies with the C¹ kernels, [`super::StressOrder`]) share grid
/// nodes under a contact rule that sticks ([`ContactRule::sticks`]). Such a solid takes its
/// strain from grid velocities the contact has just set to the pair's common velocity; at the
/// paper's 0.4 that pumped energy into bodies held together in three of 40 long random
/// sweeps (a replayed case gained 54 times its energy scale), at 0.3 into one of four
/// replays, at 0.2 into none (docs/stability.md, "Energy rises between bodies in contact").
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

/// Finds the pairs of grids that share allocated blocks.
pub fn find_pairs<D: Dim>(grids: &[&GridIndex<D>], out: &mut Vec<ContactPair>) {
    out.clear();
    for a in 0..grids.len() {
        for b in a + 1..grids.len() {
            let (alo, ahi) = grids[a].block_bounds();
            let (blo, bhi) = grids[b].block_bounds();
            if grids[a].block_count() == 0
                || grids[b].block_count() == 0
                || (0..D::DIM).any(|k| ahi[k] < blo[k] || bhi[k] < alo[k])
            {
                continue;
            }
            let blocks: Vec<(u32, u32)> = grids[a]
                .blocks()
                .iter()
                .enumerate()
                .filter_map(|(sa, &c)| grids[b].slot_of_block(c).map(|sb| (sa as u32, sb as u32)))
                .collect();
            if !blocks.is_empty() {
                out.push(ContactPair { a, b, blocks });
            }
        }
    }
}

/// What resolving one pair did.
#[derive(Clone, Copy, Debug, Default)]
pub struct Resolved {
    /// Energy removed (see [`constraint_dissipation`]).
    pub dissipated: f64,
    /// Momentum given to body A (body B received the opposite).
    pub impulse_on_a: [f64; 3],
    /// Whether a node velocity of A, of B changed (for
    /// [`super::transfer::Transfer::at_constraints`]).
    pub changed_a: bool,
    pub changed_b: bool,
}

/// Applies the contact rule at the shared nodes of one pair. A kinematic body (`kinematic_a`,
/// `kinematic_b`) counts as infinitely heavy: its velocity is not changed, the other body's is
/// changed as if by a wall moving with it.
pub fn resolve<D: Dim>(
    ga: &mut Grid<D>,
    gb: &mut Grid<D>,
    blocks: &[(u32, u32)],
    rule: ContactRule,
    (kinematic_a, kinematic_b): (bool, bool),
) -> Resolved {
    let mut out = Resolved::default();
    if kinematic_a && kinematic_b {
        return out;
    }
    let pn = ga.layout.padded_nodes();
    // padded-local indices of the nodes a block owns (the same layout in both grids)
    let mut owned = Vec::new();
    ga.layout.for_each_owned(&ga.index, 0, |_, n| owned.push(n));
    let mut impulse = D::Vector::ZERO;
    for &(sa, sb) in blocks {
        for &l in &owned {
            let (ia, ib) = (sa as usize * pn + l, sb as usize * pn + l);
            let (ma, mb) = (ga.nodes[ia].mass(), gb.nodes[ib].mass());
            if ma <= 0.0 || mb <= 0.0 {
                continue;
            }
            let normal = ga.mass_grad[ia] - gb.mass_grad[ib];
            let len = normal.length();
            if len <= 0.0 {
                continue;
            }
            let n = normal / len;
            let (va, vb) = (ga.nodes[ia].new_vel, gb.nodes[ib].new_vel);
            let approach = (va - vb).dot(n);
            if approach <= 0.0 {
                continue; // separating: Eq. 20 not met
            }
            let reduced = if kinematic_a {
                mb
            } else if kinematic_b {
                ma
            } else {
                ma * mb / (ma + mb)
            };
            // Momentum change of A (B gets the opposite).
            let dp = match rule {
                ContactRule::Stick => (vb - va) * reduced, // Eq. 21
                ContactRule::Friction(mu) => {
                    let slip = (va - vb) - n * approach;
                    let slip_len = slip.length();
                    let mut dp = n * (-reduced * approach);
                    if slip_len > 0.0 {
                        let friction = min(mu * reduced * approach, reduced * slip_len);
                        dp -= slip * (friction / slip_len);
                    }
                    dp
                }
            };
            impulse += dp;
            if !kinematic_a {
                let na = va + dp / ma;
                out.dissipated += constraint_dissipation(ma, ga.nodes[ia].vel(), va, na);
                ga.nodes[ia].new_vel = na;
                out.changed_a = true;
            }
            if !kinematic_b {
                let nb = vb - dp / mb;
                out.dissipated += constraint_dissipation(mb, gb.nodes[ib].vel(), vb, nb);
                gb.nodes[ib].new_vel = nb;
                out.changed_b = true;
            }
        }
    }
    for a in 0..D::DIM {
        out.impulse_on_a[a] = impulse[a] as f64;
    }
    out
}
