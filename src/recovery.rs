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
use crate::kernel::with_kernel;
use crate::material::Behaviour;
use crate::math::{Dim, Real};
use crate::sim::Simulation;

/// Every particle's stress as shown: the recovered σ̄_p of the sand bodies' particles, the
/// stress σ_p itself for the others (solids and kinematic bodies).
pub fn shown_stress<D: Dim>(sim: &Simulation<D>) -> Vec<D::Sym> {
    let p = sim.particles();
    let mut out = p.stress.clone();
    for (b, body) in sim.bodies().iter().enumerate() {
        if recovered(sim, b) {
            let r = body.range();
            let lp = body.radius * sim.world().inv_h;
            let (x, v, s) = (&p.x[r.clone()], &p.volume[r.clone()], &p.stress[r.clone()]);
            with_kernel!(sim.world().kernel, K, S => {
                let mut nodes = Nodes::<D, S>::around::<K>(x, sim.world().inv_h, lp);
                nodes.project::<K>(x, v, s, sim.world().inv_h, lp);
                for (o, x) in out[r].iter_mut().zip(x) {
                    *o = nodes.interpolate::<K>(x, sim.world().inv_h, lp);
                }
            });
        }
    }
    out
}

/// The stress of particle `index` as shown (an entry of [`shown_stress`]), from the nodes of
/// its own stencil alone: one pass over its body's particles.
pub fn shown_stress_of<D: Dim>(sim: &Simulation<D>, index: usize) -> D::Sym {
    let p = sim.particles();
    let Some(b) = sim.bodies().iter().position(|b| b.range().contains(&index)) else {
        return p.stress[index];
    };
    if !recovered(sim, b) {
        return p.stress[index];
    }
    let body = &sim.bodies()[b];
    let r = body.range();
    let lp = body.radius * sim.world().inv_h;
    let (x, v, s) = (&p.x[r.clone()], &p.volume[r.clone()], &p.stress[r]);
    with_kernel!(sim.world().kernel, K, S => {
        let at = std::slice::from_ref(&p.x[index]);
        let mut nodes = Nodes::<D, S>::around::<K>(at, sim.world().inv_h, lp);
        nodes.project::<K>(x, v, s, sim.world().inv_h, lp);
        nodes.interpolate::<K>(&p.x[index], sim.world().inv_h, lp)
    })
}

