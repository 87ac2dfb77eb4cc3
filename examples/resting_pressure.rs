//! The resting pressure field of sand (docs/method.md, "The stress shown for sand"): the
//! shipped 2D column collapse after 1.5 s (particles within 3 cm of its axis) and a layer
//! 0.12 m deep across the same box, band by band of depth against ρ g z (1 + 2K0)/3.
//!
//! `nice cargo run --release --example resting_pressure -- [seconds] [cell_average] [pic] [heap|layer] [geostatic]`
//! (`heap` or `layer` runs that case alone; `pic` transfers with the paper's PIC/FLIP blend
//! instead of APIC; `geostatic` releases the layer with the stress of an elastic layer at
//! rest, σ_yy = −ρ g z and σ_xx = σ_zz = ν/(1 − ν) σ_yy, instead of stress-free)

#[path = "../tests/support/resting.rs"]
mod resting;
use mpm::material::VolumetricRate;
use mpm::math::SymTensor;
use mpm::{D2, Material, SceneConfig, Shape, Simulation};
use resting::*;

fn scene(layer: bool, cell_average: bool, pic: bool) -> SceneConfig {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/column_collapse_2d.json"
    );
    let mut scene = SceneConfig::load(std::path::Path::new(path)).expect("the shipped scene");
    let body = &mut scene.bodies[0];
    if pic {
        body.apic = Some(false);
    }
    if layer {
        body.shape = Shape::cuboid(&[0.0, 0.0], &[1.0, 0.12]);
    }
    if cell_average && let Material::DruckerPrager(m) = &mut body.material {
        m.volumetric_rate = VolumetricRate::CellAverage;
    }
    scene
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seconds: f64 = args.first().map_or(Ok(1.5), |a| {
        a.parse().map_err(|_| format!("seconds: `{a}`"))
    })?;
    let cell_average = args.iter().any(|a| a == "cell_average");
    let cases: Vec<bool> = [false, true]
        .into_iter()
        .filter(|&layer| {
            !args
                .iter()
                .any(|a| a == if layer { "heap" } else { "layer" })
        })
        .collect();
    for layer in cases {
        let scene = scene(layer, cell_average, args.iter().any(|a| a == "pic"));
        let h = scene.cell_size;
        let (rho, phi) = match &scene.bodies[0].material {
            Material::DruckerPrager(m) => (m.density, m.friction_angle),
            _ => unreachable!(),
        };
        let spacing = h / scene.bodies[0].particles_per_cell as f64;
        let g = 9.81;
        let nu = match &scene.bodies[0].material {
            Material::DruckerPrager(m) => m.poisson_ratio,
            _ => unreachable!(),
        };
        let mut sim = Simulation::<D2>::new(scene).map_err(|e| e.to_string())?;
        if layer && args.iter().any(|a| a == "geostatic") {
            // released at rest: the elastic layer's own K = ν/(1 − ν)
            geostatic(&mut sim, 0.12, rho, 9.81, nu / (1.0 - nu));
        }
        sim.advance(seconds).map_err(|e| e.to_string())?;
        let p = sim.particles().clone();
        let xy: Vec<(f64, f64)> = p.x.iter().map(|x| (x[0] as f64, x[1] as f64)).collect();
        let window = if layer { (0.1, 0.9) } else { (0.47, 0.53) };
        let k0 = jaky(phi);
        println!(
            "{} after {seconds} s ({}; K0 = 1 - sin {phi}° = {k0:.3}), max speed {:.2e} m/s",
            if layer {
                "layer 0.12 m, x in [0.1, 0.9]"
            } else {
                "collapsed column, |x - 0.5| < 3 cm"
            },
            if cell_average {
                "cell-averaged volumetric rate"
            } else {
                "particle volumetric rate"
            },
            p.v.iter().map(|v| v.length() as f64).fold(0.0, f64::max)
        );
        let pressures: Vec<f64> = (0..p.len()).map(|i| p.pressure(i) as f64).collect();
        let bands =
            |field: &[f64]| pressure_bands(&xy, field, window, h, spacing, 2.0 * h, rho, g, k0);
        println!(" particle pressure:\n{}", bands(&pressures));
        let shown = mpm::recovery::shown_stress(&sim);
        let recovered: Vec<f64> = shown.iter().map(|s| -s.trace() as f64 / 3.0).collect();
        println!(" recovered pressure:\n{}", bands(&recovered));
        // σ_yy against ρ g z, and the horizontal and out-of-plane ratios K = σ_xx/σ_yy, σ_zz/σ_yy
        let deep = |i: usize| {
            let (x, _) = xy[i];
            x >= window.0 && x <= window.1
        };
        let sum = |c: usize| -> f64 {
            (0..p.len())
                .filter(|&i| deep(i))
                .map(|i| shown[i].components()[c] as f64)
                .sum()
        };
        let (sxx, syy, szz) = (sum(0), sum(1), sum(2));
        println!(
            " window means: K_x = {:.3}, K_z = {:.3}",
            sxx / syy,
            szz / syy
        );
        let vertical: Vec<f64> = shown.iter().map(|s| -s.components()[1] as f64).collect();
        let v = pressure_bands(&xy, &vertical, window, h, spacing, 2.0 * h, rho, g, 1.0);
        println!(
            " recovered -σ_yy against ρ g z: worst band mean {:.3}, bands {:?}",
            v.worst_mean,
            v.bands
                .iter()
                .map(|b| (b.mean * 1000.0).round() / 1000.0)
                .collect::<Vec<_>>()
        );
        // what the recovery costs beside a step (wall time, 20 of each)
        let clock = std::time::Instant::now();
        for _ in 0..20 {
            std::hint::black_box(mpm::recovery::shown_stress(&sim));
        }
        let recovery = clock.elapsed().as_secs_f64() / 20.0;
        let clock = std::time::Instant::now();
        for _ in 0..20 {
            sim.step().map_err(|e| e.to_string())?;
        }
        let step = clock.elapsed().as_secs_f64() / 20.0;
        println!(
            " cost: recovery {:.2} ms, step {:.2} ms ({} particles)",
            1e3 * recovery,
            1e3 * step,
            p.len()
        );
        // the whole body's Σ V σ_yy against −g Σ m y, equal at rest (the floor's reaction acts
        // at y = 0), and the band means, every 4 ms over 40 ms
        for k in 0..=10 {
            if k > 0 {
                sim.advance(0.004).map_err(|e| e.to_string())?;
            }
            let p = sim.particles();
            let n = p.len();
            let virial = (0..n)
                .map(|i| p.volume[i] as f64 * p.stress[i].components()[1] as f64)
                .sum::<f64>()
                / (-g
                    * (0..n)
                        .map(|i| p.mass[i] as f64 * p.x[i][1] as f64)
                        .sum::<f64>());
            let xy: Vec<(f64, f64)> = p.x.iter().map(|x| (x[0] as f64, x[1] as f64)).collect();
            let shown = mpm::recovery::shown_stress(&sim);
            let field = |f: &dyn Fn(&[mpm::Real]) -> f64, k0: f64| {
                let v: Vec<f64> = shown.iter().map(|s| f(s.components())).collect();
                pressure_bands(&xy, &v, window, h, spacing, 2.0 * h, rho, g, k0)
            };
            let v = field(&|c| -c[1] as f64, 1.0);
            let m = field(&|c| -(c[0] + c[1] + c[2]) as f64 / 3.0, k0);
            println!(
                "  t = {:.3} s: Σ V σ_yy / (−g Σ m y) = {virial:.3}; σ_yy/ρgz worst band {:.3}; p/p0 worst band {:.3}, within {:.1} %",
                sim.time(),
                v.worst_mean,
                m.worst_mean,
                100.0 * m.within
            );
        }
    }
    Ok(())
}
