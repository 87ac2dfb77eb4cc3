//! Steps 2–3: from the velocity gradient at the particle, ∇v_p = Σ_i v_i ⊗ ∇w_ip, split into
//! the strain rate ε̇ = ½(∇v + ∇vᵀ) and the spin ω = ½(∇v − ∇vᵀ),
//!
//! - the stress σ_p ← σ_p + Δt σ̇(ε̇, ω) by the body's constitutive model (the Jaumann rate of
//!   Eq. 2–6 with the model's plastic return), and
//! - the volume V_p ← V_p exp(Δt tr ε̇), the exact solution of V̇ = V tr ε̇ for the step's
//!   rate: first order the same as V_p (1 + Δt tr ε̇), but never zero or negative however
//!   violent the compression.
//!
//! **Grains that part and close again** (granular models, those with a
//! [`Constitutive::packed_specific_volume`], in a body whose recipe closes them,
//! [`crate::recipe::Recipe::closing`]; a departure from the paper, docs/method.md):
//! cohesionless sand past its apex carries no stress, and its grains part: a particle's volume
//! grows beyond its packed volume V_d = m_p/ρ. Such a particle (no compression, p ≤
//! [`PARTED_PRESSURE`] K, and V_p > V_d) is parted: a compression first closes it, and only
//! what the step compresses it below V_d stresses it, so separated sand regains its density
//! when it is pressed together again (Klár et al. 2016's volume correction, in rate form). The
//! stress update then takes the volumetric rate tr ε̇ + c/Δt, where c is the part of the
//! step's compression −tr ε̇ Δt that takes the volume back to V_d. The volume follows the
//! motion as before. A parted particle's volume may grow to [`PARTED_LOOSEST`] V_d, a stressed
//! one's to [`LOOSEST`] V_d; without closing, every granular particle's volume to [`LOOSEST`] V_d.
//!
//! When they run depends on the kernel and the material ([`super::StressOrder`]):
//!
//! - **first**, Sec. 4.2's order (the linear kernel, and sand): [`update_stress_first`] takes
//!   ∇v from the grid velocities v_i^n of step 1, updates the stress and scatters the internal
//!   forces f_i = −Σ_p V_p σ_p ∇w_ip of step 4;
//! - **last** (solids with the C¹ kernels): the gather takes ∇v from the new grid velocities
//!   v_i^{n+1} in its own walk and calls [`UpdateStressLast`] on each chunk of particles; the
//!   next step's scatter turns the stress into forces.
//!
//! **The solids' artificial bulk viscosity** (a departure from the paper, docs/method.md): a
//! compressing solid particle carries besides σ_p a pressure
//!
//! q_p = ρ_p (C h tr ε̇_p)²  where tr ε̇_p < 0 (else 0),   C = [`BULK_VISCOSITY`],
//!
//! computed with its stress update and added to the force that stress makes,
//! f_i = −Σ_p V_p (σ_p − q_p I) ∇w_ip (von Neumann & Richtmyer 1950, as explicit shock codes
//! do). It spreads a shock over a few cells and dissipates what a blow faster than the body's
//! waves brings and the log-strain law cannot store (docs/stability.md); at the slow
//! compressions of the validation cases q is a small fraction of the stress. Its work
//! q V |tr ε̇| Δt is booked as `dissipated_viscous`, and the time step resolves it
//! ([`crate::sim::Body::signal_speed`]). Sand has none.
//!
//! **Sand's cell-averaged volumetric rate** (an option, off by default): with it, each
//! gradient's volumetric part is replaced by its cell's mean before the update
//! ([`super::volumetric`]).
//!
//! The update is written once, generic over the number type (`update_group`): [`update_one`]
//! runs it for one particle and is the reference; [`update_chunk`] (in `stress/lanes.rs`), the
//! one the passes run, is its SIMD specialisation: eight particles per model call in SIMD lanes
//! ([`super::walk::update_in_lanes`]; the update is a long dependency chain, and in lanes
//! eight chains advance at once), with the energies and the finiteness test per chunk. A test
//! checks that they agree bit for bit.

use super::Step;
use super::report::StressReport;
use super::scatter::internal_force;
use super::volumetric::{sum_cell_dilatation, with_volumetric_rate};
use super::walk::{self, At, CHUNK, Rates, Walker};
use crate::grid::Grid;
use crate::kernel::{Kernel, KernelKind, Stencil, with_kernel};
use crate::material::{Constitutive, LOOSEST, PARTED_LOOSEST, VolumetricRate, WithModel};
use crate::math::{Dim, Number, Real, SymTensor, exp_small, max};
use std::ops::Range;

