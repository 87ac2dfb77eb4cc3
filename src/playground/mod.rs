//! An interactive session over a simulation: what the browser page drives through
//! [`crate::wasm`], and what any other front end (or a native benchmark of the same work) can
//! drive directly. Browser-free: the wall clock is passed in.
//!
//! - Scenes are [`SceneConfig`] JSON, exactly as the CLI reads them.
//! - Live parameters go through [`AnySimulation::configure`], so a slider is validated exactly
//!   like a scene file and a rejected value leaves the state unchanged. Parameters are named
//!   `gravity`, `wall_friction`, `cfl` (world) and `<model>.<field>` for materials, where
//!   `<model>` is the scene-file name of a material (`elastic`, `von_mises`,
//!   `drucker_prager`) and `<field>` one of its fields or `flip`. A material parameter applies
//!   to every body of that model and to the preset that new bodies of that model are made of.
//! - Particle positions and a per-particle colour scalar are exposed as pointers and lengths
//!   (f32), so a front end can read them in place.

use crate::config::{BodyConfig, SceneConfig};
use crate::error::{Error, Result};
use crate::geometry::{Loaded, Polygon2, Scale, Shape, TriMesh};
use crate::material::Material;
use crate::math::{Dim, Real, SymTensor};
use crate::sim::{AnySimulation, Diagnostics, Simulation};
use serde::Serialize;
use std::collections::HashMap;
use std::sync::Arc;

/// The world parameters the page can change, with the slider ranges it offers.
pub const WORLD_PARAMETERS: [&str; 3] = ["gravity", "wall_friction", "cfl"];

/// Scene-file names of the three material models, in the order the page lists them.
pub const MODELS: [&str; 3] = ["elastic", "von_mises", "drucker_prager"];

/// What a particle's colour scalar shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourMode {
    /// The body index (a categorical palette).
    Body,
    /// |v| (m/s).
    Speed,
    /// P = −tr σ / 3 (Pa, compression positive).
    Pressure,
    /// Accumulated equivalent plastic strain.
    PlasticStrain,
    /// 0 elastic, 0.5 on the yield surface, 1 flowing (plastic strain grew since the last
    /// colour update).
    Yield,
}

impl ColourMode {
    pub fn parse(name: &str) -> Result<Self> {
        Ok(match name {
            "body" => ColourMode::Body,
            "speed" => ColourMode::Speed,
            "pressure" => ColourMode::Pressure,
            "plastic_strain" => ColourMode::PlasticStrain,
            "yield" => ColourMode::Yield,
            _ => {
                return Err(Error::invalid(
                    "colour",
                    name,
                    "must be one of body, speed, pressure, plastic_strain, yield",
                ));
            }
        })
    }
}

/// What one call of [`Playground::frame`] did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameReport {
    /// Time steps taken.
    pub substeps: usize,
    /// Simulated time advanced (s).
    pub sim_time: f64,
    /// The simulated time asked for (s).
    pub requested: f64,
    /// Wall-clock time spent stepping (ms).
    pub wall_ms: f64,
    /// Whether the wall-clock budget ran out before the requested time was simulated.
    pub fell_behind: bool,
    /// Mean wall-clock time of one step (ms), 0 when no step was taken.
    pub ms_per_step: f64,
    /// The time step the next step will take (s).
    pub stable_dt: f64,
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
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
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
    /// The yield surface as q = slope · p + intercept for p ≥ apex_p; `none` for an elastic
    /// body (slope and intercept are then zero).
    pub surface: &'static str,
    pub slope: f64,
    pub intercept: f64,
    pub apex_p: f64,
}

/// Materials of new bodies, one per model.
#[derive(Clone, Debug, PartialEq)]
struct Presets {
    materials: [Material; 3],
    flip: [Option<f64>; 3],
}

impl Presets {
    fn defaults() -> Self {
        Presets {
            materials: [
                Material::elastic(1.0e5, 0.3, 1000.0),
                Material::von_mises(1.0e5, 0.3, 1000.0, 5.0e3),
                Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0),
            ],
            flip: [None; 3],
        }
    }
    /// The defaults, overridden by the first body of each model in `scene`.
    fn from_scene(scene: &SceneConfig) -> Self {
        let mut p = Self::defaults();
        for (m, model) in MODELS.iter().enumerate() {
            if let Some(b) = scene.bodies.iter().find(|b| b.material.kind() == *model) {
                p.materials[m] = b.material.clone();
                p.flip[m] = b.flip;
            }
        }
        p
    }
}

