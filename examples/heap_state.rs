//! The stress state of the shipped 2D column collapse near its axis (|x − 0.5| < 3 cm), band
//! by band of depth: the particles' own σ_xx, σ_yy, σ_zz against ρ g z, the out-of-plane
//! stress against the in-plane mean, and the share of the cone's strength they mobilise,
//! q / q_yield with each particle's own cone (docs/method.md, "The stress shown for sand");
//! with `history`, the same window means every 0.1 s while the column collapses.
//!
//! `nice cargo run --release --example heap_state -- [seconds] [cell size] [pic] [history]`

#[path = "../tests/support/resting.rs"]
#[allow(dead_code)]
mod resting;
use mpm::math::SymTensor;
use mpm::{D2, Material, SceneConfig, Simulation};

struct Row {
    depth: f64,
    xx: f64,
    yy: f64,
    zz: f64,
    xy: f64,
    mobilised: f64,
    plastic: f64,
}

fn rows(sim: &Simulation<D2>, h: f64, spacing: f64) -> Vec<Row> {
    let Material::DruckerPrager(m) = &sim.scene().bodies[0].material else {
        unreachable!()
    };
    let model = m.model();
    let p = sim.particles();
    let top = |x: f64| {
        p.x.iter()
            .filter(|q| (q[0] as f64 - x).abs() <= 0.25 * h)
            .map(|q| q[1] as f64)
            .fold(f64::MIN, f64::max)
    };
    (0..p.len())
        .filter(|&i| (p.x[i][0] as f64 - 0.5).abs() < 0.03)
        .map(|i| {
            let c = p.stress[i].components();
            let (xx, yy, zz, xy) = (c[0] as f64, c[1] as f64, c[2] as f64, c[3] as f64);
            let pressure = -(xx + yy + zz) / 3.0;
            let q = (3.0 * p.stress[i].j2() as f64).sqrt();
            let cone = model.pq_surface(p.plastic_strain[i] as f64);
            let x = p.x[i][0] as f64;
            Row {
                depth: top(x) + 0.5 * spacing - p.x[i][1] as f64,
                xx,
                yy,
                zz,
                xy,
                mobilised: q / (cone.slope * pressure.max(1e-9)),
                plastic: p.plastic_strain[i] as f64,
            }
        })
        .collect()
}

fn summary(rows: &[Row], rho_g: f64) -> String {
    let n = rows.len().max(1) as f64;
    let sum = |f: &dyn Fn(&Row) -> f64| rows.iter().map(f).sum::<f64>();
    let weight = sum(&|r| rho_g * r.depth);
    let (xx, yy, zz) = (sum(&|r| r.xx), sum(&|r| r.yy), sum(&|r| r.zz));
    let at_yield = rows.iter().filter(|r| r.mobilised > 0.98).count() as f64 / n;
    format!(
        "σ_yy/ρgz {:.3}  K_x {:.3}  K_z {:.3}  σ_zz/((σ_xx+σ_yy)/2) {:.3}  q/q_yield {:.3}  at yield {:4.1} %  ε_p {:.2}",
        -yy / weight,
        xx / yy,
        zz / yy,
        2.0 * zz / (xx + yy),
        sum(&|r| r.mobilised) / n,
        100.0 * at_yield,
        sum(&|r| r.plastic) / n,
    )
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize, d: f64| -> Result<f64, String> {
        args.get(i)
            .filter(|a| a.parse::<f64>().is_ok())
            .map_or(Ok(d), |a| {
                a.parse().map_err(|_| format!("argument {i}: `{a}`"))
            })
    };
    let seconds = num(0, 1.5)?;
    let h = num(1, 0.01)?;
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/column_collapse_2d.json"
    );
    let mut scene = SceneConfig::load(std::path::Path::new(path)).expect("the shipped scene");
    scene.cell_size = h;
    if args.iter().any(|a| a == "pic") {
        scene.bodies[0].apic = Some(false);
    }
    let spacing = h / scene.bodies[0].particles_per_cell as f64;
    let Material::DruckerPrager(m) = &scene.bodies[0].material else {
        unreachable!()
    };
    let (rho, phi) = (m.density, m.friction_angle);
    let m = *m;
    let rho_g = rho * 9.81;
    let mut sim = Simulation::<D2>::new(scene).map_err(|e| e.to_string())?;
    println!(
        "column collapse 2D, h = {h} m, {}; φ = {phi}°, Jaky K0 = {:.3}",
        if args.iter().any(|a| a == "pic") {
            "PIC/FLIP"
        } else {
            "APIC"
        },
        resting::jaky(phi)
    );
    if args.iter().any(|a| a == "elastic") {
        // Over each 10 ms: the particles that took no plastic step (ε_p unchanged) should
        // follow plane-strain elasticity, Δσ_zz = ν (Δσ_xx + Δσ_yy); those that flowed, with
        // ψ = 0, drive σ_zz towards the in-plane mean.
        let nu = m.poisson_ratio;
        let (mut miss, mut size, mut count) = (0.0, 0.0, 0usize);
        while sim.time() < seconds - 1e-9 {
            let before = sim.particles().clone();
            sim.advance(0.01).map_err(|e| e.to_string())?;
            let p = sim.particles();
            for i in 0..p.len() {
                if p.plastic_strain[i] != before.plastic_strain[i] {
                    continue;
                }
                let (a, b) = (before.stress[i].components(), p.stress[i].components());
                let d: Vec<f64> = (0..3).map(|k| (b[k] - a[k]) as f64).collect();
                miss += (d[2] - nu * (d[0] + d[1])).abs();
                size += d[2].abs();
                count += 1;
            }
        }
        println!(
            " elastic intervals (10 ms without a plastic step): {count}; Σ|Δσ_zz − ν(Δσ_xx + Δσ_yy)| / Σ|Δσ_zz| = {:.2e}",
            miss / size
        );
    } else if args.iter().any(|a| a == "history") {
        while sim.time() < seconds - 1e-9 {
            sim.advance(0.1).map_err(|e| e.to_string())?;
            let r: Vec<Row> = rows(&sim, h, spacing)
                .into_iter()
                .filter(|r| r.depth > 0.02)
                .collect();
            println!(" t = {:.1} s: {}", sim.time(), summary(&r, rho_g));
        }
    } else {
        sim.advance(seconds).map_err(|e| e.to_string())?;
    }
    let all = rows(&sim, h, spacing);
    let deep: Vec<&Row> = all.iter().filter(|r| r.depth > 0.02).collect();
    let deepest = deep.iter().map(|r| r.depth).fold(0.0, f64::max);
    println!(
        " at {:.2} s, deeper than 2 cm, bands 2 cm thick:",
        sim.time()
    );
    let mut from = 0.02;
    while from < deepest {
        let band: Vec<Row> = deep
            .iter()
            .filter(|r| r.depth >= from && r.depth < from + 0.02)
            .map(|r| Row { ..**r })
            .collect();
        if band.len() >= 4 {
            let tau: f64 = band.iter().map(|r| r.xy).sum::<f64>() / band.len() as f64;
            println!(
                "  {:.2}-{:.2} m (n {:3}): {}  τ_xy/ρgz {:.3}",
                from,
                from + 0.02,
                band.len(),
                summary(&band, rho_g),
                tau / (rho_g * (from + 0.01))
            );
        }
        from += 0.02;
    }
    let all_deep: Vec<Row> = deep.iter().map(|r| Row { ..**r }).collect();
    println!("  all: {}", summary(&all_deep, rho_g));
    Ok(())
}
