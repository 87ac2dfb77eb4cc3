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

use super::report::{GatherReport, StressReport};
use super::stress::{AfterGather, StressState, StressUpdatedFirst, UpdateStressLast};
use super::transfer::Transfer;
use super::walk::{self, CHUNK, Field, Rates, Walker};
use super::{BodyStep, Step, StressOrder, constraint_dissipation};
use crate::boundary::Walls;
use crate::grid::{Grid, Node};
use crate::kernel::{Kernel, KernelKind, with_kernel};
use crate::material::{Constitutive, WithModel};
use crate::math::{Dim, Real, VectorOps};

impl<D: Dim> Step<'_, D> {
    /// Steps 6–8 (and 2–3 when the stress is updated last) for every body; `steps` says
    /// which bodies walls or contacts constrained, and takes the stress reports.
    pub(super) fn gather_and_update(
        &mut self,
        dt: Real,
        steps: &mut [BodyStep],
    ) -> Vec<GatherReport<D>> {
        let w = self.world;
        let p = &mut *self.particles;
        let mut reports = Vec::with_capacity(self.bodies.len());
        for (body, step) in self.bodies.iter_mut().zip(steps) {
            let r = body.active();
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
                closing: body.recipe.closing,
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
    let mut walker = Walker::<D, K, S>::new(layout, particle_node, inv_h, radius * inv_h);
    let n = ps.x.len();
    for first in (0..n).step_by(CHUNK) {
        let chunk = first..n.min(first + CHUNK);
        for q in chunk.clone() {
            let x = ps.x[q];
            let at = walker.at(ps.x, q);
            let (new, old) = if A::GRADIENT {
                walk::gather::<D, K, S, _>(nodes, &at, node_fields::<D, true, APIC, OLD>)
            } else {
                walk::gather::<D, K, S, _>(nodes, &at, node_fields::<D, false, APIC, OLD>)
            };
            if A::GRADIENT {
                rates.set(q - first, new.gradient);
            }
            if APIC && let Some(c) = affine.as_deref_mut() {
                c[q] = Transfer::affine_velocity::<D, S>(new.moment, &at.st, h);
            }
            let (v_new, v_old) = (new.value, if OLD { old.value } else { new.value });
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

/// The gather's terms at node i, stated once: step 6's Σ_i w_ip v_i^{n+1} (v_PIC), with APIC
/// its moment B_p = Σ_i w_ip v_i^{n+1} ⊗ d_i (`APIC`), and for FLIP Σ_i w_ip v_i^n (`OLD`);
/// step 2 for the stress updated last, ∇v_p = Σ_i v_i^{n+1} ⊗ ∇w_ip (`GRADIENT`).
#[inline(always)]
#[allow(clippy::type_complexity)]
fn node_fields<D: Dim, const GRADIENT: bool, const APIC: bool, const OLD: bool>(
    n: &Node<D::Vector>,
) -> (Field<D, true, GRADIENT, APIC>, Field<D, OLD, false, false>) {
    (Field(n.new_vel), Field(n.vel()))
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
