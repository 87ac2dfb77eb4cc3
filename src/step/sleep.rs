//! Sleeping: material at rest stops being stepped until something touches it (off unless
//! [`crate::Simulation::set_sleeping`] switches it on).
//!
//! Rigid-body engines put resting islands to sleep; here the unit is a grid block. A block
//! falls asleep when every awake particle it handles (the particles whose stencil starts in
//! it) has stayed slower than [`SleepRule::speed`] for [`SleepRule::after`] seconds. Its
//! particles then keep their position, stress and volume, their velocity and APIC affine
//! velocity are set to zero (the kinetic energy of those last few mm/s is booked as
//! `dissipated_sleep`), and they leave the passes: a body's sleeping particles are the last
//! `Body::asleep` of its range, and every pass walks [`crate::sim::Body::active`] only.
//!
//! What they give the grid stays. Once, when they fall asleep, their share of the scatter is
//! taken with their frozen stress (the same pass, [`super::scatter::scatter`], with zero
//! velocity) and kept per owned node of each block it reaches: the mass m_i, the internal force
//! f_i = −Σ_p V_p σ_p ∇w_ip and, for contact, the mass gradient. Each step adds it to the
//! grid after the awake particles' scatter, so active material rests on sleeping material
//! and pushes against it as before, and gravity acts on its mass: a node of sleeping material
//! in equilibrium gets v*_i = Δt (f_i/m_i + g), the same small residual the awake heap had.
//!
//! Sleeping material wakes
//! - when the grid around it moves: after the walls (step 5), a sleeping particle wakes if a
//!   node its block owns, or owned by a block its stencil spills into, has |v*_i| above
//!   [`SleepRule::wake_speed`] (twice the sleep speed: the hysteresis that keeps a block
//!   from flickering between the states). An impact, a body dropped into it, contact with
//!   another body or a wall all move those nodes;
//! - all at once on anything that could move it without moving the grid first: a parameter
//!   change ([`crate::Simulation::configure`]: a lower friction angle or yield stress, gravity), an
//!   edit of the particle state ([`crate::Simulation::particles_mut`]), or sleeping switched off.
//!
//! Woken particles start from zero velocity with the stress they slept with. Sleeping
//! material does not creep: a slope that would creep slower than the sleep speed freezes
//! (docs/method.md, "Sleeping").

use super::scatter::{ScatterState, scatter};
use super::state::Step;
use crate::grid::{Grid, GridIndex};
use crate::kernel::{Kernel, with_kernel};
use crate::material::Material;
use crate::math::{Dim, Real, VectorOps};
use crate::sim::body::Body;
use crate::sim::particles::Particles;
use crate::sim::stats::Measure;
use std::collections::HashMap;

/// When material sleeps and wakes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SleepRule {
    /// A block sleeps once its particles have all been slower than this (m/s) ...
    pub speed: Real,
    /// ... for this long (s).
    pub after: f64,
    /// A sleeping particle wakes when a node of its blocks moves faster than this (m/s).
    pub wake_speed: Real,
}

impl SleepRule {
    /// The rule for a grid of cell size `h` under gravity `g`: sleep below 1 % of √(g h), the
    /// speed a particle gains falling one cell (3 mm/s at h = 1 cm), held for 0.25 s; wake
    /// above twice that.
    pub fn for_grid(h: f64, g: f64) -> Self {
        let speed = (0.01 * (g.abs().max(1e-3) * h).sqrt()) as Real;
        SleepRule {
            speed,
            after: 0.25,
            wake_speed: 2.0 * speed,
        }
    }
}

/// A block's owned nodes as the sleeping particles fill them.
#[derive(Clone, Debug)]
struct Frozen<D: Dim> {
    mass: Vec<Real>,
    force: Vec<D::Vector>,
    mass_grad: Vec<D::Vector>,
}

/// Sleeping's state, the step's own, kept from one step to the next: the rule (none: off)
/// and, body by body, what its sleeping particles give the grid ([`Sleep`]; how many sleep
/// is the body's [`Body::asleep`](crate::sim::Body), the last of its range).
#[derive(Clone, Debug)]
pub struct Sleeping<D: Dim> {
    rule: Option<SleepRule>,
    bodies: Vec<Sleep<D>>,
}

impl<D: Dim> Default for Sleeping<D> {
    fn default() -> Self {
        Sleeping {
            rule: None,
            bodies: Vec::new(),
        }
    }
}

impl<D: Dim> Sleeping<D> {
    /// The rule material sleeps by, if sleeping is on.
    pub fn rule(&self) -> Option<SleepRule> {
        self.rule
    }

