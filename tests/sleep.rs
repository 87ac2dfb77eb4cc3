//! Sleeping (src/step/sleep.rs): material at rest stops being stepped until something touches
//! it, and the answers stay those of the awake run: a settled sand ball falls asleep, a dropped
//! bunny wakes it and both end as they would awake, the energy budget closes, and a change
//! that weakens the sand wakes it.

// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

use mpm::material::DruckerPragerParams;
use mpm::step::sleep::SleepRule;
use mpm::{BodyConfig, D2, Material, SceneConfig, Simulation};
use std::path::Path;

fn scene(file: &str) -> SceneConfig {
    SceneConfig::load(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(file),
    )
    .expect("shipped scene")
}

/// The shipped 2D sand ball (φ = 35°), settled awake for 1.5 s without its bunny, and the
/// bunny's config (it appears 0.15 m above the ball's top).
fn settled_ball() -> (Simulation<D2>, BodyConfig) {
    let mut s = scene("bunny_on_sand_ball_2d.json");
    let bunny = s.bodies.pop().expect("the bunny");
    let mut sim = Simulation::<D2>::new(s).expect("scene");
    sim.advance(1.5).expect("settle");
    (sim, bunny)
}

/// What a drop is judged by.
#[derive(Debug)]
struct Outcome {
    /// The sand's highest particle (m).
    sand_top: f64,
    /// The sand's extent (m).
    sand_width: f64,
    /// The bunny's lowest centre of mass (m): the crater it makes.
    bunny_low: f64,
    /// How far its centre of mass rose again after that (m).
    bunny_rebound: f64,
    /// Its centre of mass at the end (m).
    bunny_final: f64,
}

/// Drops `bunny` on `sim` and runs for `t` seconds; `asleep` is called every 0.1 s.
fn drop_bunny(
    sim: &mut Simulation<D2>,
    bunny: BodyConfig,
    t: f64,
    mut asleep: impl FnMut(usize),
) -> Outcome {
    let b = sim.add_body(bunny).expect("bunny");
    let (mut low, mut rebound) = (f64::INFINITY, 0.0f64);
    let end = sim.time() + t;
    let mut k = 0;
    while sim.time() < end {
        sim.advance(0.005).expect("step");
        let y = sim.bodies()[b].stats().center_of_mass[1];
        if y < low {
            (low, rebound) = (y, 0.0);
        }
        rebound = rebound.max(y - low);
        k += 1;
        if k % 20 == 0 {
            asleep(sim.asleep());
        }
    }
    let p = sim.particles();
    let r = sim.bodies()[0].range();
    let xs = || r.clone().map(|i| p.x[i][0] as f64);
    Outcome {
        sand_top: r.clone().map(|i| p.x[i][1] as f64).fold(0.0, f64::max),
        sand_width: xs().fold(0.0, f64::max) - xs().fold(f64::INFINITY, f64::min),
        bunny_low: low,
        bunny_rebound: rebound,
        bunny_final: sim.bodies()[b].stats().center_of_mass[1],
    }
}

fn within(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * b.abs(),
        "{what}: {a:.5} asleep against {b:.5} awake (more than {:.0} % apart)",
        rel * 100.0
    );
}

/// Sleeping on with a rule that never lets anything sleep steps exactly as sleeping off: the
/// passes walk the same particles, and the sleeping share adds nothing.
#[test]
fn sleeping_that_never_triggers_changes_nothing() {
    let s = scene("bunny_on_sand_ball_2d.json");
    let mut off = Simulation::<D2>::new(s).expect("scene");
    let mut on = off.clone();
    on.set_sleeping(Some(SleepRule {
        speed: 0.0,
        after: f64::INFINITY,
        wake_speed: 0.0,
    }));
    off.advance(0.3).unwrap();
    on.advance(0.3).unwrap();
    assert_eq!(on.asleep(), 0);
    assert_eq!(off.steps(), on.steps());
    let (a, b) = (off.particles(), on.particles());
    assert!(a.x == b.x && a.v == b.v && a.stress == b.stress);
}

