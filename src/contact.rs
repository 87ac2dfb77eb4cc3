//! Contact between bodies on the grid (the paper's Sec. 4.3, Eq. 20–21).
//!
//! Every body has its own grid. Where two bodies have mass at the same node and approach each
//! other along the contact normal, their node velocities are corrected with equal and opposite
//! momentum changes. The normal is n = (∇m_A − ∇m_B)/|∇m_A − ∇m_B| (A's outward normal, made
//! symmetric in A and B); the approach test (v_A − v_B)·n > 0 is Eq. 20.
//!
//! Only pairs of bodies whose block sets overlap are visited, and only their shared blocks:
//! one body, or bodies apart, cost nothing.

use crate::grid::{Grid, GridIndex};
use crate::math::{Dim, Real, VectorOps};
use crate::sim::passes::constraint_dissipation;

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

/// Applies the contact rule at the shared nodes of one pair; returns the energy it removed
/// (see [`constraint_dissipation`]).
pub fn resolve<D: Dim>(
    ga: &mut Grid<D>,
    gb: &mut Grid<D>,
    blocks: &[(u32, u32)],
    rule: ContactRule,
) -> f64 {
    let pn = ga.layout.padded_nodes();
    // padded-local indices of the nodes a block owns (the same layout in both grids)
    let mut owned = Vec::new();
    ga.layout.for_each_owned(&ga.index, 0, |_, n| owned.push(n));
    let mut dissipated = 0.0;
    for &(sa, sb) in blocks {
        for &l in &owned {
            let (ia, ib) = (sa as usize * pn + l, sb as usize * pn + l);
            let (ma, mb) = (ga.nodes[ia].mass, gb.nodes[ib].mass);
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
            let reduced = ma * mb / (ma + mb);
            // Momentum change of A (B gets the opposite).
            let dp = match rule {
                ContactRule::Stick => (vb - va) * reduced, // Eq. 21
                ContactRule::Friction(mu) => {
                    let slip = (va - vb) - n * approach;
                    let slip_len = slip.length();
                    let mut dp = n * (-reduced * approach);
                    if slip_len > 0.0 {
                        let friction = (mu * reduced * approach).min(reduced * slip_len);
                        dp -= slip * (friction / slip_len);
                    }
                    dp
                }
            };
            let (na, nb) = (va + dp / ma, vb - dp / mb);
            dissipated += constraint_dissipation(ma, ga.nodes[ia].vel, va, na)
                + constraint_dissipation(mb, gb.nodes[ib].vel, vb, nb);
            ga.nodes[ia].new_vel = na;
            gb.nodes[ib].new_vel = nb;
        }
    }
    dissipated
}