    /// Switches sleeping on with `rule`, or off with `None` (everything wakes).
    pub fn set(&mut self, rule: Option<SleepRule>, bodies: &mut [Body<D>]) {
        self.rule = rule;
        if rule.is_none() {
            self.wake_all(bodies);
        }
    }

    /// Wakes every sleeping particle of `bodies`: the particles are already in place (the
    /// sleeping ones at rest, with their stress), so only the bookkeeping goes.
    pub fn wake_all(&mut self, bodies: &mut [Body<D>]) {
        for body in bodies {
            body.asleep = 0;
        }
        self.bodies.clear();
    }

    /// Wakes every sleeping particle of `body`, body `i`.
    pub fn wake_body(&mut self, i: usize, body: &mut Body<D>) {
        body.asleep = 0;
        if let Some(sleep) = self.bodies.get_mut(i) {
            *sleep = Sleep::default();
        }
    }

    /// Forgets body `i`, which is removed.
    pub fn remove(&mut self, i: usize) {
        if i < self.bodies.len() {
            self.bodies.remove(i);
        }
    }

    /// Body `i`'s sleeping particles' share and figures (of a body with sleeping particles).
    pub(super) fn body(&self, i: usize) -> &Sleep<D> {
        &self.bodies[i]
    }

    /// Body `i`'s sleeping particles' mass on each owned node of the grid block at `block`
    /// (in [`crate::grid::BlockLayout::for_each_owned`]'s order), if any sleep there.
    pub(super) fn frozen_mass(&self, i: usize, block: &[i32; 3]) -> Option<&[Real]> {
        let f = self.bodies.get(i)?.frozen.get(block)?;
        Some(&f.mass)
    }

    /// Adds each body's sleeping particles' share to its grid's owned nodes (after the awake
    /// particles' scatter and its halo reduction).
    pub(super) fn add_to(&self, bodies: &mut [Body<D>]) {
        for (sleep, body) in self.bodies.iter().zip(bodies) {
            sleep.add_to(&mut body.grid);
        }
    }
}

/// One body's sleeping particles: what they give the grid, and their figures.
#[derive(Clone, Debug)]
pub struct Sleep<D: Dim> {
    /// Seconds each block (by block coordinate) has held only slow awake particles.
    calm: HashMap<[i32; 3], f64>,
    /// The sleeping particles' share of the grid, per block coordinate.
    frozen: HashMap<[i32; 3], Frozen<D>>,
    /// The sleeping particles' figures: their measure (finished), elastic energy and largest
    /// volume.
    pub(crate) measure: Measure<D>,
    pub(crate) elastic: f64,
    pub(crate) max_volume: Real,
}

impl<D: Dim> Default for Sleep<D> {
    fn default() -> Self {
        Sleep {
            calm: HashMap::new(),
            frozen: HashMap::new(),
            measure: Measure::empty(),
            elastic: 0.0,
            max_volume: 0.0,
        }
    }
}

impl<D: Dim> Sleep<D> {
    /// Adds the sleeping particles' share to `grid`'s owned nodes.
    fn add_to(&self, grid: &mut Grid<D>) {
        if self.frozen.is_empty() {
            return;
        }
        let with_gradient = !grid.mass_grad.is_empty();
        let Grid {
            index,
            layout,
            nodes,
            mass_grad,
            ..
        } = grid;
        for slot in 0..index.block_count() {
            let Some(f) = self.frozen.get(&index.blocks()[slot]) else {
                continue;
            };
            let mut k = 0;
            layout.for_each_owned(index, slot, |_, i| {
                let n = &mut nodes[i];
                n.vm = n.vel().with_mass(n.mass() + f.mass[k]);
                n.new_vel += f.force[k];
                if with_gradient {
                    mass_grad[i] += f.mass_grad[k];
                }
                k += 1;
            });
        }
    }
}

