//! Throughput of the solver: particle-substeps per second on blocks of sand and of elastic
//! material settling on the ground, in 2D and 3D, with each kernel, and the cost of the same
//! scene in a domain twice as large (the sparse grid makes it nearly free).
//!
//! `cargo bench --bench throughput` (pin it to one core for stable figures:
//! `taskset -c 0 cargo bench --bench throughput`). Optional arguments filter the cases by
//! substring, e.g. `cargo bench --bench throughput -- 3d`.
//!
//! `-- --digest N` times nothing: it runs each selected block for N substeps and prints a hash
//! of every particle's state (all digits), to check that two builds or two versions of a pass
//! compute the same thing bit for bit, and (under callgrind, with N and a smaller N) to count
//! instructions per particle-substep.
//!
//! `-- --stress-last` runs the sand blocks of the C¹ kernels with their stress updated at the
//! end of the step (`"stress_last": true`) instead of first, the default's order; the other
//! blocks are left out.
//!
//! Each figure is printed once for people and once as a machine-readable line:
//! `bench scene=<name> dim=<2|3> particles=<n> substeps=<k> seconds=<s> particle_substeps_per_s=<x>
//! cpu_seconds=<c> cpu_particle_substeps_per_s=<y>`. The second rate counts the time the
//! thread was on a core (Linux's `/proc/thread-self/schedstat`), not the time it waited for
//! one: on a machine shared with other work it is the steadier of the two.

use mpm::{AnySimulation, BodyConfig, KernelKind, Material, SceneConfig, Shape};
use std::time::Instant;

struct Case {
    name: String,
    scene: SceneConfig,
}

fn sand() -> Material {
    Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0)
}

fn elastic() -> Material {
    Material::elastic(1.0e5, 0.3, 1000.0)
}

/// A block resting on the ground of a domain `scale` times the base size.
fn block(dim: usize, material: Material, kernel: KernelKind, scale: f64) -> SceneConfig {
    let (size, h, lo, hi) = if dim == 3 {
        (
            vec![1.0, 0.5, 1.0],
            0.0125,
            vec![0.3, 0.0, 0.3],
            vec![0.7, 0.2, 0.7],
        )
    } else {
        (vec![1.0, 0.5], 0.002, vec![0.25, 0.0], vec![0.75, 0.25])
    };
    let mut scene = SceneConfig::new(dim, &size.iter().map(|s| s * scale).collect::<Vec<_>>(), h);
    scene.kernel = kernel;
    scene.boundary.friction = 0.5;
    scene
        .bodies
        .push(BodyConfig::new("block", Shape::cuboid(&lo, &hi), material));
    scene
}

fn kernel_name(k: KernelKind) -> &'static str {
    match k {
        KernelKind::Linear => "linear",
        KernelKind::QuadraticBspline => "bspline",
        KernelKind::Gimp => "gimp",
    }
}

/// The blocks; with `stress_last`, only the sand blocks of the C¹ kernels, their stress
/// updated last.
fn cases(stress_last: bool) -> Vec<Case> {
    if stress_last {
        return cases(false)
            .into_iter()
            .filter(|c| c.name.starts_with("sand_") && !c.name.contains("linear"))
            .map(|mut c| {
                for b in &mut c.scene.bodies {
                    b.stress_last = Some(true);
                }
                c.name = format!("{}_stress_last", c.name);
                c
            })
            .collect();
    }
    let mut out = Vec::new();
    for dim in [3, 2] {
        for kernel in [
            KernelKind::Linear,
            KernelKind::QuadraticBspline,
            KernelKind::Gimp,
        ] {
            for (mat, material) in [("sand", sand()), ("elastic", elastic())] {
                let k = kernel_name(kernel);
                out.push(Case {
                    name: format!("{mat}_block_{dim}d_{k}"),
                    scene: block(dim, material.clone(), kernel, 1.0),
                });
                if mat == "sand" {
                    out.push(Case {
                        name: format!("{mat}_block_{dim}d_{k}_domain_x2"),
                        scene: block(dim, material, kernel, 2.0),
                    });
                }
            }
        }
    }
    out
}

