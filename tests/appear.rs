//! Bodies that enter later (`appear_at`): each enters exactly at its time, in its shape with its
//! velocity; a step never passes that time; errors name the body by its place in the file.

mod common;

use common::{body, cut, elastic, sand};
use mpm::{AnySimulation, BodyConfig, D2, D3, Dim, SceneConfig, Shape, Simulation};

fn scene<D: Dim>() -> SceneConfig {
    let mut s = SceneConfig::new(D::DIM, &cut::<D>([1.0, 1.0, 0.5]), 0.05);
    s.boundary.friction = 0.5;
    s.bodies.push(body(
        "sand",
        [0.1, 0.0, 0.1],
        [0.4, 0.2, 0.4],
        sand(30.0),
        D::DIM,
    ));
    s
}

/// A ball falling at 1 m/s that enters at `t`.
fn late_ball<D: Dim>(t: f64) -> BodyConfig {
    BodyConfig::new(
        "ball",
        Shape::ball(&cut::<D>([0.7, 0.6, 0.25]), 0.12),
        elastic(1e5, 0.3, 1000.0),
    )
    .with_velocity(&cut::<D>([0.0, -1.0, 0.0]))
    .appearing_at(t)
}

fn enters_at_its_time<D: Dim>() {
    let mut s = scene::<D>();
    s.bodies.push(late_ball::<D>(0.1));
    // Alone, the ball would hold this many particles, centred here.
    let mut alone = Simulation::<D>::new(SceneConfig {
        bodies: vec![late_ball::<D>(0.0)],
        ..s.clone()
    })
    .unwrap();
    let (n_ball, centre) = {
        let b = &alone.bodies()[0];
        (b.range().len(), b.stats().center_of_mass)
    };
    alone.clear();

    let mut sim = Simulation::<D>::new(s).unwrap();
    let n0 = sim.particles().len();
    assert_eq!((sim.bodies().len(), sim.scene().bodies.len()), (1, 2));
    assert_eq!(sim.next_appearance(), Some(0.1));
    sim.advance(0.0999).unwrap();
    assert_eq!(sim.particles().len(), n0, "not before its time");
    // Steps of the adaptive size: one of them ends exactly at 0.1 s, and the ball enters.
    while sim.bodies().len() < 2 {
        sim.step().unwrap();
        assert!(
            sim.time() <= 0.1 + 1e-12,
            "a step passed the time: {}",
            sim.time()
        );
    }
    assert!((sim.time() - 0.1).abs() < 1e-12, "{}", sim.time());
    assert_eq!(sim.particles().len(), n0 + n_ball);
    assert_eq!(sim.next_appearance(), None);
    let stats = sim.bodies()[1].stats().clone();
    for a in 0..D::DIM {
        assert!(
            (stats.center_of_mass[a] - centre[a]).abs() < 1e-6,
            "{stats:?}"
        );
    }
    assert!(
        (stats.momentum[1] + stats.mass).abs() < 1e-4 * stats.mass,
        "{stats:?}"
    );
    // Then it falls freely: y = y0 − v t − g t²/2.
    sim.advance(0.05).unwrap();
    let y = sim.bodies()[1].stats().center_of_mass[1];
    let want = centre[1] - 0.05 - 0.5 * 9.81 * 0.05f64.powi(2);
    assert!((y - want).abs() < 1e-3, "y {y}, want {want}");
}

#[test]
fn a_body_enters_at_its_time_2d() {
    enters_at_its_time::<D2>();
}

#[test]
fn a_body_enters_at_its_time_3d() {
    enters_at_its_time::<D3>();
}

