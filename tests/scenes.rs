//! Every shipped scene file loads, validates and runs a few steps with finite values; the
//! asset interface (paths as written, text handed over in memory) builds the same simulation
//! as loading from disk; the bunny mesh and silhouette fill the volumes they enclose.
#![cfg(not(target_arch = "wasm32"))]

use mpm::io::Snapshot;
use mpm::sim::Spout;
use mpm::{AnySimulation, Error, SceneConfig, Shape};
use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn scene_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_shipped_scene_loads_validates_and_steps() {
    let files = scene_files();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    for paper in [
        "elastic_bunny",
        "plastic_bunny",
        "notched_sand_block",
        "bunny_on_sand_ball",
        "column_collapse",
        "pour",
    ] {
        for dim in [2, 3] {
            let name = format!("{paper}_{dim}d");
            assert!(names.contains(&name), "scenes/{name}.json is missing");
        }
    }
    for path in &files {
        let scene = SceneConfig::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let dim = scene.dim;
        assert!(
            path.to_string_lossy().ends_with(&format!("_{dim}d.json")),
            "{}: dim {dim} does not match the file name",
            path.display()
        );
        assert!(
            !scene.name.is_empty(),
            "{}: give the scene a name",
            path.display()
        );
        // the particles a spout will pour count with those sampled
        let poured: u64 = scene
            .bodies
            .iter()
            .filter_map(|b| {
                let pour = b.pour.as_ref()?;
                let spout = Spout::new(
                    pour,
                    dim,
                    scene.cell_size,
                    b.particles_per_cell,
                    0.0,
                    0,
                    0.0,
                );
                Some(spout.particles())
            })
            .sum();
        let mut sim = AnySimulation::new(scene).unwrap();
        let n = sim.particle_count() + poured as usize;
        assert!(
            (1000..=60_000).contains(&n),
            "{}: {n} particles (interactive scenes hold 10³ to 6·10⁴)",
            path.display()
        );
        let e0 = sim.diagnostics().total_energy();
        let in0 = sim.diagnostics().energy_in;
        for _ in 0..3 {
            sim.step()
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
        let d = sim.diagnostics();
        assert_eq!(d.nonfinite, 0, "{}", path.display());
        assert!(
            d.kinetic.is_finite() && d.elastic.is_finite() && d.gravitational.is_finite(),
            "{}: {d:?}",
            path.display()
        );
        // three small steps from rest cannot create energy: the total grows by what a spout
        // brought in at most
        let brought = d.energy_in - in0;
        assert!(poured > 0 || brought == 0.0, "{}", path.display());
        assert!(
            d.total_energy() <= e0 + brought + 1e-6 * (e0.abs() + brought.abs()).max(1.0),
            "{}: energy grew from {e0} to {} ({brought} brought in)",
            path.display(),
            d.total_energy()
        );
        let snap = Snapshot::of(&sim);
        assert_eq!(snap.nonfinite(), 0, "{}", path.display());
        assert_eq!(snap.escaped(), 0, "{}", path.display());
    }
}

#[test]
fn the_asset_interface_builds_the_same_simulation_from_memory() {
    // what the browser does: read the JSON, list the assets, hand their text over
    let mut files_read = Vec::new();
    for path in scene_files() {
        let text = fs::read_to_string(&path).unwrap();
        let mut scene = SceneConfig::from_json(&text).unwrap();
        let assets = scene.asset_paths();
        let mut store = HashMap::new();
        for a in &assets {
            store.insert(a.clone(), fs::read_to_string(scenes_dir().join(a)).unwrap());
        }
        let mut reads = 0;
        scene
            .resolve_assets(|p| {
                reads += 1;
                files_read.push(p.to_string());
                store.get(p).cloned().ok_or_else(|| Error::Io {
                    path: p.into(),
                    message: "not fetched".into(),
                })
            })
            .unwrap();
        assert_eq!(reads, assets.len(), "each asset is read once");
        scene.validate().unwrap();
        let from_memory = AnySimulation::new(scene).unwrap();
        let from_disk = AnySimulation::new(SceneConfig::load(&path).unwrap()).unwrap();
        assert_eq!(
            Snapshot::of(&from_memory),
            Snapshot::of(&from_disk),
            "{}: the same particles either way",
            path.display()
        );
    }
    files_read.sort();
    files_read.dedup();
    assert_eq!(files_read, ["bunny.obj", "bunny2d.txt"]);
    assert!(
        fs::read_to_string(scenes_dir().join("ATTRIBUTION.md"))
            .unwrap()
            .contains("Stanford"),
        "the bunny ships with its attribution"
    );
}

#[test]
fn asset_paths_are_listed_as_written_once_each() {
    let text = r#"{"dim": 3, "domain": {"size": [1, 1, 1]}, "cell_size": 0.1, "bodies": [
        {"shape": {"union": [{"mesh": {"path": "a/b.obj"}}, {"ball": {"center": [0.5, 0.5, 0.5], "radius": 0.1}}]},
         "material": {"elastic": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000}}},
        {"shape": {"difference": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}, {"mesh": {"path": "c.obj"}}, {"mesh": {"path": "a/b.obj"}}]},
         "material": {"elastic": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000}}}]}"#;
    let mut scene = SceneConfig::from_json(text).unwrap();
    assert_eq!(scene.asset_paths(), ["a/b.obj", "c.obj"]);
    // a reader that fails names the field and the file
    let e = scene
        .resolve_assets(|p| {
            Err(Error::Io {
                path: p.into(),
                message: "404 Not Found".into(),
            })
        })
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "bodies[0].shape.union[0].mesh.path = \"a/b.obj\": cannot read an OBJ file \
         (a/b.obj: 404 Not Found); paths are relative to the scene file"
    );
}

