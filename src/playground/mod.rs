//! An interactive session over a simulation: the one driver of every front end. The browser
//! page drives it through `crate::wasm` (built for WebAssembly only), the terminal player (`mpm play`) directly, and any
//! other front end can. Browser-free: the wall clock is passed in.
//!
//! - Scenes are [`SceneConfig`] JSON, exactly as the CLI reads them.
//! - Live parameters are those of [`crate::params`]; each goes through
//!   [`AnySimulation::configure`], so it is validated exactly like a scene file and a rejected
//!   value leaves the state unchanged. A material parameter applies to every body of that
//!   model and to the preset that new bodies of that model are made of.
//! - The session is recorded as a [`Replay`] (parameters set, Clear, bodies dropped and sand
//!   poured with their simulated times), which a front end keeps and gives back to repeat it.
//! - The scene is sampled at a quality level ([`QUALITIES`]): the scene file as written
//!   (`fine`, what [`Playground::new`] gives) or coarser cells with enough particles to stay
//!   recognisable; bodies dropped take the level's particles per cell.
//! - Particle positions and a per-particle colour scalar are exposed as pointers and lengths
//!   (f32), so a front end can read them in place.

mod colours;
mod drops;
#[cfg(test)]
mod figures;
mod objects;
mod pours;
mod quality;
mod save;

pub use colours::ColourMode;
pub use drops::{DroppedBody, PouredBody, Refused, Replay};
pub use objects::{BunnyAssets, OBJECTS, ObjectInfo, ball_bunny, object_shape};
pub use pours::{
    POUR_CLEARANCE_CELLS, POUR_FILL_SHARE, POUR_HEIGHT, POUR_HEIGHT_SHARE, POUR_RADIUS_CELLS,
    POUR_SPEEDS, PourRates, PourSpeeds,
};
pub use quality::{
    ACCURACY, Accuracy, DEFAULT_QUALITY, MAX_PPC, QUALITIES, Quality, Resolution, SandCost,
    accuracy, body_ppc, resample, sample_at,
};

use crate::config::{BodyConfig, SceneConfig};
use crate::error::{Error, Result};
use crate::material::{Friction, Material, PqSurface, pq};
use crate::math::{Dim, Real, SymTensor};
use crate::measure::{Deposit, Footprints, deposits_any, principal_stresses};
use crate::params::{MODELS, Param, Target, model_index};
use crate::sim::{AnySimulation, Diagnostics, Simulation, cfl_time_step};
use colours::Colours;
use drops::Drops;
use serde::Serialize;
use std::collections::HashMap;

/// What one call of [`Playground::frame`] or [`Playground::step`] did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameReport {
    /// Time steps taken.
    pub substeps: usize,
    /// Simulated time advanced (s).
    pub sim_time: f64,
    /// The simulated time asked for (s): less than the frame's when a drop is due sooner.
    pub requested: f64,
    /// Wall-clock time spent stepping (ms).
    pub wall_ms: f64,
    /// Whether the wall-clock budget ran out before the requested time was simulated.
    pub fell_behind: bool,
    /// Mean wall-clock time of one step (ms), 0 when no step was taken.
    pub ms_per_step: f64,
    /// The time step the next step will take (s).
    pub stable_dt: f64,
    /// Drops whose time came but that the solver refused (left out of the session).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub refused: Vec<Refused>,
}

/// A prediction of what a parameter value would cost, for warnings before it is applied.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Prediction {
    /// Whether the value passes validation.
    pub valid: bool,
    /// The validation error, if any.
    pub error: String,
    /// The time step the value would give at the current particle speeds (s).
    pub stable_dt: f64,
    /// Steps per frame of `frame_time` seconds.
    pub substeps_per_frame: f64,
    /// Predicted simulated time per wall-clock time at the current cost per step
    /// (0 when unknown).
    pub realtime_ratio: f64,
}

/// A particle's stress in p–q space and the yield surface of its body's material.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StressPoint {
    pub index: usize,
    pub id: u32,
    pub body: usize,
    /// The material model's scene-file name.
    pub model: &'static str,
    /// Pressure p = −tr σ / 3 (Pa, compression positive).
    pub p: f64,
    /// Von Mises equivalent stress q = √(3 J2) (Pa).
    pub q: f64,
    pub plastic_strain: f64,
    pub position: [f64; 3],
    /// The material's yield surface in p–q space.
    pub surface: PqSurface,
    /// The principal stresses (Pa, compression positive, [`principal_stresses`]): in 2D the
    /// in-plane major and minor, then the out-of-plane one; in 3D sorted from the largest.
    pub principal: Vec<f64>,
    /// For a granular material: the friction angle φ (degrees) and the cohesion c (Pa) of its
    /// Mohr–Coulomb envelope, and for a Drucker–Prager cone the plane-strain angle φ_ps of its
    /// trace in a plane-strain Mohr plane ([`Friction`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mohr_coulomb: Option<Friction>,
}

/// What a parameter change costs ([`Playground::set_parameter_costed`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Costs {
    /// The prediction for the value set.
    pub prediction: Prediction,
    /// The prediction for the state before.
    pub before: Prediction,
}

/// A live parameter's new value for the presets and the bodies ([`Playground::edit`]).
struct Edit {
    /// The model's preset after the change (index in [`MODELS`], material, PIC/FLIP ratio),
    /// for a parameter of every body of a model.
    preset: Option<(usize, Material, Option<f64>)>,
    /// The bodies it changes: index, new material and PIC/FLIP ratio.
    bodies: Vec<(usize, Material, Option<f64>)>,
}

/// What a dropped object may measure, for a front end's size control (m).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SizeRange {
    /// What [`Playground::add_object`] accepts: two cells, up to the domain less two cells.
    pub allowed: [f64; 2],
    /// A range worth offering on a slider, and a default in it.
    pub offered: [f64; 2],
    pub default: f64,
}

/// Materials of new bodies, one per model of [`MODELS`], with their PIC/FLIP ratios.
#[derive(Clone, Debug, PartialEq)]
struct Presets {
    materials: Vec<Material>,
    flip: Vec<Option<f64>>,
}

impl Presets {
    /// The models' presets, overridden by the first body of each model in `scene`.
    fn from_scene(scene: &SceneConfig) -> Self {
        let (materials, flip) = MODELS
            .iter()
            .map(
                |m| match scene.bodies.iter().find(|b| b.material.kind() == m.id) {
                    Some(b) => (b.material.clone(), b.flip),
                    None => (m.preset(), None),
                },
            )
            .unzip();
        Presets { materials, flip }
    }
}

/// The files a scene references (meshes, vertex lists; paths relative to the scene file).
pub fn asset_paths(scene_json: &str) -> Result<Vec<String>> {
    Ok(SceneConfig::from_json(scene_json)?.asset_paths())
}

/// An interactive simulation with its presets, parameter overrides, drops and colour buffer.
#[derive(Clone, Debug)]
pub struct Playground {
    sim: AnySimulation,
    /// The scene as loaded, before re-sampling (for reset and other quality levels).
    initial: SceneConfig,
    quality: &'static Quality,
    /// The resolution `initial` was sampled at.
    resolution: Resolution,
    presets: Presets,
    /// Parameters changed since the scene was loaded, in the order they were last set.
    overrides: Vec<(String, f64)>,
    drops: Drops,
    colours: Colours,
    /// Smoothed wall-clock cost of one step (ms), for predictions.
    ms_per_step: f64,
    bunny: BunnyAssets,
    /// Where each particle entered (for the run-outs of [`Playground::measures`]).
    footprints: Footprints,
}

impl Playground {
    /// A playground over a scene given as JSON (the scene-file format) that references no
    /// file.
    pub fn from_json(text: &str) -> Result<Self> {
        Self::from_json_with_assets(text, &HashMap::new())
    }

