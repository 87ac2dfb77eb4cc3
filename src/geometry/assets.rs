//! External files that shapes reference (OBJ meshes, 2D vertex lists), parsed from text into
//! the in-memory form the inside tests use. Parsing takes text, not paths: the native loader
//! reads files, the browser fetches them; neither is needed once the scene is resolved.

use super::winding::WindingTree;
use std::fmt;
use std::sync::Arc;

/// The parsed content of a file a shape references, carried by the shape once
/// [`SceneConfig::resolve_assets`](crate::SceneConfig::resolve_assets) has loaded it. Not part
/// of the scene file: two shapes are equal when their written fields are.
#[derive(Clone)]
pub struct Loaded<T>(pub Option<Arc<T>>);

impl<T> Default for Loaded<T> {
    fn default() -> Self {
        Loaded(None)
    }
}

impl<T> Loaded<T> {
    pub fn get(&self) -> Option<&T> {
        self.0.as_deref()
    }
    pub fn is_loaded(&self) -> bool {
        self.0.is_some()
    }
}

impl<T> PartialEq for Loaded<T> {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl<T: Describe> fmt::Debug for Loaded<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Some(t) => write!(f, "Loaded({})", t.describe()),
            None => write!(f, "NotLoaded"),
        }
    }
}

/// A one-line description for debug output (the data itself can be large).
pub trait Describe {
    fn describe(&self) -> String;
}

/// A triangle mesh from an OBJ file, with its winding-number hierarchy.
#[derive(Clone, Debug)]
pub struct TriMesh {
    /// The path it was loaded from, as written in the scene.
    pub source: String,
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub tree: WindingTree,
}

impl Describe for TriMesh {
    fn describe(&self) -> String {
        format!(
            "{:?}: {} vertices, {} triangles",
            self.source,
            self.vertices.len(),
            self.triangles.len()
        )
    }
}

impl TriMesh {
    /// Builds a mesh (and its winding tree) from vertices and triangles; `source` names it.
    pub fn new(source: &str, vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Self {
        let tree = WindingTree::new(&vertices, &triangles);
        TriMesh {
            source: source.to_string(),
            vertices,
            triangles,
            tree,
        }
    }

    /// Parses Wavefront OBJ text (every object and group in the file, polygons triangulated;
    /// points, lines, normals, texture coordinates and materials ignored). The message of an
    /// error says what is wrong with the text.
    pub fn from_obj(source: &str, text: &str) -> Result<Self, String> {
        // (other fields exist when another crate enables tobj's optional features)
        #[allow(clippy::needless_update)]
        let options = tobj::LoadOptions {
            triangulate: true,
            ignore_points: true,
            ignore_lines: true,
            single_index: false,
            ..Default::default()
        };
        let mut reader = std::io::BufReader::new(text.as_bytes());
        let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
            Err(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| format!("malformed OBJ ({e})"))?;
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for model in &models {
            let m = &model.mesh;
            let offset = vertices.len() as u64;
            let count = (m.positions.len() / 3) as u64;
            for p in m.positions.chunks_exact(3) {
                let v = [p[0] as f64, p[1] as f64, p[2] as f64];
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(format!("malformed OBJ (non-finite vertex {v:?})"));
                }
                vertices.push(v);
            }
            for t in m.indices.chunks_exact(3) {
                if t.iter().any(|&i| i as u64 >= count) {
                    return Err(format!(
                        "malformed OBJ (a face refers to vertex {} of {count})",
                        t.iter().max().copied().unwrap_or(0) as u64 + 1
                    ));
                }
                let idx = t.iter().map(|&i| (offset + i as u64) as u32);
                let tri: Vec<u32> = idx.collect();
                triangles.push([tri[0], tri[1], tri[2]]);
            }
        }
        if vertices.len() > u32::MAX as usize / 2 {
            return Err("too many vertices".into());
        }
        if triangles.is_empty() {
            return Err("no triangle in the file (an OBJ mesh needs `v` and `f` lines)".into());
        }
        Ok(TriMesh::new(source, vertices, triangles))
    }
}

/// A closed 2D polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon2 {
    /// The path it was loaded from, as written in the scene (empty for inline points).
    pub source: String,
    pub points: Vec<[f64; 2]>,
}

