//! Pouring sand from a spout held still over the floor, as the angle of repose is measured
//! (ISO 4324, ASTM C1444: sand poured from a funnel at a fixed height): a front end starts a
//! pour where the user presses on the floor ([`Playground::start_pour`]) and stops it when the
//! user lets go ([`Playground::stop_pour`]). The pour is a poured body of the scene
//! (`bodies[].pour`, [`crate::sim::pour`]), recorded in the session with how long it ran, so
//! that a link, a replay and a saved scene file pour the same stream.
//!
//! **The spout** ([`Playground::pour_spout`], the one rule): its exit is a disc (3D; a
//! segment in 2D) of radius [`POUR_RADIUS_CELLS`] cells, centred over the point pressed (moved
//! in so that the stream keeps a cell from the walls), [`POUR_HEIGHT`] above the floor, or
//! [`POUR_HEIGHT_SHARE`] of the box's height where that is lower, and at least
//! [`POUR_CLEARANCE_CELLS`] cells above whatever lies under the exit when the pour starts; it
//! stays there while it pours, as a funnel held at a fixed height does.
//!
//! **The rate** is the volume poured per second Q (m³/s; in 2D m²/s per metre of depth), from
//! [`POUR_SPEEDS`]: the exit speeds it may leave the spout's exit at, times the exit's area
//! (π r², in 2D 2r).

use super::{Playground, drops::PouredBody};
use crate::config::{BodyConfig, MAX_PARTICLES, MAX_POUR_DURATION, PourConfig};
use crate::error::{Error, Result};
use crate::params::{MODELS, model_index};
use serde::Serialize;

/// The spout's radius (its half-width in 2D), in cells of the scene as sampled: the stream is
/// four cells across, resolved on the grid (the shipped pour scenes' spouts are two cells in
/// radius too).
pub const POUR_RADIUS_CELLS: f64 = 2.0;

/// The height of the spout's exit above the floor (m): high enough for the stream to be seen
/// falling and for the heap to grow beneath it, low enough that the sand lands at under 3 m/s.
pub const POUR_HEIGHT: f64 = 0.4;

/// The share of the box's height the spout's exit is held at, where that is below
/// [`POUR_HEIGHT`] (a low box).
pub const POUR_HEIGHT_SHARE: f64 = 0.5;

/// How many cells at least the exit stands above whatever lies under it when the pour starts.
pub const POUR_CLEARANCE_CELLS: f64 = 3.0;

/// The share of the box's volume (area in 2D) a pour not stopped pours before it ends by
/// itself.
pub const POUR_FILL_SHARE: f64 = 0.5;

/// Exit speeds (m/s) of the rates a pour takes: `allowed` those accepted, `offered` the range
/// a slider offers (a trickle to four times the default), `default` a slow pour.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PourSpeeds {
    pub allowed: [f64; 2],
    pub offered: [f64; 2],
    pub default: f64,
}

/// The exit speeds of [`PourSpeeds`]: 0.3 m/s by default (a funnel's stream), from 0.05 to
/// 1.2 m/s offered, from 0.01 to 3 m/s accepted.
pub const POUR_SPEEDS: PourSpeeds = PourSpeeds {
    allowed: [0.01, 3.0],
    offered: [0.05, 1.2],
    default: 0.3,
};

/// What a pour is in this scene, for a front end's rate control: the spout's radius and
/// height, the exit's area and the rates (the exit speeds of [`POUR_SPEEDS`] times the area,
/// three significant figures).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PourRates {
    /// `m³/s`, or in 2D `m²/s` (per metre of depth).
    pub unit: &'static str,
    /// The exit's radius, its half-width in 2D (m).
    pub radius: f64,
    /// The exit's height above the floor, over a bare floor (m).
    pub height: f64,
    /// The exit's area π r² (m²; in 2D its width 2r, m).
    pub exit_area: f64,
    /// What [`Playground::start_pour`] accepts, a range worth a slider, and a default.
    pub allowed: [f64; 2],
    pub offered: [f64; 2],
    pub default: f64,
    /// The exit speeds they leave at (m/s).
    pub speeds: PourSpeeds,
}

