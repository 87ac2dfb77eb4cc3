//! The time step of the paper's Sec. 4.2, one file per pass, in the order they run:
//!
//! | file | pass | Sec. 4.2 |
//! | --- | --- | --- |
//! | [`allocate`] | the sparse grid where the particles are | (the paper's grid is dense) |
//! | [`scatter`] | mass and momentum (and, stress updated last, forces) to the grid | 1 (4) |
//! | [`grid_update`] | grid velocities v_i^n, then with forces and gravity v*_i | 1, 4 |
//! | [`stress`] | velocity gradient, stress and volume, internal forces (bodies whose stress is updated first) | 2, 3, 4 |
//! | [`traction`] | a pressure on a body's surface particles, as external forces | (4) |
//! | [`volumetric`] | sand's optional cell-averaged volumetric rate, summed before the stress pass | (Coombs et al. 2018) |
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
//! granular figures past their validation bands (docs/validation.md, "The order of the stress
//! update"); its `"cell_average"` volumetric rate ([`volumetric`]) is taken in the stress-first pass
//! only.
//!
//! **Who owns what.** [`crate::Simulation`] owns the state (world settings, particles, bodies,
//! diagnostics) and lends it for each step as a [`Step`] ([`state`]); [`Step::run`] below
//! calls the passes in order, each a method of [`Step`] in its own file, and returns what the
//! simulation records ([`Finished`]). What the passes hand on to each other within the step
//! ([`BodyStep`] and the reports) is in [`report`]. Sleeping ([`sleep`]) is the step's own
//! state from one step to the next: the simulation keeps it and hands it to the step (the
//! sleeping particles' share of the grid to [`Step::run`], and after the step the waking and
//! falling asleep); a body records only how many of its particles sleep. No file of the step
//! imports `Simulation`.
//!
//! [`transfer`] holds how velocities travel between particles and grid (the PIC/FLIP blend α,
//! APIC), as each body's recipe chooses, used by the scatter and the gather.
//!
//! Each pass is a loop over one body's particles or grid nodes, generic over the dimension
//! `D` and the kernel `K` (with `S` nodes per axis). The passes walk no stencil themselves:
//! [`walk`] alone knows how a stencil lies on the grid (rows, reach, the folded third axis in
//! 2D, the packed 2D forms) and how the stress update's particles go into SIMD lanes. A pass
//! states its sums as terms handed to a walk — the scatter and the stress pass their per-node
//! terms once, in a closure the walk calls on each node with its [`walk::Weights`] (m_i +=
//! w_ip m_p in `scatter.rs`, f_i += F_p ∇w_ip with F_p = [`scatter::internal_force`]), the
//! gather its node fields once, in a closure the walk calls on each node, each field asking
//! for its sums against w_ip, ∇w_ip or w_ip d_i ([`walk::Field`]; the stress pass the gradient
//! of one) — and the stress pass its constitutive step once
//! (`stress::update_group`), run for one particle or eight in lanes
//! ([`walk::update_in_lanes`]).

pub mod allocate;
pub mod contact;
pub mod gather;
pub mod grid_update;
pub mod report;
pub mod scatter;
pub mod sleep;
pub mod state;
pub mod stress;
pub mod traction;
pub mod transfer;
pub mod volumetric;
pub mod walk;
pub mod walls;

use crate::math::{Dim, Real, VectorOps};
pub use crate::recipe::StressOrder;
use crate::sim::stats::PassTimings;
pub use report::{Bad, BodyStep, Finished};
use sleep::Sleeping;
pub(crate) use state::Step;

impl<D: Dim> Step<'_, D> {
    /// One time step of `dt` seconds: the eight steps of Sec. 4.2, with the sleeping
    /// material's share of the grid ([`sleep`]) added after the awake particles' scatter.
    pub(crate) fn run(&mut self, dt: f64, sleeping: &Sleeping<D>) -> Finished<D> {
        let h = dt as Real;
        let mut t = Clock::start(self.timings.is_some());
        let mut steps = vec![BodyStep::default(); self.bodies.len()];
        let mut contacts = Vec::new();
        t.time(Phase::Allocate, || self.allocate_grids(&mut contacts));
        t.time(Phase::Scatter, || {
            self.scatter_to_grid(); // 1 (stress last: and 4's forces)
            sleeping.add_to(self.bodies);
        });
        t.time(Phase::Grid, || self.grid_velocities()); // 1: v_i^n
        t.time(Phase::Stress, || self.update_stress_first(h, &mut steps)); // 2, 3, 4 (first)
        t.time(Phase::Grid, || {
            self.apply_tractions(h, &mut steps); // 4, the traction's external forces
            self.grid_forces(h) // 4
        });
        t.time(Phase::Contact, || {
            self.resolve_contacts(&contacts, &mut steps)
        }); // 5, bodies
        t.time(Phase::Walls, || self.apply_walls(&mut steps, sleeping, dt)); // 5, walls
        let gathered = t.time(Phase::Gather, || self.gather_and_update(h, &mut steps)); // 6–8
        t.add_to(self.timings);
        self.finish_step(dt, &steps, &gathered, sleeping)
    }
}

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