mod lanes;
pub use lanes::update_chunk;

impl<D: Dim> Step<'_, D> {
    /// Steps 2–4, particle side, in Sec. 4.2's order, for the bodies that take it (the
    /// others' stress is updated in the gather); their reports go to `steps`.
    pub(super) fn update_stress_first(&mut self, dt: Real, steps: &mut [super::BodyStep]) {
        let inv_h = self.world.inv_h;
        let kernel = self.world.kernel;
        let p = &mut self.particles;
        for (body, step) in self.bodies.iter_mut().zip(steps) {
            if body.kinematic || body.recipe.stress_order != super::StressOrder::First {
                continue;
            }
            let r = body.active();
            let x = &p.x[r.clone()];
            let state = StressState {
                stress: &mut p.stress[r.clone()],
                volume: &mut p.volume[r.clone()],
                mass: &p.mass[r.clone()],
                plastic_strain: &mut p.plastic_strain[r.clone()],
                viscous_pressure: &mut p.viscous_pressure[r],
                bulk_length: body.recipe.bulk_length,
                closing: body.recipe.closing,
            };
            let lp = body.radius * inv_h;
            let grid = &mut body.grid;
            let average = body.recipe.volumetric_rate == VolumetricRate::CellAverage;
            step.stress = body.model.with(First {
                kernel,
                grid,
                x,
                state,
                dt,
                inv_h,
                lp,
                average,
            });
        }
    }
}

/// Steps 2–4 of one body whose stress is updated first, run with its model
/// ([`crate::material::Model::with`]): [`update_stress_first`] for the kernel, after [`sum_cell_dilatation`]
/// when the body's recipe takes the cell-averaged volumetric rate.
struct First<'a, D: Dim> {
    kernel: KernelKind,
    grid: &'a mut Grid<D>,
    x: &'a [D::Vector],
    state: StressState<'a, D>,
    dt: Real,
    inv_h: Real,
    lp: Real,
    average: bool,
}

impl<D: Dim> WithModel for First<'_, D> {
    type Output = StressReport;
    fn run<M: Constitutive>(self, m: &M) -> StressReport {
        let First {
            kernel,
            grid,
            x,
            state,
            dt,
            inv_h,
            lp,
            average,
        } = self;
        with_kernel!(kernel, K, S => if average {
            sum_cell_dilatation::<D, K, S>(grid, x, state.volume, inv_h, lp);
            update_stress_first::<D, K, _, S, true>(grid, x, state, m, dt, inv_h, lp)
        } else {
            update_stress_first::<D, K, _, S, false>(grid, x, state, m, dt, inv_h, lp)
        })
    }
}

/// The particle state the stress update reads and writes.
pub struct StressState<'a, D: Dim> {
    pub stress: &'a mut [D::Sym],
    pub volume: &'a mut [Real],
    pub mass: &'a [Real],
    pub plastic_strain: &'a mut [Real],
    /// The bulk viscosity's pressure, written by the update when `bulk_length` > 0.
    pub viscous_pressure: &'a mut [Real],
    /// The bulk viscosity's length C h ([`BULK_VISCOSITY`]): zero for none (sand).
    pub bulk_length: Real,
    /// Whether parted grains close again ([`crate::recipe::Recipe::closing`]).
    pub closing: bool,
}

/// Steps 2–4, particle side, for one body in Sec. 4.2's order, in chunks of [`CHUNK`]
/// particles: their velocity gradients from the grid velocities v_i^n, their stress updates
/// ([`update_chunk`]), then their internal forces f_i += −V_p σ_p ∇w_ip (into the nodes'
/// `new_vel`). In 2D the stencil loops are the packed ones.
///
/// With `CELL_AVERAGE` each gradient's volumetric part is replaced by its cell's mean
/// ([`with_volumetric_rate`]) from the sums [`sum_cell_dilatation`] left in the grid.
///
/// Never inlined: each (dimension, kernel, model) instance stays a function of its own (when
/// such instances were inlined into their dispatch, V8 compiled the resulting WebAssembly
/// function much worse; docs/performance.md).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub fn update_stress_first<
    D: Dim,
    K: Kernel<S>,
    M: Constitutive,
    const S: usize,
    const CELL_AVERAGE: bool,
