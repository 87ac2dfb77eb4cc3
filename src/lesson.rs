//! Lessons: guided experiments for a class, one JSON file each in `lessons/`. A lesson is a
//! scene (a path to a scene file, relative to the lesson file, or the scene itself), a title, a
//! short caption that says what to look at and which one or two sliders to move, and the view
//! to show it in (colouring, plot, the sliders, a particle to inspect). The page opens it from
//! its Lessons menu or a link; the tests load every lesson, validate it and run it.
//!
//! ```json
//! { "title": "Friction angle and the heap",
//!   "caption": "Two sand columns collapse: 20° on the left, 40° on the right. …",
//!   "scene": "../scenes/heaps_2d.json",
//!   "view": { "colour": "body", "plot": "energy",
//!             "params": ["bodies[0].drucker_prager.friction_angle"] } }
//! ```

use crate::config::SceneConfig;
use crate::error::{Error, Result, check_non_negative, not_one_of};
use crate::params::Target;
use crate::playground::ColourMode;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// The plots a lesson may show.
pub const PLOTS: [&str; 3] = ["energy", "stress_path", "none"];

/// The longest title and caption (characters): a caption is read at a glance, beside the scene.
pub const MAX_TITLE: usize = 60;
pub const MAX_CAPTION: usize = 480;

/// A guided experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lesson {
    pub title: String,
    /// What to look at, and which one or two sliders to move.
    pub caption: String,
    pub scene: LessonScene,
    #[serde(default)]
    pub view: View,
    /// How long to watch (s of simulated time) before the caption's claim shows: what the
    /// tests run.
    pub duration: f64,
    /// A question asked before the first Play and answered after `duration` by the page's own
    /// measurements.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub question: Option<Question>,
    /// A soil-lab lesson: the scene is a lab test ([`crate::lab`]) run once per load, each
    /// for `duration`, in the page's Lab panel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lab: Option<LabRuns>,
}

/// The runs of a soil-lab lesson: its scene (a shear box, or a biaxial test: a body under a
/// traction) at each load, in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LabRuns {
    /// The load of each run (Pa): the shear box's lid load (its weight over the box's length),
    /// or the biaxial test's confining pressure σ3; one to four.
    pub loads: Vec<f64>,
    /// Parameters set in the scene for every run, by name ([`crate::params`]:
    /// `mohr_coulomb.dilatancy_angle`), before the load.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub set: std::collections::BTreeMap<String, f64>,
    /// A second soil test run after the scene's, at the same loads with the same `set`: the
    /// path of a scene file, relative to the lesson file, of the other kind (a biaxial test
    /// beside a shear box) on the same sand. [`Lesson::load`] and [`Lesson::from_texts`] read
    /// it into [`LabRuns::compared`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare: Option<String>,
    /// The scene of `compare`, once read.
    #[serde(skip)]
    pub compared: Option<Box<SceneConfig>>,
}

impl LabRuns {
    /// Reads the scene file `compare` names (if it names one) into `compared`, with `read`
    /// (given the path as written).
    fn read_compared(&mut self, read: impl FnOnce(&str) -> Result<SceneConfig>) -> Result<()> {
        if let Some(p) = &self.compare {
            self.compared = Some(Box::new(read(p)?));
        }
        Ok(())
    }

    /// The compared test (`compare`, read into `compared`): the other soil test on the same
    /// sand, valid at every load with `set`. Errors name `lab.compare`.
    fn validate_compare(&self, path: &str, scene: &SceneConfig) -> Result<()> {
        let Some(other) = self.compared.as_deref() else {
            return Err(Error::invalid(
                "lab.compare",
                path,
                "the scene file is not read (Lesson::load and Lesson::from_texts read it)",
            ));
        };
        let kind = |s: &SceneConfig| {
            if crate::lab::is_biaxial(s) {
                "a biaxial test (a body under a traction)"
            } else {
                "a shear box"
            }
        };
        if crate::lab::is_biaxial(other) == crate::lab::is_biaxial(scene) {
            return Err(Error::invalid(
                "lab.compare",
                path,
                format!(
                    "must be the other soil test: the scene and it are both {}",
                    kind(scene)
                ),
            ));
        }
        for i in 0..self.loads.len() {
            let at = self.scene(other, i)?;
            at.validate().map_err(|e| match e {
                Error::Invalid {
                    field,
                    value,
                    allowed,
                } => Error::invalid(format!("lab.compare: {field}"), value, allowed),
                e => e,
            })?;
            if lab_sand(&at) != lab_sand(&self.scene(scene, i)?) {
                return Err(Error::invalid(
                    "lab.compare",
                    path,
                    "must test the scene's sand: the same model, friction angle, dilatancy \
                     angle and cohesion (after lab.set)",
                ));
            }
        }
        Ok(())
    }

    /// The scene of run `i`: `scene` with the parameters of `set`, at the run's load.
    pub fn scene(&self, scene: &SceneConfig, i: usize) -> Result<SceneConfig> {
        let load = *self.loads.get(i).ok_or_else(|| {
            Error::invalid("run", i, format!("must be below {}", self.loads.len()))
        })?;
        let mut scene = scene.clone();
        for (name, &v) in &self.set {
            let field = format!("lab.set.{name}");
            Target::parse(name)
                .and_then(|t| t.set_in_scene(&mut scene, v, true))
                .map_err(|e| match e {
                    Error::Invalid { value, allowed, .. } => Error::invalid(&field, value, allowed),
                    e => e,
                })?;
        }
        lab_scene(&scene, load, &format!("lab.loads[{i}]"))
    }
}

