//! The time step of the paper's Sec. 4.2, one file per pass, in the order they run:
//!
//! | file | pass | Sec. 4.2 |
//! | --- | --- | --- |
//! | [`allocate`] | the sparse grid where the particles are | (the paper's grid is dense) |
//! | [`scatter`] | mass and momentum (and, stress updated last, forces) to the grid | 1 (4) |
//! | [`grid_update`] | grid velocities v_i^n, then with forces and gravity v*_i | 1, 4 |
//! | [`stress`] | velocity gradient, stress and volume, internal forces (bodies whose stress is updated first) | 2, 3, 4 |
//! | [`contact`] | between bodies (Eq. 20–21) | 5 |
//! | [`walls`] | at the domain's walls, on the grid | 5 |
//! | [`gather`] | PIC/FLIP velocities (and, stress updated last, steps 2–3), particle-side walls, advection | 6, 7, 8 (2, 3) |
//!
//! **Where the stress update sits** ([`StressOrder`], per body, in its
//! [`crate::recipe::Recipe`]) is the one departure from
//! Sec. 4.2's order. Sand, and every body with the paper's linear kernel, follow the paper:
//! the stress is updated from the grid velocities of step 1, then its forces are scattered
//! (update stress first). Solids (elastic, von Mises) with the C¹ kernels (GIMP, the default,
//! and the quadratic B-spline) have their stress updated at the end of the step from the new
//! grid velocities, in the gather's walk, and its forces go to the grid with the next step's
//! mass and momentum (update stress last, as in Sulsky et al. 1994 and MLS-MPM): each step
//! then walks every particle's stencil twice instead of four times, and the elastic
//! validation cases come out closer to their closed forms. The linear kernel cannot take
//! that order: its weight gradient does not vanish with its weight, so a node that a particle
//! barely reaches gets a finite force on next to no mass, and the velocity gradient taken
//! from the new grid velocities blows up (for the C¹ kernels |∇w|²/w stays bounded). Sand
//! keeps the paper's order: stress last would make it 1.07–1.22× faster but takes some
//! granular figures past issue 16's bounds (docs/validation.md, "The order of the stress
//! update"); its `"cell_average"` volumetric rate is computed in the stress-first pass only.
//!
//! [`transfer`] holds how velocities travel between particles and grid (the PIC/FLIP blend α,
//! APIC), as each body's recipe chooses, used by the scatter and the gather.
//!
//! Each pass is a loop over one body's particles or grid nodes, generic over the dimension
//! `D` and the kernel `K` (with `S` nodes per axis). The stencil loops follow the tensor
//! product of the weights, w_ijk = w_i w_j w_k, so that each node costs a few multiply-adds;
//! 2D uses the same loops with the third axis's weight 1 (LLVM folds it away). They stop at
//! the last node with weight along each axis ([`Stencil::reach`]): a GIMP stencil has two
//! along an axis where the particle's domain does not cross a node, three elsewhere. The
//! passes take the stencils from [`Stencils`], which in native 2D builds evaluates GIMP's for
//! two particles at once.

pub mod allocate;
pub mod contact;
pub mod gather;
pub mod grid_update;
pub mod report;
pub mod scatter;
pub mod stress;
pub mod transfer;
pub mod walls;

use crate::error::{Error, Result};
use crate::grid::{BlockLayout, GHOST, Grid, stencil_span};
use crate::kernel::{Kernel, KernelKind, Stencil};
use crate::math::{Dim, Real, VectorOps};
pub use crate::recipe::StressOrder;
use crate::sim::{Diagnostics, PassTimings, Simulation};
pub use report::BodyStep;

