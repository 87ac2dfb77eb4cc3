//! The low plane column (a = 0.5, H0 = 0.1 m, floor μ = 0.6) and Bui et al. (2008)'s set-up
//! with the default sand: run-out (farthest particle and deposit edge), flanks against φ_ps,
//! the toe beyond the flanks' foot, the top plateau and the time to rest, at each cell size
//! and friction angle asked for. See docs/validation.md, "Drucker–Prager: a low column on a
//! rough floor".
//!
//! `nice cargo run --release --example low_column -- 0.01,0.005 20,30,40` (cell sizes in m,
//! friction angles in degrees, or `bui` for Bui et al.'s set-up, `a2` for the plane a = 2
//! collapse, `slope` for a φ = 32° slope steepened to 40°; a third argument names a variant of
//! the numerics, e.g. `floor<μ>` for another floor friction)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::KernelKind;
use validation::*;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let list = |i: usize, default: &str| arg_list(&args, i, default);
    let hs = cell_sizes(&list(0, "0.01"))?;
    let cases = list(1, "30");
    let variant = args.get(2).cloned().unwrap_or_default();
    // `floor<μ>`: the default numerics on a floor of friction μ instead of the rough floor's
    let floor: Option<f64> = match variant.strip_prefix("floor") {
        Some(m) => Some(
            m.parse()
                .ok()
                .filter(|m: &f64| (0.0..=2.0).contains(m))
                .ok_or(format!("variant `{variant}`: floor<μ in [0, 2]>"))?,
        ),
        None => None,
    };
    for &h in &hs {
        for case in &cases {
            let n = Numerics::new(h, KernelKind::Gimp);
            let n = match variant.as_str() {
                _ if floor.is_some() => n,
                "" => n,
                "cfl0.1" => n.cfl(0.1),
                "alpha0" => n.flip(0.0),
                "alpha1" => n.flip(1.0),
                "pic" => n.pic(),
                "cell-average" => n.cell_average(),
                "plane-strain" => n.plane_strain(),
                "steady-flow" => n.steady_flow(),
                "ppc3" => n.ppc(3),
                v if v.starts_with("mu_i") => n.mu_i(
                    v[4..]
                        .parse()
                        .map_err(|_| format!("variant `{v}`: mu_i<d in m>"))?,
                ),
                "bspline" => Numerics {
                    kernel: KernelKind::QuadraticBspline,
                    ..n
                },
                v => return Err(format!("variant `{v}` unknown")),
            };
            // two cases not used to choose a variant: the plane a = 2 collapse and a slope of
            // φ = 32° steepened to 40° (it fails and comes to rest)
            if case == "a2" {
                let c = column_collapse("column_collapse_a2_2d.json", &n, 4.0);
                println!(
                    "h={h} a2 {variant}: run-out one grain {:.3} ({:+.1} % of Lube's {:.3}), farthest {:.3}, flank {:.1}°, H∞/H0 {:.3} ({:+.1} %), rest {:.2} s {:?}",
                    c.runout_thin,
                    100.0 * (c.runout_thin / lube_runout(2.0) - 1.0),
                    lube_runout(2.0),
                    c.runout,
                    c.flank,
                    c.height,
                    100.0 * (c.height / lube_height(2.0) - 1.0),
                    c.settled_at,
                    c.failure
                );
                continue;
            }
            if case == "slope" {
                let r = heap_slope(32.0, 40.0, 3.5e5, &n, 2.0);
                println!(
                    "h={h} slope φ=32 θ=40 {variant}: failed at {:?} s, rests at {:.1}° (φ_ps {:.1}°, {:+.1}°), final speed {:.1e} m/s",
                    r.failed_at,
                    r.angle,
                    r.plane_strain_angle,
                    r.angle - r.plane_strain_angle,
                    r.final_speed
                );
                continue;
            }
            let r = if case == "bui" {
                plane_deposit(bui_scene(&n), true, 4.0)
            } else {
                let phi = case_friction_angle(case)?;
                let mut scene = low_column_scene(phi, &n);
                if let Some(mu) = floor {
                    scene.boundary.friction = mu;
                }
                plane_deposit(scene, false, 4.0)
            };
            let d = &r.deposit;
            println!(
                "h={h} {case} {variant}: run-out one grain {:.3}, farthest {:.3} (edge {:.3}) flank {:.1}° ({}) vs φ_ps {:.1}° ({:+.1}) foot {:+.3} toe {:.3} L0 ({:.1} rows) plateau {:.2} L0 H∞ {:.3} rest {:.2} s {} steps {:.0} s {:?}",
                d.runout_thin,
                d.runout,
                d.runout_edge,
                d.flank(),
                d.flanks
                    .iter()
                    .map(|f| format!("{f:.1}"))
                    .collect::<Vec<_>>()
                    .join("/"),
                r.plane_strain_angle,
                d.flank() - r.plane_strain_angle,
                d.foot,
                d.toe,
                d.toe_rows,
                d.plateau,
                d.height,
                r.settled_at,
                r.cost.steps,
                r.cost.wall_seconds,
                r.failure
            );
        }
    }
    Ok(())
}