fn model_index(model: &str) -> Result<usize> {
    MODELS.iter().position(|m| *m == model).ok_or_else(|| {
        Error::invalid(
            "material",
            model,
            "must be one of elastic, von_mises, drucker_prager",
        )
    })
}

/// The fields of a model that [`Playground::set_parameter`] can change.
pub fn model_fields(model: &str) -> &'static [&'static str] {
    match model {
        "elastic" => &["youngs_modulus", "poisson_ratio", "density", "flip"],
        "von_mises" => &[
            "youngs_modulus",
            "poisson_ratio",
            "density",
            "yield_stress",
            "flip",
        ],
        "drucker_prager" => &[
            "youngs_modulus",
            "poisson_ratio",
            "density",
            "friction_angle",
            "dilatancy_angle",
            "cohesion",
            "flip",
        ],
        _ => &[],
    }
}

/// A mutable reference to `field` of a material, if it has one (`flip` is not a material field).
fn material_field<'a>(m: &'a mut Material, field: &str) -> Option<&'a mut f64> {
    match m {
        Material::Elastic(p) => match field {
            "youngs_modulus" => Some(&mut p.youngs_modulus),
            "poisson_ratio" => Some(&mut p.poisson_ratio),
            "density" => Some(&mut p.density),
            _ => None,
        },
        Material::VonMises(p) => match field {
            "youngs_modulus" => Some(&mut p.youngs_modulus),
            "poisson_ratio" => Some(&mut p.poisson_ratio),
            "density" => Some(&mut p.density),
            "yield_stress" => Some(&mut p.yield_stress),
            _ => None,
        },
        Material::DruckerPrager(p) => match field {
            "youngs_modulus" => Some(&mut p.youngs_modulus),
            "poisson_ratio" => Some(&mut p.poisson_ratio),
            "density" => Some(&mut p.density),
            "friction_angle" => Some(&mut p.friction_angle),
            "dilatancy_angle" => Some(&mut p.dilatancy_angle),
            "cohesion" => Some(&mut p.cohesion),
            _ => None,
        },
    }
}

/// The current value of `field` of a material (or its body's `flip`).
fn read_field(m: &Material, flip: Option<f64>, field: &str) -> Option<f64> {
    if field == "flip" {
        return Some(flip.unwrap_or_else(|| m.default_flip()));
    }
    let mut m = m.clone();
    material_field(&mut m, field).map(|v| *v)
}

/// A parsed parameter name.
enum Param<'a> {
    World(&'a str),
    Material { model: usize, field: &'a str },
}

fn parse_param(name: &str) -> Result<Param<'_>> {
    if WORLD_PARAMETERS.contains(&name) {
        return Ok(Param::World(name));
    }
    let known = || {
        let mut all: Vec<String> = WORLD_PARAMETERS.iter().map(|s| s.to_string()).collect();
        for m in MODELS {
            all.extend(model_fields(m).iter().map(|f| format!("{m}.{f}")));
        }
        format!("must be one of {}", all.join(", "))
    };
    let Some((model, field)) = name.split_once('.') else {
        return Err(Error::invalid("parameter", name, known()));
    };
    let m = model_index(model).map_err(|_| Error::invalid("parameter", name, known()))?;
    if !model_fields(model).contains(&field) {
        return Err(Error::invalid("parameter", name, known()));
    }
    Ok(Param::Material { model: m, field })
}

/// Applies parameter `name` = `value` to a scene (unvalidated).
fn apply_to_scene(scene: &mut SceneConfig, param: &Param<'_>, value: f64) {
    match *param {
        Param::World("gravity") => {
            let mut g = vec![0.0; scene.dim];
            g[1] = -value;
            scene.gravity = Some(g);
        }
        Param::World("wall_friction") => scene.boundary.friction = value,
        Param::World("cfl") => scene.cfl = value,
        Param::World(_) => unreachable!("parse_param admits only the world parameters"),
        Param::Material { model, field } => {
            for b in &mut scene.bodies {
                if b.material.kind() != MODELS[model] {
                    continue;
                }
                if field == "flip" {
                    b.flip = Some(value);
                } else if let Some(v) = material_field(&mut b.material, field) {
                    *v = value;
                }
            }
        }
    }
}

