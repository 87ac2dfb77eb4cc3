//! The energy account of every shipped scene, lesson and validation case: each is run as
//! `mpm run` steps it (sleeping off; the shipped settings) and a line printed with the
//! energy brought in, where the sum kinetic + gravitational + elastic + dissipated ends and
//! how far it rose above the energy in at any step (as shares of the energy in play,
//! `Diagnostics::energy_error`), and the numerical and integration terms of the account.
//!
//! `cargo run --release --example energy_account [FILTER…]`: scenes for 2 s, lessons for
//! their own duration, validation cases for 1 s; arguments keep the files whose path contains
//! one of them. Exits non-zero if an account ends more than `ACCOUNT_TOLERANCE` above the
//! energy in.

use mpm::{AnySimulation, SceneConfig};
use std::path::{Path, PathBuf};

fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let filters: Vec<String> = std::env::args().skip(1).collect();
    let mut cases: Vec<(PathBuf, SceneConfig, f64)> = Vec::new();
    for path in json_files(&root.join("scenes")) {
        let scene = SceneConfig::load(&path).unwrap();
        cases.push((path, scene, 2.0));
    }
    for path in json_files(&root.join("lessons")) {
        let (lesson, scene) = mpm::lesson::Lesson::load(&path).unwrap();
        cases.push((path, scene, lesson.duration));
    }
    for path in json_files(&root.join("scenes/validation")) {
        let scene = SceneConfig::load(&path).unwrap();
        cases.push((path, scene, 1.0));
    }
    println!(
        "| case | s | steps | energy in | sum at the end | largest rise | numerical | integration |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut open = 0;
    for (path, scene, duration) in cases {
        let name = path.strip_prefix(root).unwrap().display().to_string();
        if !filters.is_empty() && !filters.iter().any(|f| name.contains(f.as_str())) {
            continue;
        }
        let mut sim = AnySimulation::new(scene).unwrap();
        let mut rise: f64 = 0.0;
        let mut failure = None;
        while sim.time() < duration {
            match sim.step() {
                Ok(d) => rise = rise.max(d.energy_error()),
                Err(e) => {
                    failure = Some(e.to_string());
                    break;
                }
            }
        }
        let d = sim.diagnostics();
        let end = d.energy_error();
        if end > mpm::sim::ACCOUNT_TOLERANCE || failure.is_some() {
            open += 1;
        }
        println!(
            "| {name} | {duration} | {} | {:.4} | {:+.2} % | {:+.2} % | {:.4} | {:+.4} |{}",
            sim.steps(),
            d.energy_in,
            100.0 * end,
            100.0 * rise,
            d.dissipated_numerical,
            d.dissipated_integration,
            failure
                .map(|e| format!(" stopped: {e}"))
                .unwrap_or_default()
        );
    }
    if open > 0 {
        eprintln!("{open} accounts end more than 2 % above the energy in, or stopped");
        std::process::exit(1);
    }
}
