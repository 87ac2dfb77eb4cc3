//! The live parameters, in one table: what every front end may change while a scene runs,
//! with its label, symbol, unit, slider range, default, help text, the model it belongs to and
//! where in a scene its value lives. The page builds its sliders from this table (exported
//! over wasm), the terminal player its keys, the CLI its `--set` overrides and the page's URL
//! hash its keys; an unknown name gets one message listing every name.
//!
//! Values are validated where scene files are validated ([`SceneConfig::validate`] and the
//! materials' own checks): the slider ranges here are what the sliders offer, not what is
//! allowed. Adding a parameter is one entry here (a [`Field`], listed in [`WORLD`] or in
//! [`MATERIAL_FIELDS`] and named by its models' [`crate::material::Kind::FIELDS`]) and its
//! line in the tests below.
//!
//! Names: `gravity`, `wall_friction`, `cfl` (the world); `<model>.<field>` for every body of a
//! material model and the preset that new bodies of that model are made of, where `<model>` is
//! the scene-file name (`elastic`, `von_mises`, `drucker_prager`, `mohr_coulomb`);
//! `bodies[<i>].<model>.<field>` for body `i` alone. The models and the fields each shows come
//! from their registration ([`crate::material::KINDS`]); a field is described here once
//! ([`MATERIAL_FIELDS`]) for every model that has it.

use crate::config::{BodyConfig, SceneConfig};
use crate::error::{Error, Result, not_one_of};
use crate::material::{KINDS, Material};
use crate::recipe::Recipe;
use serde::Serialize;
use std::sync::LazyLock;

/// How a slider maps its travel to values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SliderScale {
    Linear,
    /// Equal travel multiplies the value by the same factor (moduli, stresses).
    Log,
}

/// How a key of the terminal player changes a value (lower case: down, upper case: up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Nudge {
    /// Multiply (up) or divide (down) by the factor.
    Times(f64),
    /// Add (up) or subtract (down), rounded to 10⁻⁶ so that repeated steps land on round values.
    Plus(f64),
    /// Multiply or divide by `factor`; up from below `floor` gives `floor`, down from `floor` or
    /// below gives 0 (a value that may be zero, on a log scale).
    TimesFrom { factor: f64, floor: f64 },
}

impl Nudge {
    /// The value after one key press.
    pub fn apply(self, value: f64, up: bool) -> f64 {
        match self {
            Nudge::Times(f) if up => value * f,
            Nudge::Times(f) => value / f,
            Nudge::Plus(d) => ((value + if up { d } else { -d }) * 1e6).round() / 1e6,
            Nudge::TimesFrom { factor, floor } if up => (value * factor).max(floor),
            Nudge::TimesFrom { floor, .. } if value <= floor => 0.0,
            Nudge::TimesFrom { factor, .. } => value / factor,
        }
    }
}

/// Where a parameter's value lives in a scene.
#[derive(Clone, Copy, Debug)]
enum Access {
    /// A world setting.
    World {
        get: fn(&SceneConfig) -> f64,
        set: fn(&mut SceneConfig, f64),
    },
    /// The field of a body's material of the same name ([`Material::field_mut`]).
    Material,
    /// A body's PIC/FLIP ratio.
    Flip,
}

/// One parameter as the front ends show it.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Field {
    /// The field's name: a world parameter's full name, or a material field's scene-file name.
    pub field: &'static str,
    pub label: &'static str,
    pub symbol: &'static str,
    /// The unit shown beside the value ("" for none).
    pub unit: &'static str,
    pub help: &'static str,
    /// The range the slider offers.
    pub min: f64,
    pub max: f64,
    /// The slider's step on a linear scale.
    pub step: f64,
    pub scale: SliderScale,
    /// The field of the same model whose value bounds this one from above (ψ ≤ φ).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at_most: Option<&'static str>,
    /// The terminal player's key (lower case).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub key: Option<char>,
    #[serde(skip)]
    pub nudge: Nudge,
    #[serde(skip)]
    access: Access,
}

