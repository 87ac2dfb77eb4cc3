//! The heaps of the friction-angle lesson (`lessons/friction_angle.json`) as the page shows
//! them: the lesson's scene sampled at each quality level (the page opens at the default,
//! `live`), run for the lesson's duration in frames of 1/60 s, then measured with the page's
//! own readout (`Playground::measures`, the core's flank fit): each heap's flanks, their mean
//! against φ and the cone's plane-strain angle φ_ps, the run-out, and the fastest particle
//! (is it at rest?). Then on to three times the duration, to see whether the heaps still move.
//!
//! `cargo run --release --example lesson_heaps` (or name the levels: `-- live fine`)

use mpm::lesson::Lesson;
use mpm::playground::{DEFAULT_QUALITY, Playground, Quality};
use std::path::Path;

fn main() -> Result<(), String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons/friction_angle.json");
    let (lesson, scene) = Lesson::load(&path).map_err(|e| e.to_string())?;
    let mut levels: Vec<String> = std::env::args().skip(1).collect();
    if levels.is_empty() {
        levels = vec![DEFAULT_QUALITY.to_string(), "fine".to_string()];
    }
    for level in &levels {
        let q = Quality::find(level).map_err(|e| e.to_string())?;
        let mut pg = Playground::with_quality(scene.clone(), q).map_err(|e| e.to_string())?;
        let r = pg.quality().clone();
        println!(
            "{level}: h = {} m, {} particles per cell, {} particles",
            r.cell_size,
            r.particles_per_cell,
            pg.particle_count()
        );
        pg.measures(); // the footprints, as the page records them on the first frame
        let mut t = 0.0;
        for end in [lesson.duration, 3.0 * lesson.duration] {
            while t < end - 1e-9 {
                let f = pg
                    .frame((1.0 / 60.0f64).min(end - t), 1e12, || 0.0)
                    .map_err(|e| e.to_string())?;
                t += f.sim_time;
            }
            let speed = pg.diagnostics().max_speed;
            for d in pg.measures() {
                let f: Vec<f64> = d.heap.flanks.iter().flatten().map(|f| f.angle).collect();
                let mean = f.iter().sum::<f64>() / f.len().max(1) as f64;
                println!(
                    "  t = {t:.2} s, {}: flanks {:?} (mean {mean:.1}°), φ = {}°, φ_ps = {:.1}°, run-out {:.3} m; fastest particle {speed:.3} m/s",
                    d.name,
                    f.iter().map(|a| format!("{a:.1}")).collect::<Vec<_>>(),
                    d.friction_angle,
                    d.repose_angle,
                    d.runout
                        .as_ref()
                        .map_or(f64::NAN, |r| r.runout[0].max(r.runout[1])),
                );
            }
        }
    }
    Ok(())
}