>(
    grid: &mut Grid<D>,
    x: &[D::Vector],
    mut ps: StressState<'_, D>,
    model: &M,
    dt: Real,
    inv_h: Real,
    lp: Real,
) -> StressReport {
    let Grid {
        layout,
        nodes,
        particle_node,
        cell_dilatation,
        ..
    } = &mut *grid;
    let mut report = StressReport::default();
    let mut at = [At {
        st: Stencil::<S>::at([0; 3]),
        origin: 0,
    }; CHUNK];
    let mut rates = Rates::<D>::zero();
    let mut walker = Walker::<D, K, S>::new(layout, particle_node, inv_h, lp);
    for first in (0..x.len()).step_by(CHUNK) {
        let chunk = first..x.len().min(first + CHUNK);
        for (i, q) in chunk.clone().enumerate() {
            at[i] = walker.at(x, q);
            // ∇v_p = Σ_i v_i^n ⊗ ∇w_ip.
            let mut grad = walk::gradient::<D, K, S>(nodes, &at[i], |n| n.vel());
            if CELL_AVERAGE {
                let [sum, volume] = cell_dilatation[walk::cell_node::<D, S>(x[q], inv_h, &at[i])];
                grad = with_volumetric_rate::<D>(grad, sum / volume);
            }
            rates.set(i, grad);
        }
        let bad = report.bad;
        update_chunk(
            model,
            &mut rates,
            ps.slice(chunk.clone()),
            first,
            dt,
            &mut report,
        );
        for (i, q) in chunk.enumerate() {
            let v = ps.volume[q];
            let viscous = (ps.bulk_length > 0.0).then(|| ps.viscous_pressure[q]);
            let force = internal_force::<D>(ps.stress[q], v, viscous);
            // A particle the update left non-finite (reported) gives no force.
            if report.bad > bad && !(force.is_finite() && v > 0.0) {
                continue;
            }
            // f_i += F_p ∇w_ip.
            walk::scatter::<D, K, S, _>(nodes, &at[i], |n, w| n.new_vel += w.gradient_times(force));
        }
    }
    grid.reduce_nodes(|o, h| o.new_vel += h.new_vel);
    report
}

/// What the gather does with the velocity gradients of each chunk of particles.
pub trait AfterGather<D: Dim> {
    /// Whether the gather forms velocity gradients at all.
    const GRADIENT: bool;
    /// Called with the rates and spins of the particles of `chunk` (at most [`CHUNK`]).
    fn chunk(&mut self, rates: &mut Rates<D>, chunk: Range<usize>);
}

/// The stress was updated before the forces (Sec. 4.2's order): the gather forms no
/// gradients.
pub struct StressUpdatedFirst;

impl<D: Dim> AfterGather<D> for StressUpdatedFirst {
    const GRADIENT: bool = false;
    #[inline(always)]
    fn chunk(&mut self, _: &mut Rates<D>, _: Range<usize>) {}
}

/// Steps 2–3 at the end of the step, on each chunk the gather walked.
pub struct UpdateStressLast<'a, D: Dim, M> {
    pub model: &'a M,
    pub state: StressState<'a, D>,
    pub dt: Real,
    pub report: StressReport,
}

impl<D: Dim, M: Constitutive> AfterGather<D> for UpdateStressLast<'_, D, M> {
    const GRADIENT: bool = true;
    #[inline(always)]
    fn chunk(&mut self, rates: &mut Rates<D>, chunk: Range<usize>) {
        let first = chunk.start;
        let state = self.state.slice(chunk);
        update_chunk(self.model, rates, state, first, self.dt, &mut self.report);
    }
}

impl<D: Dim> StressState<'_, D> {
    /// The state of the particles of `r`.
    #[inline(always)]
    pub fn slice(&mut self, r: Range<usize>) -> StressState<'_, D> {
        StressState {
            stress: &mut self.stress[r.clone()],
            volume: &mut self.volume[r.clone()],
            mass: &self.mass[r.clone()],
            plastic_strain: &mut self.plastic_strain[r.clone()],
            viscous_pressure: &mut self.viscous_pressure[r],
            bulk_length: self.bulk_length,
            closing: self.closing,
        }
    }
}

/// Steps 2–3 for one particle (`q`: its index, for the report): `update_group` for one,
/// the reference that a test compares [`update_chunk`] with.
#[allow(clippy::too_many_arguments)]
pub fn update_one<D: Dim, M: Constitutive>(
    model: &M,
    rate: D::Sym,
    spin: <D::Sym as SymTensor>::Spin,
    stress: &mut D::Sym,
    volume: &mut Real,
    mass: Real,
    plastic_strain: &mut Real,
    closing: bool,
    dt: Real,
    q: usize,
    report: &mut StressReport,
) {
    let packed = model.packed_specific_volume().map(|s| mass * s);
    let (ep, u) = update_group(
        model,
        stress,
        rate,
        spin,
        *plastic_strain,
        volume,
        packed,
        closing,
        None,
        dt,
    );
    if M::PLASTIC {
        *plastic_strain += ep;
    }
    if !u.finite {
        report.bad(q, stress.is_finite(), *volume);
        return;
    }
    report.elastic += u.elastic;
    report.dissipated += u.dissipated;
    report.max_volume = max(report.max_volume, u.max_volume);
}

