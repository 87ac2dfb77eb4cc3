//! Steps 6–8: back from the grid to the particles, in one walk over each particle's stencil
//! at its position x_p^n,
//!
//! - step 6, the new particle velocity from the grid's new velocities v_i^{n+1} and old ones
//!   v_i^n interpolated at the particle, by the body's transfer ([`super::transfer`]):
//!   v_p ← (1 − α) Σ_i w_ip v_i^{n+1} + α (v_p + Σ_i w_ip (v_i^{n+1} − v_i^n)), and with APIC
//!   C_p = B_p D_p⁻¹, B_p = Σ_i w_ip v_i^{n+1} (x_i − x_p)ᵀ;
//! - for bodies whose stress is updated last ([`super::StressOrder`]), steps 2–3: the
//!   velocity gradient ∇v_p = Σ_i v_i^{n+1} ⊗ ∇w_ip of the same walk, and with it the stress
//!   and volume ([`super::stress`]), for the next step's forces;
//! - step 7, the particle-side walls: a particle whose material (a cube of half-width
//!   `radius` about it) would cross a wall within the step takes the wall rule;
//! - step 8, advection x_p ← x_p + Δt v_p.
//!
//! The pass also sums what the diagnostics report (mass, momentum, energies, bounds).

use super::stress::{
    AfterGather, CHUNK, Rates, StressReport, StressState, StressUpdatedFirst, UpdateStressLast,
};
use super::transfer::Transfer;
use super::{
    BodyStep, Stencils, StressOrder, constraint_dissipation, first_axis_nodes, first_node, layout,
    second_axis_nodes, third_axis, third_axis_nodes, with_kernel,
};
use crate::boundary::Walls;
use crate::grid::{Grid, Node, stencil_span};
use crate::kernel::KernelKind;
use crate::kernel::{Kernel, Stencil};
use crate::material::{Constitutive, WithModel};
use crate::math::{Dim, Real, Vec2, Vec4, VectorOps, sum_from_first};
use crate::sim::{Measure, Simulation};

impl<D: Dim> Simulation<D> {
    /// Steps 6–8 (and 2–3 when the stress is updated last) for every body; `steps` says
    /// which bodies walls or contacts constrained, and takes the stress reports.
    pub(super) fn gather_and_update(
        &mut self,
        dt: Real,
        steps: &mut [BodyStep],
    ) -> Vec<GatherReport<D>> {
        let w = self.world;
        let p = &mut self.particles;
        let mut reports = Vec::with_capacity(self.bodies.len());
        for (body, step) in self.bodies.iter_mut().zip(steps) {
            let r = body.range.clone();
            let state = GatherState {
                x: &mut p.x[r.clone()],
                v: &mut p.v[r.clone()],
                affine: if body.recipe.apic {
                    Some(&mut p.affine[r.clone()])
                } else {
                    None
                },
                mass: &p.mass[r.clone()],
            };
            let stress = StressState {
                stress: &mut p.stress[r.clone()],
                volume: &mut p.volume[r.clone()],
                mass: &p.mass[r.clone()],
                plastic_strain: &mut p.plastic_strain[r.clone()],
                viscous_pressure: &mut p.viscous_pressure[r],
                bulk_length: body.recipe.bulk_length,
            };
            if body.kinematic {
                let g = advect_kinematic(state, dt, &w.walls, body.radius, w.gravity);
                reports.push(g.with_plastic_strain(stress.plastic_strain));
                continue;
            }
            let pass = Pass {
                grid: &body.grid,
                transfer: Transfer::of(&body.recipe).at_constraints(step.constrained),
                dt,
                inv_h: w.inv_h,
                walls: &w.walls,
                radius: body.radius,
                gravity: w.gravity,
            };
            let report = if body.recipe.stress_order == StressOrder::Last {
                let (g, stress) = body.model.with(Last {
                    kernel: w.kernel,
                    pass: &pass,
                    state,
                    stress,
                });
                step.stress = stress;
                g
            } else {
                let g = with_kernel!(w.kernel, K, S => gather::<D, K, _, S>(&pass, state, &mut StressUpdatedFirst));
                g.with_plastic_strain(stress.plastic_strain)
            };
            reports.push(report);
        }
        reports
    }
}

/// The gather of one body whose stress is updated last, run with its model
/// ([`crate::material::Model::with`]): [`gather`] for the kernel, updating the stress chunk by chunk
/// ([`UpdateStressLast`]).
struct Last<'a, D: Dim> {
    kernel: KernelKind,
    pass: &'a Pass<'a, D>,
    state: GatherState<'a, D>,
    stress: StressState<'a, D>,
}

