//! The parameter types of a simulation: one source of truth for scene files, the builder,
//! the CLI and the page. Everything is SI: metres, seconds, kilograms, pascals; angles in
//! degrees.

use crate::error::{Error, Result, check_non_negative, check_positive, check_range};
use crate::geometry::{AssetLoader, Shape, check_vector};
use crate::kernel::KernelKind;
use crate::material::Material;
use serde::{Deserialize, Serialize};

/// At most this many particles in one simulation (a clear error instead of an endless build).
pub const MAX_PARTICLES: usize = 20_000_000;

/// A whole scene: the world and its bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneConfig {
    #[serde(default)]
    pub name: String,
    /// 2 (plane strain) or 3.
    pub dim: usize,
    pub domain: DomainConfig,
    /// Grid spacing h (m).
    pub cell_size: f64,
    /// Gravity (m/s²); default −9.81 along y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<Vec<f64>>,
    /// CFL number of the adaptive time step, in (0, 1].
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// Upper bound of the time step (s).
    #[serde(default = "default_max_dt")]
    pub max_dt: f64,
    #[serde(default)]
    pub boundary: BoundaryConfig,
    #[serde(default)]
    pub kernel: KernelKind,
    #[serde(default)]
    pub contact: ContactConfig,
    #[serde(default)]
    pub bodies: Vec<BodyConfig>,
}

/// The simulation box: `[0, size]` along each axis, walled on every side.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainConfig {
    pub size: Vec<f64>,
}

/// Walls and ground: Coulomb friction μ ≥ 0 (0 is free slip), or sticky (no motion at all).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryConfig {
    #[serde(default)]
    pub friction: f64,
    #[serde(default)]
    pub sticky: bool,
}

/// Contact between bodies (Sec. 4.3). Without `friction`, the paper's rule: approaching
/// bodies take their common centre-of-mass velocity at shared nodes. With `friction` = μ,
/// Bardenhagen et al.'s rule: only the approaching normal velocity is removed, and the
/// tangential slip is resisted by Coulomb friction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactConfig {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
}

/// One body: a shape filled with particles of one material, or a stream poured from a spout
/// (`pour`, then without a shape).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyConfig {
    #[serde(default)]
    pub name: String,
    /// The region the particles fill; absent in the file ([`Shape::absent`]) for a poured
    /// body.
    #[serde(default = "Shape::absent", skip_serializing_if = "Shape::is_absent")]
    pub shape: Shape,
    pub material: Material,
    /// Initial velocity (m/s), default zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<Vec<f64>>,
    /// Particles per cell along each axis (1 to 8).
    #[serde(default = "default_ppc")]
    pub particles_per_cell: u32,
    /// PIC/FLIP ratio α ∈ [0, 1]; default 0.05 for sand, 0 for solids (the paper's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip: Option<f64>,
    /// Moves each lattice particle by up to this fraction of the particle spacing along each
    /// axis, in [0, 0.5); 0 (the default) keeps the regular lattice.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub jitter: f64,
    /// Seed of the jitter: the same seed gives the same particles on every run.
    #[serde(default, skip_serializing_if = "is_zero_u64")]
    pub seed: u64,
    /// A kinematic body keeps its initial velocity whatever acts on it (a piston, a moving
    /// plate, a fixed obstacle when the velocity is zero): it carries no stress, ignores gravity
    /// and the walls (it only stays inside the domain), and the bodies it touches feel it as
    /// infinitely heavy. The force they exert on it is its `contact_force`.
    #[serde(default, skip_serializing_if = "is_false")]
    pub kinematic: bool,
    /// Transfer velocities with APIC (Jiang et al. 2015; the paper's Sec. 6 names it as future
    /// work): each particle carries an affine velocity field, which keeps the angular momentum
    /// and the detail that PIC smears, without FLIP's noise. `flip` still blends in FLIP.
    /// Absent: the material's default ([`crate::recipe::Recipe`]: APIC for Drucker–Prager
    /// sand with the `gimp` and `quadratic_bspline` kernels, PIC for solids). `true` needs the
    /// `gimp` or `quadratic_bspline` kernel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub apic: Option<bool>,
    /// Update the stress at the end of the step (`true`) or first, in Sec. 4.2's order
    /// (`false`). Absent: the material's default ([`crate::recipe::Recipe`]: first for sand,
    /// last for solids with the `gimp` and `quadratic_bspline` kernels). `true` needs the
    /// `gimp` or `quadratic_bspline` kernel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stress_last: Option<bool>,
    /// Close parted grains again (granular materials): sand whose grains have parted (no
    /// compression, a volume beyond its packed m/ρ) regains its density when pressed together
    /// before it carries stress ([`crate::step::stress`]). Absent: on for a poured body, whose
    /// stream parts tenfold, off otherwise ([`crate::recipe::Recipe`]). `true` needs a granular
    /// material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub close_grains: Option<bool>,
    /// When the body enters (s of simulated time): it is sampled when the scene is built and
    /// added, with its shape and `velocity`, once the simulation reaches this time. Absent or
    /// 0: from the start. A playground's saved scene gives each dropped body its drop time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub appear_at: Option<f64>,
    /// A pressure on faces of the body's free surface (a confining pressure σ3): see
    /// [`TractionConfig`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<TractionConfig>,
    /// A spout that pours the body's particles, instead of a shape: see [`PourConfig`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pour: Option<PourConfig>,
}