/// The soil sample's sand in a lab scene: its model and the parameters of its strength and
/// flow (φ, ψ, c and the cone's match), as written; `None` without a granular body.
fn lab_sand(scene: &SceneConfig) -> Option<(&'static str, Vec<serde_json::Value>)> {
    let body = scene
        .bodies
        .iter()
        .find(|b| !b.kinematic && b.material.behaviour().friction().is_some())?;
    let kind = body.material.kind();
    let fields = serde_json::to_value(&body.material).ok()?;
    let fields = &fields[kind];
    let read = [
        "friction_angle",
        "dilatancy_angle",
        "cohesion",
        "friction_match",
    ];
    Some((kind, read.iter().map(|f| fields[*f].clone()).collect()))
}

/// The highest load a lab lesson runs at (Pa).
pub const MAX_LAB_LOAD: f64 = 1e6;

/// `scene`, a soil-lab test, at `load` (Pa): a biaxial test (a body under a traction) takes it
/// as its confining pressure σ3; a shear box ([`crate::lab::ShearBox`]) as its lid's load, the
/// lid's weight over the box's length, by setting the lid's density
/// ([`crate::lab::lid_density`]; σ_n on the shear plane is then read, not set). Errors name
/// the field; a bad load names `field`.
pub fn lab_scene(scene: &SceneConfig, load: f64, field: &str) -> Result<SceneConfig> {
    if !(load.is_finite() && load > 0.0 && load <= MAX_LAB_LOAD) {
        return Err(Error::invalid(
            field,
            load,
            format!("must be in (0, {MAX_LAB_LOAD}] (Pa)"),
        ));
    }
    let mut scene = scene.clone();
    if let Some(t) = scene.bodies.iter_mut().find_map(|b| b.traction.as_mut()) {
        t.pressure = load;
        return Ok(scene);
    }
    let (lid, density) = crate::lab::lid_density(&scene, load).map_err(|e| match e {
        Error::Invalid { value, .. } => Error::invalid(
            "bodies",
            value,
            "a lab scene is a biaxial test (a body under a traction) or a shear box (a sand sample and a solid lid)",
        ),
        e => e,
    })?;
    let name = format!(
        "bodies[{lid}].{}.density",
        scene.bodies[lid].material.kind()
    );
    Target::parse(&name)?.set_in_scene(&mut scene, density, true)?;
    Ok(scene)
}

/// The quantities a lesson's question can be answered with: what the page measures of its
/// sand bodies ([`crate::measure::deposits`]), then what the soil lab's shear box reads of a
/// run ([`lab_value`]), and how the envelopes fitted to the shear box and the biaxial test
/// differ ([`angle_difference`]).
pub const QUANTITIES: [&str; 6] = [
    "flank_angle",
    "runout",
    "runout_ratio",
    "shear_strength",
    "lid_rise",
    "angle_difference",
];

/// Whether `quantity` is read from soil-lab runs (the shear box's reader, or the envelopes
/// fitted to the runs), not from the page's sand measures.
pub fn is_lab_quantity(quantity: &str) -> bool {
    QUANTITIES[3..].contains(&quantity)
}

/// A soil-lab quantity of one shear-box run, as its reader reports it: `shear_strength` the τ
/// of its failure point ([`crate::lab::ShearBox::failure`]: the mean over the last quarter of
/// the travel, Pa), `lid_rise` the lid's
/// rise at its last reading (m); `None` before a reading or for another quantity.
pub fn lab_value(quantity: &str, test: &crate::lab::ShearBox) -> Option<f64> {
    match quantity {
        "shear_strength" => test.failure().map(|(_, tau)| tau),
        "lid_rise" => test.readings.last().map(|r| r.lid_rise),
        _ => None,
    }
}

/// `angle_difference`: the friction angle of the envelope fitted to a shear box's failure
/// points (σ_n, τ) ([`crate::lab::fit_points`]) less that of the envelope fitted to a biaxial
/// test's failure circles (σ1, σ3) ([`crate::lab::fit_circles`]), degrees; `None` until each
/// test has failures at two different loads. The page takes the same difference of the
/// envelopes it fitted (wasm `fitEnvelope`).
pub fn angle_difference(points: &[(f64, f64)], circles: &[(f64, f64)]) -> Option<f64> {
    let shear = crate::lab::fit_points(points)?;
    let biaxial = crate::lab::fit_circles(circles)?;
    Some(shear.friction_angle - biaxial.friction_angle)
}

/// The answer of a soil-lab question from its runs' values (in the order of `measure.runs`):
/// one run's value, or the first's over the second's.
pub fn lab_answer(values: &[f64]) -> Option<f64> {
    match values {
        [a] => Some(*a),
        [a, b] if *b != 0.0 => Some(a / b),
        _ => None,
    }
}

/// A question with choices, shown before the first Play and answered after the run with the
/// page's measurement of `measure`: the choice whose range holds the measured value is the
/// answer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Question {
    /// The question, as the student reads it.
    pub ask: String,
    pub measure: QuestionMeasure,
    /// Two to five choices, their ranges in increasing order and not overlapping.
    pub choices: Vec<Choice>,
}

