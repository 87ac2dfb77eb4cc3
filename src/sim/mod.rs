//! The simulation: particles, bodies with their grids, and the time step of Sec. 4.2.

pub(crate) mod body;
pub(crate) mod particles;
pub mod pour;
pub(crate) mod stats;
mod warnings;

pub use body::Body;
pub(crate) use body::World;
pub use particles::Particles;
pub use pour::Spout;
pub use stats::{ACCOUNT_TOLERANCE, BodyStats, Diagnostics, Measure, PassTimings};

use crate::boundary::STICKING_CFL;
use crate::config::{BodyConfig, MAX_PARTICLES, SceneConfig};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::kernel::KernelKind;
use crate::material::Material;
use crate::math::{D2, D3, Dim, Real, VectorOps};
use crate::recipe::Recipe;
use crate::step::sleep::{SleepRule, Sleeping};
use crate::step::{Bad, Step};

/// A body's shape sampled into particle positions (3 components, unused ones zero) and the
/// volume of each.
#[derive(Clone, Debug)]
pub(crate) struct Sampled {
    points: Vec<[f64; 3]>,
    volume: f64,
}

/// An MPM simulation in dimension `D` ([`D2`] plane strain or [`D3`]).
///
/// Its scene holds the bodies in the simulation, then those still to come (bodies whose
/// `appear_at` lies ahead), in order of appearance: `scene().bodies[i]` is `bodies()[i]` for
/// every body present. [`Simulation::step`] and [`Simulation::advance_until`] stop at the time
/// a body is due and add it, and add the layers a spout has poured before each step
/// ([`pour`]); [`Simulation::step_at_most`] steps only.
#[derive(Clone, Debug)]
pub struct Simulation<D: Dim> {
    pub(crate) scene: SceneConfig,
    /// The particles of the bodies still to come, `scene.bodies[bodies.len()..]`, sampled when
    /// they were added (so that a shape without particles is an error up front).
    pub(crate) to_come: Vec<Sampled>,
    pub(crate) world: World<D>,
    pub(crate) particles: Particles<D>,
    pub(crate) bodies: Vec<Body<D>>,
    pub(crate) time: f64,
    pub(crate) steps: u64,
    pub(crate) diagnostics: Diagnostics,
    pub(crate) failed: Option<Error>,
    /// Particle state was edited directly ([`Simulation::particles_mut`]): the energy guard
    /// cannot know the work of such edits, so it stands down for the rest of the run.
    pub(crate) edited: bool,
    pub(crate) next_id: u32,
    /// Particles are reordered by grid block every this many steps (0: never), for locality.
    pub sort_interval: u64,
    /// Wall-clock time per pass, accumulated while `Some` (native builds only).
    pub timings: Option<PassTimings>,
    /// Whether and how material at rest sleeps, the step's own state ([`crate::step::sleep`]);
    /// off by default.
    pub(crate) sleeping: Sleeping<D>,
}

impl<D: Dim> Simulation<D> {
    /// Builds a simulation from a scene (validated here).
    pub fn new(scene: SceneConfig) -> Result<Self> {
        if scene.dim != D::DIM {
            return Err(Error::invalid(
                "dim",
                scene.dim,
                format!("must be {} for a {}D simulation", D::DIM, D::DIM),
            ));
        }
        scene.validate_world()?;
        let bodies = scene.bodies.clone();
        let mut sim = Simulation {
            world: World::new(&scene),
            scene: SceneConfig {
                bodies: Vec::new(),
                ..scene
            },
            to_come: Vec::new(),
            particles: Particles::default(),
            bodies: Vec::new(),
            time: 0.0,
            steps: 0,
            diagnostics: Diagnostics::default(),
            failed: None,
            edited: false,
            next_id: 0,
            sort_interval: 16,
            timings: None,
            sleeping: Sleeping::default(),
        };
        // Every body is sampled first, so that an error names it by its place in the file;
        // those present from the start keep the file's order, the others follow by time.
        let mut sampled = Vec::with_capacity(bodies.len());
        let mut total = 0;
        for (i, b) in bodies.into_iter().enumerate() {
            let s = sim.sample_body(&b, &format!("bodies[{i}]"), total)?;
            total += s.points.len();
            sampled.push((b, s));
        }
        sampled.sort_by(|a, b| a.0.appear_time().total_cmp(&b.0.appear_time()));
        for (b, s) in sampled {
            sim.insert(b, s);
        }
        Ok(sim)
    }

    /// A builder over an empty scene with the given domain size (m) and cell size (m).
    pub fn builder(size: &[f64], cell_size: f64) -> SimulationBuilder<D> {
        SimulationBuilder {
            scene: SceneConfig::new(D::DIM, size, cell_size),
            _dim: Default::default(),
        }
    }

    /// Samples a body's shape into particles and adds it, or schedules it when its `appear_at`
    /// lies ahead; returns its index in [`Simulation::scene`].
    pub fn add_body(&mut self, config: BodyConfig) -> Result<usize> {
        let path = format!("bodies[{}]", self.scene.bodies.len());
        let sampled = self.sample_body(&config, &path, self.particle_total())?;
        Ok(self.insert(config, sampled))
    }

