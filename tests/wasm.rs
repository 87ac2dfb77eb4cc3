//! The wasm API in Node (`cargo test --target wasm32-unknown-unknown --test wasm`, runner
//! wasm-bindgen-test-runner): every shipped scene and every test scene is created and
//! stepped; each live parameter accepts a valid value and rejects an invalid one with a named
//! error and the state unchanged; bodies are added and cleared.
#![cfg(target_arch = "wasm32")]

use mpm::wasm::WebPlayground;
use wasm_bindgen::prelude::*;
use wasm_bindgen_test::*;

#[wasm_bindgen(module = "node:fs")]
extern "C" {
    #[wasm_bindgen(js_name = readFileSync, catch)]
    fn read_file_sync(path: &str, encoding: &str) -> Result<String, JsValue>;
    #[wasm_bindgen(js_name = readdirSync, catch)]
    fn readdir_sync(path: &str) -> Result<Vec<String>, JsValue>;
}

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// (path, JSON) of every scene file in `dir` (relative to the repository root).
fn scene_files(dir: &str) -> Vec<(String, String)> {
    let Ok(mut names) = readdir_sync(&format!("{ROOT}/{dir}")) else {
        return Vec::new();
    };
    names.sort();
    names
        .into_iter()
        .filter(|n| n.ends_with(".json"))
        .map(|n| {
            let path = format!("{dir}/{n}");
            let text = read_file_sync(&format!("{ROOT}/{path}"), "utf8").expect("readable");
            (path, text)
        })
        .collect()
}

fn message(e: JsError) -> String {
    let v: JsValue = e.into();
    js_sys::Error::from(v).message().into()
}

#[derive(serde::Deserialize)]
struct Diag {
    kinetic: f64,
    gravitational: f64,
    elastic: f64,
    dissipated_plastic: f64,
    dissipated_viscous: f64,
    dissipated_boundary: f64,
    dissipated_contact: f64,
    dt: f64,
    cfl: f64,
    particles: usize,
    energy_in: f64,
}

fn diag(pg: &WebPlayground) -> Diag {
    serde_json::from_str(&pg.diagnostics()).unwrap()
}

#[wasm_bindgen_test]
fn every_scene_steps_with_finite_bounded_energy() {
    let mut files = scene_files("scenes");
    files.extend(scene_files("www/test-scenes"));
    assert!(files.len() >= 13, "found {files:?}");
    assert!(
        files
            .iter()
            .any(|(p, _)| p == "scenes/bunny_on_sand_ball_3d.json")
    );
    for (path, text) in files {
        // Files the scene references (the bunny mesh, …), relative to the scene file.
        let dir = &path[..path.rfind('/').unwrap()];
        let assets: serde_json::Map<String, serde_json::Value> = mpm::wasm::asset_paths(&text)
            .unwrap_or_else(|e| panic!("{path}: {}", message(e)))
            .into_iter()
            .map(|a| {
                let t = read_file_sync(&format!("{ROOT}/{dir}/{a}"), "utf8").expect("asset");
                (a, serde_json::Value::String(t))
            })
            .collect();
        let assets = (!assets.is_empty()).then(|| serde_json::Value::Object(assets).to_string());
        let mut pg = WebPlayground::new(&text, assets, None)
            .unwrap_or_else(|e| panic!("{path}: {}", message(e)));
        // a poured body starts empty: its spout pours from the first frame on
        let poured = text.contains("\"pour\"");
        assert!(pg.particle_count() > 0 || poured, "{path}");
        let d0 = diag(&pg);
        let e0 = d0.kinetic + d0.gravitational + d0.elastic;
        for _ in 0..5 {
            pg.frame(0.004, 1e9)
                .unwrap_or_else(|e| panic!("{path}: {}", message(e)));
        }
        let d = diag(&pg);
        let total = d.kinetic + d.gravitational + d.elastic;
        for (name, v) in [
            ("kinetic", d.kinetic),
            ("gravitational", d.gravitational),
            ("elastic", d.elastic),
            (
                "dissipated",
                d.dissipated_plastic
                    + d.dissipated_viscous
                    + d.dissipated_boundary
                    + d.dissipated_contact,
            ),
            ("dt", d.dt),
            ("cfl", d.cfl),
        ] {
            assert!(v.is_finite(), "{path}: {name} = {v}");
        }
        // Energy is bounded: nothing is created beyond the starting total and what a spout
        // brought in (tolerance for the discretisation: 5 % of the initial kinetic +
        // gravitational magnitude, or of the energy brought in).
        let brought = if poured {
            d.energy_in - d0.energy_in
        } else {
            0.0
        };
        assert!(pg.particle_count() > 0, "{path}");
        let scale = d0.kinetic.abs() + d0.gravitational.abs() + d0.elastic.abs() + brought + 1e-9;
        assert!(
            total <= e0 + brought + 0.05 * scale,
            "{path}: energy grew from {e0} to {total} ({brought} brought in)"
        );
        assert!(d.cfl > 0.0 && d.cfl <= 1.0 + 1e-6, "{path}: cfl {}", d.cfl);
        assert_eq!(d.particles, pg.particle_count());
        let report: serde_json::Value =
            serde_json::from_str(&pg.frame(0.01, 1e9).unwrap()).unwrap();
        assert!(
            report["substeps"].as_u64().unwrap() >= 1,
            "{path}: {report}"
        );
    }
}