/// A material model as the front ends show it (from its registration,
/// [`crate::material::KINDS`]).
#[derive(Debug, Serialize)]
pub struct ModelInfo {
    /// The scene-file name.
    pub id: &'static str,
    pub label: &'static str,
    pub hint: &'static str,
    /// Its live parameters, in the order they are shown: the model's own, then the FLIP ratio.
    #[serde(skip)]
    pub fields: Vec<&'static Field>,
    /// The material of new bodies until a scene or a parameter says otherwise.
    #[serde(skip)]
    preset: fn() -> Material,
}

impl ModelInfo {
    /// The material that new bodies of this model are made of by default.
    pub fn preset(&self) -> Material {
        (self.preset)()
    }
}

/// What a field leaves unsaid: a linear slider over [0, 1] in steps of 0.01, no key.
const BLANK: Field = Field {
    field: "",
    label: "",
    symbol: "",
    unit: "",
    help: "",
    min: 0.0,
    max: 1.0,
    step: 0.01,
    scale: SliderScale::Linear,
    at_most: None,
    key: None,
    nudge: Nudge::Plus(0.0),
    access: Access::Flip,
};

pub const GRAVITY: Field = Field {
    field: "gravity",
    label: "Gravity",
    symbol: "g",
    unit: "m/s²",
    help: "downward acceleration",
    max: 30.0,
    access: Access::World {
        get: |s| -s.gravity_vector()[1],
        set: |s, v| {
            let mut g = vec![0.0; s.dim];
            g[1] = -v;
            s.gravity = Some(g);
        },
    },
    ..BLANK
};
pub const WALL_FRICTION: Field = Field {
    field: "wall_friction",
    label: "Wall friction",
    symbol: "μ",
    help: "Coulomb friction of the walls and the ground; 0 slips",
    max: 1.5,
    key: Some('w'),
    nudge: Nudge::Plus(0.05),
    access: Access::World {
        get: |s| s.boundary.friction,
        set: |s, v| s.boundary.friction = v,
    },
    ..BLANK
};
pub const CFL: Field = Field {
    field: "cfl",
    label: "CFL number",
    symbol: "C",
    help: "time step = C · h / (wave speed + |v|max); above about 0.6 stiff solids may go unstable",
    min: 0.05,
    access: Access::World {
        get: |s| s.cfl,
        set: |s, v| s.cfl = v,
    },
    ..BLANK
};
pub const YOUNGS_MODULUS: Field = Field {
    field: "youngs_modulus",
    label: "Young's modulus",
    symbol: "E",
    unit: "Pa",
    help: "stiffness; a stiffer material needs smaller time steps",
    min: 1e3,
    max: 1e8,
    scale: SliderScale::Log,
    key: Some('e'),
    nudge: Nudge::Times(1.25),
    access: Access::Material,
    ..BLANK
};
pub const POISSON_RATIO: Field = Field {
    field: "poisson_ratio",
    label: "Poisson ratio",
    symbol: "ν",
    help: "lateral contraction under stretch; near 0.5 almost incompressible",
    max: 0.49,
    key: Some('n'),
    nudge: Nudge::Plus(0.02),
    access: Access::Material,
    ..BLANK
};
pub const DENSITY: Field = Field {
    field: "density",
    label: "Density",
    symbol: "ρ",
    unit: "kg/m³",
    help: "mass per volume",
    min: 100.0,
    max: 8000.0,
    scale: SliderScale::Log,
    access: Access::Material,
    ..BLANK
};
pub const YIELD_STRESS: Field = Field {
    field: "yield_stress",
    label: "Yield stress",
    symbol: "σ_y",
    unit: "Pa",
    help: "uniaxial stress at which the material flows",
    min: 1e2,
    max: 1e6,
    scale: SliderScale::Log,
    key: Some('y'),
    nudge: Nudge::Times(1.25),
    access: Access::Material,
    ..BLANK
};
pub const FRICTION_ANGLE: Field = Field {
    field: "friction_angle",
    label: "Friction angle",
    symbol: "φ",
    unit: "°",
    help: "the opening of the yield cone: a poured heap stands steeper at a larger angle, up to about this slope; a dropped block collapses, spread by its momentum, and changes less",
    max: 60.0,
    step: 0.5,
    key: Some('f'),
    nudge: Nudge::Plus(2.0),
    access: Access::Material,
    ..BLANK
};
pub const DILATANCY_ANGLE: Field = Field {
    field: "dilatancy_angle",
    label: "Dilatancy angle",
    symbol: "ψ",
    unit: "°",
    help: "volume growth while shearing; at most the friction angle",
    max: 60.0,
    step: 0.5,
    at_most: Some("friction_angle"),
    key: Some('d'),
    nudge: Nudge::Plus(2.0),
    access: Access::Material,
    ..BLANK
};
pub const COHESION: Field = Field {
    field: "cohesion",
    label: "Cohesion",
    symbol: "c",
    unit: "Pa",
    help: "strength at zero pressure; 0 for dry sand",
    max: 5000.0,
    step: 10.0,
    key: Some('c'),
    nudge: Nudge::TimesFrom {
        factor: 1.5,
        floor: 10.0,
    },
    access: Access::Material,
    ..BLANK
};
pub const FLIP: Field = Field {
    field: "flip",
    label: "FLIP ratio",
    symbol: "α",
    help: "0 = PIC (damped; sand: APIC, smooth), 1 = FLIP (lively, noisy)",
    key: Some('a'),
    nudge: Nudge::Plus(0.05),
    access: Access::Flip,
    ..BLANK
};

