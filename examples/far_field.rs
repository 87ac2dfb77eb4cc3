//! Is the far field's settling under a dropped bunny elastic? The shipped 2D (or, with `3d`,
//! 3D) sand ball settled awake for 2.5 s, then its bunny added (0.15 m above the ball's top),
//! run awake; from the
//! bunny's first contact, at the listed times after it, for the sand particles more than
//! `far` (0.2 m) from the impact point at contact:
//! - `|u|` the median displacement since contact (mm), and how it splits: `rigid` the RMS of
//!   the best rigid motion (translation and rotation) of the far set, `strain` the RMS of the
//!   best affine motion's symmetric part E (x − x̄), `rest` the RMS of what no affine motion
//!   takes (mm); `slip` the median |u_x| of the particles within a cell of the floor (mm);
//! - `dep` the plastic strain taken since contact (the accumulated equivalent deviatoric
//!   strain, (√J2_trial − √J2)/(√3 G) per step): median, 90th percentile, largest, and the
//!   share that took more than 1e-5;
//! - `dee` the elastic equivalent deviatoric strain change q(Δσ)/(3 G) since contact: median
//!   and 90th percentile; `dev` the volumetric Δp/K, median;
//! - `W_p` the plastic work since contact: the far field's, Σ V q̄ Δε_p (q̄ the mean of q at
//!   contact and now), and the whole sand's (its booked plastic dissipation), J/m;
//! - `q/qc` the stress path against the cone: q / q_cone(p) (each particle's own cone),
//!   median and 90th percentile, and the share within 2 % of the cone or past it.
//!
//! With `control` no bunny is added: the same figures for the ball left at rest, from the
//! time the drop's contact would be.
//!
//!   nice cargo run --release --example far_field -- [far (m)] [control] [3d]
use mpm::math::{Dim, SymTensor};
use mpm::{D2, D3, Material, SceneConfig, Simulation};
use std::collections::HashMap;
use std::path::Path;

struct State {
    x: [f64; 3],
    stress: Vec<f64>,
    plastic: f64,
    volume: f64,
}

fn pct(v: &mut [f64], f: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * f) as usize]
}

/// Pressure (compression positive) and q = √(3 J2) of a stress's components (xx, yy, zz, then
/// the shear components).
fn pq(c: &[f64]) -> (f64, f64) {
    let p = -(c[0] + c[1] + c[2]) / 3.0;
    let dev: f64 = c[..3].iter().map(|s| (s + p) * (s + p)).sum();
    let shear: f64 = c[3..].iter().map(|s| s * s).sum();
    (p, (3.0 * (0.5 * dev + shear)).sqrt())
}

