//! Shapes that bodies are cut from, and their sampling into particles on a regular lattice.
//!
//! Shapes are written in scene files as `{"box": {...}}`, `{"ball": {...}}`,
//! `{"cylinder": {...}}`, `{"mesh": {...}}` (3D, an OBJ file), `{"polygon": {...}}` (2D, a
//! vertex list file or inline points), `{"points": {...}}` (explicit particles), and the
//! combinations `{"union": [...]}` and `{"difference": [...]}`. Meshes are filled by the
//! generalised winding number ([`winding`]), polygons by their winding number.
//!
//! Meshes and polygon files are referenced by path relative to the scene file; their parsed
//! content is carried by the shape ([`Loaded`]) once
//! [`SceneConfig::resolve_assets`](crate::SceneConfig::resolve_assets) has read them, so that
//! building a simulation needs no file access.

pub mod assets;
pub mod winding;

pub use assets::{Loaded, Polygon2, TriMesh};

use crate::error::{Error, Result, check_finite_vec, check_positive};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::sync::Arc;

/// A region of space, as written in scene files (`{"box": {...}}`, `{"union": [...]}`, ...).
/// Coordinates are in metres; in a 2D scene vectors have two components.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// An axis-aligned box.
    Box { min: Vec<f64>, max: Vec<f64> },
    /// A ball (a disc in 2D).
    Ball { center: Vec<f64>, radius: f64 },
    /// A solid circular cylinder around a line through `center` parallel to `axis` (`"x"`,
    /// `"y"` — the default, upright — or `"z"`), of `radius` and total `height` (centred on
    /// `center`). In a 2D scene it is its section through the x–y plane: a rectangle
    /// 2·radius wide and `height` long along the axis (`"x"` or `"y"`; a `"z"` axis is an
    /// error there: use a ball).
    Cylinder {
        center: Vec<f64>,
        radius: f64,
        height: f64,
        #[serde(default)]
        axis: Axis,
    },
    /// An upright solid cone (a heap): its base a disc of `radius` on the horizontal plane
    /// through `base`, its apex `height` above the base's centre. In a 2D scene it is its
    /// section through the x–y plane: a triangle 2·radius wide and `height` tall.
    Cone {
        base: Vec<f64>,
        radius: f64,
        height: f64,
    },
    /// A closed triangle mesh from a Wavefront OBJ file (3D only), placed by
    /// `world = translate + R · (scale ⊙ v)`, with R the rotation by `rotate_deg` = [x, y, z]
    /// degrees about the fixed x, then y, then z axes. `path` is relative to the scene file.
    /// Filled by the generalised winding number, so small holes do not leak.
    Mesh {
        path: String,
        #[serde(default, skip_serializing_if = "Scale::is_one")]
        scale: Scale,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotate_deg: Option<Vec<f64>>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        translate: Option<Vec<f64>>,
        /// The parsed file (not part of the scene file).
        #[serde(skip)]
        loaded: Loaded<TriMesh>,
    },
    /// A closed polygon (2D only): either `path` to a vertex list (one `x y` per line, `#`
    /// comments; relative to the scene file) or inline `points`. Placed by
    /// `world = translate + R(rotate_deg) · (scale ⊙ v)`, with `rotate_deg` one angle in
    /// degrees, counter-clockwise. Filled by its winding number.
    Polygon {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        path: Option<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        points: Option<Vec<Vec<f64>>>,
        #[serde(default, skip_serializing_if = "Scale::is_one")]
        scale: Scale,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rotate_deg: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        translate: Option<Vec<f64>>,
        /// The parsed file (not part of the scene file).
        #[serde(skip)]
        loaded: Loaded<Polygon2>,
    },
    /// Explicit particle positions; each particle gets `particle_volume` (m³, m² in 2D), or
    /// the lattice volume (cell_size / particles_per_cell)^dim when absent.
    Points {
        positions: Vec<Vec<f64>>,
        #[serde(default)]
        particle_volume: Option<f64>,
    },
    /// Points inside any of the shapes.
    Union(Vec<Shape>),
    /// Points inside the first shape and none of the others.
    Difference(Vec<Shape>),
}

/// The axis of a cylinder.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    #[default]
    Y,
    Z,
}

impl Axis {
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

/// A scale factor: one number for every axis, or one per axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a number, or a list with one number per axis (the scale factor)"
)]
pub enum Scale {
    Uniform(f64),
    PerAxis(Vec<f64>),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

impl Scale {
    pub fn is_one(&self) -> bool {
        *self == Scale::Uniform(1.0)
    }
    /// The factor along each axis.
    pub fn factors(&self) -> [f64; 3] {
        match self {
            Scale::Uniform(s) => [*s; 3],
            Scale::PerAxis(v) => std::array::from_fn(|a| v.get(a).copied().unwrap_or(1.0)),
        }
    }
    fn validate(&self, field: &str, dim: usize) -> Result<()> {
        match self {
            Scale::Uniform(s) => check_positive(field, *s, ""),
            Scale::PerAxis(v) => {
                check_vector(field, v, dim, "")?;
                for (a, s) in v.iter().enumerate() {
                    check_positive(format!("{field}[{a}]"), *s, "")?;
                }
                Ok(())
            }
        }
    }
}

/// An axis-aligned bounding box in 3D (unused axes are zero in 2D).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|a| self.min[a].min(o.min[a])),
            max: std::array::from_fn(|a| self.max[a].max(o.max[a])),
        }
    }
    fn contains(&self, p: [f64; 3], dim: usize) -> bool {
        (0..dim).all(|a| p[a] >= self.min[a] && p[a] <= self.max[a])
    }
    fn of_points(points: impl Iterator<Item = [f64; 3]>) -> Aabb {
        points
            .map(|p| Aabb { min: p, max: p })
            .reduce(Aabb::union)
            .unwrap_or(Aabb {
                min: [0.0; 3],
                max: [0.0; 3],
            })
    }
}

fn vec3(v: &[f64]) -> [f64; 3] {
    [
        v.first().copied().unwrap_or(0.0),
        v.get(1).copied().unwrap_or(0.0),
        v.get(2).copied().unwrap_or(0.0),
    ]
}