    /// A playground over a scene given as JSON, with the text of each file it references
    /// (see [`asset_paths`]) keyed by its path as written in the scene.
    pub fn from_json_with_assets(text: &str, assets: &HashMap<String, String>) -> Result<Self> {
        Self::load(text, assets, Quality::fine().id)
    }

    /// Uses the shipped bunny's mesh and silhouette for dropped bunnies.
    pub fn set_bunny(&mut self, bunny: BunnyAssets) {
        self.bunny = bunny;
    }

    /// A playground over a scene given as JSON with the texts of the files it references (see
    /// [`Self::from_json_with_assets`]), sampled at quality level `quality`.
    pub fn load(text: &str, assets: &HashMap<String, String>, quality: &str) -> Result<Self> {
        let q = Quality::find(quality)?;
        let mut scene = SceneConfig::from_json(text)?;
        scene.resolve_assets(|path| {
            assets.get(path).cloned().ok_or_else(|| Error::Io {
                path: path.to_string(),
                message: "not provided (fetch it beside the scene file)".into(),
            })
        })?;
        Self::with_quality(scene, q)
    }

    /// A playground over a scene as written (the `fine` quality level).
    pub fn new(scene: SceneConfig) -> Result<Self> {
        Self::with_quality(scene, Quality::fine())
    }

    /// A playground over a scene sampled at quality level `q`.
    pub fn with_quality(scene: SceneConfig, q: &'static Quality) -> Result<Self> {
        let (sampled, resolution) = sample_at(&scene, q)?;
        let sim = AnySimulation::new(sampled)?;
        let mut pg = Playground {
            presets: Presets::from_scene(&scene),
            initial: scene,
            quality: q,
            resolution,
            sim,
            overrides: Vec::new(),
            drops: Drops::default(),
            colours: Colours::default(),
            ms_per_step: 0.0,
            bunny: BunnyAssets::default(),
            footprints: Footprints::default(),
        };
        pg.set_sleeping(true);
        pg.footprints.update_any(&pg.sim);
        pg.update_colours(ColourMode::Body);
        Ok(pg)
    }

    /// An empty box to drop things into: 2 m × 1 m (× 1 m), cell size 2.5 cm, rough floor.
    pub fn sandbox_scene(dim: usize) -> SceneConfig {
        let size = [2.0, 1.0, 1.0];
        let mut scene = SceneConfig::new(dim, &size[..dim.clamp(2, 3)], 0.025);
        scene.name = "sandbox".into();
        scene.boundary.friction = 0.5;
        scene
    }

