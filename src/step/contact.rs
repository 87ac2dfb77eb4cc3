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

use super::{BodyStep, Step, StressOrder, constraint_dissipation};
pub use crate::boundary::{ContactRule, STICKING_CFL};
use crate::grid::{Grid, GridIndex};
use crate::math::{Dim, VectorOps, min};
use crate::sim::body::Body;

impl<D: Dim> Step<'_, D> {
    /// Step 5 between every pair of bodies whose grids share blocks (`contacts`), recording
    /// in `steps` which bodies it changed and the momentum each received.
    pub(super) fn resolve_contacts(&mut self, contacts: &[ContactPair], steps: &mut [BodyStep]) {
        let sticks = self.world.contact.sticks();
        for b in self.bodies.iter_mut() {
            b.stuck = false;
        }
        for pair in contacts {
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
            // booked with a body that deforms (not both kinematic: no contact then)
            let booked = if a.kinematic { pair.b } else { pair.a };
            // (a kinematic body's grid is never changed: both changed means both deform)
            let last = |b: &Body<D>| b.recipe.stress_order == StressOrder::Last;
            let stuck = sticks && r.changed_a && r.changed_b && last(a) && last(b);
            a.stuck |= stuck;
            b.stuck |= stuck;
            steps[booked].constraints += r.dissipated;
            steps[pair.a].constrained |= r.changed_a;
            steps[pair.b].constrained |= r.changed_b;
            for k in 0..3 {
                steps[pair.a].contact_impulse[k] += r.impulse_on_a[k];
                steps[pair.b].contact_impulse[k] -= r.impulse_on_a[k];
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