pub use crate::recipe::BULK_VISCOSITY;

/// What one constitutive call (for one particle, or for several in SIMD lanes) adds to the
/// report.
struct Group {
    /// Σ V W(σ) after the update, and Σ V D (energy the plastic correction removed).
    pub elastic: f64,
    pub dissipated: f64,
    pub max_volume: Real,
    /// The bulk viscosity's work Σ q V |tr ε̇| Δt and the fastest compression |tr ε̇|.
    pub viscous: f64,
    pub max_compression: Real,
    pub finite: bool,
}

/// The most pressure a parted granular particle carries, as a fraction of its bulk modulus K
/// (the module's *Grains that part*): zero to rounding. Sand at its apex carries none, and the
/// returned stress's rounding is about 10⁻¹⁰ K; a millimetre of the page's sand (K ≈ 0.3 MPa)
/// weighs 70 times more.
pub const PARTED_PRESSURE: Real = 1e-6;

/// Steps 2–3 for one particle, or for a group of particles in lanes: the stress by the model
/// (returning their plastic strain increments) and the volume; with `packed` = m/ρ (a
/// granular model) the volume is bounded by it, and with `closing` too its parted grains
/// close again (the module's documentation); with
/// `bulk` = (m (C h)², q), the bulk viscosity q = ρ (C h tr ε̇)² = m (C h)² (tr ε̇)²/V of the
/// compressing particles, whose work q V |tr ε̇| Δt = m (C h)² |tr ε̇|³ Δt needs no division.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn update_group<S: SymTensor, M: Constitutive>(
    model: &M,
    stress: &mut S,
    rate: S,
    spin: S::Spin,
    history: S::Scalar,
    volume: &mut S::Scalar,
    packed: Option<S::Scalar>,
    closing: bool,
    bulk: Option<(S::Scalar, &mut S::Scalar)>,
    dt: Real,
) -> (S::Scalar, Group) {
    // The volume follows the motion: V̇ = V tr ε̇.
    let dilatation = rate.trace() * dt;
    let (mut rate, mut cap) = (rate, packed.map(|v_d| v_d * LOOSEST as Real));
    if let (Some(packed), true) = (packed, closing) {
        // Grains that part and close again (the module's documentation).
        let (zero, one) = (S::Scalar::ZERO, S::Scalar::ONE);
        let uncompressed = S::Scalar::splat(-3.0 * PARTED_PRESSURE * model.elastic().k);
        let parted = S::Scalar::select_gt(stress.trace(), uncompressed, one, zero);
        let loose = S::Scalar::select_gt(*volume, packed, parted, zero);
        // what compresses it below V_d: ln(V e^Δ / V_d) if negative, to first order (it is
        // small: the step that crosses V_d)
        let stressing = (*volume * exp_small(dilatation) / packed - one).min(zero);
        let closing = (stressing - dilatation).max(zero) * loose;
        rate += S::iso(closing * (1.0 / (3.0 * dt)));
        cap = Some(packed * (parted * (PARTED_LOOSEST - LOOSEST) as Real + LOOSEST as Real));
    }
    let u = model.update(stress, rate, spin, history, dt);
    let before = *volume;
    let mut v = before * exp_small(dilatation);
    if let Some(cap) = cap {
        v = v.min(before.max(cap));
    }
    *volume = v;
    let (mut viscous, mut max_compression) = (0.0, 0.0);
    if let Some((ml2, q)) = bulk {
        let c = (-rate.trace()).max(S::Scalar::ZERO);
        let c2 = ml2 * (c * c);
        *q = c2 / v;
        viscous = ((c2 * c).sum() * dt) as f64;
        max_compression = c.max_element();
    }
    let group = Group {
        elastic: (u.energy * v).sum() as f64,
        dissipated: if M::PLASTIC {
            (u.dissipation * before).sum() as f64
        } else {
            0.0
        },
        max_volume: v.max_element(),
        viscous,
        max_compression,
        finite: stress.is_finite() && v.all_finite() && v.min_element() > 0.0,
    };
    (u.plastic_strain, group)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, Model};
    use crate::math::VectorOps;
    use crate::math::{D2, D3, Mat2, Sym2, Vec2};
    use crate::step::test_util::noise;
    use crate::step::volumetric::divergence;

    /// Made-up but plausible velocity gradients (1/s) and stresses (Pa) for `n` particles.
    fn states<D: Dim>(n: usize) -> Vec<(D::Grad, D::Sym)> {
        let mut seed = 11;
        (0..n)
            .map(|_| {
                let mut cols = [D::vector([0.0; 3]); 3];
                for c in &mut cols {
                    *c = D::vector([0; 3].map(|_| 3.0 * noise(&mut seed)));
                }
                let grad = D::from_columns(cols);
                let (e, _) = D::rate_and_spin(D::from_columns(
                    [0; 3].map(|_| D::vector([0; 3].map(|_| noise(&mut seed)))),
                ));
                (grad, e * 2e3 - D::Sym::IDENTITY * 1e3)
            })
            .collect()
    }

    /// The SIMD-lane update gives, particle by particle, exactly the stress, volume and
    /// plastic strain the one-particle reference gives (the same IEEE operations in the same
    /// order), and the same energies up to the order of the sums; for full and short chunks,
    /// elastic and yielding particles.
    fn lanes_match_the_reference<D: Dim, M: Constitutive>(model: &M) {
        for closing in [false, true] {
            lanes_match_the_reference_closing::<D, M>(model, closing);
        }
    }

    /// [`lanes_match_the_reference`] with parted grains closing again or not: every fourth
    /// particle carries no stress (a parted grain where the volume exceeds the packed one).
    fn lanes_match_the_reference_closing<D: Dim, M: Constitutive>(model: &M, closing: bool) {
        let n = 2 * CHUNK + 3;
        let s = states::<D>(n);
        let (mut stress, mut volume, mut plastic) = (
            s.iter()
                .enumerate()
                .map(|(q, x)| if q % 4 == 0 { D::Sym::ZERO } else { x.1 })
                .collect::<Vec<_>>(),
            (0..n).map(|q| 1e-4 * (1.0 + q as Real)).collect::<Vec<_>>(),
            vec![0.1; n],
        );
        // masses at 1000 to 3000 kg/m³: the sand's volume bound (twice the volume at 2200
        // kg/m³) binds for the expanding particles of the lightest
        let mass: Vec<Real> = (0..n)
            .map(|q| volume[q] * (1000.0 + 2000.0 * (q % 3) as Real / 2.0))
            .collect();
        let (mut stress2, mut volume2, mut plastic2) =
            (stress.clone(), volume.clone(), plastic.clone());
        let mut viscous = vec![0.0; n];
        let (mut lanes, mut plain) = (StressReport::default(), StressReport::default());
        let dt = 1e-3;
        let mut rates = Rates::<D>::zero();
        for first in (0..n).step_by(CHUNK) {
            let r = first..n.min(first + CHUNK);
            for q in r.clone() {
                rates.set(q - first, s[q].0);
            }
            let ps = StressState::<D> {
                stress: &mut stress[r.clone()],
                volume: &mut volume[r.clone()],
                mass: &mass[r.clone()],
                plastic_strain: &mut plastic[r.clone()],
                viscous_pressure: &mut viscous[r.clone()],
                bulk_length: 0.0,
                closing,
            };
            update_chunk(model, &mut rates, ps, first, dt, &mut lanes);
            for q in r {
                let (rate, spin) = D::rate_and_spin(s[q].0);
                let (s2, v2, p2) = (&mut stress2[q], &mut volume2[q], &mut plastic2[q]);
                let m = mass[q];
                update_one::<D, M>(model, rate, spin, s2, v2, m, p2, closing, dt, q, &mut plain);
            }
        }
        assert_eq!((stress, volume, plastic), (stress2, volume2, plastic2));
        assert!((lanes.elastic - plain.elastic).abs() <= 1e-6 * plain.elastic);
        assert!((lanes.dissipated - plain.dissipated).abs() <= 1e-6 * plain.dissipated.abs());
        assert_eq!((lanes.max_volume, lanes.bad), (plain.max_volume, plain.bad));
        if M::PLASTIC {
            assert!(plain.dissipated > 0.0, "some particles yield");
        }
    }

    /// A body's particles, `ppc` per cell along each axis over a few cells of h = 0.1 m (their
    /// volumes differing from particle to particle), and its grid, allocated where their
    /// stencils reach, whose nodes move at `v(x)`.
    struct Cells<D: Dim> {
        grid: Grid<D>,
        x: Vec<D::Vector>,
        volume: Vec<Real>,
        inv_h: Real,
        lp: Real,
    }

    fn cells<D: Dim, K: Kernel<S>, const S: usize>(
        ppc: usize,
        v: impl Fn([Real; 3]) -> [Real; 3],
    ) -> Cells<D> {
        let (h, n) = (0.1, 3);
        let inv_h = 1.0 / h;
        let lp = 0.5 / ppc as Real;
        let per_axis = n * ppc;
        let count = per_axis.pow(D::DIM as u32);
        let x: Vec<D::Vector> = (0..count)
            .map(|q| {
                let mut c = [0.0; 3];
                let mut r = q;
                for a in c.iter_mut().take(D::DIM) {
                    *a = h * (1.0 + ((r % per_axis) as Real + 0.5) / ppc as Real);
                    r /= per_axis;
                }
                D::vector(c)
            })
            .collect();
        let volume = (0..count)
            .map(|q| (h / ppc as Real).powi(D::DIM as i32) * (1.0 + 0.1 * (q % 7) as Real))
            .collect();
        let mut grid = Grid::<D>::default();
        grid.rebuild(count, S, |q| {
            K::base(super::walk::grid_coords::<D>(x[q], inv_h), D::DIM, lp)
        });
        for slot in 0..grid.index.block_count() {
            let (layout, index, nodes) = (&grid.layout, &grid.index, &mut grid.nodes);
            layout.for_each_owned(index, slot, |node, i| {
                let at = [0, 1, 2].map(|a| (node[a] - crate::grid::GHOST) as Real * h);
                nodes[i].vm = D::vector(v(at)).with_mass(1.0);
            });
        }
        grid.fill_nodes(|h, o| *h = *o);
        Cells {
            grid,
            x,
            volume,
            inv_h,
            lp,
        }
    }

    /// Sand under 10 kPa confinement (inside its cone: the steps below stay elastic).
    fn sand() -> crate::material::DruckerPrager {
        match Material::drucker_prager(3.5e5, 0.3, 2200.0, 32.0, 0.0, 0.0).model() {
            Model::DruckerPrager(m) => m,
            _ => unreachable!(),
        }
    }

    /// One stress update (Sec. 4.2's order) of the particles of `c`, each particle's
    /// volumetric rate or (`AVERAGE`) its cell's: their stresses, volumes and the nodes'
    /// internal forces.
    fn one_update<D: Dim, K: Kernel<S>, const S: usize, const AVERAGE: bool>(
        c: &Cells<D>,
    ) -> (Vec<D::Sym>, Vec<Real>, Vec<D::Vector>) {
        let mut grid = c.grid.clone();
        let n = c.x.len();
        let mut stress = vec![D::Sym::IDENTITY * -1e4; n];
        let mut volume = c.volume.clone();
        let mut plastic = vec![0.0; n];
        let mass: Vec<Real> = c.volume.iter().map(|v| v * 2200.0).collect();
        let mut viscous = vec![0.0; n];
        let state = StressState::<D> {
            stress: &mut stress,
            volume: &mut volume,
            mass: &mass,
            plastic_strain: &mut plastic,
            viscous_pressure: &mut viscous,
            bulk_length: 0.0,
            closing: false,
        };
        if AVERAGE {
            sum_cell_dilatation::<D, K, S>(&mut grid, &c.x, &c.volume, c.inv_h, c.lp);
        }
        let dt = 1e-3;
        let r = update_stress_first::<D, K, _, S, AVERAGE>(
            &mut grid,
            &c.x,
            state,
            &sand(),
            dt,
            c.inv_h,
            c.lp,
        );
        assert_eq!((r.bad, r.dissipated), (0, 0.0), "elastic and finite");
        let forces = grid.nodes.iter().map(|n| n.new_vel).collect();
        (stress, volume, forces)
    }

    fn close(a: Real, b: Real, scale: Real) -> bool {
        (a - b).abs() <= 1e-5 * scale
    }

    /// In an affine velocity field every particle of a cell has the same volumetric rate, so
    /// averaging it changes nothing: the same stresses, volumes and forces (to rounding).
    fn affine_field_is_unchanged<D: Dim, K: Kernel<S>, const S: usize>() {
        let c = cells::<D, K, S>(3, |x| {
            [
                0.3 + 1.2 * x[0] - 0.7 * x[1] + 0.2 * x[2],
                -0.1 + 0.9 * x[0] + 0.5 * x[1] - 0.3 * x[2],
                0.4 * x[0] - 0.2 * x[1] - 0.8 * x[2],
            ]
        });
        let (s0, v0, f0) = one_update::<D, K, S, false>(&c);
        let (s1, v1, f1) = one_update::<D, K, S, true>(&c);
        for q in 0..c.x.len() {
            for (a, b) in s0[q].components().iter().zip(s1[q].components()) {
                assert!(
                    close(*a, *b, 1e4),
                    "particle {q}: {:?} vs {:?}",
                    s0[q],
                    s1[q]
                );
            }
            assert!(close(v0[q], v1[q], v0[q]), "particle {q}");
        }
        let fmax = f0.iter().map(|f| f.length()).fold(0.0, max);
        assert!(fmax > 0.0);
        for (a, b) in f0.iter().zip(&f1) {
            assert!((*a - *b).length() <= 1e-5 * fmax, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn an_affine_velocity_field_gives_the_same_update_with_the_cell_average() {
        use crate::kernel::{Gimp, Linear, QuadraticBspline};
        affine_field_is_unchanged::<D2, Gimp, 3>();
        affine_field_is_unchanged::<D2, QuadraticBspline, 3>();
        affine_field_is_unchanged::<D2, Linear, 2>();
        affine_field_is_unchanged::<D3, Gimp, 3>();
    }

    /// A shearing field whose divergence varies within a cell (v = ((x − ¼)² + y, x y)): with the
    /// cell average every particle of a cell takes the same volume ratio and the same
    /// increment of tr σ (3K Δt ⟨tr ε̇⟩), which without it vary across the cell; the cell's
    /// total volume change Σ V_p tr ε̇_p is the same either way (the average is weighted by
    /// volume); each particle keeps its own deviatoric rate.
    fn varying_divergence_is_averaged<D: Dim, K: Kernel<S>, const S: usize>(ppc: usize) {
        let c = cells::<D, K, S>(ppc, |x| {
            let u = x[0] - 0.25;
            [u * u + x[1], x[0] * x[1], 0.3 * x[2]]
        });
        let (s0, v0, _) = one_update::<D, K, S, false>(&c);
        let (s1, v1, _) = one_update::<D, K, S, true>(&c);
        let mut by_cell: std::collections::BTreeMap<[i32; 3], Vec<usize>> = Default::default();
        for (q, x) in c.x.iter().enumerate() {
            let key = [0, 1, 2].map(|a| {
                if a < D::DIM {
                    (x[a] * c.inv_h).floor() as i32
                } else {
                    0
                }
            });
            by_cell.entry(key).or_default().push(q);
        }
        let ratio = |v: &[Real], q: usize| v[q] / c.volume[q];
        let trace_increment = |s: &[D::Sym], q: usize| s[q].trace() + 3e4;
        let change = (0..c.x.len())
            .map(|q| (ratio(&v0, q) - 1.0).abs())
            .fold(0.0, max);
        let dtr = (0..c.x.len())
            .map(|q| trace_increment(&s0, q).abs())
            .fold(0.0, max);
        // f32 resolves a volume ratio near 1 to 6e-8, and tr σ ≈ −3e4 Pa to 2e-3 Pa.
        let (tol_ratio, tol_trace) = (1e-2 * change + 3e-7, 1e-2 * dtr + 1e-2);
        let mut spread_plain: Real = 0.0;
        for qs in by_cell.values() {
            assert_eq!(qs.len(), ppc.pow(D::DIM as u32));
            let first = qs[0];
            for &q in qs {
                let (a, b) = (ratio(&v1, q), ratio(&v1, first));
                assert!(
                    (a - b).abs() <= tol_ratio,
                    "volume ratio, particle {q}: {a} vs {b}"
                );
                let (a, b) = (trace_increment(&s1, q), trace_increment(&s1, first));
                assert!(
                    (a - b).abs() <= tol_trace,
                    "tr σ increment, particle {q}: {a} vs {b}"
                );
                spread_plain = max(spread_plain, (ratio(&v0, q) - ratio(&v0, first)).abs());
            }
            let total = |v: &[Real]| qs.iter().map(|&q| v[q] - c.volume[q]).sum::<Real>();
            let (t0, t1) = (total(&v0), total(&v1));
            let scale = qs.iter().map(|&q| c.volume[q]).sum::<Real>() * change;
            assert!(
                (t0 - t1).abs() <= 1e-3 * scale,
                "cell volume change {t0} vs {t1}"
            );
        }
        assert!(
            spread_plain > 0.05 * change,
            "the field should vary the volumetric rate across a cell: {spread_plain} of {change}"
        );
    }

    #[test]
    fn a_divergence_varying_within_a_cell_is_averaged_over_it() {
        use crate::kernel::{Gimp, QuadraticBspline};
        for ppc in [2, 3] {
            varying_divergence_is_averaged::<D2, Gimp, 3>(ppc);
            varying_divergence_is_averaged::<D2, QuadraticBspline, 3>(ppc);
            varying_divergence_is_averaged::<D3, Gimp, 3>(ppc);
        }
    }

    /// The replaced gradient has the given trace and keeps the deviatoric part (in the plane
    /// in 2D) and the spin.
    fn volumetric_part_is_replaced<D: Dim>() {
        for (grad, _) in states::<D>(5) {
            let g = with_volumetric_rate::<D>(grad, 0.7);
            assert!((divergence::<D>(&g) - 0.7).abs() < 1e-5);
            let d = D::DIM as Real;
            let (r0, w0) = D::rate_and_spin(grad);
            let (r1, w1) = D::rate_and_spin(g);
            assert_eq!(format!("{w0:?}"), format!("{w1:?}"));
            for a in 0..D::DIM {
                for b in 0..D::DIM {
                    let iso = |r: Real| if a == b { r / d } else { 0.0 };
                    let dev = |g: &D::Grad| D::grad_entry(g, a, b) - iso(divergence::<D>(g));
                    assert!((dev(&grad) - dev(&g)).abs() < 1e-5, "({a}, {b})");
                }
            }
            if D::DIM == 2 {
                // plane strain: still no zz rate
                assert_eq!((r0.components()[2], r1.components()[2]), (0.0, 0.0));
            }
        }
    }

    #[test]
    fn the_volumetric_part_alone_is_replaced() {
        volumetric_part_is_replaced::<D2>();
        volumetric_part_is_replaced::<D3>();
    }

    #[test]
    fn stress_update_in_lanes_matches_the_plain_reference() {
        for material in [
            Material::elastic(1e6, 0.3, 1000.0),
            Material::von_mises(1e6, 0.3, 1000.0, 3e3),
            Material::drucker_prager(1e6, 0.3, 2000.0, 30.0, 5.0, 0.0),
            Material::mohr_coulomb(1e6, 0.3, 2000.0, 30.0, 5.0, 100.0),
        ] {
            struct Check;
            impl WithModel for Check {
                type Output = ();
                fn run<M: Constitutive>(self, m: &M) {
                    lanes_match_the_reference::<D2, _>(m);
                    lanes_match_the_reference::<D3, _>(m);
                }
            }
            material.model().with(Check);
        }
    }

    /// The bulk viscosity in closed form: a chunk of particles compressed at tr ε̇ = −r carries
    /// q = ρ (C h r)² with ρ = m/V after the update, its work q V r Δt is booked and its fastest
    /// compression reported; particles in expansion carry none, and sand's chunk (no length)
    /// is left untouched.
    #[test]
    fn the_viscous_pressure_is_rho_times_the_squared_compression_length() {
        let model = match Material::elastic(1e6, 0.3, 1000.0).model() {
            Model::Elastic(m) => m,
            _ => unreachable!(),
        };
        let (n, dt, length) = (13, 1e-4, 0.02);
        let mass = vec![0.5; n];
        for bulk_length in [length, 0.0] {
            let mut stress = vec![Sym2::ZERO; n];
            let mut volume = vec![5e-4; n];
            let mut plastic = vec![0.0; n];
            let mut viscous = vec![-1.0; n];
            let mut report = StressReport::default();
            // rate −r I for the even particles (compression), +r I for the odd ones
            let rate = |q: usize| {
                if q.is_multiple_of(2) {
                    -(q as Real + 1.0)
                } else {
                    3.0
                }
            };
            let mut rates = Rates::<D2>::zero();
            for first in (0..n).step_by(CHUNK) {
                let r = first..n.min(first + CHUNK);
                for q in r.clone() {
                    let g = Mat2::from_diagonal(Vec2::splat(rate(q) / 2.0));
                    rates.set(q - first, g);
                }
                let ps = StressState::<D2> {
                    stress: &mut stress[r.clone()],
                    volume: &mut volume[r.clone()],
                    mass: &mass[r.clone()],
                    plastic_strain: &mut plastic[r.clone()],
                    viscous_pressure: &mut viscous[r],
                    bulk_length,
                    closing: false,
                };
                update_chunk(&model, &mut rates, ps, first, dt, &mut report);
            }
            let mut work = 0.0;
            for q in 0..n {
                let r = (-rate(q)).max(0.0);
                let expected = if bulk_length > 0.0 {
                    mass[q] / volume[q] * (bulk_length * r).powi(2)
                } else {
                    -1.0 // untouched
                };
                assert!(
                    (viscous[q] - expected).abs() <= 1e-5 * expected.abs(),
                    "{q}"
                );
                work += (expected.max(0.0) * volume[q] * r * dt) as f64;
            }
            assert!((report.viscous - work).abs() <= 1e-5 * work, "{report:?}");
            let fastest = if bulk_length > 0.0 { 13.0 } else { 0.0 };
            assert_eq!(report.max_compression, fastest);
        }
    }
}
