//! The poured heap's flank against φ: a pour scene sampled at a page quality level, its sand
//! (Drucker–Prager, or Mohr–Coulomb with the same fields) at a friction angle, poured and run
//! until it rests, then its flanks (the 20–80 % least-squares slope, each side; in 3D of the
//! radial profile) beside the reference angle.
//!
//! `cargo run --release --example repose -- SCENE QUALITY MODEL PHI [PHI..]` prints one line
//! per angle: `repose scene=.. quality=.. model=.. phi=.. reference=.. left=.. right=.. height=..
//! particles=.. steps=.. wall=..`.
use mpm::playground::Playground;
use std::collections::HashMap;
use std::time::Instant;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (path, quality, model) = (&a[0], &a[1], &a[2]);
    let mut text = std::fs::read_to_string(path).expect("scene");
    if model == "mohr_coulomb" {
        text = text.replace("drucker_prager", "mohr_coulomb");
    }
    for phi in &a[3..] {
        let phi: f64 = phi.parse().expect("PHI");
        let mut pg = Playground::load(&text, &HashMap::new(), quality).expect("a scene");
        pg.set_parameter(&format!("{model}.friction_angle"), phi)
            .expect("φ");
        pg.set_sleeping(std::env::var("MPM_AWAKE").is_err());
        let t0 = Instant::now();
        // until the spout has stopped and the heap rests (or 10 s)
        let mut calm = 0.0;
        while pg.time() < 10.0 {
            pg.frame(0.05, 1e9, || 0.0).expect("a step");
            let still = pg.diagnostics().max_speed < 0.01;
            calm = if still && !pg.simulation().pouring() {
                calm + 0.05
            } else {
                0.0
            };
            if calm >= 0.3 {
                break;
            }
        }
        let wall = t0.elapsed().as_secs_f64();
        let d = pg.measures();
        let dep = d
            .iter()
            .find(|d| d.name == "sand")
            .or(d.first())
            .expect("a deposit");
        let f = |k: usize| dep.heap.flanks[k].as_ref().map_or(f64::NAN, |f| f.angle);
        let reference = dep.repose_angle;
        println!(
            "repose scene={path} quality={quality} model={model} phi={phi} reference={reference:.1} left={:.1} right={:.1} height={:.3} particles={} steps={} t={:.2} wall={wall:.1}",
            f(0),
            f(1),
            dep.heap.height,
            pg.particle_count(),
            pg.diagnostics().step,
            pg.time()
        );
    }
}