impl<D: Dim> Simulation<D> {
    /// One time step, no longer than `limit` seconds: the eight steps of Sec. 4.2.
    pub fn step_at_most(&mut self, limit: f64) -> Result<&Diagnostics> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if limit.is_nan() || limit <= 0.0 {
            return Err(Error::invalid("step limit", limit, "must be > 0 (s)"));
        }
        let dt = self.stable_dt().min(limit);
        let h = dt as Real;
        let mut t = Clock::start(self.timings.is_some());
        let mut steps = vec![BodyStep::default(); self.bodies.len()];
        let mut contacts = Vec::new();
        t.time(Phase::Allocate, || self.allocate_grids(&mut contacts));
        t.time(Phase::Scatter, || self.scatter_to_grid()); // 1 (stress last: and 4's forces)
        t.time(Phase::Grid, || self.grid_velocities()); // 1: v_i^n
        t.time(Phase::Stress, || self.update_stress_first(h, &mut steps)); // 2, 3, 4 (first)
        t.time(Phase::Grid, || self.grid_forces(h)); // 4
        t.time(Phase::Contact, || {
            self.resolve_contacts(&contacts, &mut steps)
        }); // 5, bodies
        t.time(Phase::Walls, || self.apply_walls(&mut steps)); // 5, walls
        let gathered = t.time(Phase::Gather, || self.gather_and_update(h, &mut steps)); // 6–8
        t.add_to(&mut self.timings);
        self.time += dt;
        self.steps += 1;
        self.finish_step(dt, &steps, &gathered)?;
        Ok(&self.diagnostics)
    }
}

/// Runs `$body` with the type `$k` and const `$s` set to the kernel `$kind` and its support.
macro_rules! with_kernel {
    ($kind:expr, $k:ident, $s:ident => $body:expr) => {
        match $kind {
            $crate::kernel::KernelKind::Linear => {
                type $k = $crate::kernel::Linear;
                const $s: usize = 2;
                $body
            }
            $crate::kernel::KernelKind::QuadraticBspline => {
                type $k = $crate::kernel::QuadraticBspline;
                const $s: usize = 3;
                $body
            }
            $crate::kernel::KernelKind::Gimp => {
                type $k = $crate::kernel::Gimp;
                const $s: usize = 3;
                $body
            }
        }
    };
}
pub(crate) use with_kernel;

/// The phases of the step, as [`PassTimings`] counts them (a pass, or the grid's two).
#[derive(Clone, Copy)]
enum Phase {
    Allocate,
    Scatter,
    Stress,
    Grid,
    Contact,
    Walls,
    Gather,
}

/// Wall-clock time per phase, when asked for (native builds only: WebAssembly has no clock
/// here).
struct Clock {
    seconds: [f64; 7],
    #[cfg(not(target_arch = "wasm32"))]
    on: bool,
}

impl Clock {
    fn start(on: bool) -> Self {
        let _ = on;
        Clock {
            seconds: [0.0; 7],
            #[cfg(not(target_arch = "wasm32"))]
            on,
        }
    }

    /// Runs `f`, adding its duration to `phase`.
    #[inline(always)]
    fn time<T>(&mut self, phase: Phase, f: impl FnOnce() -> T) -> T {
        #[cfg(not(target_arch = "wasm32"))]
        if self.on {
            let start = std::time::Instant::now();
            let out = f();
            self.seconds[phase as usize] += start.elapsed().as_secs_f64();
            return out;
        }
        let _ = phase;
        f()
    }

    fn add_to(&self, timings: &mut Option<PassTimings>) {
        if let Some(tm) = timings {
            let s = self.seconds;
            tm.steps += 1;
            tm.allocate += s[Phase::Allocate as usize];
            tm.scatter += s[Phase::Scatter as usize];
            tm.stress += s[Phase::Stress as usize];
            tm.grid += s[Phase::Grid as usize];
            tm.contact += s[Phase::Contact as usize];
            tm.walls += s[Phase::Walls as usize];
            tm.gather += s[Phase::Gather as usize];
        }
    }
}