    /// Validates a body (named `path` in errors) and samples its shape; `existing` particles
    /// are already in the simulation or to come.
    fn sample_body(&self, config: &BodyConfig, path: &str, existing: usize) -> Result<Sampled> {
        config.validate(path, D::DIM, &self.scene.domain.size)?;
        self.scene.check_transfer(config, path)?;
        self.scene.check_pour(config, path)?;
        let (points, volume) = config.sample(path, D::DIM, self.scene.cell_size)?;
        // a poured body starts empty: its particles are those its spout will pour
        let (field, count) = match &config.pour {
            Some(pour) => {
                let spout = Spout::new(
                    pour,
                    D::DIM,
                    self.scene.cell_size,
                    config.particles_per_cell,
                    0.0,
                    0,
                    0.0,
                );
                (
                    format!("{path}.pour"),
                    usize::try_from(spout.particles()).unwrap_or(usize::MAX),
                )
            }
            None => (format!("{path}.shape"), points.len()),
        };
        if config.pour.is_none() && points.is_empty() {
            return Err(Error::invalid(
                field,
                "a shape with no particle",
                "must hold at least one particle at this cell_size and particles_per_cell",
            ));
        }
        if existing.saturating_add(count) > MAX_PARTICLES {
            return Err(Error::invalid(
                field,
                format!("{count} more particles"),
                format!("the simulation holds at most {MAX_PARTICLES} particles"),
            ));
        }
        Ok(Sampled { points, volume })
    }

    /// Particles in the simulation and to come.
    fn particle_total(&self) -> usize {
        self.particles.len() + self.to_come.iter().map(|s| s.points.len()).sum::<usize>()
    }

    /// Whether simulated time `t` has been reached (to rounding).
    fn reached(&self, t: f64) -> bool {
        reached(self.time, t)
    }

    /// Adds a sampled body now, or among those to come when its time lies ahead; returns its
    /// index in the scene.
    fn insert(&mut self, config: BodyConfig, sampled: Sampled) -> usize {
        let present = self.bodies.len();
        if self.reached(config.appear_time()) {
            self.scene.bodies.insert(present, config);
            self.activate(sampled);
            return present;
        }
        let t = config.appear_time();
        let k = self.scene.bodies[present..].partition_point(|b| b.appear_time() <= t);
        self.scene.bodies.insert(present + k, config);
        self.to_come.insert(k, sampled);
        present + k
    }

    /// Puts the particles of `scene.bodies[bodies.len()]` into the simulation.
    fn activate(&mut self, Sampled { points, volume }: Sampled) {
        let config = &self.scene.bodies[self.bodies.len()];
        let density = config.material.density();
        let v0 = config
            .velocity
            .as_deref()
            .map_or(D::Vector::ZERO, |v| D::Vector::from_fn(|a| v[a] as Real));
        let recipe = Recipe::new(config, self.scene.kernel, self.scene.cell_size);
        if recipe.apic {
            self.particles.enable_affine();
        }
        let start = self.particles.len();
        let mass = (volume * density) as Real;
        let radius = (0.5 * volume.powf(1.0 / D::DIM as f64)) as Real;
        let areas = config.traction.as_ref().map(|t| {
            let b = config.shape.bounds(D::DIM);
            let spacing = volume.powf(1.0 / D::DIM as f64);
            t.area_vectors(&points, D::DIM, spacing, b.min, b.max)
        });
        let traction = config.traction.as_ref().map_or(0.0, |t| t.pressure as Real);
        if areas.is_some() {
            self.particles.enable_area();
        }
        for p in points {
            let x = self
                .world
                .walls
                .clamp(D::vector(p.map(|c| c as Real)), radius);
            self.particles
                .push(x, v0, volume as Real, mass, self.next_id);
            self.next_id += 1;
        }
        self.bodies.push(Body {
            model: config.material.model(),
            recipe,
            range: start..self.particles.len(),
            grid: Grid::default(),
            stats: BodyStats::default(),
            max_volume: volume as Real,
            min_mass: mass,
            radius,
            kinematic: config.kinematic,
            max_compression: 0.0,
            stuck: false,
            asleep: 0,
            traction,
            spout: config.pour.as_ref().map(|pour| {
                Spout::new(
                    pour,
                    D::DIM,
                    self.scene.cell_size,
                    config.particles_per_cell,
                    config.jitter,
                    config.seed,
                    self.time,
                )
            }),
        });
        if let Some(areas) = areas {
            for (a, n) in self.particles.area[start..].iter_mut().zip(areas) {
                *a = D::Vector::from_fn(|k| n[k] as Real);
            }
        }
        self.refresh_diagnostics();
    }

    /// Adds the bodies whose time has come; returns how many.
    pub fn land_due_bodies(&mut self) -> usize {
        let mut n = 0;
        while self.next_appearance().is_some_and(|t| self.reached(t)) {
            let sampled = self.to_come.remove(0);
            self.activate(sampled);
            n += 1;
        }
        n
    }

    /// Adds the layers the spouts have poured by now ([`pour`]): each where it has fallen to
    /// since it left the exit, just before its body's sleeping particles; books their kinetic
    /// and gravitational energy as energy brought in. Returns how many particles entered.
    pub fn pour_due_layers(&mut self) -> usize {
        let gravity: [f64; 3] = std::array::from_fn(|a| {
            if a < D::DIM {
                self.world.gravity[a] as f64
            } else {
                0.0
            }
        });
        let (time, mut added) = (self.time, 0);
        let mut inflow = Measure::<D>::empty();
        for b in 0..self.bodies.len() {
            let Some(spout) = &mut self.bodies[b].spout else {
                continue;
            };
            let (mut x, mut v) = (Vec::new(), Vec::new());
            while spout.next_layer().is_some_and(|t| reached(time, t)) {
                spout.pour_layer(time, gravity, &mut x, &mut v);
            }
            if x.is_empty() {
                continue;
            }
            let body = &self.bodies[b];
            let volume =
                (body.spout.as_ref().expect("a spout").spacing() as Real).powi(D::DIM as i32);
            let mass = volume * self.scene.bodies[b].material.density() as Real;
            let x: Vec<D::Vector> = x
                .iter()
                .map(|p| {
                    self.world
                        .walls
                        .clamp(D::vector(p.map(|c| c as Real)), body.radius)
                })
                .collect();
            let v: Vec<D::Vector> = v.iter().map(|c| D::vector(c.map(|c| c as Real))).collect();
            for (&x, &v) in x.iter().zip(&v) {
                inflow.record(mass, x, v);
            }
            let at = body.range.end - body.asleep;
            self.particles
                .insert(at, &x, &v, volume, mass, self.next_id);
            let n = x.len();
            self.next_id += n as u32;
            self.bodies[b].range.end += n;
            for later in &mut self.bodies[b + 1..] {
                later.range = later.range.start + n..later.range.end + n;
            }
            added += n;
        }
        if added > 0 {
            inflow.finish(self.world.gravity);
            self.measure_state();
            self.diagnostics.energy_in += inflow.kinetic + inflow.gravitational;
        }
        added
    }

