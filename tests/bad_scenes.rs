//! A table of bad scene files: each gives one clear error that names the field path, the
//! value and the allowed range (or the file), and never a panic.
#![cfg(not(target_arch = "wasm32"))]

use mpm::{AnySimulation, SceneConfig};
use std::fs;
use std::path::Path;

/// A valid 2D scene with one elastic box, as JSON text; `edit` patches it.
fn scene2(edit: impl FnOnce(&mut serde_json::Value)) -> String {
    let mut v = serde_json::json!({
        "name": "bad", "dim": 2, "domain": {"size": [1.0, 1.0]}, "cell_size": 0.05,
        "bodies": [{
            "name": "block",
            "shape": {"box": {"min": [0.2, 0.0], "max": [0.6, 0.4]}},
            "material": {"elastic": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000}}
        }]
    });
    edit(&mut v);
    v.to_string()
}

/// A valid 3D scene with the bunny mesh; `edit` patches it.
fn scene3(edit: impl FnOnce(&mut serde_json::Value)) -> String {
    let mut v = serde_json::json!({
        "dim": 3, "domain": {"size": [1.0, 1.0, 1.0]}, "cell_size": 0.1,
        "bodies": [{
            "name": "bunny",
            "shape": {"mesh": {"path": "bunny.obj", "scale": 0.5, "translate": [0.5, 0.1, 0.5]}},
            "material": {"drucker_prager": {"youngs_modulus": 3.5e5, "poisson_ratio": 0.3,
                "density": 2200, "friction_angle": 35, "dilatancy_angle": 0, "cohesion": 0}}
        }]
    });
    edit(&mut v);
    v.to_string()
}

/// Loads the scene text from a file in `dir` and builds the simulation; the error message.
fn error_of(dir: &Path, text: &str) -> String {
    let path = dir.join("scene.json");
    fs::write(&path, text).unwrap();
    match SceneConfig::load(&path) {
        Err(e) => e.to_string(),
        Ok(scene) => match AnySimulation::new(scene) {
            Err(e) => e.to_string(),
            Ok(_) => String::from("(no error)"),
        },
    }
}

