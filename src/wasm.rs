//! The WebAssembly API of the browser playground: a thin wasm-bindgen layer over
//! [`crate::playground::Playground`]. Errors become JS `Error`s whose message names the
//! parameter and its allowed range; small records cross as JSON strings; particle positions
//! and colours are read in place through pointers into wasm memory (JS builds
//! `new Float32Array(memory.buffer, ptr, len)` views after each call that may grow memory).

use crate::playground::{BunnyAssets, ColourMode, Playground};
use std::collections::HashMap;
use wasm_bindgen::prelude::*;

// The page reads positions as f32: the wasm build must keep the default precision.
const _: () = assert!(std::mem::size_of::<crate::math::Real>() == 4);

mod browser;
use browser::now_ms;

fn js_err(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

fn json(v: &impl serde::Serialize) -> String {
    serde_json::to_string(v).unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
}

/// Installs the panic hook (a Rust panic shows in the console with its message).
#[wasm_bindgen(start)]
pub fn start() {
    browser::log_panics();
}

/// The scene JSON of an empty box of dimension 2 or 3 to drop things into.
#[wasm_bindgen(js_name = sandboxScene)]
pub fn sandbox_scene(dim: usize) -> String {
    json(&Playground::sandbox_scene(dim))
}

/// The files a scene references (meshes, vertex lists), as written in it: relative to the
/// scene file. Fetch each and pass their texts to the `Playground` constructor.
#[wasm_bindgen(js_name = assetPaths)]
pub fn asset_paths(scene_json: &str) -> Result<Vec<String>, JsError> {
    crate::playground::asset_paths(scene_json).map_err(js_err)
}

/// Validates a lesson (`lessons/*.json`) as the tests do: `scene_json` is the text of the
/// scene file it names (undefined when the scene is inline), `assets_json` a JSON object of the
/// texts of the files the scene references, keyed by their paths as written in it (see
/// `assetPaths`). Throws naming the field (`view.params[0] = …: does not apply: …`,
/// `scene.bodies[1].material… = …`) or the file missing.
#[wasm_bindgen(js_name = checkLesson)]
pub fn check_lesson(
    lesson_json: &str,
    scene_json: Option<String>,
    assets_json: Option<String>,
) -> Result<(), JsError> {
    let assets = parse_assets(assets_json)?;
    crate::lesson::Lesson::from_texts(lesson_json, scene_json.as_deref(), &assets)
        .map(|_| ())
        .map_err(js_err)
}

fn parse_assets(assets_json: Option<String>) -> Result<HashMap<String, String>, JsError> {
    match assets_json {
        Some(text) => serde_json::from_str(&text)
            .map_err(|e| js_err(format!("assets: {e} (want {{\"path\": \"text\"}})"))),
        None => Ok(HashMap::new()),
    }
}

/// The live parameters, material models and droppable objects, as JSON
/// `{"params": [...], "models": [...], "objects": [...]}`: each parameter's name, model,
/// label, symbol, unit, slider range and scale, default, help text and terminal key (see
/// `crate::params`). The page builds its sliders from it.
#[wasm_bindgen(js_name = parameterTable)]
pub fn parameter_table() -> String {
    json(&serde_json::json!({
        "params": crate::params::table(),
        "models": &*crate::params::MODELS,
        "objects": crate::playground::OBJECTS,
    }))
}

/// The quality levels, as JSON `{"levels": [{id, label, hint, cell_factor, min_particles}, …],
/// "default": id}`: the resolutions a scene can be sampled at (see `Playground.setQuality`).
#[wasm_bindgen(js_name = qualityLevels)]
pub fn quality_levels() -> String {
    json(&serde_json::json!({
        "levels": crate::playground::QUALITIES,
        "default": crate::playground::DEFAULT_QUALITY,
    }))
}

/// A simulation with its presets, live parameters and render buffers: the page's
/// `Playground` class over [`Playground`].
#[wasm_bindgen(js_name = Playground)]
pub struct WebPlayground {
    core: Playground,
    colour: ColourMode,
}

#[wasm_bindgen(js_class = Playground)]
impl WebPlayground {
    /// Builds a playground from scene JSON (the scene-file format of the CLI) and, when the
    /// scene references files (see `assetPaths`), a JSON object of their texts keyed by the
    /// paths as written in the scene, sampled at quality level `quality` (see
    /// `qualityLevels`; the default level when absent).
    #[wasm_bindgen(constructor)]
    pub fn new(
        scene_json: &str,
        assets_json: Option<String>,
        quality: Option<String>,
    ) -> Result<WebPlayground, JsError> {
        let assets = parse_assets(assets_json)?;
        Ok(WebPlayground {
            core: Playground::load(
                scene_json,
                &assets,
                quality
                    .as_deref()
                    .unwrap_or(crate::playground::DEFAULT_QUALITY),
            )
            .map_err(js_err)?,
            colour: ColourMode::Body,
        })
    }

    /// Dropped bunnies use the shipped mesh (`scenes/bunny.obj`, 3D) and silhouette
    /// (`scenes/bunny2d.txt`, 2D) given as text; without them, a bunny made of balls.
    #[wasm_bindgen(js_name = setBunny)]
    pub fn set_bunny(
        &mut self,
        obj: Option<String>,
        polygon: Option<String>,
    ) -> Result<(), JsError> {
        let bunny = BunnyAssets::parse(obj.as_deref(), polygon.as_deref()).map_err(js_err)?;
        self.core.set_bunny(bunny);
        Ok(())
    }

    pub fn dim(&self) -> usize {
        self.core.dim()
    }
    /// The scene as it stands (world, and each body's parameters), as JSON.
    #[wasm_bindgen(js_name = sceneJson)]
    pub fn scene_json(&self) -> String {
        json(self.core.scene())
    }
    #[wasm_bindgen(js_name = particleCount)]
    pub fn particle_count(&self) -> usize {
        self.core.particle_count()
    }
    #[wasm_bindgen(js_name = bodyCount)]
    pub fn body_count(&self) -> usize {
        self.core.body_count()
    }
    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.core.simulation().time()
    }
    #[wasm_bindgen(js_name = stableDt)]
    pub fn stable_dt(&self) -> f64 {
        self.core.simulation().stable_dt()
    }
    /// The diagnostics after the latest step, as JSON (energies, momentum, dt, CFL, …).
    pub fn diagnostics(&self) -> String {
        json(self.core.diagnostics())
    }
    /// Switches sleeping on (material at rest stops being stepped until something touches it;
    /// the default) or off (everything wakes). Reset, Clear and `setQuality` keep the choice.
    #[wasm_bindgen(js_name = setSleeping)]
    pub fn set_sleeping(&mut self, on: bool) {
        self.core.set_sleeping(on);
    }
    /// Whether material at rest sleeps.
    pub fn sleeping(&self) -> bool {
        self.core.sleeping()
    }
    /// How many particles sleep.
    pub fn asleep(&self) -> usize {
        self.core.asleep()
    }
    /// The error that stopped the simulation, or undefined.
    pub fn failure(&self) -> Option<String> {
        self.core.failure()
    }

    /// Advances by up to `sim_time` seconds within `budget_ms` of wall-clock time, stopping at
    /// the next drop to come, which then lands; returns a JSON report (substeps, sim_time,
    /// requested, wall_ms, fell_behind, ms_per_step, stable_dt, and the drops refused).
    pub fn frame(&mut self, sim_time: f64, budget_ms: f64) -> Result<String, JsError> {
        let r = self
            .core
            .frame(sim_time, budget_ms, now_ms)
            .map_err(js_err)?;
        Ok(json(&r))
    }
    /// One time step; returns the JSON report of `frame`.
    pub fn step(&mut self) -> Result<String, JsError> {
        Ok(json(&self.core.step(now_ms).map_err(js_err)?))
    }

    /// Sets a live parameter (a name of `parameterTable`, or `bodies[i].<model>.<field>`),
    /// validated like a scene file; throws naming the parameter and its range, state unchanged.
    /// Returns what the new value costs and what the old one did, as JSON `{prediction,
    /// before}` (each as `predict` gives it, for frames of `frame_time` seconds).
    #[wasm_bindgen(js_name = setParameter)]
    pub fn set_parameter(
        &mut self,
        name: &str,
        value: f64,
        frame_time: f64,
    ) -> Result<String, JsError> {
        let costs = self.core.set_parameter_costed(name, value, frame_time);
        Ok(json(&costs.map_err(js_err)?))
    }
    /// The current value of a live parameter.
    pub fn parameter(&self, name: &str) -> Result<f64, JsError> {
        self.core.parameter(name).map_err(js_err)
    }
    /// Every live parameter and its value, as a JSON object.
    pub fn parameters(&self) -> String {
        json(
            &self
                .core
                .parameters()
                .into_iter()
                .collect::<std::collections::BTreeMap<_, _>>(),
        )
    }
    /// The parameters changed since the scene was loaded, as JSON `[[name, value], …]`.
    pub fn overrides(&self) -> String {
        json(&self.core.overrides())
    }
    /// What a parameter value would cost (JSON: valid, error, stable_dt,
    /// substeps_per_frame, realtime_ratio), without applying it.
    pub fn predict(&self, name: &str, value: f64, frame_time: f64) -> String {
        json(&self.core.predict(name, value, frame_time))
    }

    /// The quality level and resolution the scene is sampled at, as JSON: `quality` (the level's
    /// id), `cell_size`, `scene_cell_size` (m), `particles_per_cell`, and `accuracy`, the
    /// validation errors at that resolution (bar_period, bar_l2, column_runout, column_height,
    /// resting_settlement: relative errors), and `sand`, the level's sand figures in the
    /// scene's dimension (cell_size, particles_per_cell, runout and farthest: relative errors
    /// of the shipped column's run-out at one grain's thickness and at the farthest particle;
    /// flank in degrees).
    pub fn quality(&self) -> String {
        json(self.core.quality())
    }
    /// Samples the scene again at quality level `quality` and starts it again with the session
    /// so far (parameters, Clear, drops at their times); returns JSON `[{drop, error}, …]`, the
    /// drops refused at the new resolution. Throws for an unknown level, state unchanged.
    #[wasm_bindgen(js_name = setQuality)]
    pub fn set_quality(&mut self, quality: &str) -> Result<String, JsError> {
        Ok(json(&self.core.set_quality(quality).map_err(js_err)?))
    }

    /// Adds an object (`bunny`, `ball`, `box`) of a preset material (`elastic`, `von_mises`,
    /// `drucker_prager`, `mohr_coulomb`), `size` m tall, centred at `center`, moving at `velocity`.
    #[wasm_bindgen(js_name = addObject)]
    pub fn add_object(
        &mut self,
        object: &str,
        model: &str,
        center: &[f64],
        velocity: &[f64],
        size: f64,
    ) -> Result<usize, JsError> {
        self.core
            .add_object(object, model, center, velocity, size)
            .map_err(js_err)
    }
    /// Drops an object aimed at `point` (3D: on the floor; 2D: in the box) from above whatever
    /// lies there, falling at `speed` m/s, and records it in the session.
    #[wasm_bindgen(js_name = dropAt)]
    pub fn drop_at(
        &mut self,
        object: &str,
        model: &str,
        point: &[f64],
        speed: f64,
        size: f64,
    ) -> Result<usize, JsError> {
        self.core
            .drop_at(object, model, point, speed, size)
            .map_err(js_err)
    }
    /// Starts pouring the preset sand `material` (`drucker_prager` or `mohr_coulomb`) at `rate`
    /// (m³/s; m²/s in 2D) over `point` on the floor (3D: x and z count; 2D: x), from a spout
    /// held above it, until `stopPour`; records it in the session. Returns the poured body's
    /// index; throws naming the field (`rate`, `point`, `material`) and what is allowed.
    #[wasm_bindgen(js_name = startPour)]
    pub fn start_pour(
        &mut self,
        point: &[f64],
        material: &str,
        rate: f64,
    ) -> Result<usize, JsError> {
        self.core.start_pour(point, material, rate).map_err(js_err)
    }
    /// Stops the pour running now (no layer leaves after the current time); returns how long
    /// it ran (s), or undefined when none runs.
    #[wasm_bindgen(js_name = stopPour)]
    pub fn stop_pour(&mut self) -> Option<f64> {
        self.core.stop_pour()
    }
    /// Whether a pour started by `startPour` runs.
    pub fn pouring(&self) -> bool {
        self.core.pouring()
    }
    /// The rates a pour may have in this scene, as JSON: `unit`, the spout's `radius` and
    /// `height` (m), `exit_area`, `allowed` [lo, hi], `offered` [lo, hi] for a slider, a
    /// `default`, and the exit `speeds` they leave at.
    #[wasm_bindgen(js_name = pourRates)]
    pub fn pour_rates(&self) -> String {
        json(&self.core.pour_rates())
    }
    /// Throws unless `rate` is a rate a pour may have.
    #[wasm_bindgen(js_name = checkRate)]
    pub fn check_rate(&self, rate: f64) -> Result<(), JsError> {
        self.core.check_rate(rate).map_err(js_err)
    }
    /// The sizes a dropped object may have, as JSON: `allowed` [lo, hi], `offered` [lo, hi]
    /// for a slider, and a `default` (m).
    #[wasm_bindgen(js_name = sizeRange)]
    pub fn size_range(&self) -> String {
        json(&self.core.size_range())
    }
    /// Throws unless `size` (m) is a size an object may be dropped at.
    #[wasm_bindgen(js_name = checkSize)]
    pub fn check_size(&self, size: f64) -> Result<(), JsError> {
        self.core.check_size(size).map_err(js_err)
    }
    /// Simulated time since the scene started or was cleared: the clock of the drops (s).
    #[wasm_bindgen(js_name = dropClock)]
    pub fn drop_clock(&self) -> f64 {
        self.core.drop_clock()
    }
    /// The session so far, as JSON `{params: [[name, value], …], cleared, drops: [{t, object,
    /// material, size, centre, velocity, applied_at}, …], pours: [{t, material, rate, spout,
    /// duration, applied_at}, …]}` (`pours` absent when there is none; the pour running with
    /// the time it has run so far).
    pub fn session(&self) -> String {
        json(&self.core.session())
    }
    /// Repeats a session given as JSON (the form `session` returns; `applied_at` is ignored):
    /// returns JSON `{rejected: [message, …], refused: [{drop or pour, error}, …]}`, what did
    /// not apply.
    pub fn replay(&mut self, session_json: &str) -> Result<String, JsError> {
        let replay: crate::playground::Replay =
            serde_json::from_str(session_json).map_err(|e| js_err(format!("session: {e}")))?;
        let (rejected, refused) = self.core.replay(replay);
        Ok(json(
            &serde_json::json!({ "rejected": rejected, "refused": refused }),
        ))
    }
    /// Adds a body given as JSON (a scene file's `bodies[i]`).
    #[wasm_bindgen(js_name = addBodyJson)]
    pub fn add_body_json(&mut self, body_json: &str) -> Result<usize, JsError> {
        let body: crate::BodyConfig = serde_json::from_str(body_json).map_err(js_err)?;
        self.core.add_body(body).map_err(js_err)
    }
    /// The session as a scene file (JSON) that the CLI runs unchanged: the parameters as set,
    /// and each dropped body entering at its drop time (`appear_at`). The meshes and outlines
    /// it references (`assetPaths` of it) must lie beside the file.
    #[wasm_bindgen(js_name = saveScene)]
    pub fn save_scene(&self) -> Result<String, JsError> {
        self.core.saved_scene_json().map_err(js_err)
    }
    /// Removes every body (recorded in the session; the drops and pours so far are forgotten,
    /// a pour running ends).
    pub fn clear(&mut self) {
        self.core.clear();
    }
    /// Reloads the scene with the current parameter overrides; forgets the drops and a Clear.
    pub fn reset(&mut self) -> Result<(), JsError> {
        self.core.reset().map_err(js_err)
    }
    /// The top of the material within `radius` of (x, z): where a dropped object lands.
    #[wasm_bindgen(js_name = surfaceHeight)]
    pub fn surface_height(&self, x: f64, z: f64, radius: f64) -> f64 {
        self.core.surface_height(x, z, radius)
    }

    /// Byte address of the positions in wasm memory (`positionsStride` f32 per particle, the
    /// first `dim` of them x, y (, z)). Valid until
    /// the next call that steps, adds or removes bodies.
    #[wasm_bindgen(js_name = positionsPtr)]
    pub fn positions_ptr(&self) -> usize {
        self.core.positions_ptr() as usize
    }
    /// Floats from one particle's position to the next (2 in 2D, 4 in 3D: x, y, z, unused).
    #[wasm_bindgen(js_name = positionsStride)]
    pub fn positions_stride(&self) -> usize {
        self.core.positions_stride()
    }
    /// Number of f32 in the positions.
    #[wasm_bindgen(js_name = positionsLen)]
    pub fn positions_len(&self) -> usize {
        self.core.positions_len()
    }
    /// Chooses what the colour scalar shows: `body`, `speed`, `pressure`, `plastic_strain`,
    /// `yield`, `sleeping` (the body index awake, −1 − it asleep).
    #[wasm_bindgen(js_name = setColourMode)]
    pub fn set_colour_mode(&mut self, mode: &str) -> Result<(), JsError> {
        self.colour = ColourMode::parse(mode).map_err(js_err)?;
        Ok(())
    }
    /// Recomputes the colour scalars; returns the range the colour map spans `[lo, hi]`.
    #[wasm_bindgen(js_name = updateColours)]
    pub fn update_colours(&mut self) -> Vec<f32> {
        self.core.update_colours(self.colour);
        self.core.colour_range().to_vec()
    }
    /// Byte address of the colour scalars (one f32 per particle).
    #[wasm_bindgen(js_name = coloursPtr)]
    pub fn colours_ptr(&self) -> usize {
        self.core.colours_ptr() as usize
    }
    #[wasm_bindgen(js_name = coloursLen)]
    pub fn colours_len(&self) -> usize {
        self.core.colours_len()
    }
    /// The stable id of particle `index` (particles are reordered for locality).
    #[wasm_bindgen(js_name = particleId)]
    pub fn particle_id(&self, index: usize) -> Result<u32, JsError> {
        Ok(self.core.stress_point(index).map_err(js_err)?.id)
    }
    /// The index of the particle with stable id `id`, or undefined if it is gone.
    #[wasm_bindgen(js_name = indexOf)]
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.core.index_of(id)
    }
    /// The index of the particle nearest `point` (m), or undefined when there is none.
    #[wasm_bindgen(js_name = nearestParticle)]
    pub fn nearest_particle(&self, point: &[f64]) -> Result<Option<usize>, JsError> {
        self.core.nearest_particle(point).map_err(js_err)
    }
    /// Particle `index`'s stress in p–q space and its body's yield surface, as JSON.
    #[wasm_bindgen(js_name = stressPoint)]
    pub fn stress_point(&self, index: usize) -> Result<String, JsError> {
        Ok(json(&self.core.stress_point(index).map_err(js_err)?))
    }
    /// The measures of each sand body (`mpm::measure::deposits`) as JSON: its heap's flank
    /// angles with the fitted lines, its run-out from where it entered, whether it was poured
    /// or held, its plane-strain friction angle (2D) and, for a column, the experiments'
    /// run-out and final height.
    pub fn measures(&mut self) -> String {
        json(&self.core.measures())
    }
}