    /// Ends the pour of body `i`, which is present and poured, at simulated time `t` (s): its
    /// spout pours no layer that leaves after `t`, and its `pour.duration` in the scene becomes
    /// the duration that pours the layers kept ([`Spout::held`]: about `t` less its opening
    /// time), so that the scene as it stands pours the same layers. A spout that has ended keeps
    /// its duration. Returns the new duration (s). `t` must not lie before a layer poured.
    pub fn stop_pour(&mut self, i: usize, t: f64) -> Result<f64> {
        let present = self.bodies.len();
        let Some(spout) = self.bodies.get_mut(i).and_then(|b| b.spout.as_mut()) else {
            return Err(Error::invalid(
                "body",
                i,
                format!("must be a poured body present, below {present}"),
            ));
        };
        let last = spout.poured().checked_sub(1).map(|k| spout.exit_time(k));
        if !t.is_finite() || last.is_some_and(|l| !reached(t, l)) {
            return Err(Error::invalid(
                "t",
                t,
                format!(
                    "must be finite and at or after the last layer poured (at {} s)",
                    last.unwrap_or(spout.start())
                ),
            ));
        }
        let pour = self.scene.bodies[i].pour.as_mut().expect("a poured body");
        pour.duration = spout.stop_at(t, pour.duration);
        Ok(pour.duration)
    }

    /// Whether a spout present has layers left to pour.
    pub fn pouring(&self) -> bool {
        self.bodies
            .iter()
            .any(|b| b.spout.as_ref().is_some_and(|s| s.next_layer().is_some()))
    }

    /// Adds the bodies due and the layers the spouts have poured by now: what enters before
    /// a step.
    fn enter_due(&mut self) {
        self.land_due_bodies();
        self.pour_due_layers();
    }

    /// Records `t` as the `appear_at` of body `i`, which is present: the time it entered on a
    /// front end's clock (a playground's drop clock restarts at a Clear), for saving the scene.
    pub(crate) fn record_appearance(&mut self, i: usize, t: Option<f64>) {
        if i < self.bodies.len() {
            self.scene.bodies[i].appear_at = t;
        }
    }

    /// The bodies still to come, in order of appearance, with their particle counts.
    pub fn bodies_to_come(&self) -> impl Iterator<Item = (&BodyConfig, usize)> {
        self.scene.bodies[self.bodies.len()..]
            .iter()
            .zip(self.to_come.iter().map(|s| s.points.len()))
    }

    /// The time the next body to come enters (s), if any.
    pub fn next_appearance(&self) -> Option<f64> {
        self.scene
            .bodies
            .get(self.bodies.len())
            .map(|b| b.appear_time())
    }

    /// Removes body `i` (of the scene: present or to come) and its particles.
    pub fn remove_body(&mut self, i: usize) -> Result<()> {
        if i >= self.scene.bodies.len() {
            return Err(Error::invalid(
                "body",
                i,
                format!("must be a body index below {}", self.scene.bodies.len()),
            ));
        }
        if i >= self.bodies.len() {
            self.to_come.remove(i - self.bodies.len());
            self.scene.bodies.remove(i);
            return Ok(());
        }
        let r = self.bodies[i].range.clone();
        self.particles.remove(r.clone());
        self.bodies.remove(i);
        self.sleeping.remove(i);
        self.scene.bodies.remove(i);
        for b in &mut self.bodies[i..] {
            b.range = b.range.start - r.len()..b.range.end - r.len();
        }
        self.refresh_diagnostics();
        Ok(())
    }

    /// Removes every body, those to come too.
    pub fn clear(&mut self) {
        self.to_come.clear();
        self.particles.clear();
        self.bodies.clear();
        self.wake_all();
        self.scene.bodies.clear();
        self.failed = None;
        self.refresh_diagnostics();
    }

    /// Changes parameters while running: `f` edits a copy of the scene; the copy is validated
    /// like a scene file and applied, or rejected with the state unchanged. World settings,
    /// materials and PIC/FLIP ratios may change (of the bodies to come too); dimension, domain
    /// and the bodies' shapes and pours, sampling, initial velocities and times of appearance
    /// may not.
    pub fn configure(&mut self, f: impl FnOnce(&mut SceneConfig)) -> Result<()> {
        let mut next = self.scene.clone();
        f(&mut next);
        if next.dim != self.scene.dim {
            return Err(Error::invalid(
                "dim",
                next.dim,
                format!("cannot change while running (is {})", self.scene.dim),
            ));
        }
        if next.domain != self.scene.domain {
            return Err(Error::invalid(
                "domain.size",
                format!("{:?}", next.domain.size),
                format!(
                    "cannot change while running (is {:?})",
                    self.scene.domain.size
                ),
            ));
        }
        if next.bodies.len() != self.scene.bodies.len() {
            return Err(Error::invalid(
                "bodies",
                next.bodies.len(),
                "use add_body/remove_body to change the bodies",
            ));
        }
        for (i, (a, b)) in next.bodies.iter().zip(&self.scene.bodies).enumerate() {
            if a.shape != b.shape
                || a.pour != b.pour
                || a.particles_per_cell != b.particles_per_cell
                || a.velocity != b.velocity
                || a.jitter != b.jitter
                || a.seed != b.seed
                || a.kinematic != b.kinematic
                || a.appear_at != b.appear_at
            {
                return Err(Error::invalid(
                    format!("bodies[{i}]"),
                    "a new shape, sampling, initial velocity or time of appearance",
                    "cannot change while running: add a new body instead",
                ));
            }
        }
        next.validate()?;
        self.world = World::new(&next);
        self.scene = next;
        for i in 0..self.bodies.len() {
            self.rebuild_body(i);
        }
        // a weaker material, another gravity or wall friction may move what sleeps
        self.wake_all();
        Ok(())
    }