#[test]
fn every_bad_scene_gives_the_expected_error() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    fs::copy(scenes.join("bunny.obj"), dir.path().join("bunny.obj")).unwrap();
    fs::copy(scenes.join("bunny2d.txt"), dir.path().join("bunny2d.txt")).unwrap();
    fs::write(
        dir.path().join("broken.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
    )
    .unwrap();
    fs::write(dir.path().join("lines.obj"), "v 0 0 0\nv 1 0 0\nl 1 2\n").unwrap();
    fs::write(dir.path().join("broken.txt"), "0 0\n1 0\n1 one\n").unwrap();

    let cases: Vec<(&str, String, &str)> = vec![
        (
            "unknown top-level field",
            scene2(|v| v["gravty"] = serde_json::json!([0, -9.81])),
            "gravty: unknown field `gravty`, expected one of",
        ),
        (
            "unknown material field",
            scene2(|v| v["bodies"][0]["material"]["elastic"]["colour"] = "red".into()),
            "bodies[0].material.elastic.colour: unknown field `colour`",
        ),
        (
            "unknown shape",
            scene2(|v| v["bodies"][0]["shape"] = serde_json::json!({"cube": {"size": 1}})),
            "bodies[0].shape: unknown variant `cube`, expected one of `box`, `ball`, `cylinder`, `cone`, `mesh`, `polygon`",
        ),
        (
            "wrong type",
            scene2(|v| v["cell_size"] = "small".into()),
            "cell_size: invalid type: string \"small\", expected f64",
        ),
        (
            "wrong type in a vector",
            scene2(|v| v["bodies"][0]["velocity"] = serde_json::json!([0, "fast"])),
            "bodies[0].velocity[1]: invalid type: string \"fast\"",
        ),
        (
            "malformed JSON",
            "{\"dim\": 2, \"domain\": {\"size\": [1, 1]},".to_string(),
            "scene: EOF while parsing a value at line 1 column 38",
        ),
        (
            "stress updated last with the linear kernel",
            scene2(|v| {
                v["kernel"] = "linear".into();
                v["bodies"][0]["stress_last"] = true.into();
            }),
            "bodies[0].stress_last = true: needs the \"gimp\" or \"quadratic_bspline\" kernel",
        ),
        (
            "grains closed on a solid",
            scene2(|v| v["bodies"][0]["close_grains"] = true.into()),
            "bodies[0].close_grains = true: needs a granular material",
        ),
        (
            "Poisson ratio 0.5",
            scene2(|v| v["bodies"][0]["material"]["elastic"]["poisson_ratio"] = 0.5.into()),
            "bodies[0].material.elastic.poisson_ratio = 0.5: must be in [0, 0.5)",
        ),
        (
            "negative Poisson ratio",
            scene2(|v| v["bodies"][0]["material"]["elastic"]["poisson_ratio"] = (-0.1).into()),
            "bodies[0].material.elastic.poisson_ratio = -0.1: must be in [0, 0.5)",
        ),
        (
            "zero Young's modulus",
            scene2(|v| v["bodies"][0]["material"]["elastic"]["youngs_modulus"] = 0.into()),
            "bodies[0].material.elastic.youngs_modulus = 0: must be a finite number > 0 (Pa)",
        ),
        (
            "friction angle 90°",
            scene3(|v| v["bodies"][0]["material"]["drucker_prager"]["friction_angle"] = 90.into()),
            "bodies[0].material.drucker_prager.friction_angle = 90: must be in [0, 90) (degrees)",
        ),
        (
            "negative friction angle",
            scene3(|v| {
                v["bodies"][0]["material"]["drucker_prager"]["friction_angle"] = (-5).into()
            }),
            "bodies[0].material.drucker_prager.friction_angle = -5: must be in [0, 90) (degrees)",
        ),
        (
            "unknown volumetric rate of sand",
            scene3(|v| {
                v["bodies"][0]["material"]["drucker_prager"]["volumetric_rate"] = "cell".into()
            }),
            "bodies[0].material.drucker_prager.volumetric_rate: unknown variant `cell`, expected `particle` or `cell_average`",
        ),
        (
            "volumetric rate as a switch",
            scene3(|v| {
                v["bodies"][0]["material"]["drucker_prager"]["volumetric_rate"] = true.into()
            }),
            "bodies[0].material.drucker_prager.volumetric_rate: invalid type: boolean `true`, expected `particle` or `cell_average`",
        ),
        (
            "unknown friction match",
            scene3(|v| {
                v["bodies"][0]["material"]["drucker_prager"]["friction_match"] = "mohr".into()
            }),
            "bodies[0].material.drucker_prager.friction_match: unknown variant `mohr`, expected one of `plane_strain`, `steady_flow`, `start_stop`",
        ),
        (
            "steady-flow match at 60°",
            scene3(|v| {
                let m = &mut v["bodies"][0]["material"]["drucker_prager"];
                m["friction_match"] = "steady_flow".into();
                m["friction_angle"] = 60.into();
            }),
            "bodies[0].material.drucker_prager.friction_angle = 60: must be in [0, 60) (degrees, with the steady-flow friction match)",
        ),
        (
            "volumetric rate of a solid",
            scene2(|v| {
                v["bodies"][0]["material"]["elastic"]["volumetric_rate"] = "cell_average".into()
            }),
            "bodies[0].material.elastic.volumetric_rate: unknown field `volumetric_rate`",
        ),
        (
            "negative yield stress",
            scene2(|v| {
                v["bodies"][0]["material"] = serde_json::json!({"von_mises": {
                    "youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000, "yield_stress": -1}})
            }),
            "bodies[0].material.von_mises.yield_stress = -1: must be a finite number > 0 (Pa)",
        ),
        (
            "cell size not positive",
            scene2(|v| v["cell_size"] = (-0.05).into()),
            "cell_size = -0.05: must be > 0",
        ),
        (
            "domain not a whole number of cells",
            scene2(|v| v["cell_size"] = 0.3.into()),
            "domain.size[0] = 1: must be a whole number of cells of cell_size 0.3 (the walls lie on grid nodes), e.g. 0.9 or 1.2",
        ),
        (
            "dimension 4",
            scene2(|v| v["dim"] = 4.into()),
            "dim = 4: must be 2 or 3",
        ),
        (
            "gravity of the wrong dimension",
            scene3(|v| v["gravity"] = serde_json::json!([0, -9.81])),
            "gravity = [0.0, -9.81]: must have 3 components (the scene's dim)",
        ),
        (
            "CFL above 1",
            scene2(|v| v["cfl"] = 1.5.into()),
            "cfl = 1.5: must be in [0.001, 1]",
        ),
        (
            "negative wall friction",
            scene2(|v| v["boundary"] = serde_json::json!({"friction": -0.2})),
            "boundary.friction = -0.2: must be a finite number >= 0",
        ),
        (
            "a body outside the domain",
            scene2(|v| v["bodies"][0]["shape"]["box"]["max"] = serde_json::json!([1.2, 0.4])),
            "bodies[0].shape = extent [0.2, 1.2] along axis 0: must lie inside the domain [0, 1]",
        ),
        (
            "a mesh placed outside the domain",
            scene3(|v| {
                v["bodies"][0]["shape"]["mesh"]["translate"] = serde_json::json!([0.5, 0.8, 0.5])
            }),
            "bodies[0].shape = extent [0.8, 1.3",
        ),
        (
            "an empty shape (between lattice points)",
            scene2(|v| {
                v["bodies"][0]["shape"] =
                    serde_json::json!({"ball": {"center": [0.5, 0.5], "radius": 0.001}})
            }),
            "bodies[0].shape = a shape with no particle: must hold at least one particle",
        ),
        (
            "an empty difference",
            scene2(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"difference": [
                    {"box": {"min": [0.2, 0.2], "max": [0.4, 0.4]}},
                    {"box": {"min": [0.1, 0.1], "max": [0.5, 0.5]}}]})
            }),
            "bodies[0].shape = a shape with no particle",
        ),
        (
            "an empty union",
            scene2(|v| v["bodies"][0]["shape"] = serde_json::json!({"union": []})),
            "bodies[0].shape.union = []: must list at least one shape",
        ),
        (
            "a bad radius deep in a union",
            scene2(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"union": [
                    {"box": {"min": [0.2, 0.2], "max": [0.4, 0.4]}},
                    {"ball": {"center": [0.5, 0.5], "radius": 0}}]})
            }),
            "bodies[0].shape.union[1].ball.radius = 0: must be a finite number > 0 (m)",
        ),
        (
            "a missing mesh",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["path"] = "meshes/nothere.obj".into()),
            "bodies[0].shape.mesh.path = \"meshes/nothere.obj\": cannot read an OBJ file (",
        ),
        (
            "a malformed mesh",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["path"] = "broken.obj".into()),
            "bodies[0].shape.mesh.path = \"broken.obj\": malformed OBJ",
        ),
        (
            "a mesh without triangles",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["path"] = "lines.obj".into()),
            "bodies[0].shape.mesh.path = \"lines.obj\": no triangle in the file",
        ),
        (
            "the scene file itself as a mesh",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["path"] = "scene.json".into()),
            "bodies[0].shape.mesh.path = \"scene.json\":",
        ),
        (
            "a mesh in a 2D scene",
            scene2(|v| {
                v["bodies"][0]["shape"] =
                    serde_json::json!({"mesh": {"path": "bunny.obj", "scale": 0.2}})
            }),
            "bodies[0].shape.mesh = \"bunny.obj\": a mesh needs a 3D scene",
        ),
        (
            "a negative mesh scale",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["scale"] = (-0.5).into()),
            "bodies[0].shape.mesh.scale = -0.5: must be a finite number > 0",
        ),
        (
            "a scale that is neither a number nor a list",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["scale"] = "big".into()),
            "bodies[0].shape.mesh.scale: a number, or a list with one number per axis",
        ),
        (
            "a rotation with two angles in 3D",
            scene3(|v| v["bodies"][0]["shape"]["mesh"]["rotate_deg"] = serde_json::json!([0, 90])),
            "bodies[0].shape.mesh.rotate_deg = [0.0, 90.0]: must have 3 components",
        ),
        (
            "a malformed vertex list",
            scene2(|v| {
                v["bodies"][0]["shape"] =
                    serde_json::json!({"polygon": {"path": "broken.txt", "scale": 0.1}})
            }),
            "bodies[0].shape.polygon.path = \"broken.txt\": malformed vertex list: line 3 is \"1 one\"",
        ),
        (
            "a missing vertex list",
            scene2(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"polygon": {"path": "gone.txt"}})
            }),
            "bodies[0].shape.polygon.path = \"gone.txt\": cannot read a vertex list file",
        ),
        (
            "a polygon with both a file and points",
            scene2(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"polygon": {
                    "path": "bunny2d.txt", "points": [[0.1, 0.1], [0.2, 0.1], [0.2, 0.2]]}})
            }),
            "bodies[0].shape.polygon = both `path` and `points`: must give exactly one",
        ),
        (
            "a polygon with two points",
            scene2(|v| {
                v["bodies"][0]["shape"] =
                    serde_json::json!({"polygon": {"points": [[0.1, 0.1], [0.2, 0.1]]}})
            }),
            "bodies[0].shape.polygon.points = 2 points: a polygon needs at least 3 vertices",
        ),
        (
            "a polygon in a 3D scene",
            scene3(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"polygon": {
                    "points": [[0.1, 0.1], [0.2, 0.1], [0.2, 0.2]]}})
            }),
            "bodies[0].shape.polygon = inline points: a polygon needs a 2D scene",
        ),
        (
            "a cylinder along z in 2D",
            scene2(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"cylinder": {
                    "center": [0.5, 0.5], "radius": 0.1, "height": 0.2, "axis": "z"}})
            }),
            "bodies[0].shape.cylinder.axis = \"z\": must be \"x\" or \"y\" in a 2D scene",
        ),
        (
            "a cylinder along w",
            scene3(|v| {
                v["bodies"][0]["shape"] = serde_json::json!({"cylinder": {
                    "center": [0.5, 0.5, 0.5], "radius": 0.1, "height": 0.2, "axis": "w"}})
            }),
            "bodies[0].shape.cylinder.axis: unknown variant `w`, expected one of `x`, `y`, `z`",
        ),
        (
            "jitter of half the spacing",
            scene2(|v| v["bodies"][0]["jitter"] = 0.5.into()),
            "bodies[0].jitter = 0.5: must be in [0, 0.5) (of the particle spacing)",
        ),
        (
            "a negative seed",
            scene2(|v| v["bodies"][0]["seed"] = (-1).into()),
            "bodies[0].seed: invalid value: integer `-1`, expected u64",
        ),
        (
            "FLIP ratio above 1",
            scene2(|v| v["bodies"][0]["flip"] = 1.2.into()),
            "bodies[0].flip = 1.2: must be in [0, 1]",
        ),
        (
            "negative appear_at",
            scene2(|v| v["bodies"][0]["appear_at"] = (-0.5).into()),
            "bodies[0].appear_at = -0.5: must be a finite number >= 0 (s)",
        ),
        (
            "appear_at of the wrong type",
            scene2(|v| v["bodies"][0]["appear_at"] = "soon".into()),
            "bodies[0].appear_at: invalid type: string \"soon\", expected f64",
        ),
        (
            // the bodies to come are sampled up front and named by their place in the file
            "a body to come without particles",
            scene2(|v| {
                let mut late = v["bodies"][0].clone();
                late["shape"] =
                    serde_json::json!({"ball": {"center": [0.5, 0.5], "radius": 0.001}});
                late["appear_at"] = 2.0.into();
                v["bodies"][0]["appear_at"] = 1.0.into();
                v["bodies"].as_array_mut().unwrap().push(late);
            }),
            "bodies[1].shape = a shape with no particle",
        ),
        (
            "no particles per cell",
            scene2(|v| v["bodies"][0]["particles_per_cell"] = 0.into()),
            "bodies[0].particles_per_cell = 0: must be an integer in [1, 8]",
        ),
        (
            "a lattice too large to sample",
            scene2(|v| {
                v["domain"]["size"] = serde_json::json!([1000.0, 1000.0]);
                v["cell_size"] = 0.01.into();
                v["bodies"][0]["particles_per_cell"] = 8.into();
                v["bodies"][0]["shape"]["box"]["max"] = serde_json::json!([900.0, 900.0]);
            }),
            "bodies[0].shape = a shape spanning",
        ),
        (
            "the second body is bad",
            scene2(|v| {
                let mut second = v["bodies"][0].clone();
                second["velocity"] = serde_json::json!([0.0, f64::MAX]);
                second["material"]["elastic"]["density"] = 0.into();
                v["bodies"].as_array_mut().unwrap().push(second);
            }),
            "bodies[1].material.elastic.density = 0: must be a finite number > 0",
        ),
    ];
    let mut cases = cases;
    // a body poured from a spout 0.8 m up: 8 particles a layer (s = 0.025 m) standing for
    // 0.2 m of exit, 0.5 m/s
    let poured = |edit: fn(&mut serde_json::Value)| {
        scene2(|v| {
            let b = v["bodies"][0].as_object_mut().unwrap();
            b.remove("shape");
            b.insert(
                "pour".into(),
                serde_json::json!({"spout": [0.5, 0.8], "radius": 0.1, "rate": 0.1, "duration": 1.0}),
            );
            edit(v);
        })
    };
    assert_eq!(error_of(dir.path(), &poured(|_| {})), "(no error)");
    cases.extend([
        (
            "a shape and a pour",
            poured(|v| {
                v["bodies"][0]["shape"] =
                    serde_json::json!({"box": {"min": [0.2, 0.0], "max": [0.6, 0.4]}})
            }),
            "bodies[0].shape = a box and a pour: a body has a shape or a pour (a stream poured from a spout), not both",
        ),
        (
            "neither a shape nor a pour",
            scene2(|v| {
                v["bodies"][0].as_object_mut().unwrap().remove("shape");
            }),
            "bodies[0].shape = absent, and no pour: a body needs a shape, or a pour (a stream poured from a spout) instead",
        ),
        (
            "a spout outside the domain",
            poured(|v| v["bodies"][0]["pour"]["spout"] = serde_json::json!([1.2, 0.8])),
            "bodies[0].pour.spout = [1.2, 0.8]: must lie inside the domain with the stream's section at least one cell from every wall: x in [0.15, 0.85], y in [0.05, 0.95] (m)",
        ),
        (
            "a spout whose stream touches a wall",
            poured(|v| v["bodies"][0]["pour"]["spout"] = serde_json::json!([0.1, 0.8])),
            "bodies[0].pour.spout = [0.1, 0.8]: must lie inside the domain with the stream's section",
        ),
        (
            "a spout with three components in 2D",
            poured(|v| v["bodies"][0]["pour"]["spout"] = serde_json::json!([0.5, 0.8, 0.5])),
            "bodies[0].pour.spout = [0.5, 0.8, 0.5]: must have 2 components",
        ),
        (
            "a spout narrower than a cell",
            poured(|v| v["bodies"][0]["pour"]["radius"] = 0.02.into()),
            "bodies[0].pour.radius = 0.02: must be in [0.05, 0.25] (m: from one cell_size to a quarter of the smallest domain side)",
        ),
        (
            "a spout wider than a quarter of the domain",
            poured(|v| v["bodies"][0]["pour"]["radius"] = 0.3.into()),
            "bodies[0].pour.radius = 0.3: must be in [0.05, 0.25]",
        ),
        (
            "no rate",
            poured(|v| v["bodies"][0]["pour"]["rate"] = 0.into()),
            "bodies[0].pour.rate = 0: must be a finite number > 0 (m²/s per metre of depth)",
        ),
        (
            "a negative rate",
            poured(|v| v["bodies"][0]["pour"]["rate"] = (-0.1).into()),
            "bodies[0].pour.rate = -0.1: must be a finite number > 0",
        ),
        (
            "a rate faster than 10 m/s through the exit",
            poured(|v| v["bodies"][0]["pour"]["rate"] = 5.into()),
            "bodies[0].pour.rate = 5: must be in (0, 2] (m²/s per metre of depth): at most 10 m/s through the exit, whose 8 particles a layer stand for an area A = 0.2 m",
        ),
        (
            "no duration",
            poured(|v| v["bodies"][0]["pour"]["duration"] = 0.into()),
            "bodies[0].pour.duration = 0: must be in (0, 1000] (s)",
        ),
        (
            "a negative duration",
            poured(|v| v["bodies"][0]["pour"]["duration"] = (-1.0).into()),
            "bodies[0].pour.duration = -1: must be in (0, 1000] (s)",
        ),
        (
            "a pour longer than 1000 s",
            poured(|v| v["bodies"][0]["pour"]["duration"] = 2000.into()),
            "bodies[0].pour.duration = 2000: must be in (0, 1000] (s)",
        ),
        (
            "a pour with a misspelt field",
            poured(|v| v["bodies"][0]["pour"]["speed"] = 1.into()),
            "bodies[0].pour.speed: unknown field `speed`",
        ),
        (
            "a pour without a rate",
            poured(|v| {
                v["bodies"][0]["pour"].as_object_mut().unwrap().remove("rate");
            }),
            "bodies[0].pour: missing field `rate`",
        ),
        (
            "a kinematic poured body",
            poured(|v| v["bodies"][0]["kinematic"] = true.into()),
            "bodies[0].kinematic = true: must be false for a poured body (a stream moves under forces)",
        ),
        (
            "a poured body under a traction",
            poured(|v| {
                v["bodies"][0]["traction"] = serde_json::json!({"pressure": 1e3, "faces": ["left"]})
            }),
            "bodies[0].traction = a traction on a poured body: must be absent for a poured body",
        ),
        (
            "a poured body thrown",
            poured(|v| v["bodies"][0]["velocity"] = serde_json::json!([0.0, -1.0])),
            "bodies[0].velocity = [0.0, -1.0]: must be absent or zero for a poured body",
        ),
        (
            "a pour of more particles than a simulation holds",
            poured(|v| {
                let b = &mut v["bodies"][0];
                b["particles_per_cell"] = 8.into();
                b["pour"]["radius"] = 0.25.into();
                b["pour"]["rate"] = 5.into();
                b["pour"]["duration"] = 1000.into();
            }),
            "bodies[0].pour = 128000000 more particles: the simulation holds at most 20000000 particles",
        ),
    ]);
    cases.push((
        "a material naming two models",
        scene2(|v| {
            v["bodies"][0]["material"]["von_mises"] = serde_json::json!({
                "youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000, "yield_stress": 1e3
            })
        }),
        "bodies[0].material: names two models, `elastic` and `von_mises`: a material names exactly one of",
    ));
    cases.push((
        "a material naming no model",
        scene2(|v| v["bodies"][0]["material"] = serde_json::json!({})),
        "bodies[0].material: names no material model: it must name one of",
    ));
    let mut failures = Vec::new();
    for (what, text, expected) in &cases {
        let got = error_of(dir.path(), text);
        if std::env::var("SHOW").is_ok() {
            eprintln!("{got}");
        }
        if !got.starts_with(expected) {
            failures.push(format!(
                "{what}:\n  expected {expected:?}\n  got      {got:?}"
            ));
        }
        assert!(!got.contains('\n'), "{what}: one line, got {got:?}");
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn a_missing_scene_file_names_the_file() {
    let e = SceneConfig::load(Path::new("/nonexistent/scene.json"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/scene.json: "), "{e}");
}

#[test]
fn unresolved_assets_are_an_error_not_a_panic() {
    let text = scene3(|_| {});
    let scene = SceneConfig::from_json(&text).unwrap();
    let e = AnySimulation::new(scene).err().unwrap().to_string();
    assert!(
        e.starts_with("bodies[0].shape.mesh.path = \"bunny.obj\": is not loaded"),
        "{e}"
    );
}

/// Valid scenes that will not do what they seem to say get a warning (and still run): an
/// empty scene, a body entering after the run's end, bodies that overlap. Bodies side by side,
/// touching, get none.
#[test]
fn valid_but_suspicious_scenes_get_warnings() {
    let sim = |text: String| AnySimulation::new(SceneConfig::from_json(&text).unwrap()).unwrap();
    let empty = sim(scene2(|v| v["bodies"] = serde_json::json!([])));
    let w = empty.warnings(None);
    assert!(w.iter().any(|w| w.contains("no bodies")), "{w:?}");
    let late = sim(scene2(|v| v["bodies"][0]["appear_at"] = 5.0.into()));
    assert!(late.warnings(None).is_empty());
    let w = late.warnings(Some(1.0));
    assert!(
        w.iter()
            .any(|w| w.contains("bodies[0]") && w.contains("never appears")),
        "{w:?}"
    );
    let second = |min: [f64; 2], max: [f64; 2]| {
        scene2(|v| {
            let mut b = v["bodies"][0].clone();
            b["name"] = "other".into();
            b["shape"] = serde_json::json!({"box": {"min": min, "max": max}});
            v["bodies"].as_array_mut().unwrap().push(b);
        })
    };
    let w = sim(second([0.4, 0.2], [0.8, 0.6])).warnings(None);
    assert!(w.iter().any(|w| w.contains("overlap")), "{w:?}");
    // touching along x = 0.6: no warning
    let w = sim(second([0.6, 0.0], [0.9, 0.4])).warnings(None);
    assert!(w.is_empty(), "{w:?}");
}