/// What a ruler and a protractor read between dragged points `a` and `b` (m, 2 or 3
/// components), as JSON: `{length, inclination}` (the angle to the horizontal, degrees).
#[wasm_bindgen(js_name = handMeasure)]
pub fn hand_measure(a: &[f64], b: &[f64]) -> Result<String, JsError> {
    if a.len() != b.len()
        || !(2..=3).contains(&a.len())
        || a.iter().chain(b).any(|x| !x.is_finite())
    {
        return Err(JsError::new(
            "points: must be two points of 2 or 3 finite coordinates each",
        ));
    }
    Ok(format!(
        "{{\"length\":{},\"inclination\":{}}}",
        crate::measure::length(a, b),
        crate::measure::inclination(a, b)
    ))
}

/// The surface and flanks of a 2D heap (`mpm::measure::heap`) of particles at `xy` (x, y
/// pairs, m; spacing `spacing`) over columns of width `bin` tiling `[0, width]`, as JSON: the
/// page's angle readout, computed for any set of points (the tests check the readout with it).
#[wasm_bindgen(js_name = heapMeasure)]
pub fn heap_measure(xy: &[f64], spacing: f64, bin: f64, width: f64) -> Result<String, JsError> {
    if !(xy.len().is_multiple_of(2) && spacing > 0.0 && bin > 0.0 && width >= bin) {
        return Err(JsError::new(
            "heapMeasure: xy holds (x, y) pairs; spacing and bin must be > 0, width >= bin",
        ));
    }
    let points: Vec<(f64, f64)> = xy.chunks(2).map(|p| (p[0], p[1])).collect();
    Ok(json(&crate::measure::heap(
        &points, spacing, bin, 0.0, width,
    )))
}