    /// Changes world settings while running, as [`Simulation::configure`] does, without
    /// touching the bodies: `f` edits a copy of the world settings (the scene without its
    /// bodies), which is validated and applied, or rejected with the state unchanged.
    pub fn set_world(&mut self, f: impl FnOnce(&mut SceneConfig)) -> Result<()> {
        let mut next = self.scene.world();
        f(&mut next);
        if next.dim != self.scene.dim || next.domain != self.scene.domain || !next.bodies.is_empty()
        {
            return Err(Error::invalid(
                "world",
                "a new dimension, domain or bodies",
                "cannot change here: use configure",
            ));
        }
        next.validate_world()?;
        self.world = World::new(&next);
        next.bodies = std::mem::take(&mut self.scene.bodies);
        self.scene = next;
        self.wake_all();
        Ok(())
    }

    /// Gives bodies (present or to come) new materials and PIC/FLIP ratios, each
    /// `(index, material, flip)` checked as a scene file's body is
    /// ([`BodyConfig::check_material`]); on error nothing changes. Only those bodies' models and
    /// recipes are built again, and only those whose change can move material at rest wake
    /// ([`crate::step::sleep::may_move`]).
    pub fn set_materials(&mut self, changes: Vec<(usize, Material, Option<f64>)>) -> Result<()> {
        let n = self.scene.bodies.len();
        for (i, material, flip) in &changes {
            if *i >= n {
                return Err(Error::invalid(
                    "bodies",
                    i,
                    format!("must be a body of the scene, below {n}"),
                ));
            }
            BodyConfig::check_material(&format!("bodies[{i}]"), material, *flip)?;
        }
        for (i, material, flip) in changes {
            let config = &mut self.scene.bodies[i];
            let moves = crate::step::sleep::may_move(&config.material, &material);
            config.material = material;
            config.flip = flip;
            if i < self.bodies.len() {
                self.rebuild_body(i);
                if moves {
                    self.sleeping.wake_body(i, &mut self.bodies[i]);
                }
            }
        }
        Ok(())
    }

    /// Body `i`'s model and recipe from its entry in the scene, after its material, PIC/FLIP
    /// ratio or the world changed.
    fn rebuild_body(&mut self, i: usize) {
        let config = &self.scene.bodies[i];
        let recipe = Recipe::new(config, self.scene.kernel, self.scene.cell_size);
        if recipe.apic {
            self.particles.enable_affine();
        }
        let body = &mut self.bodies[i];
        body.model = config.material.model();
        body.traction = config.traction.as_ref().map_or(0.0, |t| t.pressure as Real);
        if recipe.bulk_length == 0.0 {
            // no viscous pressure left for a body that turned to sand to meet again
            self.particles.viscous_pressure[body.range.clone()].fill(0.0);
        }
        if recipe.apic && !body.recipe.apic {
            // a body that turns to APIC starts from a zero affine velocity
            self.particles.affine[body.range.clone()].fill(D::GRAD_ZERO);
        }
        body.recipe = recipe;
    }

    /// The scene as it stands: world settings and the bodies' parameters, the bodies present
    /// first, then those to come.
    pub fn scene(&self) -> &SceneConfig {
        &self.scene
    }
    /// How many particle ids have been issued: every particle that ever entered has an id
    /// below it, and a particle entering next gets this one.
    pub fn ids_issued(&self) -> u32 {
        self.next_id
    }

    pub fn particles(&self) -> &Particles<D> {
        &self.particles
    }
    /// Direct access to particle state (for tests and tools that set up special states);
    /// wakes every sleeping particle, since the edit may move it.
    pub fn particles_mut(&mut self) -> &mut Particles<D> {
        self.wake_all();
        self.edited = true;
        &mut self.particles
    }
    pub fn bodies(&self) -> &[Body<D>] {
        &self.bodies
    }
    /// The world settings every body sees (cell size, kernel, walls), as the step uses them.
    pub(crate) fn world(&self) -> &World<D> {
        &self.world
    }
    /// Diagnostics after the latest step.
    pub fn diagnostics(&self) -> &Diagnostics {
        &self.diagnostics
    }
    pub fn time(&self) -> f64 {
        self.time
    }
    pub fn steps(&self) -> u64 {
        self.steps
    }
    pub fn cell_size(&self) -> f64 {
        self.world.h as f64
    }
    /// The error that stopped the simulation, if any.
    pub fn failure(&self) -> Option<&Error> {
        self.failed.as_ref()
    }

