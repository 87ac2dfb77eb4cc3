//! Pouring (`bodies[].pour`, src/sim/pour.rs): a spout pours its body's particles layer by
//! layer, in 2D and 3D. The volume poured follows the rate to within one layer and every
//! particle keeps its mass; a stream clear of the floor falls freely, its momentum that of the
//! inflow plus gravity's impulse and its energy brought in that of the particles at the exit;
//! the energy account of a heap being poured closes; pouring leaves every other body's
//! particles, and every sleeping particle, as they were; a spout opens as its body enters; the
//! 2D heap regains its density where its grains close and stands at the plane-strain angle of
//! its cone, following φ.

// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use mpm::config::PourConfig;
use mpm::sim::Spout;
use mpm::{BodyConfig, D2, D3, Dim, Material, SceneConfig, Shape, Simulation};

fn sand() -> Material {
    Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0)
}

const DENSITY: f64 = 2200.0;

fn pour(spout: &[f64], radius: f64, rate: f64, duration: f64) -> PourConfig {
    PourConfig {
        spout: spout.to_vec(),
        radius,
        rate,
        duration,
    }
}

/// A scene of dimension `dim`, domain `size`, cells of `h`, a rough floor, with `bodies`.
fn scene(size: &[f64], h: f64, bodies: Vec<BodyConfig>) -> SceneConfig {
    let mut s = SceneConfig::new(size.len(), size, h);
    s.boundary.friction = 0.8;
    s.bodies = bodies;
    s
}

/// The spout of body `b` as the simulation runs it.
fn spout<D: Dim>(sim: &Simulation<D>, b: usize) -> Spout {
    sim.bodies()[b].spout().expect("a poured body").clone()
}

/// The 2D and 3D pours of the mass and free-fall tests: a spout `height` m up in the middle
/// of a box `width` wide and `height` + 0.1 m tall, pouring about 0.5 m/s of exit speed for
/// `duration` s.
fn stream_scene(dim: usize, height: f64, duration: f64) -> SceneConfig {
    let (size, h, radius): (Vec<f64>, f64, f64) = if dim == 2 {
        (vec![0.4, height + 0.1], 0.01, 0.02)
    } else {
        (vec![0.4, height + 0.1, 0.4], 0.02, 0.03)
    };
    let mut spout = vec![0.2; dim];
    spout[1] = height;
    // about 0.5 m/s through the exit's πr² (2r in 2D)
    let area = if dim == 2 {
        2.0 * radius
    } else {
        std::f64::consts::PI * radius * radius
    };
    let body = BodyConfig::poured("stream", pour(&spout, radius, 0.5 * area, duration), sand());
    scene(&size, h, vec![body])
}

/// Poured volume Σ m / ρ against Q τ at every step of a pour of `duration` s and a while
/// after: within one layer's volume; every particle's mass ρ s^dim, as entered. With gravity
/// off the stream moves as one, and its particles' volumes Σ V_p follow Q τ as closely.
fn volume_follows_the_rate<D: Dim>(gravity: bool) {
    let duration = 0.4;
    let mut s = stream_scene(D::DIM, 0.5, duration);
    if !gravity {
        s.gravity = Some(vec![0.0; D::DIM]);
    }
    let q = s.bodies[0].pour.as_ref().unwrap().rate;
    let mut sim = Simulation::<D>::new(s).unwrap();
    let spout = spout(&sim, 0);
    let sp = spout.spacing();
    let mass = DENSITY * sp.powi(D::DIM as i32);
    let layer = spout.per_layer() as f64 * sp.powi(D::DIM as i32);
    assert_eq!(sim.particles().len(), 0, "a poured body starts empty");
    let mut steps = 0;
    while sim.time() < duration + 0.1 {
        sim.step().unwrap();
        steps += 1;
        let tau = sim.time().min(duration);
        let p = sim.particles();
        let poured: f64 = p.mass.iter().map(|&m| m as f64).sum::<f64>() / DENSITY;
        assert!(
            (poured - q * tau).abs() <= layer * (1.0 + 1e-5),
            "{}D, t = {}: poured {poured}, rate × time {}, a layer {layer}",
            D::DIM,
            sim.time(),
            q * tau
        );
        for &m in &p.mass {
            assert!((m as f64 - mass).abs() <= 1e-6 * mass, "{m} against {mass}");
        }
        if !gravity {
            let volume: f64 = p.volume.iter().map(|&v| v as f64).sum();
            assert!(
                (volume - q * tau).abs() <= layer * (1.0 + 1e-3),
                "{}D without gravity, t = {}: Σ V_p {volume}, rate × time {}",
                D::DIM,
                sim.time(),
                q * tau
            );
        }
    }
    assert!(steps > 50);
    let total = sim.particles().len() as u64;
    assert_eq!(total, spout.particles(), "every layer poured");
    assert_eq!(total, spout.layers() * spout.per_layer() as u64);
    // the layers the formula counts: every k with k s / v0 < T
    let v0 = spout.exit_speed();
    let layers = spout.layers() as f64;
    assert!((layers - 1.0) * sp / v0 < duration && layers * sp / v0 >= duration - 1e-12);
}

