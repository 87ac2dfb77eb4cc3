//! A session saved as a scene file: what a front end's "Save scene" writes and the CLI runs
//! unchanged. Each body dropped or poured during the session becomes a body of the file that
//! enters at its time (`appear_at`), a pour with how long it ran (`pour.duration`), so running
//! the file replays the demo.

use super::Playground;
use crate::config::SceneConfig;
use crate::error::Result;

impl Playground {
    /// The session as a scene, at the resolution of the scene as written (whatever the quality
    /// level it is sampled at: opened at a level, the file samples as the session did): the
    /// world with every parameter as set now; the scene's bodies
    /// (none after a Clear) and each body dropped since, with its materials as set now and its
    /// drop time as `appear_at`, counted from the start of the scene or from the Clear; each
    /// pour, a poured body entering at its start with its duration (the pour running, with the
    /// time it has run so far); the drops and pours of a replay still to come, as the bodies
    /// they will be. A parameter changed during
    /// the session holds its last value from the start in the file. Meshes and outlines keep
    /// their paths, relative to the scene file ([`SceneConfig::asset_paths`] lists the files
    /// that must lie beside it; a dropped bunny is `bunny.obj` in 3D, `bunny2d.txt` in 2D).
    pub fn saved_scene(&self) -> Result<SceneConfig> {
        let mut scene = self.sim.scene().clone();
        // the pour running: as far as it has poured
        if let Some(run) = self.drops.running
            && let Some((_, d)) = self.sim.pour_held(run.body, self.sim.time())
            && let Some(pour) = scene.bodies[run.body].pour.as_mut()
        {
            pour.duration = d;
        }
        for d in &self.drops.list[self.drops.next..] {
            let mut body =
                self.object_body(&d.object, &d.material, &d.centre, &d.velocity, d.size)?;
            body.appear_at = (d.t > 0.0).then_some(d.t);
            scene.bodies.push(body);
        }
        for p in &self.drops.pours[self.drops.next_pour..] {
            let mut body = self.scheduled_pour_body(p)?;
            body.appear_at = (p.t > 0.0).then_some(p.t);
            scene.bodies.push(body);
        }
        self.as_written(&mut scene);
        // The order of appearance (a stable sort: the bodies of the start keep theirs).
        scene
            .bodies
            .sort_by(|a, b| a.appear_time().total_cmp(&b.appear_time()));
        scene.validate()?;
        Ok(scene)
    }

    /// [`Self::saved_scene`] as the JSON of a scene file.
    pub fn saved_scene_json(&self) -> Result<String> {
        let scene = self.saved_scene()?;
        Ok(serde_json::to_string_pretty(&scene).expect("a scene serialises") + "\n")
    }
}

#[cfg(test)]
mod tests {
    use super::super::BunnyAssets;
    use super::*;
    use crate::Shape;
    use crate::config::BodyConfig;
    use crate::material::Material;
    use crate::sim::AnySimulation;
    use std::collections::HashMap;

    fn read(path: &str) -> String {
        std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
    }

    fn clock() -> impl FnMut() -> f64 {
        || 0.0
    }

    /// A sand block, then a session: a parameter, an elastic bunny dropped at about 0.02 s
    /// (at once in the box emptied by a Clear, where time stands still), a von Mises ball about
    /// 0.03 s later, and a box that a replay schedules for later still. Returns the drop times.
    fn session(dim: usize, cleared: bool) -> (Playground, Vec<f64>) {
        let mut scene = Playground::sandbox_scene(dim);
        let (lo, hi) = ([0.2, 0.0, 0.3], [0.6, 0.3, 0.7]);
        scene.bodies.push(BodyConfig::new(
            "sand",
            Shape::cuboid(&lo[..dim], &hi[..dim]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0),
        ));
        let mut pg = Playground::new(scene).unwrap();
        pg.set_bunny(
            BunnyAssets::parse(
                Some(&read("scenes/bunny.obj")),
                Some(&read("scenes/bunny2d.txt")),
            )
            .unwrap(),
        );
        pg.frame(0.03, 1e9, clock()).unwrap();
        if cleared {
            pg.clear();
        }
        pg.set_parameter("drucker_prager.friction_angle", 25.0)
            .unwrap();
        pg.frame(0.02, 1e9, clock()).unwrap();
        let point = [0.4, 0.5, 0.5];
        pg.drop_at("bunny", "elastic", &point[..dim], 1.0, 0.2)
            .unwrap();
        pg.frame(0.03, 1e9, clock()).unwrap();
        pg.set_parameter("von_mises.yield_stress", 2000.0).unwrap();
        let point = [1.4, 0.5, 0.5];
        pg.drop_at("ball", "von_mises", &point[..dim], 0.0, 0.2)
            .unwrap();
        pg.frame(0.01, 1e9, clock()).unwrap();
        let mut times: Vec<f64> = pg.session().drops.iter().map(|d| d.t).collect();
        // A replay's drop still to come (a link opened, then saved at once).
        let mut d = pg.session().drops[0].clone();
        (d.t, d.object, d.centre[0]) = (pg.drop_clock() + 0.02, "box".into(), 1.0);
        times.push(d.t);
        let later = crate::playground::Replay {
            drops: vec![d],
            ..Default::default()
        };
        let (rejected, refused) = pg.replay(later);
        assert!(rejected.is_empty() && refused.is_empty());
        (pg, times)
    }

