//! The ringing of a sand layer released stress-free between walls (docs/method.md, "The
//! stress shown for sand"): the shipped column's sand as a layer 0.12 m deep, its load ratio
//! Σ V σ_yy / (−g Σ m y) (1 at rest: the floor's reaction acts at y = 0) sampled every
//! millisecond, and its least and greatest value in each window of `window` seconds, with the
//! energy the plastic returns, the walls and the transfers removed in that window.
//!
//! `nice cargo run --release --example resting_ring -- [2|3] [cell size] [seconds] [window] [width] [pic]`
//!
//! 2D takes the shipped column's box, 1 m wide; 3D a box `width` square in plan (0.2 m unless
//! given).

use mpm::math::SymTensor;
use mpm::{D2, D3, Dim, SceneConfig, Shape, Simulation};

fn scene(dim: usize, h: f64, pic: bool, width: f64) -> SceneConfig {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/column_collapse_2d.json"
    );
    let path3 = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/column_collapse_3d.json"
    );
    let file = if dim == 2 { path } else { path3 };
    let mut scene = SceneConfig::load(std::path::Path::new(file)).expect("the shipped scene");
    scene.cell_size = h;
    let body = &mut scene.bodies[0];
    if pic {
        body.apic = Some(false);
    }
    body.shape = if dim == 2 {
        Shape::cuboid(&[0.0, 0.0], &[1.0, 0.12])
    } else {
        scene.domain.size = vec![width, 0.4, width];
        Shape::cuboid(&[0.0, 0.0, 0.0], &[width, 0.12, width])
    };
    scene
}

fn ring<D: Dim>(scene: SceneConfig, seconds: f64, window: f64) -> Result<(), String> {
    let g = 9.81;
    let mut sim = Simulation::<D>::new(scene).map_err(|e| e.to_string())?;
    println!(
        "{} particles, dt {:.2e} s",
        sim.particles().len(),
        sim.stable_dt()
    );
    let mut t0 = 0.0;
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    let mut last = (0.0, 0.0);
    let mut crossings = Vec::new();
    // the dissipated energies at the window's start: plastic, walls, transfers
    let booked = |sim: &Simulation<D>| {
        let d = sim.diagnostics();
        [
            d.dissipated_plastic,
            d.dissipated_boundary,
            d.dissipated_numerical,
        ]
    };
    let mut at_start = booked(&sim);
    while sim.time() < seconds {
        sim.advance(0.001).map_err(|e| e.to_string())?;
        let p = sim.particles();
        let n = p.len();
        let carried: f64 = (0..n)
            .map(|i| p.volume[i] as f64 * p.stress[i].components()[1] as f64)
            .sum();
        let weight: f64 = -g
            * (0..n)
                .map(|i| p.mass[i] as f64 * p.x[i][1] as f64)
                .sum::<f64>();
        let r = carried / weight;
        // upward crossings of 1, for the period
        if last.1 < 1.0 && r >= 1.0 {
            crossings.push(sim.time());
        }
        last = (sim.time(), r);
        lo = lo.min(r);
        hi = hi.max(r);
        if sim.time() >= t0 + window - 1e-9 {
            let recent: Vec<f64> = crossings.iter().copied().filter(|&t| t > t0).collect();
            let period = if recent.len() > 1 {
                (recent[recent.len() - 1] - recent[0]) / (recent.len() - 1) as f64
            } else {
                f64::NAN
            };
            let now = booked(&sim);
            println!(
                "  {:.2}-{:.2} s: load ratio {lo:.3} … {hi:.3} (half-swing {:.3}), period {:.1} ms; dissipated: plastic {:.2e}, walls {:.2e}, transfers {:.2e} J{}",
                t0,
                sim.time(),
                0.5 * (hi - lo),
                1e3 * period,
                now[0] - at_start[0],
                now[1] - at_start[1],
                now[2] - at_start[2],
                if D::DIM == 2 { "/m" } else { "" }
            );
            at_start = now;
            t0 = sim.time();
            lo = f64::MAX;
            hi = f64::MIN;
        }
    }
    Ok(())
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize, d: f64| -> Result<f64, String> {
        args.get(i).map_or(Ok(d), |a| {
            a.parse().map_err(|_| format!("argument {i}: `{a}`"))
        })
    };
    let dim = num(0, 2.0)? as usize;
    let h = num(1, 0.01)?;
    let seconds = num(2, 3.0)?;
    let window = num(3, 0.25)?;
    let width = num(4, 0.2)?;
    let pic = args.iter().any(|a| a == "pic");
    println!(
        "layer 0.12 m, {dim}D, h = {h} m, {}",
        if pic { "PIC/FLIP" } else { "APIC (default)" }
    );
    let scene = scene(dim, h, pic, width);
    match dim {
        2 => ring::<D2>(scene, seconds, window),
        3 => ring::<D3>(scene, seconds, window),
        _ => Err(format!("dimension: {dim}, 2 or 3")),
    }
}