/// The soil lab's Mohr–Coulomb envelope ([`crate::lab`]) fitted to the failures of several
/// runs: with `kind` `"points"`, `values` holds shear-box failure points [σ_n, τ, σ_n, τ, …];
/// with `"circles"`, biaxial failure circles [σ1, σ3, σ1, σ3, …] (Pa, compression positive).
/// Returns the JSON `{"friction_angle", "cohesion"}` (degrees, Pa), or `null` when the
/// failures fix no envelope (fewer than two distinct normal stresses).
#[wasm_bindgen(js_name = fitEnvelope)]
pub fn fit_envelope(kind: &str, values: &[f64]) -> Result<String, JsError> {
    let pairs: Vec<(f64, f64)> = values.chunks_exact(2).map(|p| (p[0], p[1])).collect();
    let fit = match kind {
        "points" => crate::lab::fit_points(&pairs),
        "circles" => crate::lab::fit_circles(&pairs),
        _ => {
            return Err(js_err(format!(
                "fitEnvelope: kind = {kind:?}: must be \"points\" or \"circles\""
            )));
        }
    };
    Ok(json(&fit))
}

/// What a plane-strain shear box reads on a material of friction angle φ, dilatancy ψ
/// (degrees) and cohesion c (Pa), by Davis (1968): the JSON `{"friction_angle", "cohesion"}`.
#[wasm_bindgen(js_name = davisEnvelope)]
pub fn davis_envelope(friction_angle: f64, dilatancy_angle: f64, cohesion: f64) -> String {
    json(&crate::lab::davis(
        friction_angle,
        dilatancy_angle,
        cohesion,
    ))
}