/// A spout pouring the body's material (the funnel of an angle-of-repose test, ISO 4324): a
/// stream leaves the exit, a section about the vertical axis through `spout` (a disc of
/// `radius` in 3D, a segment of half-width `radius` in 2D), downwards at `rate` over `duration`
/// from the body's `appear_at`. How the stream is made of particles: [`crate::sim::pour`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PourConfig {
    /// The centre of the exit (m), with the section at least one cell from every wall.
    pub spout: Vec<f64>,
    /// The exit's radius (m; in 2D its half-width), from one cell to a quarter of the smallest
    /// side of the domain.
    pub radius: f64,
    /// The volume leaving the exit per second Q (m³/s; m²/s per metre of depth in 2D), at most
    /// what leaves at [`MAX_EXIT_SPEED`].
    pub rate: f64,
    /// How long the spout runs T (s), in (0, [`MAX_POUR_DURATION`]].
    pub duration: f64,
}

/// The fastest exit speed of a spout accepted (m/s): ten times the speed of a funnel's stream
/// in an angle-of-repose test, far below the sand's wave speed.
pub const MAX_EXIT_SPEED: f64 = 10.0;

/// The longest a spout may run (s).
pub const MAX_POUR_DURATION: f64 = 1e3;

/// A traction boundary: a pressure (Pa, compression positive) on faces of the body's
/// bounding box. The particles in the outermost lattice layer of each face are its surface
/// particles, each carrying its share of the face's area and the face's normal, N dA; the
/// area is carried with the deformation (Nanson: n da = J F⁻ᵀ N dA) and the force −p n da is
/// applied to the grid as an external force ([`crate::step::traction`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TractionConfig {
    /// The pressure p ≥ 0 (Pa; compression positive).
    pub pressure: f64,
    /// The loaded faces: `left`, `right` (x), `bottom`, `top` (y), `back`, `front` (z, 3D).
    pub faces: Vec<Face>,
    /// The rise time (s): the pressure grows linearly from zero at t = 0 to `pressure` at
    /// t = `rise_time`, as a triaxial cell is pressurised; 0 (the default) loads it at once.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rise_time: f64,
}

/// A face of a body's bounding box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Face {
    Left,
    Right,
    Bottom,
    Top,
    Back,
    Front,
}

impl Face {
    /// The axis the face is normal to and the sign of its outward normal.
    pub fn axis_and_sign(self) -> (usize, f64) {
        match self {
            Face::Left => (0, -1.0),
            Face::Right => (0, 1.0),
            Face::Bottom => (1, -1.0),
            Face::Top => (1, 1.0),
            Face::Back => (2, -1.0),
            Face::Front => (2, 1.0),
        }
    }
}

/// The largest traction pressure accepted (Pa): far beyond any soil test, small enough that
/// the step stays finite.
pub const MAX_TRACTION: f64 = 1e9;