impl<D: Dim> WithModel for Last<'_, D> {
    type Output = (GatherReport<D>, StressReport);
    fn run<M: Constitutive>(self, m: &M) -> Self::Output {
        let mut after = UpdateStressLast {
            model: m,
            state: self.stress,
            dt: self.pass.dt,
            report: StressReport::default(),
        };
        let g = with_kernel!(self.kernel, K, S => gather::<D, K, _, S>(self.pass, self.state, &mut after));
        (
            g.with_plastic_strain(after.state.plastic_strain),
            after.report,
        )
    }
}

/// The particle state the gather reads and writes.
pub struct GatherState<'a, D: Dim> {
    pub x: &'a mut [D::Vector],
    pub v: &'a mut [D::Vector],
    /// The APIC affine velocities, for APIC bodies.
    pub affine: Option<&'a mut [D::Grad]>,
    pub mass: &'a [Real],
}

/// What the gather of one body works with besides its particles.
pub struct Pass<'a, D: Dim> {
    pub grid: &'a Grid<D>,
    pub transfer: Transfer,
    pub dt: Real,
    pub inv_h: Real,
    pub walls: &'a Walls<D>,
    /// Half the particle spacing.
    pub radius: Real,
    pub gravity: D::Vector,
}

/// Steps 6–8 for one body, in chunks of [`CHUNK`] particles: the walks, new velocities and
/// positions of a chunk, then `after` with its velocity gradients (when it wants them).
///
/// Never inlined: each (dimension, kernel, model) instance stays a function of its own (when
/// such instances were inlined into their dispatch, V8 compiled the resulting WebAssembly
/// function much worse; docs/performance.md).
#[inline(never)]
pub fn gather<D: Dim, K: Kernel<S>, A: AfterGather<D>, const S: usize>(
    pass: &Pass<'_, D>,
    ps: GatherState<'_, D>,
    after: &mut A,
) -> GatherReport<D> {
    // PIC (α = 0) needs no old grid velocities; APIC bodies sum B_p in the same walk.
    match (pass.transfer.flip == 0.0, ps.affine.is_some()) {
        (true, false) => gather_chunks::<D, K, A, S, false, false>(pass, ps, after),
        (false, false) => gather_chunks::<D, K, A, S, true, false>(pass, ps, after),
        (true, true) => gather_chunks::<D, K, A, S, false, true>(pass, ps, after),
        (false, true) => gather_chunks::<D, K, A, S, true, true>(pass, ps, after),
    }
}

/// [`gather`], with the old grid velocities interpolated or not (`OLD`), and the APIC
/// B_p or not (`APIC`).
#[inline(always)]
fn gather_chunks<
    D: Dim,
    K: Kernel<S>,
    A: AfterGather<D>,
    const S: usize,
    const OLD: bool,
    const APIC: bool,