impl<D: Dim> Step<'_, D> {
    /// After the step's gather: wakes the sleeping particles whose grid moved, and puts to
    /// sleep the blocks that have been at rest long enough.
    pub(crate) fn sleep_and_wake(&mut self, sleeping: &mut Sleeping<D>, dt: f64) {
        let Some(rule) = sleeping.rule else {
            return;
        };
        sleeping
            .bodies
            .resize_with(self.bodies.len(), Default::default);
        let (kernel, inv_h) = (self.world.kernel, self.world.inv_h);
        for (body, sleep) in self.bodies.iter_mut().zip(&mut sleeping.bodies) {
            // A body under a traction stays awake: the traction pushes on awake particles
            // only, and a sleeping surface would drop its confinement.
            if body.kinematic || body.traction != 0.0 {
                continue;
            }
            let grid = &body.grid;
            let padded = grid.layout.padded_nodes();
            let slots = grid.index.block_count();
            let r = body.range.clone();
            let awake = r.len() - body.asleep;
            // Waking: the blocks whose owned nodes move, and the blocks below them whose
            // stencils spill into them.
            let mut woken = Vec::new();
            let mut spilled = vec![false; slots];
            if body.asleep > 0 {
                let fast = moving_blocks(grid, rule.wake_speed);
                if fast.iter().any(|&f| f) {
                    spilled = spill_down(&grid.index, &fast);
                    woken = (awake..r.len())
                        .filter(|&q| spilled[grid.particle_node[q] as usize / padded])
                        .collect();
                }
            }
            // Falling asleep: blocks whose awake particles have all stayed slow.
            let v = &self.particles.v[r.clone()];
            let mut fastest = vec![0.0 as Real; slots];
            let mut handles = vec![false; slots];
            for q in 0..awake {
                let s = grid.particle_node[q] as usize / padded;
                fastest[s] = fastest[s].max(v[q].length_squared());
                handles[s] = true;
            }
            let mut calm = HashMap::with_capacity(sleep.calm.len());
            let mut ready = vec![false; slots];
            let limit = rule.speed * rule.speed;
            for s in 0..slots {
                // a block whose neighbourhood wakes does not fall asleep
                if !handles[s] || fastest[s] >= limit || spilled[s] {
                    continue;
                }
                let block = grid.index.blocks()[s];
                let t = sleep.calm.get(&block).copied().unwrap_or(0.0) + dt;
                if t >= rule.after {
                    ready[s] = true;
                } else {
                    calm.insert(block, t);
                }
            }
            sleep.calm = calm;
            let sleepers: Vec<usize> = (0..awake)
                .filter(|&q| ready[grid.particle_node[q] as usize / padded])
                .collect();
            if woken.is_empty() && sleepers.is_empty() {
                continue;
            }
            // New order of the body's particles: awake, newly asleep, still asleep; the woken
            // ones join the awake, each group in its former order.
            let mut is_sleeper = vec![false; r.len()];
            for &q in &sleepers {
                is_sleeper[q] = true;
            }
            let mut is_woken = vec![false; r.len()];
            for &q in &woken {
                is_woken[q] = true;
            }
            let order: Vec<u32> = (0..awake)
                .filter(|&q| !is_sleeper[q])
                .chain(woken.iter().copied())
                .chain(sleepers.iter().copied())
                .chain((awake..r.len()).filter(|&q| !is_woken[q]))
                .map(|q| q as u32)
                .collect();
            let p = &mut *self.particles;
            // the kinetic energy of the particles brought to rest
            let mut stopped = 0.0;
            for &q in &sleepers {
                let i = r.start + q;
                stopped += 0.5 * (p.mass[i] * p.v[i].length_squared()) as f64;
                p.v[i] = D::Vector::ZERO;
                if !p.affine.is_empty() {
                    p.affine[i] = D::GRAD_ZERO;
                }
            }
            self.diagnostics.dissipated_sleep += stopped;
            self.diagnostics.kinetic -= stopped;
            body.stats.kinetic -= stopped;
            p.permute(r.clone(), &order);
            body.asleep = body.asleep + sleepers.len() - woken.len();
            let lp = body.radius * inv_h;
            let law = *body.model.elastic();
            let from = r.end - body.asleep;
            with_kernel!(kernel, K, S => freeze::<D, K, S>(sleep, p, from..r.end, inv_h, lp, &law, self.world.gravity));
            // The grid's particle_node no longer matches the order: the next step's
            // allocation rebuilds it before any pass reads it.
        }
    }
}

/// Whether a body at rest whose material changes from `old` to `new` can move, and so must
/// wake: a new model, density, dilatancy or any other setting than these, or a lower friction
/// angle, cohesion or yield stress. A stiffer or softer elastic response (Young's modulus,
/// Poisson's ratio) moves nothing at rest, since the stress is the particles' state and stays
/// in equilibrium; a higher friction angle, cohesion or yield stress widens the yield surface
/// the resting stress lies within.
pub fn may_move(old: &Material, new: &Material) -> bool {
    // `new` with `old`'s elastic moduli and strengths: any other difference wakes
    macro_rules! weaker {
        ($a:expr, $b:expr, $($strength:ident),*) => {{
            let mut same = $b.clone();
            same.youngs_modulus = $a.youngs_modulus;
            same.poisson_ratio = $a.poisson_ratio;
            $(same.$strength = $a.$strength;)*
            same != *$a $(|| $b.$strength < $a.$strength)*
        }};
    }
    match (old, new) {
        (Material::Elastic(a), Material::Elastic(b)) => weaker!(a, b,),
        (Material::VonMises(a), Material::VonMises(b)) => weaker!(a, b, yield_stress),
        (Material::DruckerPrager(a), Material::DruckerPrager(b)) => {
            weaker!(a, b, friction_angle, cohesion)
        }
        (Material::MohrCoulomb(a), Material::MohrCoulomb(b)) => {
            weaker!(a, b, friction_angle, cohesion)
        }
        _ => true,
    }
}