    pub fn simulation(&self) -> &AnySimulation {
        &self.sim
    }
    pub fn dim(&self) -> usize {
        self.sim.dim()
    }
    pub fn scene(&self) -> &SceneConfig {
        self.sim.scene()
    }
    pub fn diagnostics(&self) -> &Diagnostics {
        self.sim.diagnostics()
    }
    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.sim.time()
    }
    pub fn particle_count(&self) -> usize {
        self.sim.particle_count()
    }
    /// Bodies in the scene, those to come included.
    pub fn body_count(&self) -> usize {
        self.sim.scene().bodies.len()
    }
    /// The error that stopped the simulation, if any (a reset or clear starts again).
    pub fn failure(&self) -> Option<String> {
        self.sim.failure().map(|e| e.to_string())
    }

    /// Switches sleeping on (material at rest stops being stepped until something touches it,
    /// with the rule for the scene's grid, [`Simulation::sleep_when_at_rest`]) or off (everything
    /// wakes). On by default.
    pub fn set_sleeping(&mut self, on: bool) {
        self.sim.set_sleeping_at_rest(on);
    }
    /// Whether material at rest sleeps.
    pub fn sleeping(&self) -> bool {
        self.sim.sleeping()
    }
    /// How many particles sleep.
    pub fn asleep(&self) -> usize {
        self.sim.asleep()
    }

    /// Advances by up to `sim_time` seconds of simulated time, stopping early when
    /// `budget_ms` of wall-clock time (read from `now_ms`) has been spent, or at the time of the
    /// next drop to come, which then lands. An empty box with no body to come does not step (its
    /// time stands still), and every drop to come lands in it. Stops with an error if the
    /// simulation goes non-finite.
    pub fn frame(
        &mut self,
        sim_time: f64,
        budget_ms: f64,
        mut now_ms: impl FnMut() -> f64,
    ) -> Result<FrameReport> {
        for (name, v) in [("sim_time", sim_time), ("budget_ms", budget_ms)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(name, v, "must be a finite number >= 0"));
            }
        }
        let start = now_ms();
        let requested = match self.drops.next_time() {
            Some(t) => sim_time.min((t - self.drop_clock()).max(0.0)),
            None => sim_time,
        };
        let mut report = FrameReport {
            requested,
            sim_time: requested,
            ..Default::default()
        };
        if !self.idle() {
            let t0 = self.sim.time();
            let end = t0 + requested;
            report.substeps = self
                .sim
                .advance_until(end, |_| now_ms() - start < budget_ms)?;
            report.sim_time = self.sim.time() - t0;
            report.fell_behind = self.sim.time() < end - 1e-12 * end.abs().max(1.0);
        }
        report.wall_ms = now_ms() - start;
        self.finish(&mut report);
        Ok(report)
    }

    /// One time step of the adaptive size (then the drops whose time came land).
    pub fn step(&mut self, mut now_ms: impl FnMut() -> f64) -> Result<FrameReport> {
        let start = now_ms();
        let t0 = self.sim.time();
        self.sim.step()?;
        let mut report = FrameReport {
            substeps: 1,
            sim_time: self.sim.time() - t0,
            wall_ms: now_ms() - start,
            ..Default::default()
        };
        self.finish(&mut report);
        Ok(report)
    }

    /// The bookkeeping after stepping: the cost per step, the next time step, the drops due.
    fn finish(&mut self, report: &mut FrameReport) {
        if report.substeps > 0 {
            report.ms_per_step = report.wall_ms / report.substeps as f64;
            self.ms_per_step = if self.ms_per_step > 0.0 {
                0.8 * self.ms_per_step + 0.2 * report.ms_per_step
            } else {
                report.ms_per_step
            };
        }
        report.refused = self.land_due_drops();
        report.stable_dt = self.sim.stable_dt();
        self.footprints.update_any(&self.sim);
    }

    /// The parameter `target` (called `name`) = `value` for the presets and the bodies,
    /// without applying it: the preset it changes, checked, and the bodies it changes with
    /// their new materials and PIC/FLIP ratios (checked where they are applied,
    /// [`AnySimulation::set_materials`]). Nothing for a world parameter.
    fn edit(&self, target: &Target, name: &str, value: f64) -> Result<Edit> {
        let p = target.param;
        let mut preset = None;
        if let (Some(m), None) = (p.model, target.body) {
            let mut material = self.presets.materials[m].clone();
            let mut flip = self.presets.flip[m];
            p.set_material(&mut material, &mut flip, value);
            p.validate_preset(name, &material, flip)?;
            preset = Some((m, material, flip));
        }
        let scene = self.sim.scene();
        let bodies = target
            .bodies(scene, value, false)?
            .into_iter()
            .map(|i| {
                let b = &scene.bodies[i];
                let (mut material, mut flip) = (b.material.clone(), b.flip);
                p.set_material(&mut material, &mut flip, value);
                (i, material, flip)
            })
            .collect();
        Ok(Edit { preset, bodies })
    }

    /// Sets a live parameter (see [`crate::params`] for the names), validated like a scene
    /// file; on error the state is unchanged.
    pub fn set_parameter(&mut self, name: &str, value: f64) -> Result<()> {
        self.apply(&Target::parse(name)?, name, value)
    }

    /// [`Playground::set_parameter`], returning what the new value costs and what the old one
    /// did ([`Playground::predict`]), for a front end's warnings: one parse and one check of
    /// the name and value.
    pub fn set_parameter_costed(
        &mut self,
        name: &str,
        value: f64,
        frame_time: f64,
    ) -> Result<Costs> {
        let target = Target::parse(name)?;
        let before = self.cost(self.sim.scene(), self.wave_speed(None), frame_time);
        self.apply(&target, name, value)?;
        let prediction = self.cost(self.sim.scene(), self.wave_speed(None), frame_time);
        Ok(Costs { prediction, before })
    }

    /// Applies the parameter `target` (called `name`) = `value`: the world's setting, or the
    /// materials of the bodies it changes (only those are built again) and its preset.
    fn apply(&mut self, target: &Target, name: &str, value: f64) -> Result<()> {
        if target.param.model.is_none() {
            self.sim.set_world(|s| {
                target.param.set_in_scene(s, value);
            })?;
        } else {
            let edit = self.edit(target, name, value)?;
            self.sim.set_materials(edit.bodies)?;
            if let Some((m, material, flip)) = edit.preset {
                self.presets.materials[m] = material;
                self.presets.flip[m] = flip;
            }
        }
        if self.sleeping() {
            // The rule follows the grid and gravity (a world change woke everything; a material
            // change, the bodies it can move: `Simulation::set_materials`).
            self.set_sleeping(true);
        }
        self.overrides.retain(|(n, _)| n != name);
        self.overrides.push((name.to_string(), value));
        Ok(())
    }

    /// The value of a live parameter: the body's, or the first body of that model's, else the
    /// preset's.
    pub fn parameter(&self, name: &str) -> Result<f64> {
        let target = Target::parse(name)?;
        let scene = self.sim.scene();
        let p = target.param;
        if let Some(i) = target.body {
            let b = scene.bodies.get(i).filter(|b| p.applies_to(b));
            return b
                .and_then(|b| p.material_value(&b.material, b.flip))
                .ok_or_else(|| Error::invalid("parameter", name, "no such body of that model"));
        }
        Ok(p.value_in_scene(scene)
            .or_else(|| {
                let m = p.model?;
                p.material_value(&self.presets.materials[m], self.presets.flip[m])
            })
            .unwrap_or(0.0))
    }

    /// Every live parameter with its current value.
    pub fn parameters(&self) -> Vec<(String, f64)> {
        Param::all()
            .map(|p| {
                let name = p.name();
                let v = self.parameter(&name).unwrap_or(0.0);
                (name, v)
            })
            .collect()
    }

    /// Parameters changed since the scene was loaded, in the order they were last set.
    pub fn overrides(&self) -> &[(String, f64)] {
        &self.overrides
    }

    /// What setting `name` = `value` would cost, without applying it: the time step at the
    /// current particle speeds, the steps per frame of `frame_time` seconds and, from the
    /// measured cost of a step, the ratio of simulated to wall-clock time.
    pub fn predict(&self, name: &str, value: f64, frame_time: f64) -> Prediction {
        let checked = Target::parse(name).and_then(|target| {
            if target.param.model.is_none() {
                let mut world = self.sim.scene().world();
                target.param.set_in_scene(&mut world, value);
                world.validate_world()?;
                return Ok(self.cost(&world, self.wave_speed(None), frame_time));
            }
            let edit = self.edit(&target, name, value)?;
            for (i, material, flip) in &edit.bodies {
                BodyConfig::check_material(&format!("bodies[{i}]"), material, *flip)?;
            }
            Ok(self.cost(self.sim.scene(), self.wave_speed(Some(&edit)), frame_time))
        });
        checked.unwrap_or_else(|e| Prediction {
            error: e.to_string(),
            ..Prediction::default()
        })
    }

    /// The largest wave speed at the reference density of the bodies' materials, or of the
    /// presets when there is no body (what the next dropped body would need), after `edit`.
    fn wave_speed(&self, edit: Option<&Edit>) -> f64 {
        let bodies = &self.sim.scene().bodies;
        let edited = |i: usize, m: &'_ Material| {
            let changed = edit.and_then(|e| e.bodies.iter().find(|(j, ..)| *j == i));
            changed.map_or(m.wave_speed(), |(_, m, _)| m.wave_speed())
        };
        if bodies.is_empty() {
            let preset = edit.and_then(|e| e.preset.as_ref());
            (0..self.presets.materials.len())
                .map(|m| match preset {
                    Some((p, material, _)) if *p == m => material.wave_speed(),
                    _ => self.presets.materials[m].wave_speed(),
                })
                .fold(0.0, f64::max)
        } else {
            (0..bodies.len())
                .map(|i| edited(i, &bodies[i].material))
                .fold(0.0, f64::max)
        }
    }

    /// The cost of stepping with the world settings of `world` and the wave speed `c`.
    fn cost(&self, world: &SceneConfig, c: f64, frame_time: f64) -> Prediction {
        let mut out = Prediction {
            valid: true,
            ..Prediction::default()
        };
        let speed = c + self.sim.diagnostics().max_speed;
        let g = world
            .gravity_vector()
            .iter()
            .map(|g| g * g)
            .sum::<f64>()
            .sqrt();
        out.stable_dt = cfl_time_step(world.cfl, world.cell_size, speed, g, world.max_dt);
        out.substeps_per_frame = (frame_time / out.stable_dt).ceil();
        if self.ms_per_step > 0.0 && out.substeps_per_frame > 0.0 {
            // Cost per step scales with the particle count, not with the parameter.
            out.realtime_ratio =
                frame_time / (out.substeps_per_frame * self.ms_per_step * 1e-3).max(1e-9);
        }
        out
    }

    /// The sizes a dropped object may have in this scene.
    pub fn size_range(&self) -> SizeRange {
        let scene = self.sim.scene();
        let h = scene.cell_size;
        let smallest = scene
            .domain
            .size
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        let offered = [(3.0 * h).max(0.05 * smallest), 0.6 * smallest];
        SizeRange {
            allowed: [2.0 * h, smallest - 2.0 * h],
            offered,
            default: (0.25 * smallest).clamp(offered[0], offered[1]),
        }
    }

    /// Checks the size of an object to drop (m).
    pub fn check_size(&self, size: f64) -> Result<()> {
        let [lo, hi] = self.size_range().allowed;
        if size.is_finite() && size >= lo && size <= hi {
            return Ok(());
        }
        Err(Error::invalid(
            "size",
            size,
            format!(
                "must be in [{lo}, {hi}] (m): at least two cells, and the object must fit in the domain"
            ),
        ))
    }

    /// Adds a body of kind `object` (`bunny`, `ball`, `box`) made of the preset material
    /// `model` (`elastic`, `von_mises`, `drucker_prager`, `mohr_coulomb`), `size` metres tall, centred at
    /// `center` (moved inside the domain if it pokes out), moving at `velocity`. Returns the
    /// new body's index. Not recorded in the session (see [`Self::drop_at`]); its `appear_at`
    /// is the drop clock's time, for [`Self::saved_scene`].
    pub fn add_object(
        &mut self,
        object: &str,
        model: &str,
        center: &[f64],
        velocity: &[f64],
        size: f64,
    ) -> Result<usize> {
        let body = self.object_body(object, model, center, velocity, size)?;
        self.add_now(body, self.drop_clock())
    }

    /// Adds a body now, and records `t`, its time on the drop clock (no later than now), as its
    /// `appear_at` (none at 0): the time a saved scene gives it.
    fn add_now(&mut self, mut body: BodyConfig, t: f64) -> Result<usize> {
        body.appear_at = None;
        let i = self.sim.add_body(body)?;
        let clock = self.drop_clock();
        let t = if t <= clock + 1e-9 { t } else { clock };
        self.sim.record_appearance(i, (t > 0.0).then_some(t));
        Ok(i)
    }

    /// The body [`Self::add_object`] adds.
    fn object_body(
        &self,
        object: &str,
        model: &str,
        center: &[f64],
        velocity: &[f64],
        size: f64,
    ) -> Result<BodyConfig> {
        let m = model_index(model)?;
        let dim = self.dim();
        crate::geometry::check_vector("center", center, dim, "m")?;
        crate::geometry::check_vector("velocity", velocity, dim, "m/s")?;
        self.check_size(size)?;
        let domain = self.sim.scene().domain.size.clone();
        let h = self.sim.scene().cell_size;
        let mut c = [0.0; 3];
        c[..dim].copy_from_slice(center);
        let shape = object_shape(object, dim, c, size, &self.bunny)?;
        // Keep the object one cell inside the walls.
        let b = shape.bounds(dim);
        for a in 0..dim {
            let lo = h - b.min[a];
            let hi = domain[a] - h - b.max[a];
            c[a] += lo.max(0.0) + hi.min(0.0);
        }
        let shape = object_shape(object, dim, c, size, &self.bunny)?;
        let mut body = BodyConfig::new(object, shape, self.presets.materials[m].clone())
            .with_velocity(velocity);
        body.flip = self.presets.flip[m];
        // The quality level's particles per cell, more for a small body (to keep its shape).
        body.particles_per_cell =
            body_ppc(self.quality, dim, self.resolution.particles_per_cell, |p| {
                let mut b = body.clone();
                b.particles_per_cell = p;
                Ok(b.sample("body", dim, h)?.0.len())
            })?;
        Ok(body)
    }

    /// Drops an object aimed at `point` (3D: a point on the floor, its x and z count; 2D: a
    /// point in the box), falling at `speed` (m/s): above whatever lies there, at least a gap
    /// of two cells or 5 % of the height (in 3D, from at least 55 % of the height), and below
    /// the ceiling. Recorded in the session with its figures rounded as
    /// [`DroppedBody::rounded`] says, so that a replay drops the same body. Returns the new
    /// body's index.
    pub fn drop_at(
        &mut self,
        object: &str,
        model: &str,
        point: &[f64],
        speed: f64,
        size: f64,
    ) -> Result<usize> {
        let dim = self.dim();
        crate::geometry::check_vector("point", point, dim, "m")?;
        crate::error::check_non_negative("speed", speed, "m/s")?;
        self.check_size(size)?;
        let (h, height) = (self.scene().cell_size, self.scene().domain.size[1]);
        let z = if dim == 3 { point[2] } else { 0.0 };
        let surface = self.surface_height(point[0], z, 0.6 * size);
        let gap = (2.0 * h).max(0.05 * height);
        let lowest = surface + 0.5 * size + gap;
        let y = if dim == 3 {
            lowest.max(0.55 * height)
        } else {
            lowest.max(point[1])
        }
        .min(height - h - 0.5 * size);
        let mut centre = point.to_vec();
        centre[1] = y;
        let mut velocity = vec![0.0; dim];
        velocity[1] = -speed;
        let clock = self.drop_clock();
        let d = DroppedBody::rounded(clock, object, model, size, &centre, &velocity);
        let body = self.object_body(&d.object, &d.material, &d.centre, &d.velocity, d.size)?;
        let i = self.add_now(body, d.t)?;
        self.drops.record(d, clock);
        Ok(i)
    }

    /// Adds a body as written in a scene file (not recorded in the session).
    pub fn add_body(&mut self, body: BodyConfig) -> Result<usize> {
        self.sim.add_body(body)
    }

    /// Simulated time since the scene started or was cleared: the clock of the drops (s).
    pub fn drop_clock(&self) -> f64 {
        self.sim.time() - self.drops.origin
    }

    /// Whether the box is empty with nothing to come (no body, no spout's layer): then its
    /// time stands still.
    fn idle(&self) -> bool {
        self.particle_count() == 0 && self.sim.next_appearance().is_none() && !self.sim.pouring()
    }

    /// Lands the drops and starts the pours whose time has come (all of them in an idle box,
    /// where time does not run). One the solver refuses is left out of the session and returned
    /// with its message.
    fn land_due_drops(&mut self) -> Vec<Refused> {
        let mut refused = Vec::new();
        while let Some(t) = self.drops.next_time() {
            if t > self.drop_clock() + 1e-9 && !self.idle() {
                break;
            }
            if self.drops.pour_next() {
                let p = self.drops.pours[self.drops.next_pour].clone();
                let body = self.scheduled_pour_body(&p);
                match body.and_then(|b| self.add_now(b, p.t)) {
                    Ok(_) => {
                        self.drops.pours[self.drops.next_pour].applied_at = Some(self.drop_clock());
                        self.drops.next_pour += 1;
                    }
                    Err(e) => {
                        self.drops.pours.remove(self.drops.next_pour);
                        refused.push(Refused {
                            drop: None,
                            pour: Some(p),
                            error: e.to_string(),
                        });
                    }
                }
                continue;
            }
            let d = self.drops.list[self.drops.next].clone();
            let body = self.object_body(&d.object, &d.material, &d.centre, &d.velocity, d.size);
            match body.and_then(|b| self.add_now(b, d.t)) {
                Ok(_) => {
                    self.drops.list[self.drops.next].applied_at = Some(self.drop_clock());
                    self.drops.next += 1;
                }
                Err(e) => {
                    self.drops.list.remove(self.drops.next);
                    refused.push(Refused {
                        drop: Some(d),
                        pour: None,
                        error: e.to_string(),
                    });
                }
            }
        }
        refused
    }

    /// Repeats a session on this playground: sets its parameters in order, clears the scene if
    /// it was cleared, and schedules its drops and pours (those due now land or start at once,
    /// the others when the simulation reaches their times; a pour running here stops first).
    /// Returns the parameters refused (with their messages) and the drops and pours refused so
    /// far; everything else applies.
    pub fn replay(&mut self, replay: Replay) -> (Vec<String>, Vec<Refused>) {
        self.stop_pour();
        let mut rejected = Vec::new();
        if let Some(q) = replay.quality.as_deref().filter(|&q| q != self.quality.id) {
            match Quality::find(q).and_then(|q| Self::with_quality(self.initial.clone(), q)) {
                Ok(mut next) => {
                    next.bunny = std::mem::take(&mut self.bunny);
                    next.set_sleeping(self.sleeping());
                    *self = next;
                }
                Err(e) => rejected.push(e.to_string()),
            }
        }
        rejected.extend(
            replay
                .params
                .iter()
                .filter_map(|(name, value)| self.set_parameter(name, *value).err())
                .map(|e| e.to_string()),
        );
        if replay.cleared {
            self.clear();
        }
        self.drops.schedule(replay.drops, replay.pours);
        (rejected, self.land_due_drops())
    }

    /// The session so far, as [`Self::replay`] takes it.
    pub fn session(&self) -> Replay {
        Replay {
            quality: Some(self.quality.id.to_string()),
            params: self.overrides.clone(),
            cleared: self.drops.cleared,
            drops: self.drops.list.clone(),
            pours: self.session_pours(),
        }
    }

    /// Removes every body; the drops and pours are forgotten (a pour running ends) and their
    /// clock starts again.
    pub fn clear(&mut self) {
        self.sim.clear();
        self.footprints.clear();
        self.colours.values.clear();
        self.drops.forget(self.sim.time());
        self.drops.cleared = true;
    }

    /// Reloads the scene and applies the parameter overrides again; the drops, the pours and a
    /// Clear are forgotten.
    pub fn reset(&mut self) -> Result<()> {
        let mut next = Playground::with_quality(self.initial.clone(), self.quality)?;
        for (name, value) in &self.overrides {
            // Each was valid when it was set; one that no longer applies is dropped.
            let _ = next.set_parameter(name, *value);
        }
        next.ms_per_step = self.ms_per_step;
        next.bunny = std::mem::take(&mut self.bunny);
        next.set_sleeping(self.sleeping());
        *self = next;
        Ok(())
    }

    /// `scene` (the simulated one, or built from it) at the resolution of the scene as loaded:
    /// its cell size and time-step cap, its bodies' particles per cell, the default for bodies
    /// dropped.
    fn as_written(&self, scene: &mut SceneConfig) {
        scene.cell_size = self.initial.cell_size;
        scene.max_dt = self.initial.max_dt;
        let own = if self.drops.cleared {
            &[][..]
        } else {
            &self.initial.bodies[..]
        };
        // The scene format's default, as a body dropped is written.
        let dropped = BodyConfig::new(
            "",
            crate::Shape::ball(&[0.0; 2], 1.0),
            Material::elastic(1.0, 0.0, 1.0),
        )
        .particles_per_cell;
        for (i, b) in scene.bodies.iter_mut().enumerate() {
            b.particles_per_cell = own.get(i).map_or(dropped, |b| b.particles_per_cell);
        }
    }

    /// The quality level and the resolution the scene is sampled at.
    pub fn quality(&self) -> &Resolution {
        &self.resolution
    }

    /// Samples the scene again at quality level `quality` and starts it again with the session
    /// so far: the parameters set, the Clear, and the drops and pours at their times (those the
    /// new resolution refuses are returned; a pour running is replayed as far as it ran, and
    /// runs no more). An unknown level is an error, the state unchanged.
    pub fn set_quality(&mut self, quality: &str) -> Result<Vec<Refused>> {
        let q = Quality::find(quality)?;
        let mut session = self.session();
        session.quality = None;
        let mut next = Playground::with_quality(self.initial.clone(), q)?;
        next.bunny = std::mem::take(&mut self.bunny);
        next.set_sleeping(self.sleeping());
        let (_, refused) = next.replay(session);
        *self = next;
        Ok(refused)
    }

    /// Reloads the scene as loaded, forgetting the parameter overrides too.
    pub fn reset_to_scene(&mut self) -> Result<()> {
        self.overrides.clear();
        self.reset()
    }

    /// The highest particle (its y, m) within horizontal distance `radius` of `x` (and `z`),
    /// or 0 when there is none: where a dropped object would land.
    pub fn surface_height(&self, x: f64, z: f64, radius: f64) -> f64 {
        fn top<D: Dim>(s: &Simulation<D>, x: f64, z: f64, r: f64) -> f64 {
            let mut y_max = 0.0f64;
            for p in &s.particles().x {
                let a = xyz::<D>(*p);
                let dx = a[0] - x;
                let dz = if D::DIM == 3 { a[2] - z } else { 0.0 };
                if dx * dx + dz * dz <= r * r {
                    y_max = y_max.max(a[1]);
                }
            }
            y_max
        }
        match &self.sim {
            AnySimulation::D2(s) => top(s, x, z, radius),
            AnySimulation::D3(s) => top(s, x, z, radius),
        }
    }

    /// Floats from one particle's position to the next: 2 in 2D; in 3D the solver keeps
    /// SIMD-aligned vectors (x, y, z and one unused float), so 4.
    pub fn positions_stride(&self) -> usize {
        use std::mem::size_of;
        match &self.sim {
            AnySimulation::D2(_) => size_of::<<crate::D2 as Dim>::Vector>() / size_of::<Real>(),
            AnySimulation::D3(_) => size_of::<<crate::D3 as Dim>::Vector>() / size_of::<Real>(),
        }
    }

    /// Address of the particle positions: [`Self::positions_stride`] f32 per particle, the
    /// first `dim` of which are x, y (, z).
    pub fn positions_ptr(&self) -> *const f32 {
        match &self.sim {
            AnySimulation::D2(s) => s.particles().x.as_ptr().cast(),
            AnySimulation::D3(s) => s.particles().x.as_ptr().cast(),
        }
    }
    /// Number of f32 in the positions buffer.
    pub fn positions_len(&self) -> usize {
        self.particle_count() * self.positions_stride()
    }
    /// Address of the colour scalars (one f32 per particle, after [`Self::update_colours`]).
    pub fn colours_ptr(&self) -> *const f32 {
        self.colours.values.as_ptr()
    }
    pub fn colours_len(&self) -> usize {
        self.colours.values.len()
    }
    pub fn colours(&self) -> &[f32] {
        &self.colours.values
    }
    /// The range the colour map spans: [0, body count) for bodies, [0, 1] for yield states,
    /// else [0, the 99th percentile].
    pub fn colour_range(&self) -> [f32; 2] {
        self.colours.range
    }

    /// Recomputes the per-particle colour scalar.
    pub fn update_colours(&mut self, mode: ColourMode) {
        match &self.sim {
            AnySimulation::D2(s) => self.colours.update(s, mode),
            AnySimulation::D3(s) => self.colours.update(s, mode),
        }
    }

    /// The particle whose stable id is `id`, if it still exists.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        match &self.sim {
            AnySimulation::D2(s) => s.particles().id.iter().position(|&i| i == id),
            AnySimulation::D3(s) => s.particles().id.iter().position(|&i| i == id),
        }
    }

    /// The particle nearest `point` (m), if there is any: a front end that picked a particle in
    /// a frame drawn earlier finds it again by where it was (particles are reordered for
    /// locality between steps).
    pub fn nearest_particle(&self, point: &[f64]) -> Result<Option<usize>> {
        crate::geometry::check_vector("point", point, self.dim(), "m")?;
        fn nearest<D: Dim>(s: &Simulation<D>, p: &[f64]) -> Option<usize> {
            let d2 = |x: &D::Vector| {
                (0..D::DIM)
                    .map(|a| (x[a] as f64 - p[a]).powi(2))
                    .sum::<f64>()
            };
            let x = &s.particles().x;
            (0..x.len()).min_by(|&i, &j| d2(&x[i]).total_cmp(&d2(&x[j])))
        }
        Ok(match &self.sim {
            AnySimulation::D2(s) => nearest(s, point),
            AnySimulation::D3(s) => nearest(s, point),
        })
    }

    /// The measures of each sand body as it stands ([`crate::measure::deposits`]): the angle
    /// of its heap's flanks, its run-out from where it entered (a body is recorded at the end
    /// of the frame it entered in), and for a column the experiments' run-out and height.
    pub fn measures(&mut self) -> Vec<Deposit> {
        self.footprints.update_any(&self.sim);
        deposits_any(&self.sim, &self.footprints)
    }

    /// The stress of particle `index` in p–q space, with its body's yield surface.
    pub fn stress_point(&self, index: usize) -> Result<StressPoint> {
        if index >= self.particle_count() {
            return Err(Error::invalid(
                "particle",
                index,
                format!("must be below the particle count {}", self.particle_count()),
            ));
        }
        Ok(match &self.sim {
            AnySimulation::D2(s) => stress_point(s, index),
            AnySimulation::D3(s) => stress_point(s, index),
        })
    }
}