/// The bunny of the "drop a bunny" tool: a union of balls (body, haunch, head, ears, tail),
/// `height` tall, its base centred at `base`. 2D gives the side view.
pub fn ball_bunny(dim: usize, base: [f64; 3], height: f64) -> Shape {
    // (x, y, z, r) in units of the height; x points forward, base on y = 0.
    const BALLS: [[f64; 4]; 10] = [
        [-0.05, 0.28, 0.0, 0.28],
        [-0.22, 0.22, 0.0, 0.22],
        [0.22, 0.52, 0.0, 0.17],
        [0.15, 0.70, -0.06, 0.065],
        [0.11, 0.80, -0.06, 0.06],
        [0.08, 0.90, -0.06, 0.06],
        [0.25, 0.70, 0.06, 0.065],
        [0.27, 0.80, 0.06, 0.06],
        [0.29, 0.90, 0.06, 0.06],
        [-0.46, 0.32, 0.0, 0.08],
    ];
    Shape::Union(
        BALLS
            .iter()
            .map(|b| {
                let c = [
                    base[0] + b[0] * height,
                    base[1] + b[1] * height,
                    base[2] + b[2] * height,
                ];
                Shape::ball(&c[..dim], b[3] * height)
            })
            .collect(),
    )
}

/// The shipped bunny (`scenes/bunny.obj`, `scenes/bunny2d.txt`): height 1, base on y = 0,
/// centred on x (and z), as parsed meshes, so that dropping one needs no file access.
#[derive(Clone, Debug, Default)]
pub struct BunnyAssets {
    pub mesh: Option<Arc<TriMesh>>,
    pub polygon: Option<Arc<Polygon2>>,
}

impl BunnyAssets {
    /// Parses the OBJ mesh and the 2D vertex list (either may be absent).
    pub fn parse(obj: Option<&str>, polygon: Option<&str>) -> Result<Self> {
        let bad = |path: &str, message: String| Error::Io {
            path: path.to_string(),
            message,
        };
        Ok(BunnyAssets {
            mesh: obj
                .map(|t| TriMesh::from_obj("bunny.obj", t).map(Arc::new))
                .transpose()
                .map_err(|m| bad("bunny.obj", m))?,
            polygon: polygon
                .map(|t| Polygon2::from_vertex_list("bunny2d.txt", t).map(Arc::new))
                .transpose()
                .map_err(|m| bad("bunny2d.txt", m))?,
        })
    }
}

/// The shape of a dropped object of kind `object` (`bunny`, `ball`, `box`) and size `size`
/// (its height, m) with its centre at `center`. The bunny is the shipped mesh (3D) or
/// silhouette (2D) when `bunny` holds it, else [`ball_bunny`].
pub fn object_shape(
    object: &str,
    dim: usize,
    center: [f64; 3],
    size: f64,
    bunny: &BunnyAssets,
) -> Result<Shape> {
    let h = size / 2.0;
    Ok(match object {
        "ball" => Shape::ball(&center[..dim], h),
        "box" => Shape::cuboid(
            &[center[0] - h, center[1] - h, center[2] - h][..dim],
            &[center[0] + h, center[1] + h, center[2] + h][..dim],
        ),
        "bunny" => {
            let base = [center[0], center[1] - h, center[2]];
            match (dim, &bunny.mesh, &bunny.polygon) {
                (3, Some(mesh), _) => Shape::Mesh {
                    path: "bunny.obj".into(),
                    scale: Scale::Uniform(size),
                    rotate_deg: None,
                    translate: Some(base.to_vec()),
                    loaded: Loaded(Some(mesh.clone())),
                },
                (2, _, Some(polygon)) => Shape::Polygon {
                    path: Some("bunny2d.txt".into()),
                    points: None,
                    scale: Scale::Uniform(size),
                    rotate_deg: None,
                    translate: Some(base[..2].to_vec()),
                    loaded: Loaded(Some(polygon.clone())),
                },
                _ => ball_bunny(dim, base, size),
            }
        }
        _ => {
            return Err(Error::invalid(
                "object",
                object,
                "must be one of bunny, ball, box",
            ));
        }
    })
}