/// What answers a question: `quantity` of body `bodies[0]`, less that of `bodies[1]` when
/// two are named. `flank_angle` is the mean of the body's fitted flanks (degrees), `runout`
/// its farthest run-out beyond its footprint (m; in 3D the mean over the sectors),
/// `runout_ratio` that over the footprint's half-width L0 (or R0). A soil-lab quantity of the
/// shear box names `runs` instead (indices into `lab.loads`): run `runs[0]`'s value, over run
/// `runs[1]`'s when two are named; `angle_difference` ([`angle_difference`]) names neither:
/// it compares the envelopes fitted to all the runs of the scene and of `lab.compare`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuestionMeasure {
    pub quantity: String,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<usize>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub runs: Vec<usize>,
}

/// One answer to choose: its text and the range `[low, high)` of the measured value it
/// stands for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Choice {
    pub text: String,
    pub range: [f64; 2],
}

/// The longest question and choice (characters).
pub const MAX_ASK: usize = 200;
pub const MAX_CHOICE: usize = 120;

impl Question {
    /// Checks the question against the lesson's scene and lab runs; errors name the field
    /// path (`question.choices[1].range`).
    pub fn validate(&self, scene: &SceneConfig, lab: Option<&LabRuns>) -> Result<()> {
        let n = self.ask.trim().chars().count();
        if n == 0 || n > MAX_ASK {
            return Err(Error::invalid(
                "question.ask",
                format!("{n} characters"),
                format!("must hold 1 to {MAX_ASK} characters"),
            ));
        }
        if !QUANTITIES.contains(&self.measure.quantity.as_str()) {
            return Err(not_one_of(
                "question.measure.quantity",
                &self.measure.quantity,
                QUANTITIES,
            ));
        }
        if is_lab_quantity(&self.measure.quantity) {
            self.validate_lab(scene, lab)?;
        } else if !self.measure.runs.is_empty() {
            return Err(Error::invalid(
                "question.measure.runs",
                format!("{} runs", self.measure.runs.len()),
                "only a soil-lab quantity of the shear box (shear_strength, lid_rise) names runs",
            ));
        } else if !(1..=2).contains(&self.measure.bodies.len()) {
            return Err(Error::invalid(
                "question.measure.bodies",
                format!("{} bodies", self.measure.bodies.len()),
                "must name 1 body, or 2 (the first less the second)",
            ));
        }
        for (i, &b) in self.measure.bodies.iter().enumerate() {
            let field = format!("question.measure.bodies[{i}]");
            let Some(body) = scene.bodies.get(b) else {
                return Err(Error::invalid(
                    field,
                    b,
                    format!("must be a body of the scene, below {}", scene.bodies.len()),
                ));
            };
            if body.material.behaviour().friction().is_none() {
                let granular: Vec<&str> = crate::material::KINDS
                    .iter()
                    .filter(|k| (k.preset)().behaviour().friction().is_some())
                    .map(|k| k.name)
                    .collect();
                return Err(Error::invalid(
                    field,
                    b,
                    format!(
                        "must be a granular body ({}): the page measures sand",
                        granular.join(" or ")
                    ),
                ));
            }
        }
        if !(2..=5).contains(&self.choices.len()) {
            return Err(Error::invalid(
                "question.choices",
                format!("{} choices", self.choices.len()),
                "must hold 2 to 5 choices",
            ));
        }
        let mut last = f64::NEG_INFINITY;
        for (i, c) in self.choices.iter().enumerate() {
            let n = c.text.trim().chars().count();
            if n == 0 || n > MAX_CHOICE {
                return Err(Error::invalid(
                    format!("question.choices[{i}].text"),
                    format!("{n} characters"),
                    format!("must hold 1 to {MAX_CHOICE} characters"),
                ));
            }
            let [lo, hi] = c.range;
            if !(lo.is_finite() && hi.is_finite() && lo < hi && lo >= last) {
                return Err(Error::invalid(
                    format!("question.choices[{i}].range"),
                    format!("[{lo}, {hi}]"),
                    "must be finite [low, high] with low < high, at or above the range before",
                ));
            }
            last = hi;
        }
        Ok(())
    }
}

impl Question {
    /// A soil-lab question: the lesson has lab runs of a shear box, the measure names one or
    /// two of them and no body.
    fn validate_lab(&self, scene: &SceneConfig, lab: Option<&LabRuns>) -> Result<()> {
        let Some(lab) = lab else {
            return Err(Error::invalid(
                "question.measure.quantity",
                &self.measure.quantity,
                "a soil-lab quantity needs the lesson's lab runs (lab.loads)",
            ));
        };
        if !self.measure.bodies.is_empty() {
            return Err(Error::invalid(
                "question.measure.bodies",
                format!("{} bodies", self.measure.bodies.len()),
                "a soil-lab quantity names runs, not bodies",
            ));
        }
        if self.measure.quantity == "angle_difference" {
            return self.validate_angles(lab);
        }
        if crate::lab::is_biaxial(scene) {
            return Err(Error::invalid(
                "question.measure.quantity",
                &self.measure.quantity,
                "is read from a shear box: the scene is a biaxial test",
            ));
        }
        if !(1..=2).contains(&self.measure.runs.len()) {
            return Err(Error::invalid(
                "question.measure.runs",
                format!("{} runs", self.measure.runs.len()),
                "must name 1 run, or 2 (the first over the second)",
            ));
        }
        for (i, &r) in self.measure.runs.iter().enumerate() {
            if r >= lab.loads.len() {
                return Err(Error::invalid(
                    format!("question.measure.runs[{i}]"),
                    r,
                    format!("must be a run of lab.loads, below {}", lab.loads.len()),
                ));
            }
        }
        Ok(())
    }