    /// One time step, no longer than `limit` seconds: the eight steps of Sec. 4.2
    /// ([`crate::step`]).
    pub fn step_at_most(&mut self, limit: f64) -> Result<&Diagnostics> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if limit.is_nan() || limit <= 0.0 {
            return Err(Error::invalid("step limit", limit, "must be > 0 (s)"));
        }
        let stable = self.stable_dt();
        if stable < MIN_DT {
            let e = self.step_too_small(stable);
            self.failed = Some(e.clone());
            return Err(e);
        }
        let dt = stable.min(limit);
        self.ramp_tractions(dt);
        let (mut step, sleeping) = self.lend();
        let done = step.run(dt, sleeping);
        self.time += dt;
        self.steps += 1;
        self.record_measures(dt, done.signal_speed, &done.measures, &done.elastic);
        if let Some((i, particle, bad)) = done.bad {
            let body = self.scene.bodies[i].name.clone();
            let step = self.steps;
            let e = match bad {
                Bad::Crushed => Error::Crushed {
                    body,
                    particle,
                    step,
                },
                Bad::NonFinite(quantity) => Error::NonFinite {
                    body,
                    particle,
                    quantity,
                    step,
                },
            };
            self.failed = Some(e.clone());
            return Err(e);
        }
        if let Some(e) = self.energy_guard() {
            self.failed = Some(e.clone());
            return Err(e);
        }
        let (mut step, sleeping) = self.lend();
        step.sleep_and_wake(sleeping, dt);
        Ok(&self.diagnostics)
    }

    /// The pressure of each traction with a rise time, at the middle of the step of `dt` to
    /// come ([`crate::config::TractionConfig::ramp`]).
    fn ramp_tractions(&mut self, dt: f64) {
        let t = self.time + 0.5 * dt;
        for (body, config) in self.bodies.iter_mut().zip(&self.scene.bodies) {
            if let Some(tr) = config.traction.as_ref().filter(|tr| tr.rise_time > 0.0) {
                body.traction = (tr.pressure * tr.ramp(t)) as Real;
            }
        }
    }

    /// The state the step works on, lent to it, and sleeping's state, the step's own.
    fn lend(&mut self) -> (Step<'_, D>, &mut Sleeping<D>) {
        let step = Step {
            world: &self.world,
            particles: &mut self.particles,
            bodies: &mut self.bodies,
            diagnostics: &mut self.diagnostics,
            timings: &mut self.timings,
            steps: self.steps,
            sort_interval: self.sort_interval,
        };
        (step, &mut self.sleeping)
    }

    /// Switches sleeping on with `rule` (or with [`SleepRule::for_grid`] for this scene's
    /// grid), or off with `None` (everything wakes).
    pub fn set_sleeping(&mut self, rule: Option<SleepRule>) {
        self.sleeping.set(rule, &mut self.bodies);
    }

    /// Sleeping on with the rule for this scene's grid ([`SleepRule::for_grid`]).
    pub fn sleep_when_at_rest(&mut self) {
        let g = self.world.gravity.length() as f64;
        self.set_sleeping(Some(SleepRule::for_grid(self.world.h as f64, g)));
    }

    /// The rule material sleeps by, if sleeping is on.
    pub fn sleeping(&self) -> Option<SleepRule> {
        self.sleeping.rule()
    }

    /// Wakes every sleeping particle.
    pub fn wake_all(&mut self) {
        self.sleeping.wake_all(&mut self.bodies);
    }

    /// How many particles sleep.
    pub fn asleep(&self) -> usize {
        self.bodies.iter().map(|b| b.asleep).sum()
    }

    /// Bytes of particle and grid state.
    pub fn memory_bytes(&self) -> usize {
        self.particles.x.capacity() * Particles::<D>::bytes_per_particle()
            + self
                .bodies
                .iter()
                .map(|b| b.grid.memory_bytes())
                .sum::<usize>()
    }

    /// The largest signal speed of the bodies (m/s), see [`Body::signal_speed`].
    pub fn max_wave_speed(&self) -> f64 {
        body::max_signal_speed(&self.bodies)
    }

    /// The time step the next step will take: dt = CFL · h / max(c + |v|), capped by max_dt,
    /// with c = √((K + 4G/3)/ρ) at each body's lowest density (raised by the bulk viscosity
    /// of a fast-compressing solid, [`Body::signal_speed`]); after a step in which a contact
    /// held solids together ([`Simulation::step_cfl`]), also at most
    /// [`STICKING_CFL`] · h / (c + |v|) with c the largest signal speed of those bodies only.
    pub fn stable_dt(&self) -> f64 {
        let (h, v) = (self.world.h as f64, self.diagnostics.max_speed);
        let (g, max_dt) = (self.world.gravity.length() as f64, self.world.max_dt);
        let dt = cfl_time_step(self.world.cfl, h, self.max_wave_speed() + v, g, max_dt);
        if !self.solids_stuck() {
            return dt;
        }
        let stuck = body::max_signal_speed(self.bodies.iter().filter(|b| b.stuck));
        dt.min(cfl_time_step(self.step_cfl(), h, stuck + v, g, max_dt))
    }

    /// The error for a stable step `dt` below [`MIN_DT`]: what sets it (the fastest body's
    /// wave speed, the particles' speed or gravity) and the setting to change.
    pub(crate) fn step_too_small(&self, dt: f64) -> Error {
        let (cfl, h) = (self.step_cfl(), self.world.h as f64);
        let when = if self.steps > 0 {
            format!(" at step {} (t = {:.4} s)", self.steps, self.time)
        } else {
            String::new()
        };
        let speed = self.diagnostics.max_speed;
        let g = self.world.gravity.length() as f64;
        let fastest = self
            .bodies
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.signal_speed().total_cmp(&b.1.signal_speed()));
        let c = fastest.map_or(0.0, |(_, b)| b.signal_speed());
        let by_gravity = g > 0.0 && (cfl * h / g).sqrt() < cfl * h / (c + speed);
        let cause = match fastest {
            _ if by_gravity => format!(
                "gravity of {g:.3e} m/s² would move a particle by {cfl} cells in a longer step: lower gravity (or a coarser cell_size)"
            ),
            Some((i, b)) if c >= speed => {
                let config = &self.scene.bodies[i];
                format!(
                    "body {:?} carries waves at {c:.3e} m/s (youngs_modulus {:.3e} Pa, density {:.3e} kg/m³ at its loosest): lower its youngs_modulus or raise its density (or a coarser cell_size or a larger cfl, now {cfl})",
                    config.name,
                    config.material.elastic_params().youngs_modulus,
                    b.min_mass as f64 / b.max_volume as f64,
                )
            }
            _ => format!(
                "particles move at {speed:.3e} m/s: lower the bodies' velocity (or a coarser cell_size)"
            ),
        };
        Error::StepTooSmall {
            dt,
            floor: MIN_DT,
            steps: 1.0 / dt,
            when,
            cause,
        }
    }

    /// The energy guard ([`ENERGY_GUARD`]): an error when the live energy has risen above the
    /// energy brought in by more than the margin.
    pub(crate) fn energy_guard(&self) -> Option<Error> {
        if self.edited {
            return None;
        }
        let d = &self.diagnostics;
        let mass: f64 = self.bodies.iter().map(|b| b.stats.mass).sum();
        let lift = mass * self.world.gravity.length() as f64 * self.world.h as f64;
        let scale = d.energy_in.abs() + lift;
        let total = d.total_energy();
        if !(total - d.energy_in > ENERGY_GUARD * scale && scale > 0.0) {
            return None;
        }
        let flip = self
            .bodies
            .iter()
            .map(|b| b.recipe.flip as f64)
            .fold(0.0, f64::max);
        let kernel = match self.scene.kernel {
            KernelKind::Linear => {
                ", or the gimp or quadratic_bspline kernel (the linear kernel's forces jump as a particle crosses a cell)"
            }
            _ => "",
        };
        Some(Error::EnergyGrew {
            total,
            budget: d.energy_in,
            margin: 100.0 * ENERGY_GUARD,
            step: self.steps,
            time: self.time,
            advice: format!(
                "lower cfl (now {}) or the flip share (now up to {flip}){kernel}; a softer material (youngs_modulus) or slower bodies need fewer steps to stay stable",
                self.step_cfl()
            ),
        })
    }

    /// Whether the latest contact pass held two solids that update their stress last
    /// together (each such body's `stuck`).
    fn solids_stuck(&self) -> bool {
        self.bodies.iter().any(|b| b.stuck)
    }

    /// The CFL number of the next step for the bodies a contact held together: the scene's,
    /// or at most [`STICKING_CFL`] after a step in which a contact rule that
    /// sticks ([`ContactRule::sticks`]) changed the grid velocities of two solids that update
    /// their stress last (only those bodies' signal speeds take it, [`Simulation::stable_dt`]).
    pub fn step_cfl(&self) -> f64 {
        if self.solids_stuck() {
            self.world.cfl.min(STICKING_CFL)
        } else {
            self.world.cfl
        }
    }

    /// Advances by `duration` seconds (the last step is shortened to land on it, and the bodies
    /// due on the way enter at their times); returns the number of steps taken.
    pub fn advance(&mut self, duration: f64) -> Result<usize> {
        self.advance_until(self.time + duration, |_| true)
    }

    /// Steps towards simulated time `end` (the last step is shortened to land on it) while
    /// `go_on`, shown the latest diagnostics, allows another step (a wall-clock budget, a
    /// progress report); returns the number of steps taken. A step never passes the time a
    /// body is due: it ends there and the body enters. The one driver loop of every front end.
    pub fn advance_until(
        &mut self,
        end: f64,
        mut go_on: impl FnMut(&Diagnostics) -> bool,
    ) -> Result<usize> {
        let mut n = 0;
        self.enter_due();
        while self.time < end - 1e-12 * end.abs().max(1.0) && go_on(&self.diagnostics) {
            let stop = self.next_appearance().map_or(end, |t| t.min(end));
            self.step_at_most(stop - self.time)?;
            self.enter_due();
            n += 1;
        }
        Ok(n)
    }

    /// One time step of the adaptive size, ending at the time the next body is due if that
    /// comes sooner (then it enters); the layers the spouts have poured enter before it and
    /// after it.
    pub fn step(&mut self) -> Result<&Diagnostics> {
        self.enter_due();
        let limit = self
            .next_appearance()
            .map_or(f64::INFINITY, |t| t - self.time);
        self.step_at_most(limit)?;
        self.enter_due();
        Ok(&self.diagnostics)
    }

    /// Sets the diagnostics of the particle state, and each body's figures, from the bodies'
    /// `measures` and stored `elastic` energies: time, counts, energies, momentum, the largest
    /// speed, and the CFL number of a step of `dt` at the signal speed `c`.
    pub(crate) fn record_measures(
        &mut self,
        dt: f64,
        c: f64,
        measures: &[Measure<D>],
        elastic: &[f64],
    ) {
        let d = &mut self.diagnostics;
        d.time = self.time;
        d.step = self.steps;
        d.dt = dt;
        d.particles = self.particles.len();
        d.grid_blocks = self.bodies.iter().map(|b| b.grid.index.block_count()).sum();
        let (mut kinetic, mut grav, mut stored, mut momentum, mut max_speed) =
            (0.0, 0.0, 0.0, [0.0; 3], 0.0f64);
        for (i, body) in self.bodies.iter_mut().enumerate() {
            let g = &measures[i];
            body.stats.elastic = elastic[i];
            g.write(&mut body.stats, body.range.len());
            kinetic += g.kinetic;
            grav += g.gravitational;
            stored += elastic[i];
            max_speed = max_speed.max(g.max_speed as f64);
            for a in 0..3 {
                momentum[a] += g.momentum[a];
            }
        }
        d.kinetic = kinetic;
        d.gravitational = grav;
        d.elastic = stored;
        d.momentum = momentum;
        d.max_speed = max_speed;
        d.cfl = dt * (c + max_speed) / self.world.h as f64;
    }

    /// Recomputes the diagnostics and per-body figures from the particle state, without
    /// stepping (after bodies are added or removed, or particle state is edited directly):
    /// the energies, momentum, bounds and speeds as they stand, and each body's lowest density
    /// (for the time step). The cumulative dissipation and the latest step's contact forces
    /// stay as the latest step left them; the change of the total energy, made by no step,
    /// is booked as energy brought in ([`Diagnostics::energy_in`]).
    pub fn refresh_diagnostics(&mut self) {
        let before = self.diagnostics.total_energy();
        self.measure_state();
        self.diagnostics.energy_in += self.diagnostics.total_energy() - before;
    }

    /// Sets the diagnostics and per-body figures from the particle state as it stands
    /// ([`Simulation::refresh_diagnostics`] without booking the change of energy). A body
    /// without particles keeps the largest volume and smallest mass its sampling gives (its
    /// wave speed).
    fn measure_state(&mut self) {
        let gravity = self.world.gravity;
        let p = &self.particles;
        let mut measures = Vec::with_capacity(self.bodies.len());
        let mut elastic = Vec::with_capacity(self.bodies.len());
        for body in &mut self.bodies {
            let law = *body.model.elastic();
            let mut m = Measure::<D>::empty();
            let (mut stored, mut max_volume): (f64, Real) = (0.0, 0.0);
            let empty = body.range.is_empty();
            let kept = (body.max_volume, body.min_mass);
            body.min_mass = Real::INFINITY;
            for i in body.range.clone() {
                stored += (law.energy_density(p.stress[i]) * p.volume[i]) as f64;
                max_volume = max_volume.max(p.volume[i]);
                body.min_mass = body.min_mass.min(p.mass[i]);
                m.record(p.mass[i], p.x[i], p.v[i]);
            }
            m = m.with_plastic_strain(&p.plastic_strain[body.range.clone()]);
            m.finish(gravity);
            body.max_volume = max_volume;
            if empty {
                (body.max_volume, body.min_mass) = kept;
            }
            measures.push(m);
            elastic.push(stored);
        }
        let c = self.max_wave_speed();
        self.record_measures(self.diagnostics.dt, c, &measures, &elastic);
        self.diagnostics.nonfinite = 0;
    }
}