/// The world parameters, in the order they are shown.
pub static WORLD: [&Field; 3] = [&GRAVITY, &WALL_FRICTION, &CFL];

/// The fields a material model may name in its live parameters ([`crate::material::Kind::FIELDS`]).
pub static MATERIAL_FIELDS: [&Field; 7] = [
    &YOUNGS_MODULUS,
    &POISSON_RATIO,
    &DENSITY,
    &YIELD_STRESS,
    &FRICTION_ANGLE,
    &DILATANCY_ANGLE,
    &COHESION,
];

/// The material models, in the order the page lists them, with their live parameters.
pub static MODELS: LazyLock<Vec<ModelInfo>> = LazyLock::new(|| {
    KINDS
        .iter()
        .map(|k| ModelInfo {
            id: k.name,
            label: k.label,
            hint: k.hint,
            fields: k
                .fields
                .iter()
                .map(|name| {
                    *MATERIAL_FIELDS
                        .iter()
                        .find(|f| f.field == *name)
                        .unwrap_or_else(|| {
                            panic!("{}.{name} has no entry in MATERIAL_FIELDS", k.name)
                        })
                })
                .chain([&FLIP])
                .collect(),
            preset: k.preset,
        })
        .collect()
});

/// The index in [`MODELS`] of the model with scene-file name `id`.
pub fn model_index(id: &str) -> Result<usize> {
    MODELS
        .iter()
        .position(|m| m.id == id)
        .ok_or_else(|| not_one_of("material", id, MODELS.iter().map(|m| m.id)))
}

/// A live parameter: a world setting, or a field of one material model.
#[derive(Clone, Copy, Debug)]
pub struct Param {
    /// The model's index in [`MODELS`]; `None` for the world.
    pub model: Option<usize>,
    pub field: &'static Field,
}

/// What a parameter name refers to: every body of a model (and its preset), or one body.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    pub param: Param,
    /// `Some(i)` for `bodies[i].<model>.<field>`.
    pub body: Option<usize>,
}

/// A parameter's description for the front ends: its [`Field`] with the full name, model and
/// default value.
#[derive(Clone, Debug, Serialize)]
pub struct Spec {
    pub name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<&'static str>,
    pub default: f64,
    #[serde(flatten)]
    pub field: &'static Field,
}

impl Param {
    /// Every live parameter: the world's, then each model's, in the order they are shown.
    pub fn all() -> impl Iterator<Item = Param> {
        let world = WORLD.iter().map(|&field| Param { model: None, field });
        let models = MODELS.iter().enumerate().flat_map(|(m, info)| {
            info.fields.iter().map(move |&field| Param {
                model: Some(m),
                field,
            })
        });
        world.chain(models)
    }

