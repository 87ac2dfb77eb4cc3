//! What acts on the toe of the low column (`low_column`, a = 0.5, floor μ = 0.6) or of Bui et
//! al. (2008)'s rods while it slows: every 0.02 s the floor's friction force on the toe's
//! particles against μ times their weight, their speed, how many are stress-free (at the
//! apex), how many lie on the floor's first particle row or have no neighbour below
//! (separated), the material's thickness in their grid column (in grains of
//! [`mpm::measure::GRAIN`]) and the vertical stress at the toe's base against the weight of
//! the column above, with the FLIP share the transfer applies. The toe is what lies beyond the
//! flank's foot at rest. See docs/validation.md, "The toe on fine grids".
//!
//! The floor's force is measured, not modelled: at each sample the simulation is copied, the
//! copy's walls made frictionless, and both take the same step; the toe's momentum differs
//! between them by the friction impulse its particles received (the transfer is linear in the
//! nodes' velocities and its weights sum to one).
//!
//! `nice taskset -c 1 cargo run --release --example toe_contact -- 30 0.0025` (φ in degrees
//! or `bui`, h in m)

#[path = "../tests/support/validation.rs"]
mod validation;
use mpm::math::SymTensor;
use mpm::measure::GRAIN;
use mpm::recipe::Recipe;
use mpm::step::transfer::FLIP_AT_CONSTRAINTS;
use mpm::{KernelKind, Simulation};
use std::collections::HashMap;
use validation::*;

#[derive(Clone, Default)]
struct Sample {
    t: f64,
    speed: Vec<f32>,
    /// the floor's horizontal force (N per m of depth), positive against the motion
    friction: Vec<f32>,
    weight: Vec<f32>,
    apex: Vec<bool>,
    floor_row: Vec<bool>,
    separated: Vec<bool>,
    thickness: Vec<f32>,
    /// −σ_yy against ρ g times the material above the particle in its column
    load: Vec<f32>,
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let case = args.first().cloned().unwrap_or("30".into());
    let h: f64 = args
        .get(1)
        .and_then(|a| a.parse().ok())
        .filter(|h| (0.001..=0.05).contains(h))
        .ok_or("h: give a cell size in [0.001, 0.05] m")?;
    if let Some(v) = args.get(2) {
        return Err(format!(
            "`{v}`: toe_contact takes a case and a cell size only"
        ));
    }
    let n = Numerics::new(h, KernelKind::Gimp);
    let bui = case == "bui";
    let scene = if bui {
        bui_scene(&n)
    } else {
        let phi = case_friction_angle(&case)?;
        low_column_scene(phi, &n)
    };
    let mu = scene.boundary.friction;
    let g: f64 = 9.81;
    let body = &scene.bodies[0];
    let alpha = body
        .flip
        .unwrap_or_else(|| Recipe::default_flip(&body.material));
    let density = body.material.elastic_params().density;
    let s = spacing(&scene);
    let mut sim = Simulation::<mpm::D2>::new(scene).map_err(|e| e.to_string())?;
    let (xc, l0) = if bui {
        (0.0, 0.2)
    } else {
        column_extent(&sim, s)
    };
    let h0 = 0.1;
    let count = sim.particles().len();
    let mut samples: Vec<Sample> = Vec::new();
    let rest = 1e-3 * (g * h0).sqrt();
    let mut next = 0.0;
    loop {
        sim.advance(0.01).map_err(|e| e.to_string())?;
        let t = sim.time();
        if t + 1e-9 >= next {
            next += 0.02;
            samples.push(sample(&mut sim, count, s, h, g, density)?);
        }
        if (t > 0.3 && sim.diagnostics().max_speed < rest) || t >= 3.0 {
            break;
        }
    }
    let pos = positions_by_id(&sim, xc);
    let right: Vec<(f64, f64)> = pos.iter().copied().filter(|q| q.0 >= 0.0).collect();
    let d = measure_deposit(&right, s, h, l0, h0);
    let foot = l0 * (1.0 + d.foot);
    println!(
        "{case}, h = {h}: rest at {:.2} s; flank {:.1}°, foot {:+.3}, run-out at one grain {:.3}, farthest {:.3} (L0 = {l0} m); floor μ = {mu}",
        sim.time(),
        d.flank(),
        d.foot,
        d.runout_thin,
        d.runout,
    );
    println!(
        "FLIP share applied: α = {alpha} (the cap {FLIP_AT_CONSTRAINTS} where walls act is above it), the same at the front as everywhere"
    );
    let toe: Vec<usize> = (0..count).filter(|&id| pos[id].0 > foot).collect();
    let k = toe.len().max(1) as f64;
    println!(
        "toe: {} particles beyond the flank's foot (x > {:.3} m)",
        toe.len(),
        foot
    );
    println!(
        "   t (s) | mean speed (m/s) | floor force / (μ weight) | on the floor row | separated | at apex | thickness (grains) | −σ_yy / ρ g (depth) on the floor row"
    );
    for smp in &samples {
        let w: f64 = toe.iter().map(|&id| smp.weight[id] as f64).sum();
        let f: f64 = toe.iter().map(|&id| smp.friction[id] as f64).sum();
        let share = |v: &Vec<bool>| 100.0 * toe.iter().filter(|&&id| v[id]).count() as f64 / k;
        let row: Vec<usize> = toe
            .iter()
            .copied()
            .filter(|&id| smp.floor_row[id])
            .collect();
        let load = row.iter().map(|&id| smp.load[id] as f64).sum::<f64>() / row.len().max(1) as f64;
        let mut th: Vec<f32> = toe.iter().map(|&id| smp.thickness[id]).collect();
        th.sort_by(f32::total_cmp);
        println!(
            "   {:.2} | {:.3} | {:.2} | {:.0} % | {:.0} % | {:.0} % | {:.1} | {:.2}",
            smp.t,
            toe.iter().map(|&id| smp.speed[id] as f64).sum::<f64>() / k,
            f / (mu * w).max(1e-12),
            share(&smp.floor_row),
            share(&smp.separated),
            share(&smp.apex),
            th.get(th.len() / 2).copied().unwrap_or(0.0) as f64 / GRAIN,
            load,
        );
    }
    Ok(())
}

