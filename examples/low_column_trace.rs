//! The low column of `low_column` followed particle by particle: which particles end in the
//! flank (the surface between 20 % and 80 % of the deposit's height) and in the toe (beyond
//! the flank's foot), and what they did on the way: speed, whether they stopped and started
//! again, their stress against their cone (√J2 / (3 α(ε_p) p), 1 on the cone), how many sat
//! at the apex (zero stress), their plastic strain, and the flow's volumetric against its
//! shear rate (from APIC's affine velocity). See docs/validation.md, "Drucker–Prager: a low
//! column on a rough floor".
//!
//! `nice cargo run --release --example low_column_trace -- 30 0.005 [variant]` (φ in degrees,
//! h in m; variant: `cfl0.1`, `alpha0`, `alpha1`, `pic`, `cell-average`, `plane-strain`)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::material::drucker_prager::flowing_alpha;
use mpm::math::SymTensor;
use mpm::{KernelKind, Material, Simulation};
use validation::*;

struct Sample {
    t: f64,
    speed: Vec<f32>,
    apex: Vec<bool>,
    ratio: Vec<f32>,
    vol_shear: Vec<f32>,
    ep: Vec<f32>,
    /// Stress resolved on a plane at the slope `SLOPE_DEG` (down to the right): shear τ_tn
    /// and compressive normal −σ_nn (Pa), and the stretching D_tt over the shear |D_tn|.
    tau: Vec<f32>,
    sigma_n: Vec<f32>,
    stretch: Vec<f32>,
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let phi: f64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(30.0);
    let h: f64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(0.005);
    let variant = args.get(2).cloned().unwrap_or_default();
    // the plane the stress is resolved on: the flank's slope (default φ_ps)
    let slope_deg: f64 = args
        .get(3)
        .and_then(|a| a.parse().ok())
        .unwrap_or(plane_strain_angle(phi));
    let mut n = Numerics::new(h, KernelKind::Gimp);
    n = match variant.as_str() {
        "" => n,
        "cfl0.1" => n.cfl(0.1),
        "alpha0" => n.flip(0.0),
        "alpha1" => n.flip(1.0),
        "pic" => n.pic(),
        "cell-average" => n.cell_average(),
        "plane-strain" => n.plane_strain(),
        v => return Err(format!("variant `{v}` unknown")),
    };
    let scene = low_column_scene(phi, &n);
    let Material::DruckerPrager(m) = scene.bodies[0].material else {
        unreachable!()
    };
    let alpha_s = m.model().alpha_phi as f64;
    let alpha_f = match m.friction_match {
        mpm::material::FrictionMatch::StartStop => flowing_alpha(alpha_s),
        _ => alpha_s,
    };
    let widens = m.friction_match == mpm::material::FrictionMatch::StartStop;
    let alpha = |ep: f64| {
        if widens {
            alpha_s + ep.min(1.0) * (alpha_f - alpha_s)
        } else {
            alpha_s
        }
    };
    let s = spacing(&scene);
    let mut sim = Simulation::<mpm::D2>::new(scene).map_err(|e| e.to_string())?;
    let (xc, l0) = column_extent(&sim, s);
    let h0 = 0.1;
    let count = sim.particles().len();
    let mut samples: Vec<Sample> = Vec::new();
    let rest = 1e-3 * (9.81f64 * h0).sqrt();
    loop {
        sim.advance(0.01).map_err(|e| e.to_string())?;
        let p = sim.particles();
        let mut smp = Sample {
            t: sim.time(),
            speed: vec![0.0; count],
            apex: vec![false; count],
            ratio: vec![0.0; count],
            vol_shear: vec![0.0; count],
            ep: vec![0.0; count],
            tau: vec![0.0; count],
            sigma_n: vec![0.0; count],
            stretch: vec![0.0; count],
        };
        let th = slope_deg.to_radians();
        let (tx, ty, nx, ny) = (th.cos(), -th.sin(), th.sin(), th.cos());
        for i in 0..p.len() {
            let id = p.id[i] as usize;
            let st = p.stress[i];
            let pr = -st.trace() as f64 / 3.0;
            let ep = p.plastic_strain[i] as f64;
            smp.speed[id] = p.v[i].length();
            smp.apex[id] = st.trace() > -1e-3;
            smp.ratio[id] = if pr > 1e-3 {
                (st.j2().sqrt() as f64 / (3.0 * alpha(ep) * pr)) as f32
            } else {
                0.0
            };
            let c = p.affine[i];
            let (dxx, dyy, dxy) = (
                c.col(0).x as f64,
                c.col(1).y as f64,
                0.5 * (c.col(1).x + c.col(0).y) as f64,
            );
            let vol = dxx + dyy;
            let shear = (0.25 * (dxx - dyy).powi(2) + dxy * dxy).sqrt();
            smp.vol_shear[id] = if shear > 1e-3 {
                (vol / shear) as f32
            } else {
                0.0
            };
            smp.ep[id] = ep as f32;
            let (sxx, syy, sxy) = (st.xx as f64, st.yy as f64, st.xy as f64);
            let (tt, tn, nn) = (
                tx * tx * sxx + 2.0 * tx * ty * sxy + ty * ty * syy,
                tx * nx * sxx + (tx * ny + ty * nx) * sxy + ty * ny * syy,
                nx * nx * sxx + 2.0 * nx * ny * sxy + ny * ny * syy,
            );
            let _ = tt;
            smp.tau[id] = tn.abs() as f32;
            smp.sigma_n[id] = (-nn) as f32;
            let (dtt, dtn) = (
                tx * tx * dxx + 2.0 * tx * ty * dxy + ty * ty * dyy,
                tx * nx * dxx + (tx * ny + ty * nx) * dxy + ty * ny * dyy,
            );
            smp.stretch[id] = if dtn.abs() > 1e-3 {
                (dtt / dtn.abs()) as f32
            } else {
                0.0
            };
        }
        samples.push(smp);
        let t = sim.time();
        if (t > 0.3 && sim.diagnostics().max_speed < rest) || t >= 3.0 {
            break;
        }
    }
    let pos = positions_by_id(&sim, xc);
    let right: Vec<(f64, f64)> = pos.iter().copied().filter(|q| q.0 >= 0.0).collect();
    let d = measure_deposit(&right, s, h, l0, h0);
    let foot = l0 * (1.0 + d.foot);
    println!(
        "φ = {phi}, h = {h} {variant}: rest at {:.2} s; flank {:.1}° (φ_ps {:.1}°, atan 3α_s {:.1}°), foot {:+.3}, toe {:.3} L0, run-out {:.3}",
        sim.time(),
        d.flank(),
        plane_strain_angle(phi),
        (3.0 * alpha_s).atan().to_degrees(),
        d.foot,
        d.toe,
        d.runout
    );
    // surface: the top particle rows of each bin
    let nb = ((right.iter().map(|q| q.0).fold(0.0, f64::max)) / h) as usize + 1;
    let mut top = vec![0.0f64; nb];
    for q in &right {
        let b = (q.0 / h) as usize;
        top[b] = top[b].max(q.1);
    }
    let height = top.iter().cloned().fold(0.0, f64::max);
    let mut flank = Vec::new();
    let mut toe = Vec::new();
    let mut core = Vec::new();
    let mut layer = Vec::new();
    for (id, q) in pos.iter().enumerate() {
        if q.0 < 0.0 {
            continue;
        }
        let b = (q.0 / h) as usize;
        if q.0 > foot {
            toe.push(id);
        } else if q.1 > top[b] - 1.5 * s && top[b] > 0.2 * height && top[b] < 0.8 * height {
            flank.push(id);
        } else if top[b] > 0.2 * height
            && top[b] < 0.8 * height
            && samples.iter().any(|smp| smp.speed[id] > 0.05)
        {
            layer.push(id);
        } else if q.0 < l0 * 0.5 && q.1 < 0.5 * h0 {
            core.push(id);
        }
    }
    let last = samples.len() - 1;
    for (name, group) in [
        ("flank surface", &flank),
        ("flowed material under the flank", &layer),
        ("toe", &toe),
        ("core", &core),
    ] {
        if group.is_empty() {
            println!("{name}: none");
            continue;
        }
        let k = group.len() as f64;
        // stop-and-go: slower than 2 mm/s for five samples, then faster than 2 cm/s
        let restarted = group
            .iter()
            .filter(|&&id| {
                let mut still = 0;
                let mut stopped = false;
                for smp in &samples {
                    let v = smp.speed[id];
                    if v < 2e-3 {
                        still += 1;
                        if still >= 5 && smp.t > 0.1 {
                            stopped = true;
                        }
                    } else {
                        still = 0;
                        if stopped && v > 2e-2 {
                            return true;
                        }
                    }
                }
                false
            })
            .count();
        let last_moving = group
            .iter()
            .map(|&id| {
                samples
                    .iter()
                    .rev()
                    .find(|smp| smp.speed[id] > 5e-3)
                    .map_or(0.0, |smp| smp.t)
            })
            .sum::<f64>()
            / k;
        let peak = group
            .iter()
            .map(|&id| samples.iter().map(|smp| smp.speed[id]).fold(0.0, f32::max) as f64)
            .sum::<f64>()
            / k;
        let flowed = group
            .iter()
            .filter(|&&id| samples[last].ep[id] >= 1.0)
            .count() as f64
            / k;
        println!(
            "{name}: {} particles; peak speed {peak:.3} m/s, last moving (> 5 mm/s) at {last_moving:.2} s; stopped and restarted: {:.0} %; ε_p ≥ 1 at rest: {:.0} % (median ε_p {:.2})",
            group.len(),
            100.0 * restarted as f64 / k,
            100.0 * flowed,
            {
                let mut e: Vec<f32> = group.iter().map(|&id| samples[last].ep[id]).collect();
                e.sort_by(f32::total_cmp);
                e[e.len() / 2]
            }
        );
        println!(
            "   t (s) | mean speed | at apex | √J2/(3α p), moving | vol/shear rate, moving | Στ/Σσ_n on the slope, moving (tan φ_ps {:.3}) | D_tt/|D_tn|, moving | ε_p < 1, moving",
            plane_strain_angle(phi).to_radians().tan()
        );
        for smp in samples.iter().step_by(5) {
            let moving: Vec<usize> = group
                .iter()
                .copied()
                .filter(|&id| smp.speed[id] > 1e-2)
                .collect();
            let km = moving.len().max(1) as f64;
            println!(
                "   {:.2} | {:.3} | {:.0} % | {:.3} ({} moving) | {:+.3} | {:.3} | {:+.3} | {}",
                smp.t,
                group.iter().map(|&id| smp.speed[id] as f64).sum::<f64>() / k,
                100.0 * group.iter().filter(|&&id| smp.apex[id]).count() as f64 / k,
                moving.iter().map(|&id| smp.ratio[id] as f64).sum::<f64>() / km,
                moving.len(),
                moving
                    .iter()
                    .map(|&id| smp.vol_shear[id] as f64)
                    .sum::<f64>()
                    / km,
                moving.iter().map(|&id| smp.tau[id] as f64).sum::<f64>()
                    / moving
                        .iter()
                        .map(|&id| smp.sigma_n[id] as f64)
                        .sum::<f64>()
                        .max(1e-9),
                moving.iter().map(|&id| smp.stretch[id] as f64).sum::<f64>() / km,
                moving.iter().filter(|&&id| smp.ep[id] < 1.0).count(),
            );
        }
    }
    Ok(())
}