/// Checks that a vector field has `dim` finite components.
pub fn check_vector(field: &str, v: &[f64], dim: usize, unit: &str) -> Result<()> {
    if v.len() != dim {
        return Err(Error::invalid(
            field,
            format!("{v:?}"),
            format!("must have {dim} components (the scene's dim)"),
        ));
    }
    check_finite_vec(field, v, unit)
}

/// A placement: `world = t + R (s ⊙ local)`.
#[derive(Clone, Copy, Debug)]
struct Placement {
    s: [f64; 3],
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Placement {
    /// From rotations about x, y, z (degrees), applied in that order about fixed axes.
    fn new(scale: &Scale, rotate_deg: [f64; 3], translate: [f64; 3]) -> Self {
        let [ax, ay, az] = rotate_deg.map(f64::to_radians);
        let (sx, cx) = ax.sin_cos();
        let (sy, cy) = ay.sin_cos();
        let (sz, cz) = az.sin_cos();
        let rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
        let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
        let rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
        Placement {
            s: scale.factors(),
            r: matmul(rz, matmul(ry, rx)),
            t: translate,
        }
    }
    fn forward(&self, v: [f64; 3]) -> [f64; 3] {
        let sv: [f64; 3] = std::array::from_fn(|a| self.s[a] * v[a]);
        std::array::from_fn(|i| {
            self.t[i] + self.r[i][0] * sv[0] + self.r[i][1] * sv[1] + self.r[i][2] * sv[2]
        })
    }
    fn inverse(&self, p: [f64; 3]) -> [f64; 3] {
        let d: [f64; 3] = std::array::from_fn(|a| p[a] - self.t[a]);
        // Rᵀ d, then divide by the scale
        std::array::from_fn(|j| {
            (self.r[0][j] * d[0] + self.r[1][j] * d[1] + self.r[2][j] * d[2]) / self.s[j]
        })
    }
}

fn matmul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// The winding number of a closed polygon with `n` vertices given by `at(i)` about `q`.
pub(crate) fn polygon_winding(n: usize, at: impl Fn(usize) -> [f64; 2], q: [f64; 2]) -> i32 {
    let mut w = 0;
    for i in 0..n {
        let (a, b) = (at(i), at((i + 1) % n));
        let side = (b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= q[1] {
            if b[1] > q[1] && side > 0.0 {
                w += 1;
            }
        } else if b[1] <= q[1] && side < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Reads and parses the files shapes reference, once per path.
pub struct AssetLoader<'a> {
    read: &'a mut dyn FnMut(&str) -> Result<String>,
    meshes: HashMap<String, Arc<TriMesh>>,
    polygons: HashMap<String, Arc<Polygon2>>,
}

impl<'a> AssetLoader<'a> {
    /// A loader that reads a file's text with `read` (given the path as written).
    pub fn new(read: &'a mut dyn FnMut(&str) -> Result<String>) -> Self {
        AssetLoader {
            read,
            meshes: HashMap::new(),
            polygons: HashMap::new(),
        }
    }

    fn text(&mut self, field: &str, path: &str, what: &str) -> Result<String> {
        if path.trim().is_empty() {
            return Err(Error::invalid(
                field,
                "\"\"",
                format!("must name {what}, relative to the scene file"),
            ));
        }
        (self.read)(path).map_err(|e| {
            Error::invalid(
                field,
                format!("{path:?}"),
                format!("cannot read {what} ({e}); paths are relative to the scene file"),
            )
        })
    }

    fn mesh(&mut self, field: &str, path: &str) -> Result<Arc<TriMesh>> {
        self.cached(
            |l| &mut l.meshes,
            (field, path),
            "an OBJ file",
            TriMesh::from_obj,
            "must be a closed triangle mesh in Wavefront OBJ format",
        )
    }

    fn polygon(&mut self, field: &str, path: &str) -> Result<Arc<Polygon2>> {
        self.cached(
            |l| &mut l.polygons,
            (field, path),
            "a vertex list file",
            Polygon2::from_vertex_list,
            "must list one vertex `x y` per line",
        )
    }

    /// The file at `path` (for the scene field `field`), parsed once: `what` names the file in
    /// read errors, `expected` says what a parse error should have been.
    fn cached<T>(
        &mut self,
        cache: fn(&mut Self) -> &mut HashMap<String, Arc<T>>,
        (field, path): (&str, &str),
        what: &str,
        parse: fn(&str, &str) -> std::result::Result<T, String>,
        expected: &str,
    ) -> Result<Arc<T>> {
        if let Some(v) = cache(self).get(path) {
            return Ok(v.clone());
        }
        let text = self.text(field, path, what)?;
        let parsed = parse(path, &text)
            .map_err(|e| Error::invalid(field, format!("{path:?}"), format!("{e}; {expected}")))?;
        let v = Arc::new(parsed);
        cache(self).insert(path.to_string(), v.clone());
        Ok(v)
    }
}

impl Shape {
    /// The shape of a body written without one (a poured body, whose particles come from its
    /// spout): an empty list of points, which holds no particle.
    pub fn absent() -> Shape {
        Shape::Points {
            positions: Vec::new(),
            particle_volume: None,
        }
    }
    /// Whether this is [`Shape::absent`] (an empty list of points reads the same).
    pub fn is_absent(&self) -> bool {
        matches!(self, Shape::Points { positions, particle_volume: None } if positions.is_empty())
    }
    /// An axis-aligned box.
    pub fn cuboid(min: &[f64], max: &[f64]) -> Shape {
        Shape::Box {
            min: min.to_vec(),
            max: max.to_vec(),
        }
    }
    /// A ball.
    pub fn ball(center: &[f64], radius: f64) -> Shape {
        Shape::Ball {
            center: center.to_vec(),
            radius,
        }
    }
    /// A cylinder along `axis` through `center`.
    pub fn cylinder(center: &[f64], radius: f64, height: f64, axis: Axis) -> Shape {
        Shape::Cylinder {
            center: center.to_vec(),
            radius,
            height,
            axis,
        }
    }
    /// An upright cone, its base's centre at `base`.
    pub fn cone(base: &[f64], radius: f64, height: f64) -> Shape {
        Shape::Cone {
            base: base.to_vec(),
            radius,
            height,
        }
    }
    /// A mesh read from `path` (relative to the scene file) when the scene's assets are
    /// resolved, scaled by `scale`, then moved by `translate`.
    pub fn mesh(path: &str, scale: f64, translate: &[f64]) -> Shape {
        Shape::Mesh {
            path: path.to_string(),
            scale: Scale::Uniform(scale),
            rotate_deg: None,
            translate: Some(translate.to_vec()),
            loaded: Loaded::default(),
        }
    }
    /// A mesh given in memory (already loaded; `path` only names it).
    pub fn mesh_from(mesh: TriMesh, scale: f64, translate: &[f64]) -> Shape {
        Shape::Mesh {
            path: mesh.source.clone(),
            scale: Scale::Uniform(scale),
            rotate_deg: None,
            translate: Some(translate.to_vec()),
            loaded: Loaded(Some(Arc::new(mesh))),
        }
    }
    /// A 2D polygon with inline vertices.
    pub fn polygon(points: &[[f64; 2]]) -> Shape {
        Shape::Polygon {
            path: None,
            points: Some(points.iter().map(|p| p.to_vec()).collect()),
            scale: Scale::default(),
            rotate_deg: None,
            translate: None,
            loaded: Loaded::default(),
        }
    }
    /// A 2D polygon read from a vertex list file at `path` (relative to the scene file).
    pub fn polygon_file(path: &str, scale: f64, translate: &[f64]) -> Shape {
        Shape::Polygon {
            path: Some(path.to_string()),
            points: None,
            scale: Scale::Uniform(scale),
            rotate_deg: None,
            translate: Some(translate.to_vec()),
            loaded: Loaded::default(),
        }
    }

    /// The scene-file name of the shape.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Box { .. } => "box",
            Shape::Ball { .. } => "ball",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Cone { .. } => "cone",
            Shape::Mesh { .. } => "mesh",
            Shape::Polygon { .. } => "polygon",
            Shape::Points { .. } => "points",
            Shape::Union(_) => "union",
            Shape::Difference(_) => "difference",
        }
    }

    /// Appends every external file the shape references, as written.
    pub fn asset_paths(&self, out: &mut Vec<String>) {
        match self {
            Shape::Mesh { path, .. } => out.push(path.clone()),
            Shape::Polygon {
                path: Some(path), ..
            } => out.push(path.clone()),
            Shape::Union(s) | Shape::Difference(s) => {
                for s in s {
                    s.asset_paths(out);
                }
            }
            _ => {}
        }
    }

    /// Loads the files the shape references (skipping those already loaded from the same
    /// path); `path` names the shape in errors (e.g. `bodies[0].shape`).
    pub fn resolve_assets(&mut self, path: &str, loader: &mut AssetLoader<'_>) -> Result<()> {
        match self {
            Shape::Mesh {
                path: file, loaded, ..
            } if loaded.get().is_none_or(|m| m.source != *file) => {
                *loaded = Loaded(Some(loader.mesh(&format!("{path}.mesh.path"), file)?));
            }
            Shape::Polygon {
                path: Some(file),
                loaded,
                ..
            } if loaded.get().is_none_or(|p| p.source != *file) => {
                *loaded = Loaded(Some(loader.polygon(&format!("{path}.polygon.path"), file)?));
            }
            Shape::Union(shapes) => {
                for (i, s) in shapes.iter_mut().enumerate() {
                    s.resolve_assets(&format!("{path}.union[{i}]"), loader)?;
                }
            }
            Shape::Difference(shapes) => {
                for (i, s) in shapes.iter_mut().enumerate() {
                    s.resolve_assets(&format!("{path}.difference[{i}]"), loader)?;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Checks the shape for a scene of dimension `dim`; `path` names it in messages.
    pub fn validate(&self, path: &str, dim: usize) -> Result<()> {
        match self {
            Shape::Box { min, max } => {
                check_vector(&format!("{path}.box.min"), min, dim, "m")?;
                check_vector(&format!("{path}.box.max"), max, dim, "m")?;
                for a in 0..dim {
                    if max[a] <= min[a] {
                        return Err(Error::invalid(
                            format!("{path}.box.max[{a}]"),
                            max[a],
                            format!("must be greater than box.min[{a}] = {}", min[a]),
                        ));
                    }
                }
                Ok(())
            }
            Shape::Ball { center, radius } => {
                check_vector(&format!("{path}.ball.center"), center, dim, "m")?;
                check_positive(format!("{path}.ball.radius"), *radius, "m")
            }
            Shape::Cylinder {
                center,
                radius,
                height,
                axis,
            } => {
                check_vector(&format!("{path}.cylinder.center"), center, dim, "m")?;
                check_positive(format!("{path}.cylinder.radius"), *radius, "m")?;
                check_positive(format!("{path}.cylinder.height"), *height, "m")?;
                if dim == 2 && *axis == Axis::Z {
                    return Err(Error::invalid(
                        format!("{path}.cylinder.axis"),
                        "\"z\"",
                        "must be \"x\" or \"y\" in a 2D scene (the section of a cylinder along z is a disc: use a ball)",
                    ));
                }
                Ok(())
            }
            Shape::Cone {
                base,
                radius,
                height,
            } => {
                check_vector(&format!("{path}.cone.base"), base, dim, "m")?;
                check_positive(format!("{path}.cone.radius"), *radius, "m")?;
                check_positive(format!("{path}.cone.height"), *height, "m")
            }
            Shape::Mesh {
                path: file,
                scale,
                rotate_deg,
                translate,
                loaded,
            } => {
                if dim != 3 {
                    return Err(Error::invalid(
                        format!("{path}.mesh"),
                        format!("{file:?}"),
                        "a mesh needs a 3D scene (in 2D use a polygon)",
                    ));
                }
                scale.validate(&format!("{path}.mesh.scale"), 3)?;
                if let Some(r) = rotate_deg {
                    check_vector(&format!("{path}.mesh.rotate_deg"), r, 3, "degrees")?;
                }
                if let Some(t) = translate {
                    check_vector(&format!("{path}.mesh.translate"), t, 3, "m")?;
                }
                match loaded.get() {
                    Some(m) if m.source == *file => Ok(()),
                    _ => Err(Error::invalid(
                        format!("{path}.mesh.path"),
                        format!("{file:?}"),
                        "is not loaded: resolve the scene's assets first (SceneConfig::load or SceneConfig::resolve_assets)",
                    )),
                }
            }
            Shape::Polygon {
                path: file,
                points,
                scale,
                rotate_deg,
                translate,
                loaded,
            } => {
                if dim != 2 {
                    return Err(Error::invalid(
                        format!("{path}.polygon"),
                        file.as_deref()
                            .map_or("inline points".into(), |f| format!("{f:?}")),
                        "a polygon needs a 2D scene (in 3D use a mesh)",
                    ));
                }
                match (file, points) {
                    (Some(_), Some(_)) | (None, None) => {
                        return Err(Error::invalid(
                            format!("{path}.polygon"),
                            if file.is_some() {
                                "both `path` and `points`"
                            } else {
                                "neither `path` nor `points`"
                            },
                            "must give exactly one of `path` (a vertex list file) and `points`",
                        ));
                    }
                    (None, Some(points)) => {
                        for (i, p) in points.iter().enumerate() {
                            check_vector(&format!("{path}.polygon.points[{i}]"), p, 2, "m")?;
                        }
                        let pts: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[1]]).collect();
                        Polygon2::new("", pts).map_err(|e| {
                            Error::invalid(
                                format!("{path}.polygon.points"),
                                format!("{} points", points.len()),
                                format!("{e}; must outline a polygon"),
                            )
                        })?;
                    }
                    (Some(file), None) => {
                        if loaded.get().is_none_or(|p| p.source != *file) {
                            return Err(Error::invalid(
                                format!("{path}.polygon.path"),
                                format!("{file:?}"),
                                "is not loaded: resolve the scene's assets first (SceneConfig::load or SceneConfig::resolve_assets)",
                            ));
                        }
                    }
                }
                scale.validate(&format!("{path}.polygon.scale"), 2)?;
                if let Some(r) = rotate_deg {
                    check_finite_vec(format!("{path}.polygon.rotate_deg"), &[*r], "degrees")
                        .map_err(|_| {
                            Error::invalid(
                                format!("{path}.polygon.rotate_deg"),
                                r,
                                "must be a finite angle (degrees)",
                            )
                        })?;
                }
                if let Some(t) = translate {
                    check_vector(&format!("{path}.polygon.translate"), t, 2, "m")?;
                }
                Ok(())
            }
            Shape::Points {
                positions,
                particle_volume,
            } => {
                if positions.is_empty() {
                    return Err(Error::invalid(
                        format!("{path}.points.positions"),
                        "[]",
                        "must hold at least one point",
                    ));
                }
                for (i, p) in positions.iter().enumerate() {
                    check_vector(&format!("{path}.points.positions[{i}]"), p, dim, "m")?;
                }
                if let Some(v) = particle_volume {
                    check_positive(
                        format!("{path}.points.particle_volume"),
                        *v,
                        if dim == 2 { "m²" } else { "m³" },
                    )?;
                }
                Ok(())
            }
            Shape::Union(shapes) | Shape::Difference(shapes) => {
                let key = if matches!(self, Shape::Union(_)) {
                    "union"
                } else {
                    "difference"
                };
                if shapes.is_empty() {
                    return Err(Error::invalid(
                        format!("{path}.{key}"),
                        "[]",
                        "must list at least one shape",
                    ));
                }
                for (i, s) in shapes.iter().enumerate() {
                    s.validate(&format!("{path}.{key}[{i}]"), dim)?;
                }
                Ok(())
            }
        }
    }

    /// Whether a point lies inside (explicit point lists contain nothing). Prepares the
    /// shape on every call: to test many points, use [`Shape::inside_test`].
    pub fn contains(&self, p: [f64; 3], dim: usize) -> bool {
        self.inside_test(dim).contains(p)
    }

    /// The shape prepared for many inside tests (placements and bounds computed once).
    pub fn inside_test(&self, dim: usize) -> InsideTest<'_> {
        InsideTest::new(self, dim)
    }

    /// A box holding every point of the shape.
    pub fn bounds(&self, dim: usize) -> Aabb {
        match self {
            Shape::Box { min, max } => Aabb {
                min: vec3(min),
                max: vec3(max),
            },
            Shape::Ball { center, radius } => {
                let c = vec3(center);
                Aabb {
                    min: std::array::from_fn(|a| if a < dim { c[a] - radius } else { 0.0 }),
                    max: std::array::from_fn(|a| if a < dim { c[a] + radius } else { 0.0 }),
                }
            }
            Shape::Cylinder {
                center,
                radius,
                height,
                axis,
            } => {
                let c = vec3(center);
                let half = |a: usize| {
                    if a >= dim {
                        0.0
                    } else if a == axis.index() {
                        0.5 * height
                    } else {
                        *radius
                    }
                };
                Aabb {
                    min: std::array::from_fn(|a| if a < dim { c[a] - half(a) } else { 0.0 }),
                    max: std::array::from_fn(|a| if a < dim { c[a] + half(a) } else { 0.0 }),
                }
            }
            Shape::Cone {
                base,
                radius,
                height,
            } => {
                let b = vec3(base);
                let span = |a: usize, side: f64| match a {
                    1 => b[1] + if side > 0.0 { *height } else { 0.0 },
                    _ if a < dim => b[a] + side * radius,
                    _ => 0.0,
                };
                Aabb {
                    min: std::array::from_fn(|a| span(a, -1.0)),
                    max: std::array::from_fn(|a| span(a, 1.0)),
                }
            }
            Shape::Mesh { loaded, .. } => {
                let place = self.placement().expect("a mesh has a placement");
                match loaded.get() {
                    Some(m) => Aabb::of_points(m.vertices.iter().map(|&v| place.forward(v))),
                    None => Aabb::of_points(std::iter::empty()),
                }
            }
            Shape::Polygon { .. } => {
                let place = self.placement().expect("a polygon has a placement");
                let mut pts = Vec::new();
                self.polygon_points(|p| pts.push(place.forward([p[0], p[1], 0.0])));
                let mut b = Aabb::of_points(pts.into_iter());
                b.min[2] = 0.0;
                b.max[2] = 0.0;
                b
            }
            Shape::Points { positions, .. } => Aabb::of_points(positions.iter().map(|p| vec3(p))),
            Shape::Union(s) => s
                .iter()
                .map(|s| s.bounds(dim))
                .reduce(Aabb::union)
                .unwrap_or(Aabb {
                    min: [0.0; 3],
                    max: [0.0; 3],
                }),
            Shape::Difference(s) => s.first().map_or(
                Aabb {
                    min: [0.0; 3],
                    max: [0.0; 3],
                },
                |s| s.bounds(dim),
            ),
        }
    }

    /// The placement of a mesh or polygon.
    fn placement(&self) -> Option<Placement> {
        match self {
            Shape::Mesh {
                scale,
                rotate_deg,
                translate,
                ..
            } => Some(Placement::new(
                scale,
                rotate_deg.as_deref().map_or([0.0; 3], vec3),
                translate.as_deref().map_or([0.0; 3], vec3),
            )),
            Shape::Polygon {
                scale,
                rotate_deg,
                translate,
                ..
            } => {
                let mut s = scale.clone();
                if let Scale::PerAxis(v) = &mut s {
                    v.resize(3, 1.0);
                }
                Some(Placement::new(
                    &s,
                    [0.0, 0.0, rotate_deg.unwrap_or(0.0)],
                    translate.as_deref().map_or([0.0; 3], vec3),
                ))
            }
            _ => None,
        }
    }

    /// Calls `f` with each local vertex of a polygon (inline or loaded).
    fn polygon_points(&self, mut f: impl FnMut([f64; 2])) {
        if let Shape::Polygon { points, loaded, .. } = self {
            if let Some(points) = points {
                for p in points {
                    f([
                        p.first().copied().unwrap_or(0.0),
                        p.get(1).copied().unwrap_or(0.0),
                    ]);
                }
            } else if let Some(poly) = loaded.get() {
                for &p in &poly.points {
                    f(p);
                }
            }
        }
    }

    /// How many points [`Shape::sample_jittered`] would test: the lattice of spacing
    /// cell_size / per_cell over the shape's bounds (explicit points: their number).
    pub fn lattice_candidates(&self, dim: usize, cell_size: f64, per_cell: u32) -> f64 {
        if let Shape::Points { positions, .. } = self {
            return positions.len() as f64; // taken as they are, no lattice
        }
        let (lo, hi) = self.lattice_range(dim, cell_size / per_cell as f64, 0.0);
        (0..dim)
            .map(|a| (hi[a] - lo[a] + 1).max(0) as f64)
            .product()
    }

    fn lattice_range(&self, dim: usize, dx: f64, jitter: f64) -> ([i64; 3], [i64; 3]) {
        let b = self.bounds(dim);
        let mut lo = [0i64; 3];
        let mut hi = [0i64; 3];
        for a in 0..dim {
            lo[a] = (b.min[a] / dx - 0.5 - jitter).ceil() as i64;
            hi[a] = (b.max[a] / dx - 0.5 + jitter).floor() as i64;
        }
        (lo, hi)
    }

    /// Samples the shape into particles: a lattice of `per_cell` points per axis and cell of
    /// size `cell_size`, aligned with the grid (points at (k + ½) Δx), or the explicit
    /// points. Returns positions (3 components, unused ones zero) and the volume of each.
    pub fn sample(&self, dim: usize, cell_size: f64, per_cell: u32) -> (Vec<[f64; 3]>, f64) {
        self.sample_jittered(dim, cell_size, per_cell, 0.0, 0)
    }

    /// Like [`Shape::sample`], with each lattice point moved by up to `jitter` (in [0, ½))
    /// times the spacing along each axis, pseudo-randomly from `seed` and the point's lattice
    /// index, so that the result is the same on every run and platform.
    pub fn sample_jittered(
        &self,
        dim: usize,
        cell_size: f64,
        per_cell: u32,
        jitter: f64,
        seed: u64,
    ) -> (Vec<[f64; 3]>, f64) {
        let dx = cell_size / per_cell as f64;
        let lattice_volume = dx.powi(dim as i32);
        if let Shape::Points {
            positions,
            particle_volume,
        } = self
        {
            return (
                positions.iter().map(|p| vec3(p)).collect(),
                particle_volume.unwrap_or(lattice_volume),
            );
        }
        let lattice = Lattice::new(dim, dx, jitter, seed);
        let inside = InsideTest::for_lattice(self, &lattice);
        let (lo, hi) = self.lattice_range(dim, dx, jitter);
        let mut out = Vec::new();
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    let idx = [i, j, k];
                    let p = lattice.point(idx);
                    if inside.contains_at(idx, p) {
                        out.push(p);
                    }
                }
            }
        }
        (out, lattice_volume)
    }
}

