//! How dense a resting sand deposit is: a scene run through the playground at a quality level
//! (sleeping on, as the page runs it), or a sand box dropped in the empty sandbox, then the
//! interior of each granular body's deposit cut into cubes (squares in 2D) of 1.5 particle
//! spacings and the share of them holding no particle. The interior: under its own cell-wide
//! column's top and those around by two spacings or more, where the deposit is at least four
//! spacings thick, two spacings in from its lateral ends.
//!
//! `cargo run --release --example deposit_density -- SCENE|sandbox2|sandbox3 QUALITY SECONDS
//! [close|loose]` prints one line per granular body: `density body=.. particles=.. cubes=..
//! empty=.. share=..`; `close`/`loose` sets the scene's granular bodies' `close_grains` (not a
//! dropped box's, which takes its recipe's default).
use mpm::AnySimulation;
use mpm::playground::{Playground, Quality};
use mpm::{Dim, Simulation};
use std::collections::{HashMap, HashSet};

fn points<D: Dim>(s: &Simulation<D>, b: usize) -> Vec<[f64; 3]> {
    let p = s.particles();
    s.bodies()[b]
        .range()
        .map(|i| std::array::from_fn(|a| if a < D::DIM { p.x[i][a] as f64 } else { 0.0 }))
        .collect()
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (what, quality, seconds) = (&a[0], &a[1], a[2].parse::<f64>().expect("SECONDS"));
    let close = a.get(3).map(|c| c == "close");
    let q = Quality::find(quality).expect("a quality level");
    let mut scene = if let Some(dim) = what.strip_prefix("sandbox") {
        Playground::sandbox_scene(dim.parse().expect("sandbox2 or sandbox3"))
    } else {
        mpm::SceneConfig::load(std::path::Path::new(what)).expect("a scene")
    };
    let granular =
        |m: &mpm::Material| matches!(m.behaviour(), mpm::material::Behaviour::Granular(_));
    for b in scene.bodies.iter_mut() {
        if granular(&b.material) {
            b.close_grains = close;
        }
    }
    let dim = scene.dim;
    let mut pg = Playground::with_quality(scene, q).expect("the scene at the level");
    if what.starts_with("sandbox") {
        let point = [1.0, 0.0, 0.5];
        pg.drop_at("box", "drucker_prager", &point[..dim], 0.0, 0.25)
            .expect("a sand box");
    }
    pg.set_sleeping(true);
    while pg.time() < seconds {
        pg.frame(0.05, 1e9, || 0.0).expect("a step");
    }
    let h = pg.scene().cell_size;
    for (b, body) in pg.scene().bodies.clone().iter().enumerate() {
        if !granular(&body.material) {
            continue;
        }
        let p = match pg.simulation() {
            AnySimulation::D2(s) => points(s, b),
            AnySimulation::D3(s) => points(s, b),
        };
        let s = h / body.particles_per_cell as f64;
        let column = |x: &[f64; 3]| ((x[0] / h).floor() as i64, (x[2] / h).floor() as i64);
        let mut top: HashMap<(i64, i64), f64> = HashMap::new();
        for x in &p {
            let t = top.entry(column(x)).or_insert(x[1]);
            *t = x[1].max(*t);
        }
        let surface = |x: &[f64; 3]| {
            let (i, k) = column(x);
            let dk = if dim == 3 { -1..=1 } else { 0..=0 };
            dk.flat_map(|c| (-1..=1).map(move |r| (i + r, k + c)))
                .map(|c| top.get(&c).copied().unwrap_or(f64::NEG_INFINITY))
                .fold(f64::INFINITY, f64::min)
        };
        let lo = |a: usize| p.iter().map(|x| x[a]).fold(f64::INFINITY, f64::min);
        let hi = |a: usize| p.iter().map(|x| x[a]).fold(f64::NEG_INFINITY, f64::max);
        let laterals: Vec<usize> = if dim == 3 { vec![0, 2] } else { vec![0] };
        let (l0, l1): (Vec<f64>, Vec<f64>) = (
            laterals.iter().map(|&a| lo(a)).collect(),
            laterals.iter().map(|&a| hi(a)).collect(),
        );
        let floor = lo(1);
        let inside = |x: &[f64; 3]| {
            let top = surface(x);
            x[1] < top - 2.0 * s
                && top - floor > 4.0 * s
                && laterals
                    .iter()
                    .enumerate()
                    .all(|(k, &a)| x[a] > l0[k] + 2.0 * s && x[a] < l1[k] - 2.0 * s)
        };
        // cubes of 1.5 spacings from the deposit's lowest corner; a cube is counted where its
        // centre is inside, and is empty where no particle lies in it
        let c = 1.5 * s;
        let cube = |x: &[f64; 3]| -> [i64; 3] {
            [
                ((x[0] - l0[0]) / c).floor() as i64,
                ((x[1] - floor) / c).floor() as i64,
                if dim == 3 {
                    ((x[2] - l0[1]) / c).floor() as i64
                } else {
                    0
                },
            ]
        };
        let full: HashSet<[i64; 3]> = p.iter().map(cube).collect();
        let n = |a: usize| ((l1[a] - l0[a]) / c).ceil() as i64;
        let ny = ((hi(1) - floor) / c).ceil() as i64;
        let nz = if dim == 3 { n(1) } else { 1 };
        let (mut cubes, mut empty) = (0usize, 0usize);
        for i in 0..n(0) {
            for j in 0..ny {
                for k in 0..nz {
                    let centre = [
                        l0[0] + (i as f64 + 0.5) * c,
                        floor + (j as f64 + 0.5) * c,
                        if dim == 3 {
                            l0[1] + (k as f64 + 0.5) * c
                        } else {
                            0.0
                        },
                    ];
                    if inside(&centre) {
                        cubes += 1;
                        if !full.contains(&[i, j, k]) {
                            empty += 1;
                        }
                    }
                }
            }
        }
        println!(
            "density scene={what} quality={quality} close={close:?} body={} particles={} cubes={cubes} empty={empty} share={:.4} t={:.2}",
            body.name,
            p.len(),
            empty as f64 / cubes.max(1) as f64,
            pg.time()
        );
    }
}
