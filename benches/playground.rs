//! Native time per step of a scene driven through the playground (the same code path the
//! browser takes), for the wasm-versus-native comparison of `cargo xtask bench-web`.
//!
//! `cargo bench --bench playground -- SCENE.json [STEPS]` prints
//! `native scene=<path> particles=<n> steps=<k> median_ms_per_step=<x> mean_ms_per_step=<y>`.

use mpm::playground::Playground;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let path = args
        .first()
        .map(String::as_str)
        .unwrap_or("www/test-scenes/bench_3d.json");
    let steps: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(200);
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    // Meshes and outlines the scene names, read from its folder (as the page fetches them).
    let dir = std::path::Path::new(path)
        .parent()
        .unwrap_or(std::path::Path::new("."));
    let assets: std::collections::HashMap<String, String> = mpm::playground::asset_paths(&text)
        .unwrap_or_else(|e| panic!("{path}: {e}"))
        .into_iter()
        .map(|f| {
            let body = std::fs::read_to_string(dir.join(&f)).unwrap_or_else(|e| panic!("{f}: {e}"));
            (f, body)
        })
        .collect();
    let mut pg =
        Playground::from_json_with_assets(&text, &assets).unwrap_or_else(|e| panic!("{path}: {e}"));
    // Warm up (caches, grid allocation) as long as the wasm benchmark does, then time each step.
    let warm = Instant::now();
    let mut i = 0;
    while i < 30 || warm.elapsed().as_secs_f64() < 3.0 {
        pg.step(|| 0.0).expect("step");
        i += 1;
    }
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t = Instant::now();
        pg.step(|| 0.0).expect("step");
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mean = times.iter().sum::<f64>() / steps as f64;
    times.sort_by(f64::total_cmp);
    println!(
        "native scene={path} particles={} steps={steps} median_ms_per_step={:.4} mean_ms_per_step={mean:.4}",
        pg.particle_count(),
        times[steps / 2]
    );
}
