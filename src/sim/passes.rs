//! The passes of one time step (the paper's Sec. 4.2), each a loop over one body's particles
//! or grid nodes, generic over the dimension `D`, the kernel `K` (with `S` nodes per axis)
//! and, for the stress update, the constitutive model `M`.

use crate::boundary::Walls;
use crate::grid::{GHOST, Grid};
use crate::kernel::Kernel;
use crate::material::Constitutive;
use crate::math::{
    Batch, Dim, LANES, Lane, Lanes, Real, SymTensor, VectorOps, exp_small, max, stencil_span,
};

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
    layout: &crate::grid::BlockLayout<D>,
    node: u32,
    st: &crate::math::Stencil<S>,
) -> usize {
    debug_assert_eq!(
        node as usize % layout.padded_nodes(),
        layout.stencil_origin(0, st.base),
        "particle's stencil moved since the grid was allocated"
    );
    node as usize
}

/// Grid coordinates of a position.
#[inline(always)]
pub fn grid_coords<D: Dim>(x: D::Vector, inv_h: Real) -> [Real; 3] {
    let mut g = [0.0; 3];
    for (a, c) in g.iter_mut().enumerate().take(D::DIM) {
        *c = x[a] * inv_h + GHOST as Real;
    }
    g
}

/// Step 1: rasterise mass and momentum, m_i = Σ_p m_p w_ip and (mv)_i = Σ_p m_p v_p w_ip
/// (with APIC, m_p (v_p + C_p (x_i − x_p)) w_ip); for bodies that may touch another body also
/// the mass gradient ∇m_i = Σ_p m_p ∇w_ip.
pub fn scatter<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &mut Grid<D>,
    x: &[D::Vector],
    v: &[D::Vector],
    mass: &[Real],
    affine: Option<&[D::Grad]>,
    inv_h: Real,
    lp: Real,
) {
    let (p, span) = layout::<D, S>(grid);
    let Grid {
        layout,
        nodes,
        mass_grad,
        particle_node,
        ..
    } = &mut *grid;
    let with_gradient = !mass_grad.is_empty();
    let h = 1.0 / inv_h;
    for q in 0..x.len() {
        let st = K::stencil(grid_coords::<D>(x[q], inv_h), D::DIM, inv_h, lp);
        let origin = first_node(layout, particle_node[q], &st);
        let grad = if with_gradient {
            Some(&mut mass_grad[origin..origin + span])
        } else {
            None
        };
        D::scatter_mass(
            &mut nodes[origin..origin + span],
            grad,
            p,
            &st,
            mass[q],
            v[q] * mass[q],
            affine.map(|c| c[q] * (mass[q] * h)),
        );
    }
    grid.reduce_nodes(|o, h| o.vm += h.vm);
    if with_gradient {
        grid.reduce_mass_gradient();
    }
}

/// Grid velocities v_i = (mv)_i / m_i, on every node, halos included (they are then
/// overwritten from their owners).
pub fn grid_velocities<D: Dim>(grid: &mut Grid<D>) {
    for node in &mut grid.nodes {
        let m = node.mass();
        if m > 0.0 {
            node.vm = (node.vel() / m).with_mass(m);
        }
    }
    grid.fill_nodes(|h, o| h.vm = o.vm);
}

/// Particles per chunk of the stress pass (a multiple of `LANES`).
const CHUNK: usize = 2 * LANES;

/// The mutable particle state the stress pass touches.
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

/// What one constitutive call (for `LANES` particles in SIMD lanes) adds to the report.
struct Group {
    /// Σ V W(σ) after the update, and Σ V D (energy the plastic correction removed).
    elastic: f64,
    dissipated: f64,
    max_volume: Real,
    finite: bool,
}

/// The stress update of one group of particles by the model (returning their plastic strain
/// increments), and V̇ = V tr(ε̇) integrated exactly for the step's rate: first-order the same
/// as V (1 + Δt tr ε̇), but never zero or negative however violent the compression.
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