/// The files a scene references (meshes, vertex lists; paths relative to the scene file).
pub fn asset_paths(scene_json: &str) -> Result<Vec<String>> {
    Ok(SceneConfig::from_json(scene_json)?.asset_paths())
}

/// An interactive simulation with its presets, parameter overrides and colour buffer.
#[derive(Clone, Debug)]
pub struct Playground {
    sim: AnySimulation,
    /// The scene as loaded (for reset).
    initial: SceneConfig,
    presets: Presets,
    /// Parameters changed since the scene was loaded, in the order they were last set.
    overrides: Vec<(String, f64)>,
    colours: Vec<f32>,
    colour_range: [f32; 2],
    /// Plastic strain at the previous colour update, by particle id (for the yield view).
    previous_plastic: Vec<Real>,
    /// Smoothed wall-clock cost of one step (ms), for predictions.
    ms_per_step: f64,
    bunny: BunnyAssets,
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
        let mut scene = SceneConfig::from_json(text)?;
        scene.resolve_assets(|path| {
            assets.get(path).cloned().ok_or_else(|| Error::Io {
                path: path.to_string(),
                message: "not provided (fetch it beside the scene file)".into(),
            })
        })?;
        Self::new(scene)
    }

    /// Uses the shipped bunny's mesh and silhouette for dropped bunnies.
    pub fn set_bunny(&mut self, bunny: BunnyAssets) {
        self.bunny = bunny;
    }

    /// A playground over a scene.
    pub fn new(scene: SceneConfig) -> Result<Self> {
        let sim = AnySimulation::new(scene.clone())?;
        let mut pg = Playground {
            presets: Presets::from_scene(&scene),
            initial: scene,
            sim,
            overrides: Vec::new(),
            colours: Vec::new(),
            colour_range: [0.0, 1.0],
            previous_plastic: Vec::new(),
            ms_per_step: 0.0,
            bunny: BunnyAssets::default(),
        };
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
    pub fn particle_count(&self) -> usize {
        self.sim.particle_count()
    }
    pub fn body_count(&self) -> usize {
        self.sim.scene().bodies.len()
    }
    /// The error that stopped the simulation, if any (a reset or clear starts again).
    pub fn failure(&self) -> Option<String> {
        self.sim.failure().map(|e| e.to_string())
    }

    /// Advances by up to `sim_time` seconds of simulated time, stopping early when
    /// `budget_ms` of wall-clock time (read from `now_ms`) has been spent. Stops with an error
    /// if the simulation goes non-finite.
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
        let end = self.sim.time() + sim_time;
        let mut report = FrameReport {
            requested: sim_time,
            ..Default::default()
        };
        if self.particle_count() > 0 {
            let t0 = self.sim.time();
            while self.sim.time() < end - 1e-12 * end.abs().max(1.0) {
                if now_ms() - start >= budget_ms {
                    report.fell_behind = true;
                    break;
                }
                self.sim.step_at_most(end - self.sim.time())?;
                report.substeps += 1;
            }
            report.sim_time = self.sim.time() - t0;
        } else {
            report.sim_time = sim_time;
        }
        report.wall_ms = now_ms() - start;
        if report.substeps > 0 {
            report.ms_per_step = report.wall_ms / report.substeps as f64;
            self.ms_per_step = if self.ms_per_step > 0.0 {
                0.8 * self.ms_per_step + 0.2 * report.ms_per_step
            } else {
                report.ms_per_step
            };
        }
        report.stable_dt = self.sim.stable_dt();
        Ok(report)
    }

    /// One time step of the adaptive size.
    pub fn step(&mut self) -> Result<()> {
        self.sim.step().map(|_| ())
    }

    /// Sets a live parameter (see the module docs for the names), validated like a scene file;
    /// on error the state is unchanged.
    pub fn set_parameter(&mut self, name: &str, value: f64) -> Result<()> {
        let param = parse_param(name)?;
        let mut presets = self.presets.clone();
        if let Param::Material { model, field } = param {
            if field == "flip" {
                presets.flip[model] = Some(value);
                crate::error::check_range(name, value, 0.0, 1.0, false, "")?;
            } else if let Some(v) = material_field(&mut presets.materials[model], field) {
                *v = value;
                // The preset's own check names the parameter as the page does.
                presets.materials[model].validate("material")?;
            }
        }
        self.sim
            .configure(|scene| apply_to_scene(scene, &param, value))?;
        self.presets = presets;
        self.overrides.retain(|(n, _)| n != name);
        self.overrides.push((name.to_string(), value));
        Ok(())
    }

    /// The value of a live parameter: the first body of that model's, else the preset's.
    pub fn parameter(&self, name: &str) -> Result<f64> {
        let scene = self.sim.scene();
        Ok(match parse_param(name)? {
            Param::World("gravity") => -scene.gravity_vector()[1],
            Param::World("wall_friction") => scene.boundary.friction,
            Param::World("cfl") => scene.cfl,
            Param::World(_) => unreachable!("parse_param admits only the world parameters"),
            Param::Material { model, field } => {
                let from_body = scene
                    .bodies
                    .iter()
                    .find(|b| b.material.kind() == MODELS[model])
                    .and_then(|b| read_field(&b.material, b.flip, field));
                from_body
                    .or_else(|| {
                        read_field(
                            &self.presets.materials[model],
                            self.presets.flip[model],
                            field,
                        )
                    })
                    .unwrap_or(0.0)
            }
        })
    }

    /// Every live parameter with its current value.
    pub fn parameters(&self) -> Vec<(String, f64)> {
        let mut names: Vec<String> = WORLD_PARAMETERS.iter().map(|s| s.to_string()).collect();
        for m in MODELS {
            names.extend(model_fields(m).iter().map(|f| format!("{m}.{f}")));
        }
        names
            .into_iter()
            .map(|n| {
                let v = self.parameter(&n).unwrap_or(0.0);
                (n, v)
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
        let mut out = Prediction::default();
        let mut scene = self.sim.scene().clone();
        let mut presets = self.presets.clone();
        let checked = parse_param(name).and_then(|param| {
            apply_to_scene(&mut scene, &param, value);
            if let Param::Material { model, field } = param {
                if field == "flip" {
                    crate::error::check_range(name, value, 0.0, 1.0, false, "")?;
                } else if let Some(v) = material_field(&mut presets.materials[model], field) {
                    *v = value;
                    presets.materials[model].validate("material")?;
                }
            }
            scene.validate()
        });
        if let Err(e) = checked {
            out.error = e.to_string();
            return out;
        }
        out.valid = true;
        // The wave speed at the reference density: of the bodies, or of the presets when
        // there is none (what the next dropped body would need).
        let c = if scene.bodies.is_empty() {
            presets
                .materials
                .iter()
                .map(|m| m.wave_speed())
                .fold(0.0, f64::max)
        } else {
            scene
                .bodies
                .iter()
                .map(|b| b.material.wave_speed())
                .fold(0.0, f64::max)
        };
        let speed = c + self.sim.diagnostics().max_speed;
        out.stable_dt = if speed > 0.0 {
            (scene.cfl * scene.cell_size / speed).min(scene.max_dt)
        } else {
            scene.max_dt
        };
        out.substeps_per_frame = (frame_time / out.stable_dt).ceil();
        if self.ms_per_step > 0.0 && out.substeps_per_frame > 0.0 {
            // Cost per step scales with the particle count, not with the parameter.
            out.realtime_ratio =
                frame_time / (out.substeps_per_frame * self.ms_per_step * 1e-3).max(1e-9);
        }
        out
    }

    /// Adds a body of kind `object` (`bunny`, `ball`, `box`) made of the preset material
    /// `model` (`elastic`, `von_mises`, `drucker_prager`), `size` metres tall, centred at
    /// `center` (moved inside the domain if it pokes out), moving at `velocity`. Returns the
    /// new body's index.
    pub fn add_object(
        &mut self,
        object: &str,
        model: &str,
        center: &[f64],
        velocity: &[f64],
        size: f64,
    ) -> Result<usize> {
        let m = model_index(model)?;
        let dim = self.dim();
        crate::geometry::check_vector("center", center, dim, "m")?;
        crate::geometry::check_vector("velocity", velocity, dim, "m/s")?;
        let domain = self.sim.scene().domain.size.clone();
        let h = self.sim.scene().cell_size;
        let largest = domain.iter().cloned().fold(f64::INFINITY, f64::min) - 2.0 * h;
        if !(size.is_finite() && size >= 2.0 * h && size <= largest) {
            return Err(Error::invalid(
                "size",
                size,
                format!(
                    "must be in [{}, {}] (m): at least two cells, and the object must fit in the domain",
                    2.0 * h,
                    largest
                ),
            ));
        }
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
        self.sim.add_body(body)
    }

    /// Adds a body as written in a scene file.
    pub fn add_body(&mut self, body: BodyConfig) -> Result<usize> {
        self.sim.add_body(body)
    }

    /// Removes every body.
    pub fn clear(&mut self) {
        self.sim.clear();
        self.colours.clear();
    }

    /// Reloads the scene and applies the parameter overrides again.
    pub fn reset(&mut self) -> Result<()> {
        let mut next = Playground::new(self.initial.clone())?;
        for (name, value) in &self.overrides {
            // Each was valid when it was set; one that no longer applies is dropped.
            let _ = next.set_parameter(name, *value);
        }
        next.ms_per_step = self.ms_per_step;
        next.bunny = std::mem::take(&mut self.bunny);
        *self = next;
        Ok(())
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
        self.colours.as_ptr()
    }
    pub fn colours_len(&self) -> usize {
        self.colours.len()
    }
    pub fn colours(&self) -> &[f32] {
        &self.colours
    }
    /// The range the colour map spans: [0, body count) for bodies, [0, 1] for yield states,
    /// else [0, the 99th percentile].
    pub fn colour_range(&self) -> [f32; 2] {
        self.colour_range
    }

    /// Recomputes the per-particle colour scalar.
    pub fn update_colours(&mut self, mode: ColourMode) {
        let scene = self.sim.scene().clone();
        let (colours, prev) = (&mut self.colours, &mut self.previous_plastic);
        match &self.sim {
            AnySimulation::D2(s) => fill_colours(s, &scene, mode, colours, prev),
            AnySimulation::D3(s) => fill_colours(s, &scene, mode, colours, prev),
        }
        self.colour_range = match mode {
            ColourMode::Body => [0.0, self.body_count().max(1) as f32],
            ColourMode::Yield => [0.0, 1.0],
            _ => {
                let hi = percentile(&self.colours, 0.99).max(match mode {
                    ColourMode::Speed => 0.05,
                    ColourMode::Pressure => 10.0,
                    _ => 1e-3,
                });
                [0.0, hi]
            }
        };
    }

    /// The particle whose stable id is `id`, if it still exists.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        match &self.sim {
            AnySimulation::D2(s) => s.particles().id.iter().position(|&i| i == id),
            AnySimulation::D3(s) => s.particles().id.iter().position(|&i| i == id),
        }
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

/// The value at fraction `q` of the sorted values (0 for none).
fn percentile(values: &[f32], q: f64) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v: Vec<f32> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    let (_, x, _) = v.select_nth_unstable_by(k, f32::total_cmp);
    *x
}

