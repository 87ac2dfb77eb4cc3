//! The `mpm` binary on tiny scenes: `run` writes PLY frames that a PLY reader parses, PNG
//! snapshots that the png crate decodes, and a summary with the documented fields; `check`
//! reports counts, memory and the time step; every subcommand has `--help`; bad input gives an
//! error on stderr and a non-zero exit.
#![cfg(not(target_arch = "wasm32"))]

use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use std::fs;
use std::path::Path;
use std::process::{Command, Output};

fn mpm(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mpm"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the mpm binary runs")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

const TINY_2D: &str = r#"{
  "name": "tiny block", "dim": 2, "domain": {"size": [1.0, 1.0]}, "cell_size": 0.05,
  "boundary": {"friction": 0.5},
  "bodies": [{"name": "sand",
    "shape": {"box": {"min": [0.3, 0.6], "max": [0.6, 0.8]}},
    "material": {"drucker_prager": {"youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200,
                                    "friction_angle": 35, "dilatancy_angle": 0, "cohesion": 0}}}]
}"#;

const TINY_3D: &str = r#"{
  "name": "tiny bunny", "dim": 3, "domain": {"size": [0.5, 0.5, 0.5]}, "cell_size": 0.05,
  "bodies": [{"name": "bunny",
    "shape": {"mesh": {"path": "meshes/bunny.obj", "scale": 0.3, "translate": [0.25, 0.1, 0.25]}},
    "material": {"elastic": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000}},
    "particles_per_cell": 2}]
}"#;

fn decode_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(fs::File::open(path).unwrap()));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

fn float(p: &Property) -> f64 {
    match p {
        Property::Float(x) => *x as f64,
        Property::Int(i) => *i as f64,
        other => panic!("unexpected property {other:?}"),
    }
}

/// Parses a PLY file with ply-rs; returns its vertices and the header length in bytes.
fn read_ply(path: &Path) -> (Vec<DefaultElement>, usize) {
    let bytes = fs::read(path).unwrap();
    let header_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .expect("a PLY header")
        + 11;
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut std::io::Cursor::new(&bytes))
        .unwrap();
    let names: Vec<&str> = ply.header.elements["vertex"]
        .properties
        .keys()
        .map(|k| k.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "x",
            "y",
            "z",
            "vx",
            "vy",
            "vz",
            "body",
            "plastic_strain",
            "pressure"
        ]
    );
    let vertices = ply.payload["vertex"].clone();
    assert_eq!(
        bytes.len(),
        header_end + vertices.len() * 36,
        "binary records of 36 bytes"
    );
    (vertices, header_end)
}