/// Per slot: whether a node the block owns, carrying at least [`FULL_NODE_SHARE`] of the
/// heaviest node's mass, moves faster than `speed`. The lighter nodes at the material's edge
/// (the kernel's tail) carry large accelerations f_i/m_i at rest and move no particle by much.
fn moving_blocks<D: Dim>(grid: &Grid<D>, speed: Real) -> Vec<bool> {
    let limit = speed * speed;
    let heaviest = grid.nodes.iter().map(|n| n.mass()).fold(0.0, Real::max);
    let light = FULL_NODE_SHARE * heaviest;
    (0..grid.index.block_count())
        .map(|slot| {
            let mut fast = false;
            grid.layout.for_each_owned(&grid.index, slot, |_, i| {
                let n = &grid.nodes[i];
                fast |= n.mass() >= light && n.new_vel.length_squared() > limit
            });
            fast
        })
        .collect()
}

/// The least share of the heaviest node's mass a node must carry for its motion to wake
/// sleeping material.
const FULL_NODE_SHARE: Real = 0.05;

/// Per slot: whether the block or a block its halo spills into (its upper neighbours) is
/// flagged in `fast`.
fn spill_down<D: Dim>(index: &GridIndex<D>, fast: &[bool]) -> Vec<bool> {
    let blocks = index.blocks();
    (0..blocks.len())
        .map(|s| {
            (0..1u32 << D::DIM).any(|corner| {
                let mut b = blocks[s];
                for (a, c) in b.iter_mut().enumerate().take(D::DIM) {
                    *c += (corner >> a & 1) as i32;
                }
                index.slot_of_block(b).is_some_and(|t| fast[t])
            })
        })
        .collect()
}

/// Takes the share of the sleeping particles `range` (all of the body's, at rest) to the
/// grid, and their figures, into `sleep`.
fn freeze<D: Dim, K: Kernel<S>, const S: usize>(
    sleep: &mut Sleep<D>,
    p: &Particles<D>,
    range: std::ops::Range<usize>,
    inv_h: Real,
    lp: Real,
    law: &crate::material::Elastic,
    gravity: D::Vector,
) {
    sleep.frozen.clear();
    sleep.measure = Measure::empty();
    sleep.elastic = 0.0;
    sleep.max_volume = 0.0;
    if range.is_empty() {
        sleep.measure.finish(gravity);
        return;
    }
    let x = &p.x[range.clone()];
    let mut grid = Grid::<D>::default();
    grid.rebuild(x.len(), S, |q| {
        K::base(super::walk::grid_coords::<D>(x[q], inv_h), D::DIM, lp)
    });
    grid.enable_mass_gradient();
    let state = ScatterState {
        x,
        v: &p.v[range.clone()],
        mass: &p.mass[range.clone()],
        stress: Some((
            &p.stress[range.clone()],
            &p.volume[range.clone()],
            &p.viscous_pressure[range.clone()],
        )),
        affine: None,
    };
    scatter::<D, K, S>(&mut grid, state, inv_h, lp);
    let b = GridIndex::<D>::BLOCK.pow(D::DIM as u32);
    for slot in 0..grid.index.block_count() {
        let mut f = Frozen::<D> {
            mass: Vec::with_capacity(b),
            force: Vec::with_capacity(b),
            mass_grad: Vec::with_capacity(b),
        };
        grid.layout.for_each_owned(&grid.index, slot, |_, i| {
            f.mass.push(grid.nodes[i].mass());
            f.force.push(grid.nodes[i].new_vel);
            f.mass_grad.push(grid.mass_grad[i]);
        });
        if f.mass.iter().any(|&m| m > 0.0) {
            sleep.frozen.insert(grid.index.blocks()[slot], f);
        }
    }
    for i in range.clone() {
        sleep.measure.record(p.mass[i], p.x[i], p.v[i]);
        sleep.elastic += (law.energy_density(p.stress[i]) * p.volume[i]) as f64;
        sleep.max_volume = sleep.max_volume.max(p.volume[i]);
    }
    sleep.measure = sleep.measure.with_plastic_strain(&p.plastic_strain[range]);
    sleep.measure.finish(gravity);
}
