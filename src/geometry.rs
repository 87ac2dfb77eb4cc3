//! Shapes that bodies are cut from, and their sampling into particles on a regular lattice.

use crate::error::{Error, Result, check_finite_vec, check_positive};
use serde::{Deserialize, Serialize};

/// A region of space, as written in scene files (`{"box": {...}}`, `{"union": [...]}`, ...).
/// Coordinates are in metres; in a 2D scene vectors have two components.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// An axis-aligned box.
    Box { min: Vec<f64>, max: Vec<f64> },
    /// A ball (a disc in 2D).
    Ball { center: Vec<f64>, radius: f64 },
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

impl Shape {
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

    /// Whether a point lies inside (explicit point lists contain nothing).
    pub fn contains(&self, p: [f64; 3], dim: usize) -> bool {
        match self {
            Shape::Box { min, max } => (0..dim).all(|a| p[a] >= min[a] && p[a] <= max[a]),
            Shape::Ball { center, radius } => {
                (0..dim).map(|a| (p[a] - center[a]).powi(2)).sum::<f64>() <= radius * radius
            }
            Shape::Points { .. } => false,
            Shape::Union(s) => s.iter().any(|s| s.contains(p, dim)),
            Shape::Difference(s) => {
                s[0].contains(p, dim) && !s[1..].iter().any(|s| s.contains(p, dim))
            }
        }
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
            Shape::Points { positions, .. } => positions
                .iter()
                .map(|p| Aabb {
                    min: vec3(p),
                    max: vec3(p),
                })
                .reduce(Aabb::union)
                .expect("validated: at least one point"),
            Shape::Union(s) => s
                .iter()
                .map(|s| s.bounds(dim))
                .reduce(Aabb::union)
                .expect("validated: non-empty"),
            Shape::Difference(s) => s[0].bounds(dim),
        }
    }

    /// Samples the shape into particles: a lattice of `per_cell` points per axis and cell of
    /// size `cell_size`, aligned with the grid (points at (k + ½) Δx), or the explicit
    /// points. Returns positions (3 components, unused ones zero) and the volume of each.
    pub fn sample(&self, dim: usize, cell_size: f64, per_cell: u32) -> (Vec<[f64; 3]>, f64) {
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
        let b = self.bounds(dim);
        let mut lo = [0i64; 3];
        let mut hi = [0i64; 3];
        for a in 0..dim {
            lo[a] = (b.min[a] / dx - 0.5).ceil() as i64;
            hi[a] = (b.max[a] / dx - 0.5).floor() as i64;
        }
        let mut out = Vec::new();
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    let idx = [i, j, k];
                    let p: [f64; 3] = std::array::from_fn(|a| {
                        if a < dim {
                            (idx[a] as f64 + 0.5) * dx
                        } else {
                            0.0
                        }
                    });
                    if self.contains(p, dim) {
                        out.push(p);
                    }
                }
            }
        }
        (out, lattice_volume)
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
    }
}
