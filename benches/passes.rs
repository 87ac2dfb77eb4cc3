//! Skipping what a scene does not need, measured: the cost of each pass of the step
//! (`Simulation::timings`) for scenes that need different work — one elastic body (no plastic
//! return, no contact), sand (the plastic return), many bodies apart (no contact work), many
//! bodies touching (contact), the same scene in a domain 4× larger per axis (the sparse grid
//! keeps the cost flat), each in 2D and 3D. Writes `docs/reports/passes-report.md`.
//!
//! `taskset -c 0 cargo bench --bench passes` (or `cargo xtask passes`; about two minutes).
//!
//! `-- --trace DIM STEPS SCENE` times nothing and writes no report: it runs the scene whose
//! name contains SCENE (e.g. `touching`) in DIM dimensions for STEPS steps on one fresh
//! simulation, for instruction counts per function under
//! `valgrind --tool=callgrind target/release/deps/passes-* --trace 2 200 touching`.

#[path = "support/report.rs"]
mod report;

use mpm::math::Dim;
use mpm::{BodyConfig, D2, D3, Material, PassTimings, SceneConfig, Shape, Simulation};
use report::*;
use std::fmt::Write;

fn elastic() -> Material {
    Material::elastic(1.0e5, 0.3, 1000.0)
}
fn sand() -> Material {
    Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0)
}

/// Boxes [lo, hi] in 3D coordinates, cut to `dim`.
fn body(name: &str, lo: [f64; 3], hi: [f64; 3], m: Material, dim: usize) -> BodyConfig {
    BodyConfig::new(name, Shape::cuboid(&lo[..dim], &hi[..dim]), m)
}

/// The scenes: (name, scene). The block is 0.4 × 0.2 (× 0.4) m on the floor of a 1 × 0.5
/// (× 1) m domain; the eight-body scenes split the same volume into eight blocks, 0.05 m
/// wide, either 0.05 m apart or side by side.
fn scenes(dim: usize) -> Vec<(String, SceneConfig)> {
    let h = if dim == 2 { 0.004 } else { 0.02 };
    let size = |scale: f64| -> Vec<f64> {
        [1.0, 0.5, 1.0][..dim]
            .iter()
            .map(|s| s * scale)
            .collect::<Vec<_>>()
    };
    let new = |scale: f64| {
        let mut s = SceneConfig::new(dim, &size(scale), h);
        s.boundary.friction = 0.5;
        s
    };
    let mut out = Vec::new();
    let mut one = new(1.0);
    one.bodies.push(body(
        "block",
        [0.3, 0.0, 0.3],
        [0.7, 0.2, 0.7],
        elastic(),
        dim,
    ));
    out.push(("one elastic body".to_string(), one.clone()));
    let mut s = new(1.0);
    s.bodies
        .push(body("sand", [0.3, 0.0, 0.3], [0.7, 0.2, 0.7], sand(), dim));
    out.push(("sand only".to_string(), s));
    let mut apart = new(1.0);
    let mut touching = new(1.0);
    for i in 0..8 {
        let x = 0.05 + 0.1 * i as f64;
        apart.bodies.push(body(
            &format!("apart {i}"),
            [x, 0.0, 0.3],
            [x + 0.05, 0.2, 0.7],
            elastic(),
            dim,
        ));
        let x = 0.3 + 0.05 * i as f64;
        touching.bodies.push(body(
            &format!("touching {i}"),
            [x, 0.0, 0.3],
            [x + 0.05, 0.2, 0.7],
            elastic(),
            dim,
        ));
    }
    out.push(("8 elastic bodies apart".to_string(), apart));
    out.push(("8 elastic bodies touching".to_string(), touching));
    let mut big = new(4.0);
    big.bodies = one.bodies.clone();
    out.push(("one elastic body, domain 4× per axis".to_string(), big));
    out
}

struct Measured {
    particles: usize,
    blocks: usize,
    t: PassTimings,
}