    /// The parameter called `name` (`gravity`, `drucker_prager.friction_angle`, …).
    pub fn find(name: &str) -> Result<Param> {
        let found = match name.split_once('.') {
            None => WORLD
                .iter()
                .find(|f| f.field == name)
                .map(|&field| Param { model: None, field }),
            Some((model, field)) => {
                let m = MODELS.iter().position(|info| info.id == model);
                m.and_then(|m| {
                    let field = *MODELS[m].fields.iter().find(|f| f.field == field)?;
                    Some(Param {
                        model: Some(m),
                        field,
                    })
                })
            }
        };
        found.ok_or_else(|| unknown(name))
    }

    /// The model's scene-file name, or `None` for the world.
    pub fn model_id(&self) -> Option<&'static str> {
        self.model.map(|m| MODELS[m].id)
    }

    /// The full name: `gravity`, or `<model>.<field>`.
    pub fn name(&self) -> String {
        match self.model_id() {
            None => self.field.field.to_string(),
            Some(m) => format!("{m}.{}", self.field.field),
        }
    }

    /// The value of a world parameter in `scene`; `None` for a material parameter.
    pub fn world_value(&self, scene: &SceneConfig) -> Option<f64> {
        match self.field.access {
            Access::World { get, .. } => Some(get(scene)),
            _ => None,
        }
    }

    /// The value for a body of `material` whose PIC/FLIP ratio is `flip` (`None`: the model's
    /// default); `None` for a world parameter or a material without the field.
    pub fn material_value(&self, material: &Material, flip: Option<f64>) -> Option<f64> {
        match self.field.access {
            Access::World { .. } => None,
            Access::Flip => Some(flip.unwrap_or_else(|| Recipe::default_flip(material))),
            Access::Material => material.clone().field_mut(self.field.field).map(|v| *v),
        }
    }

    /// Sets the value for a material and its PIC/FLIP ratio (unvalidated); false if it has no
    /// such field.
    pub fn set_material(&self, material: &mut Material, flip: &mut Option<f64>, v: f64) -> bool {
        match self.field.access {
            Access::World { .. } => false,
            Access::Flip => {
                *flip = Some(v);
                true
            }
            Access::Material => material
                .field_mut(self.field.field)
                .map(|x| *x = v)
                .is_some(),
        }
    }

    /// Checks a preset after this parameter, called `name`, was set in it: the material's own
    /// checks (naming the field `material.<model>.<field>`), or the PIC/FLIP ratio's range.
    pub fn validate_preset(
        &self,
        name: &str,
        material: &Material,
        flip: Option<f64>,
    ) -> Result<()> {
        match self.field.access {
            Access::World { .. } => Ok(()),
            Access::Flip => flip.map_or(Ok(()), |a| crate::config::check_flip(name, a)),
            Access::Material => material.validate("material"),
        }
    }

    /// Whether a body belongs to this parameter's model.
    pub fn applies_to(&self, body: &BodyConfig) -> bool {
        self.model == Some(body.material.index())
    }

    /// Sets the value in `scene` (unvalidated): the world setting, or the field of every body of
    /// the model. Returns how many places changed (0: no body of that model).
    pub fn set_in_scene(&self, scene: &mut SceneConfig, v: f64) -> usize {
        if let Access::World { set, .. } = self.field.access {
            set(scene, v);
            return 1;
        }
        let mut n = 0;
        for b in scene.bodies.iter_mut().filter(|b| self.applies_to(b)) {
            n += usize::from(self.set_material(&mut b.material, &mut b.flip, v));
        }
        n
    }

    /// The value in `scene`: the world setting, or the field of the first body of the model.
    pub fn value_in_scene(&self, scene: &SceneConfig) -> Option<f64> {
        self.world_value(scene).or_else(|| {
            let b = scene.bodies.iter().find(|b| self.applies_to(b))?;
            self.material_value(&b.material, b.flip)
        })
    }

    /// The default: the world's of a new scene, or the model's preset.
    pub fn default_value(&self) -> f64 {
        match self.model {
            None => self
                .world_value(&SceneConfig::new(3, &[1.0; 3], 0.1))
                .unwrap_or(0.0),
            Some(m) => self
                .material_value(&MODELS[m].preset(), None)
                .unwrap_or(0.0),
        }
    }

    /// The description the front ends read.
    pub fn spec(&self) -> Spec {
        Spec {
            name: self.name(),
            model: self.model_id(),
            default: self.default_value(),
            field: self.field,
        }
    }
}