/// SplitMix64 (Steele, Lea and Flood 2014): a fixed, portable mixing function.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The sampling lattice: point `idx` is at (idx + ½ + jitter·u) Δx along each axis, with u
/// in [−1, 1) a hash of the seed, the index and the axis.
#[derive(Clone, Copy, Debug)]
pub struct Lattice {
    dim: usize,
    dx: f64,
    jitter: f64,
    seed_hash: u64,
}

impl Lattice {
    pub fn new(dim: usize, dx: f64, jitter: f64, seed: u64) -> Self {
        Lattice {
            dim,
            dx,
            jitter,
            seed_hash: splitmix64(seed ^ 0x6a09_e667_f3bc_c908),
        }
    }

    /// The position of lattice point `idx` (unused axes zero).
    pub fn point(&self, idx: [i64; 3]) -> [f64; 3] {
        let h = if self.jitter > 0.0 {
            let [i, j, k] = idx;
            splitmix64(splitmix64(splitmix64(self.seed_hash ^ i as u64) ^ j as u64) ^ k as u64)
        } else {
            0
        };
        std::array::from_fn(|a| {
            if a >= self.dim {
                return 0.0;
            }
            let u = if self.jitter > 0.0 {
                let r = splitmix64(h ^ (a as u64 + 1)) >> 11;
                (r as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
            } else {
                0.0
            };
            (idx[a] as f64 + 0.5 + self.jitter * u) * self.dx
        })
    }

    /// A box holding every point of the index box `lo..=hi`.
    fn region(&self, lo: [i64; 3], hi: [i64; 3]) -> Aabb {
        let (dx, j) = (self.dx, self.jitter);
        Aabb {
            min: std::array::from_fn(|a| {
                if a < self.dim {
                    (lo[a] as f64 + 0.5 - j) * dx
                } else {
                    0.0
                }
            }),
            max: std::array::from_fn(|a| {
                if a < self.dim {
                    (hi[a] as f64 + 0.5 + j) * dx
                } else {
                    0.0
                }
            }),
        }
    }
}

/// Which points of an index box of the lattice are inside a mesh.
#[derive(Debug)]
struct Bitmap {
    lo: [i64; 3],
    n: [i64; 3],
    bits: Vec<u64>,
}

impl Bitmap {
    fn new(lo: [i64; 3], hi: [i64; 3]) -> Self {
        let n: [i64; 3] = std::array::from_fn(|a| (hi[a] - lo[a] + 1).max(0));
        let len = (n[0] * n[1] * n[2]) as usize;
        Bitmap {
            lo,
            n,
            bits: vec![0; len.div_ceil(64)],
        }
    }
    fn index(&self, idx: [i64; 3]) -> Option<usize> {
        let r: [i64; 3] = std::array::from_fn(|a| idx[a] - self.lo[a]);
        if (0..3).all(|a| r[a] >= 0 && r[a] < self.n[a]) {
            Some(((r[2] * self.n[1] + r[1]) * self.n[0] + r[0]) as usize)
        } else {
            None
        }
    }
    fn set(&mut self, idx: [i64; 3]) {
        if let Some(i) = self.index(idx) {
            self.bits[i / 64] |= 1 << (i % 64);
        }
    }
    fn get(&self, idx: [i64; 3]) -> bool {
        self.index(idx)
            .is_some_and(|i| self.bits[i / 64] & (1 << (i % 64)) != 0)
    }
}

/// Classifies the lattice points of `lo..=hi` against a placed mesh, region by region: a
/// region whose bounding sphere stays clear of every triangle takes the inside/outside state
/// of its centre (the winding number is constant off a closed surface), unless that value is
/// ambiguous (near a hole); other regions are halved down to single points.
fn classify_mesh(
    mesh: &TriMesh,
    place: &Placement,
    lattice: &Lattice,
    lo: [i64; 3],
    hi: [i64; 3],
    out: &mut Bitmap,
) {
    let count: i64 = (0..3).map(|a| hi[a] - lo[a] + 1).product();
    if count <= 0 {
        return;
    }
    if count > 8 {
        let b = lattice.region(lo, hi);
        let c: [f64; 3] = std::array::from_fn(|a| 0.5 * (b.min[a] + b.max[a]));
        let rho = (0..3)
            .map(|a| (0.5 * (b.max[a] - b.min[a])).powi(2))
            .sum::<f64>()
            .sqrt();
        let min_scale = place.s.iter().cloned().fold(f64::INFINITY, f64::min);
        let c_local = place.inverse(c);
        if !mesh.tree.near_surface(c_local, rho / min_scale) {
            let w = mesh.tree.winding_number(c_local).abs();
            if !(0.25..=0.75).contains(&w) {
                if w > 0.5 {
                    for k in lo[2]..=hi[2] {
                        for j in lo[1]..=hi[1] {
                            for i in lo[0]..=hi[0] {
                                out.set([i, j, k]);
                            }
                        }
                    }
                }
                return;
            }
        }
        let axis = (0..3).max_by_key(|&a| hi[a] - lo[a]).unwrap_or(0);
        let mid = lo[axis] + (hi[axis] - lo[axis]) / 2;
        let mut hi1 = hi;
        hi1[axis] = mid;
        let mut lo2 = lo;
        lo2[axis] = mid + 1;
        classify_mesh(mesh, place, lattice, lo, hi1, out);
        classify_mesh(mesh, place, lattice, lo2, hi, out);
        return;
    }
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                if mesh.tree.contains(place.inverse(lattice.point([i, j, k]))) {
                    out.set([i, j, k]);
                }
            }
        }
    }
}

