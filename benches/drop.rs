//! The page's drop natively: a shipped scene through the playground at a quality level, with
//! the worker's per-frame work (frames of 1/60 s, colours, the sand measures, diagnostics),
//! settled for 3 s simulated with sleeping on (the page's default), an elastic bunny of the
//! default size dropped on the middle of the floor as the page's drop figure does
//! (`www/bench/live-page.mjs --drops`), then the 4 s simulated after it timed. The steps it
//! takes are deterministic, so two trees' step counts compare exactly.
//!
//! `cargo bench --bench drop -- SCENE.json [QUALITY] [--awake]` prints
//! `native_drop scene=<path> quality=<q> sleeping=<on|off> particles=<n> asleep_before=<share>
//! steps=<k> wall=<s> rtf_drop=<simulated per wall-clock second>`.

use mpm::playground::{BunnyAssets, ColourMode, Playground};
use std::collections::HashMap;
use std::time::Instant;

/// Simulated seconds before the drop and timed after it.
const SETTLE: f64 = 3.0;
const AFTER: f64 = 4.0;

fn main() {
    let all: Vec<String> = std::env::args().skip(1).collect();
    let awake = all.iter().any(|a| a == "--awake");
    let args: Vec<&String> = all.iter().filter(|a| !a.starts_with("--")).collect();
    let path = args
        .first()
        .map_or("scenes/bunny_on_sand_ball_3d.json", |s| s.as_str());
    let quality = args.get(1).map_or("balanced", |s| s.as_str());
    let read = |p: &std::path::Path| {
        std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    };
    let text = read(std::path::Path::new(path));
    let dir = std::path::Path::new(path)
        .parent()
        .unwrap_or(std::path::Path::new("."));
    let assets: HashMap<String, String> = mpm::playground::asset_paths(&text)
        .unwrap_or_else(|e| panic!("{path}: {e}"))
        .into_iter()
        .map(|f| {
            let body = read(&dir.join(&f));
            (f, body)
        })
        .collect();
    let mut pg = Playground::load(&text, &assets, quality).unwrap_or_else(|e| panic!("{e}"));
    // The page's bunny (the scenes' own mesh and outline).
    let obj = read(std::path::Path::new("scenes/bunny.obj"));
    let outline = read(std::path::Path::new("scenes/bunny2d.txt"));
    pg.set_bunny(BunnyAssets::parse(Some(&obj), Some(&outline)).expect("the shipped bunny"));
    pg.set_sleeping(!awake);
    let t0 = Instant::now();
    // One frame of the worker: step 1/60 s, then what it sends the page.
    let frame = |pg: &mut Playground| {
        pg.frame(1.0 / 60.0, 1e9, || t0.elapsed().as_secs_f64() * 1e3)
            .expect("step");
        pg.update_colours(ColourMode::Body);
        std::hint::black_box(pg.measures());
        std::hint::black_box(pg.diagnostics());
    };
    while pg.time() < SETTLE {
        frame(&mut pg);
    }
    let asleep = pg.asleep() as f64 / pg.particle_count().max(1) as f64;
    let size = pg.size_range().default;
    let w = pg.scene().domain.size.clone();
    let point: Vec<f64> = if pg.dim() == 3 {
        vec![w[0] / 2.0, 0.0, w[2] / 2.0]
    } else {
        vec![w[0] / 2.0, 0.0]
    };
    pg.drop_at("bunny", "elastic", &point, 0.0, size)
        .expect("the drop");
    let (s0, n0, w0) = (pg.time(), pg.diagnostics().step, Instant::now());
    while pg.time() < s0 + AFTER {
        frame(&mut pg);
    }
    let wall = w0.elapsed().as_secs_f64();
    println!(
        "native_drop scene={path} quality={quality} sleeping={} particles={} asleep_before={asleep:.3} steps={} wall={wall:.3} rtf_drop={:.3}",
        if awake { "off" } else { "on" },
        pg.particle_count(),
        pg.diagnostics().step - n0,
        (pg.time() - s0) / wall
    );
}