#[test]
fn the_poured_volume_follows_the_rate_and_each_particle_keeps_its_mass() {
    volume_follows_the_rate::<D2>(true);
    volume_follows_the_rate::<D3>(true);
    volume_follows_the_rate::<D2>(false);
    volume_follows_the_rate::<D3>(false);
}

/// A stream clear of the floor, followed step by step (the layers entering between steps):
/// each particle where free fall since its exit puts it, at its speed (within 3 %; the first
/// and the last layer within 10 %, their momentum shared with the next layer's); the
/// momentum the inflow brought plus gravity's impulse on the mass present, step by step, is
/// the bodies' momentum (within 10⁻⁴); the energy brought in is that of the particles at
/// the exit, ½ m v0² + m g y_exit each (within 10⁻⁵).
fn falls_freely<D: Dim>() {
    let (height, duration, until) = (1.0, 0.3, 0.35);
    let s = stream_scene(D::DIM, height, duration);
    let exit = s.bodies[0].pour.as_ref().unwrap().spout.clone();
    let mut sim = Simulation::<D>::new(s).unwrap();
    let spout = spout(&sim, 0);
    let (v0, n) = (spout.exit_speed(), spout.per_layer());
    let g = 9.81;
    let (mut inflow, mut impulse) = (vec![0.0; D::DIM], vec![0.0; D::DIM]);
    while sim.time() < until {
        let before = sim.particles().len();
        sim.pour_due_layers();
        let p = sim.particles();
        for i in before..p.len() {
            for (a, m) in inflow.iter_mut().enumerate() {
                *m += p.mass[i] as f64 * p.v[i][a] as f64;
            }
        }
        let mass: f64 = p.mass.iter().map(|&m| m as f64).sum();
        let dt = sim.step_at_most(f64::INFINITY).unwrap().dt;
        impulse[1] -= mass * g * dt;
    }
    let t = sim.time();
    let p = sim.particles();
    // the largest relative errors of the fall and the speed: of the layers inside the stream,
    // and of its two ends, the first layer and the last (whose momentum the grid shares with
    // the layer next to them, within a cell)
    let (mut inside, mut ends) = ([0.0f64; 2], [0.0f64; 2]);
    for i in 0..p.len() {
        let k = p.id[i] as u64 / n as u64;
        let tau = t - spout.exit_time(k);
        let fall = v0 * tau + 0.5 * g * tau * tau;
        let y = p.x[i][1] as f64;
        let v = -v0 - g * tau;
        let errors = [
            (y - (height - fall)).abs() / fall,
            (p.v[i][1] as f64 - v).abs() / v.abs(),
        ];
        let worst = if k == 0 || k + 1 == spout.layers() {
            &mut ends
        } else {
            &mut inside
        };
        for (w, e) in worst.iter_mut().zip(errors) {
            *w = w.max(e);
        }
        // the section does not move sideways
        let off = (0..D::DIM)
            .filter(|&a| a != 1)
            .map(|a| (p.x[i][a] as f64 - exit[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(off < exit[0], "{off}");
        assert!(p.v[i][0].abs() < 1e-3, "{:?}", p.v[i]);
    }
    eprintln!(
        "{}D: the largest error of the fall and the speed inside the stream {:.2} %, {:.2} %; at its ends {:.2} %, {:.2} %",
        D::DIM,
        100.0 * inside[0],
        100.0 * inside[1],
        100.0 * ends[0],
        100.0 * ends[1]
    );
    assert!(inside[0] < 0.03 && inside[1] < 0.03, "{inside:?}");
    assert!(ends[0] < 0.1 && ends[1] < 0.1, "{ends:?}");
    let d = sim.diagnostics();
    let expected = inflow[1] + impulse[1];
    assert!(
        (d.momentum[1] - expected).abs() <= 1e-4 * expected.abs(),
        "{}D: momentum {:?} against the inflow's {inflow:?} plus gravity's impulse {impulse:?}",
        D::DIM,
        d.momentum
    );
    assert!(
        d.momentum[0].abs() <= 1e-6 * expected.abs(),
        "{:?}",
        d.momentum
    );
    let mass = p.mass[0] as f64;
    let at_exit = p.len() as f64 * (0.5 * mass * v0 * v0 + mass * g * height);
    assert!(
        (d.energy_in - at_exit).abs() <= 1e-5 * at_exit,
        "{}D: energy brought in {} against {at_exit} at the exit",
        D::DIM,
        d.energy_in
    );
    // a stream in free fall loses nothing to speak of
    assert!(d.energy_error().abs() < 1e-3, "{d:?}");
}

#[test]
fn a_stream_clear_of_the_floor_falls_freely() {
    falls_freely::<D2>();
    falls_freely::<D3>();
}

/// A heap poured onto a rough floor, followed at every step: the account stays within
/// [`mpm::sim::ACCOUNT_TOLERANCE`] while the stream lands and at rest, the spout's energy is
/// booked (the energy brought in grows as the layers enter) and the landing dissipates it.
fn account_closes<D: Dim>(scene: SceneConfig, until: f64) {
    let mut sim = Simulation::<D>::new(scene).unwrap();
    let (mut worst, mut energy_in) = (0.0f64, 0.0);
    let mut grew = 0;
    while sim.time() < until {
        let d = sim.step().unwrap();
        worst = worst.max(d.energy_error().abs());
        if d.energy_in > energy_in {
            grew += 1;
        }
        energy_in = d.energy_in;
    }
    let d = sim.diagnostics();
    eprintln!(
        "{}D pour: {} particles, largest error {:.4} %, at the end {:+.4} % of {:.4} J in (plastic {:.4}, numerical {:.4}, integration {:+.4})",
        D::DIM,
        d.particles,
        100.0 * worst,
        100.0 * d.energy_error(),
        d.energy_in,
        d.dissipated_plastic,
        d.dissipated_numerical,
        d.dissipated_integration
    );
    assert!(grew > 20, "the energy brought in grew {grew} times");
    assert!(
        worst <= mpm::sim::ACCOUNT_TOLERANCE,
        "{}D: the account was {:.2} % off: {d:?}",
        D::DIM,
        100.0 * worst
    );
    assert!(d.dissipated_plastic > 0.1 * d.energy_in, "{d:?}");
    assert!(d.kinetic < 0.01 * d.energy_in, "at rest: {d:?}");
}

#[test]
fn the_energy_account_of_a_pour_closes_in_2d() {
    let text = include_str!("../scenes/pour_2d.json");
    let mut s = SceneConfig::from_json(text).unwrap();
    s.bodies[0].pour.as_mut().unwrap().duration = 1.5;
    account_closes::<D2>(s, 2.5);
}

#[test]
fn the_energy_account_of_a_pour_closes_in_3d() {
    let text = include_str!("../scenes/pour_3d.json");
    let mut s = SceneConfig::from_json(text).unwrap();
    s.cell_size = 0.04;
    s.max_dt = 0.002;
    let p = s.bodies[0].pour.as_mut().unwrap();
    (p.radius, p.duration) = (0.04, 1.0);
    account_closes::<D3>(s, 2.0);
}

/// Particle `i`'s id and position.
fn state<D: Dim>(sim: &Simulation<D>, i: usize) -> (u32, [f64; 3]) {
    let p = sim.particles();
    (
        p.id[i],
        std::array::from_fn(|a| if a < D::DIM { p.x[i][a] as f64 } else { 0.0 }),
    )
}

/// Body `b`'s particles (ids and positions) and how many of them sleep.
fn body_state<D: Dim>(sim: &Simulation<D>, b: usize) -> (Vec<(u32, [f64; 3])>, usize) {
    let body = &sim.bodies()[b];
    (
        body.range().map(|i| state(sim, i)).collect(),
        body.active().len(),
    )
}

/// Two sand blocks resting on the floor, one on either side of a spout that pours between
/// them, with sleeping on: the pour's body lies between the blocks' in the particle arrays.
/// Each time layers enter, the blocks' particles (ids, positions, order) are those before,
/// and every body's sleeping particles too, still the last of its range; the new particles
/// take the next ids, awake, just before the pour body's sleepers. The blocks, once asleep,
/// stay asleep (the stream never reaches them), and the heap falls partly asleep while the
/// spout still pours.
fn pouring_keeps_the_others<D: Dim>() {
    let (size, h): (Vec<f64>, f64) = if D::DIM == 2 {
        (vec![1.2, 0.6], 0.02)
    } else {
        (vec![1.2, 0.6, 0.6], 0.04)
    };
    let block = |x0: f64| {
        let (mut lo, mut hi) = (vec![0.2; D::DIM], vec![0.4; D::DIM]);
        (lo[0], hi[0], lo[1], hi[1]) = (x0, x0 + 0.12, 0.0, 0.08);
        BodyConfig::new("block", Shape::cuboid(&lo, &hi), sand())
    };
    let mut exit = vec![0.3; D::DIM];
    (exit[0], exit[1]) = (0.6, 0.4);
    // a layer every 1.2 s: the heap comes to rest, and partly sleeps, between layers (its
    // grains closing as they settle)
    let radius = h;
    let rate = if D::DIM == 2 { 0.0005 } else { 1.2e-4 } / 1.5;
    let poured = BodyConfig::poured("heap", pour(&exit, radius, rate, 12.0), sand());
    let s = scene(&size, h, vec![block(0.08), poured, block(1.0)]);
    let mut sim = Simulation::<D>::new(s).unwrap();
    assert!((spout(&sim, 1).exit_time(1) - 1.2).abs() < 1e-9);
    sim.sleep_when_at_rest();
    let (mut emissions, mut blocks_asleep, mut heap_asleep) = (0, 0, 0);
    let mut asleep_once = [false; 3];
    while sim.time() < 12.0 {
        sim.step_at_most(f64::INFINITY).unwrap();
        let before: Vec<_> = (0..3).map(|b| body_state(&sim, b)).collect();
        let ids = sim.ids_issued();
        let ranges: Vec<_> = sim.bodies().iter().map(|b| b.range()).collect();
        let added = sim.pour_due_layers();
        let after: Vec<_> = (0..3).map(|b| body_state(&sim, b)).collect();
        for b in [0, 2] {
            // a block once asleep stays asleep: the stream does not reach it
            let asleep = sim.bodies()[b].range().len() - sim.bodies()[b].active().len();
            if asleep_once[b] {
                assert_eq!(asleep, sim.bodies()[b].range().len(), "block {b} woke");
            }
            asleep_once[b] |= asleep == sim.bodies()[b].range().len();
        }
        if added == 0 {
            assert_eq!(before, after);
            continue;
        }
        emissions += 1;
        assert_eq!(before[0], after[0], "the first block moved");
        assert_eq!(before[2], after[2], "the last block moved");
        let r = sim.bodies()[2].range();
        assert_eq!(r, ranges[2].start + added..ranges[2].end + added);
        // the heap: its awake particles, the new ones, its sleepers as before
        let (old, old_active) = &before[1];
        let (new, new_active) = &after[1];
        assert_eq!(
            *new_active,
            old_active + added,
            "the new particles are awake"
        );
        assert_eq!(new[..*old_active], old[..*old_active]);
        assert_eq!(new[*new_active..], old[*old_active..], "the sleepers, last");
        let ids_new: Vec<u32> = new[*old_active..*new_active].iter().map(|p| p.0).collect();
        assert_eq!(ids_new, (ids..ids + added as u32).collect::<Vec<_>>());
        if asleep_once[0] && asleep_once[2] {
            blocks_asleep += 1;
        }
        if new.len() > *new_active {
            heap_asleep += 1;
        }
    }
    eprintln!(
        "{}D: {emissions} emissions, {blocks_asleep} with the blocks asleep, {heap_asleep} with some of the heap asleep",
        D::DIM
    );
    assert_eq!(emissions, spout(&sim, 1).layers());
    assert!(blocks_asleep >= 3, "{blocks_asleep}");
    assert!(heap_asleep >= 3, "{heap_asleep}");
}

#[test]
fn pouring_keeps_every_other_particle_and_the_sleepers() {
    pouring_keeps_the_others::<D2>();
    pouring_keeps_the_others::<D3>();
}

/// A poured body present with no particles yet: the step, the diagnostics, the measures and
/// every colour of the page cope; the page's box is not idle while the spout has layers
/// left, so its time runs and the heap grows.
#[test]
fn an_empty_poured_body_steps_and_the_page_pours() {
    for dim in [2, 3] {
        let s = stream_scene(dim, 0.5, 0.2);
        let mut sim = mpm::AnySimulation::new(s.clone()).unwrap();
        assert_eq!(sim.particle_count(), 0);
        assert!(sim.pouring());
        sim.step_at_most(1e-3).unwrap();
        assert_eq!(sim.particle_count(), 0, "step_at_most only steps");
        assert!(sim.diagnostics().total_energy() == 0.0);
        assert!(mpm::measure::deposits_any(&sim, &Default::default()).is_empty());
        let mut pg = mpm::playground::Playground::new(s).unwrap();
        for (_, mode) in mpm::playground::ColourMode::ALL {
            pg.update_colours(mode);
        }
        assert!(pg.measures().is_empty());
        pg.frame(0.1, 1e9, || 0.0).unwrap();
        assert!((pg.time() - 0.1).abs() < 1e-12, "{}", pg.time());
        assert!(pg.particle_count() > 0);
        for (_, mode) in mpm::playground::ColourMode::ALL {
            pg.update_colours(mode);
        }
        pg.frame(0.5, 1e9, || 0.0).unwrap();
        let m = pg.measures();
        assert_eq!(m.len(), 1);
        assert!(m[0].runout.is_none() && m[0].column.is_none(), "{m:?}");
        assert!(m[0].heap.height > 0.0);
        assert!(!pg.simulation().pouring());
    }
}

/// The page's measures say which deposit was poured: the heap from the spout, and neither the
/// sand box cut from a shape in the air beside it (a drop) nor the one standing on the floor;
/// none of them was held (nothing stood against their sides at the start).
#[test]
fn a_deposit_says_whether_its_body_was_poured() {
    for dim in [2, 3] {
        let (size, h): (Vec<f64>, f64) = if dim == 2 {
            (vec![1.2, 0.6], 0.02)
        } else {
            (vec![1.2, 0.6, 0.6], 0.04)
        };
        let cut = |name: &str, x0: f64, y0: f64| {
            let (mut lo, mut hi) = (vec![0.2; dim], vec![0.4; dim]);
            (lo[0], hi[0], lo[1], hi[1]) = (x0, x0 + 0.16, y0, y0 + 0.16);
            BodyConfig::new(name, Shape::cuboid(&lo, &hi), sand())
        };
        let mut exit = vec![0.3; dim];
        (exit[0], exit[1]) = (0.6, 0.4);
        let heap = BodyConfig::poured("heap", pour(&exit, h, 0.004, 1.0), sand());
        let s = scene(
            &size,
            h,
            vec![cut("dropped", 0.1, 0.25), heap, cut("standing", 0.95, 0.0)],
        );
        let mut pg = mpm::playground::Playground::new(s).unwrap();
        pg.measures(); // the footprints, as the page records them on the first frame
        pg.frame(0.4, 1e9, || 0.0).unwrap();
        let m = pg.measures();
        let flags: Vec<_> = m
            .iter()
            .map(|d| (d.name.as_str(), d.poured, d.held))
            .collect();
        assert_eq!(
            flags,
            [
                ("dropped", false, false),
                ("heap", true, false),
                ("standing", false, false)
            ],
            "{dim}D"
        );
    }
}

/// A rate that is not a number is refused like the others, naming the field and the range.
#[test]
fn a_rate_that_is_not_a_number_is_refused() {
    let mut s = stream_scene(2, 0.5, 1.0);
    s.bodies[0].pour.as_mut().unwrap().rate = f64::NAN;
    let e = Simulation::<D2>::new(s.clone()).unwrap_err().to_string();
    assert_eq!(
        e,
        "bodies[0].pour.rate = NaN: must be a finite number > 0 (m²/s per metre of depth)"
    );
    assert_eq!(s.validate().unwrap_err().to_string(), e);
}

/// A scene with a pour reads back as written: the poured body has no `shape` in the file,
/// and its `pour` keeps every figure.
#[test]
fn a_pour_scene_reads_back_as_written() {
    for text in [
        include_str!("../scenes/pour_2d.json"),
        include_str!("../scenes/pour_3d.json"),
    ] {
        let s = SceneConfig::from_json(text).unwrap();
        let json = serde_json::to_value(&s).unwrap();
        assert!(json["bodies"][0].get("shape").is_none(), "{json}");
        assert!(json["bodies"][0]["pour"]["rate"].as_f64().unwrap() > 0.0);
        let again = SceneConfig::from_json(&json.to_string()).unwrap();
        assert_eq!(again, s);
    }
}

/// A poured body with an `appear_at` is one to come until then, with none of its particles;
/// its spout opens as it enters (its first layer at that time, at the exit) and runs its
/// duration from there.
#[test]
fn a_pour_that_enters_later_opens_at_its_appear_at() {
    let mut s = stream_scene(2, 0.5, 0.1);
    s.bodies[0].appear_at = Some(0.2);
    let mut sim = Simulation::<D2>::new(s).unwrap();
    assert_eq!((sim.bodies().len(), sim.next_appearance()), (0, Some(0.2)));
    sim.advance_until(0.2 - 1e-3, |_| true).unwrap();
    assert_eq!((sim.bodies().len(), sim.particles().len()), (0, 0));
    sim.advance_until(0.2, |_| true).unwrap();
    let spout = spout(&sim, 0);
    assert_eq!(spout.exit_time(0), sim.time());
    let p = sim.particles();
    assert_eq!(p.len(), spout.per_layer(), "the first layer, at the exit");
    assert!(p.x.iter().all(|x| (x[1] as f64 - 0.5).abs() < 1e-6));
    sim.advance_until(0.2 + 0.1 - 1e-6, |_| true).unwrap();
    assert_eq!(sim.particles().len() as u64, spout.particles());
    assert!(!sim.pouring());
}

/// A pour stopped at a time t, in 2D and 3D: no layer enters after it whatever the steps
/// (stopped between layers, and at the instant a layer leaves, which it keeps); the
/// scene's duration becomes the one that pours the layers kept (a scene built with it pours
/// the same particles), close to t less the opening time; a spout that ended keeps its
/// duration; a time before a layer poured, or a body that is not poured, is an error.
fn stops_exactly<D: Dim>() {
    let mut s = stream_scene(D::DIM, 0.5, 2.0);
    s.bodies[0].appear_at = Some(0.05);
    let mut sim = Simulation::<D>::new(s.clone()).unwrap();
    sim.advance(0.2).unwrap();
    let sp = spout(&sim, 0);
    let (n, period) = (sp.per_layer(), sp.spacing() / sp.exit_speed());
    // between two layers: those left by now stay, no other comes
    let t = sim.time();
    let poured = sim.particles().len();
    assert_eq!(poured as u64, sp.poured() * n as u64);
    let d = sim.stop_pour(0, t).unwrap();
    assert!((d - (t - 0.05)).abs() <= 0.5 * period, "{d} for {t}");
    assert_eq!(sim.scene().bodies[0].pour.as_ref().unwrap().duration, d);
    assert!(!sim.pouring());
    sim.advance(0.3).unwrap();
    assert_eq!(
        sim.particles().len(),
        poured,
        "{}D: no layer after the stop",
        D::DIM
    );
    // the scene as it stands pours the same particles
    let mut again = Simulation::<D>::new(sim.scene().clone()).unwrap();
    again.advance(1.0).unwrap();
    assert_eq!(again.particles().len(), poured);
    assert_eq!(spout(&again, 0).layers(), sp.poured());

    // stopped at the instant a layer leaves: it is kept
    let mut sim = Simulation::<D>::new(s.clone()).unwrap();
    sim.advance(0.05 + 7.0 * period).unwrap();
    let t = sim.time();
    let d = sim.stop_pour(0, t).unwrap();
    sim.advance(0.2).unwrap();
    assert_eq!(sim.particles().len(), 8 * n, "{}D: layers 0 to 7", D::DIM);
    let mut again = Simulation::<D>::new(sim.scene().clone()).unwrap();
    again.advance(1.0).unwrap();
    assert_eq!(
        again.particles().len(),
        8 * n,
        "{}D: {d} s pours 8 layers",
        D::DIM
    );

    // a spout that ended keeps its duration; stopping it again changes nothing
    let mut short = s.clone();
    short.bodies[0].pour.as_mut().unwrap().duration = 0.1;
    let mut sim = Simulation::<D>::new(short).unwrap();
    sim.advance(0.5).unwrap();
    let all = sim.particles().len();
    assert_eq!(sim.stop_pour(0, sim.time()).unwrap(), 0.1);
    assert_eq!(sim.particles().len(), all);

    // errors: a time before a layer poured, a body that is not poured (or not present)
    let mut sim = Simulation::<D>::new(s.clone()).unwrap();
    sim.advance(0.3).unwrap();
    let e = sim.stop_pour(0, 0.1).unwrap_err().to_string();
    assert!(
        e.starts_with("t = 0.1: must be finite and at or after the last layer poured"),
        "{e}"
    );
    let e = sim.stop_pour(3, 0.3).unwrap_err().to_string();
    assert!(
        e.starts_with("body = 3: must be a poured body present"),
        "{e}"
    );
    assert!(sim.pouring(), "unchanged by the errors");
}

#[test]
fn a_pour_stopped_at_a_time_pours_no_layer_after_it() {
    stops_exactly::<D2>();
    stops_exactly::<D3>();
}

/// The shipped 2D pour (`scenes/pour_2d.json`, h = 1 cm) as the page runs it (sleeping on),
/// its sand given the material `model` (the scene's Drucker–Prager sand, or Mohr–Coulomb with
/// the same fields) at friction angle `phi`, until the spout has stopped and the heap rests:
/// (the mean of its two flanks, the angle of repose its deposit is judged against).
fn poured_heap(model: &str, phi: f64) -> (f64, f64) {
    use mpm::playground::Playground;
    let text = std::fs::read_to_string("scenes/pour_2d.json")
        .unwrap()
        .replace("drucker_prager", model);
    let mut pg = Playground::load(&text, &Default::default(), "balanced").unwrap();
    pg.set_parameter(&format!("{model}.friction_angle"), phi)
        .unwrap();
    pg.set_sleeping(true);
    let mut calm = 0.0;
    while pg.time() < 10.0 && calm < 0.3 {
        pg.frame(0.05, 1e9, || 0.0).unwrap();
        let still = pg.diagnostics().max_speed < 0.01 && !pg.simulation().pouring();
        calm = if still { calm + 0.05 } else { 0.0 };
    }
    assert!(
        calm >= 0.3,
        "the {model} heap at φ = {phi}° rests within 10 s"
    );
    let d = pg.measures();
    assert_eq!(d[0].model, model);
    let flank = |k: usize| d[0].heap.flanks[k].as_ref().expect("a flank").angle;
    let angle = (flank(0) + flank(1)) / 2.0;
    eprintln!(
        "{model} φ = {phi}°: flanks {:.1}° and {:.1}°, angle of repose {:.1}°",
        flank(0),
        flank(1),
        d[0].repose_angle
    );
    (angle, d[0].repose_angle)
}

/// The heaps of `model` poured at φ = 20° and 40° (each its mean flank and its angle of
/// repose), each asserted within [reference − 4°, reference + 1°].
fn poured_at_20_and_40(model: &str) -> [(f64, f64); 2] {
    let heaps = [20.0, 40.0].map(|phi| poured_heap(model, phi));
    for (angle, reference) in heaps {
        assert!(
            (reference - 4.0..=reference + 1.0).contains(&angle),
            "{model}: flanks {angle:.1}° against its angle of repose {reference:.1}°"
        );
    }
    heaps
}

/// The angle of repose as it is measured, by pouring: the heap poured in the page's 2D scene
/// stands at the angle of repose of its cone, φ_ps (sin φ_ps = 3 α_φ), the mean of its
/// flanks within [φ_ps − 4°, φ_ps + 1°] at φ = 20° and 40°, and raising φ from 20° to 40°
/// raises it by at least 14° (φ_ps rises by 17.5°).
#[test]
fn a_poured_heap_stands_at_the_plane_strain_angle_and_follows_phi() {
    let [(low, _), (high, _)] = poured_at_20_and_40("drucker_prager");
    assert!(high - low >= 14.0, "{low:.1}° → {high:.1}°");
}

/// Mohr–Coulomb sand without dilatancy poured the same way stands at Davis's angle
/// atan(sin φ), the slope on which its flowing layer stops (18.9° and 32.7° at φ = 20° and
/// 40°), not at φ: within [φ_d − 4°, φ_d + 1°], and raising φ from 20° to 40° raises the heap
/// as much as it raises φ_d (13.8°), within 2°.
#[test]
fn a_poured_mohr_coulomb_heap_stands_at_davis_s_angle() {
    let [(low, low_d), (high, high_d)] = poured_at_20_and_40("mohr_coulomb");
    let (rise, expect) = (high - low, high_d - low_d);
    assert!(
        (rise - expect).abs() <= 2.0,
        "{low:.1}° → {high:.1}°: a rise of {rise:.1}° against {expect:.1}°"
    );
}

/// The volume poured, Σ m/ρ, against what the particles fill, Σ V_p, once a 2D heap poured
/// from `scenes/pour_2d.json` rests (5 s): a falling stream stretches its particles about
/// tenfold, and where they land only a compression closes them again
/// ([`mpm::recipe::Recipe::closing`], on for a poured body): then the heap fills at most 1.3
/// times the volume poured; with its grains left loose, more than 1.8 times.
#[test]
fn a_poured_heap_regains_its_density_where_its_grains_close() {
    let ratio = |close: bool| {
        let mut scene = SceneConfig::load(std::path::Path::new("scenes/pour_2d.json")).unwrap();
        scene.bodies[0].close_grains = Some(close);
        let rho = scene.bodies[0].material.density();
        let mut sim = Simulation::<D2>::new(scene).unwrap();
        sim.advance_until(5.0, |_| true).unwrap();
        let p = sim.particles();
        let poured: f64 = p.mass.iter().map(|&m| m as f64 / rho).sum();
        let filled: f64 = p.volume.iter().map(|&v| v as f64).sum();
        filled / poured
    };
    let (closed, loose) = (ratio(true), ratio(false));
    eprintln!("Σ V_p / Σ m/ρ: {closed:.2} closing, {loose:.2} loose");
    assert!(closed <= 1.3, "{closed:.2}");
    assert!(loose > 1.8, "{loose:.2}");
}