/// The share of each pass in a run (from the solver's own pass timings).
fn pass_shares(t: &mpm::PassTimings) -> String {
    let parts = [
        ("allocate", t.allocate),
        ("scatter", t.scatter),
        ("stress", t.stress),
        ("grid", t.grid),
        ("contact", t.contact),
        ("walls", t.walls),
        ("gather", t.gather),
    ];
    let total: f64 = parts.iter().map(|p| p.1).sum();
    parts
        .iter()
        .map(|(n, v)| format!("{n} {:.0}%", 100.0 * v / total))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Seconds this thread has spent on a core (Linux); `None` elsewhere.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

/// Runs `steps` substeps `rounds` times after a warm-up; returns the median wall-clock and
/// on-core seconds per round.
fn time(sim: &mut AnySimulation, steps: usize, rounds: usize) -> (f64, Option<f64>) {
    for _ in 0..steps {
        sim.step().expect("warm-up step");
    }
    let (mut wall, mut cpu): (Vec<f64>, Vec<Option<f64>>) = (0..rounds)
        .map(|_| {
            let (start, c0) = (Instant::now(), cpu_seconds());
            for _ in 0..steps {
                sim.step().expect("step");
            }
            let c = c0.zip(cpu_seconds()).map(|(a, b)| b - a);
            (start.elapsed().as_secs_f64(), c)
        })
        .unzip();
    wall.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut cpu: Option<Vec<f64>> = cpu.drain(..).collect();
    let cpu = cpu.as_mut().map(|c| {
        c.sort_by(|a, b| a.partial_cmp(b).unwrap());
        c[rounds / 2]
    });
    (wall[rounds / 2], cpu)
}

/// Whether the case `name` is among those the command line's filters (substrings) select.
fn selected(filters: &[String], name: &str) -> bool {
    filters.is_empty() || filters.iter().any(|f| name.contains(f.as_str()))
}

/// FNV-1a over the particles' state as Rust prints it (floats in their shortest exact form).
fn digest(sim: &AnySimulation) -> u64 {
    let text = match sim {
        AnySimulation::D2(s) => format!("{:?}", s.particles()),
        AnySimulation::D3(s) => format!("{:?}", s.particles()),
    };
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let digest_steps = args.iter().position(|a| a == "--digest").map(|i| {
        match args.get(i + 1).map(|n| n.parse::<usize>()) {
            Some(Ok(n)) => n,
            _ => {
                eprintln!("--digest takes a number of substeps, e.g. --digest 25");
                std::process::exit(2)
            }
        }
    });
    let stress_last = args.iter().any(|a| a == "--stress-last");
    let filters: Vec<String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| !a.starts_with("--") && (*i == 0 || args[i - 1] != "--digest"))
        .map(|(_, a)| a.clone())
        .collect();
    if let Some(steps) = digest_steps {
        for case in cases(stress_last) {
            if !selected(&filters, &case.name) {
                continue;
            }
            let mut sim = AnySimulation::new(case.scene).expect("valid benchmark scene");
            for _ in 0..steps {
                sim.step().expect("step");
            }
            println!(
                "digest scene={} particles={} substeps={steps} state={:016x}",
                case.name,
                sim.particle_count(),
                digest(&sim)
            );
        }
        return;
    }
    println!("MPM throughput (median of 5 rounds; particle-substeps per second, higher is better)");
    let mut base: Option<(String, f64)> = None;
    for case in cases(stress_last) {
        if !selected(&filters, &case.name) {
            continue;
        }
        let dim = case.scene.dim;
        let mut sim = AnySimulation::new(case.scene).expect("valid benchmark scene");
        sim.set_timings(true);
        let n = sim.particle_count();
        let steps = if dim == 3 { 20 } else { 40 };
        let (secs, cpu) = time(&mut sim, steps, 5);
        let rate = (n * steps) as f64 / secs;
        let cpu_rate = cpu.map(|c| (n * steps) as f64 / c);
        let bytes = sim.memory_bytes() as f64 / n as f64;
        let mut note = String::new();
        if let Some(name) = case.name.strip_suffix("_domain_x2") {
            if let Some((_, r)) = base.as_ref().filter(|(b, _)| b == name) {
                note = format!("  cost vs. small domain: {:.3}x", r / rate);
            }
        } else {
            base = Some((case.name.clone(), rate));
        }
        let on_core = cpu_rate.map_or(String::new(), |r| format!(" ({:.2} M on core)", r / 1e6));
        println!(
            "{:<32} {dim}D {n:>8} particles  {:>6.2} M particle-substeps/s{on_core}  {:>5.0} B/particle{note}",
            case.name,
            rate / 1e6,
            bytes
        );
        println!(
            "{:<32}    time per pass: {}",
            "",
            pass_shares(&sim.timings().unwrap_or_default())
        );
        let cpu_fields = cpu.zip(cpu_rate).map_or(String::new(), |(c, r)| {
            format!(" cpu_seconds={c:.4} cpu_particle_substeps_per_s={r:.0}")
        });
        println!(
            "bench scene={} dim={dim} particles={n} substeps={steps} seconds={secs:.4} particle_substeps_per_s={rate:.0}{cpu_fields}",
            case.name
        );
    }
}