>(
    pass: &Pass<'_, D>,
    ps: GatherState<'_, D>,
    after: &mut A,
) -> GatherReport<D> {
    let &Pass {
        grid,
        transfer,
        dt,
        inv_h,
        walls,
        radius,
        gravity,
    } = pass;
    let (p, span) = layout::<D, S>(grid);
    let Grid {
        layout,
        nodes,
        particle_node,
        ..
    } = grid;
    let mut r = GatherReport::<D>::empty();
    let h = 1.0 / inv_h;
    let mut affine = ps.affine;
    let mut rates = Rates::<D>::zero();
    let mut stencils = Stencils::<D, K, S>::new(inv_h, radius * inv_h);
    let n = ps.x.len();
    for first in (0..n).step_by(CHUNK) {
        let chunk = first..n.min(first + CHUNK);
        for q in chunk.clone() {
            let x = ps.x[q];
            let st = stencils.at(ps.x, q);
            let cell = &nodes[first_node(layout, particle_node[q], &st)..][..span];
            // Step 6 (and 2).
            let (v_new, v_old, b) = if !A::GRADIENT {
                if D::DIM == 2 && !APIC {
                    let (n, o) = gather_velocity_2d_packed::<D, K, S, OLD>(cell, p, &st);
                    (n, o, D::GRAD_ZERO)
                } else {
                    gather_velocity::<D, K, S, OLD, APIC>(cell, p, &st)
                }
            } else {
                let (v_new, v_old, grad, b) = if D::DIM == 2 && !APIC {
                    let (n, o, g) = gather_2d_packed::<D, K, S, OLD>(cell, p, &st);
                    (n, o, g, D::GRAD_ZERO)
                } else {
                    gather_particle::<D, K, S, OLD, APIC>(cell, p, &st)
                };
                rates.set(q - first, grad);
                (v_new, v_old, b)
            };
            if APIC && let Some(c) = affine.as_deref_mut() {
                c[q] = Transfer::affine_velocity::<D, S>(b, &st, h);
            }
            let blended = transfer.velocity(ps.v[q], v_new, v_old);
            // Steps 7 and 8.
            let m = ps.mass[q];
            let next = x + blended * dt;
            let (v, x) = if walls.inside(next, radius) {
                (blended, next) // the common case: clear of the walls
            } else {
                let v = walls.particle_velocity(x, blended, dt, radius);
                r.dissipated_walls += constraint_dissipation(m, ps.v[q], blended, v);
                (v, walls.clamp(x + v * dt, radius))
            };
            // Finite values times zero are (signed) zeros; a NaN or an infinity gives NaN.
            let zeros = v * 0.0 + x * 0.0;
            if zeros.dot(zeros) != 0.0 {
                r.bad += 1;
                r.first_bad.get_or_insert(q);
                continue;
            }
            ps.v[q] = v;
            ps.x[q] = x;
            r.record(m, x, v);
        }
        after.chunk(&mut rates, chunk);
    }
    r.finish(gravity);
    r
}

/// Steps 7–8 for a kinematic body: its particles keep their velocities and move, staying
/// inside the domain.
pub fn advect_kinematic<D: Dim>(
    ps: GatherState<'_, D>,
    dt: Real,
    walls: &Walls<D>,
    radius: Real,
    gravity: D::Vector,
) -> GatherReport<D> {
    let mut r = GatherReport::<D>::empty();
    for q in 0..ps.x.len() {
        let x = walls.clamp(ps.x[q] + ps.v[q] * dt, radius);
        ps.x[q] = x;
        r.record(ps.mass[q], x, ps.v[q]);
    }
    r.finish(gravity);
    r
}

/// Step 6 for one particle: (Σ_i w_ip v_i^{n+1}, Σ_i w_ip v_i^n, B_p); without `OLD` (PIC,
/// which needs no old velocities) the second is the first; with `APIC` the third is the B_p
/// of [`gather_affine`], summed in the same walk (zero without). `nodes` starts at the
/// stencil's first node (node (i, j, k) at `i + j p + k p²`).
#[inline(always)]
pub fn gather_velocity<D: Dim, K: Kernel<S>, const S: usize, const OLD: bool, const APIC: bool>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> (D::Vector, D::Vector, D::Grad) {
    let nodes = &nodes[..stencil_span(D::DIM, p, S)];
    let (mut new, mut old) = (D::Vector::ZERO, D::Vector::ZERO);
    let mut b = [D::Vector::ZERO; 3];
    for k in 0..third_axis_nodes::<D, K, S>(st) {
        let (wk, _) = third_axis::<D, S>(st, k);
        for j in 0..second_axis_nodes::<D, K, S>(st) {
            let base = j * p + k * p * p;
            let row = &nodes[base..base + S];
            let (mut rn, mut ro, mut rx) = (D::Vector::ZERO, D::Vector::ZERO, D::Vector::ZERO);
            for i in 0..first_axis_nodes::<D, K, S>(st) {
                let v = row[i].new_vel * st.w[i][0];
                rn += v;
                if APIC {
                    rx += v * st.d[i][0];
                }
                if OLD {
                    ro += row[i].vel() * st.w[i][0];
                }
            }
            let wjk = st.w[j][1] * wk;
            new += rn * wjk;
            old += ro * wjk;
            if APIC {
                affine_row::<D, S>(&mut b, st, rn, rx, wjk, j, k);
            }
        }
    }
    (new, if OLD { old } else { new }, D::from_columns(b))
}

/// A row's share of B_p = Σ_i w_ip v_i^{n+1} ⊗ d_i: `rn` = Σ_i w_i v_i^{n+1} and
/// `rx` = Σ_i w_i d_i v_i^{n+1} along the row, whose weight is `wjk`.
#[inline(always)]
fn affine_row<D: Dim, const S: usize>(
    b: &mut [D::Vector; 3],
    st: &Stencil<S>,
    rn: D::Vector,
    rx: D::Vector,
    wjk: Real,
    j: usize,
    k: usize,
) {
    b[0] += rx * wjk;
    b[1] += rn * (wjk * st.d[j][1]);
    if D::DIM == 3 {
        b[2] += rn * (wjk * st.d[k][2]);
    }
}