    /// `angle_difference`: the lesson runs both tests (`lab.compare`, checked with the
    /// lesson) at two or more different loads, so that each fits an envelope; no run named.
    fn validate_angles(&self, lab: &LabRuns) -> Result<()> {
        if lab.compare.is_none() {
            return Err(Error::invalid(
                "question.measure.quantity",
                &self.measure.quantity,
                "compares the shear box with the biaxial test: the lesson needs lab.compare",
            ));
        }
        if !self.measure.runs.is_empty() {
            return Err(Error::invalid(
                "question.measure.runs",
                format!("{} runs", self.measure.runs.len()),
                "angle_difference compares the envelopes fitted to every run: name no runs",
            ));
        }
        let first = lab.loads.first().copied().unwrap_or(0.0);
        if lab.loads.iter().all(|&l| l == first) {
            return Err(Error::invalid(
                "lab.loads",
                format!("{:?}", lab.loads),
                "angle_difference fits each test's envelope: must hold two or more different loads",
            ));
        }
        Ok(())
    }
}

/// A lesson's scene: a scene file's path (relative to the lesson file) or the scene itself.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum LessonScene {
    Path(String),
    Inline(Box<SceneConfig>),
}

/// How a lesson shows its scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct View {
    /// What the colours show: `body`, `speed`, `pressure`, `plastic_strain` or `yield`.
    #[serde(default = "default_colour")]
    pub colour: String,
    /// The plot shown: `energy`, `stress_path` or `none`.
    #[serde(default = "default_plot")]
    pub plot: String,
    /// The sliders to show, by parameter name (see [`crate::params`]): one to three, the first
    /// one or two those the caption asks to move.
    #[serde(default)]
    pub params: Vec<String>,
    /// Inspect the particle nearest this point (m), to follow its stress path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inspect: Option<Vec<f64>>,
}

fn default_colour() -> String {
    "body".into()
}
fn default_plot() -> String {
    "energy".into()
}

impl Default for View {
    fn default() -> Self {
        View {
            colour: default_colour(),
            plot: default_plot(),
            params: Vec::new(),
            inspect: None,
        }
    }
}