#[test]
fn run_writes_frames_and_a_summary_2d() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("tiny.json"), TINY_2D).unwrap();
    let t = 0.1;
    let out = mpm(
        &[
            "run",
            "tiny.json",
            "--time",
            "0.1",
            "--frames",
            "2",
            "--out",
            "frames",
            "--summary",
            "summary.json",
            "--size",
            "64x48",
            "--color",
            "plastic-strain",
            "-q",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));

    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    for key in [
        "time",
        "steps",
        "wall_seconds",
        "particles",
        "nonfinite_particles",
        "escaped_particles",
    ] {
        assert!(summary[key].is_number(), "summary.{key}: {summary}");
    }
    for key in ["kinetic", "gravitational", "elastic"] {
        assert!(summary["energy"][key].is_number(), "summary.energy.{key}");
    }
    assert!((summary["time"].as_f64().unwrap() - t).abs() < 1e-9);
    assert!(summary["steps"].as_u64().unwrap() > 10);
    assert_eq!(summary["nonfinite_particles"], 0);
    assert_eq!(summary["escaped_particles"], 0);
    let n = summary["particles"].as_u64().unwrap() as usize;
    assert_eq!(
        n,
        12 * 8,
        "a 0.3 × 0.2 m box at 2 × 2 particles per 0.05 m cell"
    );
    let body = &summary["bodies"][0];
    assert_eq!(body["name"], "sand");
    assert_eq!(body["particles"].as_u64().unwrap() as usize, n);
    for key in ["center_of_mass", "bbox_min", "bbox_max", "momentum"] {
        assert_eq!(body[key].as_array().unwrap().len(), 2, "bodies[0].{key}");
    }
    assert!(body["kinetic_energy"].as_f64().unwrap() > 0.0);
    assert!(body["max_plastic_strain"].is_number());
    // the block fell freely (it starts 0.6 m up): g t²/2 within a time step's worth
    let y = body["center_of_mass"][1].as_f64().unwrap();
    let fell = 0.7 - y;
    assert!(
        (fell - 0.5 * 9.81 * t * t).abs() < 9.81 * t * 2e-3 + 1e-4,
        "fell {fell} m in {t} s"
    );

    for k in 1..=2 {
        let (w, h, rgb) = decode_png(&dir.path().join(format!("frames/frame_{k:04}.png")));
        assert_eq!((w, h), (64, 48));
        assert_eq!(rgb.len(), 64 * 48 * 3);
        let background = &rgb[0..3];
        let drawn = rgb
            .chunks(3)
            .filter(|p| (p[0] as i32 - background[0] as i32).abs() > 40)
            .count();
        assert!(drawn > 20, "frame {k}: {drawn} particle pixels");

        let (vertices, _) = read_ply(&dir.path().join(format!("frames/frame_{k:04}.ply")));
        assert_eq!(vertices.len(), n);
        for v in &vertices {
            let (x, y, z) = (float(&v["x"]), float(&v["y"]), float(&v["z"]));
            assert!(
                (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y),
                "({x}, {y})"
            );
            assert_eq!((z, float(&v["vz"])), (0.0, 0.0), "2D frames have z = 0");
            assert_eq!(float(&v["body"]), 0.0);
        }
        // the last frame is the state the summary describes
        if k == 2 {
            let mean_y = vertices.iter().map(|v| float(&v["y"])).sum::<f64>() / n as f64;
            assert!((mean_y - y).abs() < 1e-5, "{mean_y} vs {y}");
            let vy = vertices.iter().map(|v| float(&v["vy"])).sum::<f64>() / n as f64;
            assert!((vy + 9.81 * t).abs() < 0.05, "falling at {vy} m/s");
        }
    }
}