/// Five rounds of `steps` steps on each of three fresh simulations of the scene (after as
/// many warm-up steps each); the median round of the fifteen. Fresh simulations because the
/// spread between them (memory placement) is larger than between rounds of one.
fn measure<D: Dim>(scene: SceneConfig, steps: u64) -> Measured {
    let mut rounds = Vec::new();
    let (mut particles, mut blocks) = (0, 0);
    for _ in 0..3 {
        let mut sim = Simulation::<D>::new(scene.clone()).expect("bench scene");
        for _ in 0..steps {
            sim.step().expect("warm-up");
        }
        for _ in 0..5 {
            sim.timings = Some(PassTimings::default());
            for _ in 0..steps {
                sim.step().expect("step");
            }
            rounds.push(sim.timings.take().unwrap());
        }
        particles = sim.particles().len();
        blocks = sim.diagnostics().grid_blocks;
    }
    rounds.sort_by(|a, b| total(a).partial_cmp(&total(b)).unwrap());
    Measured {
        particles,
        blocks,
        t: rounds[rounds.len() / 2],
    }
}

fn total(t: &PassTimings) -> f64 {
    t.allocate + t.scatter + t.stress + t.grid + t.contact + t.walls + t.gather
}

/// `--trace DIM STEPS SCENE` (see the module documentation).
fn trace(args: &[String]) {
    let usage =
        "--trace takes DIM (2 or 3), STEPS and part of a scene's name, e.g. --trace 2 200 touching";
    let (Some(dim), Some(steps), Some(part)) = (
        args.first().and_then(|d| d.parse::<usize>().ok()),
        args.get(1).and_then(|n| n.parse::<u64>().ok()),
        args.get(2),
    ) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    if dim != 2 && dim != 3 {
        eprintln!("{usage}");
        std::process::exit(2);
    }
    let Some((name, scene)) = scenes(dim)
        .into_iter()
        .find(|(n, _)| n.contains(part.as_str()))
    else {
        eprintln!("no scene of the passes bench is named like {part:?}");
        std::process::exit(2);
    };
    fn run<D: Dim>(scene: SceneConfig, steps: u64) -> usize {
        let mut sim = Simulation::<D>::new(scene).expect("bench scene");
        for _ in 0..steps {
            sim.step().expect("step");
        }
        sim.particles().len()
    }
    let particles = if dim == 2 {
        run::<D2>(scene, steps)
    } else {
        run::<D3>(scene, steps)
    };
    println!("{dim}D {name}: {particles} particles, {steps} steps");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--trace") {
        return trace(&args[i + 1..]);
    }
    let mut rows = Vec::new();
    for dim in [2, 3] {
        let mut base = None;
        for (name, scene) in scenes(dim) {
            let steps = if dim == 2 { 100 } else { 30 };
            let m = if dim == 2 {
                measure::<D2>(scene, steps)
            } else {
                measure::<D3>(scene, steps)
            };
            let per = |x: f64| 1e9 * x / (m.particles as f64 * m.t.steps as f64);
            let tot = per(total(&m.t));
            if name == "one elastic body" {
                base = Some(tot);
            }
            let rel = base.map_or(String::new(), |b| format!("{:.2}×", tot / b));
            println!(
                "{dim}D {name}: {} particles, {tot:.1} ns/particle-step {rel}",
                m.particles
            );
            rows.push(vec![
                format!("{dim}D"),
                name,
                format!("{}", m.particles),
                format!("{}", m.blocks),
                format!("{:.1}", per(m.t.allocate)),
                format!("{:.1}", per(m.t.scatter)),
                format!("{:.1}", per(m.t.stress)),
                format!("{:.1}", per(m.t.grid)),
                format!("{:.1}", per(m.t.contact)),
                format!("{:.1}", per(m.t.walls)),
                format!("{:.1}", per(m.t.gather)),
                format!("{tot:.1}"),
                rel,
            ]);
        }
    }
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Cost of each pass (generated)\n\nRegenerate with `taskset -c 0 cargo bench --bench passes` (or `cargo xtask passes`). Nanoseconds per particle per step, the median of fifteen rounds (five on each of three fresh simulations; 100 steps in 2D, 30 in 3D, after as many warm-up steps), one core; the last column is the total against the one elastic body of the same dimension. Written by `benches/passes.rs`; the discussion is in [work-precision.md](../work-precision.md#skipping-what-a-scene-does-not-need). Measured at {}.\n\n{}\n\n{}",
        measured_at(),
        solver_line(&["solid", "sand"], "cargo xtask passes"),
        table(
            &[
                "dim",
                "scene",
                "particles",
                "grid blocks",
                "allocate",
                "scatter",
                "stress",
                "grid",
                "contact",
                "walls",
                "gather",
                "total",
                "vs one body"
            ],
            &rows
        )
    );
    let path = root().join("docs").join("reports").join("passes-report.md");
    std::fs::write(&path, md).unwrap();
    println!("wrote {}", path.display());
}