/// A position as three components (z = 0 in 2D).
fn xyz<D: Dim>(v: D::Vector) -> [f64; 3] {
    std::array::from_fn(|a| if a < D::DIM { v[a] as f64 } else { 0.0 })
}

fn body_of<D: Dim>(s: &Simulation<D>) -> Vec<u32> {
    let mut out = vec![0u32; s.particles().len()];
    for (i, b) in s.bodies().iter().enumerate() {
        for p in b.range() {
            out[p] = i as u32;
        }
    }
    out
}

// `as f32` is a no-op in the default build and a conversion with the `f64` feature.
#[allow(clippy::unnecessary_cast)]
fn fill_colours<D: Dim>(
    s: &Simulation<D>,
    scene: &SceneConfig,
    mode: ColourMode,
    out: &mut Vec<f32>,
    previous_plastic: &mut Vec<Real>,
) {
    let p = s.particles();
    out.clear();
    match mode {
        ColourMode::Body => out.extend(body_of(s).into_iter().map(|b| b as f32)),
        ColourMode::Speed => out.extend((0..p.len()).map(|i| p.speed(i) as f32)),
        ColourMode::Pressure => out.extend((0..p.len()).map(|i| p.pressure(i) as f32)),
        ColourMode::PlasticStrain => out.extend(p.plastic_strain.iter().map(|&e| e as f32)),
        ColourMode::Yield => {
            let max_id = p.id.iter().copied().max().map_or(0, |m| m as usize + 1);
            if previous_plastic.len() < max_id {
                previous_plastic.resize(max_id, Real::NAN);
            }
            out.resize(p.len(), 0.0);
            for (b, body) in s.bodies().iter().enumerate() {
                let surface = Surface::of(&scene.bodies[b].material);
                for i in body.range() {
                    let id = p.id[i] as usize;
                    let ep = p.plastic_strain[i];
                    let before = previous_plastic[id];
                    previous_plastic[id] = ep;
                    out[i] = if before.is_finite() && ep > before {
                        1.0
                    } else if surface.on_surface(p.stress[i]) {
                        0.5
                    } else {
                        0.0
                    };
                }
            }
        }
    }
}

