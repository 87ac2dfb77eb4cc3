//! What a drop wakes, over time: the shipped 2D sand ball settled awake for 1.5 s, then run
//! 1 s with sleeping on (and, beside it, awake), then its bunny added (it appears 0.15 m
//! above the ball's top); every 0.05 s after the bunny's first contact with the sand, for
//! 1.5 s:
//! - `awake` the share of the sand's particles awake in the sleeping run, and how far from
//!   the impact point (the bunny's lowest particle at first contact) the awake ones reach
//!   (`reach`, m, the 90th percentile of their distances);
//! - `fast` the share of the sand's particles faster than the sleep speed in the awake run
//!   (what an instantaneous-speed signal sees), and their 90th-percentile distance;
//! - `moved` the share of the sand's particles displaced more than a tenth of a cell since the
//!   drop in the awake run (what a displacement signal would see), and theirs;
//! - `far_mm` the median and largest displacement since the drop (mm) of the awake run's sand
//!   particles more than 0.2 m (half the ball's diameter) from the impact point.
//!
//!   cargo run --release --example wake_trace
use mpm::{D2, SceneConfig, Simulation};
use std::path::Path;

fn main() {
    let mut s = SceneConfig::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bunny_on_sand_ball_2d.json"),
    )
    .expect("shipped scene");
    let bunny = s.bodies.pop().expect("the bunny");
    let h = s.cell_size;
    let mut awake = Simulation::<D2>::new(s).expect("scene");
    awake.advance(1.5).expect("settle");
    let mut sleeping = awake.clone();
    sleeping.sleep_when_at_rest();
    let rule = sleeping.sleeping().expect("on");
    awake.advance(1.0).expect("rest");
    sleeping.advance(1.0).expect("rest");
    let sand = awake.bodies()[0].range();
    let n = sand.len();
    println!(
        "sand particles {n}; asleep before the drop {:.3}; sleep speed {:.4} m/s, wake speed {:.4} m/s",
        sleeping.asleep() as f64 / n as f64,
        rule.speed,
        rule.wake_speed
    );
    let b = awake.add_body(bunny.clone()).expect("bunny");
    sleeping.add_body(bunny).expect("bunny");
    // first contact: the bunny's lowest particle within a cell of the sand's top
    let top = |s: &Simulation<D2>| {
        let p = s.particles();
        sand.clone().map(|i| p.x[i][1] as f64).fold(0.0, f64::max)
    };
    let lowest = |s: &Simulation<D2>| {
        let p = s.particles();
        s.bodies()[b]
            .range()
            .map(|i| (p.x[i][1] as f64, p.x[i][0] as f64))
            .fold((f64::INFINITY, 0.0), |a, c| if c.0 < a.0 { c } else { a })
    };
    while lowest(&awake).0 > top(&awake) + h {
        awake.advance(0.002).expect("fall");
        sleeping.advance(0.002).expect("fall");
    }
    let (y0, x0) = lowest(&awake);
    let t0 = awake.time();
    // by particle id: the run reorders its particles by grid block
    let x_drop: std::collections::HashMap<u32, [f64; 2]> = {
        let p = awake.particles();
        sand.clone()
            .map(|i| (p.id[i], [p.x[i][0] as f64, p.x[i][1] as f64]))
            .collect()
    };
    println!("impact at t = {t0:.3} s, x = {x0:.3} m, y = {y0:.3} m");
    println!("t_after  awake  reach   fast  reach   moved  reach  far_mm(median max)");
    let share = |mut d: Vec<f64>| -> (f64, f64) {
        let k = d.len();
        if k == 0 {
            return (0.0, 0.0);
        }
        d.sort_by(f64::total_cmp);
        (k as f64 / n as f64, d[(0.9 * (k - 1) as f64) as usize])
    };
    let dist = |x: [f64; 2]| ((x[0] - x0).powi(2) + (x[1] - y0).powi(2)).sqrt();
    for k in 0..=30 {
        let t = t0 + 0.05 * k as f64;
        awake.advance(t - awake.time()).expect("step");
        sleeping.advance(t - sleeping.time()).expect("step");
        let (pa, ps) = (awake.particles(), sleeping.particles());
        // a body's sleeping particles are the last of its range
        let woke = share(
            sleeping.bodies()[0]
                .active()
                .map(|i| dist([ps.x[i][0] as f64, ps.x[i][1] as f64]))
                .collect(),
        );
        let fast = share(
            sand.clone()
                .filter(|&i| pa.v[i].length() > rule.speed)
                .map(|i| dist([pa.x[i][0] as f64, pa.x[i][1] as f64]))
                .collect(),
        );
        let moved = share(
            sand.clone()
                .filter(|&i| {
                    let d = x_drop[&pa.id[i]];
                    let dx = pa.x[i][0] as f64 - d[0];
                    let dy = pa.x[i][1] as f64 - d[1];
                    (dx * dx + dy * dy).sqrt() > 0.1 * h
                })
                .map(|i| dist([pa.x[i][0] as f64, pa.x[i][1] as f64]))
                .collect(),
        );
        let mut far: Vec<f64> = sand
            .clone()
            .filter(|&i| dist(x_drop[&pa.id[i]]) > 0.2)
            .map(|i| {
                let d = x_drop[&pa.id[i]];
                1e3 * ((pa.x[i][0] as f64 - d[0]).powi(2) + (pa.x[i][1] as f64 - d[1]).powi(2))
                    .sqrt()
            })
            .collect();
        far.sort_by(f64::total_cmp);
        let (far_median, far_max) = (far[far.len() / 2], far[far.len() - 1]);
        println!(
            "{:6.2}  {:6.3} {:6.3}  {:6.3} {:6.3}  {:6.3} {:6.3}  {far_median:6.2} {far_max:6.2}",
            t - t0,
            woke.0,
            woke.1,
            fast.0,
            fast.1,
            moved.0,
            moved.1
        );
    }
}