/// A settled sand ball falls asleep (and, wholly asleep, steps at more than twice the awake
/// step), keeps its energy (what the sleepers lost is the kinetic
/// energy of their last mm/s, booked as dissipated), and a bunny dropped on it wakes it; the
/// crater, the heap's height and width and the bunny's rebound end within 2 % of the awake
/// run's, and the ball falls asleep again once everything rests.
#[test]
fn a_dropped_bunny_wakes_the_settled_ball_and_both_end_as_awake() {
    let (mut awake, bunny) = settled_ball();
    let mut sleeping = awake.clone();
    sleeping.sleep_when_at_rest();
    let n = sleeping.particles().len();
    let budget = |s: &Simulation<D2>| s.diagnostics().total_energy() + s.diagnostics().dissipated();
    let before = budget(&sleeping);
    awake.advance(1.0).unwrap();
    sleeping.advance(1.0).unwrap();
    assert!(
        sleeping.asleep() > 95 * n / 100,
        "{} of {n} particles asleep a second after the ball settled",
        sleeping.asleep()
    );
    // wholly asleep, the sand's waves no longer bound the step
    assert!(awake.stable_dt() < 0.5 * sleeping.stable_dt());
    let e = sleeping.diagnostics();
    let drift = budget(&sleeping) - before;
    // the transfers' loss and the stress update's integration error are booked from the
    // grid's awake share only: the sleeping material's share of a node moves with no step
    assert!(
        drift.abs() < 1e-3 * e.elastic.max(e.kinetic).max(1e-9),
        "the energy budget moved by {drift:.3e} J while the ball slept (elastic {:.3e} J)",
        e.elastic
    );
    assert!(e.dissipated_sleep > 0.0 && e.dissipated_sleep < 1e-3 * e.elastic);
    let mut counts = Vec::new();
    let a = drop_bunny(&mut awake, bunny.clone(), 2.5, |_| ());
    let s = drop_bunny(&mut sleeping, bunny, 2.5, |k| counts.push(k));
    eprintln!("awake {a:?}\nasleep {s:?}\nasleep every 0.1 s: {counts:?}");
    assert!(
        counts.iter().any(|&k| k < n / 10),
        "the drop woke almost nothing: {counts:?}"
    );
    assert!(
        *counts.last().unwrap() > n * 9 / 10,
        "the ball did not fall asleep again: {counts:?}"
    );
    within(s.sand_top, a.sand_top, 0.02, "sand's height");
    within(s.sand_width, a.sand_width, 0.02, "sand's width");
    within(
        s.bunny_low,
        a.bunny_low,
        0.02,
        "crater (bunny's lowest centre of mass)",
    );
    within(s.bunny_rebound, a.bunny_rebound, 0.02, "bunny's rebound");
    within(s.bunny_final, a.bunny_final, 0.02, "bunny's final height");
    let budget_awake = budget(&awake);
    within(budget(&sleeping), budget_awake, 0.02, "energy budget");
}

/// A sleeping ball wakes on a lower friction angle and slumps as the awake ball does; editing
/// the particles wakes it too.
#[test]
fn weakening_the_sand_wakes_it_and_it_slumps_as_awake() {
    let (mut awake, _) = settled_ball();
    let mut sleeping = awake.clone();
    sleeping.sleep_when_at_rest();
    sleeping.advance(1.0).unwrap();
    awake.advance(1.0).unwrap();
    assert!(sleeping.asleep() > 0);
    let weaken = |s: &mut mpm::SceneConfig| {
        if let Material::DruckerPrager(m) = &mut s.bodies[0].material {
            m.friction_angle = 10.0;
        }
    };
    sleeping.configure(weaken).unwrap();
    assert_eq!(sleeping.asleep(), 0, "a weaker sand must wake");
    awake.configure(weaken).unwrap();
    let top = |s: &Simulation<D2>| {
        let p = s.particles();
        s.bodies()[0]
            .range()
            .map(|i| p.x[i][1] as f64)
            .fold(0.0, f64::max)
    };
    let t0 = top(&awake);
    awake.advance(1.0).unwrap();
    sleeping.advance(1.0).unwrap();
    assert!(
        top(&awake) < t0 - 0.01,
        "the 10° sand did not slump: top {t0:.3} → {:.3}",
        top(&awake)
    );
    within(top(&sleeping), top(&awake), 0.02, "slumped sand's height");
    // an edit of the particles wakes what sleeps
    sleeping.advance(1.5).unwrap();
    assert!(sleeping.asleep() > 0);
    let _ = sleeping.particles_mut();
    assert_eq!(sleeping.asleep(), 0);
}