/// A shape prepared for inside tests: placements inverted and bounds computed once.
#[derive(Debug)]
pub struct InsideTest<'a> {
    node: Node<'a>,
    dim: usize,
}

#[derive(Debug)]
enum Node<'a> {
    Box([f64; 3], [f64; 3]),
    Ball([f64; 3], f64),
    Cylinder {
        center: [f64; 3],
        r2: f64,
        half: f64,
        axis: usize,
    },
    Cone {
        base: [f64; 3],
        radius: f64,
        height: f64,
    },
    Mesh {
        mesh: &'a TriMesh,
        place: Placement,
        bounds: Aabb,
        /// Precomputed for a lattice ([`InsideTest::for_lattice`]).
        lattice: Option<Bitmap>,
    },
    Polygon {
        points: Vec<[f64; 2]>,
        place: Placement,
        bounds: Aabb,
    },
    Nothing,
    Union(Vec<Node<'a>>),
    Difference(Vec<Node<'a>>),
}

impl<'a> InsideTest<'a> {
    fn new(shape: &'a Shape, dim: usize) -> Self {
        InsideTest {
            node: Self::node(shape, dim, None),
            dim,
        }
    }

    /// Prepared to test the points of `lattice` by index ([`InsideTest::contains_at`]):
    /// meshes are classified region by region over the lattice at once, which costs about one
    /// winding-number query per lattice point near the surface instead of one per point.
    pub fn for_lattice(shape: &'a Shape, lattice: &Lattice) -> Self {
        InsideTest {
            node: Self::node(shape, lattice.dim, Some(lattice)),
            dim: lattice.dim,
        }
    }

    fn node(shape: &'a Shape, dim: usize, lattice: Option<&Lattice>) -> Node<'a> {
        match shape {
            Shape::Box { min, max } => Node::Box(vec3(min), vec3(max)),
            Shape::Ball { center, radius } => Node::Ball(vec3(center), radius * radius),
            Shape::Cylinder {
                center,
                radius,
                height,
                axis,
            } => Node::Cylinder {
                center: vec3(center),
                r2: radius * radius,
                half: 0.5 * height,
                axis: axis.index(),
            },
            Shape::Cone {
                base,
                radius,
                height,
            } => Node::Cone {
                base: vec3(base),
                radius: *radius,
                height: *height,
            },
            Shape::Mesh { loaded, .. } => match loaded.get() {
                Some(mesh) => {
                    let place = shape.placement().expect("a mesh has a placement");
                    let lattice = lattice.filter(|l| l.dim == 3).map(|l| {
                        let (lo, hi) = shape.lattice_range(3, l.dx, l.jitter);
                        let mut bitmap = Bitmap::new(lo, hi);
                        classify_mesh(mesh, &place, l, lo, hi, &mut bitmap);
                        bitmap
                    });
                    Node::Mesh {
                        mesh,
                        place,
                        bounds: shape.bounds(dim),
                        lattice,
                    }
                }
                None => Node::Nothing,
            },
            Shape::Polygon { .. } => {
                let mut points = Vec::new();
                shape.polygon_points(|p| points.push(p));
                if points.len() < 3 {
                    return Node::Nothing;
                }
                Node::Polygon {
                    points,
                    place: shape.placement().expect("a polygon has a placement"),
                    bounds: shape.bounds(dim),
                }
            }
            Shape::Points { .. } => Node::Nothing,
            Shape::Union(s) => Node::Union(s.iter().map(|s| Self::node(s, dim, lattice)).collect()),
            Shape::Difference(s) => {
                Node::Difference(s.iter().map(|s| Self::node(s, dim, lattice)).collect())
            }
        }
    }

    /// Whether `p` (3 components; the third is ignored in 2D) is inside.
    pub fn contains(&self, p: [f64; 3]) -> bool {
        Self::test(&self.node, None, p, self.dim)
    }

    /// Whether lattice point `idx`, at `p`, is inside (for a test made by
    /// [`InsideTest::for_lattice`]).
    pub fn contains_at(&self, idx: [i64; 3], p: [f64; 3]) -> bool {
        Self::test(&self.node, Some(idx), p, self.dim)
    }

    fn test(node: &Node<'_>, idx: Option<[i64; 3]>, p: [f64; 3], dim: usize) -> bool {
        match node {
            Node::Box(min, max) => (0..dim).all(|a| p[a] >= min[a] && p[a] <= max[a]),
            Node::Ball(c, r2) => (0..dim).map(|a| (p[a] - c[a]).powi(2)).sum::<f64>() <= *r2,
            Node::Cylinder {
                center,
                r2,
                half,
                axis,
            } => {
                (p[*axis] - center[*axis]).abs() <= *half
                    && (0..dim)
                        .filter(|a| a != axis)
                        .map(|a| (p[a] - center[a]).powi(2))
                        .sum::<f64>()
                        <= *r2
            }
            Node::Cone {
                base,
                radius,
                height,
            } => {
                // Over the base, the section's radius shrinks linearly to 0 at the apex.
                let up = p[1] - base[1];
                let r = radius * (1.0 - up / height);
                up >= 0.0
                    && r >= 0.0
                    && (0..dim)
                        .filter(|&a| a != 1)
                        .map(|a| (p[a] - base[a]).powi(2))
                        .sum::<f64>()
                        <= r * r
            }
            Node::Mesh {
                mesh,
                place,
                bounds,
                lattice,
            } => match (lattice, idx) {
                (Some(bitmap), Some(idx)) => bitmap.get(idx),
                _ => bounds.contains(p, dim) && mesh.tree.contains(place.inverse(p)),
            },
            Node::Polygon {
                points,
                place,
                bounds,
            } => {
                if !bounds.contains(p, dim) {
                    return false;
                }
                let q = place.inverse([p[0], p[1], 0.0]);
                polygon_winding(points.len(), |i| points[i], [q[0], q[1]]) != 0
            }
            Node::Nothing => false,
            Node::Union(s) => s.iter().any(|s| Self::test(s, idx, p, dim)),
            Node::Difference(s) => {
                s.first().is_some_and(|s| Self::test(s, idx, p, dim))
                    && !s[1..].iter().any(|s| Self::test(s, idx, p, dim))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_sampling_fills_the_volume() {
        let s = Shape::ball(&[0.5, 0.5, 0.5], 0.3);
        let (pts, v) = s.sample(3, 0.02, 2);
        let vol = pts.len() as f64 * v;
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 0.027;
        assert!((vol - exact).abs() / exact < 0.02, "{vol} vs {exact}");
        let (pts2, v2) = Shape::cuboid(&[0.1, 0.2], &[0.5, 0.4]).sample(2, 0.1, 2);
        assert_eq!(pts2.len(), 8 * 4);
        assert!((v2 - 0.0025).abs() < 1e-12);
        assert!(pts2.iter().all(|p| p[2] == 0.0));
    }

    #[test]
    fn difference_cuts_the_notch() {
        let s = Shape::Difference(vec![
            Shape::cuboid(&[0.0, 0.0], &[1.0, 1.0]),
            Shape::cuboid(&[0.5, 0.5], &[1.0, 1.0]),
        ]);
        let (pts, _) = s.sample(2, 0.1, 1);
        assert_eq!(pts.len(), 100 - 25);
        assert!(!s.contains([0.75, 0.75, 0.0], 2));
    }

    #[test]
    fn cylinders_in_3d_and_their_sections_in_2d() {
        let c = Shape::cylinder(&[0.5, 0.3, 0.5], 0.2, 0.4, Axis::Y);
        let (pts, v) = c.sample(3, 0.02, 2);
        let vol = pts.len() as f64 * v;
        let exact = std::f64::consts::PI * 0.04 * 0.4;
        assert!((vol - exact).abs() / exact < 0.02, "{vol} vs {exact}");
        assert!(c.contains([0.5, 0.49, 0.69], 3));
        assert!(!c.contains([0.5, 0.51, 0.5], 3));
        assert!(!c.contains([0.69, 0.3, 0.69], 3));
        // 2D: a rectangle 2r wide and h tall
        let c = Shape::cylinder(&[0.5, 0.3], 0.2, 0.4, Axis::Y);
        let (pts, v) = c.sample(2, 0.02, 2);
        assert!((pts.len() as f64 * v - 0.4 * 0.4).abs() < 1e-9);
        let b = Shape::cylinder(&[0.5, 0.3], 0.1, 0.4, Axis::X).bounds(2);
        let want = ([0.3, 0.2, 0.0], [0.7, 0.4, 0.0]);
        for a in 0..3 {
            assert!((b.min[a] - want.0[a]).abs() < 1e-12 && (b.max[a] - want.1[a]).abs() < 1e-12);
        }
        let e = Shape::cylinder(&[0.5, 0.3], 0.1, 0.4, Axis::Z)
            .validate("s", 2)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.cylinder.axis = \"z\": must be \"x\" or \"y\""),
            "{e}"
        );
    }

    #[test]
    fn cones_in_3d_and_their_sections_in_2d() {
        // V = π r² h / 3 in 3D; the section's area r h in 2D.
        let c = Shape::cone(&[0.5, 0.1, 0.5], 0.3, 0.2);
        let (pts, v) = c.sample(3, 0.01, 2);
        let vol = pts.len() as f64 * v;
        let exact = std::f64::consts::PI * 0.09 * 0.2 / 3.0;
        assert!((vol - exact).abs() / exact < 0.02, "{vol} vs {exact}");
        // Halfway up, the section's radius is half the base's.
        assert!(c.contains([0.5, 0.2, 0.64], 3));
        assert!(!c.contains([0.5, 0.2, 0.66], 3));
        assert!(!c.contains([0.5, 0.09, 0.5], 3));
        assert!(!c.contains([0.5, 0.31, 0.5], 3));
        let b = c.bounds(3);
        let want = ([0.2, 0.1, 0.2], [0.8, 0.3, 0.8]);
        for a in 0..3 {
            assert!((b.min[a] - want.0[a]).abs() < 1e-12 && (b.max[a] - want.1[a]).abs() < 1e-12);
        }
        let c = Shape::cone(&[0.5, 0.0], 0.3, 0.2);
        let (pts, v) = c.sample(2, 0.01, 2);
        let area = pts.len() as f64 * v;
        assert!((area - 0.06).abs() / 0.06 < 0.02, "{area}");
        let e = Shape::cone(&[0.5, 0.0], 0.3, -0.2)
            .validate("s", 2)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("s.cone.height = -0.2"), "{e}");
    }

    #[test]
    fn polygons_are_placed_and_filled() {
        // a unit square, scaled by 2 along x, rotated 90°, moved to (1, 1)
        let mut s = Shape::polygon(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        if let Shape::Polygon {
            scale,
            rotate_deg,
            translate,
            ..
        } = &mut s
        {
            *scale = Scale::PerAxis(vec![2.0, 1.0]);
            *rotate_deg = Some(90.0);
            *translate = Some(vec![1.0, 1.0]);
        }
        s.validate("s", 2).unwrap();
        let b = s.bounds(2);
        for a in 0..2 {
            assert!((b.min[a] - [0.0, 1.0][a]).abs() < 1e-12, "{b:?}");
            assert!((b.max[a] - [1.0, 3.0][a]).abs() < 1e-12, "{b:?}");
        }
        assert!(s.contains([0.5, 2.5, 0.0], 2));
        assert!(!s.contains([1.5, 1.5, 0.0], 2));
        let (pts, v) = s.sample(2, 0.05, 2);
        assert!((pts.len() as f64 * v - 2.0).abs() < 1e-9);
        assert!(s.validate("s", 3).is_err());
    }

    #[test]
    fn meshes_are_placed_and_filled() {
        let cube = TriMesh::from_obj(
            "cube.obj",
            "v -1 0 -1\nv 1 0 -1\nv 1 2 -1\nv -1 2 -1\nv -1 0 1\nv 1 0 1\nv 1 2 1\nv -1 2 1\n\
             f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n",
        )
        .unwrap();
        let mut s = Shape::mesh_from(cube, 0.1, &[0.5, 0.2, 0.5]);
        if let Shape::Mesh { rotate_deg, .. } = &mut s {
            *rotate_deg = Some(vec![0.0, 0.0, 90.0]); // the 0.2-tall cube now lies along −x
        }
        s.validate("s", 3).unwrap();
        let b = s.bounds(3);
        let want = ([0.3, 0.1, 0.4], [0.5, 0.3, 0.5 + 0.1]);
        for a in 0..3 {
            assert!((b.min[a] - want.0[a]).abs() < 1e-9, "{b:?}");
            assert!((b.max[a] - want.1[a]).abs() < 1e-9, "{b:?}");
        }
        let (pts, v) = s.sample(3, 0.02, 2);
        assert!((pts.len() as f64 * v - 0.2 * 0.2 * 0.2).abs() < 1e-9);
        assert!(s.validate("s", 2).is_err());
    }

    #[test]
    fn jitter_is_deterministic_and_bounded() {
        let s = Shape::cuboid(&[0.1, 0.1, 0.1], &[0.5, 0.3, 0.4]);
        let (a, _) = s.sample_jittered(3, 0.05, 2, 0.3, 7);
        let (b, _) = s.sample_jittered(3, 0.05, 2, 0.3, 7);
        let (c, _) = s.sample_jittered(3, 0.05, 2, 0.3, 8);
        let (grid, _) = s.sample(3, 0.05, 2);
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert!(a.len().abs_diff(grid.len()) < grid.len() / 10);
        let dx = 0.025;
        for p in &a {
            assert!(s.contains(*p, 3));
            for k in 0..3 {
                // within 0.3 spacing of a lattice point
                let f = p[k] / dx - 0.5;
                assert!((f - f.round()).abs() <= 0.3 + 1e-9, "{p:?}");
            }
        }
        assert!(a.iter().any(|p| {
            let f = p[0] / dx - 0.5;
            (f - f.round()).abs() > 0.1
        }));
    }

    #[test]
    fn validation_messages() {
        let s = Shape::Union(vec![
            Shape::cuboid(&[0.0, 0.0], &[1.0, 1.0]),
            Shape::ball(&[0.0, 0.0, 0.0], 1.0),
        ]);
        assert_eq!(
            s.validate("bodies[0].shape", 2).unwrap_err().to_string(),
            "bodies[0].shape.union[1].ball.center = [0.0, 0.0, 0.0]: must have 2 components (the scene's dim)"
        );
        let s = Shape::cuboid(&[0.0, 1.0], &[1.0, 1.0]);
        assert!(
            s.validate("s", 2)
                .unwrap_err()
                .to_string()
                .starts_with("s.box.max[1] = 1: must be greater")
        );
        let s = Shape::mesh("bunny.obj", 1.0, &[0.0, 0.0, 0.0]);
        assert!(
            s.validate("b.shape", 3)
                .unwrap_err()
                .to_string()
                .starts_with("b.shape.mesh.path = \"bunny.obj\": is not loaded")
        );
    }
}
