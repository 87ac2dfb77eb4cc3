//! Pouring: a body fed by a spout (`bodies[].pour`), as the angle of repose is measured by
//! pouring sand from a funnel held above the floor (ISO 4324, ASTM C1444).
//!
//! **The stream.** The spout's exit is a section about the vertical axis through `spout`: a
//! disc of radius r in 3D, a segment of half-width r in 2D. Its particles are the points of
//! the body's sampling lattice (spacing s = h / `particles_per_cell`, aligned with the grid as
//! a sampled shape's lattice is) whose horizontal coordinates lie inside the section, n of
//! them: one layer. Each particle has the volume s^dim and the mass ρ s^dim of the body's
//! material, and zero stress, as a sampled body's particles have; with the body's `jitter`
//! each is moved by up to that share of s along each axis, a hash of `seed`, the layer and its
//! place in the layer ([`Lattice`]).
//!
//! **The rate.** The layer carries the exit area A = n s^(dim−1) (π r² or 2r to within the
//! lattice: the area its particles stand for), so the rate Q leaves it at the exit speed
//! v0 = Q / A, downwards, and a layer leaves every s / v0 seconds: layer k at
//! t_k = t_0 + k s / v0, for every k with t_k < t_0 + T (t_0 the body's entry, its
//! `appear_at`; T the `duration`). By t_0 + τ the spout has poured ⌊τ v0 / s⌋ + 1 layers of
//! volume A s each: Q τ to within one layer, whatever the time steps.
//!
//! **Entering.** Before a step, each layer due (t_k at or before the simulation's time t) is
//! added where it would be had it fallen freely since t_k: with τ = t − t_k,
//! x = x_exit − v0 τ e_y + ½ g τ² and v = −v0 e_y + g τ (g the world's gravity, along −y in
//! every shipped scene). The new particles join their body's range just before its sleeping
//! particles ([`crate::step::sleep`] keeps those last) and are stepped from the next step on;
//! their speed is in the diagnostics before that step's time step is chosen. Their kinetic and
//! gravitational energy, Σ ½ m |v|² − m g·x, is energy brought in
//! ([`crate::Diagnostics::energy_in`]), booked once, as each layer enters.
//!
//! **Stopping.** A spout may be stopped early at a time t ([`Spout::stop_at`],
//! [`crate::Simulation::stop_pour`]): no layer leaves after t, and its duration becomes what
//! pours the layers left by t, so that a scene file with that duration pours the same layers.

use crate::config::PourConfig;
use crate::geometry::Lattice;

impl PourConfig {
    /// The horizontal lattice indices `[i, k]` (along x and z; k = 0 in 2D) of the exit
    /// section's particles on a lattice of `spacing`: those whose lattice point lies inside
    /// the section.
    pub fn section(&self, dim: usize, spacing: f64) -> Vec<[i64; 2]> {
        let (r, s) = (self.radius, spacing);
        let centre = |a: usize| {
            if a < self.spout.len() {
                self.spout[a]
            } else {
                0.0
            }
        };
        let span = |a: usize| {
            let lo = ((centre(a) - r) / s).floor() as i64 - 1;
            let hi = ((centre(a) + r) / s).ceil() as i64 + 1;
            lo..=hi
        };
        let offset = |i: i64, a: usize| (i as f64 + 0.5) * s - centre(a);
        let mut out = Vec::new();
        let zs = if dim == 3 { span(2) } else { 0..=0 };
        for k in zs {
            for i in span(0) {
                let inside = if dim == 3 {
                    offset(i, 0).hypot(offset(k, 2)) < r
                } else {
                    offset(i, 0).abs() < r
                };
                if inside {
                    out.push([i, k]);
                }
            }
        }
        out
    }

    /// The exit area A = n s^(dim−1) the section's n particles stand for (m², m in 2D), on a
    /// lattice of `spacing` s.
    pub fn exit_area(&self, dim: usize, spacing: f64) -> f64 {
        self.section(dim, spacing).len() as f64 * spacing.powi(dim as i32 - 1)
    }

    /// The exit speed v0 = Q / A (m/s), on a lattice of `spacing`.
    pub fn exit_speed(&self, dim: usize, spacing: f64) -> f64 {
        self.rate / self.exit_area(dim, spacing)
    }
}

/// A body's spout as it runs: its section, its exit speed and the next layer to leave.
#[derive(Clone, Debug)]
pub struct Spout {
    dim: usize,
    /// The section's horizontal lattice indices ([`PourConfig::section`]).
    section: Vec<[i64; 2]>,
    /// The body's sampling lattice (its jitter and seed), spacing s.
    lattice: Lattice,
    spacing: f64,
    /// The height of the exit (m).
    exit_height: f64,
    exit_speed: f64,
    /// When the spout opens (s): the body's entry.
    start: f64,
    /// How many layers leave in all, and the next to leave.
    layers: u64,
    next: u64,
}