/// A number to three significant figures.
fn tidy(x: f64) -> f64 {
    format!("{x:.2e}").parse().unwrap_or(x)
}

impl Playground {
    /// The rates a pour may have in this scene, and the spout they leave.
    pub fn pour_rates(&self) -> PourRates {
        let dim = self.dim();
        let r = POUR_RADIUS_CELLS * self.scene().cell_size;
        let exit_area = if dim == 3 {
            std::f64::consts::PI * r * r
        } else {
            2.0 * r
        };
        let s = POUR_SPEEDS;
        PourRates {
            unit: if dim == 3 { "m³/s" } else { "m²/s" },
            radius: r,
            height: self.pour_height(),
            exit_area,
            allowed: s.allowed.map(|v| tidy(v * exit_area)),
            offered: s.offered.map(|v| tidy(v * exit_area)),
            default: tidy(s.default * exit_area),
            speeds: s,
        }
    }

    /// Checks a pour's rate (m³/s; m²/s in 2D).
    pub fn check_rate(&self, rate: f64) -> Result<()> {
        let r = self.pour_rates();
        let [lo, hi] = r.allowed;
        if rate.is_finite() && rate >= lo && rate <= hi {
            return Ok(());
        }
        let [v0, v1] = r.speeds.allowed;
        Err(Error::invalid(
            "rate",
            rate,
            format!(
                "must be in [{lo}, {hi}] ({}): exit speeds of {v0} to {v1} m/s through the spout's exit of {} {}",
                r.unit,
                tidy(r.exit_area),
                if self.dim() == 3 { "m²" } else { "m" },
            ),
        ))
    }

    /// The index in [`MODELS`] of `material`, a granular model (what a pour takes).
    fn pour_model(&self, material: &str) -> Result<usize> {
        let m = model_index(material)?;
        if self.presets.materials[m].behaviour().friction().is_none() {
            let granular: Vec<&str> = (0..MODELS.len())
                .filter(|&k| self.presets.materials[k].behaviour().friction().is_some())
                .map(|k| MODELS[k].id)
                .collect();
            return Err(Error::invalid(
                "material",
                material,
                format!(
                    "must be a granular model to pour: {} (a solid would pour as one stretched body)",
                    granular.join(" or ")
                ),
            ));
        }
        Ok(m)
    }

    /// The height of the spout's exit above a bare floor (m): [`POUR_HEIGHT`], or
    /// [`POUR_HEIGHT_SHARE`] of the box's height where that is lower.
    pub fn pour_height(&self) -> f64 {
        POUR_HEIGHT.min(POUR_HEIGHT_SHARE * self.scene().domain.size[1])
    }

    /// Where a pour over floor point `point` (3D: its x and z count; 2D: its x) puts the
    /// centre of the spout's exit: over the point, moved in so that the stream's section keeps
    /// a cell from the walls; at [`Self::pour_height`] above the floor, raised to stand
    /// [`POUR_CLEARANCE_CELLS`] cells above whatever lies under the exit (within its radius and
    /// a cell); never within a cell of the ceiling. The one rule of the spout's place.
    pub fn pour_spout(&self, point: &[f64]) -> Vec<f64> {
        let (dim, h) = (self.dim(), self.scene().cell_size);
        let size = &self.scene().domain.size;
        let r = POUR_RADIUS_CELLS * h;
        let across = |a: usize| point[a].clamp(h + r, (size[a] - h - r).max(h + r));
        let x = across(0);
        let z = if dim == 3 { across(2) } else { 0.0 };
        let surface = self.surface_height(x, z, r + h);
        let y = self
            .pour_height()
            .max(surface + POUR_CLEARANCE_CELLS * h)
            .min(size[1] - h);
        if dim == 3 { vec![x, y, z] } else { vec![x, y] }
    }