/// Grid coordinates of a position: x/h plus the ghost nodes before the domain.
#[inline(always)]
pub fn grid_coords<D: Dim>(x: D::Vector, inv_h: Real) -> [Real; 3] {
    let mut g = [0.0; 3];
    for (a, c) in g.iter_mut().enumerate().take(D::DIM) {
        *c = x[a] * inv_h + GHOST as Real;
    }
    g
}

/// The particles' stencils, one particle after another, for a pass that walks them in order.
/// In native 2D builds two particles' GIMP stencils are evaluated at once
/// ([`Kernel::stencil_pair_2d`], a packing specialisation of [`Kernel::stencil`]): the second
/// waits here for the pass to ask for it.
pub struct Stencils<D: Dim, K: Kernel<S>, const S: usize> {
    inv_h: Real,
    lp: Real,
    /// The particle whose stencil `next` is (`usize::MAX`: none).
    cached: usize,
    next: Stencil<S>,
    _kernel: std::marker::PhantomData<(D, K)>,
}

impl<D: Dim, K: Kernel<S>, const S: usize> Stencils<D, K, S> {
    /// For particles of half-width `lp` grid units on a grid of 1/`inv_h` cells.
    #[inline(always)]
    pub fn new(inv_h: Real, lp: Real) -> Self {
        Stencils {
            inv_h,
            lp,
            cached: usize::MAX,
            next: Stencil::at([0; 3]),
            _kernel: std::marker::PhantomData,
        }
    }

    /// The stencil of particle `q` at `x[q]` (in 2D, with particle q + 1's when q is not
    /// the second of a pair: a pass asks for q + 1 next, whose position it has not moved yet).
    #[inline(always)]
    pub fn at(&mut self, x: &[D::Vector], q: usize) -> Stencil<S> {
        let (inv_h, lp) = (self.inv_h, self.lp);
        // Pairs pay for GIMP's weights natively; the linear kernel's and the B-spline's cost
        // about what keeping the second stencil does, and in WebAssembly V8 ran the pairs
        // slower (docs/performance.md).
        if D::DIM != 2 || K::KIND != KernelKind::Gimp || cfg!(target_arch = "wasm32") {
            return K::stencil(grid_coords::<D>(x[q], inv_h), D::DIM, inv_h, lp);
        }
        if self.cached == q {
            return self.next;
        }
        let b = x[if q + 1 < x.len() { q + 1 } else { q }];
        let [first, second] = K::stencil_pair_2d(
            grid_coords::<D>(x[q], inv_h),
            grid_coords::<D>(b, inv_h),
            inv_h,
            lp,
        );
        (self.next, self.cached) = (second, q + 1);
        first
    }
}

/// Nodes per row of a padded block for a kernel of `S` nodes per axis, and the number of
/// consecutive nodes a stencil spans (compile-time constants after monomorphisation).
#[inline(always)]
fn layout<D: Dim, const S: usize>(grid: &Grid<D>) -> (usize, usize) {
    let p = Grid::<D>::BLOCK + S - 1;
    debug_assert_eq!(grid.layout.padded(), p, "grid laid out for another kernel");
    (p, stencil_span(D::DIM, p, S))
}

/// The storage index of a particle's first stencil node, found when the grid was allocated
/// (`node`); debug builds check it against the stencil's own first node.
#[inline(always)]
fn first_node<D: Dim, const S: usize>(
    layout: &BlockLayout<D>,
    node: u32,
    st: &Stencil<S>,
) -> usize {
    debug_assert_eq!(
        node as usize % layout.padded_nodes(),
        layout.stencil_origin(0, st.base),
        "particle's stencil moved since the grid was allocated"
    );
    node as usize
}

/// The stencil's weight and derivative along the third axis for node `k`: those of the
/// kernel in 3D, and (1, 0) in 2D, where the loops over `k` run once.
#[inline(always)]
fn third_axis<D: Dim, const S: usize>(st: &Stencil<S>, k: usize) -> (Real, Real) {
    if D::DIM == 3 {
        (st.w[k][2], st.dw[k][2])
    } else {
        (1.0, 0.0)
    }
}