impl Describe for Polygon2 {
    fn describe(&self) -> String {
        format!("{:?}: {} vertices", self.source, self.points.len())
    }
}

impl Polygon2 {
    /// Parses a vertex list: one vertex `x y` per line (spaces, tabs or a comma between the
    /// numbers), `#` starts a comment, blank lines are skipped. The polygon closes by itself
    /// (a last vertex equal to the first is dropped).
    pub fn from_vertex_list(source: &str, text: &str) -> Result<Self, String> {
        let mut points = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|f| !f.is_empty())
                .collect();
            let parsed: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
            match parsed {
                Some(v) if v.len() == 2 && v.iter().all(|x| x.is_finite()) => {
                    points.push([v[0], v[1]])
                }
                _ => {
                    let mut shown: String = line.chars().take(40).collect();
                    if line.chars().count() > 40 {
                        shown.push('…');
                    }
                    return Err(format!(
                        "malformed vertex list: line {} is {shown:?}, expected two finite numbers `x y`",
                        i + 1
                    ));
                }
            }
        }
        Polygon2::new(source, points)
    }

    /// A polygon from its vertices (at least three, not all on one line).
    pub fn new(source: &str, mut points: Vec<[f64; 2]>) -> Result<Self, String> {
        if points.len() > 1 && points.first() == points.last() {
            points.pop();
        }
        if points.len() < 3 {
            return Err(format!(
                "a polygon needs at least 3 vertices, found {}",
                points.len()
            ));
        }
        let poly = Polygon2 {
            source: source.to_string(),
            points,
        };
        if poly.area().abs() <= 0.0 {
            return Err("the polygon has zero area".into());
        }
        Ok(poly)
    }

    /// Signed area (positive counter-clockwise).
    pub fn area(&self) -> f64 {
        let p = &self.points;
        (0..p.len())
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            * 0.5
    }

    /// The winding number of the polygon about `q` (Sunday's crossing rule): ±1 inside a
    /// simple polygon, 0 outside.
    pub fn winding_number(&self, q: [f64; 2]) -> i32 {
        super::polygon_winding(self.points.len(), |i| self.points[i], q)
    }

    pub fn contains(&self, q: [f64; 2]) -> bool {
        self.winding_number(q) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "# unit cube, outward\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";

    #[test]
    fn obj_quads_are_triangulated_and_filled() {
        let m = TriMesh::from_obj("cube.obj", CUBE).unwrap();
        assert_eq!(m.triangles.len(), 12);
        assert!((m.tree.winding_number([0.5, 0.5, 0.5]) - 1.0).abs() < 1e-9);
        assert!(m.tree.winding_number([1.5, 0.5, 0.5]).abs() < 1e-9);
    }

    #[test]
    fn malformed_obj_is_an_error_not_a_panic() {
        for bad in [
            "",
            "v 0 0 0\nv 1 0 0\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n",
            "v 0 0 zero\nf 1 1 1\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",
            "f 1 2 3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -9 2 3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
            "\u{0}\u{1}binary junk",
        ] {
            assert!(TriMesh::from_obj("x.obj", bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn vertex_lists() {
        let p =
            Polygon2::from_vertex_list("sq", "# a square\n0 0\n1, 0\n\n1 1 # corner\n0 1\n0 0\n")
                .unwrap();
        assert_eq!(p.points.len(), 4);
        assert!((p.area() - 1.0).abs() < 1e-12);
        assert!(p.contains([0.5, 0.5]));
        assert!(!p.contains([1.5, 0.5]));
        let e = Polygon2::from_vertex_list("sq", "0 0\n1 0\nfoo\n").unwrap_err();
        assert!(e.contains("line 3 is \"foo\""), "{e}");
        assert!(Polygon2::from_vertex_list("sq", "0 0\n1 0\n").is_err());
        assert!(Polygon2::from_vertex_list("sq", "0 0 0\n1 0 0\n1 1 0\n").is_err());
        assert!(Polygon2::from_vertex_list("sq", "0 0\n1 1\n2 2\n").is_err());
        // clockwise polygons are inside too
        let cw = Polygon2::new("", vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]).unwrap();
        assert_eq!(cw.winding_number([0.5, 0.5]), -1);
    }
}