/// [`gather_velocity`] in 2D, packing specialisation: v^{n+1} and v^n side by side in one
/// `Vec4`.
#[inline(always)]
pub fn gather_velocity_2d_packed<D: Dim, K: Kernel<S>, const S: usize, const OLD: bool>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> (D::Vector, D::Vector) {
    debug_assert_eq!(D::DIM, 2);
    let nodes = &nodes[..stencil_span(2, p, S)];
    let acc = sum_from_first(second_axis_nodes::<D, K, S>(st), |j| {
        let row = &nodes[j * p..j * p + S];
        sum_from_first(first_axis_nodes::<D, K, S>(st), |i| {
            let (n, o) = (row[i].new_vel, row[i].vel());
            Vec4::new(n[0], n[1], o[0], o[1]) * st.w[i][0]
        }) * st.w[j][1]
    });
    let new = D::vector([acc.x, acc.y, 0.0]);
    (
        new,
        if OLD {
            D::vector([acc.z, acc.w, 0.0])
        } else {
            new
        },
    )
}

/// Steps 6 and 2 for one particle: (Σ_i w_ip v_i^{n+1}, Σ_i w_ip v_i^n,
/// Σ_i v_i^{n+1} ⊗ ∇w_ip, B_p); without `OLD` (PIC) the second is the first; with `APIC` the
/// fourth is the B_p of [`gather_affine`], summed in the same walk (zero without). `nodes`
/// starts at the stencil's first node (node (i, j, k) at `i + j p + k p²`).
#[inline(always)]
pub fn gather_particle<D: Dim, K: Kernel<S>, const S: usize, const OLD: bool, const APIC: bool>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> (D::Vector, D::Vector, D::Grad, D::Grad) {
    let nodes = &nodes[..stencil_span(D::DIM, p, S)];
    let (mut new, mut old) = (D::Vector::ZERO, D::Vector::ZERO);
    let mut c = [D::Vector::ZERO; 3];
    let mut b = [D::Vector::ZERO; 3];
    // The first axis's weights as vectors, once.
    let w: [D::Vector; S] = std::array::from_fn(|i| D::Vector::splat(st.w[i][0]));
    let dw: [D::Vector; S] = std::array::from_fn(|i| D::Vector::splat(st.dw[i][0]));
    for k in 0..third_axis_nodes::<D, K, S>(st) {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        for j in 0..second_axis_nodes::<D, K, S>(st) {
            let base = j * p + k * p * p;
            let row = &nodes[base..base + S];
            // Along the row: Σ_i w_i v_i^{n+1}, Σ_i w_i v_i^n and Σ_i ∂w_i v_i^{n+1}; then the
            // row's weights.
            let (mut rn, mut ro, mut rd) = (D::Vector::ZERO, D::Vector::ZERO, D::Vector::ZERO);
            let mut rx = D::Vector::ZERO;
            for i in 0..first_axis_nodes::<D, K, S>(st) {
                let v = row[i].new_vel;
                let vw = v * w[i];
                rn += vw;
                if APIC {
                    rx += vw * st.d[i][0];
                }
                if OLD {
                    ro += row[i].vel() * w[i];
                }
                rd += v * dw[i];
            }
            let wjk = st.w[j][1] * wk;
            new += rn * wjk;
            old += ro * wjk;
            c[0] += rd * wjk;
            c[1] += rn * (st.dw[j][1] * wk);
            if D::DIM == 3 {
                c[2] += rn * (st.w[j][1] * dwk);
            }
            if APIC {
                affine_row::<D, S>(&mut b, st, rn, rx, wjk, j, k);
            }
        }
    }
    let old = if OLD { old } else { new };
    (new, old, D::from_columns(c), D::from_columns(b))
}