/// The stencil nodes with weight along axis `a`: the first `reach[a]` of `S` for GIMP (the
/// rest carry none, and the walks skip them), all `S` for the other kernels (a constant, so
/// that their loops unroll) — and for GIMP in the 2D WebAssembly build, where V8 ran the
/// loops of varying length slower than the unrolled ones (docs/performance.md).
#[inline(always)]
fn nodes_along<D: Dim, K: Kernel<S>, const S: usize>(st: &Stencil<S>, a: usize) -> usize {
    let skip = D::DIM == 3 || !cfg!(target_arch = "wasm32");
    if K::KIND == KernelKind::Gimp && skip {
        st.reach[a]
    } else {
        S
    }
}

/// The stencil nodes with weight along the first axis.
#[inline(always)]
fn first_axis_nodes<D: Dim, K: Kernel<S>, const S: usize>(st: &Stencil<S>) -> usize {
    nodes_along::<D, K, S>(st, 0)
}

/// The stencil nodes with weight along the second axis.
#[inline(always)]
fn second_axis_nodes<D: Dim, K: Kernel<S>, const S: usize>(st: &Stencil<S>) -> usize {
    nodes_along::<D, K, S>(st, 1)
}

/// The stencil nodes with weight along the third axis in 3D; one in 2D.
#[inline(always)]
fn third_axis_nodes<D: Dim, K: Kernel<S>, const S: usize>(st: &Stencil<S>) -> usize {
    if D::DIM == 3 {
        nodes_along::<D, K, S>(st, 2)
    } else {
        1
    }
}

/// The energy a constraint removes from a mass `m` whose velocity it changes from `before` to
/// `after` within a step that started at velocity `start`: minus the work of the impulse
/// J = m (after − before) over the mean velocity (start + after)/2. It is ½ m v² for a mass
/// stopped by an impact, the friction force times the distance slid for a sliding one, and
/// zero for a mass held at rest (whose grid velocity only carries the step's Δt g).
#[inline(always)]
pub fn constraint_dissipation<V: VectorOps>(m: Real, start: V, before: V, after: V) -> f64 {
    0.5 * (m * (before - after).dot(start + after)) as f64
}

#[cfg(test)]
pub(crate) mod test_util {
    //! Grids and stencils in realistic states, for the tests that compare a pass's
    //! specialisation with its reference version.
    use crate::grid::Node;
    use crate::kernel::{Kernel, Stencil};
    use crate::math::{Dim, Real, VectorOps};

    /// A deterministic number in [-1, 1) from a counter (no random-number crate needed).
    pub fn noise(seed: &mut u64) -> Real {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((*seed >> 40) as f64 / (1u64 << 23) as f64 - 1.0) as Real
    }

    /// Stencil nodes with made-up momenta, masses and new velocities, and the stencils of
    /// particles at made-up positions, laid out with rows `p` long: for comparing two versions
    /// of a stencil loop.
    pub fn random_stencils<D: Dim, K: Kernel<S>, const S: usize>(
        count: usize,
        p: usize,
    ) -> (Vec<Node<D::Vector>>, Vec<Stencil<S>>) {
        let mut seed = 7;
        let span = crate::grid::stencil_span(D::DIM, p, S);
        let nodes = (0..span)
            .map(|_| {
                let v = D::vector([noise(&mut seed), noise(&mut seed), noise(&mut seed)]);
                let n = D::vector([noise(&mut seed), noise(&mut seed), noise(&mut seed)]);
                Node {
                    vm: v.with_mass(1.0 + noise(&mut seed).abs()),
                    new_vel: n,
                }
            })
            .collect();
        let stencils = (0..count)
            .map(|_| {
                let xg = [0; 3].map(|_| 5.0 + 2.0 * noise(&mut seed));
                K::stencil(xg, D::DIM, 40.0, 0.25)
            })
            .collect();
        (nodes, stencils)
    }
}
