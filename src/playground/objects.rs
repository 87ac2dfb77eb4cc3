//! The objects a front end drops into a scene: a bunny (the shipped mesh in 3D, its silhouette
//! in 2D, or a bunny made of balls when neither was given), a ball or a box.

use crate::error::{Error, Result, not_one_of};
use crate::geometry::{Loaded, Polygon2, Scale, Shape, TriMesh};
use serde::Serialize;
use std::sync::Arc;

/// An object a front end offers to drop.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ObjectInfo {
    pub id: &'static str,
    pub label: &'static str,
}

/// The objects [`object_shape`] makes, in the order the page lists them.
pub static OBJECTS: [ObjectInfo; 3] = [
    ObjectInfo {
        id: "bunny",
        label: "Bunny",
    },
    ObjectInfo {
        id: "ball",
        label: "Ball",
    },
    ObjectInfo {
        id: "box",
        label: "Box",
    },
];

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
        _ => return Err(not_one_of("object", object, OBJECTS.iter().map(|o| o.id))),
    })
}
