//! The shipped scenes' run times: each scene of `scenes/` stepped natively over the span
//! docs/scenes.md shows it for, as written (the page's *Fine* level, sleeping off, as `mpm run`
//! steps it), and the table of docs/scenes.md between its `<!-- run times -->` markers
//! rewritten with the particles, the cell size, the steps, the wall-clock and on-core seconds
//! and the solver's digest.
//!
//! `taskset -c 0 cargo bench --bench scenes` (or `cargo xtask scene-times`; about two minutes
//! on a quiet core). Arguments filter the scenes by substring.

#[path = "support/report.rs"]
mod report;

use mpm::{AnySimulation, SceneConfig};
use report::*;
use std::time::Instant;

/// The scenes (file stem without `_2d`/`_3d`) and the span of simulated time each is shown for.
const SPANS: [(&str, f64); 6] = [
    ("elastic_bunny", 2.0),
    ("plastic_bunny", 2.0),
    ("notched_sand_block", 2.0),
    ("bunny_on_sand_ball", 1.5),
    ("column_collapse", 1.5),
    ("pour", 5.0),
];

const BEGIN: &str = "<!-- run times: written by `cargo xtask scene-times` (benches/scenes.rs) -->";
const END: &str = "<!-- end of run times -->";

/// Seconds this thread has spent on a core (Linux); `None` elsewhere.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

struct Run {
    particles: usize,
    cell: f64,
    steps: usize,
    wall: f64,
    cpu: Option<f64>,
}

fn run(file: &str, span: f64) -> Run {
    let path = root().join("scenes").join(file);
    let scene = SceneConfig::load(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
    let cell = scene.cell_size;
    let mut sim = AnySimulation::new(scene).unwrap_or_else(|e| panic!("{file}: {e}"));
    let (start, c0) = (Instant::now(), cpu_seconds());
    let steps = sim.advance(span).unwrap_or_else(|e| panic!("{file}: {e}"));
    let run = Run {
        particles: sim.particle_count(),
        cell,
        steps,
        wall: start.elapsed().as_secs_f64(),
        cpu: c0.zip(cpu_seconds()).map(|(a, b)| b - a),
    };
    println!(
        "scene {file} span={span} particles={} steps={} seconds={:.2} cpu_seconds={}",
        run.particles,
        run.steps,
        run.wall,
        run.cpu.map_or("-".into(), |c| format!("{c:.2}"))
    );
    run
}

fn main() {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let mut rows = Vec::new();
    for (stem, span) in SPANS {
        if !filters.is_empty() && !filters.iter().any(|f| stem.contains(f.as_str())) {
            continue;
        }
        let [r3, r2] = [3, 2].map(|d| run(&format!("{stem}_{d}d.json"), span));
        let secs = |r: &Run| {
            format!(
                "{:.1} s ({})",
                r.wall,
                r.cpu.map_or("-".into(), |c| format!("{c:.1} s on core"))
            )
        };
        rows.push(vec![
            format!("`{stem}`"),
            format!("{span} s"),
            format!("{} / {}", r3.particles, r2.particles),
            format!("{} / {}", r3.cell, r2.cell),
            format!("{} / {}", r3.steps, r2.steps),
            secs(&r3),
            secs(&r2),
        ]);
    }
    if !filters.is_empty() {
        println!("(a filtered run does not rewrite docs/scenes.md)");
        return;
    }
    let generated = format!(
        "{BEGIN}\n\n{}\nMeasured at {}: each scene as written (the page's *Fine* level), sleeping off, stepped natively in one thread ({}) of the shared two-core development machine; wall-clock seconds, and in brackets the seconds the thread was on the core (the steadier figure when other work loads the machine).\n\n{}\n\n{END}",
        table(
            &[
                "scene",
                "span",
                "particles 3D / 2D",
                "cell 3D / 2D (m)",
                "steps 3D / 2D",
                "run time 3D",
                "run time 2D",
            ],
            &rows
        ),
        measured_at(),
        placement(),
        solver_line(&["solid", "sand"], "cargo xtask scene-times"),
    );
    let doc = root().join("docs/scenes.md");
    let text = std::fs::read_to_string(&doc).unwrap();
    let (Some(b), Some(e)) = (text.find(BEGIN), text.find(END)) else {
        panic!("docs/scenes.md has no run-time markers ({BEGIN} … {END})");
    };
    let text = format!("{}{generated}{}", &text[..b], &text[e + END.len()..]);
    std::fs::write(&doc, text).unwrap();
    println!("wrote {}", doc.display());
}
