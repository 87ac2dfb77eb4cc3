//! Steps 2–4, particle side: from the grid velocities of step 1,
//!
//! - step 2, the velocity gradient ∇v_p = Σ_i v_i^n ⊗ ∇w_ip, split into the strain rate
//!   ε̇ = ½(∇v + ∇vᵀ) and the spin ω = ½(∇v − ∇vᵀ);
//! - step 3, the stress update σ_p ← σ_p + Δt σ̇(ε̇, ω) by the body's constitutive model (the
//!   Jaumann rate of Eq. 2–6 with the model's plastic return), and the volume
//!   V_p ← V_p exp(Δt tr ε̇), the exact solution of V̇ = V tr ε̇ for the step's rate: first order
//!   the same as V_p (1 + Δt tr ε̇), but never zero or negative however violent the compression;
//! - step 4, the internal forces f_i = −Σ_p V_p σ_p ∇w_ip, accumulated in the nodes'
//!   `new_vel` (the grid side of step 4 turns them into velocities).
//!
//! [`update_stress_plain`] does this one particle at a time and is the reference;
//! [`update_stress`], the one the step runs, is its SIMD specialisation: the constitutive
//! update of four particles per model call in SIMD lanes (the update is a long dependency
//! chain, and in lanes four chains advance at once). A test checks that they agree.

use super::{first_node, grid_coords, layout, third_axis, third_axis_nodes, with_kernel};
use crate::grid::{Grid, Node, stencil_span};
use crate::kernel::{Kernel, Stencil};
use crate::material::{Constitutive, Model};
use crate::math::{
    Batch, Dim, LANES, Lane, Lanes, Real, SymTensor, Vec4, VectorOps, exp_small, max,
    sum_from_first,
};
use crate::sim::Simulation;

impl<D: Dim> Simulation<D> {
    /// Steps 2–3 and the particle side of step 4, for every body that carries stress.
    pub(super) fn update_stress(&mut self, dt: Real) -> Vec<StressReport> {
        let inv_h = self.world.inv_h;
        let kernel = self.world.kernel;
        let p = &mut self.particles;
        let mut reports = Vec::with_capacity(self.bodies.len());
        for body in &mut self.bodies {
            if body.kinematic {
                reports.push(StressReport::default());
                continue;
            }
            let r = body.range.clone();
            let state = StressState {
                x: &p.x[r.clone()],
                stress: &mut p.stress[r.clone()],
                volume: &mut p.volume[r.clone()],
                plastic_strain: &mut p.plastic_strain[r],
            };
            let lp = body.radius * inv_h;
            let report = with_kernel!(kernel, K, S => stress_pass::<D, K, S>(&mut body.grid, state, &body.model, dt, inv_h, lp));
            if report.bad == 0 {
                body.max_volume = report.max_volume;
            }
            reports.push(report);
        }
        reports
    }
}

/// The stress pass of one body, dispatched on its model.
fn stress_pass<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &mut Grid<D>,
    state: StressState<'_, D>,
    model: &Model,
    dt: Real,
    inv_h: Real,
    lp: Real,
) -> StressReport {
    match model {
        Model::Elastic(m) => update_stress::<D, K, _, S>(grid, state, m, dt, inv_h, lp),
        Model::VonMises(m) => update_stress::<D, K, _, S>(grid, state, m, dt, inv_h, lp),
        Model::DruckerPrager(m) => update_stress::<D, K, _, S>(grid, state, m, dt, inv_h, lp),
    }
}

/// The particle state the stress pass reads and writes.
pub struct StressState<'a, D: Dim> {
    pub x: &'a [D::Vector],
    pub stress: &'a mut [D::Sym],
    pub volume: &'a mut [Real],
    pub plastic_strain: &'a mut [Real],
}

/// What the stress pass measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct StressReport {
    /// Stored elastic energy Σ V W(σ) after the update.
    pub elastic: f64,
    /// Energy removed by plastic correction in this step.
    pub dissipated: f64,
    /// The largest particle volume (with the body's smallest particle mass it bounds the
    /// lowest density, for the wave speed).
    pub max_volume: Real,
    /// Number of particles whose stress or volume went non-finite, and the first of them.
    pub bad: usize,
    pub first_bad: Option<(usize, &'static str)>,
}

impl StressReport {
    /// Counts particle `q` as bad (its stress or, with a finite stress, its volume).
    fn bad(&mut self, q: usize, stress_finite: bool) {
        self.bad += 1;
        let what = if stress_finite { "volume" } else { "stress" };
        self.first_bad.get_or_insert((q, what));
    }
}