    /// The poured body of a pour record: the preset `material`, from `spout` (moved in to keep
    /// the stream a cell from the walls), at `rate`, for the record's `duration`, or with
    /// `open` until it has poured [`POUR_FILL_SHARE`] of the box (or the most particles the
    /// simulation holds, or [`MAX_POUR_DURATION`]); sampled at the quality level's particles
    /// per cell, jittered as the shipped pour scenes are.
    fn pour_body(&self, pour: &PouredBody, open: bool) -> Result<BodyConfig> {
        let m = self.pour_model(&pour.material)?;
        self.check_rate(pour.rate)?;
        let dim = self.dim();
        crate::geometry::check_vector("spout", &pour.spout, dim, "m")?;
        let (h, size) = (self.scene().cell_size, &self.scene().domain.size);
        let radius = POUR_RADIUS_CELLS * h;
        let spout: Vec<f64> = (0..dim)
            .map(|a| {
                let reach = if a == 1 { 0.0 } else { radius };
                let (lo, hi) = (h + reach, size[a] - h - reach);
                pour.spout[a].clamp(lo, hi.max(lo))
            })
            .collect();
        let ppc = self.resolution.particles_per_cell;
        let duration = if open {
            let volume: f64 = size.iter().product();
            let spacing = h / ppc as f64;
            let room = MAX_PARTICLES.saturating_sub(self.particle_count()) as f64;
            let particles_per_second = pour.rate / spacing.powi(dim as i32);
            (POUR_FILL_SHARE * volume / pour.rate)
                .min(0.5 * room / particles_per_second)
                .min(MAX_POUR_DURATION)
        } else {
            pour.duration
        };
        let config = PourConfig {
            spout,
            radius,
            rate: pour.rate,
            duration,
        };
        let mut body = BodyConfig::poured("pour", config, self.presets.materials[m].clone())
            .with_particles_per_cell(ppc)
            .with_jitter(0.25, 1);
        body.flip = self.presets.flip[m];
        Ok(body)
    }

    /// Starts pouring the preset sand `material` (`drucker_prager` or `mohr_coulomb`; a solid
    /// is refused) at `rate` (m³/s; m²/s in 2D; [`Self::pour_rates`]) over `point` on the floor
    /// (3D: its x and z count; 2D: its x), from the spout [`Self::pour_spout`] puts there, until
    /// [`Self::stop_pour`] (or until it has poured [`POUR_FILL_SHARE`] of the box). A pour
    /// running is stopped first: one runs at a time. Recorded in the session, its figures
    /// rounded as [`PouredBody::rounded`] says. Returns the poured body's index.
    pub fn start_pour(&mut self, point: &[f64], material: &str, rate: f64) -> Result<usize> {
        let dim = self.dim();
        crate::geometry::check_vector("point", point, dim, "m")?;
        let size = self.scene().domain.size.clone();
        let over = |a: usize| point[a] >= 0.0 && point[a] <= size[a];
        if !(over(0) && (dim == 2 || over(2))) {
            let z = if dim == 3 {
                format!(", z in [0, {}]", size[2])
            } else {
                String::new()
            };
            return Err(Error::invalid(
                "point",
                format!("{point:?}"),
                format!("must be over the floor: x in [0, {}]{z} (m)", size[0]),
            ));
        }
        self.pour_model(material)?;
        self.check_rate(rate)?;
        self.stop_pour();
        let spout = self.pour_spout(point);
        let clock = self.drop_clock();
        let record = PouredBody::rounded(clock, material, rate, &spout, 0.0);
        let body = self.pour_body(&record, true)?;
        let i = self.add_now(body, record.t)?;
        self.drops.record_pour(record, clock, i);
        Ok(i)
    }

    /// Stops the pour running now, exactly: no layer leaves its spout after the current time
    /// ([`crate::Simulation::stop_pour`]), and the session records how long it ran (about the
    /// time since it started: the duration that pours the layers it poured). Returns that
    /// duration (s); nothing when no pour runs.
    pub fn stop_pour(&mut self) -> Option<f64> {
        let run = self.drops.running.take()?;
        let d = self.sim.stop_pour(run.body, self.sim.time()).ok()?;
        self.drops.pours[run.record].duration = d;
        Some(d)
    }