/// The shipped 2D scenes, as their files set them up, end as they would awake with sleeping
/// on: after 2.5 s every body's centre of mass and bounding box within 2 % of the domain's
/// height of the awake run's.
#[test]
fn the_shipped_2d_scenes_end_as_awake_with_sleeping_on() {
    for file in [
        "bunny_on_sand_ball_2d.json",
        "column_collapse_2d.json",
        "elastic_bunny_2d.json",
        "notched_sand_block_2d.json",
        "plastic_bunny_2d.json",
    ] {
        let s = scene(file);
        let tolerance = 0.02 * s.domain.size[1];
        let mut awake = Simulation::<D2>::new(s).expect("scene");
        let mut sleeping = awake.clone();
        sleeping.sleep_when_at_rest();
        let mut most = 0;
        while awake.time() < 2.5 {
            awake.advance(0.1).unwrap();
            sleeping.advance(0.1).unwrap();
            most = most.max(sleeping.asleep());
        }
        eprintln!(
            "{file}: at most {most} of {} asleep",
            sleeping.particles().len()
        );
        for (a, s) in awake.bodies().iter().zip(sleeping.bodies()) {
            let (a, s) = (a.stats(), s.stats());
            for (what, x, y) in [
                ("centre of mass", &a.center_of_mass, &s.center_of_mass),
                ("lowest corner", &a.bbox_min, &s.bbox_min),
                ("highest corner", &a.bbox_max, &s.bbox_max),
            ] {
                for k in 0..2 {
                    assert!(
                        (x[k] - y[k]).abs() < tolerance,
                        "{file}: {what}[{k}] {:.4} asleep, {:.4} awake",
                        y[k],
                        x[k]
                    );
                }
            }
        }
    }
}

/// Two sand balls settled and asleep: a slider that makes one stronger or stiffer leaves both
/// asleep; one that lowers its friction angle wakes that ball only, and it slumps.
#[test]
fn a_weaker_sand_wakes_only_its_own_body() {
    let mut s = scene("bunny_on_sand_ball_2d.json");
    let sand = s.bodies.swap_remove(0);
    s.bodies.clear();
    for (i, x) in [0.25, 0.75].into_iter().enumerate() {
        let mut b = sand.clone();
        b.name = format!("ball {i}");
        b.shape = mpm::Shape::Ball {
            center: vec![x, 0.1],
            radius: 0.1,
        };
        s.bodies.push(b);
    }
    let Material::DruckerPrager(dp) = &sand.material else {
        panic!("the ball is Drucker-Prager sand")
    };
    let mut sim = Simulation::<D2>::new(s).expect("scene");
    sim.sleep_when_at_rest();
    sim.advance(2.5).unwrap();
    let asleep = |s: &Simulation<D2>| {
        s.bodies()
            .iter()
            .map(|b| b.range().len() - b.active().len())
            .collect::<Vec<_>>()
    };
    let before = asleep(&sim);
    assert!(
        before
            .iter()
            .zip(sim.bodies())
            .all(|(&a, b)| a > b.range().len() / 4),
        "the balls did not fall asleep: {before:?}"
    );
    let flip = sim.scene().bodies[1].flip;
    let mut m = *dp;
    for (what, change) in [
        (
            "a higher friction angle",
            &(|m: &mut DruckerPragerParams| m.friction_angle = 40.0)
                as &dyn Fn(&mut DruckerPragerParams),
        ),
        ("cohesion", &|m| m.cohesion = 100.0),
        ("a stiffer sand", &|m| m.youngs_modulus *= 2.0),
    ] {
        change(&mut m);
        sim.set_materials(vec![(1, Material::DruckerPrager(m), flip)])
            .unwrap();
        assert_eq!(asleep(&sim), before, "{what} woke sand");
    }
    let top = |s: &Simulation<D2>, i: usize| {
        let p = s.particles();
        s.bodies()[i]
            .range()
            .map(|q| p.x[q][1] as f64)
            .fold(0.0, f64::max)
    };
    let t0 = top(&sim, 1);
    (m.friction_angle, m.cohesion) = (10.0, 0.0);
    sim.set_materials(vec![(1, Material::DruckerPrager(m), flip)])
        .unwrap();
    let after = asleep(&sim);
    assert_eq!(after[0], before[0], "the other ball woke");
    assert_eq!(after[1], 0, "the weakened ball stayed asleep");
    sim.advance(1.0).unwrap();
    assert!(
        top(&sim, 1) < t0 - 0.01,
        "the 10° ball did not slump: top {t0:.3} → {:.3}",
        top(&sim, 1)
    );
}