/// Sets up a scene in Rust; [`SimulationBuilder::build`] validates it like a scene file.
#[derive(Clone, Debug)]
pub struct SimulationBuilder<D: Dim> {
    pub scene: SceneConfig,
    _dim: std::marker::PhantomData<D>,
}

impl<D: Dim> SimulationBuilder<D> {
    pub fn name(mut self, name: &str) -> Self {
        self.scene.name = name.to_string();
        self
    }
    /// Gravity (m/s²).
    pub fn gravity(mut self, g: &[f64]) -> Self {
        self.scene.gravity = Some(g.to_vec());
        self
    }
    pub fn cfl(mut self, cfl: f64) -> Self {
        self.scene.cfl = cfl;
        self
    }
    /// Largest time step (s).
    pub fn max_dt(mut self, dt: f64) -> Self {
        self.scene.max_dt = dt;
        self
    }
    /// Coulomb friction μ of walls and ground.
    pub fn wall_friction(mut self, mu: f64) -> Self {
        self.scene.boundary.friction = mu;
        self
    }
    /// Sticky walls (no motion at the walls).
    pub fn sticky_walls(mut self) -> Self {
        self.scene.boundary.sticky = true;
        self
    }
    pub fn kernel(mut self, k: KernelKind) -> Self {
        self.scene.kernel = k;
        self
    }
    /// Coulomb friction between bodies instead of the paper's sticking contact.
    pub fn contact_friction(mut self, mu: f64) -> Self {
        self.scene.contact.friction = Some(mu);
        self
    }
    pub fn body(mut self, body: BodyConfig) -> Self {
        self.scene.bodies.push(body);
        self
    }
    pub fn build(self) -> Result<Simulation<D>> {
        Simulation::new(self.scene)
    }
}

