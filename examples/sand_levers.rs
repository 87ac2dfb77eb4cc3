//! The default start–stop sand's slopes, heaps (walls lifted at 0.05 m/s) and plane collapses
//! at one cell size under levers that are not defaults: the quadratic B-spline kernel beside
//! GIMP (`sand_levers h`), GIMP with μ(I) friction of grain diameter d (`sand_levers h all d`,
//! d in m), GIMP at the CFL numbers 0.4, 0.2 and 0.1 (`sand_levers h all cfl`, or `cfl-flip1`
//! with α = 1), or GIMP with the cell-averaged volumetric rate (`sand_levers h all
//! cell-average`). `slopes`, `heaps` or `collapse` in place of `all` runs one family. See
//! docs/validation.md, "The sand model behind the figures".
//!
//! `taskset -c 0 cargo run --release --example sand_levers -- 0.01` (about 4 minutes; 0.005:
//! about 10)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::KernelKind;
use validation::*;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let h: f64 = match args.first() {
        None => 0.01,
        Some(a) => a
            .parse()
            .ok()
            .filter(|h| (0.001..=0.05).contains(h))
            .ok_or(format!("h: `{a}` is not a cell size in [0.001, 0.05] m"))?,
    };
    let which = args.get(1).cloned().unwrap_or("all".into());
    if !["all", "slopes", "heaps", "collapse"].contains(&which.as_str()) {
        return Err(format!(
            "family: `{which}` is not all, slopes, heaps or collapse"
        ));
    }
    let variant = args.get(2).cloned().unwrap_or("kernels".into());
    let runs: Vec<(String, Numerics)> = match variant.as_str() {
        "kernels" => [KernelKind::Gimp, KernelKind::QuadraticBspline]
            .into_iter()
            .map(|k| (kernel_name(k).to_string(), Numerics::new(h, k).start_stop()))
            .collect(),
        "cell-average" => vec![(
            "gimp cell-average".to_string(),
            Numerics::new(h, KernelKind::Gimp)
                .start_stop()
                .cell_average(),
        )],
        "cfl" | "cfl-flip1" => [0.4, 0.2, 0.1]
            .into_iter()
            .map(|c| {
                let n = Numerics::new(h, KernelKind::Gimp).start_stop().cfl(c);
                if variant == "cfl" {
                    (format!("gimp cfl={c}"), n)
                } else {
                    (format!("gimp α=1 cfl={c}"), n.flip(1.0))
                }
            })
            .collect(),
        d => {
            let d: f64 = d
                .parse()
                .ok()
                .filter(|d| (1e-5..=0.01).contains(d))
                .ok_or(format!(
                    "d: `{d}` is not `kernels`, `cfl`, `cfl-flip1`, `cell-average` or a grain diameter in [1e-5, 0.01] m"
                ))?;
            vec![(
                format!("gimp mu_i d={d}"),
                Numerics::new(h, KernelKind::Gimp).start_stop().mu_i(d),
            )]
        }
    };
    for (k, n) in runs {
        if which == "all" || which == "slopes" {
            for (phi, th) in [
                (20.0, 30.0),
                (32.0, 40.0),
                (45.0, 50.0),
                (32.0, 25.0),
                (45.0, 35.0),
            ] {
                let r = heap_slope(phi, th, 3.5e5, &n, 2.0);
                println!(
                    "{k} h={h} slope φ={phi} θ={th}: failed {:?} → {:.1}° ({:+.1}) creep {:.2} mm peak {:.3}",
                    r.failed_at,
                    r.angle,
                    r.angle - r.plane_strain_angle,
                    r.creep * 1e3,
                    r.peak_speed
                );
            }
        }
        if which == "all" || which == "heaps" {
            for phi in [20.0, 32.0, 45.0] {
                let p = repose_pile(&n, repose_duration(LIFT_SPEED), Some(phi), LIFT_SPEED);
                println!(
                    "{k} h={h} heap φ={phi}: {:.1}° ({:+.1})",
                    p.angle,
                    p.angle - p.plane_strain_angle
                );
            }
        }
        if which == "all" || which == "collapse" {
            for (file, a) in PLANE_COLLAPSES {
                let c = column_collapse(file, &n, 4.0);
                println!(
                    "{k} h={h} collapse a={a}: farthest {:+.1} % edge {:+.1} % H {:+.1} % ({:?})",
                    (c.runout / lube_runout(a) - 1.0) * 100.0,
                    (c.runout_edge / lube_runout(a) - 1.0) * 100.0,
                    (c.height / lube_height(a) - 1.0) * 100.0,
                    c.failure
                );
            }
        }
    }
    Ok(())
}