/// The longest traction rise time accepted (s).
pub const MAX_RISE_TIME: f64 = 1e3;

impl TractionConfig {
    /// The fraction of the pressure applied at time `t` (s): t / rise time, at most 1.
    pub fn ramp(&self, t: f64) -> f64 {
        if self.rise_time > 0.0 {
            (t / self.rise_time).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// Checks the traction of a body of dimension `dim`; `path` names it
    /// (`bodies[0].traction`). A pull (negative pressure) is refused: the surface particles
    /// of sand would be torn off, and no test here needs one.
    pub fn validate(&self, path: &str, dim: usize) -> Result<()> {
        check_range(
            format!("{path}.pressure"),
            self.pressure,
            0.0,
            MAX_TRACTION,
            false,
            "Pa, compression positive; a pull is not supported",
        )?;
        check_range(
            format!("{path}.rise_time"),
            self.rise_time,
            0.0,
            MAX_RISE_TIME,
            false,
            "s; 0 loads at once",
        )?;
        if self.faces.is_empty() {
            return Err(Error::invalid(
                format!("{path}.faces"),
                "[]",
                "must name at least one face: left, right, bottom, top (and back, front in 3D)",
            ));
        }
        for (i, f) in self.faces.iter().enumerate() {
            let (axis, _) = f.axis_and_sign();
            if axis >= dim {
                return Err(Error::invalid(
                    format!("{path}.faces[{i}]"),
                    format!("{f:?}").to_lowercase(),
                    "is a face of 3D bodies only: in 2D use left, right, bottom, top",
                ));
            }
            if self.faces[..i].contains(f) {
                return Err(Error::invalid(
                    format!("{path}.faces[{i}]"),
                    format!("{f:?}").to_lowercase(),
                    "names a face twice",
                ));
            }
        }
        Ok(())
    }

    /// Each sampled point's area vector N dA (3 components): the sum over the loaded faces it
    /// lies on of the face's outward normal times `spacing`^(dim−1), a point lying on a face
    /// when it is within one lattice `spacing` of it (the outermost layer). `min`, `max`: the
    /// body's bounding box.
    pub fn area_vectors(
        &self,
        points: &[[f64; 3]],
        dim: usize,
        spacing: f64,
        min: [f64; 3],
        max: [f64; 3],
    ) -> Vec<[f64; 3]> {
        let da = spacing.powi(dim as i32 - 1);
        points
            .iter()
            .map(|x| {
                let mut a = [0.0; 3];
                for f in &self.faces {
                    let (axis, sign) = f.axis_and_sign();
                    let depth = if sign > 0.0 {
                        max[axis] - x[axis]
                    } else {
                        x[axis] - min[axis]
                    };
                    if depth < spacing {
                        a[axis] += sign * da;
                    }
                }
                a
            })
            .collect()
    }
}

fn is_false(x: &bool) -> bool {
    !*x
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}
fn is_zero_u64(x: &u64) -> bool {
    *x == 0
}

/// A PIC/FLIP ratio α must lie in [0, 1]; `field` names it.
pub fn check_flip(field: impl std::fmt::Display, alpha: f64) -> Result<()> {
    check_range(field, alpha, 0.0, 1.0, false, "")
}

/// At most this many lattice points are tested when a shape is sampled (a clear error instead
/// of an endless loop over a huge bounding box).
pub const MAX_LATTICE_POINTS: f64 = 2.0e8;

fn default_cfl() -> f64 {
    0.4
}
fn default_max_dt() -> f64 {
    1e-3
}
fn default_ppc() -> u32 {
    2
}

impl BodyConfig {
    /// A body with default particle density, zero velocity and the paper's α.
    pub fn new(name: &str, shape: Shape, material: Material) -> Self {
        BodyConfig {
            name: name.to_string(),
            shape,
            material,
            velocity: None,
            particles_per_cell: default_ppc(),
            flip: None,
            jitter: 0.0,
            seed: 0,
            kinematic: false,
            apic: None,
            stress_last: None,
            close_grains: None,
            appear_at: None,
            traction: None,
            pour: None,
        }
    }
    /// A body poured from a spout (no shape): `pour` says where, how fast and how long.
    pub fn poured(name: &str, pour: PourConfig, material: Material) -> Self {
        BodyConfig {
            pour: Some(pour),
            ..Self::new(name, Shape::absent(), material)
        }
    }
    /// Puts a pressure `pressure` (Pa) on the body's `faces`.
    pub fn with_traction(mut self, pressure: f64, faces: &[Face]) -> Self {
        self.traction = Some(TractionConfig {
            pressure,
            faces: faces.to_vec(),
            rise_time: 0.0,
        });
        self
    }
    /// Makes the body enter when the simulation reaches time `t` (s).
    pub fn appearing_at(mut self, t: f64) -> Self {
        self.appear_at = Some(t);
        self
    }
    /// When the body enters (s): its `appear_at`, or 0.
    pub fn appear_time(&self) -> f64 {
        self.appear_at.unwrap_or(0.0)
    }
    /// Transfers this body's velocities with APIC.
    pub fn with_apic(mut self) -> Self {
        self.apic = Some(true);
        self
    }
    /// Updates this body's stress at the end of the step (`true`) or first (`false`).
    pub fn with_stress_last(mut self, last: bool) -> Self {
        self.stress_last = Some(last);
        self
    }
    /// Closes this body's parted grains again (`true`) or lets them stay loose (`false`).
    pub fn with_close_grains(mut self, close: bool) -> Self {
        self.close_grains = Some(close);
        self
    }
    /// Transfers this body's velocities with the paper's PIC/FLIP blend only (no APIC).
    pub fn without_apic(mut self) -> Self {
        self.apic = Some(false);
        self
    }
    /// Makes the body kinematic: it moves at its initial velocity whatever acts on it.
    pub fn kinematic(mut self) -> Self {
        self.kinematic = true;
        self
    }
    /// Jitters the lattice by up to `jitter` (in [0, 0.5)) of the particle spacing, from
    /// `seed`.
    pub fn with_jitter(mut self, jitter: f64, seed: u64) -> Self {
        self.jitter = jitter;
        self.seed = seed;
        self
    }
    pub fn with_velocity(mut self, v: &[f64]) -> Self {
        self.velocity = Some(v.to_vec());
        self
    }
    pub fn with_particles_per_cell(mut self, n: u32) -> Self {
        self.particles_per_cell = n;
        self
    }
    pub fn with_flip(mut self, alpha: f64) -> Self {
        self.flip = Some(alpha);
        self
    }
    /// Checks the body against a world of dimension `dim` and extent `domain`; `path` names
    /// it (e.g. `bodies[2]`).
    pub fn validate(&self, path: &str, dim: usize, domain: &[f64]) -> Result<()> {
        if self.pour.is_some() {
            self.check_poured(path)?;
        } else if self.shape.is_absent() {
            return Err(Error::invalid(
                format!("{path}.shape"),
                "absent, and no pour",
                "a body needs a shape, or a pour (a stream poured from a spout) instead",
            ));
        } else {
            self.shape.validate(&format!("{path}.shape"), dim)?;
        }
        Self::check_material(path, &self.material, self.flip)?;
        if let Some(v) = &self.velocity {
            check_vector(&format!("{path}.velocity"), v, dim, "m/s")?;
        }
        if !(1..=8).contains(&self.particles_per_cell) {
            return Err(Error::invalid(
                format!("{path}.particles_per_cell"),
                self.particles_per_cell,
                "must be an integer in [1, 8]",
            ));
        }
        if let Some(t) = self.appear_at {
            check_non_negative(format!("{path}.appear_at"), t, "s")?;
        }
        if let Some(t) = &self.traction {
            t.validate(&format!("{path}.traction"), dim)?;
            if self.kinematic {
                return Err(Error::invalid(
                    format!("{path}.traction"),
                    "a traction on a kinematic body",
                    "must be on a body that moves under forces (not kinematic)",
                ));
            }
        }
        check_range(
            format!("{path}.jitter"),
            self.jitter,
            0.0,
            0.5,
            true,
            "of the particle spacing",
        )?;
        if self.pour.is_some() {
            return Ok(()); // the spout is checked with the grid: SceneConfig::check_pour
        }
        let b = self.shape.bounds(dim);
        for a in 0..dim {
            let tol = 1e-9 * domain[a];
            if b.min[a] < -tol || b.max[a] > domain[a] + tol {
                return Err(Error::invalid(
                    format!("{path}.shape"),
                    format!("extent [{}, {}] along axis {a}", b.min[a], b.max[a]),
                    format!("must lie inside the domain [0, {}]", domain[a]),
                ));
            }
        }
        Ok(())
    }

    /// What a poured body (named `path`) may not have: a shape (its particles come from the
    /// spout), a kinematic motion or a traction (a stream moves under forces, and has no faces
    /// of a box to load), an initial velocity (the stream leaves at the exit speed).
    fn check_poured(&self, path: &str) -> Result<()> {
        if !self.shape.is_absent() {
            return Err(Error::invalid(
                format!("{path}.shape"),
                format!("a {} and a pour", self.shape.kind()),
                "a body has a shape or a pour (a stream poured from a spout), not both",
            ));
        }
        if self.kinematic {
            return Err(Error::invalid(
                format!("{path}.kinematic"),
                true,
                "must be false for a poured body (a stream moves under forces)",
            ));
        }
        if self.traction.is_some() {
            return Err(Error::invalid(
                format!("{path}.traction"),
                "a traction on a poured body",
                "must be absent for a poured body (a stream has no faces of a box to load)",
            ));
        }
        if let Some(v) = self
            .velocity
            .as_ref()
            .filter(|v| v.iter().any(|&c| c != 0.0))
        {
            return Err(Error::invalid(
                format!("{path}.velocity"),
                format!("{v:?}"),
                "must be absent or zero for a poured body (the stream leaves the spout at rate / exit area, downwards)",
            ));
        }
        Ok(())
    }

    /// Checks a material and a PIC/FLIP ratio for the body `path` (`bodies[1]`), as part of
    /// [`BodyConfig::validate`].
    pub fn check_material(path: &str, material: &Material, flip: Option<f64>) -> Result<()> {
        material.validate(&format!("{path}.material"))?;
        if let Some(a) = flip {
            check_flip(format!("{path}.flip"), a)?;
        }
        Ok(())
    }

    /// Samples the body's shape into particle positions (3 components, unused ones zero) and
    /// the volume of each, on a lattice of `particles_per_cell` per axis and cell of
    /// `cell_size`, jittered by `jitter` and `seed`. The body must be valid; `path` names it in
    /// errors (a lattice too large to test).
    pub fn sample(&self, path: &str, dim: usize, cell_size: f64) -> Result<(Vec<[f64; 3]>, f64)> {
        let candidates = self
            .shape
            .lattice_candidates(dim, cell_size, self.particles_per_cell);
        if candidates > MAX_LATTICE_POINTS {
            return Err(Error::invalid(
                format!("{path}.shape"),
                format!("a shape spanning {candidates:.3e} lattice points"),
                format!(
                    "must span at most {MAX_LATTICE_POINTS:e} lattice points at this cell_size and particles_per_cell"
                ),
            ));
        }
        Ok(self.shape.sample_jittered(
            dim,
            cell_size,
            self.particles_per_cell,
            self.jitter,
            self.seed,
        ))
    }
}

/// Validated world settings shared by every body.
impl SceneConfig {
    /// An empty scene of dimension `dim` with the given domain size and cell size, default
    /// gravity, CFL 0.4, max dt 1 ms, slip walls.
    pub fn new(dim: usize, size: &[f64], cell_size: f64) -> Self {
        SceneConfig {
            name: String::new(),
            dim,
            domain: DomainConfig {
                size: size.to_vec(),
            },
            cell_size,
            gravity: None,
            cfl: default_cfl(),
            max_dt: default_max_dt(),
            boundary: BoundaryConfig::default(),
            kernel: KernelKind::default(),
            contact: ContactConfig::default(),
            bodies: Vec::new(),
        }
    }

    /// Parses a scene from JSON; errors name the offending field path.
    pub fn from_json(text: &str) -> Result<Self> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let scene: SceneConfig = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            if path == "." || path == "?" || path.is_empty() {
                Error::Parse(format!("scene: {inner}"))
            } else {
                Error::Parse(format!("{path}: {inner}"))
            }
        })?;
        Ok(scene)
    }

    /// A scene from its JSON and the files it references: parses it, loads the meshes and
    /// vertex lists through `read` ([`Self::resolve_assets`]) and validates it. Errors name the
    /// field or the file.
    pub fn from_json_and_files(
        text: &str,
        read: impl FnMut(&str) -> Result<String>,
    ) -> Result<Self> {
        let mut scene = Self::from_json(text)?;
        scene.resolve_assets(read)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads a scene file: [`Self::from_json_and_files`] with the referenced files' paths
    /// relative to the scene file's directory. Errors name the file or the field.
    pub fn load(path: &std::path::Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let dir = path.parent().unwrap_or(std::path::Path::new(""));
        Self::from_json_and_files(&text, |p| {
            let full = dir.join(p);
            std::fs::read_to_string(&full).map_err(|e| Error::Io {
                path: full.display().to_string(),
                message: e.to_string(),
            })
        })
    }

    /// Every external file the scene references (meshes, vertex lists), as written in it
    /// (relative to the scene file), in order of appearance, each once.
    pub fn asset_paths(&self) -> Vec<String> {
        let mut all = Vec::new();
        for b in &self.bodies {
            b.shape.asset_paths(&mut all);
        }
        let mut seen = std::collections::HashSet::new();
        all.retain(|p| seen.insert(p.clone()));
        all
    }

    /// Loads every external file the scene references: `read` returns a file's text given
    /// its path as written in the scene (see [`SceneConfig::asset_paths`]); each file is read
    /// once and parsed into the shapes, so that building the simulation needs no file access.
    /// Errors name the field (e.g. `bodies[0].shape.mesh.path`) and the file.
    pub fn resolve_assets(&mut self, mut read: impl FnMut(&str) -> Result<String>) -> Result<()> {
        let mut loader = AssetLoader::new(&mut read);
        for (i, b) in self.bodies.iter_mut().enumerate() {
            b.shape
                .resolve_assets(&format!("bodies[{i}].shape"), &mut loader)?;
        }
        Ok(())
    }

    /// Gravity in effect (default −9.81 m/s² along y).
    pub fn gravity_vector(&self) -> Vec<f64> {
        self.gravity.clone().unwrap_or_else(|| {
            let mut g = vec![0.0; self.dim];
            if self.dim >= 2 {
                g[1] = -9.81;
            }
            g
        })
    }

    /// The world settings alone: the scene without its bodies.
    pub fn world(&self) -> SceneConfig {
        SceneConfig {
            name: self.name.clone(),
            domain: self.domain.clone(),
            gravity: self.gravity.clone(),
            bodies: Vec::new(),
            ..*self
        }
    }

    /// Checks the world settings (everything but the bodies).
    pub fn validate_world(&self) -> Result<()> {
        if self.dim != 2 && self.dim != 3 {
            return Err(Error::invalid("dim", self.dim, "must be 2 or 3"));
        }
        check_vector("domain.size", &self.domain.size, self.dim, "m")?;
        for (a, &s) in self.domain.size.iter().enumerate() {
            check_positive(format!("domain.size[{a}]"), s, "m")?;
        }
        let min_size = self
            .domain
            .size
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        if !(self.cell_size.is_finite() && self.cell_size > 0.0 && self.cell_size <= min_size / 2.0)
        {
            return Err(Error::invalid(
                "cell_size",
                self.cell_size,
                format!(
                    "must be > 0 and at most half the smallest domain size ({}) (m)",
                    min_size / 2.0
                ),
            ));
        }
        for (a, &s) in self.domain.size.iter().enumerate() {
            let n = s / self.cell_size;
            if (n - n.round()).abs() > 1e-6 * n.max(1.0) {
                let tidy = |x: f64| (x * 1e9).round() / 1e9;
                let (lo, hi) = (
                    tidy(n.floor().max(1.0) * self.cell_size),
                    tidy(n.ceil() * self.cell_size),
                );
                return Err(Error::invalid(
                    format!("domain.size[{a}]"),
                    s,
                    format!(
                        "must be a whole number of cells of cell_size {} (the walls lie on grid nodes), e.g. {lo} or {hi}",
                        self.cell_size
                    ),
                ));
            }
        }
        let cells: f64 = self
            .domain
            .size
            .iter()
            .map(|s| s / self.cell_size)
            .product();
        if cells > 1e12 {
            return Err(Error::invalid(
                "cell_size",
                self.cell_size,
                "gives more than 10¹² cells in the domain",
            ));
        }
        if let Some(g) = &self.gravity {
            check_vector("gravity", g, self.dim, "m/s²")?;
        }
        check_range("cfl", self.cfl, 1e-3, 1.0, false, "")?;
        check_positive("max_dt", self.max_dt, "s")?;
        check_non_negative("boundary.friction", self.boundary.friction, "")?;
        if let Some(mu) = self.contact.friction {
            check_non_negative("contact.friction", mu, "")?;
        }
        Ok(())
    }

    /// Checks the whole scene.
    pub fn validate(&self) -> Result<()> {
        self.validate_world()?;
        for (i, b) in self.bodies.iter().enumerate() {
            b.validate(&format!("bodies[{i}]"), self.dim, &self.domain.size)?;
            self.check_transfer(b, &format!("bodies[{i}]"))?;
            self.check_pour(b, &format!("bodies[{i}]"))?;
        }
        Ok(())
    }

    /// A poured body's spout (`path` names the body) against the grid and the domain: the
    /// exit's radius from one cell (the stream is resolved) to a quarter of the smallest side;
    /// the section at least one cell from every wall; the rate positive and at most what
    /// leaves the section at [`MAX_EXIT_SPEED`]; the duration in (0, [`MAX_POUR_DURATION`]].
    pub fn check_pour(&self, body: &BodyConfig, path: &str) -> Result<()> {
        let Some(pour) = &body.pour else {
            return Ok(());
        };
        let (dim, h, size) = (self.dim, self.cell_size, &self.domain.size);
        let path = format!("{path}.pour");
        check_vector(&format!("{path}.spout"), &pour.spout, dim, "m")?;
        let smallest = size.iter().cloned().fold(f64::INFINITY, f64::min);
        check_range(
            format!("{path}.radius"),
            pour.radius,
            h,
            0.25 * smallest,
            false,
            "m: from one cell_size to a quarter of the smallest domain side",
        )?;
        // the section's reach along each axis: the radius across, nothing along the axis
        let reach = |a: usize| if a == 1 { 0.0 } else { pour.radius };
        if (0..dim).any(|a| {
            let x = pour.spout[a];
            x - reach(a) < h - 1e-9 * h || x + reach(a) > size[a] - h + 1e-9 * h
        }) {
            let names = ["x", "y", "z"];
            let ranges: Vec<String> = (0..dim)
                .map(|a| {
                    let tidy = |x: f64| (x * 1e9).round() / 1e9;
                    let lo = tidy(h + reach(a));
                    let hi = tidy(size[a] - h - reach(a));
                    format!("{} in [{lo}, {hi}]", names[a])
                })
                .collect();
            return Err(Error::invalid(
                format!("{path}.spout"),
                format!("{:?}", pour.spout),
                format!(
                    "must lie inside the domain with the stream's section at least one cell from every wall: {} (m)",
                    ranges.join(", ")
                ),
            ));
        }
        let unit = if dim == 2 {
            "m²/s per metre of depth"
        } else {
            "m³/s"
        };
        check_positive(format!("{path}.rate"), pour.rate, unit)?;
        let spacing = h / body.particles_per_cell.max(1) as f64;
        let area = pour.exit_area(dim, spacing);
        let most = MAX_EXIT_SPEED * area;
        if pour.rate > most {
            // six significant digits
            let tidy = |x: f64| format!("{x:.5e}").parse::<f64>().unwrap_or(x);
            return Err(Error::invalid(
                format!("{path}.rate"),
                pour.rate,
                format!(
                    "must be in (0, {}] ({unit}): at most {MAX_EXIT_SPEED} m/s through the exit, whose {} particles a layer stand for an area A = {} {}",
                    tidy(most),
                    pour.section(dim, spacing).len(),
                    tidy(area),
                    if dim == 2 { "m" } else { "m²" }
                ),
            ));
        }
        let d = pour.duration;
        if !(d.is_finite() && d > 0.0 && d <= MAX_POUR_DURATION) {
            return Err(Error::invalid(
                format!("{path}.duration"),
                pour.duration,
                format!("must be in (0, {MAX_POUR_DURATION}] (s)"),
            ));
        }
        Ok(())
    }

    /// APIC needs a kernel whose weights spread over every particle: not the linear one (its
    /// inertia D_p vanishes when a particle sits on a node); so does the stress updated last
    /// (the linear kernel keeps Sec. 4.2's order, [`crate::recipe::Recipe`]).
    pub fn check_transfer(&self, body: &BodyConfig, path: &str) -> Result<()> {
        if body.apic == Some(true) && self.kernel == KernelKind::Linear {
            return Err(Error::invalid(
                format!("{path}.apic"),
                true,
                "needs the \"gimp\" or \"quadratic_bspline\" kernel (the scene's kernel is \"linear\")",
            ));
        }
        if body.stress_last == Some(true) && self.kernel == KernelKind::Linear {
            return Err(Error::invalid(
                format!("{path}.stress_last"),
                true,
                "needs the \"gimp\" or \"quadratic_bspline\" kernel (the scene's kernel is \"linear\")",
            ));
        }
        if body.close_grains == Some(true)
            && !matches!(
                body.material.behaviour(),
                crate::material::Behaviour::Granular(_)
            )
        {
            return Err(Error::invalid(
                format!("{path}.close_grains"),
                true,
                "needs a granular material (\"drucker_prager\" or \"mohr_coulomb\"): a solid's grains do not part",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_example_parses() {
        let text = r#"{
          "name": "notched sand block", "dim": 3, "domain": { "size": [2.0, 1.0, 1.0] },
          "cell_size": 0.02, "gravity": [0.0, -9.81, 0.0], "cfl": 0.4, "max_dt": 0.001,
          "boundary": { "friction": 0.5 },
          "bodies": [ { "name": "sand",
              "shape": { "difference": [ { "box": { "min": [0.1, 0.0, 0.3], "max": [0.7, 0.5, 0.7] } },
                                         { "box": { "min": [0.5, 0.25, 0.3], "max": [0.7, 0.5, 0.7] } } ] },
              "material": { "drucker_prager": { "youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200,
                                                "friction_angle": 35, "dilatancy_angle": 0, "cohesion": 0 } },
              "velocity": [0, 0, 0], "particles_per_cell": 2, "flip": 0.05 } ] }"#;
        let s = SceneConfig::from_json(text).unwrap();
        s.validate().unwrap();
        assert_eq!(s.bodies[0].flip, Some(0.05));
    }

    #[test]
    fn errors_name_the_path() {
        let text = r#"{"dim": 2, "domain": {"size": [1, 1]}, "cell_size": 0.1,
            "bodies": [{"shape": {"box": {"min": [0, 0], "max": [1, 1]}},
                        "material": {"elastic": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1, "colour": 3}}}]}"#;
        let e = SceneConfig::from_json(text).unwrap_err().to_string();
        assert!(
            e.starts_with("bodies[0].material.elastic.colour: unknown field `colour`"),
            "{e}"
        );
        let text = r#"{"dim": 2, "domain": {"size": [1, 1]}, "cell_size": "small"}"#;
        let e = SceneConfig::from_json(text).unwrap_err().to_string();
        assert!(e.starts_with("cell_size: invalid type"), "{e}");
        let mut s = SceneConfig::new(2, &[1.0, 1.0], 0.1);
        s.cfl = 1.5;
        assert_eq!(
            s.validate().unwrap_err().to_string(),
            "cfl = 1.5: must be in [0.001, 1]"
        );
        s.cfl = 0.5;
        s.bodies.push(BodyConfig::new(
            "b",
            Shape::cuboid(&[0.5, 0.5], &[1.5, 0.9]),
            Material::elastic(1e5, 0.3, 1e3),
        ));
        assert!(
            s.validate()
                .unwrap_err()
                .to_string()
                .starts_with("bodies[0].shape = extent [0.5, 1.5] along axis 0")
        );
    }
}