/// [`gather_particle`] in 2D, packing specialisation: along a row, (v^{n+1} w_i, v^n w_i) —
/// or for PIC (v^{n+1} w_i, v^{n+1} ∂w_i) — in one `Vec4`, then the two gradient columns
/// (Σ_i ∂w_i v_i^{n+1}) w_j and (Σ_i w_i v_i^{n+1}) ∂w_j side by side in another.
#[inline(always)]
pub fn gather_2d_packed<D: Dim, K: Kernel<S>, const S: usize, const OLD: bool>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> (D::Vector, D::Vector, D::Grad) {
    debug_assert_eq!(D::DIM, 2);
    let nodes = &nodes[..stencil_span(2, p, S)];
    let (mut vel, mut grad) = (Vec4::ZERO, Vec4::ZERO);
    for j in 0..second_axis_nodes::<D, K, S>(st) {
        let row = &nodes[j * p..j * p + S];
        // rn: Σ_i w_i v_i^{n+1}, rd: Σ_i ∂w_i v_i^{n+1}, ro: Σ_i w_i v_i^n.
        let (rn, rd, ro) = if OLD {
            let (mut rv, mut rd) = (Vec4::ZERO, Vec2::ZERO);
            for i in 0..first_axis_nodes::<D, K, S>(st) {
                let (n, o) = (row[i].new_vel, row[i].vel());
                rv += Vec4::new(n[0], n[1], o[0], o[1]) * st.w[i][0];
                rd += Vec2::new(n[0], n[1]) * st.dw[i][0];
            }
            (Vec2::new(rv.x, rv.y), rd, Vec2::new(rv.z, rv.w))
        } else {
            let mut r = Vec4::ZERO;
            for i in 0..first_axis_nodes::<D, K, S>(st) {
                let n = row[i].new_vel;
                r += Vec4::new(n[0], n[1], n[0], n[1])
                    * Vec4::new(st.w[i][0], st.w[i][0], st.dw[i][0], st.dw[i][0]);
            }
            let rn = Vec2::new(r.x, r.y);
            (rn, Vec2::new(r.z, r.w), rn)
        };
        vel += Vec4::new(rn.x, rn.y, ro.x, ro.y) * st.w[j][1];
        grad += Vec4::new(rd.x, rd.y, rn.x, rn.y)
            * Vec4::new(st.w[j][1], st.w[j][1], st.dw[j][1], st.dw[j][1]);
    }
    let new = D::vector([vel.x, vel.y, 0.0]);
    let old = if OLD {
        D::vector([vel.z, vel.w, 0.0])
    } else {
        new
    };
    (
        new,
        old,
        D::from_columns([
            D::vector([grad.x, grad.y, 0.0]),
            D::vector([grad.z, grad.w, 0.0]),
            D::Vector::ZERO,
        ]),
    )
}

/// Step 6 of APIC for one particle: B = Σ_i w_ip v_i^{n+1} ⊗ d_i (offsets in cells), in a walk
/// of its own: the reference that the walks summing it on the way are tested against.
#[inline(always)]
pub fn gather_affine<D: Dim, K: Kernel<S>, const S: usize>(
    nodes: &[Node<D::Vector>],
    p: usize,
    st: &Stencil<S>,
) -> D::Grad {
    let nodes = &nodes[..stencil_span(D::DIM, p, S)];
    let mut c = [D::Vector::ZERO; 3];
    for k in 0..third_axis_nodes::<D, K, S>(st) {
        let (wk, _) = third_axis::<D, S>(st, k);
        for j in 0..second_axis_nodes::<D, K, S>(st) {
            let base = j * p + k * p * p;
            let row = &nodes[base..base + S];
            let (mut rn, mut rx) = (D::Vector::ZERO, D::Vector::ZERO);
            for i in 0..first_axis_nodes::<D, K, S>(st) {
                let v = row[i].new_vel * st.w[i][0];
                rn += v;
                rx += v * st.d[i][0];
            }
            let wjk = st.w[j][1] * wk;
            c[0] += rx * wjk;
            c[1] += rn * (wjk * st.d[j][1]);
            if D::DIM == 3 {
                c[2] += rn * (wjk * st.d[k][2]);
            }
        }
    }
    D::from_columns(c)
}

/// What the gather pass measured (after the step): the figures of the particle state it
/// recorded ([`Measure`], which it dereferences to) and what it did itself.
#[derive(Clone, Copy, Debug)]
pub struct GatherReport<D: Dim> {
    pub measure: Measure<D>,
    /// Kinetic energy removed by the particle-side wall projection.
    pub dissipated_walls: f64,
    pub bad: usize,
    pub first_bad: Option<usize>,
}

impl<D: Dim> GatherReport<D> {
    /// Nothing recorded yet.
    pub fn empty() -> Self {
        GatherReport {
            measure: Measure::empty(),
            dissipated_walls: 0.0,
            bad: 0,
            first_bad: None,
        }
    }