/// Steps 2–4, particle side, one particle at a time: the reference version of
/// [`update_stress`].
pub fn update_stress_plain<D: Dim, K: Kernel<S>, M: Constitutive, const S: usize>(
    grid: &mut Grid<D>,
    ps: StressState<'_, D>,
    model: &M,
    dt: Real,
    inv_h: Real,
    lp: Real,
) -> StressReport {
    let (p, span) = layout::<D, S>(grid);
    let Grid {
        layout,
        nodes,
        particle_node,
        ..
    } = &mut *grid;
    let mut report = StressReport::default();
    for q in 0..ps.x.len() {
        let st = K::stencil(grid_coords::<D>(ps.x[q], inv_h), D::DIM, inv_h, lp);
        let cell = &mut nodes[first_node(layout, particle_node[q], &st)..][..span];
        let (rate, spin) = D::rate_and_spin(velocity_gradient::<D, S>(cell, p, &st));
        let mut sigma = ps.stress[q];
        let u = model.update(&mut sigma, rate, spin, dt);
        let before = ps.volume[q];
        let v = before * exp_small(rate.trace() * dt);
        ps.stress[q] = sigma;
        ps.volume[q] = v;
        if M::PLASTIC {
            ps.plastic_strain[q] += u.plastic_strain;
        }
        if !(sigma.is_finite() && v.is_finite() && v > 0.0) {
            report.bad(q, sigma.is_finite());
            continue;
        }
        report.elastic += (u.energy * v) as f64;
        report.dissipated += (u.dissipation * before) as f64;
        report.max_volume = max(report.max_volume, v);
        scatter_force::<D, S>(cell, p, &st, sigma * -v);
    }
    grid.reduce_nodes(|o, h| o.new_vel += h.new_vel);
    report
}

/// Particles per chunk of [`update_stress`] (a multiple of `LANES`).
const CHUNK: usize = 2 * LANES;

/// Steps 2–4, particle side — SIMD specialisation of [`update_stress_plain`]: in chunks of
/// eight particles, the velocity gradients, then the constitutive and volume updates of four
/// particles per call in SIMD lanes (with the energies and the finiteness test per group of
/// four), then the forces. A short last chunk is padded with zero stress and rate and a real
/// particle's volume, whose update adds nothing. In 2D the stencil loops are the packed ones
/// ([`velocity_gradient_2d_packed`], [`scatter_force_2d_packed`]).
///
/// Never inlined: each (dimension, kernel, model) instance stays a function of its own (when
/// the 2D instances were inlined into the dispatch, V8 compiled the resulting WebAssembly
/// function much worse; docs/performance.md).
#[inline(never)]
pub fn update_stress<D: Dim, K: Kernel<S>, M: Constitutive, const S: usize>(
    grid: &mut Grid<D>,
    ps: StressState<'_, D>,
    model: &M,
    dt: Real,
    inv_h: Real,
    lp: Real,
) -> StressReport {
    let (p, span) = layout::<D, S>(grid);
    let Grid {
        layout,
        nodes,
        particle_node,
        ..
    } = &mut *grid;
    let mut report = StressReport::default();
    let n = ps.x.len();
    let mut st = [Stencil::<S>::at([0; 3]); CHUNK];
    let mut origin = [0usize; CHUNK];
    let mut stress = [D::Sym::ZERO; CHUNK];
    let mut rate = [D::Sym::ZERO; CHUNK];
    let mut spin = [<D::Sym as SymTensor>::Spin::default(); CHUNK];
    let mut volume = [0.0; CHUNK];
    let mut plastic = [0.0; CHUNK];
    let mut finite = [true; CHUNK];
    for first in (0..n).step_by(CHUNK) {
        let len = CHUNK.min(n - first);
        if len < CHUNK {
            stress = [D::Sym::ZERO; CHUNK];
            rate = [D::Sym::ZERO; CHUNK];
            spin = [Default::default(); CHUNK];
            volume = [ps.volume[first]; CHUNK];
        }
        // Step 2 for the chunk.
        for i in 0..len {
            let q = first + i;
            st[i] = K::stencil(grid_coords::<D>(ps.x[q], inv_h), D::DIM, inv_h, lp);
            origin[i] = first_node(layout, particle_node[q], &st[i]);
            let cell = &nodes[origin[i]..origin[i] + span];
            let grad = if D::DIM == 2 {
                velocity_gradient_2d_packed::<D, S>(cell, p, &st[i])
            } else {
                velocity_gradient::<D, S>(cell, p, &st[i])
            };
            (rate[i], spin[i]) = D::rate_and_spin(grad);
            stress[i] = ps.stress[q];
            volume[i] = ps.volume[q];
        }
        // Step 3, four particles per model call.
        for g in (0..len).step_by(LANES) {
            let group = |a: &[D::Sym]| -> [D::Sym; LANES] { a[g..g + LANES].try_into().unwrap() };
            let spins: [_; LANES] = spin[g..g + LANES].try_into().unwrap();
            let mut lanes = D::Sym::pack(&group(&stress));
            let mut v = Lanes::from_slice(&volume[g..g + LANES]);
            let (ep, u) = update_group(
                model,
                &mut lanes,
                D::Sym::pack(&group(&rate)),
                D::Sym::pack_spin(&spins),
                &mut v,
                dt,
            );
            stress[g..g + LANES].copy_from_slice(&D::Sym::unpack(lanes));
            v.write_to_slice(&mut volume[g..g + LANES]);
            ep.write_to_slice(&mut plastic[g..g + LANES]);
            finite[g..g + LANES].fill(u.finite);
            if u.finite {
                report.elastic += u.elastic;
                report.dissipated += u.dissipated;
                report.max_volume = max(report.max_volume, u.max_volume);
            }
        }
        // Step 4, particle side, for the chunk.
        for i in 0..len {
            let q = first + i;
            let sigma = stress[i];
            ps.stress[q] = sigma;
            ps.volume[q] = volume[i];
            if M::PLASTIC {
                ps.plastic_strain[q] += plastic[i];
            }
            // Only a group that was not all finite is looked at particle by particle.
            let ok = finite[i] || sigma.is_finite() && volume[i].is_finite() && volume[i] > 0.0;
            if !ok {
                report.bad(q, sigma.is_finite());
                continue;
            }
            let cell = &mut nodes[origin[i]..origin[i] + span];
            if D::DIM == 2 {
                scatter_force_2d_packed::<D, S>(cell, p, &st[i], sigma * -volume[i]);
            } else {
                scatter_force::<D, S>(cell, p, &st[i], sigma * -volume[i]);
            }
        }
    }
    grid.reduce_nodes(|o, h| o.new_vel += h.new_vel);
    report
}