#[wasm_bindgen_test]
fn a_missing_asset_is_named() {
    let text = read_file_sync(&format!("{ROOT}/scenes/elastic_bunny_3d.json"), "utf8").unwrap();
    assert_eq!(
        mpm::wasm::asset_paths(&text).unwrap(),
        vec!["bunny.obj".to_string()]
    );
    let e = message(WebPlayground::new(&text, None, None).err().unwrap());
    assert!(e.contains("bunny.obj"), "{e}");
    let e = message(
        WebPlayground::new(&text, Some("[1, 2]".into()), None)
            .err()
            .unwrap(),
    );
    assert!(e.starts_with("assets: "), "{e}");
}

/// A valid and an invalid value of every live parameter, and the error's start.
const PARAMETERS: &[(&str, f64, f64, &str)] = &[
    (
        "gravity",
        3.7,
        f64::NAN,
        "gravity[1] = NaN: must be a finite number",
    ),
    (
        "wall_friction",
        0.2,
        -1.0,
        "boundary.friction = -1: must be a finite number >= 0",
    ),
    ("cfl", 0.3, 1.5, "cfl = 1.5: must be in [0.001, 1]"),
    (
        "elastic.youngs_modulus",
        2e5,
        0.0,
        "material.elastic.youngs_modulus = 0: must be a finite number > 0 (Pa)",
    ),
    (
        "elastic.poisson_ratio",
        0.25,
        0.5,
        "material.elastic.poisson_ratio = 0.5: must be in [0, 0.5)",
    ),
    (
        "elastic.density",
        1200.0,
        -5.0,
        "material.elastic.density = -5: must be a finite number > 0 (kg/m³)",
    ),
    (
        "elastic.flip",
        0.5,
        1.5,
        "elastic.flip = 1.5: must be in [0, 1]",
    ),
    (
        "von_mises.yield_stress",
        4000.0,
        0.0,
        "material.von_mises.yield_stress = 0: must be a finite number > 0 (Pa)",
    ),
    (
        "von_mises.youngs_modulus",
        3e5,
        f64::INFINITY,
        "material.von_mises.youngs_modulus = inf: must be a finite number > 0 (Pa)",
    ),
    (
        "drucker_prager.friction_angle",
        30.0,
        90.0,
        "material.drucker_prager.friction_angle = 90: must be in [0, 90) (degrees)",
    ),
    (
        "drucker_prager.dilatancy_angle",
        5.0,
        45.0,
        "material.drucker_prager.dilatancy_angle = 45: must be in [0, 30]",
    ),
    (
        "drucker_prager.cohesion",
        100.0,
        -1.0,
        "material.drucker_prager.cohesion = -1: must be a finite number >= 0 (Pa)",
    ),
    (
        "drucker_prager.poisson_ratio",
        0.2,
        f64::NAN,
        "material.drucker_prager.poisson_ratio = NaN: must be in [0, 0.5)",
    ),
    (
        "drucker_prager.density",
        1800.0,
        0.0,
        "material.drucker_prager.density = 0: must be a finite number > 0",
    ),
    (
        "drucker_prager.flip",
        0.9,
        -0.1,
        "drucker_prager.flip = -0.1: must be in [0, 1]",
    ),
];