    /// Whether a pour started by [`Self::start_pour`] runs (until [`Self::stop_pour`], a Clear,
    /// a Reset or another start).
    pub fn pouring(&self) -> bool {
        self.drops.running.is_some()
    }

    /// The pours of the session, the one running with the duration that pours what it has
    /// poured so far.
    pub(super) fn session_pours(&self) -> Vec<PouredBody> {
        let mut pours = self.drops.pours.clone();
        if let Some(run) = self.drops.running
            && let Some((_, d)) = self.sim.pour_held(run.body, self.sim.time())
        {
            pours[run.record].duration = d;
        }
        pours
    }

    /// The body of a pour to come (a link's), for its time.
    pub(super) fn scheduled_pour_body(&self, pour: &PouredBody) -> Result<BodyConfig> {
        self.pour_body(pour, false)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Quality, Replay};
    use super::*;
    use crate::config::SceneConfig;
    use crate::material::Material;
    use crate::sim::{AnySimulation, Spout};
    use crate::{Dim, Shape, Simulation};
    use std::collections::HashMap;

    /// A clock that never runs out: the frames step all they are asked.
    fn clock() -> impl FnMut() -> f64 {
        || 0.0
    }

    fn live() -> &'static Quality {
        Quality::find("live").unwrap()
    }

    /// The empty sandbox at the live level (it keeps its 2.5 cm cells and 2 particles per cell).
    fn sandbox(dim: usize) -> Playground {
        Playground::with_quality(Playground::sandbox_scene(dim), live()).unwrap()
    }

    /// The floor point in the middle of the box.
    fn middle(dim: usize) -> Vec<f64> {
        [1.0, 0.0, 0.5][..dim].to_vec()
    }

    fn spout_of(sim: &AnySimulation, i: usize) -> Spout {
        match sim {
            AnySimulation::D2(s) => s.bodies()[i].spout().unwrap().clone(),
            AnySimulation::D3(s) => s.bodies()[i].spout().unwrap().clone(),
        }
    }

    /// Body `i`'s particles and the volume they were poured as, Σ m / ρ (m³; m² in 2D).
    fn poured(sim: &AnySimulation, i: usize) -> (usize, f64) {
        fn of<D: Dim>(s: &Simulation<D>, i: usize) -> (usize, f64) {
            let range = s.bodies()[i].range();
            let rho = s.scene().bodies[i].material.density();
            let mass: f64 = s.particles().mass[range.clone()]
                .iter()
                .map(|&m| m as f64)
                .sum();
            (range.len(), mass / rho)
        }
        match sim {
            AnySimulation::D2(s) => of(s, i),
            AnySimulation::D3(s) => of(s, i),
        }
    }

    /// Steps until the drop clock reaches `t` (s).
    fn run_to(pg: &mut Playground, t: f64) {
        while pg.drop_clock() < t - 1e-9 {
            let left = t - pg.drop_clock();
            pg.frame(left.min(0.05), 1e9, clock()).unwrap();
        }
    }

    /// Held for a second, in 2D and 3D: the volume poured is rate × the time held within one
    /// layer, and nothing more comes after the release; the spout stands where the rule puts
    /// it over a bare floor, with its radius in cells; the session records the pour (rounded as
    /// a link writes it) with the time it ran.
    #[test]
    fn a_pour_held_for_a_second_pours_rate_times_the_time_held() {
        for dim in [2, 3] {
            let mut pg = sandbox(dim);
            let rates = pg.pour_rates();
            let (h, q) = (pg.scene().cell_size, rates.default);
            assert_eq!(rates.radius, 2.0 * h);
            assert_eq!(rates.height, 0.4);
            pg.frame(0.1, 1e9, clock()).unwrap();
            assert_eq!(pg.time(), 0.0, "an empty box: time stands still");
            let i = pg.start_pour(&middle(dim), "drucker_prager", q).unwrap();
            assert!(pg.pouring());
            let pour = pg.scene().bodies[i].pour.clone().unwrap();
            let mut want = vec![1.0, 0.4, 0.5];
            want.truncate(dim);
            assert_eq!((pour.spout, pour.radius, pour.rate), (want, 2.0 * h, q));
            run_to(&mut pg, 1.0);
            let spout = spout_of(pg.simulation(), i);
            let layer = spout.per_layer() as f64 * spout.spacing().powi(dim as i32);
            let period = spout.spacing() / spout.exit_speed();
            let (n, volume) = poured(pg.simulation(), i);
            assert!(
                n > 0 && (volume - q * 1.0).abs() <= layer * 1.001,
                "{dim}D: {volume} vs {q}"
            );
            let held = pg.stop_pour().unwrap();
            assert!(!pg.pouring());
            assert!((held - 1.0).abs() <= period, "{dim}D: held {held}");
            assert!((volume - q * held).abs() <= layer * 1.001, "{dim}D");
            run_to(&mut pg, 1.5);
            assert_eq!(
                poured(pg.simulation(), i).0,
                n,
                "{dim}D: nothing after the release"
            );
            let s = pg.session();
            assert_eq!(s.pours.len(), 1);
            let p = &s.pours[0];
            assert_eq!(
                (p.t, p.material.as_str(), p.rate, p.duration),
                (0.0, "drucker_prager", q, held)
            );
            assert_eq!(p.spout, pg.scene().bodies[i].pour.as_ref().unwrap().spout);
            assert_eq!(pg.scene().bodies[i].pour.as_ref().unwrap().duration, held);
            assert_eq!(
                pg.stop_pour(),
                None,
                "stopping with none running does nothing"
            );
            assert_eq!(pg.session(), s);
        }
    }

    /// A pour runs across frames, and the frames the page's budget cuts short lose none of its
    /// layers: at every frame the layers in are those whose exit time the simulation reached.
    #[test]
    fn a_pour_keeps_its_layers_across_frames_cut_short() {
        for dim in [2, 3] {
            let mut pg = sandbox(dim);
            let q = pg.pour_rates().default;
            let i = pg.start_pour(&middle(dim), "mohr_coulomb", q).unwrap();
            // a wall clock of 1 ms a reading and a budget of 4 ms: a few steps a frame
            let mut ms = 0.0;
            let mut behind = 0;
            for frame in 0..300 {
                let budget = if frame % 3 == 0 { 0.0 } else { 4.0 };
                let r = pg
                    .frame(1.0 / 30.0, budget, || {
                        ms += 1.0;
                        ms
                    })
                    .unwrap();
                behind += usize::from(r.fell_behind);
                let spout = spout_of(pg.simulation(), i);
                let due = (0..spout.layers())
                    .take_while(|&k| spout.exit_time(k) <= pg.time() + 1e-9)
                    .count();
                assert_eq!(spout.poured() as usize, due, "{dim}D, frame {frame}");
                assert_eq!(poured(pg.simulation(), i).0, due * spout.per_layer());
            }
            assert!(
                behind > 200,
                "{dim}D: the budget cut the frames short ({behind})"
            );
            assert!(pg.time() > 0.1, "{dim}D: {}", pg.time());
            assert!(pg.pouring());
        }
    }

    /// A session with a pour replays it: a fresh playground given the session pours the same
    /// particles at the same time, and records the same pour; the link's figures are rounded
    /// (0.1 ms, three significant figures of the rate, 1 mm).
    #[test]
    fn a_session_replays_its_pour() {
        for dim in [2, 3] {
            let mut pg = sandbox(dim);
            pg.drop_at("box", "elastic", &[0.4, 0.5, 0.5][..dim], 0.0, 0.2)
                .unwrap();
            run_to(&mut pg, 0.123_456);
            let q = 1.234_567 * pg.pour_rates().default;
            let i = pg
                .start_pour(&[1.401_49, 0.9, 0.333_3][..dim], "drucker_prager", q)
                .unwrap();
            run_to(&mut pg, 0.7);
            pg.stop_pour().unwrap();
            run_to(&mut pg, 1.0);
            let live = poured(pg.simulation(), i);
            let session = pg.session();
            let p = &session.pours[0];
            assert_eq!(p.t, 0.1234);
            assert_eq!(p.rate, format!("{q:.2e}").parse::<f64>().unwrap());
            assert_eq!(&p.spout[..1], &[1.401]);

            let mut again = sandbox(dim);
            let (rejected, refused) = again.replay(session.clone());
            assert!(rejected.is_empty() && refused.is_empty());
            run_to(&mut again, 1.0);
            assert_eq!(again.body_count(), 2);
            assert_eq!(
                again.scene().bodies[i],
                pg.scene().bodies[i],
                "{dim}D: the same body"
            );
            assert_eq!(
                poured(again.simulation(), i),
                live,
                "{dim}D: the same particles"
            );
            let replayed = again.session();
            assert_eq!(replayed.pours.len(), 1);
            let (a, b) = (&replayed.pours[0], &session.pours[0]);
            assert!((a.applied_at.unwrap() - b.t).abs() < 1e-9, "{a:?}");
            assert_eq!(
                (a.t, a.rate, a.duration, &a.spout),
                (b.t, b.rate, b.duration, &b.spout)
            );
            assert!(
                !again.pouring(),
                "a replayed pour is not one the user holds"
            );
            // the session crosses as JSON (the page's link and its replay)
            let json = serde_json::to_string(&session).unwrap();
            let back: Replay = serde_json::from_str(&json).unwrap();
            assert_eq!(back.pours, session.pours);
        }
    }

    /// The saved scene gives the pour as a poured body entering at its start with the time it
    /// ran, and the simulation built from the file (what `mpm run` runs) pours the same
    /// particles, the same volume; a pour still running is saved with the time it has run so
    /// far, which pours what it has poured.
    #[test]
    fn a_saved_scene_pours_what_the_session_poured() {
        for dim in [2, 3] {
            let mut pg = sandbox(dim);
            run_to(&mut pg, 0.0);
            pg.drop_at("ball", "drucker_prager", &[0.5, 0.5, 0.5][..dim], 0.0, 0.2)
                .unwrap();
            run_to(&mut pg, 0.2);
            let q = pg.pour_rates().default;
            let i = pg.start_pour(&middle(dim), "drucker_prager", q).unwrap();
            run_to(&mut pg, 0.8);
            let held = pg.stop_pour().unwrap();
            // a second pour, still running when the file is saved
            let j = pg
                .start_pour(&[1.6, 0.0, 0.6][..dim], "mohr_coulomb", 2.0 * q)
                .unwrap();
            run_to(&mut pg, 1.1);
            assert!(pg.pouring());
            let saved = pg.saved_scene_json().unwrap();
            let scene = SceneConfig::from_json(&saved).unwrap();
            let b = &scene.bodies[i];
            assert_eq!(
                (b.appear_at, b.pour.as_ref().unwrap().duration),
                (Some(0.2), held)
            );
            let running = scene.bodies[j].pour.as_ref().unwrap().duration;
            assert!(
                (running - 0.3).abs() < 0.02,
                "{dim}D: saved with the time run so far: {running}"
            );
            assert!(pg.pouring(), "saving stops nothing");
            let (live_i, live_j) = (poured(pg.simulation(), i), poured(pg.simulation(), j));
            let mut sim = AnySimulation::new(scene).unwrap();
            sim.advance(1.6).unwrap();
            let (file_i, file_j) = (poured(&sim, i), poured(&sim, j));
            assert_eq!(file_i.0, live_i.0, "{dim}D: the same particles");
            assert!(
                (file_i.1 - live_i.1).abs() <= 1e-9 * live_i.1,
                "{dim}D: the same volume"
            );
            assert_eq!(
                file_j.0, live_j.0,
                "{dim}D: what the running pour poured so far"
            );
            assert!((file_j.1 - live_j.1).abs() <= 1e-9 * live_j.1);
            assert!((file_i.1 - q * held).abs() <= 0.05 * q * held);
        }
    }

    /// Bad figures are refused, each naming its field and what is allowed, the state unchanged:
    /// a rate outside the range, a point off the floor or of the wrong dimension, a solid or an
    /// unknown material. Drucker–Prager and Mohr–Coulomb pour.
    #[test]
    fn bad_pours_name_the_field() {
        for dim in [2, 3] {
            let mut pg = sandbox(dim);
            let r = pg.pour_rates();
            let p = middle(dim);
            let unit = if dim == 3 { "m³/s" } else { "m²/s" };
            for rate in [0.0, -1.0, f64::NAN, 2.0 * r.allowed[1], 0.5 * r.allowed[0]] {
                let e = pg
                    .start_pour(&p, "drucker_prager", rate)
                    .unwrap_err()
                    .to_string();
                let want = format!(
                    "rate = {rate}: must be in [{}, {}] ({unit}): exit speeds of 0.01 to 3 m/s",
                    r.allowed[0], r.allowed[1]
                );
                assert!(e.starts_with(&want), "{dim}D: {e}");
            }
            let off = [2.5, 0.0, 0.5];
            let e = pg
                .start_pour(&off[..dim], "drucker_prager", r.default)
                .unwrap_err()
                .to_string();
            let z = if dim == 3 { ", z in [0, 1]" } else { "" };
            assert!(
                e.ends_with(&format!("must be over the floor: x in [0, 2]{z} (m)")),
                "{e}"
            );
            assert!(e.starts_with("point = [2.5"), "{e}");
            let e = pg
                .start_pour(&[1.0], "drucker_prager", r.default)
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with(&format!("point = [1.0]: must have {dim} components")),
                "{e}"
            );
            let e = pg
                .start_pour(&p, "elastic", r.default)
                .unwrap_err()
                .to_string();
            assert_eq!(
                e,
                "material = elastic: must be a granular model to pour: drucker_prager or mohr_coulomb (a solid would pour as one stretched body)"
            );
            let e = pg
                .start_pour(&p, "von_mises", r.default)
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("material = von_mises: must be a granular model"),
                "{e}"
            );
            let e = pg
                .start_pour(&p, "sugar", r.default)
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("material = sugar: must be one of"), "{e}");
            assert!(!pg.pouring() && pg.body_count() == 0 && pg.session().pours.is_empty());
            assert!(pg.check_rate(r.default).is_ok() && pg.check_rate(r.offered[1]).is_ok());
            for material in ["drucker_prager", "mohr_coulomb"] {
                let i = pg.start_pour(&p, material, r.default).unwrap();
                assert_eq!(pg.scene().bodies[i].material.kind(), material);
            }
        }
    }

    /// One pour runs at a time: a second start stops the first (its time recorded); Clear and
    /// Reset end the pour running and forget the pours; a Clear's empty box stands still.
    #[test]
    fn one_pour_at_a_time_and_clear_removes_it() {
        for dim in [2, 3] {
            let mut pg = sandbox(dim);
            let q = pg.pour_rates().default;
            let first = pg.start_pour(&middle(dim), "drucker_prager", q).unwrap();
            run_to(&mut pg, 0.2);
            let second = pg
                .start_pour(&[0.5, 0.0, 0.5][..dim], "drucker_prager", q)
                .unwrap();
            run_to(&mut pg, 0.4);
            let s = pg.session();
            assert_eq!(s.pours.len(), 2);
            assert!((s.pours[0].duration - 0.2).abs() < 0.05, "{:?}", s.pours[0]);
            assert!(
                (s.pours[1].duration - 0.2).abs() < 0.05,
                "running: {:?}",
                s.pours[1]
            );
            let n = poured(pg.simulation(), first).0;
            run_to(&mut pg, 0.5);
            assert_eq!(poured(pg.simulation(), first).0, n, "the first stopped");
            assert!(poured(pg.simulation(), second).0 > 0);
            pg.clear();
            assert!(!pg.pouring() && pg.particle_count() == 0 && pg.body_count() == 0);
            assert!(pg.session().pours.is_empty() && pg.session().cleared);
            let t = pg.time();
            pg.frame(0.1, 1e9, clock()).unwrap();
            assert_eq!(pg.time(), t, "nothing pours into the cleared box");
            assert_eq!(pg.stop_pour(), None);
            pg.start_pour(&middle(dim), "drucker_prager", q).unwrap();
            run_to(&mut pg, 0.1);
            pg.reset().unwrap();
            assert!(!pg.pouring() && pg.body_count() == 0 && pg.session().pours.is_empty());
        }
    }

    /// The spout's place: over a bare floor at the fixed height; over sand, at least three
    /// cells above it; near a wall, moved in so that its stream keeps a cell from the wall; in
    /// a low box, at half its height.
    #[test]
    fn the_spout_stands_over_the_point_at_its_height() {
        for dim in [2, 3] {
            let mut scene = Playground::sandbox_scene(dim);
            let (lo, hi) = ([0.8, 0.0, 0.3], [1.2, 0.5, 0.7]);
            scene.bodies.push(BodyConfig::new(
                "sand",
                Shape::cuboid(&lo[..dim], &hi[..dim]),
                Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0),
            ));
            let pg = Playground::new(scene).unwrap();
            let h = pg.scene().cell_size;
            let top = pg.surface_height(1.0, 0.5, 3.0 * h);
            assert!(top > 0.49, "{top}");
            let over = pg.pour_spout(&middle(dim));
            assert!(
                (over[1] - (top + 3.0 * h)).abs() < 1e-9,
                "{dim}D: {over:?} over {top}"
            );
            let bare = pg.pour_spout(&[1.8, 0.0, 0.5][..dim]);
            assert_eq!(bare[1], 0.4);
            let wall = pg.pour_spout(&[0.0, 0.0, 1.0][..dim]);
            assert!((wall[0] - 3.0 * h).abs() < 1e-12, "{wall:?}");
            if dim == 3 {
                assert!((wall[2] - (1.0 - 3.0 * h)).abs() < 1e-12, "{wall:?}");
            }
            let mut low = Playground::sandbox_scene(dim);
            low.domain.size[1] = 0.5;
            let low = Playground::new(low).unwrap();
            assert_eq!(low.pour_spout(&middle(dim))[1], 0.25);
        }
    }

    /// A pour takes the quality level's cells and particles per cell, as a dropped body does:
    /// on the column collapse, 4 per cell per axis in 2 cm cells at Live, 2 in 1 cm cells as
    /// written; its radius is two of the level's cells.
    #[test]
    fn a_pour_takes_the_quality_level() {
        let text = include_str!("../../scenes/column_collapse_2d.json");
        let none = HashMap::new();
        for (level, h, ppc) in [("live", 0.02, 4), ("fine", 0.01, 2)] {
            let mut pg = Playground::load(text, &none, level).unwrap();
            assert_eq!(pg.quality().particles_per_cell, ppc);
            let q = pg.pour_rates().default;
            let i = pg.start_pour(&[1.0, 0.0], "drucker_prager", q).unwrap();
            let b = &pg.scene().bodies[i];
            assert_eq!(b.particles_per_cell, ppc, "{level}");
            assert!(
                (b.pour.as_ref().unwrap().radius - 2.0 * h).abs() < 1e-12,
                "{level}"
            );
            let saved = pg.saved_scene().unwrap();
            let again = Playground::with_quality(saved, Quality::find(level).unwrap()).unwrap();
            assert_eq!(again.scene().cell_size, pg.scene().cell_size);
            assert_eq!(
                again.scene().bodies[i].particles_per_cell,
                ppc,
                "{level}: saved and opened"
            );
        }
    }
}