/// What one constitutive call (for `LANES` particles in SIMD lanes) adds to the report.
struct Group {
    /// Σ V W(σ) after the update, and Σ V D (energy the plastic correction removed).
    elastic: f64,
    dissipated: f64,
    max_volume: Real,
    finite: bool,
}

/// Step 3 for one group of particles in lanes: the stress by the model (returning their
/// plastic strain increments) and the volume.
#[inline(always)]
fn update_group<S: SymTensor, M: Constitutive>(
    model: &M,
    stress: &mut S,
    rate: S,
    spin: S::Spin,
    volume: &mut S::Scalar,
    dt: Real,
) -> (S::Scalar, Group) {
    let u = model.update(stress, rate, spin, dt);
    let before = *volume;
    let v = before * exp_small(rate.trace() * dt);
    *volume = v;
    let group = Group {
        elastic: (u.energy * v).sum() as f64,
        dissipated: if M::PLASTIC {
            (u.dissipation * before).sum() as f64
        } else {
            0.0
        },
        max_volume: v.max_element(),
        finite: stress.is_finite() && v.all_finite() && v.min_element() > 0.0,
    };
    (u.plastic_strain, group)
}

/// Step 2 for one particle: ∇v_p = Σ_i v_i ⊗ ∇w_ip from the nodes' `vel`. `nodes` starts at
/// the stencil's first node (node (i, j, k) at `i + j p + k p²`).
#[inline(always)]
pub fn velocity_gradient<D: Dim, const S: usize>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> D::Grad {
    let nodes = &nodes[..stencil_span(D::DIM, p, S)];
    let mut c = [D::Vector::ZERO; 3];
    for k in 0..third_axis_nodes::<D, S>() {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        for j in 0..S {
            let base = j * p + k * p * p;
            let row = &nodes[base..base + S];
            // Σ_i v_i ∂w_i and Σ_i v_i w_i along the row, then the row's weights.
            let (mut a, mut b) = (D::Vector::ZERO, D::Vector::ZERO);
            for i in 0..S {
                a += row[i].vel() * st.dw[i][0];
                b += row[i].vel() * st.w[i][0];
            }
            c[0] += a * (st.w[j][1] * wk);
            c[1] += b * (st.dw[j][1] * wk);
            if D::DIM == 3 {
                c[2] += b * (st.w[j][1] * dwk);
            }
        }
    }
    D::from_columns(c)
}