/// Whether simulated time `t` has been reached at time `now` (to rounding).
fn reached(now: f64, t: f64) -> bool {
    t <= now + 1e-12 * now.abs().max(1.0)
}

/// A simulation whose dimension is chosen at run time (by the scene's `dim`).
#[derive(Clone, Debug)]
pub enum AnySimulation {
    D2(Simulation<D2>),
    D3(Simulation<D3>),
}

/// The CFL condition: dt = `cfl` · `h` / `speed` (the fastest signal, m/s), at most `max_dt`
/// (which a world where nothing moves or carries stress takes), and at most √(`cfl` · `h` /
/// `accel`): a body force of acceleration `accel` (m/s², gravity) moves a particle starting
/// at rest by accel · dt² in a step, which must not pass `cfl` cells either. (In the shipped
/// scenes that bound is about 60 times the wave speed's, which sets the step.)
pub fn cfl_time_step(cfl: f64, h: f64, speed: f64, accel: f64, max_dt: f64) -> f64 {
    let dt = if speed > 0.0 {
        (cfl * h / speed).min(max_dt)
    } else {
        max_dt
    };
    if accel > 0.0 {
        dt.min((cfl * h / accel).sqrt())
    } else {
        dt
    }
}

/// The shortest time step a run takes (s): a scene whose stable step is shorter is refused
/// before stepping ([`crate::Error::StepTooSmall`]), and a run whose step falls below it
/// stops there. Steel (E = 200 GPa, ρ = 7800 kg/m³) at h = 1 mm and CFL 0.4 steps 7·10⁻⁸ s.
pub const MIN_DT: f64 = 1e-8;

/// The most steps `mpm run` takes on: a run whose estimate (its duration over the stable
/// step at the start) is larger is refused before stepping.
pub const MAX_STEPS: f64 = 1e8;

