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

    /// Reads a lesson file with its scene (a scene file beside it, or inline, with the files it
    /// references), validates both; errors name the file and the field.
    pub fn load(path: &std::path::Path) -> Result<(Lesson, SceneConfig)> {
        let io = |p: &std::path::Path, e: std::io::Error| Error::Io {
            path: p.display().to_string(),
            message: e.to_string(),
        };
        let text = std::fs::read_to_string(path).map_err(|e| io(path, e))?;
        let lesson = Lesson::from_json(&text)?;
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