    /// With the largest plastic strain of the particles.
    pub fn with_plastic_strain(mut self, plastic_strain: &[Real]) -> Self {
        self.measure = self.measure.with_plastic_strain(plastic_strain);
        self
    }
}

impl<D: Dim> std::ops::Deref for GatherReport<D> {
    type Target = Measure<D>;
    fn deref(&self) -> &Measure<D> {
        &self.measure
    }
}

impl<D: Dim> std::ops::DerefMut for GatherReport<D> {
    fn deref_mut(&mut self) -> &mut Measure<D> {
        &mut self.measure
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{Gimp, Linear};
    use crate::math::{D2, D3};
    use crate::step::test_util::random_stencils;

    /// The packed 2D gather gives what the generic walk gives, up to rounding.
    fn packed_gather_matches<K: Kernel<S>, const S: usize>() {
        let p = 10;
        let (nodes, stencils) = random_stencils::<D2, K, S>(50, p);
        for st in &stencils {
            let (n, o, g, _) = gather_particle::<D2, K, S, true, false>(&nodes, p, st);
            let (n2, o2, g2) = gather_2d_packed::<D2, K, S, true>(&nodes, p, st);
            // PIC: v^{n+1} twice and the same gradient up to rounding; the velocity-only walks
            // as the full ones.
            let (n3, o3, g3) = gather_2d_packed::<D2, K, S, false>(&nodes, p, st);
            let (n4, o4) = gather_velocity_2d_packed::<D2, K, S, true>(&nodes, p, st);
            let (n5, o5, _) = gather_velocity::<D2, K, S, true, false>(&nodes, p, st);
            let big = 1.0
                + g2.abs()
                    .to_cols_array()
                    .iter()
                    .fold(0.0, |m: Real, x| m.max(*x));
            let dg3 = (g3 - g2)
                .abs()
                .to_cols_array()
                .iter()
                .fold(0.0, |m: Real, x| m.max(*x));
            assert!(
                n3 == n2 && o3 == n3 && dg3 <= 1e-5 * big,
                "PIC {g3} vs {g2}"
            );
            assert!((n4 - n5).length() <= 1e-6 && (o4 - o5).length() <= 1e-6);
            assert!((n4 - n).length() <= 1e-6 && (o4 - o).length() <= 1e-6);
            let scale = 1.0
                + g.abs()
                    .to_cols_array()
                    .iter()
                    .fold(0.0, |m: Real, x| m.max(*x));
            let dg = (g - g2)
                .abs()
                .to_cols_array()
                .iter()
                .fold(0.0, |m: Real, x| m.max(*x));
            assert!(
                (n - n2).length() <= 1e-6 && (o - o2).length() <= 1e-6 && dg <= 1e-5 * scale,
                "{n} {o} {g} vs {n2} {o2} {g2}"
            );
        }
    }

    /// The walks that sum APIC's B_p on the way give what its own walk gives.
    fn fused_affine_matches<D: Dim, K: Kernel<S>, const S: usize>() {
        let p = 10;
        let (nodes, stencils) = random_stencils::<D, K, S>(50, p);
        for st in &stencils {
            let b = gather_affine::<D, K, S>(&nodes, p, st);
            let (n, o, _) = gather_velocity::<D, K, S, true, false>(&nodes, p, st);
            let (n1, o1, b1) = gather_velocity::<D, K, S, true, true>(&nodes, p, st);
            let (n2, o2, _, b2) = gather_particle::<D, K, S, true, true>(&nodes, p, st);
            assert_eq!((n1, o1), (n, o));
            for (a, c) in [(b, b1), (b, b2)] {
                for col in 0..D::DIM {
                    let d = D::column(&a, col) - D::column(&c, col);
                    assert!(d.length() <= 1e-6 * (1.0 + D::column(&a, col).length()));
                }
            }
            assert!((n2 - n).length() <= 1e-6 && (o2 - o).length() <= 1e-6);
        }
    }

    #[test]
    fn walks_summing_apic_b_match_its_own_walk() {
        fused_affine_matches::<D2, Gimp, 3>();
        fused_affine_matches::<D3, Gimp, 3>();
        fused_affine_matches::<D3, crate::kernel::QuadraticBspline, 3>();
    }

    #[test]
    fn packed_2d_gather_matches_the_generic_one() {
        packed_gather_matches::<Linear, 2>();
        packed_gather_matches::<Gimp, 3>();
    }
}