/// A yield surface in (p, q): q = slope p + intercept, or none.
#[derive(Clone, Copy, Debug)]
struct Surface {
    kind: &'static str,
    slope: f64,
    intercept: f64,
    apex_p: f64,
}

impl Surface {
    fn of(m: &Material) -> Surface {
        match m {
            Material::Elastic(_) => Surface {
                kind: "none",
                slope: 0.0,
                intercept: 0.0,
                apex_p: 0.0,
            },
            // √J2 = Y = σ_y/√3, so q = √3 √J2 = σ_y: a cylinder about the hydrostatic axis.
            Material::VonMises(p) => Surface {
                kind: "von_mises",
                slope: 0.0,
                intercept: p.yield_stress,
                apex_p: f64::NEG_INFINITY,
            },
            // f = √J2 + α_φ I1 − k_c = 0 with I1 = −3p: q = √3 (k_c + 3 α_φ p), a cone whose
            // apex is at p = −k_c / (3 α_φ).
            Material::DruckerPrager(params) => {
                let m = params.model();
                let (a, k) = (m.alpha_phi as f64, m.k_c as f64);
                Surface {
                    kind: "drucker_prager",
                    slope: 3f64.sqrt() * 3.0 * a,
                    intercept: 3f64.sqrt() * k,
                    apex_p: if a > 0.0 {
                        -k / (3.0 * a)
                    } else {
                        f64::NEG_INFINITY
                    },
                }
            }
        }
    }