/// Bodies listed in any order enter in order of time; those of the start keep the file's
/// order; advance lands every one on its time.
#[test]
fn bodies_enter_in_order_of_time() {
    let mut s = scene::<D2>();
    let mut b = |name: &str, x: f64, t: Option<f64>| {
        let mut body = BodyConfig::new(
            name,
            Shape::cuboid(&[x, 0.5], &[x + 0.1, 0.6]),
            elastic(1e5, 0.3, 1000.0),
        );
        body.appear_at = t;
        s.bodies.push(body);
    };
    b("c", 0.5, Some(0.03));
    b("a", 0.65, Some(0.0));
    b("b", 0.8, Some(0.01));
    let mut sim = AnySimulation::new(s.clone()).unwrap();
    let names: Vec<String> = sim.scene().bodies.iter().map(|b| b.name.clone()).collect();
    assert_eq!(names, ["sand", "a", "b", "c"]);
    assert_eq!(sim.bodies_present(), 2);
    let mut entered = Vec::new();
    while sim.time() < 0.05 - 1e-12 {
        let before = sim.bodies_present();
        sim.step().unwrap();
        if sim.bodies_present() > before {
            entered.push((sim.time(), sim.scene().bodies[before].name.clone()));
        }
    }
    assert_eq!(entered.len(), 2, "{entered:?}");
    assert!((entered[0].0 - 0.01).abs() < 1e-12 && entered[0].1 == "b");
    assert!((entered[1].0 - 0.03).abs() < 1e-12 && entered[1].1 == "c");
    // advance lands every body on the way and finishes at its end
    let mut sim = AnySimulation::new(s).unwrap();
    sim.advance(0.05).unwrap();
    assert_eq!(sim.bodies_present(), 4);
    assert!((sim.time() - 0.05).abs() < 1e-12);
}

/// The bodies to come take parameter changes like those present; their shapes and times
/// are fixed; one may be removed before it enters; Clear forgets them.
#[test]
fn bodies_to_come_take_parameters_and_can_be_removed() {
    let mut s = scene::<D2>();
    s.bodies.push(late_ball::<D2>(0.2));
    s.bodies.push(late_ball::<D2>(0.3));
    let mut sim = Simulation::<D2>::new(s).unwrap();
    sim.configure(|s| {
        s.bodies[1].material = elastic(2e5, 0.3, 1000.0);
    })
    .unwrap();
    assert_eq!(sim.scene().bodies[1].material, elastic(2e5, 0.3, 1000.0));
    let e = sim
        .configure(|s| s.bodies[2].appear_at = Some(0.25))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("bodies[2] = a new shape, sampling, initial velocity or time of appearance"),
        "{e}"
    );
    sim.remove_body(2).unwrap();
    assert_eq!(sim.scene().bodies.len(), 2);
    sim.advance(0.25).unwrap();
    assert_eq!(sim.bodies().len(), 2);
    let c = elastic(2e5, 0.3, 1000.0).wave_speed();
    assert!(
        (sim.bodies()[1].wave_speed() / c - 1.0).abs() < 1e-3,
        "the ball entered with the material set while it was to come"
    );
    sim.advance(0.1).unwrap();
    assert_eq!(sim.bodies().len(), 2, "the removed body never enters");
    let mut again = Simulation::<D2>::new({
        let mut s = scene::<D2>();
        s.bodies.push(late_ball::<D2>(0.2));
        s
    })
    .unwrap();
    again.clear();
    assert_eq!(again.next_appearance(), None);
    again.advance(0.3).unwrap();
    assert_eq!(again.particles().len(), 0);
}

/// The builder's bodies are checked like a scene file's: a time that is not a finite number
/// ≥ 0 is an error naming the body's place in the list.
#[test]
fn bad_times_are_errors_naming_the_field() {
    for (t, shown) in [(f64::NAN, "NaN"), (f64::INFINITY, "inf"), (-1.0, "-1")] {
        let e = Simulation::<D2>::builder(&[1.0, 1.0], 0.05)
            .body(body("a", [0.1, 0.0, 0.0], [0.3, 0.2, 0.0], sand(30.0), 2))
            .body(late_ball::<D2>(t))
            .build()
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!("bodies[1].appear_at = {shown}: must be a finite number >= 0 (s)")
        );
    }
}
