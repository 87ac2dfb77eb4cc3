//! A heap poured from a spout (`bodies[].pour`), followed over time: the volume poured
//! (Σ m / ρ) against the particles' volume Σ V_p and the heap's bulk (the volume under its
//! surface, the highest particle per cell-wide column plus half a spacing), the heap's height
//! and flanks as the CLI's summary measures them, the kinetic energy and the energy account.
//!
//! `cargo run --release --example pour_heap -- [SCENE] [SECONDS] [EVERY]` (default
//! `scenes/pour_2d.json`, 5 s, every 0.5 s). Figures in docs/method.md ("Pouring").

use mpm::measure::{Footprints, deposits};
use mpm::{D2, D3, Dim, SceneConfig, Simulation};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().map_or("scenes/pour_2d.json", String::as_str);
    let until: f64 = args.get(1).map_or(5.0, |a| a.parse().expect("SECONDS"));
    let every: f64 = args.get(2).map_or(0.5, |a| a.parse().expect("EVERY"));
    let scene = SceneConfig::load(std::path::Path::new(path)).expect("a scene");
    match scene.dim {
        2 => follow::<D2>(scene, until, every),
        _ => follow::<D3>(scene, until, every),
    }
}

fn follow<D: Dim>(scene: SceneConfig, until: f64, every: f64) {
    let b = scene
        .bodies
        .iter()
        .position(|b| b.pour.is_some())
        .expect("a poured body");
    let density = scene.bodies[b].material.density();
    let mut sim = Simulation::<D>::new(scene).expect("a valid scene");
    let h = sim.cell_size();
    println!(
        "{:>5} {:>6} {:>10} {:>10} {:>10} {:>6} {:>6} {:>7} {:>7} {:>7} {:>10} {:>9}",
        "t",
        "n",
        "poured",
        "ΣV_p",
        "bulk",
        "V/Q",
        "bulk/Q",
        "height",
        "left",
        "right",
        "kinetic",
        "account"
    );
    let mut t = 0.0;
    while t < until - 1e-9 {
        t = (t + every).min(until);
        sim.advance_until(t, |_| true).expect("a step");
        let body = &sim.bodies()[b];
        let p = sim.particles();
        let r = body.range();
        let poured: f64 = r.clone().map(|i| p.mass[i] as f64).sum::<f64>() / density;
        let volume: f64 = r.clone().map(|i| p.volume[i] as f64).sum();
        let s = body.spout().expect("a spout").spacing();
        // the volume under the surface: the top of each column (cell × cell in 3D) plus s/2
        let mut top = std::collections::HashMap::<[i64; 2], f64>::new();
        for i in r.clone() {
            let x = p.x[i];
            let key = [
                (x[0] as f64 / h).floor() as i64,
                if D::DIM == 3 {
                    (x[2] as f64 / h).floor() as i64
                } else {
                    0
                },
            ];
            let y = x[1] as f64 + 0.5 * s;
            top.entry(key).and_modify(|t| *t = t.max(y)).or_insert(y);
        }
        let bulk: f64 = top.values().sum::<f64>() * h.powi(D::DIM as i32 - 1);
        let deposit = deposits(&sim, &Footprints::default());
        let (height, flanks) = deposit
            .iter()
            .find(|d| d.body == b)
            .map_or((0.0, [None, None]), |d| (d.heap.height, d.heap.flanks));
        let angle = |k: usize| flanks[k].map_or("-".to_string(), |f| format!("{:.2}", f.angle));
        let d = sim.diagnostics();
        println!(
            "{t:>5.2} {:>6} {poured:>10.5} {volume:>10.5} {bulk:>10.5} {:>6.3} {:>6.3} {height:>7.4} {:>7} {:>7} {:>10.3e} {:>+8.4}%",
            r.len(),
            volume / poured.max(1e-300),
            bulk / poured.max(1e-300),
            angle(0),
            angle(1),
            d.kinetic,
            100.0 * d.energy_error()
        );
    }
}