impl Spout {
    /// The spout of `pour` for a body of `particles_per_cell`, `jitter` and `seed` on a grid of
    /// `cell_size` in dimension `dim`, opening at time `start` (s). The pour must be valid
    /// ([`crate::SceneConfig::check_pour`]).
    pub fn new(
        pour: &PourConfig,
        dim: usize,
        cell_size: f64,
        particles_per_cell: u32,
        jitter: f64,
        seed: u64,
        start: f64,
    ) -> Self {
        let spacing = cell_size / particles_per_cell.max(1) as f64;
        let section = pour.section(dim, spacing);
        let exit_speed = pour.rate / (section.len() as f64 * spacing.powi(dim as i32 - 1));
        let layers = layers_in(pour.duration, exit_speed, spacing);
        Spout {
            dim,
            section,
            lattice: Lattice::new(dim, spacing, jitter, seed),
            spacing,
            exit_height: pour.spout[1],
            exit_speed,
            start,
            layers,
            next: 0,
        }
    }

    /// Particles in one layer.
    pub fn per_layer(&self) -> usize {
        self.section.len()
    }
    /// The exit speed v0 (m/s).
    pub fn exit_speed(&self) -> f64 {
        self.exit_speed
    }
    /// The particles' spacing s (m), and each one's volume s^dim.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }
    /// Layers the spout pours in all.
    pub fn layers(&self) -> u64 {
        self.layers
    }
    /// Particles the spout pours in all.
    pub fn particles(&self) -> u64 {
        self.layers.saturating_mul(self.per_layer() as u64)
    }
    /// Particles leaving per second, n v0 / s.
    pub fn particles_per_second(&self) -> f64 {
        self.per_layer() as f64 * self.exit_speed / self.spacing
    }
    /// Layers poured so far.
    pub fn poured(&self) -> u64 {
        self.next
    }
    /// When layer `k` leaves the exit (s): t_k = t_0 + k s / v0.
    pub fn exit_time(&self, k: u64) -> f64 {
        self.start + k as f64 * self.spacing / self.exit_speed
    }
    /// When the next layer leaves, if one is left.
    pub fn next_layer(&self) -> Option<f64> {
        (self.next < self.layers).then(|| self.exit_time(self.next))
    }

    /// When the spout opens (s).
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The duration (s) a spout of this exit speed and spacing runs to pour the layers that
    /// have left by time `t` (s): those whose exit time has come, at least those poured and
    /// the first, at most all. With `t` before the end, `t` − start when that pours exactly
    /// those layers (a whole number of 0.1 ms, or 1 µs, nearest it when one does, for a short
    /// record), else the middle of the span of durations that do; from the end on, `duration`,
    /// the spout's own. Returns the layers and the duration.
    pub fn held(&self, t: f64, duration: f64) -> (u64, f64) {
        let left = (0..self.layers)
            .take_while(|&k| super::reached(t, self.exit_time(k)))
            .count() as u64;
        let kept = left.max(self.next).clamp(1, self.layers);
        if kept == self.layers && super::reached(t, self.start + duration) {
            return (kept, duration);
        }
        let pours = |d: f64| d > 0.0 && layers_in(d, self.exit_speed, self.spacing) == kept;
        let held = t - self.start;
        for per in [1e4, 1e6] {
            let d = (held * per).round() / per;
            if pours(d) {
                return (kept, d);
            }
        }
        if pours(held) {
            return (kept, held);
        }
        (kept, (kept as f64 - 0.5) * self.spacing / self.exit_speed)
    }

    /// Stops the spout at time `t` (s): no layer leaves after it (see [`Self::held`]); returns
    /// the duration that pours the layers kept.
    pub fn stop_at(&mut self, t: f64, duration: f64) -> f64 {
        let (kept, d) = self.held(t, duration);
        self.layers = kept;
        d
    }

    /// Appends the next layer's particles to `x` and `v` (3 components, unused ones zero) as
    /// they stand at time `t` (s), not before its exit time, after falling freely under
    /// `gravity` since then; and counts it poured.
    pub fn pour_layer(
        &mut self,
        t: f64,
        gravity: [f64; 3],
        x: &mut Vec<[f64; 3]>,
        v: &mut Vec<[f64; 3]>,
    ) {
        let k = self.next;
        let tau = (t - self.exit_time(k)).max(0.0);
        let s = self.spacing;
        let exit_velocity = [0.0, -self.exit_speed, 0.0];
        for &[i, j] in &self.section {
            // the lattice point and its jitter: the layer is row k of the body's lattice
            let p = self.lattice.point([i, k as i64, j]);
            let exit = [p[0], self.exit_height + p[1] - (k as f64 + 0.5) * s, p[2]];
            x.push(std::array::from_fn(|a| {
                if a < self.dim {
                    exit[a] + exit_velocity[a] * tau + 0.5 * gravity[a] * tau * tau
                } else {
                    0.0
                }
            }));
            v.push(std::array::from_fn(|a| {
                if a < self.dim {
                    exit_velocity[a] + gravity[a] * tau
                } else {
                    0.0
                }
            }));
        }
        self.next += 1;
    }
}

/// The layers a spout of exit speed `exit_speed` (m/s) and lattice `spacing` (m) pours in
/// `duration` (s): every k with k s / v0 < T, at least one.
pub fn layers_in(duration: f64, exit_speed: f64, spacing: f64) -> u64 {
    (duration * exit_speed / spacing).ceil().max(1.0) as u64
}