    /// The saved file, loaded as the CLI loads it (parse, the files beside it, validate), puts
    /// the same bodies in at the same times, where they were dropped, with the parameters as
    /// set.
    #[test]
    fn a_saved_session_replays_as_a_scene_file() {
        for dim in [2, 3] {
            for cleared in [false, true] {
                let (pg, drop_times) = session(dim, cleared);
                let text = pg.saved_scene_json().unwrap();
                let mut scene = SceneConfig::from_json(&text).unwrap();
                let files = scene.asset_paths();
                assert_eq!(files, [if dim == 3 { "bunny.obj" } else { "bunny2d.txt" }]);
                scene
                    .resolve_assets(|p| Ok(read(&format!("scenes/{p}"))))
                    .unwrap();
                scene.validate().unwrap();
                let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
                let want: &[&str] = if cleared {
                    &["bunny", "ball", "box"]
                } else {
                    &["sand", "bunny", "ball", "box"]
                };
                assert_eq!(names, want, "cleared: {cleared}");
                let first = usize::from(!cleared);
                let times: Vec<f64> = scene.bodies[first..]
                    .iter()
                    .map(|b| b.appear_time())
                    .collect();
                assert_eq!(times, drop_times, "the drop clock's times");
                if cleared {
                    assert_eq!(times[0], 0.0, "dropped into the emptied box at once");
                } else {
                    assert!(times[0] >= 0.0499 && times[0] < 0.051, "{times:?}");
                }
                assert!(times[1] > times[0] + 0.029, "{times:?}");
                for b in &scene.bodies {
                    match &b.material {
                        Material::DruckerPrager(p) => assert_eq!(p.friction_angle, 25.0),
                        Material::VonMises(p) => assert_eq!(p.yield_stress, 2000.0),
                        _ => {}
                    }
                }

                let mut sim = AnySimulation::new(scene.clone()).unwrap();
                let live = pg.scene().bodies.clone();
                let live_stats = pg.simulation().body_stats();
                for (k, &t) in times.iter().enumerate() {
                    let i = first + k;
                    if t > 0.0 {
                        sim.advance_until(t - 1e-4, |_| true).unwrap();
                        assert_eq!(sim.bodies_present(), i, "before {t}");
                    }
                    sim.advance_until(t, |_| true).unwrap();
                    assert_eq!(sim.bodies_present(), i + 1, "at {t}");
                    assert!((sim.time() - t).abs() < 1e-12);
                    let entered = sim.scene().bodies[i].clone();
                    let stats = &sim.body_stats()[i];
                    if k < 2 {
                        assert_eq!(entered, live[i], "the dropped body");
                        assert_eq!(stats.particles, live_stats[i].particles);
                    }
                    // In its shape, not yet moved.
                    let b = entered.shape.bounds(dim);
                    let h = scene.cell_size;
                    for a in 0..dim {
                        assert!(stats.bbox_min[a] >= b.min[a] - 1e-6, "{stats:?} {b:?}");
                        assert!(stats.bbox_max[a] <= b.max[a] + 1e-6, "{stats:?} {b:?}");
                        assert!(stats.bbox_max[a] >= b.max[a] - h, "{stats:?} {b:?}");
                    }
                }
            }
        }
    }

    /// The live playground and one opened from the saved file agree: the same bodies and
    /// particle counts once every body is in.
    #[test]
    fn a_saved_scene_opens_in_a_playground() {
        let (mut live, _) = session(2, false);
        let text = live.saved_scene_json().unwrap();
        let assets = HashMap::from([("bunny2d.txt".to_string(), read("scenes/bunny2d.txt"))]);
        let mut again = Playground::from_json_with_assets(&text, &assets).unwrap();
        assert_eq!(again.body_count(), 4);
        assert_eq!(again.simulation().bodies_present(), 1);
        while again.simulation().bodies_present() < 4 {
            let r = again.frame(0.01, 1e9, clock()).unwrap();
            assert!(r.substeps > 0, "{r:?}");
        }
        while live.body_count() < 4 {
            live.frame(0.01, 1e9, clock()).unwrap();
        }
        assert_eq!(again.particle_count(), live.particle_count());
        assert_eq!(again.scene().bodies, live.scene().bodies);
    }

    /// A scene whose every body comes later runs in a playground: the box is not idle.
    #[test]
    fn a_scene_of_bodies_to_come_runs() {
        let mut scene = Playground::sandbox_scene(2);
        scene.bodies.push(
            BodyConfig::new(
                "late",
                Shape::cuboid(&[0.2, 0.0], &[0.4, 0.2]),
                Material::elastic(1e5, 0.3, 1000.0),
            )
            .appearing_at(0.05),
        );
        let mut pg = Playground::new(scene).unwrap();
        assert_eq!((pg.particle_count(), pg.body_count()), (0, 1));
        pg.frame(0.04, 1e9, clock()).unwrap();
        assert_eq!(pg.particle_count(), 0);
        assert!((pg.time() - 0.04).abs() < 1e-12, "time runs: {}", pg.time());
        pg.frame(0.02, 1e9, clock()).unwrap();
        assert!(pg.particle_count() > 0);
        assert_eq!(pg.saved_scene().unwrap().bodies[0].appear_at, Some(0.05));
    }
}