impl Lesson {
    /// Parses a lesson from JSON; errors name the field path (`scene.bodies[0].shape`,
    /// `view.colour`).
    pub fn from_json(text: &str) -> Result<Self> {
        let de = &mut serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            if path == "." || path == "?" || path.is_empty() {
                Error::Parse(format!("lesson: {inner}"))
            } else {
                Error::Parse(format!("{path}: {inner}"))
            }
        })
    }

    /// The path of the scene file, relative to the lesson file, when the scene is not inline.
    pub fn scene_path(&self) -> Option<&str> {
        match &self.scene {
            LessonScene::Path(p) => Some(p),
            LessonScene::Inline(_) => None,
        }
    }

    /// Checks the lesson against its scene (loaded and validated): title and caption, the
    /// colouring and plot names, each parameter (a name the scene's bodies take), the point to
    /// inspect (inside the domain) and the duration. Errors name the field path.
    pub fn validate(&self, scene: &SceneConfig) -> Result<()> {
        for (field, text, max) in [
            ("title", &self.title, MAX_TITLE),
            ("caption", &self.caption, MAX_CAPTION),
        ] {
            let n = text.trim().chars().count();
            if n == 0 || n > max {
                return Err(Error::invalid(
                    field,
                    format!("{n} characters"),
                    format!("must hold 1 to {max} characters"),
                ));
            }
        }
        if ColourMode::parse(&self.view.colour).is_err() {
            return Err(not_one_of(
                "view.colour",
                &self.view.colour,
                ColourMode::ALL.iter().map(|(n, _)| n),
            ));
        }
        if !PLOTS.contains(&self.view.plot.as_str()) {
            return Err(not_one_of("view.plot", &self.view.plot, PLOTS));
        }
        if !(1..=3).contains(&self.view.params.len()) {
            return Err(Error::invalid(
                "view.params",
                format!("{} names", self.view.params.len()),
                "must name 1 to 3 parameters (the sliders the caption asks to move first)",
            ));
        }
        for (i, name) in self.view.params.iter().enumerate() {
            let field = format!("view.params[{i}]");
            let target = Target::parse(name).map_err(|e| match e {
                Error::Invalid { allowed, .. } => Error::invalid(&field, name, allowed),
                e => e,
            })?;
            let mut copy = scene.clone();
            target
                .set_in_scene(&mut copy, target.param.default_value(), true)
                .map_err(|e| match e {
                    Error::Invalid { allowed, .. } => {
                        Error::invalid(&field, name, format!("does not apply: {allowed}"))
                    }
                    e => e,
                })?;
        }
        if let Some(p) = &self.view.inspect {
            crate::geometry::check_vector("view.inspect", p, scene.dim, "m")?;
            for (a, (&x, &size)) in p.iter().zip(&scene.domain.size).enumerate() {
                if !(0.0..=size).contains(&x) {
                    return Err(Error::invalid(
                        format!("view.inspect[{a}]"),
                        x,
                        format!("must lie in the domain [0, {size}] (m)"),
                    ));
                }
            }
        } else if self.view.plot == "stress_path" {
            return Err(Error::invalid(
                "view.inspect",
                "none",
                "a point is needed to show a stress path (the particle nearest it is inspected)",
            ));
        }
        if let Some(lab) = &self.lab {
            if !(1..=4).contains(&lab.loads.len()) {
                return Err(Error::invalid(
                    "lab.loads",
                    format!("{} loads", lab.loads.len()),
                    "must hold 1 to 4 loads (Pa)",
                ));
            }
            for i in 0..lab.loads.len() {
                lab.scene(scene, i)?.validate()?;
            }
            if let Some(path) = &lab.compare {
                lab.validate_compare(path, scene)?;
            }
        }
        if let Some(q) = &self.question {
            q.validate(scene, self.lab.as_ref())?;
        }
        check_non_negative("duration", self.duration, "s")?;
        if !(self.duration > 0.0 && self.duration <= 60.0) {
            return Err(Error::invalid(
                "duration",
                self.duration,
                "must be in (0, 60] (s)",
            ));
        }
        Ok(())
    }

    /// The scene of an inline lesson, with the files it references read by `read` (paths
    /// relative to the lesson file) and validated; errors name the field as `scene.…`.
    pub fn inline_scene(
        &self,
        read: impl FnMut(&str) -> Result<String>,
    ) -> Result<Option<SceneConfig>> {
        let LessonScene::Inline(scene) = &self.scene else {
            return Ok(None);
        };
        let mut scene = (**scene).clone();
        let prefixed = |e: Error| match e {
            Error::Invalid {
                field,
                value,
                allowed,
            } => Error::Invalid {
                field: format!("scene.{field}"),
                value,
                allowed,
            },
            e => e,
        };
        scene.resolve_assets(read).map_err(prefixed)?;
        scene.validate().map_err(prefixed)?;
        Ok(Some(scene))
    }

    /// A lesson from texts, as a web page has them: the lesson's JSON, the text of the scene
    /// file it names (`None` for an inline scene) and the texts of the files the scene
    /// references, keyed by their paths as written in it, with the compared soil test's scene
    /// file keyed by `lab.compare` as written. Validates both; errors name the
    /// field (`view.params[0] = …`, `scene.cfl = …`) or the file missing.
    pub fn from_texts(
        text: &str,
        scene_text: Option<&str>,
        assets: &HashMap<String, String>,
    ) -> Result<(Lesson, SceneConfig)> {
        let mut lesson = Lesson::from_json(text)?;
        let read = |p: &str| {
            assets.get(p).cloned().ok_or_else(|| Error::Io {
                path: p.to_string(),
                message: "not provided (fetch it beside the scene file)".into(),
            })
        };
        let scene = match lesson.scene_path() {
            Some(p) => {
                let text = scene_text.ok_or_else(|| {
                    Error::invalid("scene", p, "the text of this scene file is needed")
                })?;
                SceneConfig::from_json_and_files(text, read)?
            }
            None => lesson.inline_scene(read)?.expect("an inline scene"),
        };
        if let Some(lab) = &mut lesson.lab {
            lab.read_compared(|p| SceneConfig::from_json_and_files(&read(p)?, read))?;
        }
        lesson.validate(&scene)?;
        Ok((lesson, scene))
    }

    /// Reads a lesson file with its scene (a scene file beside it, or inline, with the files it
    /// references), validates both; errors name the file and the field.
    pub fn load(path: &std::path::Path) -> Result<(Lesson, SceneConfig)> {
        let io = |p: &std::path::Path, e: std::io::Error| Error::Io {
            path: p.display().to_string(),
            message: e.to_string(),
        };
        let text = std::fs::read_to_string(path).map_err(|e| io(path, e))?;
        let mut lesson = Lesson::from_json(&text)?;
        let dir = path.parent().unwrap_or(std::path::Path::new(""));
        let scene = match lesson.scene_path() {
            Some(p) => SceneConfig::load(&dir.join(p))?,
            None => lesson
                .inline_scene(|p| {
                    let full = dir.join(p);
                    std::fs::read_to_string(&full).map_err(|e| io(&full, e))
                })?
                .expect("an inline scene"),
        };
        if let Some(lab) = &mut lesson.lab {
            lab.read_compared(|p| SceneConfig::load(&dir.join(p)))?;
        }
        lesson.validate(&scene)?;
        Ok((lesson, scene))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::BodyConfig;
    use crate::{Material, Shape};

    fn scene() -> SceneConfig {
        let mut s = SceneConfig::new(2, &[1.0, 1.0], 0.05);
        s.bodies.push(BodyConfig::new(
            "sand",
            Shape::cuboid(&[0.1, 0.0], &[0.3, 0.3]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, 30.0, 0.0, 0.0),
        ));
        s
    }

    fn lesson(edit: impl FnOnce(&mut serde_json::Value)) -> Result<()> {
        let mut v = serde_json::json!({
            "title": "A heap", "caption": "Watch the heap form; move the friction angle.",
            "scene": "heap.json", "duration": 1.0,
            "view": {"colour": "speed", "plot": "stress_path", "inspect": [0.2, 0.1],
                     "params": ["drucker_prager.friction_angle", "bodies[0].drucker_prager.cohesion"]}
        });
        edit(&mut v);
        Lesson::from_json(&v.to_string())?.validate(&scene())
    }

    #[test]
    fn errors_name_the_field() {
        lesson(|_| {}).unwrap();
        type Edit = Box<dyn FnOnce(&mut serde_json::Value)>;
        let cases: Vec<(Edit, &str)> = vec![
            (
                Box::new(|v| v["view"]["colour"] = "rainbow".into()),
                "view.colour = rainbow: must be one of body, speed",
            ),
            (
                Box::new(|v| v["view"]["plot"] = "histogram".into()),
                "view.plot = histogram: must be one of energy, stress_path, none",
            ),
            (
                Box::new(|v| v["view"]["params"][1] = "von_mises.yield_stress".into()),
                "view.params[1] = von_mises.yield_stress: does not apply: no body of the scene is von_mises",
            ),
            (
                Box::new(|v| v["view"]["params"][0] = "friction".into()),
                "view.params[0] = friction: must be one of gravity",
            ),
            (
                Box::new(|v| v["view"]["params"][0] = "bodies[3].drucker_prager.cohesion".into()),
                "view.params[0] = bodies[3].drucker_prager.cohesion: does not apply: the scene has 1 bodies",
            ),
            (
                Box::new(|v| v["view"]["params"] = serde_json::json!([])),
                "view.params = 0 names: must name 1 to 3 parameters",
            ),
            (
                Box::new(|v| v["view"]["inspect"] = serde_json::json!([0.2, 1.5])),
                "view.inspect[1] = 1.5: must lie in the domain [0, 1] (m)",
            ),
            (
                Box::new(|v| {
                    v["view"].as_object_mut().unwrap().remove("inspect");
                }),
                "view.inspect = none: a point is needed to show a stress path",
            ),
            (
                Box::new(|v| v["duration"] = (-1.0).into()),
                "duration = -1: must be a finite number >= 0 (s)",
            ),
            (
                Box::new(|v| v["caption"] = "".into()),
                "caption = 0 characters: must hold 1 to 480 characters",
            ),
            (
                Box::new(|v| v["view"]["zoom"] = 2.into()),
                "view.zoom: unknown field `zoom`",
            ),
        ];
        for (edit, want) in cases {
            let e = lesson(edit).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  want {want}");
        }
    }

    #[test]
    fn a_question_is_validated_with_field_paths() {
        let ask = |edit: &dyn Fn(&mut serde_json::Value)| {
            lesson(|v| {
                v["question"] = serde_json::json!({
                    "ask": "How far will the sand run out?",
                    "measure": {"quantity": "runout", "bodies": [0]},
                    "choices": [{"text": "under 10 cm", "range": [0, 0.1]},
                                {"text": "10 cm or more", "range": [0.1, 2]}]
                });
                edit(v);
            })
        };
        ask(&|_| ()).unwrap();
        type Edit<'a> = &'a dyn Fn(&mut serde_json::Value);
        let cases: [(Edit, &str); 7] = [
            (&|v| v["question"]["ask"] = "".into(), "question.ask"),
            (
                &|v| v["question"]["measure"]["quantity"] = "colour".into(),
                "question.measure.quantity",
            ),
            (
                &|v| v["question"]["measure"]["bodies"] = serde_json::json!([3]),
                "question.measure.bodies[0]",
            ),
            (
                &|v| v["question"]["choices"] = serde_json::json!([{"text": "a", "range": [0, 1]}]),
                "question.choices",
            ),
            (
                &|v| v["question"]["choices"][1]["range"] = serde_json::json!([0.05, 2]),
                "question.choices[1].range",
            ),
            (
                &|v| v["question"]["choices"][0]["range"] = serde_json::json!([0.1, 0.1]),
                "question.choices[0].range",
            ),
            (
                &|v| v["question"]["choices"][0]["text"] = "".into(),
                "question.choices[0].text",
            ),
        ];
        for (edit, field) in cases {
            let e = ask(edit).unwrap_err().to_string();
            assert!(e.starts_with(&format!("{field} ")), "{field}: {e}");
        }
        // an unknown key names its path
        let e = ask(&|v| v["question"]["hint"] = "x".into())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("question.hint: unknown field `hint`"), "{e}");
    }

    /// A question measures any granular body, whatever its model, and no solid one.
    #[test]
    fn a_question_measures_granular_bodies_of_any_model() {
        let mut s = scene();
        let mc = Material::mohr_coulomb(3.5e5, 0.3, 2200.0, 30.0, 0.0, 0.0);
        s.bodies.push(BodyConfig::new(
            "mc",
            Shape::cuboid(&[0.4, 0.0], &[0.6, 0.3]),
            mc,
        ));
        let solid = Material::elastic(1e5, 0.3, 1000.0);
        s.bodies.push(BodyConfig::new(
            "block",
            Shape::cuboid(&[0.7, 0.0], &[0.9, 0.3]),
            solid,
        ));
        let ask = |bodies: serde_json::Value| {
            let v = serde_json::json!({
                "title": "Two heaps", "caption": "Compare the heaps.", "scene": "heaps.json",
                "duration": 1.0, "view": {"params": ["bodies[1].mohr_coulomb.friction_angle"]},
                "question": {"ask": "Which stands steeper?",
                             "measure": {"quantity": "flank_angle", "bodies": bodies},
                             "choices": [{"text": "the cone", "range": [-90, 0]},
                                         {"text": "Mohr–Coulomb", "range": [0, 90]}]}
            });
            Lesson::from_json(&v.to_string())?.validate(&s)
        };
        ask(serde_json::json!([1, 0])).unwrap();
        let e = ask(serde_json::json!([1, 2])).unwrap_err().to_string();
        assert_eq!(
            e,
            "question.measure.bodies[1] = 2: must be a granular body (drucker_prager or \
             mohr_coulomb): the page measures sand"
        );
    }

    /// A soil-lab question names runs of the lesson's lab loads; its errors name the field.
    #[test]
    fn a_lab_question_names_runs_of_a_shear_box() {
        let shear =
            SceneConfig::from_json(include_str!("../scenes/lab/shear_box_mc_2d.json")).unwrap();
        let ask = |edit: &dyn Fn(&mut serde_json::Value)| {
            let mut v = serde_json::json!({
                "title": "Shear box", "caption": "Twice the load.", "scene": "box.json",
                "duration": 0.4, "view": {"plot": "none", "params": ["mohr_coulomb.friction_angle"]},
                "lab": {"loads": [10000, 20000], "set": {"mohr_coulomb.dilatancy_angle": 10}},
                "question": {"ask": "What τ at twice the load?",
                             "measure": {"quantity": "shear_strength", "runs": [1, 0]},
                             "choices": [{"text": "the same", "range": [0, 1.3]},
                                         {"text": "twice", "range": [1.3, 3]}]}
            });
            edit(&mut v);
            Lesson::from_json(&v.to_string())?.validate(&shear)
        };
        ask(&|_| ()).unwrap();
        type Edit<'a> = &'a dyn Fn(&mut serde_json::Value);
        let cases: [(Edit, &str); 6] = [
            (
                &|v| v["question"]["measure"]["runs"] = serde_json::json!([2]),
                "question.measure.runs[0] = 2: must be a run of lab.loads, below 2",
            ),
            (
                &|v| v["question"]["measure"]["bodies"] = serde_json::json!([0]),
                "question.measure.bodies = 1 bodies: a soil-lab quantity names runs",
            ),
            (
                &|v| {
                    v.as_object_mut().unwrap().remove("lab");
                },
                "question.measure.quantity = shear_strength: a soil-lab quantity needs",
            ),
            (
                &|v| v["lab"]["loads"][1] = (-5.0).into(),
                "lab.loads[1] = -5: must be in (0, 1000000] (Pa)",
            ),
            (
                &|v| v["lab"]["loads"] = serde_json::json!([]),
                "lab.loads = 0 loads: must hold 1 to 4 loads",
            ),
            (
                &|v| v["lab"]["set"] = serde_json::json!({"drucker_prager.friction_angle": 30}),
                "lab.set.drucker_prager.friction_angle = ",
            ),
        ];
        for (edit, want) in cases {
            let e = ask(edit).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  want {want}");
        }
        // the load sets the lid's: its weight over the box's length (0.1 m), as the shear
        // box's reader weighs it on the simulation's particles
        let at = lab_scene(&shear, 20e3, "load").unwrap();
        let lid = &at.bodies[3];
        let g = at.gravity_vector()[1].abs();
        let a = lid.shape.bounds(2);
        let load = lid.material.density() * g * (a.max[1] - a.min[1]) * (a.max[0] - a.min[0]) / 0.1;
        assert!((load / 20e3 - 1.0).abs() < 1e-9, "lid load {load} Pa");
        let sim = crate::Simulation::<crate::D2>::new(at).unwrap();
        let read = crate::lab::ShearBox::new(&sim).unwrap().lid_pressure();
        assert!(
            (read / 20e3 - 1.0).abs() < 0.01,
            "the reader's lid load {read} Pa"
        );
    }

    /// `angle_difference` compares the shear box with the biaxial test of `lab.compare` (read
    /// by `from_texts` from the texts given): the other test, on the same sand, at two or more
    /// loads; errors name the field. The difference is that of the two fitted envelopes,
    /// and none until each test has two failures.
    #[test]
    fn an_angle_question_compares_the_shear_box_with_the_biaxial_test() {
        let shear = include_str!("../scenes/lab/shear_box_mc_2d.json");
        let biaxial = include_str!("../scenes/lab/biaxial_mc_2d.json");
        let check = |edit: &dyn Fn(&mut serde_json::Value), compare: &str| {
            let mut v = serde_json::json!({
                "title": "Two tests", "caption": "The same sand in both.", "scene": "box.json",
                "duration": 0.1, "view": {"plot": "none", "params": ["mohr_coulomb.friction_angle"]},
                "lab": {"loads": [10000, 40000], "compare": "biaxial.json"},
                "question": {"ask": "The same angle?",
                             "measure": {"quantity": "angle_difference"},
                             "choices": [{"text": "lower", "range": [-90, -1]},
                                         {"text": "the same", "range": [-1, 1]},
                                         {"text": "higher", "range": [1, 90]}]}
            });
            edit(&mut v);
            let assets = HashMap::from([("biaxial.json".to_string(), compare.to_string())]);
            Lesson::from_texts(&v.to_string(), Some(shear), &assets).map(|(l, _)| l)
        };
        let lesson = check(&|_| (), biaxial).unwrap();
        let lab = lesson.lab.unwrap();
        assert!(crate::lab::is_biaxial(lab.compared.as_deref().unwrap()));
        // each run of the compared test is its scene at the run's load: σ3
        let scene = SceneConfig::from_json(biaxial).unwrap();
        let at = lab.scene(lab.compared.as_deref().unwrap(), 1).unwrap();
        assert_eq!(at.bodies[0].traction.as_ref().unwrap().pressure, 40e3);
        assert_eq!(at.bodies.len(), scene.bodies.len());
        type Edit<'a> = &'a dyn Fn(&mut serde_json::Value);
        let other_phi = biaxial.replacen("\"friction_angle\": 30", "\"friction_angle\": 35", 1);
        assert_ne!(other_phi, biaxial);
        let cases: [(Edit, &str, &str); 6] = [
            (
                &|v| {
                    v["lab"]
                        .as_object_mut()
                        .unwrap()
                        .remove("compare")
                        .map(|_| ())
                        .unwrap()
                },
                biaxial,
                "question.measure.quantity = angle_difference: compares the shear box with the \
                 biaxial test: the lesson needs lab.compare",
            ),
            (
                &|v| v["question"]["measure"]["runs"] = serde_json::json!([0, 1]),
                biaxial,
                "question.measure.runs = 2 runs: angle_difference compares the envelopes",
            ),
            (
                &|v| v["lab"]["loads"] = serde_json::json!([20000, 20000]),
                biaxial,
                "lab.loads = [20000.0, 20000.0]: angle_difference fits each test's envelope",
            ),
            (
                &|_| (),
                shear,
                "lab.compare = biaxial.json: must be the other soil test: the scene and it are \
                 both a shear box",
            ),
            (
                &|_| (),
                &other_phi,
                "lab.compare = biaxial.json: must test the scene's sand",
            ),
            (
                &|v| v["lab"]["compare"] = "elsewhere.json".into(),
                biaxial,
                "elsewhere.json: not provided",
            ),
        ];
        for (edit, compare, want) in cases {
            let e = check(edit, compare).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e}\n  want {want}");
        }
        // the difference of the two fitted envelopes: Davis's 26.57° less φ = 30°
        let tan = crate::lab::davis(30.0, 0.0, 0.0)
            .friction_angle
            .to_radians()
            .tan();
        let points = [(10e3, 10e3 * tan), (40e3, 40e3 * tan)];
        let kp = (1.0 + 0.5) / (1.0 - 0.5);
        let circles = [(10e3 * kp, 10e3), (40e3 * kp, 40e3)];
        let d = angle_difference(&points, &circles).unwrap();
        assert!((d - (26.565 - 30.0)).abs() < 0.01, "{d}");
        assert_eq!(angle_difference(&points, &circles[..1]), None);
        assert_eq!(angle_difference(&points[..1], &circles), None);
    }

    #[test]
    fn from_texts_takes_the_scene_and_its_files_as_texts() {
        let lesson = serde_json::json!({
            "title": "t", "caption": "c", "duration": 1.0,
            "view": {"params": ["drucker_prager.friction_angle"]},
            "scene": "heap.json",
        })
        .to_string();
        let scene = serde_json::to_string(&scene()).unwrap();
        let none = HashMap::new();
        let (l, s) = Lesson::from_texts(&lesson, Some(&scene), &none).unwrap();
        assert_eq!((l.scene_path(), s.bodies.len()), (Some("heap.json"), 1));
        let e = Lesson::from_texts(&lesson, None, &none).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("scene = heap.json: the text of this scene file is needed"),
            "{e}"
        );
        // An inline scene's outline comes from the texts given, keyed as written.
        let mut v: serde_json::Value = serde_json::from_str(&lesson).unwrap();
        v["scene"] = serde_json::from_str(&scene).unwrap();
        v["scene"]["bodies"][0]["shape"] =
            serde_json::json!({"polygon": {"path": "../outline.txt"}});
        let e = Lesson::from_texts(&v.to_string(), None, &none)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("../outline.txt") && e.contains("not provided"),
            "{e}"
        );
        let outline = HashMap::from([(
            "../outline.txt".to_string(),
            "0.1 0\n0.3 0\n0.3 0.3\n0.1 0.3\n".to_string(),
        )]);
        Lesson::from_texts(&v.to_string(), None, &outline).unwrap();
        v["view"]["params"][0] = "von_mises.yield_stress".into();
        let e = Lesson::from_texts(&v.to_string(), None, &outline)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("view.params[0] = von_mises.yield_stress: does not apply"),
            "{e}"
        );
    }

    #[test]
    fn an_inline_scene_names_its_fields_under_scene() {
        let mut v = serde_json::json!({
            "title": "t", "caption": "c", "duration": 1.0,
            "view": {"params": ["gravity"]},
            "scene": scene(),
        });
        let l = Lesson::from_json(&v.to_string()).unwrap();
        let s = l.inline_scene(|_| unreachable!()).unwrap().unwrap();
        l.validate(&s).unwrap();
        v["scene"]["cfl"] = 3.into();
        let l = Lesson::from_json(&v.to_string()).unwrap();
        let e = l.inline_scene(|_| unreachable!()).unwrap_err().to_string();
        assert_eq!(e, "scene.cfl = 3: must be in [0.001, 1]");
        v["scene"]["bodies"][0]["flip"] = "much".into();
        let e = Lesson::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(e.starts_with("scene"), "{e}");
    }
}