/// [`velocity_gradient`] in 2D, packing specialisation: both columns in one `Vec4`,
/// (L_xx, L_yx, L_xy, L_yy) = Σ_i (v_i, v_i) ∘ (∂_x w_i ×2, ∂_y w_i ×2).
#[inline(always)]
pub fn velocity_gradient_2d_packed<D: Dim, const S: usize>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> D::Grad {
    debug_assert_eq!(D::DIM, 2);
    let nodes = &nodes[..stencil_span(2, p, S)];
    let l = sum_from_first(S, |j| {
        let row = &nodes[j * p..j * p + S];
        let wj = Vec4::new(st.w[j][1], st.w[j][1], st.dw[j][1], st.dw[j][1]);
        sum_from_first(S, |i| {
            let g = Vec4::new(st.dw[i][0], st.dw[i][0], st.w[i][0], st.w[i][0]) * wj;
            let v = row[i].vel();
            Vec4::new(v[0], v[1], v[0], v[1]) * g
        })
    });
    D::from_columns([
        D::vector([l.x, l.y, 0.0]),
        D::vector([l.z, l.w, 0.0]),
        D::Vector::ZERO,
    ])
}

/// Step 4 for one particle: f_i += A ∇w_ip for the symmetric A = −V_p σ_p, into the nodes'
/// `new_vel`.
#[inline(always)]
pub fn scatter_force<D: Dim, const S: usize>(
    nodes: &mut [Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
    a: D::Sym,
) {
    let nodes = &mut nodes[..stencil_span(D::DIM, p, S)];
    let [a0, a1, a2] = D::sym_columns(a);
    for k in 0..third_axis_nodes::<D, S>() {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        for j in 0..S {
            let base = j * p + k * p * p;
            // A ∇w = A e_x ∂_x w + A e_y ∂_y w (+ A e_z ∂_z w): the row's factors first.
            let pjk = a0 * (st.w[j][1] * wk);
            let mut qjk = a1 * (st.dw[j][1] * wk);
            if D::DIM == 3 {
                qjk += a2 * (st.w[j][1] * dwk);
            }
            let row = &mut nodes[base..base + S];
            for i in 0..S {
                row[i].new_vel += pjk * st.dw[i][0] + qjk * st.w[i][0];
            }
        }
    }
}

/// [`scatter_force`] in 2D, packing specialisation: a node's force from both columns of A in
/// one `Vec4`, (a_xx, a_xy) ∂_x w_i and (a_xy, a_yy) ∂_y w_i side by side.
#[inline(always)]
pub fn scatter_force_2d_packed<D: Dim, const S: usize>(
    nodes: &mut [Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
    a: D::Sym,
) {
    debug_assert_eq!(D::DIM, 2);
    let nodes = &mut nodes[..stencil_span(2, p, S)];
    let [c0, c1, _] = D::sym_columns(a);
    let a = Vec4::new(c0[0], c0[1], c1[0], c1[1]);
    for j in 0..S {
        let wj = a * Vec4::new(st.w[j][1], st.w[j][1], st.dw[j][1], st.dw[j][1]);
        let row = &mut nodes[j * p..j * p + S];
        for i in 0..S {
            let t = wj * Vec4::new(st.dw[i][0], st.dw[i][0], st.w[i][0], st.w[i][0]);
            row[i].new_vel += D::vector([t.x + t.z, t.y + t.w, 0.0]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{Gimp, KernelKind, Linear};
    use crate::math::{D2, D3};
    use crate::step::test_util::{random_stencils, settled_block};
    use crate::{Material, Simulation};

    /// Runs the stress pass of body 0 with the lanes (`lanes = true`) or the reference.
    fn run<D: Dim, K: Kernel<S>, const S: usize>(
        sim: &mut Simulation<D>,
        lanes: bool,
    ) -> StressReport {
        let inv_h = sim.world.inv_h;
        let body = &mut sim.bodies[0];
        let p = &mut sim.particles;
        let state = StressState {
            x: &p.x,
            stress: &mut p.stress,
            volume: &mut p.volume,
            plastic_strain: &mut p.plastic_strain,
        };
        let (grid, lp, dt) = (&mut body.grid, body.radius * inv_h, 1e-4);
        macro_rules! go {
            ($m:expr) => {
                if lanes {
                    update_stress::<D, K, _, S>(grid, state, $m, dt, inv_h, lp)
                } else {
                    update_stress_plain::<D, K, _, S>(grid, state, $m, dt, inv_h, lp)
                }
            };
        }
        match &body.model {
            Model::Elastic(m) => go!(m),
            Model::VonMises(m) => go!(m),
            Model::DruckerPrager(m) => go!(m),
        }
    }

    /// The SIMD-lane stress pass gives what the one-particle-at-a-time reference gives: the
    /// same stresses, volumes, plastic strains, forces and energies up to rounding (the lanes
    /// sum energies in a different order, and 2D's packed loops round differently).
    fn lanes_match_the_reference<D: Dim, K: Kernel<S>, const S: usize>(material: Material) {
        let mut a = settled_block::<D>(material, K::KIND, 30);
        let mut b = a.clone();
        let ra = run::<D, K, S>(&mut a, true);
        let rb = run::<D, K, S>(&mut b, false);
        let (pa, pb) = (a.particles(), b.particles());
        let scale = pb
            .stress
            .iter()
            .flat_map(|s| s.components().to_vec())
            .fold(0.0, |m: Real, c| m.max(c.abs()));
        assert!(scale > 0.0, "the block carries stress");
        for q in 0..pa.len() {
            for (x, y) in pa.stress[q]
                .components()
                .iter()
                .zip(pb.stress[q].components())
            {
                assert!(
                    (x - y).abs() <= 1e-4 * scale,
                    "{}D particle {q}: {:?} vs {:?}",
                    D::DIM,
                    pa.stress[q],
                    pb.stress[q]
                );
            }
            assert!((pa.volume[q] - pb.volume[q]).abs() <= 1e-6 * pb.volume[q]);
            assert!((pa.plastic_strain[q] - pb.plastic_strain[q]).abs() <= 1e-6);
        }
        let (na, nb) = (&a.bodies[0].grid.nodes, &b.bodies[0].grid.nodes);
        let fmax = nb.iter().map(|n| n.new_vel.length()).fold(0.0, Real::max);
        assert!(fmax > 0.0);
        for (x, y) in na.iter().zip(nb) {
            assert!(
                (x.new_vel - y.new_vel).length() <= 1e-4 * fmax,
                "{}D force",
                D::DIM
            );
        }
        assert!(
            (ra.elastic - rb.elastic).abs() <= 1e-5 * rb.elastic.abs(),
            "{} vs {}",
            ra.elastic,
            rb.elastic
        );
        assert!((ra.dissipated - rb.dissipated).abs() <= 1e-4 * rb.dissipated.abs().max(1e-12));
        assert_eq!((ra.bad, ra.max_volume), (rb.bad, rb.max_volume));
    }

    #[test]
    fn stress_pass_in_lanes_matches_the_plain_reference() {
        let sand = || Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0);
        let solid = || Material::von_mises(1e5, 0.3, 1000.0, 2e3);
        lanes_match_the_reference::<D2, Gimp, 3>(sand());
        lanes_match_the_reference::<D3, Gimp, 3>(sand());
        lanes_match_the_reference::<D2, Linear, 2>(solid());
        lanes_match_the_reference::<D3, Linear, 2>(solid());
        let _ = KernelKind::Gimp;
    }

    /// The packed 2D stencil loops give what the generic loops give, up to rounding.
    fn packed_loops_match<K: Kernel<S>, const S: usize>() {
        let p = 10;
        let (nodes, stencils) = random_stencils::<D2, K, S>(50, p);
        for st in &stencils {
            let (g, h) = (
                velocity_gradient::<D2, S>(&nodes, p, st),
                velocity_gradient_2d_packed::<D2, S>(&nodes, p, st),
            );
            let scale = g
                .abs()
                .to_cols_array()
                .iter()
                .fold(1.0, |m: Real, x| m.max(*x));
            assert!(
                (g - h)
                    .abs()
                    .to_cols_array()
                    .iter()
                    .all(|d| *d <= 1e-5 * scale),
                "{g} vs {h}"
            );
            let a = crate::math::Sym2 {
                xx: 1.5,
                yy: -0.7,
                zz: 0.2,
                xy: 0.4,
            };
            let (mut f, mut f2) = (nodes.clone(), nodes.clone());
            scatter_force::<D2, S>(&mut f, p, st, a);
            scatter_force_2d_packed::<D2, S>(&mut f2, p, st, a);
            for (x, y) in f.iter().zip(&f2) {
                assert!((x.new_vel - y.new_vel).length() <= 1e-5 * (1.0 + x.new_vel.length()));
            }
        }
    }

    #[test]
    fn packed_2d_loops_match_the_generic_ones() {
        packed_loops_match::<Linear, 2>();
        packed_loops_match::<Gimp, 3>();
    }
}