    /// Whether a stress lies on (within 2 % of) the yield surface.
    fn on_surface<S: SymTensor<Scalar = Real>>(&self, stress: S) -> bool {
        if self.kind == "none" {
            return false;
        }
        let p = -stress.trace() as f64 / 3.0;
        let q = (3.0 * stress.j2() as f64).sqrt();
        let limit = self.slope * p + self.intercept;
        let scale = limit.abs().max(1e-3 * (q + p.abs())).max(1e-9);
        q >= limit - 0.02 * scale || p <= self.apex_p
    }
}

fn stress_point<D: Dim>(s: &Simulation<D>, i: usize) -> StressPoint {
    let p = s.particles();
    let body = s
        .bodies()
        .iter()
        .position(|b| b.range().contains(&i))
        .unwrap_or(0);
    let material = &s.scene().bodies[body].material;
    let surface = Surface::of(material);
    let sigma = p.stress[i];
    let x = xyz::<D>(p.x[i]);
    StressPoint {
        index: i,
        id: p.id[i],
        body,
        model: material.kind(),
        p: -sigma.trace() as f64 / 3.0,
        q: (3.0 * sigma.j2() as f64).sqrt(),
        plastic_strain: p.plastic_strain[i] as f64,
        position: x,
        surface: surface.kind,
        slope: surface.slope,
        intercept: surface.intercept,
        apex_p: if surface.apex_p.is_finite() {
            surface.apex_p
        } else {
            -1e300
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let mut pg = Playground::new(Playground::sandbox_scene(dim)).unwrap();
            for (k, object) in ["bunny", "ball", "box"].into_iter().enumerate() {
                let c = [0.05 + k as f64, 0.95, 0.5];
                pg.add_object(object, MODELS[k], &c[..dim], &[0.0; 3][..dim], 0.3)
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
            let assets: HashMap<String, String> = asset_paths(&text)
                .unwrap()
                .into_iter()
                .map(|p| {
                    let t = read(&format!("scenes/{p}"));
                    (p, t)
                })
                .collect();
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