/// Whether body `b`'s stress is shown recovered: a granular body that carries stress.
fn recovered<D: Dim>(sim: &Simulation<D>, b: usize) -> bool {
    let body = &sim.bodies()[b];
    !body.kinematic
        && !body.range.is_empty()
        && matches!(
            sim.scene().bodies.get(b).map(|c| c.material.behaviour()),
            Some(Behaviour::Granular(_))
        )
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

/// A dense box of nodes: per node Σ_p w_ip V_p σ_p and Σ_p w_ip V_p, then their ratio σ_i.
struct Nodes<D: Dim, const S: usize> {
    lo: [i32; 3],
    size: [usize; 3],
    nodes: Vec<(D::Sym, Real)>,
}

impl<D: Dim, const S: usize> Nodes<D, S> {
    /// The box of every node the stencils of particles at `x` reach.
    fn around<K: Kernel<S>>(x: &[D::Vector], inv_h: Real, lp: Real) -> Self {
        let (mut lo, mut hi) = ([0; 3], [0; 3]);
        for a in 0..D::DIM {
            (lo[a], hi[a]) = (i32::MAX, i32::MIN);
        }
        for p in x {
            for (a, (base, _)) in axes::<D, K, S>(p, inv_h, lp)
                .iter()
                .enumerate()
                .take(D::DIM)
            {
                lo[a] = lo[a].min(*base);
                hi[a] = hi[a].max(*base + S as i32 - 1);
            }
        }
        let size: [usize; 3] = std::array::from_fn(|a| (hi[a] - lo[a] + 1).max(1) as usize);
        Nodes {
            lo,
            size,
            nodes: vec![(D::Sym::default(), 0.0); size.iter().product()],
        }
    }

    /// Calls `f` with the index in the box and the weight of each node of the stencil at
    /// `x` that lies in the box.
    #[inline(always)]
    fn each<K: Kernel<S>>(
        &self,
        x: &D::Vector,
        inv_h: Real,
        lp: Real,
        mut f: impl FnMut(usize, Real),
    ) {
        let ax = axes::<D, K, S>(x, inv_h, lp);
        let reach = |a: usize| if a < D::DIM { S } else { 1 };
        // the stencil's offset in the box along each axis; a stencil wholly outside is skipped
        let off: [i32; 3] = std::array::from_fn(|a| ax[a].0 - self.lo[a]);
        if (0..D::DIM).any(|a| off[a] + S as i32 <= 0 || off[a] >= self.size[a] as i32) {
            return;
        }
        let inside = |a: usize, k: usize| {
            let n = off[a] + k as i32;
            (n >= 0 && n < self.size[a] as i32).then_some(n as usize)
        };
        for k in 0..reach(2) {
            let Some(nz) = inside(2, k) else { continue };
            for j in 0..reach(1) {
                let Some(ny) = inside(1, j) else { continue };
                for i in 0..reach(0) {
                    let Some(nx) = inside(0, i) else { continue };
                    let w = ax[0].1[i] * ax[1].1[j] * ax[2].1[k];
                    f(nx + self.size[0] * (ny + self.size[1] * nz), w);
                }
            }
        }
    }

    /// σ_i = Σ_p w_ip V_p σ_p / Σ_p w_ip V_p over the particles at `x`.
    fn project<K: Kernel<S>>(
        &mut self,
        x: &[D::Vector],
        volume: &[Real],
        stress: &[D::Sym],
        inv_h: Real,
        lp: Real,
    ) {
        let mut nodes = std::mem::take(&mut self.nodes);
        for ((p, &v), &s) in x.iter().zip(volume).zip(stress) {
            self.each::<K>(p, inv_h, lp, |n, w| {
                nodes[n].0 += s * (w * v);
                nodes[n].1 += w * v;
            });
        }
        for node in &mut nodes {
            if node.1 > 0.0 {
                node.0 = node.0 * (1.0 / node.1);
            }
        }
        self.nodes = nodes;
    }

    /// σ̄_p = Σ_i w_ip σ_i at `x`.
    fn interpolate<K: Kernel<S>>(&self, x: &D::Vector, inv_h: Real, lp: Real) -> D::Sym {
        let mut s = D::Sym::default();
        self.each::<K>(x, inv_h, lp, |n, w| s += self.nodes[n].0 * w);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{D2, D3, Sym2, SymTensor};
    use crate::playground::{ColourMode, Playground};
    use crate::{BodyConfig, Material, SceneConfig, Shape};

    fn sand() -> Material {
        Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0)
    }

    /// A sand block (its lattice jittered by `jitter` of the spacing) and an elastic one
    /// beside it, on 2 cm cells.
    fn scene(dim: usize, jitter: f64) -> SceneConfig {
        let mut s = SceneConfig::new(dim, &[1.0, 0.6, 0.6][..dim], 0.02);
        let at = |lo: [f64; 3], hi: [f64; 3]| Shape::cuboid(&lo[..dim], &hi[..dim]);
        s.bodies.push(
            BodyConfig::new("sand", at([0.1, 0.0, 0.1], [0.5, 0.3, 0.3]), sand())
                .with_jitter(jitter, 7),
        );
        s.bodies.push(BodyConfig::new(
            "block",
            at([0.6, 0.0, 0.1], [0.8, 0.2, 0.3]),
            Material::elastic(1e5, 0.3, 1000.0),
        ));
        s
    }

    /// A stress field σ(x) set on every particle, its shown stress.
    fn shown_of<D: Dim>(
        jitter: f64,
        f: impl Fn(usize, D::Vector) -> D::Sym,
    ) -> (Simulation<D>, Vec<D::Sym>) {
        let mut sim = Simulation::<D>::new(scene(D::DIM, jitter)).unwrap();
        let p = sim.particles_mut();
        for i in 0..p.len() {
            p.stress[i] = f(i, p.x[i]);
        }
        let shown = shown_stress(&sim);
        (sim, shown)
    }

    fn close(a: &[Real], b: &[Real], tol: Real) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    /// A uniform stress is shown as it is (on a jittered lattice); a linear one (σ_yy = −ρ g
    /// (0.3 − y), the others in proportion) as it is on a regular lattice at particles three
    /// cells from the body's faces, whose nodes see particles placed symmetrically about them.
    #[test]
    fn a_uniform_and_a_linear_stress_are_shown_as_they_are() {
        let (sim, shown) = shown_of::<D2>(0.25, |_, _| Sym2::iso(-1000.0));
        let uniform = Sym2::iso(-1000.0);
        assert!(sim.bodies()[0].range().all(|i| close(
            shown[i].components(),
            uniform.components(),
            0.05
        )));
        let linear = |x: <D2 as Dim>::Vector| {
            let yy = -2200.0 * 9.81 * (0.3 - x[1]);
            Sym2 {
                xx: yy / 3.0,
                yy,
                zz: yy / 3.0,
                xy: 0.1 * yy,
            }
        };
        let (sim, shown) = shown_of::<D2>(0.0, |_, x| linear(x));
        let p = sim.particles();
        let mut interior = 0;
        for i in sim.bodies()[0].range() {
            let x = p.x[i];
            // three cells in from every face of the block
            if x[0] > 0.16 && x[0] < 0.44 && x[1] > 0.06 && x[1] < 0.24 {
                interior += 1;
                let (a, b) = (shown[i].components(), linear(x).components().to_vec());
                assert!(close(a, &b, 0.5), "at {x:?}: {a:?} against {b:?}");
            }
        }
        assert!(interior > 100, "{interior}");
    }

    /// Σ_p V_p σ̄_p = Σ_p V_p σ_p (Σ_i w_ip = 1): the shown stress of a body at rest is in the
    /// same equilibrium with its weight as its own; the elastic block's is its own.
    #[test]
    fn the_recovery_keeps_the_body_s_total_stress_and_leaves_solids_alone() {
        // a smooth field and a noise from particle to particle (a hash of the index)
        let (sim, shown) = shown_of::<D3>(0.25, |i, x| {
            let noise = ((i * 7919) % 101) as Real / 50.0 - 1.0;
            let mut s = <D3 as Dim>::Sym::iso(-500.0);
            s.yy = -3000.0 * (1.0 + 0.3 * (10.0 * x[0]).sin() + 0.6 * noise);
            s.xz = 200.0 * noise;
            s
        });
        let p = sim.particles();
        for body in [0, 1] {
            let r = sim.bodies()[body].range();
            let total = |s: &[<D3 as Dim>::Sym]| -> Vec<f64> {
                (0..6)
                    .map(|c| {
                        r.clone()
                            .map(|i| (p.volume[i] * s[i].components()[c]) as f64)
                            .sum()
                    })
                    .collect()
            };
            let (own, recovered) = (total(&p.stress), total(&shown));
            for c in 0..6 {
                assert!(
                    (own[c] - recovered[c]).abs() <= 1e-4 * own[1].abs(),
                    "{own:?} {recovered:?}"
                );
            }
        }
        // the sand's noise is smoothed, the block's kept
        let spread = |s: &[<D3 as Dim>::Sym], r: std::ops::Range<usize>| {
            let yy: Vec<Real> = r.map(|i| s[i].yy).collect();
            yy.iter().copied().fold(Real::MIN, Real::max)
                - yy.iter().copied().fold(Real::MAX, Real::min)
        };
        assert!(
            spread(&shown, sim.bodies()[0].range())
                < 0.5 * spread(&p.stress, sim.bodies()[0].range())
        );
        assert!(sim.bodies()[1].range().all(|i| shown[i] == p.stress[i]));
    }

    /// What the page shows is the recovered stress: Inspect's stress point (p, q, principal
    /// stresses) and the pressure colour, for sand; one particle's recovery from its own
    /// stencil agrees with the whole body's.
    #[test]
    fn the_page_shows_the_recovered_stress() {
        for dim in [2, 3] {
            let mut pg = Playground::new(scene(dim, 0.25)).unwrap();
            pg.frame(0.1, 1e6, || 0.0).unwrap();
            pg.update_colours(ColourMode::Pressure);
            let shown: Vec<[f64; 6]> = match pg.simulation() {
                crate::AnySimulation::D2(s) => shown_stress(s)
                    .iter()
                    .enumerate()
                    .map(|(i, t)| {
                        if i % 17 == 0 {
                            assert_eq!(*t, shown_stress_of(s, i));
                        }
                        std::array::from_fn(|c| t.components().get(c).map_or(0.0, |&v| v as f64))
                    })
                    .collect(),
                crate::AnySimulation::D3(s) => shown_stress(s)
                    .iter()
                    .enumerate()
                    .map(|(i, t)| {
                        if i % 17 == 0 {
                            assert_eq!(*t, shown_stress_of(s, i));
                        }
                        std::array::from_fn(|c| t.components()[c] as f64)
                    })
                    .collect(),
            };
            let mut differs = 0;
            for (i, s) in shown.iter().enumerate() {
                let p = -(s[0] + s[1] + s[2]) / 3.0;
                let point = pg.stress_point(i).unwrap();
                assert!(
                    (point.p - p).abs() <= 1e-3 * p.abs().max(1.0),
                    "{} {p}",
                    point.p
                );
                assert!((pg.colours()[i] as f64 - p).abs() <= 1e-3 * p.abs().max(1.0));
                differs += usize::from(match pg.simulation() {
                    crate::AnySimulation::D2(s) => s.particles().pressure(i) as f64 != p,
                    crate::AnySimulation::D3(s) => s.particles().pressure(i) as f64 != p,
                });
            }
            assert!(
                differs > 100,
                "the shown pressure is the particles' own in {dim}D"
            );
        }
    }
}
