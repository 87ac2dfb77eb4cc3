//! The time step of a drop: a shipped scene at a quality level, run 3 s (sleeping on, as the
//! page), then an elastic bunny of the default size dropped on the middle of the floor (the
//! page's click), and the steps of the 1 s after it.
//!
//!   cargo run --release --example drop_step -- scenes/elastic_bunny_2d.json balanced
//!
//! prints `drop_step scene=<path> quality=<q> steps=<n> mean_dt=<s> min_dt=<s>`.
use mpm::playground::{BunnyAssets, Playground};
use std::collections::HashMap;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().expect("a scene file");
    let quality = args.get(1).map_or("balanced", String::as_str);
    let text = std::fs::read_to_string(path).expect("scene file");
    let dir = std::path::Path::new(path).parent().expect("scene's folder");
    let assets: HashMap<String, String> = mpm::playground::asset_paths(&text)
        .expect("assets")
        .into_iter()
        .map(|p| {
            let t = std::fs::read_to_string(dir.join(&p)).expect("asset");
            (p, t)
        })
        .collect();
    let mut pg = Playground::load(&text, &assets, quality).expect("scene");
    let read = |p: &str| std::fs::read_to_string(dir.join(p)).ok();
    pg.set_bunny(
        BunnyAssets::parse(read("bunny.obj").as_deref(), read("bunny2d.txt").as_deref())
            .expect("bunny"),
    );
    while pg.time() < 3.0 {
        pg.step(|| 0.0).expect("settle");
    }
    let dim = pg.dim();
    let size = pg.scene().domain.size.clone();
    let point = [
        size[0] / 2.0,
        0.0,
        size.get(2).copied().unwrap_or(0.0) / 2.0,
    ];
    let default = pg.size_range().default;
    pg.drop_at("bunny", "elastic", &point[..dim], 0.0, default)
        .expect("drop");
    let (t0, mut n, mut min_dt) = (pg.time(), 0usize, f64::INFINITY);
    while pg.time() < t0 + 1.0 {
        let r = pg.step(|| 0.0).expect("step");
        min_dt = min_dt.min(r.sim_time);
        n += 1;
    }
    println!(
        "drop_step scene={path} quality={quality} steps={n} mean_dt={:.3e} min_dt={min_dt:.3e}",
        (pg.time() - t0) / n as f64
    );
}