/// The test a [`LabTest`] reads.
enum LabReader {
    Shear(crate::lab::ShearBox),
    Biaxial(crate::lab::Biaxial),
}

/// A soil-lab test run live ([`crate::lab`]): a plane-strain scene of `scenes/lab/` (a body
/// under a traction makes it a biaxial test, else a shear box), its readings taken from the
/// forces the solver computes, as the CLI's `--lab-csv` takes them.
#[wasm_bindgen]
pub struct LabTest {
    sim: crate::Simulation<crate::D2>,
    reader: LabReader,
    sent: usize,
}

#[wasm_bindgen]
impl LabTest {
    /// Builds the test from scene JSON (dim 2); errors name the field.
    #[wasm_bindgen(constructor)]
    pub fn new(scene_json: &str) -> Result<LabTest, JsError> {
        let scene = crate::SceneConfig::from_json(scene_json).map_err(js_err)?;
        if scene.dim != 2 {
            return Err(js_err(format!(
                "LabTest: dim = {}: the soil tests are plane strain: must be 2",
                scene.dim
            )));
        }
        let biaxial = crate::lab::is_biaxial(&scene);
        let sim = crate::Simulation::<crate::D2>::new(scene).map_err(js_err)?;
        let reader = if biaxial {
            let mut t = crate::lab::Biaxial::new(&sim).map_err(js_err)?;
            t.read(&sim);
            LabReader::Biaxial(t)
        } else {
            let mut t = crate::lab::ShearBox::new(&sim).map_err(js_err)?;
            t.read(&sim);
            LabReader::Shear(t)
        };
        Ok(LabTest {
            sim,
            reader,
            sent: 0,
        })
    }