/// Solves the d × d system a x = b (d ≤ 3) by Gaussian elimination with partial pivoting.
fn solve(mut a: [[f64; 3]; 3], mut b: [f64; 3], d: usize) -> [f64; 3] {
    for c in 0..d {
        let piv = (c..d)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        a.swap(c, piv);
        b.swap(c, piv);
        for r in c + 1..d {
            let f = a[r][c] / a[c][c];
            for k in c..d {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 3];
    for c in (0..d).rev() {
        let s: f64 = (c + 1..d).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    x
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let far: f64 = args
        .first()
        .filter(|a| a.parse::<f64>().is_ok())
        .map_or(0.2, |a| a.parse().unwrap());
    // `control`: no bunny; "contact" at the awake drop's contact time, the impact point there
    let control = args.iter().any(|a| a == "control");
    if args.iter().any(|a| a == "3d") {
        run::<D3>("scenes/bunny_on_sand_ball_3d.json", far, control);
    } else {
        run::<D2>("scenes/bunny_on_sand_ball_2d.json", far, control);
    }
}

fn run<D: Dim>(file: &str, far: f64, control: bool) {
    let d = D::DIM;
    let mut s = SceneConfig::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join(file))
        .expect("shipped scene");
    let bunny = s.bodies.pop().expect("the bunny");
    let Material::DruckerPrager(dp) = s.bodies[0].material.clone() else {
        unreachable!("the ball is Drucker-Prager sand")
    };
    let model = dp.model();
    let (e, nu) = (dp.youngs_modulus, dp.poisson_ratio);
    let (g, k) = (e / (2.0 * (1.0 + nu)), e / (3.0 * (1.0 - 2.0 * nu)));
    let h = s.cell_size;
    let mut sim = Simulation::<D>::new(s).expect("scene");
    sim.advance(2.5).expect("settle");
    let sand = sim.bodies()[0].range();
    let b = if control {
        0
    } else {
        sim.add_body(bunny).expect("bunny")
    };
    let pos = |x: D::Vector| -> [f64; 3] {
        std::array::from_fn(|c| if c < d { x[c] as f64 } else { 0.0 })
    };
    let top = |s: &Simulation<D>| {
        let p = s.particles();
        sand.clone().map(|i| p.x[i][1] as f64).fold(0.0, f64::max)
    };
    let lowest = |s: &Simulation<D>| {
        let p = s.particles();
        s.bodies()[b]
            .range()
            .map(|i| pos(p.x[i]))
            .fold(
                [0.0, f64::INFINITY, 0.0],
                |a, c| if c[1] < a[1] { c } else { a },
            )
    };
    let x0 = if control {
        let t = if d == 2 { 0.252 } else { 0.25 };
        sim.advance(t).expect("rest");
        [0.412, 0.241, 0.5]
    } else {
        while lowest(&sim)[1] > top(&sim) + h {
            sim.advance(0.002).expect("fall");
        }
        lowest(&sim)
    };
    let t0 = sim.time();
    let state = |s: &Simulation<D>| -> HashMap<u32, State> {
        let p = s.particles();
        sand.clone()
            .map(|i| {
                (
                    p.id[i],
                    State {
                        x: pos(p.x[i]),
                        stress: p.stress[i].components().iter().map(|&c| c as f64).collect(),
                        plastic: p.plastic_strain[i] as f64,
                        volume: p.volume[i] as f64,
                    },
                )
            })
            .collect()
    };
    let dist = |x: &[f64; 3]| (0..3).map(|c| (x[c] - x0[c]).powi(2)).sum::<f64>().sqrt();
    let start = state(&sim);
    let far_ids: Vec<u32> = start
        .iter()
        .filter(|(_, st)| dist(&st.x) > far)
        .map(|(&id, _)| id)
        .collect();
    let mobilised = |st: &State| {
        let (p, q) = pq(&st.stress);
        let cone = model.pq_surface(st.plastic);
        q / (cone.slope * p + cone.intercept).max(1e-9)
    };
    let m0: Vec<f64> = far_ids.iter().map(|id| mobilised(&start[id])).collect();
    println!(
        "{file}: sand {} particles, far (> {far} m from the impact at {:.3?}, t = {t0:.3} s) {}; G {g:.0} Pa, K {k:.0} Pa",
        start.len(),
        &x0[..d],
        far_ids.len()
    );
    println!(
        "at contact: q/qc median {:.3}, 90 % {:.3}, at the cone {:.3}",
        pct(&mut m0.clone(), 0.5),
        pct(&mut m0.clone(), 0.9),
        m0.iter().filter(|&&m| m > 0.98).count() as f64 / m0.len() as f64
    );
    let sand_stats = |s: &Simulation<D>| s.bodies()[0].stats().clone();
    let (elastic0, plastic0) = (
        sand_stats(&sim).elastic,
        sand_stats(&sim).dissipated_plastic,
    );
    let kinetic0 = if control {
        0.0
    } else {
        sim.bodies()[b].stats().kinetic
    };
    let per = if d == 2 { "J/m" } else { "J" };
    println!(
        "at contact: sand's elastic energy {elastic0:.3e} {per}, bunny's kinetic {kinetic0:.3e} {per}"
    );
    println!(
        "t_after  |u|mm  ū_x    ū_y   rigid strain rest  slip |  dep med     90%      max     >1e-5 | dee med     90%   dev med  | q/qc med  90%  at-cone  |  |E|      |W|     | W_p far  W_p all ({per})"
    );
    let n = far_ids.len() as f64;
    for t_after in [0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 1.5] {
        sim.advance(t0 + t_after - sim.time()).expect("step");
        let now = state(&sim);
        // displacements and the best affine fit u = ū + G (x − x̄)
        let xs: Vec<[f64; 3]> = far_ids.iter().map(|id| start[id].x).collect();
        let us: Vec<[f64; 3]> = far_ids
            .iter()
            .map(|id| std::array::from_fn(|c| now[id].x[c] - start[id].x[c]))
            .collect();
        let mean = |v: &[[f64; 3]]| -> [f64; 3] {
            std::array::from_fn(|c| v.iter().map(|x| x[c]).sum::<f64>() / n)
        };
        let (xb, ub) = (mean(&xs), mean(&us));
        let mut sxx = [[0.0; 3]; 3];
        let mut sux = [[0.0; 3]; 3]; // Σ (u_c − ū_c)(x_j − x̄_j)
        for (x, u) in xs.iter().zip(&us) {
            for i in 0..d {
                for j in 0..d {
                    sxx[i][j] += (x[i] - xb[i]) * (x[j] - xb[j]);
                    sux[i][j] += (u[i] - ub[i]) * (x[j] - xb[j]);
                }
            }
        }
        // row c of G solves Sxx G_c = Sux_c
        let grad: [[f64; 3]; 3] = std::array::from_fn(|c| solve(sxx, sux[c], d));
        let sym: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (grad[i][j] + grad[j][i])));
        let skew: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (grad[i][j] - grad[j][i])));
        let norm = |m: &[[f64; 3]; 3]| m.iter().flatten().map(|a| a * a).sum::<f64>().sqrt();
        let (mut rigid, mut strain, mut rest, mut mags) = (0.0, 0.0, 0.0, Vec::new());
        for (x, u) in xs.iter().zip(&us) {
            let dx: [f64; 3] = std::array::from_fn(|c| x[c] - xb[c]);
            let apply = |m: &[[f64; 3]; 3], c: usize| (0..3).map(|j| m[c][j] * dx[j]).sum::<f64>();
            for c in 0..d {
                let r = ub[c] + apply(&skew, c);
                let st = apply(&sym, c);
                rigid += r * r;
                strain += st * st;
                rest += (u[c] - r - st).powi(2);
            }
            mags.push(1e3 * (0..3).map(|c| u[c] * u[c]).sum::<f64>().sqrt());
        }
        let rms = |s: f64| 1e3 * (s / n).sqrt();
        let mut slip: Vec<f64> = far_ids
            .iter()
            .filter(|id| start[*id].x[1] < h)
            .map(|id| {
                let (a, b) = (&start[id].x, &now[id].x);
                1e3 * ((b[0] - a[0]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
            })
            .collect();
        let mut dep: Vec<f64> = far_ids
            .iter()
            .map(|id| now[id].plastic - start[id].plastic)
            .collect();
        let over = dep.iter().filter(|&&x| x > 1e-5).count() as f64 / n;
        let (mut dee, mut dev): (Vec<f64>, Vec<f64>) = far_ids
            .iter()
            .map(|id| {
                let (a, b) = (&start[id].stress, &now[id].stress);
                let ds: Vec<f64> = a.iter().zip(b).map(|(a, b)| b - a).collect();
                let (dp, dq) = pq(&ds);
                (dq / (3.0 * g), (dp / k).abs())
            })
            .unzip();
        // the far field's plastic work ≈ Σ V q̄ Δε_p (ε_p the equivalent plastic strain, q
        // its conjugate; q̄ the mean of the two ends), and the whole sand's since contact
        let far_work: f64 = far_ids
            .iter()
            .map(|id| {
                let (a, b) = (&start[id], &now[id]);
                0.5 * (pq(&a.stress).1 + pq(&b.stress).1) * (b.plastic - a.plastic) * b.volume
            })
            .sum();
        let all_work = sand_stats(&sim).dissipated_plastic - plastic0;
        let mut mob: Vec<f64> = far_ids.iter().map(|id| mobilised(&now[id])).collect();
        let at_cone = mob.iter().filter(|&&m| m > 0.98).count() as f64 / n;
        println!(
            "{t_after:6.2}  {:5.2} {:+5.2} {:+5.2}  {:5.2} {:5.2} {:5.2} {:5.2} | {:.2e} {:.2e} {:.2e} {:5.3} | {:.2e} {:.2e} {:.2e} | {:5.3} {:5.3} {:5.3} | {:.2e} {:.2e} | {far_work:.2e} {all_work:.2e}",
            pct(&mut mags, 0.5),
            1e3 * ub[0],
            1e3 * ub[1],
            rms(rigid),
            rms(strain),
            rms(rest),
            pct(&mut slip, 0.5),
            pct(&mut dep, 0.5),
            pct(&mut dep, 0.9),
            pct(&mut dep, 1.0),
            over,
            pct(&mut dee, 0.5),
            pct(&mut dee, 0.9),
            pct(&mut dev, 0.5),
            pct(&mut mob, 0.5),
            pct(&mut mob, 0.9),
            at_cone,
            norm(&sym),
            norm(&skew),
        );
    }
}
