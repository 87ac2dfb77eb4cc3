//! How dense a resting sand deposit is: a scene run through the playground at a quality level
//! (sleeping on, as the page runs it), or a sand box dropped in the empty sandbox, then the
//! interior of each granular body's deposit cut into cubes (squares in 2D) of 1.5 particle
//! spacings and the share of them holding no particle (`mpm::measure::interior_gaps`, which
//! says what the interior is).
//!
//! `cargo run --release --example deposit_density -- SCENE|sandbox2|sandbox3 QUALITY SECONDS
//! [close|loose]` prints one line per granular body: `density body=.. particles=.. cubes=..
//! empty=.. share=..`; `close`/`loose` sets the scene's granular bodies' `close_grains` (not a
//! dropped box's, which takes its recipe's default).
use mpm::AnySimulation;
use mpm::playground::{Playground, Quality};
use mpm::{Dim, Simulation};

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
        let gaps = mpm::measure::interior_gaps(&p, dim, s, h);
        let (cubes, empty) = (gaps.cubes, gaps.empty);
        println!(
            "density scene={what} quality={quality} close={close:?} body={} particles={} cubes={cubes} empty={empty} share={:.4} t={:.2}",
            body.name,
            p.len(),
            gaps.share(),
            pg.time()
        );
    }
}