/// Every live parameter's description, in the order they are shown.
pub fn table() -> Vec<Spec> {
    Param::all().map(|p| p.spec()).collect()
}

fn unknown(name: &str) -> Error {
    let names: Vec<String> = Param::all().map(|p| p.name()).collect();
    Error::invalid(
        "parameter",
        name,
        format!(
            "must be one of {} (or bodies[i].<model>.<field> for one body)",
            names.join(", ")
        ),
    )
}

impl Target {
    /// Parses `gravity`, `<model>.<field>` or `bodies[<i>].<model>.<field>`.
    pub fn parse(name: &str) -> Result<Target> {
        let Some(rest) = name.strip_prefix("bodies[") else {
            return Ok(Target {
                param: Param::find(name)?,
                body: None,
            });
        };
        let (index, param) = rest
            .split_once("].")
            .and_then(|(i, p)| Some((i.parse::<usize>().ok()?, p)))
            .ok_or_else(|| unknown(name))?;
        let param = Param::find(param).map_err(|_| unknown(name))?;
        if param.model.is_none() {
            return Err(unknown(name));
        }
        Ok(Target {
            param,
            body: Some(index),
        })
    }

    /// The bodies of `scene` whose material the value `v` changes: none for a world
    /// parameter, every body of the model, or the one body named. Errors when the body named
    /// does not exist or is of another model, or (`require_body`) no body has the parameter's
    /// model.
    pub fn bodies(&self, scene: &SceneConfig, v: f64, require_body: bool) -> Result<Vec<usize>> {
        let name = || match self.body {
            Some(i) => format!("bodies[{i}].{}", self.param.name()),
            None => self.param.name(),
        };
        let model = self.param.model_id().unwrap_or("");
        let Some(_) = self.param.model else {
            return Ok(Vec::new());
        };
        match self.body {
            None => {
                let all: Vec<usize> = (0..scene.bodies.len())
                    .filter(|&i| self.param.applies_to(&scene.bodies[i]))
                    .collect();
                if all.is_empty() && require_body {
                    return Err(Error::invalid(
                        name(),
                        v,
                        format!("no body of the scene is {model}"),
                    ));
                }
                Ok(all)
            }
            Some(i) => {
                let n = scene.bodies.len();
                let body = scene.bodies.get(i).ok_or_else(|| {
                    Error::invalid(name(), v, format!("the scene has {n} bodies"))
                })?;
                if !self.param.applies_to(body) {
                    let kind = body.material.kind();
                    return Err(Error::invalid(
                        name(),
                        v,
                        format!("body {i} is {kind}, not {model}"),
                    ));
                }
                Ok(vec![i])
            }
        }
    }

    /// Sets the value in `scene` (unvalidated). Errors when no body takes it (see
    /// [`Target::bodies`]).
    pub fn set_in_scene(&self, scene: &mut SceneConfig, v: f64, require_body: bool) -> Result<()> {
        if self.param.model.is_none() {
            self.param.set_in_scene(scene, v);
            return Ok(());
        }
        for i in self.bodies(scene, v, require_body)? {
            let b = &mut scene.bodies[i];
            self.param.set_material(&mut b.material, &mut b.flip, v);
        }
        Ok(())
    }
}