    /// `"shear_box"` or `"biaxial"`.
    pub fn kind(&self) -> String {
        match self.reader {
            LabReader::Shear(_) => "shear_box".into(),
            LabReader::Biaxial(_) => "biaxial".into(),
        }
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Runs `span` seconds, reading every `every` seconds; returns the readings not yet
    /// returned, as a JSON array (`mpm::lab::ShearReading` or `BiaxialReading` fields).
    pub fn advance(&mut self, span: f64, every: f64) -> Result<String, JsError> {
        if !(span > 0.0 && every > 0.0 && span.is_finite() && every.is_finite()) {
            return Err(js_err(
                "LabTest.advance: span and every must be finite and > 0",
            ));
        }
        let sim = &mut self.sim;
        let (out, n) = match &mut self.reader {
            LabReader::Shear(t) => {
                t.run(sim, span, every).map_err(js_err)?;
                (json(&t.readings[self.sent..].to_vec()), t.readings.len())
            }
            LabReader::Biaxial(t) => {
                t.run(sim, span, every).map_err(js_err)?;
                (json(&t.readings[self.sent..].to_vec()), t.readings.len())
            }
        };
        self.sent = n;
        Ok(out)
    }

    /// The failure read so far, JSON: the shear box's point `[σ_n, τ]` on its shear plane
    /// (the mean over the last quarter of the travel), or the biaxial test's circle `[σ1, σ3]` at its peak deviator (Pa); `null`
    /// before any reading.
    pub fn failure(&self) -> String {
        match &self.reader {
            LabReader::Shear(t) => json(&t.failure()),
            LabReader::Biaxial(t) => json(&t.failure()),
        }
    }

    /// A lesson's soil-lab quantity of this run as its reader reports it
    /// ([`crate::lesson::lab_value`]: `shear_strength`, Pa; `lid_rise`, m); `undefined`
    /// before a reading, for a biaxial test or another name.
    pub fn quantity(&self, name: &str) -> Option<f64> {
        match &self.reader {
            LabReader::Shear(t) => crate::lesson::lab_value(name, t),
            LabReader::Biaxial(_) => None,
        }
    }

    /// The particles as [x, y, body, x, y, body, …] (m; body index), for drawing.
    pub fn particles(&self) -> Vec<f32> {
        let x = &self.sim.particles().x;
        let mut out = Vec::with_capacity(3 * x.len());
        for (b, body) in self.sim.bodies().iter().enumerate() {
            for i in body.range() {
                out.extend([x[i][0], x[i][1], b as f32]);
            }
        }
        out
    }
}

/// The scene (JSON) of run `run` of a soil-lab lesson (`lesson_json`, its scene `scene_json`):
/// the lesson's `lab.set` parameters at the run's load ([`crate::lesson::LabRuns::scene`]).
#[wasm_bindgen(js_name = lessonLabScene)]
pub fn lesson_lab_scene(
    lesson_json: &str,
    scene_json: &str,
    run: usize,
) -> Result<String, JsError> {
    let lesson = crate::lesson::Lesson::from_json(lesson_json).map_err(js_err)?;
    let scene = crate::SceneConfig::from_json(scene_json).map_err(js_err)?;
    let lab = lesson
        .lab
        .ok_or_else(|| js_err("lessonLabScene: the lesson has no lab runs (lab.loads)"))?;
    Ok(json(&lab.scene(&scene, run).map_err(js_err)?))
}

/// A soil-lab scene (JSON) at `load` (Pa): the shear box's lid load (its weight over the
/// box's length) or the biaxial test's σ3 ([`crate::lesson::lab_scene`]), as JSON; errors name the field.
#[wasm_bindgen(js_name = labSceneAt)]
pub fn lab_scene_at(scene_json: &str, load: f64) -> Result<String, JsError> {
    let scene = crate::SceneConfig::from_json(scene_json).map_err(js_err)?;
    let scene = crate::lesson::lab_scene(&scene, load, "load").map_err(js_err)?;
    Ok(json(&scene))
}

/// A soil-lab lesson's answer from its runs' quantities, in the order of the question's
/// `measure.runs` ([`crate::lesson::lab_answer`]: one run's value, or the first's over the
/// second's); `undefined` when they fix none.
#[wasm_bindgen(js_name = labAnswer)]
pub fn lab_answer(values: &[f64]) -> Option<f64> {
    crate::lesson::lab_answer(values)
}