#[test]
fn run_resolves_meshes_relative_to_the_scene_file_3d() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    fs::create_dir_all(scenes.join("meshes")).unwrap();
    fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny.obj"),
        scenes.join("meshes/bunny.obj"),
    )
    .unwrap();
    fs::write(scenes.join("tiny.json"), TINY_3D).unwrap();
    // run from the directory above the scene's
    let out = mpm(
        &[
            "run",
            "scenes/tiny.json",
            "-t",
            "0.01",
            "-o",
            "out",
            "--summary",
            "-",
            "--size",
            "80x60",
            "--camera",
            "orthographic",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(summary["dim"], 3);
    let n = summary["particles"].as_u64().unwrap() as usize;
    // 0.2045 m³ of bunny at scale 0.3, 0.025 m particle spacing
    let expected = 0.2045 * 0.027 / 0.025f64.powi(3);
    assert!(
        (n as f64 - expected).abs() < 0.15 * expected,
        "{n} particles, about {expected:.0} expected"
    );
    assert_eq!(
        summary["bodies"][0]["center_of_mass"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    let (w, h, _) = decode_png(&dir.path().join("out/frame_0001.png"));
    assert_eq!((w, h), (80, 60));
    let (vertices, _) = read_ply(&dir.path().join("out/frame_0001.ply"));
    assert_eq!(vertices.len(), n);
    assert!(vertices.iter().any(|v| float(&v["z"]) != 0.0));
    assert!(text(&out.stderr).contains("particles"), "a closing report");
}

#[test]
fn check_reports_counts_memory_and_time_step() {
    let dir = tempfile::tempdir().unwrap();
    // a max_dt above the CFL step, so that the CFL bound sets dt
    let scene = TINY_2D.replace(
        "\"cell_size\": 0.05,",
        "\"cell_size\": 0.05, \"max_dt\": 0.01,",
    );
    fs::write(dir.path().join("tiny.json"), scene).unwrap();
    let out = mpm(&["check", "tiny.json"], dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(s.contains("tiny.json: valid"), "{s}");
    assert!(s.contains("particles: 96"), "{s}");
    assert!(s.contains("memory: about"), "{s}");
    // dt = CFL h / c with c = √((K + 4G/3)/ρ)
    let (e, nu, rho): (f64, f64, f64) = (3.5e5, 0.3, 2200.0);
    let c = ((e / (3.0 * (1.0 - 2.0 * nu)) + 4.0 / 3.0 * e / (2.0 * (1.0 + nu))) / rho).sqrt();
    let dt = 0.4 * 0.05 / c;
    assert!(
        s.contains(&format!("stable dt: {dt:.4e} s")),
        "{s} (expected dt {dt:.4e})"
    );
    // --set as the page's slider: four times stiffer sand carries waves twice as fast.
    let out = mpm(
        &[
            "check",
            "tiny.json",
            "--set",
            "drucker_prager.youngs_modulus=1.4e6",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    let dt = dt / 2.0;
    assert!(
        s.contains(&format!("stable dt: {dt:.4e} s")),
        "{s} (expected dt {dt:.4e})"
    );
}

/// A Mohr–Coulomb body in a scene file: `check` names its material and takes its live
/// parameters (`--set mohr_coulomb.…`, listed by `run --help`), `run` steps it.
#[test]
fn a_mohr_coulomb_scene_checks_and_runs() {
    let dir = tempfile::tempdir().unwrap();
    let scene = TINY_2D.replace("drucker_prager", "mohr_coulomb");
    fs::write(dir.path().join("mc.json"), scene).unwrap();
    let out = mpm(
        &[
            "check",
            "mc.json",
            "--set",
            "mohr_coulomb.friction_angle=25",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(s.contains("mohr_coulomb"), "{s}");
    let out = mpm(
        &[
            "check",
            "mc.json",
            "--set",
            "mohr_coulomb.friction_angle=95",
        ],
        dir.path(),
    );
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("bodies[0].material.mohr_coulomb.friction_angle = 95"),
        "{}",
        text(&out.stderr)
    );
    let help = text(&mpm(&["run", "--help"], dir.path()).stdout);
    assert!(help.contains("mohr_coulomb.friction_angle"), "{help}");
    let out = mpm(
        &["run", "mc.json", "-t", "0.05", "-n", "1", "-o", "out"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// `mpm check SCENE | head`: the reader closes the pipe before the command has written
/// everything; the command ends quietly (success, nothing on stderr), not with a panic on
/// the closed pipe.
#[test]
fn a_closed_output_ends_the_command_quietly() {
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("tiny.json"), TINY_2D).unwrap();
    for args in [
        vec!["check", "tiny.json"],
        vec!["run", "tiny.json", "-q", "-t", "0.01", "--summary", "-"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_mpm"))
            .args(&args)
            .current_dir(dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // closed before the scene is even read
        let out = child.wait_with_output().unwrap();
        let err = text(&out.stderr);
        assert!(out.status.success(), "{args:?}: {:?} {err}", out.status);
        assert!(err.is_empty(), "{args:?}: {err}");
    }
}

#[test]
fn every_subcommand_has_help() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (vec!["--help"], "run"),
        (vec!["run", "--help"], "--time"),
        (vec!["check", "--help"], "SCENE"),
        (vec!["play", "--help"], "--speed"),
        (vec!["help", "run"], "--frames"),
    ] {
        let out = mpm(&args, dir.path());
        assert!(out.status.success(), "{args:?}");
        assert!(
            text(&out.stdout).contains(needle),
            "{args:?}: {}",
            text(&out.stdout)
        );
    }
}

#[test]
fn errors_go_to_stderr_with_a_non_zero_exit() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("tiny.json"), TINY_2D).unwrap();
    fs::write(
        dir.path().join("bad.json"),
        TINY_2D.replace("\"poisson_ratio\": 0.3", "\"poisson_ratio\": 0.7"),
    )
    .unwrap();
    for (args, needle) in [
        (
            vec!["run", "bad.json", "--time", "1"],
            "mpm: error: bad.json: bodies[0].material.drucker_prager.poisson_ratio = 0.7: must be in [0, 0.5)",
        ),
        (vec!["check", "bad.json"], "poisson_ratio = 0.7"),
        (
            vec!["run", "missing.json", "--time", "1"],
            "mpm: error: cannot read the scene file: missing.json:",
        ),
        (
            vec!["run", "tiny.json", "--time", "-1"],
            "--time = -1: must be a finite number > 0",
        ),
        (vec!["run", "tiny.json"], "--time"),
        (
            vec!["run", "tiny.json", "-t", "1", "--size", "10x10000"],
            "[16, 8192]",
        ),
        (
            vec!["check", "tiny.json", "--cell-size", "0.3"],
            "--cell-size: domain.size[0] = 1: must be a whole number of cells",
        ),
        (
            vec!["play", "tiny.json"],
            "play needs an interactive terminal",
        ),
        (
            vec![
                "check",
                "tiny.json",
                "--set",
                "drucker_prager.friction_angle=95",
            ],
            "--set: bodies[0].material.drucker_prager.friction_angle = 95: must be in [0, 90)",
        ),
        (
            vec!["run", "tiny.json", "-t", "1", "--set", "warp=9"],
            "--set: parameter = warp: must be one of gravity, wall_friction, cfl",
        ),
        (vec!["frobnicate"], "unrecognized subcommand"),
    ] {
        let out = mpm(&args, dir.path());
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(out.stdout.is_empty(), "{args:?}: nothing on stdout");
        let err = text(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// A body with `appear_at` enters at its time in `mpm run`, and `mpm check` lists it.
#[test]
fn run_adds_bodies_at_their_times() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene: serde_json::Value = serde_json::from_str(TINY_2D).unwrap();
    let mut late = scene["bodies"][0].clone();
    late["name"] = "late".into();
    late["shape"] = serde_json::json!({"box": {"min": [0.7, 0.6], "max": [0.9, 0.8]}});
    late["appear_at"] = 0.05.into();
    scene["bodies"].as_array_mut().unwrap().push(late);
    fs::write(dir.path().join("late.json"), scene.to_string()).unwrap();
    let summary = |t: &str| -> serde_json::Value {
        let out = mpm(
            &["run", "late.json", "-t", t, "-q", "--summary", "-"],
            dir.path(),
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let before = summary("0.04");
    assert_eq!(before["bodies"].as_array().unwrap().len(), 1);
    let after = summary("0.06");
    let bodies = after["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 2);
    assert_eq!(bodies[1]["name"], "late");
    // 0.2 m × 0.2 m at 0.025 m spacing (the top particles at 0.7875 m), in for 0.01 s
    assert_eq!(bodies[1]["particles"], 64);
    let top = bodies[1]["bbox_max"][1].as_f64().unwrap();
    assert!(top < 0.7875 && top > 0.786, "{top}");
    // its footprint is where it entered, so it has not run out while it falls
    let late = &after["deposits"][1];
    assert_eq!(late["name"], "late");
    for side in 0..2 {
        let r = late["runout"]["runout"][side].as_f64().unwrap();
        assert!(r.abs() < 1e-3, "late body's run-out {r}");
    }
    let out = mpm(&["check", "late.json"], dir.path());
    let shown = text(&out.stdout);
    assert!(
        shown.contains("body 1 \"late\": drucker_prager, 64 particles, enters at t = 0.05 s"),
        "{shown}"
    );
    assert!(shown.contains("64 to come"), "{shown}");
}

/// A playground session saved as a scene runs in `mpm run` as it is, beside the bunny's file:
/// the dropped bodies enter at their drop times.
#[test]
fn a_saved_playground_session_runs_in_the_cli() {
    use mpm::playground::{BunnyAssets, Playground};
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let read = |f: &str| fs::read_to_string(scenes.join(f)).unwrap();
    let mut pg = Playground::from_json(&read("column_collapse_2d.json")).unwrap();
    pg.set_bunny(BunnyAssets::parse(None, Some(&read("bunny2d.txt"))).unwrap());
    pg.set_parameter("drucker_prager.friction_angle", 22.0)
        .unwrap();
    pg.frame(0.02, 1e9, || 0.0).unwrap();
    pg.drop_at("bunny", "elastic", &[0.8, 0.3], 0.5, 0.1)
        .unwrap();
    let t = pg.session().drops[0].t;
    let dir = tempfile::tempdir().unwrap();
    let saved = pg.saved_scene_json().unwrap();
    fs::write(dir.path().join("saved.json"), &saved).unwrap();
    let out = mpm(&["check", "saved.json"], dir.path());
    assert!(
        !out.status.success(),
        "the bunny's outline must lie beside the file"
    );
    assert!(
        text(&out.stderr).contains("bodies[1].shape.polygon.path"),
        "{}",
        text(&out.stderr)
    );
    fs::copy(scenes.join("bunny2d.txt"), dir.path().join("bunny2d.txt")).unwrap();
    let run = |time: f64| -> serde_json::Value {
        let time = format!("{time}");
        let out = mpm(
            &["run", "saved.json", "-t", &time, "-q", "--summary", "-"],
            dir.path(),
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    assert_eq!(run(t - 0.001)["bodies"].as_array().unwrap().len(), 1);
    let s = run(t + 0.001);
    let bodies = s["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 2);
    assert_eq!(
        s["particles"].as_u64().unwrap() as usize,
        pg.particle_count()
    );
    assert!(saved.contains("\"friction_angle\": 22.0"), "{saved}");
}

/// A folder holding `column.json`: the tiny 2D scene's sand as a column 0.2 m wide and 0.4 m
/// high on cells of 0.025 m.
fn column_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let mut scene: serde_json::Value = serde_json::from_str(TINY_2D).unwrap();
    scene["cell_size"] = 0.025.into();
    scene["bodies"][0]["shape"] =
        serde_json::json!({"box": {"min": [0.4, 0.0], "max": [0.6, 0.4]}});
    fs::write(dir.path().join("column.json"), scene.to_string()).unwrap();
    dir
}

/// The summary measures each sand body as the page does (`mpm::measure`): a column that
/// collapses runs out on both sides of its footprint and ends lower, with flanks of a sand
/// heap's slope; at the start it has run out nowhere and stands at its height.
#[test]
fn the_summary_measures_a_collapsing_column() {
    let dir = column_dir();
    let deposit = |t: &str| -> serde_json::Value {
        let out = mpm(
            &["run", "column.json", "-t", t, "-q", "--summary", "-"],
            dir.path(),
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(summary["deposits"].as_array().unwrap().len(), 1);
        summary["deposits"][0].clone()
    };
    let start = deposit("0.001");
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert!(
        (f(&start["runout"]["footprint"]) - 0.1).abs() < 1e-3,
        "{start}"
    );
    for side in 0..2 {
        assert!(f(&start["runout"]["runout"][side]).abs() < 1e-3, "{start}");
    }
    assert!((f(&start["heap"]["height"]) - 0.4).abs() < 2e-3, "{start}");
    let end = deposit("1.0");
    for side in 0..2 {
        let r = f(&end["runout"]["runout"][side]);
        assert!(r > 0.05, "run-out {r}: {end}");
        let angle = f(&end["heap"]["flanks"][side]["angle"]);
        assert!(angle > 5.0 && angle < 60.0, "flank {angle}°: {end}");
    }
    assert!(f(&end["heap"]["height"]) < 0.35, "{end}");
}

/// The summary measures sand by its behaviour, not its model: the same column of
/// Mohr–Coulomb sand collapses and gets its deposit too (run-outs on both sides, two flanks,
/// lower), with its own angle of repose, Davis's angle below φ.
#[test]
fn the_summary_measures_a_mohr_coulomb_column() {
    let dir = column_dir();
    let path = dir.path().join("column.json");
    let mut scene: serde_json::Value = serde_json::from_slice(&fs::read(&path).unwrap()).unwrap();
    let material = scene["bodies"][0]["material"]["drucker_prager"].take();
    scene["bodies"][0]["material"] = serde_json::json!({ "mohr_coulomb": material });
    fs::write(&path, scene.to_string()).unwrap();
    let out = mpm(
        &["run", "column.json", "-t", "1.0", "-q", "--summary", "-"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let deposits = summary["deposits"].as_array().unwrap();
    assert_eq!(deposits.len(), 1, "{summary}");
    let end = &deposits[0];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!(end["model"], "mohr_coulomb");
    // its angle of repose: Davis's atan(sin φ) for ψ = 0, 29.8° for φ = 35°
    let davis = 35f64.to_radians().sin().atan().to_degrees();
    assert!((f(&end["repose_angle"]) - davis).abs() < 1e-9, "{end}");
    for side in 0..2 {
        let r = f(&end["runout"]["runout"][side]);
        assert!(r > 0.05, "run-out {r}: {end}");
        let angle = f(&end["heap"]["flanks"][side]["angle"]);
        assert!(angle > 5.0 && angle < 60.0, "flank {angle}°: {end}");
    }
    assert!(f(&end["heap"]["height"]) < 0.35, "{end}");
}

/// `--sleep` lets the collapsed column sleep once it rests, and it ends where the awake run
/// ends (height and run-outs within 2 %); without it nothing sleeps.
#[test]
fn run_sleep_lets_a_resting_column_sleep_where_it_would_rest() {
    let dir = column_dir();
    let summary = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["run", "column.json", "-t", "3", "-q", "--summary", "-"];
        args.extend_from_slice(extra);
        let out = mpm(&args, dir.path());
        assert!(out.status.success(), "{}", text(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let (awake, asleep) = (summary(&[]), summary(&["--sleep"]));
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!(f(&awake["asleep_particles"]), 0.0);
    let n = f(&asleep["particles"]);
    assert!(
        f(&asleep["asleep_particles"]) > 0.5 * n,
        "{} of {n} asleep after 3 s",
        asleep["asleep_particles"]
    );
    let (a, s) = (&awake["deposits"][0], &asleep["deposits"][0]);
    let close = |x: f64, y: f64, what: &str| {
        assert!(
            (x - y).abs() <= 0.02 * y.abs(),
            "{what}: {x} asleep, {y} awake"
        )
    };
    close(f(&s["heap"]["height"]), f(&a["heap"]["height"]), "height");
    for side in 0..2 {
        close(
            f(&s["runout"]["runout"][side]),
            f(&a["runout"]["runout"][side]),
            "run-out",
        );
    }
}

/// `check` of a poured body prints its rate, exit speed, particles per second and particles
/// in all; `run` pours them: the summary counts every layer once the spout has run.
#[test]
fn a_pour_checks_and_runs() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(
        dir.path().join("pour.json"),
        r#"{"name": "pour", "dim": 2, "domain": {"size": [0.6, 0.4]}, "cell_size": 0.02,
            "boundary": {"friction": 0.8},
            "bodies": [{"name": "sand",
              "pour": {"spout": [0.3, 0.3], "radius": 0.04, "rate": 0.008, "duration": 0.25},
              "material": {"drucker_prager": {"youngs_modulus": 3.5e5, "poisson_ratio": 0.3,
                "density": 2200, "friction_angle": 35, "dilatancy_angle": 0, "cohesion": 0}}}]}"#,
    )
    .unwrap();
    let out = mpm(&["check", "pour.json"], dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let shown = text(&out.stdout);
    // s = 0.01 m, 8 particles a layer standing for 0.08 m: 0.1 m/s, a layer every 0.1 s
    for part in [
        "body 0 \"sand\": drucker_prager, 0 particles",
        "poured from a spout at [0.3, 0.3] m, radius 0.04 m, for 0.25 s from t = 0 s",
        "rate 0.008 m²/s per metre of depth",
        "(8 particles a layer)",
        "exit speed 0.100 m/s",
        "80 particles/s",
        "24 particles in all",
        "particles: 0, 24 to be poured",
    ] {
        assert!(shown.contains(part), "{part:?} in {shown}");
    }
    let out = mpm(
        &["run", "pour.json", "-t", "0.4", "-q", "--summary", "-"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(s["particles"], 24);
    assert_eq!(s["energy"]["account_closes"], true, "{s}");
    assert!(s["deposits"][0]["runout"].is_null(), "{s}");
}

/// `--quality` samples the scene as the page's level does: `run` steps the particles the
/// playground at that level holds, and `check` says how the scene was sampled.
#[test]
fn quality_samples_as_the_page_does() {
    use mpm::playground::{Playground, Quality};
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let file = scenes.join("column_collapse_2d.json");
    let path = file.to_str().unwrap();
    let scene = mpm::SceneConfig::load(&file).unwrap();
    for q in ["live", "balanced", "fine"] {
        let pg = Playground::with_quality(scene.clone(), Quality::find(q).unwrap()).unwrap();
        let out = mpm(
            &[
                "run",
                path,
                "-t",
                "0.002",
                "-q",
                "--quality",
                q,
                "--summary",
                "-",
            ],
            &scenes,
        );
        assert!(out.status.success(), "{}", text(&out.stderr));
        let s: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(s["particles"], pg.particle_count(), "{q}");
        let out = mpm(&["check", path, "--quality", q], &scenes);
        let shown = text(&out.stdout);
        let r = pg.quality();
        let line = format!(
            "sampled at quality {q}: cell {} m (the file's 0.01 m), {} particles per cell per axis",
            r.cell_size, r.particles_per_cell
        );
        assert_eq!(shown.contains(&line), q != "fine", "{q}: {shown}");
        assert!(
            shown.contains(&format!("cell {} m", r.cell_size)),
            "{q}: {shown}"
        );
    }
    let out = mpm(&["check", path, "--quality", "coarse"], &scenes);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("possible values: live, balanced, fine"),
        "{}",
        text(&out.stderr)
    );
}