#[wasm_bindgen_test]
fn every_live_parameter_is_validated_with_the_state_unchanged() {
    for dim in [2, 3] {
        let text =
            read_file_sync(&format!("{ROOT}/www/test-scenes/drop_{dim}d.json"), "utf8").unwrap();
        let mut pg = WebPlayground::new(&text, None, None).unwrap();
        pg.frame(0.01, 1e9).unwrap();
        for &(name, good, bad, error) in PARAMETERS {
            pg.set_parameter(name, good, 1.0 / 60.0)
                .unwrap_or_else(|e| panic!("{name} = {good}: {}", message(e)));
            assert_eq!(pg.parameter(name).unwrap(), good, "{name}");
            let (scene, time, n) = (pg.scene_json(), pg.time(), pg.particle_count());
            let e = message(pg.set_parameter(name, bad, 1.0 / 60.0).unwrap_err());
            assert!(
                e.starts_with(error),
                "{name} = {bad}: got {e:?}, want {error:?}"
            );
            assert_eq!(pg.scene_json(), scene, "{name}: state changed on error");
            assert_eq!((pg.time(), pg.particle_count()), (time, n));
            assert_eq!(pg.parameter(name).unwrap(), good, "{name}");
        }
        let e = message(pg.set_parameter("warp_speed", 9.0, 1.0 / 60.0).unwrap_err());
        assert!(
            e.starts_with("parameter = warp_speed: must be one of gravity, wall_friction, cfl"),
            "{e}"
        );
        // The changed parameters drive the next frames without trouble.
        pg.frame(0.02, 1e9).unwrap();
        assert!(pg.failure().is_none());
        let overrides: Vec<(String, f64)> = serde_json::from_str(&pg.overrides()).unwrap();
        assert_eq!(overrides.len(), PARAMETERS.len());
    }
}

#[wasm_bindgen_test]
fn bodies_are_added_and_cleared() {
    for dim in [2usize, 3] {
        let mut pg = WebPlayground::new(&mpm::wasm::sandbox_scene(dim), None, None).unwrap();
        assert_eq!(pg.particle_count(), 0);
        let obj = read_file_sync(&format!("{ROOT}/scenes/bunny.obj"), "utf8").unwrap();
        let polygon = read_file_sync(&format!("{ROOT}/scenes/bunny2d.txt"), "utf8").unwrap();
        let e = message(pg.set_bunny(Some("v 0 0".into()), None).unwrap_err());
        assert!(e.starts_with("bunny.obj: "), "{e}");
        pg.set_bunny(Some(obj), Some(polygon)).unwrap();
        pg.frame(1.0 / 60.0, 1e9).unwrap();
        let mut last = 0;
        for (object, model) in [
            ("bunny", "elastic"),
            ("ball", "drucker_prager"),
            ("box", "von_mises"),
        ] {
            let c = [1.0, 0.5, 0.5];
            let v = [0.0, -1.0, 0.0];
            pg.add_object(object, model, &c[..dim], &v[..dim], 0.3)
                .unwrap();
            assert!(pg.particle_count() > last, "{object}");
            last = pg.particle_count();
            assert_eq!(pg.positions_len(), last * pg.positions_stride());
            assert!(pg.positions_stride() >= dim);
        }
        assert_eq!(pg.body_count(), 3);
        let e = message(
            pg.add_object(
                "teapot",
                "elastic",
                &[1.0, 0.5, 0.5][..dim],
                &[0.0; 3][..dim],
                0.3,
            )
            .unwrap_err(),
        );
        assert!(
            e.starts_with("object = teapot: must be one of bunny, ball, box"),
            "{e}"
        );
        let e = message(
            pg.add_object(
                "ball",
                "elastic",
                &[1.0, f64::NAN, 0.5][..dim],
                &[0.0; 3][..dim],
                0.3,
            )
            .unwrap_err(),
        );
        assert!(e.starts_with("center[1] = NaN"), "{e}");
        assert_eq!(pg.body_count(), 3);
        pg.frame(0.02, 1e9).unwrap();
        for mode in ["body", "speed", "pressure", "plastic_strain", "yield"] {
            pg.set_colour_mode(mode).unwrap();
            let range = pg.update_colours();
            assert!(range[1] > range[0], "{mode}: {range:?}");
            assert_eq!(pg.colours_len(), pg.particle_count());
        }
        assert!(pg.set_colour_mode("rainbow").is_err());
        let sp: serde_json::Value = serde_json::from_str(&pg.stress_point(0).unwrap()).unwrap();
        assert!(sp["p"].as_f64().unwrap().is_finite());
        // The views JS builds over wasm memory read the same positions as Rust does.
        let memory: js_sys::WebAssembly::Memory = wasm_bindgen::memory().unchecked_into();
        let view = js_sys::Float32Array::new_with_byte_offset_and_length(
            &memory.buffer(),
            pg.positions_ptr() as u32,
            pg.positions_len() as u32,
        );
        let stride = pg.positions_stride();
        for i in (0..pg.particle_count()).step_by(97) {
            let sp: serde_json::Value = serde_json::from_str(&pg.stress_point(i).unwrap()).unwrap();
            for a in 0..dim {
                // Rust's f32 went through JSON as f64: compare in f32.
                let want = sp["position"][a].as_f64().unwrap() as f32;
                let got = view.get_index((i * stride + a) as u32);
                assert_eq!(got, want, "particle {i} axis {a}");
            }
        }
        pg.update_colours();
        assert_eq!(pg.colours_len(), pg.particle_count());
        let id = pg.particle_id(0).unwrap();
        assert!(pg.index_of(id).is_some());
        pg.clear();
        assert_eq!((pg.particle_count(), pg.body_count()), (0, 0));
        pg.frame(1.0 / 60.0, 1e9).unwrap();
        pg.reset().unwrap();
        assert_eq!(pg.particle_count(), 0);
    }
}