#[test]
fn the_bunny_fills_its_volume() {
    let scene = SceneConfig::load(&scenes_dir().join("elastic_bunny_3d.json")).unwrap();
    let Shape::Mesh { loaded, .. } = &scene.bodies[0].shape else {
        panic!("the elastic bunny is a mesh")
    };
    let mesh = loaded.get().unwrap().clone();
    assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (2001, 3998));
    // at unit scale the mesh encloses 0.2045 m³ (the data's README)
    let bunny = Shape::mesh_from(mesh, 1.0, &[0.6, 0.0, 0.5]);
    let (points, volume) = bunny.sample(3, 0.02, 1);
    let filled = points.len() as f64 * volume;
    assert!(
        (filled - 0.2045).abs() < 0.01 * 0.2045,
        "filled {filled} m³ of 0.2045"
    );
    // the silhouette: lattice area against the polygon's own (shoelace) area
    let text = fs::read_to_string(scenes_dir().join("bunny2d.txt")).unwrap();
    let poly = mpm::geometry::Polygon2::from_vertex_list("bunny2d.txt", &text).unwrap();
    assert_eq!(poly.points.len(), 88); // (the 89 lines of the file include a comment)
    let shape = Shape::polygon(
        &poly
            .points
            .iter()
            .map(|p| [p[0] + 0.6, p[1]])
            .collect::<Vec<_>>(),
    );
    let (points, area) = shape.sample(2, 0.005, 1);
    let filled = points.len() as f64 * area;
    assert!(
        (filled - poly.area()).abs() < 0.01 * poly.area(),
        "filled {filled} m² of {}",
        poly.area()
    );
}

#[test]
fn sampling_is_deterministic_and_jitter_follows_the_seed() {
    let path = scenes_dir().join("column_collapse_3d.json");
    let a = Snapshot::of(&AnySimulation::new(SceneConfig::load(&path).unwrap()).unwrap());
    let b = Snapshot::of(&AnySimulation::new(SceneConfig::load(&path).unwrap()).unwrap());
    assert_eq!(a.position, b.position);
    let mut scene = SceneConfig::load(&path).unwrap();
    assert!(scene.bodies[0].jitter > 0.0, "the column is jittered");
    scene.bodies[0].seed += 1;
    let c = Snapshot::of(&AnySimulation::new(scene).unwrap());
    assert_ne!(a.position, c.position);
}

/// A plane heap of cohesionless Mohr–Coulomb sand, φ = 35°, written as a scene file, with
/// flanks at `slope` degrees on a floor as rough as the sand: after `seconds` of gravity,
/// how far its base spread (m) and how fast its fastest particle still moves (m/s).
fn mohr_coulomb_heap(slope: f64, seconds: f64) -> (f64, f64) {
    let (height, top) = (0.1f64, 0.05);
    let run = height / slope.to_radians().tan();
    let (l, r) = (0.6 - top - run, 0.6 + top + run);
    let text = format!(
        r#"{{"dim": 2, "domain": {{"size": [1.2, 0.4]}}, "cell_size": 0.01,
            "boundary": {{"friction": 0.7}},
            "bodies": [{{"name": "heap",
                "shape": {{"polygon": {{"points": [[{l}, 0], [{r}, 0], [{}, {height}], [{}, {height}]]}}}},
                "material": {{"mohr_coulomb": {{"youngs_modulus": 3.5e5, "poisson_ratio": 0.3,
                    "density": 2200, "friction_angle": 35, "dilatancy_angle": 0,
                    "cohesion": 0}}}}}}]}}"#,
        0.6 + top,
        0.6 - top
    );
    let scene = SceneConfig::from_json(&text).unwrap();
    scene.validate().unwrap();
    assert_eq!(scene.bodies[0].material.kind(), "mohr_coulomb");
    let mut sim = AnySimulation::new(scene).unwrap();
    let width = |sim: &AnySimulation| {
        let b = &sim.body_stats()[0];
        b.bbox_max[0] - b.bbox_min[0]
    };
    let w0 = width(&sim);
    sim.advance(seconds).unwrap();
    (width(&sim) - w0, sim.diagnostics().max_speed)
}

/// A Mohr–Coulomb heap loads from a scene file and stands with its flanks at 25°, below its
/// friction angle of 35° (its base spreads by less than a cell, nothing moves faster than
/// 2 cm/s after a second); at 50°, steeper than the friction angle, the same heap slumps.
#[test]
fn a_mohr_coulomb_heap_loads_and_stands_below_its_friction_angle() {
    let (spread, speed) = mohr_coulomb_heap(25.0, 1.0);
    assert!(
        spread < 0.01 && speed < 0.02,
        "25°: spread {spread} m, {speed} m/s"
    );
    let (spread, _) = mohr_coulomb_heap(50.0, 1.0);
    assert!(spread > 0.03, "50°: spread {spread} m");
}