/// How far the live energy (kinetic + gravitational + elastic) may rise above the energy
/// brought in ([`Diagnostics::energy_in`]: the bodies' and the poured particles' at entry,
/// the work of the kinematic bodies and of tractions) before the run stops as unstable
/// ([`crate::Error::EnergyGrew`]): 10 % of the energy in play, the energy brought in plus
/// that of lifting every particle by one cell against gravity. Walls and contacts only remove
/// energy, so a stable run stays below.
pub const ENERGY_GUARD: f64 = 0.1;

macro_rules! delegate {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            AnySimulation::D2($s) => $e,
            AnySimulation::D3($s) => $e,
        }
    };
}

impl AnySimulation {
    pub fn new(scene: SceneConfig) -> Result<Self> {
        match scene.dim {
            2 => Ok(AnySimulation::D2(Simulation::new(scene)?)),
            3 => Ok(AnySimulation::D3(Simulation::new(scene)?)),
            d => Err(Error::invalid("dim", d, "must be 2 or 3")),
        }
    }
    pub fn dim(&self) -> usize {
        delegate!(self, s => s.scene().dim)
    }
    pub fn step(&mut self) -> Result<&Diagnostics> {
        delegate!(self, s => s.step())
    }
    pub fn step_at_most(&mut self, limit: f64) -> Result<&Diagnostics> {
        delegate!(self, s => s.step_at_most(limit))
    }
    pub fn advance(&mut self, duration: f64) -> Result<usize> {
        delegate!(self, s => s.advance(duration))
    }
    /// See [`Simulation::advance_until`].
    pub fn advance_until(
        &mut self,
        end: f64,
        go_on: impl FnMut(&Diagnostics) -> bool,
    ) -> Result<usize> {
        delegate!(self, s => s.advance_until(end, go_on))
    }
    pub fn diagnostics(&self) -> &Diagnostics {
        delegate!(self, s => s.diagnostics())
    }
    pub fn body_stats(&self) -> Vec<BodyStats> {
        delegate!(self, s => s.bodies().iter().map(|b| b.stats().clone()).collect())
    }
    pub fn scene(&self) -> &SceneConfig {
        delegate!(self, s => s.scene())
    }
    pub fn configure(&mut self, f: impl FnOnce(&mut SceneConfig)) -> Result<()> {
        delegate!(self, s => s.configure(f))
    }
    /// See [`Simulation::set_world`].
    pub fn set_world(&mut self, f: impl FnOnce(&mut SceneConfig)) -> Result<()> {
        delegate!(self, s => s.set_world(f))
    }
    /// See [`Simulation::set_materials`].
    pub fn set_materials(&mut self, changes: Vec<(usize, Material, Option<f64>)>) -> Result<()> {
        delegate!(self, s => s.set_materials(changes))
    }
    pub fn add_body(&mut self, body: BodyConfig) -> Result<usize> {
        delegate!(self, s => s.add_body(body))
    }
    pub fn remove_body(&mut self, i: usize) -> Result<()> {
        delegate!(self, s => s.remove_body(i))
    }
    pub(crate) fn record_appearance(&mut self, i: usize, t: Option<f64>) {
        delegate!(self, s => s.record_appearance(i, t))
    }
    /// See [`Simulation::next_appearance`].
    pub fn next_appearance(&self) -> Option<f64> {
        delegate!(self, s => s.next_appearance())
    }
    /// The number of bodies present (the scene's first ones; the rest are to come).
    pub fn bodies_present(&self) -> usize {
        delegate!(self, s => s.bodies().len())
    }
    pub fn clear(&mut self) {
        delegate!(self, s => s.clear())
    }
    /// See [`Simulation::pouring`].
    pub fn pouring(&self) -> bool {
        delegate!(self, s => s.pouring())
    }
    /// See [`Simulation::stop_pour`].
    pub fn stop_pour(&mut self, i: usize, t: f64) -> Result<f64> {
        delegate!(self, s => s.stop_pour(i, t))
    }
    /// See [`Spout::held`]: the layers body `i`'s spout has poured by time `t` and the duration
    /// that pours them, if body `i` is present and poured.
    pub fn pour_held(&self, i: usize, t: f64) -> Option<(u64, f64)> {
        delegate!(self, s => {
            let spout = s.bodies().get(i)?.spout()?;
            let duration = s.scene().bodies[i].pour.as_ref()?.duration;
            Some(spout.held(t, duration))
        })
    }
    /// Sleeping on with the rule for the scene's grid, or off (see
    /// [`Simulation::sleep_when_at_rest`]).
    pub fn set_sleeping_at_rest(&mut self, on: bool) {
        delegate!(self, s => if on { s.sleep_when_at_rest() } else { s.set_sleeping(None) })
    }
    /// Whether sleeping is on.
    pub fn sleeping(&self) -> bool {
        delegate!(self, s => s.sleeping().is_some())
    }
    /// How many particles sleep.
    pub fn asleep(&self) -> usize {
        delegate!(self, s => s.asleep())
    }
    pub fn time(&self) -> f64 {
        delegate!(self, s => s.time())
    }
    pub fn steps(&self) -> u64 {
        delegate!(self, s => s.steps())
    }
    pub fn stable_dt(&self) -> f64 {
        delegate!(self, s => s.stable_dt())
    }
    pub fn particle_count(&self) -> usize {
        delegate!(self, s => s.particles().len())
    }
    pub fn memory_bytes(&self) -> usize {
        delegate!(self, s => s.memory_bytes())
    }
    pub fn failure(&self) -> Option<&Error> {
        delegate!(self, s => s.failure())
    }
    /// Starts (or stops) accumulating per-pass wall-clock times.
    pub fn set_timings(&mut self, on: bool) {
        delegate!(self, s => s.timings = on.then(PassTimings::default))
    }
    pub fn timings(&self) -> Option<PassTimings> {
        delegate!(self, s => s.timings)
    }
}