/// A position as three components (z = 0 in 2D).
fn xyz<D: Dim>(v: D::Vector) -> [f64; 3] {
    std::array::from_fn(|a| if a < D::DIM { v[a] as f64 } else { 0.0 })
}

fn stress_point<D: Dim>(s: &Simulation<D>, i: usize) -> StressPoint {
    let p = s.particles();
    let body = s
        .bodies()
        .iter()
        .position(|b| b.range().contains(&i))
        .unwrap_or(0);
    let material = &s.scene().bodies[body].material;
    // sand's stress as recovered on the grid (crate::recovery), what its nodes carry
    let stress = crate::recovery::shown_stress_of(s, i);
    let (pressure, q) = pq(stress);
    StressPoint {
        index: i,
        id: p.id[i],
        body,
        model: material.kind(),
        p: pressure,
        q,
        plastic_strain: p.plastic_strain[i] as f64,
        position: xyz::<D>(p.x[i]),
        surface: material.pq_surface(p.plastic_strain[i] as f64),
        principal: principal_stresses(
            &stress
                .components()
                .iter()
                .map(|&c| c as f64)
                .collect::<Vec<_>>(),
        ),
        mohr_coulomb: material.behaviour().friction(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Shape;

    fn sand_scene(dim: usize) -> SceneConfig {
        let mut s = Playground::sandbox_scene(dim);
        let (lo, hi) = ([0.2, 0.0, 0.3], [0.6, 0.4, 0.7]);
        s.bodies.push(BodyConfig::new(
            "sand",
            Shape::cuboid(&lo[..dim], &hi[..dim]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0),
        ));
        s
    }

    fn clock() -> impl FnMut() -> f64 {
        let t0 = std::time::Instant::now();
        move || t0.elapsed().as_secs_f64() * 1e3
    }

    #[test]
    fn frames_advance_within_the_budget() {
        for dim in [2, 3] {
            let mut pg = Playground::new(sand_scene(dim)).unwrap();
            let r = pg.frame(1.0 / 60.0, 1e6, clock()).unwrap();
            assert!(r.substeps > 1 && !r.fell_behind, "{r:?}");
            assert!((r.sim_time - 1.0 / 60.0).abs() < 1e-9);
            let r = pg.frame(1.0, 0.0, clock()).unwrap();
            assert!(r.fell_behind && r.substeps == 0, "{r:?}");
            assert!(pg.frame(f64::NAN, 1.0, clock()).is_err());
        }
    }

    #[test]
    fn parameters_are_validated_like_scene_files() {
        let mut pg = Playground::new(sand_scene(3)).unwrap();
        pg.set_parameter("drucker_prager.friction_angle", 25.0)
            .unwrap();
        assert_eq!(pg.parameter("drucker_prager.friction_angle").unwrap(), 25.0);
        let before = pg.scene().clone();
        let e = pg
            .set_parameter("drucker_prager.friction_angle", 95.0)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "material.drucker_prager.friction_angle = 95: must be in [0, 90) (degrees)"
        );
        assert_eq!(pg.scene(), &before);
        let e = pg.set_parameter("cfl", f64::NAN).unwrap_err().to_string();
        assert_eq!(e, "cfl = NaN: must be in [0.001, 1]");
        let e = pg
            .set_parameter("drucker_prager.colour", 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("parameter = drucker_prager.colour: must be one of gravity"));
        // ψ ≤ φ of each body: the body's own check names it.
        let e = pg
            .set_parameter("drucker_prager.dilatancy_angle", 30.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("material.drucker_prager.dilatancy_angle = 30"),
            "{e}"
        );
        assert_eq!(pg.scene(), &before);
        pg.set_parameter("gravity", 3.0).unwrap();
        assert_eq!(pg.scene().gravity_vector(), vec![0.0, -3.0, 0.0]);
        // Parameters of a model no body has change the preset.
        pg.set_parameter("von_mises.yield_stress", 1234.0).unwrap();
        assert_eq!(pg.parameter("von_mises.yield_stress").unwrap(), 1234.0);
        let i = pg
            .add_object("box", "von_mises", &[1.0, 0.5, 0.5], &[0.0, 0.0, 0.0], 0.2)
            .unwrap();
        assert_eq!(
            pg.scene().bodies[i].material,
            Material::von_mises(1.0e5, 0.3, 1000.0, 1234.0)
        );
        assert_eq!(
            pg.overrides()
                .iter()
                .map(|o| o.0.as_str())
                .collect::<Vec<_>>(),
            [
                "drucker_prager.friction_angle",
                "gravity",
                "von_mises.yield_stress"
            ]
        );
        pg.reset().unwrap();
        assert_eq!(pg.body_count(), 1);
        assert_eq!(pg.parameter("gravity").unwrap(), 3.0);
        assert_eq!(pg.parameter("drucker_prager.friction_angle").unwrap(), 25.0);
    }

    #[test]
    fn objects_are_kept_inside_and_coloured() {
        for dim in [2, 3] {
            let live = Quality::find("live").unwrap();
            let mut pg = Playground::with_quality(Playground::sandbox_scene(dim), live).unwrap();
            for (k, object) in ["bunny", "ball", "box"].into_iter().enumerate() {
                let c = [0.05 + k as f64, 0.95, 0.5];
                pg.add_object(object, MODELS[k].id, &c[..dim], &[0.0; 3][..dim], 0.3)
                    .unwrap();
            }
            assert_eq!(pg.body_count(), 3);
            let n = pg.particle_count();
            assert!(n > 300, "{n}");
            assert_eq!(pg.positions_len(), n * pg.positions_stride());
            assert!(pg.positions_stride() >= dim);
            for mode in ["body", "speed", "pressure", "plastic_strain", "yield"] {
                pg.update_colours(ColourMode::parse(mode).unwrap());
                assert_eq!(pg.colours_len(), n);
                assert!(pg.colours().iter().all(|c| c.is_finite()));
            }
            pg.frame(0.05, 1e6, clock()).unwrap();
            let sp = pg.stress_point(n - 1).unwrap();
            assert_eq!(sp.model, "drucker_prager");
            assert!(sp.p.is_finite() && sp.q >= 0.0);
            assert_eq!(pg.index_of(sp.id), Some(n - 1));
            assert!(pg.surface_height(1.0, 0.5, 0.3) > 0.0);
            let e = pg
                .add_object("box", "elastic", &[0.5; 3][..dim], &[0.0; 3][..dim], 5.0)
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("size = 5: must be in"), "{e}");
            pg.clear();
            assert_eq!(pg.particle_count(), 0);
        }
    }

    fn read(path: &str) -> String {
        std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
    }

    #[test]
    fn shipped_scenes_load_with_their_assets_and_the_real_bunny_drops() {
        let mut names: Vec<String> =
            std::fs::read_dir(format!("{}/scenes", env!("CARGO_MANIFEST_DIR")))
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".json"))
                .collect();
        names.sort();
        assert!(names.len() >= 10, "{names:?}");
        let bunny = BunnyAssets::parse(
            Some(&read("scenes/bunny.obj")),
            Some(&read("scenes/bunny2d.txt")),
        )
        .unwrap();
        for name in names {
            let text = read(&format!("scenes/{name}"));
            let assets = super::figures::shipped_assets(&text);
            if !assets.is_empty() {
                let e = Playground::from_json(&text).unwrap_err().to_string();
                assert!(e.contains("not provided"), "{name}: {e}");
            }
            let mut pg = Playground::from_json_with_assets(&text, &assets).unwrap();
            pg.set_bunny(bunny.clone());
            let (n, dim) = (pg.particle_count(), pg.dim());
            let size = 0.2;
            let c = [0.3, 0.7, 0.3];
            pg.add_object("bunny", "elastic", &c[..dim], &[0.0; 3][..dim], size)
                .unwrap();
            // The real bunny: its volume is 0.2045 h³ in 3D, the silhouette's area in 2D.
            let added = (pg.particle_count() - n) as f64;
            let per_particle = (pg.scene().cell_size / 2.0).powi(dim as i32);
            let measure = added * per_particle / size.powi(dim as i32);
            let want = if dim == 3 {
                0.2045
            } else {
                bunny.polygon.as_ref().unwrap().area()
            };
            assert!(
                (measure / want - 1.0).abs() < 0.15,
                "{name}: bunny measure {measure}, want {want}"
            );
            pg.frame(0.003, 1e9, clock()).unwrap();
            assert!(pg.failure().is_none());
            pg.reset().unwrap();
            assert_eq!(pg.particle_count(), n, "{name}: reset restores the scene");
        }
    }

    /// A session (parameters, bodies dropped, Clear) is recorded with rounded figures, and a
    /// fresh playground given it drops the same bodies when its simulation reaches their
    /// times; what cannot apply is returned with its message.
    #[test]
    fn a_session_replays_its_parameters_and_drops() {
        for dim in [2, 3] {
            let mut pg = Playground::new(sand_scene(dim)).unwrap();
            pg.set_parameter("gravity", 5.0).unwrap();
            pg.frame(0.02, 1e9, clock()).unwrap();
            let i = pg
                .drop_at("ball", "elastic", &[0.412_345_6, 0.2, 0.5][..dim], 1.0, 0.2)
                .unwrap();
            let body = pg.scene().bodies[i].clone();
            let session = pg.session();
            assert_eq!(session.params, [("gravity".to_string(), 5.0)]);
            let d = session.drops[0].clone();
            assert!(d.t > 0.0199 && d.t <= pg.drop_clock(), "{d:?}");
            assert_eq!((d.centre[0], d.velocity[1], d.size), (0.412, -1.0, 0.2));
            assert!(d.centre[1] > 0.5, "above the sand: {d:?}");
            pg.frame(0.01, 1e9, clock()).unwrap();

            let mut again = Playground::new(sand_scene(dim)).unwrap();
            let mut replay = session.clone();
            replay.params.push(("cfl".into(), 7.0));
            let mut teapot = d.clone();
            teapot.object = "teapot".into();
            teapot.t = 0.001;
            replay.drops.push(teapot);
            let (rejected, refused) = again.replay(replay);
            assert_eq!(rejected, ["cfl = 7: must be in [0.001, 1]"]);
            assert!(refused.is_empty() && again.body_count() == 1);
            assert_eq!(again.parameter("gravity").unwrap(), 5.0);
            let r = again.frame(0.1, 1e9, clock()).unwrap();
            assert_eq!(r.requested, 0.001, "the frame stops at the next drop");
            assert_eq!(r.refused.len(), 1);
            assert!(r.refused[0].error.starts_with("object = teapot"), "{r:?}");
            let r = again.frame(0.1, 1e9, clock()).unwrap();
            assert!((r.requested - (d.t - 0.001)).abs() < 1e-12, "{r:?}");
            assert_eq!(again.body_count(), 2);
            assert_eq!(again.scene().bodies[1], body, "the same body");
            let landed = again.session().drops[0].applied_at.unwrap();
            assert!((landed - d.t).abs() < 1e-9, "{landed} vs {}", d.t);
            assert_eq!(
                again.session().drops.len(),
                1,
                "the refused drop is left out"
            );

            // Clear empties the box and restarts the drop clock; Reset forgets both.
            again.clear();
            let s = again.session();
            assert!(s.cleared && s.drops.is_empty() && again.drop_clock() == 0.0);
            again.reset().unwrap();
            let s = again.session();
            assert!(!s.cleared && s.drops.is_empty() && again.body_count() == 1);
            assert_eq!(s.params, [("gravity".to_string(), 5.0)]);
            again.reset_to_scene().unwrap();
            assert_eq!(again.parameter("gravity").unwrap(), 9.81);
        }
    }

    /// A quality level re-samples the scene (coarser cells dividing the domain, enough
    /// particles, the time-step cap with the cells), is part of the session, and switching
    /// levels starts the scene again with the parameters and the drops so far.
    #[test]
    fn quality_levels_resample_the_scene_and_keep_the_session() {
        let text = read("scenes/column_collapse_2d.json");
        let none = HashMap::new();
        let fine = Playground::load(&text, &none, "fine").unwrap();
        let mut pg = Playground::load(&text, &none, "live").unwrap();
        let (h0, n0) = (fine.scene().cell_size, fine.particle_count());
        let r = pg.quality().clone();
        assert_eq!((r.quality, r.scene_cell_size), ("live", h0));
        let f = r.cell_size / h0;
        assert!(f > 1.0 && f <= 2.0 + 1e-9, "{r:?}");
        for &side in &pg.scene().domain.size {
            let cells = side / r.cell_size;
            assert!(
                (cells - cells.round()).abs() < 1e-6,
                "{side} / {}",
                r.cell_size
            );
        }
        assert!((pg.scene().max_dt / fine.scene().max_dt - f).abs() < 1e-9);
        // The particles: as many as the finer lattice gives, and at least the level's floor.
        let n = pg.particle_count();
        let want = n0 as f64 * (r.particles_per_cell as f64 / 2.0 / f).powi(2);
        assert!(
            (n as f64 / want - 1.0).abs() < 0.1,
            "{n} particles, want {want}"
        );
        assert!(n >= 2000 && n < n0 * 2, "{n}");
        // The cheaper to simulate: particles over cell size, against the scene as written.
        assert!((n as f64 / r.cell_size) < 0.7 * (n0 as f64 / h0));
        // Saved, the session is the scene as written: opened at a level, it samples as this did.
        let saved = pg.saved_scene().unwrap();
        assert_eq!(saved.cell_size, h0);
        assert_eq!(saved.bodies[0].particles_per_cell, 2);
        let again = Playground::with_quality(saved, Quality::find("live").unwrap()).unwrap();
        assert_eq!(again.scene(), pg.scene());
        let e = Playground::load(&text, &none, "ultra")
            .err()
            .unwrap()
            .to_string();
        assert_eq!(e, "quality = ultra: must be one of live, balanced, fine");

        pg.set_parameter("gravity", 5.0).unwrap();
        pg.frame(0.02, 1e9, clock()).unwrap();
        pg.drop_at("ball", "elastic", &[0.2, 0.3], 0.0, 0.1)
            .unwrap();
        let t = pg.session().drops[0].t;
        let e = pg.set_quality("ultra").unwrap_err().to_string();
        assert!(e.starts_with("quality = ultra"), "{e}");
        assert_eq!(pg.body_count(), 2, "unchanged");
        assert!(pg.set_quality("fine").unwrap().is_empty());
        assert_eq!(pg.time(), 0.0, "the scene starts again");
        assert_eq!(pg.particle_count(), n0);
        assert_eq!(pg.parameter("gravity").unwrap(), 5.0);
        assert_eq!(pg.session().quality.as_deref(), Some("fine"));
        assert_eq!(pg.body_count(), 1, "the ball lands again at its time");
        while pg.body_count() < 2 {
            pg.frame(0.01, 1e9, clock()).unwrap();
        }
        assert!((pg.session().drops[0].applied_at.unwrap() - t).abs() < 1e-9);
        pg.reset().unwrap();
        assert_eq!(pg.quality().quality, "fine", "reset keeps the level");
        // A session replayed on a playground at another level takes the session's.
        let mut again = Playground::load(&text, &none, "live").unwrap();
        let (rejected, _) = again.replay(pg.session());
        assert!(rejected.is_empty(), "{rejected:?}");
        assert_eq!(
            (again.quality().quality, again.particle_count()),
            ("fine", n0)
        );
        let mut bad = pg.session();
        bad.quality = Some("ultra".into());
        let (rejected, _) = again.replay(bad);
        assert!(rejected[0].starts_with("quality = ultra"), "{rejected:?}");
    }

    /// Bodies dropped take the level's resolution, and a small one more particles per cell. An
    /// empty box keeps its cells (there is nothing to make cheaper).
    #[test]
    fn dropped_bodies_take_the_quality_level() {
        for dim in [2, 3] {
            let live = Quality::find("live").unwrap();
            let mut pg = Playground::with_quality(Playground::sandbox_scene(dim), live).unwrap();
            assert_eq!(
                pg.quality().cell_size,
                Playground::sandbox_scene(dim).cell_size
            );
            let c = [1.0, 0.5, 0.5];
            let big = pg
                .add_object("box", "elastic", &c[..dim], &[0.0; 3][..dim], 0.5)
                .unwrap();
            let small = pg
                .add_object("ball", "elastic", &c[..dim], &[0.0; 3][..dim], 0.15)
                .unwrap();
            let bodies = &pg.scene().bodies;
            assert_eq!(
                bodies[big].particles_per_cell,
                pg.quality().particles_per_cell
            );
            assert!(bodies[small].particles_per_cell > bodies[big].particles_per_cell);
            let stats = pg.simulation().body_stats();
            let least = live.min_body_particles[dim - 2];
            assert!(
                stats[small].particles >= least,
                "{dim}D: {:?}",
                stats[small]
            );
        }
    }

    /// A parameter of one body changes that body only, is named by its scene path when
    /// refused, and survives a reset.
    #[test]
    fn one_body_takes_its_own_parameters() {
        let mut scene = sand_scene(2);
        scene.bodies.push(scene.bodies[0].clone());
        let mut pg = Playground::new(scene).unwrap();
        let name = "bodies[1].drucker_prager.friction_angle";
        pg.set_parameter(name, 20.0).unwrap();
        assert_eq!(pg.parameter(name).unwrap(), 20.0);
        assert_eq!(pg.parameter("drucker_prager.friction_angle").unwrap(), 35.0);
        let e = pg.set_parameter(name, 90.0).unwrap_err().to_string();
        assert!(
            e.starts_with("bodies[1].material.drucker_prager.friction_angle = 90"),
            "{e}"
        );
        let e = pg.set_parameter("bodies[5].drucker_prager.cohesion", 1.0);
        assert!(
            e.unwrap_err()
                .to_string()
                .contains("the scene has 2 bodies")
        );
        pg.reset().unwrap();
        assert_eq!(pg.parameter(name).unwrap(), 20.0);
    }

    /// A live parameter changes only what it names, and the simulation then steps bit for bit
    /// as one configured with the whole scene so modified: a parameter of every body of a
    /// model, one body's, a PIC/FLIP ratio and a world setting, in 2D and 3D.
    #[test]
    fn a_parameter_steps_exactly_as_the_scene_rebuilt_with_it() {
        fn state(sim: &AnySimulation) -> String {
            fn of<D: Dim>(s: &Simulation<D>) -> String {
                let bodies: Vec<_> = s.bodies().iter().map(|b| (b.model, b.recipe)).collect();
                format!("{:?} {bodies:?} {:?}", s.particles(), s.diagnostics())
            }
            match sim {
                AnySimulation::D2(s) => of(s),
                AnySimulation::D3(s) => of(s),
            }
        }
        for dim in [2, 3] {
            let mut scene = sand_scene(dim);
            let (lo, hi) = ([1.2, 0.0, 0.3], [1.5, 0.3, 0.6]);
            scene.bodies.push(BodyConfig::new(
                "block",
                Shape::cuboid(&lo[..dim], &hi[..dim]),
                Material::elastic(1e5, 0.3, 1000.0),
            ));
            scene.bodies.push(scene.bodies[0].clone());
            scene.bodies[2].shape = Shape::cuboid(&[0.7, 0.0, 0.3][..dim], &[0.9, 0.2, 0.5][..dim]);
            let mut pg = Playground::with_quality(scene, Quality::find("live").unwrap()).unwrap();
            for _ in 0..40 {
                pg.step(clock()).unwrap();
            }
            for (name, value) in [
                ("drucker_prager.friction_angle", 25.0),
                ("bodies[2].drucker_prager.cohesion", 200.0),
                ("elastic.flip", 0.4),
                ("bodies[1].elastic.youngs_modulus", 3e5),
                ("gravity", 6.0),
            ] {
                let target = Target::parse(name).unwrap();
                let mut rebuilt = pg.simulation().clone();
                rebuilt
                    .configure(|s| target.set_in_scene(s, value, true).unwrap())
                    .unwrap();
                rebuilt.set_sleeping_at_rest(true);
                pg.set_parameter(name, value).unwrap();
                assert_eq!(pg.scene(), rebuilt.scene(), "{name}");
                assert_eq!(state(pg.simulation()), state(&rebuilt), "{name}");
                for _ in 0..15 {
                    pg.step(clock()).unwrap();
                    rebuilt.step().unwrap();
                }
                assert_eq!(state(pg.simulation()), state(&rebuilt), "{dim}D {name}");
            }
        }
    }

    /// Sleeping is on by default: a sand block left to settle falls asleep (the colour mode
    /// marks exactly those particles); switched off, everything wakes and stays awake. Reset,
    /// Clear and another quality level keep the choice.
    #[test]
    fn a_settled_scene_sleeps_unless_sleeping_is_off() {
        let live = Quality::find("live").unwrap();
        for dim in [2, 3] {
            let mut on = Playground::with_quality(sand_scene(dim), live).unwrap();
            let mut off = on.clone();
            off.set_sleeping(false);
            assert!(on.sleeping() && !off.sleeping());
            for pg in [&mut on, &mut off] {
                while pg.time() < 2.0 {
                    pg.frame(0.05, 1e9, clock()).unwrap();
                }
            }
            let n = on.particle_count();
            let asleep = on.asleep();
            assert!(asleep > n / 2, "{dim}D: {asleep} of {n} asleep");
            assert_eq!(off.asleep(), 0, "{dim}D: off keeps all awake");
            on.update_colours(ColourMode::Sleeping);
            let marked = on.colours().iter().filter(|&&c| c < 0.0).count();
            assert_eq!(marked, asleep);
            assert!(on.colours().iter().all(|&c| c == 0.0 || c == -1.0));
            // The sand at rest: the awake run's particles are as slow as those asleep.
            let fast = |pg: &Playground| match &pg.sim {
                AnySimulation::D2(s) => (0..n).filter(|&i| s.particles().speed(i) > 0.05).count(),
                AnySimulation::D3(s) => (0..n).filter(|&i| s.particles().speed(i) > 0.05).count(),
            };
            assert_eq!(fast(&off), 0, "{dim}D: settled");
            // Switched off, everything wakes; Reset and quality keep the choice off.
            on.set_sleeping(false);
            assert_eq!(on.asleep(), 0);
            on.reset().unwrap();
            assert!(!on.sleeping());
            on.set_sleeping(true);
            on.set_quality("balanced").unwrap();
            assert!(
                on.sleeping() && on.asleep() == 0,
                "a new simulation: nothing asleep"
            );
            on.clear();
            assert!(on.sleeping() && on.asleep() == 0);
            assert!(on.simulation().scene().bodies.is_empty());
        }
    }

    #[test]
    fn predictions_warn_of_stiff_materials() {
        let pg = Playground::new(sand_scene(2)).unwrap();
        let soft = pg.predict("drucker_prager.youngs_modulus", 3.5e5, 1.0 / 60.0);
        let stiff = pg.predict("drucker_prager.youngs_modulus", 3.5e9, 1.0 / 60.0);
        assert!(soft.valid && stiff.valid);
        assert!(stiff.substeps_per_frame > 50.0 * soft.substeps_per_frame);
        let bad = pg.predict("drucker_prager.poisson_ratio", 0.5, 1.0 / 60.0);
        assert!(!bad.valid && bad.error.contains("poisson_ratio"), "{bad:?}");
    }
}