/// One sample of every particle (by id), the floor's force from a frictionless copy's step.
fn sample(
    sim: &mut Simulation<mpm::D2>,
    count: usize,
    s: f64,
    h: f64,
    g: f64,
    density: f64,
) -> Result<Sample, String> {
    let mut copy = sim.clone();
    copy.set_world(|w| w.boundary.friction = 0.0)
        .map_err(|e| e.to_string())?;
    let dt = sim.stable_dt();
    sim.step_at_most(dt).map_err(|e| e.to_string())?;
    copy.step_at_most(dt).map_err(|e| e.to_string())?;
    let (p, q) = (sim.particles(), copy.particles());
    let mut off = vec![0.0f64; count];
    for i in 0..q.len() {
        off[q.id[i] as usize] = q.v[i][0] as f64;
    }
    // particles by cell of side s, for the neighbour below; material per grid column
    let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut column: HashMap<i64, f64> = HashMap::new();
    for i in 0..p.len() {
        let (x, y) = (p.x[i][0] as f64, p.x[i][1] as f64);
        cells
            .entry(((x / s).floor() as i64, (y / s).floor() as i64))
            .or_default()
            .push(i);
        *column.entry((x / h).floor() as i64).or_default() += p.mass[i] as f64;
    }
    let mut smp = Sample {
        t: sim.time(),
        speed: vec![0.0; count],
        friction: vec![0.0; count],
        weight: vec![0.0; count],
        apex: vec![false; count],
        floor_row: vec![false; count],
        separated: vec![false; count],
        thickness: vec![0.0; count],
        load: vec![0.0; count],
    };
    for i in 0..p.len() {
        let id = p.id[i] as usize;
        let (x, y) = (p.x[i][0] as f64, p.x[i][1] as f64);
        let (vx, m) = (p.v[i][0] as f64, p.mass[i] as f64);
        smp.speed[id] = p.v[i].length();
        // the floor's friction opposes the motion: positive when it slows the particle
        smp.friction[id] = (-(vx - off[id]) * m / dt * vx.signum()) as f32;
        smp.weight[id] = (m * g) as f32;
        smp.apex[id] = p.stress[i].trace() > -1e-3;
        smp.floor_row[id] = y < s;
        let (cx, cy) = ((x / s).floor() as i64, (y / s).floor() as i64);
        let below = (cx - 1..=cx + 1).any(|a| {
            (cy - 2..=cy).any(|b| {
                cells.get(&(a, b)).is_some_and(|v| {
                    v.iter().any(|&j| {
                        let (xj, yj) = (p.x[j][0] as f64, p.x[j][1] as f64);
                        j != i && (xj - x).abs() < s && yj < y - 0.25 * s && yj > y - 1.5 * s
                    })
                })
            })
        });
        smp.separated[id] = !smp.floor_row[id] && !below;
        let th = column
            .get(&((x / h).floor() as i64))
            .copied()
            .unwrap_or(0.0)
            / (density * h);
        smp.thickness[id] = th as f32;
        smp.load[id] = (-p.stress[i].yy as f64 / (density * g * (th - y).max(0.5 * s))) as f32;
    }
    Ok(smp)
}