/// The page builds its sliders from `parameterTable` and keeps a session as JSON that
/// `replay` takes back: both cross the boundary intact.
#[wasm_bindgen_test]
fn the_parameter_table_and_a_session_cross_as_json() {
    let table: serde_json::Value = serde_json::from_str(&mpm::wasm::parameter_table()).unwrap();
    let names: Vec<&str> = table["params"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    for &(name, ..) in PARAMETERS {
        assert!(names.contains(&name), "{name} in {names:?}");
    }
    let phi = &table["params"][names
        .iter()
        .position(|n| *n == "drucker_prager.friction_angle")
        .unwrap()];
    assert_eq!(
        (
            phi["unit"].as_str(),
            phi["default"].as_f64(),
            phi["key"].as_str()
        ),
        (Some("°"), Some(35.0), Some("f"))
    );
    assert_eq!(table["models"][2]["id"], "drucker_prager");
    assert_eq!(table["objects"][0]["id"], "bunny");

    let mut pg = WebPlayground::new(&mpm::wasm::sandbox_scene(2), None, None).unwrap();
    pg.set_parameter("gravity", 4.0, 1.0 / 60.0).unwrap();
    pg.drop_at("box", "von_mises", &[1.0, 0.5], 0.5, 0.3)
        .unwrap();
    pg.frame(0.05, 1e9).unwrap();
    pg.drop_at("ball", "elastic", &[0.5, 0.5], 0.0, 0.2)
        .unwrap();
    let session = pg.session();
    let mut again = WebPlayground::new(&mpm::wasm::sandbox_scene(2), None, None).unwrap();
    let out: serde_json::Value = serde_json::from_str(&again.replay(&session).unwrap()).unwrap();
    assert_eq!(out, serde_json::json!({"rejected": [], "refused": []}));
    // The first drop lands at once (the box is empty, its time stands still), the second when
    // the simulation reaches its time.
    assert_eq!(again.body_count(), 1);
    while again.body_count() < 2 {
        again.frame(0.02, 1e9).unwrap();
    }
    let times = |pg: &WebPlayground| -> Vec<f64> {
        let s: serde_json::Value = serde_json::from_str(&pg.session()).unwrap();
        s["drops"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d["applied_at"].as_f64().unwrap())
            .collect()
    };
    let (a, b) = (times(&pg), times(&again));
    assert!(a.len() == 2 && (a[1] - b[1]).abs() < 1e-9, "{a:?} {b:?}");
    assert_eq!(again.scene_json(), pg.scene_json());
    let e = message(again.replay("{\"drops\": 3}").unwrap_err());
    assert!(e.starts_with("session: "), "{e}");
}

/// The quality levels cross as JSON; a playground opens at the default level, re-samples at
/// another (the particles scale as the lattice does), records it in the session, and refuses an
/// unknown level with the state unchanged. A particle picked where it was drawn is found again.
#[wasm_bindgen_test]
fn quality_levels_resample_the_scene() {
    let levels: serde_json::Value = serde_json::from_str(&mpm::wasm::quality_levels()).unwrap();
    let ids: Vec<&str> = levels["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["live", "balanced", "fine"]);
    assert_eq!(levels["default"], "live");
    let text =
        read_file_sync(&format!("{ROOT}/scenes/notched_sand_block_2d.json"), "utf8").unwrap();
    let mut pg = WebPlayground::new(&text, None, None).unwrap();
    let q: serde_json::Value = serde_json::from_str(&pg.quality()).unwrap();
    assert_eq!(q["quality"], "live");
    let (h, h0) = (
        q["cell_size"].as_f64().unwrap(),
        q["scene_cell_size"].as_f64().unwrap(),
    );
    let ppc = q["particles_per_cell"].as_f64().unwrap();
    assert!(h > h0 && h <= 2.0 * h0 + 1e-12, "{q}");
    assert!(q["accuracy"]["column_runout"].as_f64().unwrap().is_finite());
    let live = pg.particle_count();
    pg.frame(0.01, 1e9).unwrap();
    let e = message(pg.set_quality("ultra").unwrap_err());
    assert_eq!(e, "quality = ultra: must be one of live, balanced, fine");
    assert_eq!(pg.particle_count(), live);
    assert_eq!(pg.set_quality("fine").unwrap(), "[]");
    let fine = pg.particle_count();
    let want = (ppc / 2.0 * h0 / h).powi(2);
    assert!(
        (live as f64 / fine as f64 / want - 1.0).abs() < 0.1,
        "{live} / {fine}, want {want}"
    );
    assert_eq!(pg.time(), 0.0);
    let session: serde_json::Value = serde_json::from_str(&pg.session()).unwrap();
    assert_eq!(session["quality"], "fine");
    // Picking: the particle nearest a drawn position is that particle.
    let stride = pg.positions_stride();
    let memory: js_sys::WebAssembly::Memory = wasm_bindgen::memory().unchecked_into();
    let view = js_sys::Float32Array::new_with_byte_offset_and_length(
        &memory.buffer(),
        pg.positions_ptr() as u32,
        pg.positions_len() as u32,
    );
    let i = 1234;
    let at = [
        view.get_index((i * stride) as u32) as f64,
        view.get_index((i * stride + 1) as u32) as f64,
    ];
    assert_eq!(pg.nearest_particle(&at).unwrap(), Some(i));
    assert!(pg.nearest_particle(&[0.5]).is_err());
}

/// The wasm build computes stencils in four SIMD lanes (`kernel::F4`); they must equal, bit
/// for bit, what the one-axis scalar kernel gives (the native build's arithmetic).
#[wasm_bindgen_test]
fn simd_stencils_equal_the_scalar_kernel_bit_for_bit() {
    use mpm::kernel::{Gimp, Kernel, Linear, QuadraticBspline};
    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }
    fn check<const S: usize, K: Kernel<S>>(lp: f32) {
        let inv_h = 25.0;
        let mut xs: Vec<f32> = (0..2000).map(|i| 2.0 + i as f32 * 0.003_71).collect();
        // Exact node positions, ties, and what is clamped (huge, infinite, NaN; a negative
        // coordinate fails a debug assertion of the scalar kernel).
        xs.extend([
            0.5,
            0.75,
            1.0,
            3.0,
            3.5,
            1e30,
            4_194_304.0,
            f32::INFINITY,
            f32::NAN,
        ]);
        for (i, &x) in xs.iter().enumerate() {
            let xg = [x, xs[(i * 7 + 3) % xs.len()], xs[(i * 13 + 5) % xs.len()]];
            for dim in [2, 3] {
                let st = K::stencil(xg, dim, inv_h, lp);
                for a in 0..dim {
                    let (base, w, dw) = K::axis(xg[a], lp);
                    assert_eq!(st.base[a], base, "{:?} base at {xg:?}", K::KIND);
                    let f = xg[a] - base as f32;
                    for k in 0..S {
                        let ok = same(st.w[k][a], w[k])
                            && same(st.dw[k][a], dw[k] * inv_h)
                            && same(st.d[k][a], k as f32 - f);
                        assert!(ok, "{:?} node {k} axis {a} at {xg:?}", K::KIND);
                    }
                }
            }
        }
    }
    check::<2, Linear>(0.0);
    check::<3, QuadraticBspline>(0.0);
    for lp in [0.125, 0.25, 0.5] {
        check::<3, Gimp>(lp);
    }
}

/// `saveScene` gives a scene file in which the dropped body enters at its drop time: a new
/// playground made from it has the same bodies once that time comes.
#[wasm_bindgen_test]
fn a_saved_scene_replays_the_drops() {
    let scene = read_file_sync(&format!("{ROOT}/scenes/column_collapse_2d.json"), "utf8").unwrap();
    let mut pg = WebPlayground::new(&scene, None, None).unwrap();
    pg.set_parameter("drucker_prager.friction_angle", 28.0, 1.0 / 60.0)
        .unwrap();
    pg.frame(0.02, 1e9).unwrap();
    pg.drop_at("box", "elastic", &[0.8, 0.3], 0.0, 0.06)
        .unwrap();
    let saved = pg.save_scene().unwrap();
    let v: serde_json::Value = serde_json::from_str(&saved).unwrap();
    let t = v["bodies"][1]["appear_at"].as_f64().unwrap();
    assert!(t > 0.0199 && t < 0.021, "{t}");
    assert_eq!(
        v["bodies"][0]["material"]["drucker_prager"]["friction_angle"],
        28.0
    );
    let mut again = WebPlayground::new(&saved, None, None).unwrap();
    assert_eq!((again.body_count(), again.particle_count() > 0), (2, true));
    let before = again.particle_count();
    again.frame(t + 0.001, 1e9).unwrap();
    assert_eq!(again.particle_count(), pg.particle_count());
    assert!(again.particle_count() > before);
    assert_eq!(again.scene_json(), pg.scene_json());
}

#[wasm_bindgen_test]
fn every_lesson_checks_with_its_files_and_a_bad_one_names_the_field() {
    let lessons = scene_files("lessons");
    assert!(lessons.len() >= 5, "{} lessons", lessons.len());
    for (path, text) in lessons {
        // The scene: a file beside the lesson, or inline; its files relative to the file that
        // names them.
        let lesson: serde_json::Value = serde_json::from_str(&text).unwrap();
        let (scene, base) = match lesson["scene"].as_str() {
            Some(p) => {
                let scene_path = format!("lessons/{p}");
                let text = read_file_sync(&format!("{ROOT}/{scene_path}"), "utf8").unwrap();
                let dir = scene_path.rsplit_once('/').unwrap().0.to_string();
                (Some(text), dir)
            }
            None => (None, "lessons".to_string()),
        };
        let scene_text = scene.clone().unwrap_or_else(|| lesson["scene"].to_string());
        let mut files: serde_json::Map<String, serde_json::Value> =
            mpm::wasm::asset_paths(&scene_text)
                .unwrap_or_else(|e| panic!("{path}: {}", message(e)))
                .into_iter()
                .map(|f| {
                    let t = read_file_sync(&format!("{ROOT}/{base}/{f}"), "utf8").unwrap();
                    (f, t.into())
                })
                .collect();
        // a soil-lab lesson's compared test: its scene file, relative to the lesson file,
        // keyed as written (the page fetches it so)
        if let Some(p) = lesson["lab"]["compare"].as_str() {
            let t = read_file_sync(&format!("{ROOT}/lessons/{p}"), "utf8").unwrap();
            files.insert(p.to_string(), t.into());
        }
        let assets = serde_json::Value::Object(files).to_string();
        mpm::wasm::check_lesson(&text, scene.clone(), Some(assets.clone()))
            .unwrap_or_else(|e| panic!("{path}: {}", message(e)));
        let mut bad = lesson.clone();
        bad["view"]["colour"] = "rainbow".into();
        let e = mpm::wasm::check_lesson(&bad.to_string(), scene.clone(), Some(assets)).unwrap_err();
        assert!(
            message(e).starts_with("view.colour = rainbow: must be one of"),
            "{path}"
        );
        if lesson["scene"].is_object() && scene_text.contains(".txt") {
            // The outline missing: named.
            let e = mpm::wasm::check_lesson(&text, None, None).unwrap_err();
            assert!(message(e).contains("bunny2d.txt"), "{path}");
        }
    }
}

/// The measures cross to JavaScript: the 2D column collapse's sand is a column with Lube et
/// al.'s markers and no run-out at the start, neither poured nor held (the page's collapse);
/// the hand tool's reading is the core's; a bad point is an error naming what is allowed.
#[wasm_bindgen_test]
fn the_measures_cross_as_json() {
    let text = read_file_sync(&format!("{ROOT}/scenes/column_collapse_2d.json"), "utf8").unwrap();
    let mut pg = WebPlayground::new(&text, None, None).unwrap();
    let m: serde_json::Value = serde_json::from_str(&pg.measures()).unwrap();
    let d = &m[0];
    assert_eq!(d["name"], "column");
    assert!(d["poured"] == false && d["held"] == false, "{d}");
    assert!(
        d["column"]["law"]["source"]
            .as_str()
            .unwrap()
            .contains("2005")
    );
    for side in 0..2 {
        assert!(
            d["runout"]["runout"][side].as_f64().unwrap().abs() < 1e-3,
            "{d}"
        );
    }
    let r: serde_json::Value =
        serde_json::from_str(&mpm::wasm::hand_measure(&[0.0, 0.0], &[0.3, 0.3]).unwrap()).unwrap();
    assert!((r["length"].as_f64().unwrap() - 0.3 * 2f64.sqrt()).abs() < 1e-12);
    assert!((r["inclination"].as_f64().unwrap() - 45.0).abs() < 1e-9);
    let e = message(mpm::wasm::hand_measure(&[0.0], &[1.0]).unwrap_err());
    assert!(e.starts_with("points: "), "{e}");
}

/// A pour crosses the boundary: `pourRates` as JSON, `startPour` and `stopPour` (a no-op with
/// none running), the session's `pours` replayed by another playground to the same particles,
/// the saved scene's poured body with the time it ran, and errors naming the field.
#[wasm_bindgen_test]
fn a_pour_starts_stops_and_replays() {
    let mut pg = WebPlayground::new(&mpm::wasm::sandbox_scene(2), None, None).unwrap();
    let rates: serde_json::Value = serde_json::from_str(&pg.pour_rates()).unwrap();
    assert_eq!(rates["unit"], "m²/s");
    let q = rates["default"].as_f64().unwrap();
    let e = message(
        pg.start_pour(&[1.0, 0.5], "drucker_prager", 0.0)
            .unwrap_err(),
    );
    assert!(e.starts_with("rate = 0: must be in ["), "{e}");
    let e = message(pg.start_pour(&[1.0, 0.5], "elastic", q).unwrap_err());
    assert!(
        e.starts_with("material = elastic: must be a granular model"),
        "{e}"
    );
    assert!(message(pg.check_rate(-1.0).unwrap_err()).starts_with("rate = -1"));
    assert_eq!(pg.stop_pour(), None);
    pg.start_pour(&[1.0, 0.5], "drucker_prager", q).unwrap();
    assert!(pg.pouring());
    while pg.time() < 0.3 {
        pg.frame(0.05, 1e9).unwrap();
    }
    let held = pg.stop_pour().unwrap();
    assert!((held - 0.3).abs() < 0.05, "{held}");
    assert!(!pg.pouring());
    pg.frame(0.1, 1e9).unwrap();
    let n = pg.particle_count();
    assert!(n > 0);
    let session = pg.session();
    let s: serde_json::Value = serde_json::from_str(&session).unwrap();
    assert_eq!(s["pours"][0]["duration"].as_f64(), Some(held));
    let saved: serde_json::Value = serde_json::from_str(&pg.save_scene().unwrap()).unwrap();
    assert_eq!(saved["bodies"][0]["pour"]["duration"].as_f64(), Some(held));
    let mut again = WebPlayground::new(&mpm::wasm::sandbox_scene(2), None, None).unwrap();
    let out: serde_json::Value = serde_json::from_str(&again.replay(&session).unwrap()).unwrap();
    assert_eq!(out, serde_json::json!({"rejected": [], "refused": []}));
    while again.time() < pg.time() {
        again.frame(0.05, 1e9).unwrap();
    }
    assert_eq!(again.particle_count(), n);
}
