//! The stress shown for sand: each granular body's particle stresses projected onto the grid
//! and interpolated back (a recovery for what is shown; the step never reads it),
//!
//! σ_i = Σ_p w_ip V_p σ_p / Σ_p w_ip V_p,   σ̄_p = Σ_i w_ip σ_i,
//!
//! with the scene's kernel w_ip. Sand at rest is held by the grid's nodal forces
//! f_i = −Σ_p V_p σ_p ∇w_ip alone: with several particles per cell, particle stresses that
//! differ from their neighbours' by a field whose nodal forces cancel are invisible to the
//! motion, and the history of a flow leaves such a field behind (in the shipped column
//! collapse at rest, pressures a hundredfold apart at one depth, a fifth of the deep particles
//! at the cone's apex). The projection keeps what the nodes carry and drops what they do not
//! see: σ̄_p is a convex combination of nearby stresses (Σ_i w_ip = 1), so a uniform stress is
//! recovered exactly, and a linear one exactly away from the body's edge. Solids keep their
//! own stress. docs/method.md gives the figures and the cost.
//!
//! The nodes are a dense box over each sand body's particles (its bounding box plus the
//! kernel's reach): one pass to scatter, one to gather, as the step's own transfers.

use crate::kernel::Kernel;
use crate::material::Behaviour;
use crate::math::{Dim, Real};
use crate::sim::Simulation;
use crate::step::with_kernel;

/// Every particle's stress as shown: the recovered σ̄_p of the sand bodies' particles, the
/// stress σ_p itself for the others (solids and kinematic bodies).
pub fn shown_stress<D: Dim>(sim: &Simulation<D>) -> Vec<D::Sym> {
    let mut out = sim.particles().stress.clone();
    for (i, body) in sim.bodies().iter().enumerate() {
        let granular =
            sim.scene().bodies.get(i).map(|b| b.material.behaviour()) == Some(Behaviour::Granular);
        if granular && !body.kinematic && !body.range.is_empty() {
            let r = body.range();
            let lp = body.radius * sim.world.inv_h;
            with_kernel!(sim.world.kernel, K, S => recover::<D, K, S>(
                &sim.particles().x[r.clone()],
                &sim.particles().volume[r.clone()],
                &sim.particles().stress[r.clone()],
                sim.world.inv_h,
                lp,
                &mut out[r],
            ));
        }
    }
    out
}

/// The recovered stress of one particle (see [`shown_stress`]).
pub fn shown_stress_of<D: Dim>(sim: &Simulation<D>, index: usize) -> D::Sym {
    // The projection needs the particle's neighbours; one recovery of its body is cheap
    // beside a frame's steps.
    shown_stress(sim)[index]
}

/// Per axis: the stencil's first node and weights of a particle at `x` (m).
fn axes<D: Dim, K: Kernel<S>, const S: usize>(
    x: &D::Vector,
    inv_h: Real,
    lp: Real,
) -> [(i32, [Real; S]); 3] {
    std::array::from_fn(|a| {
        if a < D::DIM {
            let (base, w, _) = K::axis(x[a] * inv_h + crate::grid::GHOST as Real, lp);
            (base, w)
        } else {
            let mut w = [0.0; S];
            w[0] = 1.0;
            (0, w)
        }
    })
}

/// The nodes of the stencil at `ax` in the box starting at `lo` with `stride`, and their
/// weights.
fn stencil<const S: usize>(
    ax: &[(i32, [Real; S]); 3],
    dim: usize,
    lo: [i32; 3],
    stride: [usize; 3],
    mut f: impl FnMut(usize, Real),
) {
    let reach = |a: usize| if a < dim { S } else { 1 };
    for k in 0..reach(2) {
        for j in 0..reach(1) {
            for i in 0..reach(0) {
                let w = ax[0].1[i] * ax[1].1[j] * ax[2].1[k];
                let n = (ax[0].0 + i as i32 - lo[0]) as usize * stride[0]
                    + (ax[1].0 + j as i32 - lo[1]) as usize * stride[1]
                    + (ax[2].0 + k as i32 - lo[2]) as usize * stride[2];
                f(n, w);
            }
        }
    }
}

fn recover<D: Dim, K: Kernel<S>, const S: usize>(
    x: &[D::Vector],
    volume: &[Real],
    stress: &[D::Sym],
    inv_h: Real,
    lp: Real,
    out: &mut [D::Sym],
) {
    let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
    for p in x {
        for (a, (base, _)) in axes::<D, K, S>(p, inv_h, lp).iter().enumerate() {
            lo[a] = lo[a].min(*base);
            hi[a] = hi[a].max(*base + S as i32 - 1);
        }
    }
    let size: [usize; 3] = std::array::from_fn(|a| (hi[a] - lo[a] + 1).max(1) as usize);
    let stride = [1, size[0], size[0] * size[1]];
    let mut nodes = vec![(D::Sym::default(), 0.0 as Real); size.iter().product()];
    for ((p, &v), &s) in x.iter().zip(volume).zip(stress) {
        let ax = axes::<D, K, S>(p, inv_h, lp);
        stencil(&ax, D::DIM, lo, stride, |n, w| {
            nodes[n].0 += s * (w * v);
            nodes[n].1 += w * v;
        });
    }
    for node in &mut nodes {
        if node.1 > 0.0 {
            node.0 = node.0 * (1.0 / node.1);
        }
    }
    for (p, o) in x.iter().zip(out) {
        let ax = axes::<D, K, S>(p, inv_h, lp);
        let mut s = D::Sym::default();
        stencil(&ax, D::DIM, lo, stride, |n, w| s += nodes[n].0 * w);
        *o = s;
    }
}