/// Steps 2–4, particle side: the velocity gradient ∇v_p = Σ_i v_i ⊗ ∇w_ip, the stress update
/// by the body's model, the volume update V_p ← V_p exp(Δt tr ε̇), and the internal forces
/// f_i = −Σ_p V_p σ_p ∇w_ip (accumulated in the nodes' `new_vel`).
///
/// Never inlined: each (dimension, kernel, model) instance stays a function of its own. Inlined
/// into the caller's dispatch, the 2D instances became one 50 KB WebAssembly function that V8
/// ran 25-28 % slower (notched 2D sand block, one Node process, builds interleaved).
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
    // In chunks: the velocity gradients of a few particles, then their constitutive updates,
    // LANES particles per model call in SIMD lanes, then their forces. (The update is a long
    // dependency chain; in lanes four chains go at once.) A short last chunk is padded with
    // zero stress and rate and a real particle's volume, whose update adds nothing.
    let mut st = [crate::math::Stencil::<S>::at([0; 3]); CHUNK];
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
        for i in 0..len {
            let q = first + i;
            st[i] = K::stencil(grid_coords::<D>(ps.x[q], inv_h), D::DIM, inv_h, lp);
            origin[i] = first_node(layout, particle_node[q], &st[i]);
            let cell = &nodes[origin[i]..origin[i] + span];
            (rate[i], spin[i]) = D::rate_and_spin(D::velocity_gradient(cell, p, &st[i]));
            stress[i] = ps.stress[q];
            volume[i] = ps.volume[q];
        }
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
                report.bad += 1;
                report.first_bad.get_or_insert((
                    q,
                    if sigma.is_finite() {
                        "volume"
                    } else {
                        "stress"
                    },
                ));
                continue;
            }
            D::scatter_force(
                &mut nodes[origin[i]..origin[i] + span],
                p,
                &st[i],
                sigma * -volume[i],
            );
        }
    }
    grid.reduce_nodes(|o, h| o.new_vel += h.new_vel);
    report
}

/// Step 4, grid side: v*_i = v_i + Δt (f_i/m_i + g) (on halos too: they are refilled before
/// the particles gather).
pub fn grid_forces<D: Dim>(grid: &mut Grid<D>, gravity: D::Vector, dt: Real) {
    for node in &mut grid.nodes {
        let m = node.mass();
        if m > 0.0 {
            node.new_vel = node.vel() + (node.new_vel / m + gravity) * dt;
        }
    }
}

/// Step 4 for a kinematic body: its grid velocities stay those its particles brought.
pub fn hold_velocities<D: Dim>(grid: &mut Grid<D>) {
    for node in &mut grid.nodes {
        node.new_vel = node.vel();
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

/// Step 5, walls: constrains the nodes on or beyond the domain's faces; returns the energy
/// the constraint removed.
pub fn grid_walls<D: Dim>(grid: &mut Grid<D>, walls: &Walls<D>) -> f64 {
    let edge = Grid::<D>::BLOCK as i32;
    let mut dissipated = 0.0;
    let Grid {
        index,
        layout,
        nodes,
        ..
    } = grid;
    for slot in 0..index.block_count() {
        if !walls.block_touches(index.block_origin(slot), edge) {
            continue;
        }
        layout.for_each_owned(index, slot, |coord, n| {
            let node = &mut nodes[n];
            let m = node.mass();
            if m <= 0.0 {
                return;
            }
            let before = node.new_vel;
            let after = walls.node_velocity(coord, before);
            if after != before {
                dissipated += constraint_dissipation(m, node.vel(), before, after);
                node.new_vel = after;
            }
        });
    }
    dissipated
}

/// Copies the owners' updated velocities into the halos (before the particles gather).
pub fn fill_new_velocities<D: Dim>(grid: &mut Grid<D>) {
    grid.fill_nodes(|h, o| h.new_vel = o.new_vel);
}

/// The mutable particle state the gather pass touches.
pub struct GatherState<'a, D: Dim> {
    pub x: &'a mut [D::Vector],
    pub v: &'a mut [D::Vector],
    /// The APIC affine velocities, for APIC bodies.
    pub affine: Option<&'a mut [D::Grad]>,
    pub mass: &'a [Real],
    pub plastic_strain: &'a [Real],
}

/// What the gather pass measured (after the step).
#[derive(Clone, Copy, Debug)]
pub struct GatherReport<D: Dim> {
    pub mass: f64,
    pub kinetic: f64,
    pub gravitational: f64,
    pub momentum: [f64; 3],
    /// Σ m x.
    pub first_moment: [f64; 3],
    pub min: D::Vector,
    pub max: D::Vector,
    pub max_speed: Real,
    pub max_plastic_strain: Real,
    /// Kinetic energy removed by the particle-side wall projection.
    pub dissipated_walls: f64,
    pub bad: usize,
    pub first_bad: Option<usize>,
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
        r.record(ps.mass[q], x, ps.v[q], ps.plastic_strain[q]);
    }
    r.finish(gravity);
    r
}