/// Parses a `NAME=VALUE` assignment (the CLI's `--set`).
pub fn parse_assignment(text: &str) -> Result<(Target, f64)> {
    let bad = |why: &str| Error::invalid("--set", text, why.to_string());
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| bad("expected NAME=VALUE, e.g. drucker_prager.friction_angle=25"))?;
    let target = Target::parse(name.trim())?;
    let value: f64 = value
        .trim()
        .parse()
        .map_err(|_| bad("the value must be a number"))?;
    Ok((target, value))
}

/// Applies `NAME=VALUE` assignments to a scene in order and validates it: an unknown name, a
/// parameter no body takes, or a value the scene refuses is an error naming it.
pub fn apply_assignments(scene: &mut SceneConfig, assignments: &[String]) -> Result<()> {
    for a in assignments {
        let (target, value) = parse_assignment(a)?;
        target.set_in_scene(scene, value, true)?;
    }
    scene.validate()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;

    fn scene() -> SceneConfig {
        let mut s = SceneConfig::new(2, &[1.0, 1.0], 0.05);
        for (i, m) in MODELS.iter().enumerate() {
            let x = 0.02 + 0.24 * i as f64;
            s.bodies.push(BodyConfig::new(
                m.id,
                Shape::cuboid(&[x, 0.0], &[x + 0.2, 0.2]),
                m.preset(),
            ));
        }
        s
    }

    /// Every parameter, with a value that differs from its default, reads back what was set,
    /// and its default and both slider ends are values the scene accepts.
    #[test]
    fn every_parameter_is_set_read_and_bounded_by_valid_values() {
        let names: Vec<String> = Param::all().map(|p| p.name()).collect();
        assert_eq!(
            names,
            [
                "gravity",
                "wall_friction",
                "cfl",
                "elastic.youngs_modulus",
                "elastic.poisson_ratio",
                "elastic.density",
                "elastic.flip",
                "von_mises.yield_stress",
                "von_mises.youngs_modulus",
                "von_mises.poisson_ratio",
                "von_mises.density",
                "von_mises.flip",
                "drucker_prager.friction_angle",
                "drucker_prager.dilatancy_angle",
                "drucker_prager.cohesion",
                "drucker_prager.youngs_modulus",
                "drucker_prager.poisson_ratio",
                "drucker_prager.density",
                "drucker_prager.flip",
                "mohr_coulomb.friction_angle",
                "mohr_coulomb.dilatancy_angle",
                "mohr_coulomb.cohesion",
                "mohr_coulomb.youngs_modulus",
                "mohr_coulomb.poisson_ratio",
                "mohr_coulomb.density",
                "mohr_coulomb.flip",
            ]
        );
        let defaults: Vec<f64> = Param::all().map(|p| p.default_value()).collect();
        #[rustfmt::skip]
        assert_eq!(defaults, [
            9.81, 0.0, 0.4,
            1e5, 0.3, 1000.0, 0.0,
            5e3, 1e5, 0.3, 1000.0, 0.0,
            35.0, 0.0, 0.0, 3.5e5, 0.3, 2200.0, 0.05,
            35.0, 0.0, 0.0, 3.5e5, 0.3, 2200.0, 0.05,
        ]);
        for p in Param::all() {
            let f = p.field;
            assert!(f.min < f.max, "{}", p.name());
            let mut s = scene();
            assert_eq!(
                p.value_in_scene(&s),
                Some(p.default_value()),
                "{}",
                p.name()
            );
            // The slider's ends and the default validate (ψ after φ at its largest).
            for v in [f.min, f.max, p.default_value()] {
                let mut s = scene();
                if let Some(bound) = f.at_most {
                    let b = Param::find(&format!("{}.{bound}", p.model_id().unwrap())).unwrap();
                    b.set_in_scene(&mut s, b.field.max);
                }
                assert!(p.set_in_scene(&mut s, v) >= 1);
                s.validate()
                    .unwrap_or_else(|e| panic!("{} = {v}: {e}", p.name()));
            }
            let v = 0.5 * (f.min + f.max) + 0.123;
            assert!(p.set_in_scene(&mut s, v) >= 1);
            assert_eq!(p.value_in_scene(&s), Some(v), "{}", p.name());
            // Only the bodies of the parameter's model change.
            for b in &s.bodies {
                if let Some(m) = p.model_id()
                    && b.material.kind() != m
                {
                    let preset = &MODELS[model_index(b.material.kind()).unwrap()].preset();
                    assert_eq!(&b.material, preset, "{}", p.name());
                    assert_eq!(b.flip, None, "{}", p.name());
                }
            }
        }
    }

    #[test]
    fn names_parse_and_unknown_ones_list_the_known() {
        let t = Target::parse("bodies[2].drucker_prager.friction_angle").unwrap();
        assert_eq!(
            (t.param.name(), t.body),
            ("drucker_prager.friction_angle".into(), Some(2))
        );
        for bad in [
            "warp_speed",
            "drucker_prager.colour",
            "bodies[x].elastic.density",
            "bodies[0].gravity",
            "bodies[1]",
        ] {
            let e = Target::parse(bad).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!(
                    "parameter = {bad}: must be one of gravity, wall_friction, cfl, elastic.youngs_modulus"
                )),
                "{e}"
            );
        }
        let mut s = scene();
        let e = Target::parse("bodies[0].drucker_prager.cohesion")
            .unwrap()
            .set_in_scene(&mut s, 5.0, true)
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "bodies[0].drucker_prager.cohesion = 5: body 0 is elastic, not drucker_prager"
        );
        s.bodies.truncate(1);
        let e = apply_assignments(&mut s, &["von_mises.yield_stress=3".into()]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "von_mises.yield_stress = 3: no body of the scene is von_mises"
        );
    }

    #[test]
    fn assignments_apply_in_order_and_are_validated_like_scene_files() {
        let mut s = scene();
        apply_assignments(
            &mut s,
            &[
                "drucker_prager.friction_angle=25".into(),
                " gravity = 3 ".into(),
                "bodies[0].elastic.flip=0.5".into(),
            ],
        )
        .unwrap();
        assert_eq!(s.gravity_vector(), [0.0, -3.0]);
        assert_eq!(s.bodies[0].flip, Some(0.5));
        assert_eq!(
            Param::find("drucker_prager.friction_angle")
                .unwrap()
                .value_in_scene(&s),
            Some(25.0)
        );
        let e = apply_assignments(&mut s, &["drucker_prager.friction_angle=95".into()]);
        assert_eq!(
            e.unwrap_err().to_string(),
            "bodies[2].material.drucker_prager.friction_angle = 95: must be in [0, 90) (degrees)"
        );
        for (bad, why) in [
            ("cfl", "expected NAME=VALUE"),
            ("cfl=fast", "the value must be a number"),
        ] {
            let e = apply_assignments(&mut scene(), &[bad.into()]).unwrap_err();
            assert!(
                e.to_string().starts_with(&format!("--set = {bad}: {why}")),
                "{e}"
            );
        }
    }

    #[test]
    fn keys_are_unique_and_nudges_move_both_ways() {
        let keys: Vec<char> = Param::all().filter_map(|p| p.field.key).collect();
        let mut unique = keys.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(
            WORLD.len() + MODELS.iter().map(|m| m.fields.len()).sum::<usize>(),
            Param::all().count()
        );
        // Each key once per field (a field shared by models keeps its key).
        let fields: std::collections::BTreeSet<&str> = Param::all()
            .filter(|p| p.field.key.is_some())
            .map(|p| p.field.field)
            .collect();
        assert_eq!(unique.len(), fields.len(), "{keys:?}");
        assert_eq!(Nudge::Plus(2.0).apply(30.0, true), 32.0);
        assert_eq!(Nudge::Plus(0.02).apply(0.3, false), 0.28);
        assert_eq!(Nudge::Times(1.25).apply(8.0, false), 6.4);
        let c = COHESION.nudge;
        assert_eq!(c.apply(0.0, true), 10.0);
        assert_eq!(c.apply(10.0, true), 15.0);
        assert_eq!(c.apply(15.0, false), 10.0);
        assert_eq!(c.apply(10.0, false), 0.0);
    }
}
