//! A 0.25 m Drucker–Prager sand box dropped in the empty 2D or 3D sandbox (the page's Drop
//! tool: released a gap of 5 % of the box's height above the floor), at the sandbox's cells
//! or at cells `CELL` (m), run 3 s with sleeping on (as the page), then its flanks (the
//! 20–80 % least-squares slope, each side; in 3D of the radial profile).
//!
//! `cargo run --release --example sandbox_drop -- DIM CELL|page PHI [PHI..]` (at the page's
//! default level, or `QUALITY=balanced|fine`) prints one line per angle: `sandbox_drop dim=..
//! cell=.. ppc=.. phi=.. left=.. right=.. particles=.. wall=..`.
use mpm::playground::{Playground, Quality};
use std::time::Instant;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let dim: usize = a[0].parse().expect("DIM");
    for phi in &a[2..] {
        let phi: f64 = phi.parse().expect("PHI");
        let mut scene = Playground::sandbox_scene(dim);
        if a[1] != "page" {
            scene.cell_size = a[1].parse().expect("CELL");
        }
        let level = std::env::var("QUALITY");
        let q = Quality::find(level.as_deref().unwrap_or(mpm::playground::DEFAULT_QUALITY))
            .expect("QUALITY: live, balanced or fine");
        let mut pg = Playground::with_quality(scene, q).expect("the sandbox");
        pg.set_parameter("drucker_prager.friction_angle", phi)
            .expect("φ");
        let point = [1.0, 0.0, 0.5];
        let b = pg
            .drop_at("box", "drucker_prager", &point[..dim], 0.0, 0.25)
            .expect("a drop");
        let t0 = Instant::now();
        while pg.time() < 3.0 {
            pg.frame(0.05, 1e9, || 0.0).expect("a step");
        }
        let d = pg.measures();
        let f = |k: usize| d[0].heap.flanks[k].as_ref().map_or(f64::NAN, |f| f.angle);
        println!(
            "sandbox_drop dim={dim} cell={} ppc={} phi={phi} left={:.1} right={:.1} particles={} wall={:.1}",
            pg.scene().cell_size,
            pg.scene().bodies[b].particles_per_cell,
            f(0),
            f(1),
            pg.particle_count(),
            t0.elapsed().as_secs_f64()
        );
    }
}