impl<D: Dim> GatherReport<D> {
    /// Nothing recorded yet.
    pub fn empty() -> Self {
        GatherReport {
            mass: 0.0,
            kinetic: 0.0,
            gravitational: 0.0,
            momentum: [0.0; 3],
            first_moment: [0.0; 3],
            min: D::Vector::splat(Real::INFINITY),
            max: D::Vector::splat(Real::NEG_INFINITY),
            max_speed: 0.0,
            max_plastic_strain: 0.0,
            dissipated_walls: 0.0,
            bad: 0,
            first_bad: None,
        }
    }

    /// After the last particle: the speed from its square, and the gravitational energy
    /// −Σ m g·x = −g·Σ m x from the first moment (one accumulator fewer per particle).
    #[inline(always)]
    pub fn finish(&mut self, gravity: D::Vector) {
        self.max_speed = self.max_speed.sqrt();
        self.gravitational = -(0..D::DIM)
            .map(|a| gravity[a] as f64 * self.first_moment[a])
            .sum::<f64>();
    }

    /// Adds one particle (`max_speed` holds the squared speed until [`Self::finish`]).
    #[inline(always)]
    pub fn record(&mut self, m: Real, x: D::Vector, v: D::Vector, plastic_strain: Real) {
        let (md, v2) = (m as f64, v.length_squared());
        self.mass += md;
        self.kinetic += 0.5 * md * v2 as f64;
        for a in 0..D::DIM {
            self.momentum[a] += md * v[a] as f64;
            self.first_moment[a] += md * x[a] as f64;
        }
        self.min = self.min.min(x);
        self.max = self.max.max(x);
        self.max_speed = max(self.max_speed, v2);
        self.max_plastic_strain = max(self.max_plastic_strain, plastic_strain);
    }
}

/// Steps 6–8: the PIC/FLIP blend v_p = (1 − α) Σ_i v_i^{n+1} w_ip + α (v_p + Σ_i Δv_i w_ip)
/// (with APIC also C_p = B_p D_p⁻¹ from B_p = Σ_i w_ip v_i^{n+1} (x_i − x_p)ᵀ),
/// the particle-side wall projection for particles of half-width `radius`, and advection
/// x_p += Δt v_p.
#[allow(clippy::too_many_arguments)]
pub fn gather_and_advect<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &Grid<D>,
    ps: GatherState<'_, D>,
    alpha: Real,
    dt: Real,
    inv_h: Real,
    walls: &Walls<D>,
    radius: Real,
    gravity: D::Vector,
) -> GatherReport<D> {
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
    for q in 0..ps.x.len() {
        let x = ps.x[q];
        let st = K::stencil(grid_coords::<D>(x, inv_h), D::DIM, inv_h, radius * inv_h);
        let origin = first_node(layout, particle_node[q], &st);
        let cell = &nodes[origin..origin + span];
        let (v_pic, v_old) = D::gather_velocity(cell, p, &st);
        if let Some(c) = affine.as_deref_mut() {
            c[q] = D::affine_velocity(D::gather_affine(cell, p, &st), &st, h);
        }
        let blended = v_pic * (1.0 - alpha) + (ps.v[q] + v_pic - v_old) * alpha;
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
        r.record(m, x, v, ps.plastic_strain[q]);
    }
    r.finish(gravity);
    r
}
