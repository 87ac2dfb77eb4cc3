//! `mpm play`: the scene in the terminal, drawn with braille dots (orthographic in 2D, an
//! orbiting projection in 3D), with keys to pause, step, reset and nudge the parameters.
//! Every change goes through `Simulation::configure`, which validates it like a scene file;
//! a rejected value leaves the simulation as it was and its message is shown.

use crate::cli::{Failure, PlayArgs, build, load_scene};
use mpm::{AnySimulation, Material, SceneConfig};
use ratatui::Frame;
use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind, KeyModifiers};
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Style, Stylize};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CanvasLine, Points};
use ratatui::widgets::{Block, Paragraph, Wrap};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

pub fn play(a: PlayArgs) -> Result<(), Failure> {
    mpm::error::check_range("--speed", a.speed, 1e-4, 100.0, false, "")?;
    let scene = load_scene(&a.scene)?;
    let sim = build(scene.clone(), &a.scene.scene)?;
    if !std::io::stdout().is_terminal() || !std::io::stdin().is_terminal() {
        return Err(Failure(
            "play needs an interactive terminal (use `mpm run` to write frames instead)".into(),
        ));
    }
    let mut app = App::new(scene, sim, a.speed);
    let mut terminal =
        ratatui::try_init().map_err(|e| Failure(format!("cannot set up the terminal: {e}")))?;
    let result = (|| -> std::io::Result<()> {
        let frame_time = Duration::from_millis(33);
        while !app.quit {
            let start = Instant::now();
            terminal.draw(|f| app.draw(f))?;
            app.tick(frame_time);
            let rest = frame_time.saturating_sub(start.elapsed());
            if event::poll(rest.max(Duration::from_millis(1)))?
                && let Event::Key(k) = event::read()?
                && k.kind != KeyEventKind::Release
            {
                app.key(k.code, k.modifiers.contains(KeyModifiers::SHIFT));
            }
        }
        Ok(())
    })();
    ratatui::restore();
    result.map_err(|e| Failure(format!("terminal: {e}")))
}

/// What the colours show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Colouring {
    Body,
    PlasticStrain,
    Speed,
}

pub struct App {
    /// The scene as loaded (for a full reset).
    original: SceneConfig,
    sim: AnySimulation,
    paused: bool,
    quit: bool,
    /// Simulated seconds per real second wanted.
    speed: f64,
    /// The body whose material the keys change.
    selected: usize,
    azimuth: f64,
    elevation: f64,
    colouring: Colouring,
    status: (String, bool),
    /// Achieved simulated/real time ratio over the latest frame.
    achieved: f64,
}

const BODY_COLOURS: [Color; 6] = [
    Color::LightRed,
    Color::LightBlue,
    Color::LightGreen,
    Color::LightYellow,
    Color::LightMagenta,
    Color::LightCyan,
];
const RAMP: [Color; 5] = [
    Color::Blue,
    Color::Cyan,
    Color::Green,
    Color::Yellow,
    Color::Red,
];

impl App {
    pub fn new(original: SceneConfig, sim: AnySimulation, speed: f64) -> Self {
        App {
            original,
            sim,
            paused: false,
            quit: false,
            speed,
            selected: 0,
            azimuth: 30.0,
            elevation: 20.0,
            colouring: Colouring::Body,
            status: (
                "space pause · s step · r reset · q quit · h help".into(),
                false,
            ),
            achieved: 0.0,
        }
    }

    /// Advances the simulation for one frame of `frame` real time (within that wall budget).
    pub fn tick(&mut self, frame: Duration) {
        if self.paused || self.sim.failure().is_some() {
            self.achieved = 0.0;
            return;
        }
        let start = Instant::now();
        let t0 = self.sim.time();
        let target = t0 + self.speed * frame.as_secs_f64();
        while self.sim.time() < target - 1e-12 && start.elapsed() < frame {
            if let Err(e) = self.sim.step_at_most(target - self.sim.time()) {
                self.status = (format!("stopped: {e} (r to reset)"), true);
                break;
            }
        }
        self.achieved = (self.sim.time() - t0) / frame.as_secs_f64();
    }

    fn step_once(&mut self) {
        if let Err(e) = self.sim.step() {
            self.status = (format!("stopped: {e} (r to reset)"), true);
        }
    }

    /// Applies `f` to the scene through the validated `configure`; reports the outcome.
    fn nudge(&mut self, what: &str, f: impl FnOnce(&mut SceneConfig)) {
        match self.sim.configure(f) {
            Ok(()) => self.status = (format!("{what} changed"), false),
            Err(e) => self.status = (format!("rejected: {e}"), true),
        }
    }

    /// Handles a key; `shift` raises instead of lowering.
    pub fn key(&mut self, code: KeyCode, shift: bool) {
        let b = self.selected;
        let up = shift;
        let factor = if up { 1.25 } else { 0.8 };
        match code {
            KeyCode::Char('q') | KeyCode::Esc => self.quit = true,
            KeyCode::Char(' ') | KeyCode::Char('p') => {
                self.paused = !self.paused;
                self.status = (if self.paused { "paused" } else { "running" }.into(), false);
            }
            KeyCode::Char('s') | KeyCode::Char('.') => {
                self.paused = true;
                self.step_once();
            }
            KeyCode::Char('r') => self.reset(false),
            KeyCode::Char('R') => self.reset(true),
            KeyCode::Tab => {
                let n = self.sim.scene().bodies.len().max(1);
                self.selected = (self.selected + 1) % n;
            }
            KeyCode::Char('m') => {
                self.colouring = match self.colouring {
                    Colouring::Body => Colouring::PlasticStrain,
                    Colouring::PlasticStrain => Colouring::Speed,
                    Colouring::Speed => Colouring::Body,
                }
            }
            KeyCode::Char('+') => self.speed = (self.speed * 2.0).min(100.0),
            KeyCode::Char('-') => self.speed = (self.speed / 2.0).max(1e-4),
            KeyCode::Left => self.azimuth -= 10.0,
            KeyCode::Right => self.azimuth += 10.0,
            KeyCode::Up => self.elevation = (self.elevation + 10.0).min(89.0),
            KeyCode::Down => self.elevation = (self.elevation - 10.0).max(-89.0),
            KeyCode::Char('h') | KeyCode::Char('?') => {
                self.status = (
                    "e/E Young's modulus, n/N Poisson ratio, y/Y yield stress, f/F friction angle, \
                     d/D dilatancy, c/C cohesion, a/A FLIP ratio, w/W wall friction, Tab next body, \
                     m colours, +/- speed, arrows orbit, r reset (R: as in the file)"
                        .into(),
                    false,
                );
            }
            KeyCode::Char(ch) => {
                let key = ch.to_ascii_lowercase();
                let up = up || ch.is_ascii_uppercase();
                let factor = if ch.is_ascii_uppercase() {
                    1.25
                } else {
                    factor
                };
                let delta = |step: f64| if up { step } else { -step };
                if b >= self.sim.scene().bodies.len() && key != 'w' {
                    return;
                }
                match key {
                    'e' => self.nudge("Young's modulus", |s| {
                        set_elastic(&mut s.bodies[b].material, |e, _| *e *= factor)
                    }),
                    'n' => self.nudge("Poisson ratio", |s| {
                        set_elastic(&mut s.bodies[b].material, |_, nu| {
                            *nu = round(*nu + delta(0.02))
                        })
                    }),
                    'y' => self.nudge("yield stress", |s| {
                        if let Material::VonMises(m) = &mut s.bodies[b].material {
                            m.yield_stress *= factor;
                        }
                    }),
                    'f' => self.nudge("friction angle", |s| {
                        if let Material::DruckerPrager(m) = &mut s.bodies[b].material {
                            m.friction_angle = round(m.friction_angle + delta(2.0));
                        }
                    }),
                    'd' => self.nudge("dilatancy angle", |s| {
                        if let Material::DruckerPrager(m) = &mut s.bodies[b].material {
                            m.dilatancy_angle = round(m.dilatancy_angle + delta(2.0));
                        }
                    }),
                    'c' => self.nudge("cohesion", |s| {
                        if let Material::DruckerPrager(m) = &mut s.bodies[b].material {
                            m.cohesion = if up {
                                (m.cohesion * 1.5).max(10.0)
                            } else if m.cohesion <= 10.0 {
                                0.0
                            } else {
                                m.cohesion / 1.5
                            };
                        }
                    }),
                    'a' => self.nudge("FLIP ratio", |s| {
                        let body = &mut s.bodies[b];
                        body.flip = Some(round(body.flip_ratio() + delta(0.05)));
                    }),
                    'w' => self.nudge("wall friction", |s| {
                        s.boundary.friction = round(s.boundary.friction + delta(0.05));
                    }),
                    _ => {}
                }
            }
            _ => {}
        }
    }

    fn reset(&mut self, to_file: bool) {
        let scene = if to_file {
            self.original.clone()
        } else {
            self.sim.scene().clone()
        };
        match AnySimulation::new(scene) {
            Ok(sim) => {
                self.sim = sim;
                self.status = (
                    if to_file {
                        "reset to the scene file"
                    } else {
                        "reset with the current parameters"
                    }
                    .into(),
                    false,
                );
            }
            Err(e) => self.status = (format!("cannot reset: {e}"), true),
        }
    }

    pub fn draw(&self, f: &mut Frame) {
        let [main, side] =
            Layout::horizontal([Constraint::Min(20), Constraint::Length(38)]).areas(f.area());
        let [view, status] =
            Layout::vertical([Constraint::Min(5), Constraint::Length(3)]).areas(main);
        self.draw_view(f, view);
        f.render_widget(self.panel(), side);
        let (msg, bad) = &self.status;
        let style = if *bad {
            Style::new().fg(Color::LightRed)
        } else {
            Style::new().fg(Color::Gray)
        };
        f.render_widget(
            Paragraph::new(msg.as_str())
                .style(style)
                .wrap(Wrap { trim: true })
                .block(Block::bordered()),
            status,
        );
    }

    /// Screen coordinates of a world point (metres in the view plane).
    fn project(&self, p: [f64; 3], dim: usize) -> (f64, f64) {
        if dim == 2 {
            return (p[0], p[1]);
        }
        let (az, el) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let right = [az.cos(), 0.0, -az.sin()];
        let up = [-az.sin() * el.sin(), el.cos(), -az.cos() * el.sin()];
        let d = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        (d(p, right), d(p, up))
    }

    fn draw_view(&self, f: &mut Frame, area: Rect) {
        let snap = mpm::io::Snapshot::of(&self.sim);
        let dim = snap.dim;
        let dom = snap.domain;
        let corners: Vec<[f64; 3]> = (0..8usize)
            .filter(|m| dim == 3 || m >> 2 & 1 == 0)
            .map(|m| std::array::from_fn(|a| if m >> a & 1 == 1 { dom[a] } else { 0.0 }))
            .collect();
        let proj: Vec<(f64, f64)> = corners.iter().map(|&c| self.project(c, dim)).collect();
        let (mut x0, mut x1, mut y0, mut y1) = (
            proj.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
            proj.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
            proj.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
            proj.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
        );
        // square braille dots: 2 × 4 per cell, cells about twice as tall as wide
        let (cols, rows) = (
            area.width.saturating_sub(2).max(1) as f64,
            area.height.saturating_sub(2).max(1) as f64,
        );
        let (wx, wy) = (x1 - x0, y1 - y0);
        let per_dot = (wx / (2.0 * cols)).max(wy / (4.0 * rows)).max(1e-9);
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        x0 = cx - per_dot * cols;
        x1 = cx + per_dot * cols;
        y0 = cy - per_dot * 2.0 * rows;
        y1 = cy + per_dot * 2.0 * rows;

        let groups = match self.colouring {
            Colouring::Body => BODY_COLOURS.len(),
            _ => RAMP.len(),
        };
        let mut buckets: Vec<Vec<(f64, f64)>> = vec![Vec::new(); groups];
        let max_speed = snap
            .velocity
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .fold(1e-6, f32::max);
        for i in 0..snap.len() {
            let p = snap.position[i].map(|x| x as f64);
            let g = match self.colouring {
                Colouring::Body => snap.body[i] as usize % groups,
                Colouring::PlasticStrain => bucket(snap.plastic_strain[i] / 0.5, groups),
                Colouring::Speed => {
                    let v = snap.velocity[i];
                    bucket(
                        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() / max_speed,
                        groups,
                    )
                }
            };
            buckets[g].push(self.project(p, dim));
        }
        let edges: Vec<(usize, usize)> = (0..corners.len())
            .flat_map(|i| (0..corners.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| i < j && (i ^ j).count_ones() == 1)
            .collect();
        let d = self.sim.diagnostics();
        let title = format!(
            " {} · t = {:.3} s{} ",
            self.sim.scene().name,
            d.time,
            if self.paused { " · paused" } else { "" }
        );
        let canvas = Canvas::default()
            .block(Block::bordered().title(title))
            .marker(Marker::Braille)
            .x_bounds([x0, x1])
            .y_bounds([y0, y1])
            .paint(|ctx| {
                for &(i, j) in &edges {
                    let (a, b) = (proj[i], proj[j]);
                    ctx.draw(&CanvasLine {
                        x1: a.0,
                        y1: a.1,
                        x2: b.0,
                        y2: b.1,
                        color: Color::DarkGray,
                    });
                }
                ctx.layer();
                for (g, pts) in buckets.iter().enumerate() {
                    let color = match self.colouring {
                        Colouring::Body => BODY_COLOURS[g],
                        _ => RAMP[g],
                    };
                    ctx.draw(&Points { coords: pts, color });
                }
            });
        f.render_widget(canvas, area);
    }

    fn panel(&self) -> Paragraph<'_> {
        let scene = self.sim.scene();
        let d = self.sim.diagnostics();
        let unit = if scene.dim == 2 { " J/m" } else { " J" };
        let mut lines = vec![
            Line::from(vec![
                Span::raw(format!("{}D · {} particles", scene.dim, d.particles)).bold(),
            ]),
            Line::from(format!("steps {}  dt {:.2e} s", d.step, d.dt)),
            Line::from(format!(
                "CFL {:.2}  speed ×{} (got ×{:.2})",
                d.cfl, self.speed, self.achieved
            )),
            Line::from(format!("kinetic       {:>10.3e}{unit}", d.kinetic)),
            Line::from(format!("gravitational {:>10.3e}{unit}", d.gravitational)),
            Line::from(format!("elastic       {:>10.3e}{unit}", d.elastic)),
            Line::from(format!("dissipated    {:>10.3e}{unit}", d.dissipated())),
            Line::from(""),
            Line::from(format!("wall friction w/W  {:.2}", scene.boundary.friction)),
        ];
        for (i, b) in scene.bodies.iter().enumerate() {
            let sel = i == self.selected;
            let head = format!(
                "{} body {i} {:?}: {}",
                if sel { "▶" } else { " " },
                b.name,
                b.material.kind()
            );
            lines.push(Line::from(""));
            lines.push(Line::from(Span::raw(head).fg(if sel {
                Color::White
            } else {
                Color::Gray
            })));
            if !sel {
                continue;
            }
            let e = b.material.elastic_params();
            lines.push(Line::from(format!(
                "  E   e/E  {:.3e} Pa",
                e.youngs_modulus
            )));
            lines.push(Line::from(format!("  ν   n/N  {:.2}", e.poisson_ratio)));
            match &b.material {
                Material::VonMises(m) => {
                    lines.push(Line::from(format!("  σy  y/Y  {:.3e} Pa", m.yield_stress)))
                }
                Material::DruckerPrager(m) => {
                    lines.push(Line::from(format!("  φ   f/F  {:.1}°", m.friction_angle)));
                    lines.push(Line::from(format!("  ψ   d/D  {:.1}°", m.dilatancy_angle)));
                    lines.push(Line::from(format!("  c   c/C  {:.3e} Pa", m.cohesion)));
                }
                Material::Elastic(_) => {}
            }
            lines.push(Line::from(format!("  α   a/A  {:.2}", b.flip_ratio())));
        }
        lines.push(Line::from(""));
        lines.push(Line::from(format!("colours (m): {:?}", self.colouring)).fg(Color::Gray));
        Paragraph::new(lines).block(Block::bordered().title(" mpm play "))
    }
}

fn bucket(t: f32, n: usize) -> usize {
    if !t.is_finite() {
        return n - 1;
    }
    ((t.clamp(0.0, 1.0) * n as f32) as usize).min(n - 1)
}

/// Rounds away binary noise from repeated nudges.
fn round(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// Edits E and ν of any material.
fn set_elastic(m: &mut Material, f: impl FnOnce(&mut f64, &mut f64)) {
    match m {
        Material::Elastic(p) => f(&mut p.youngs_modulus, &mut p.poisson_ratio),
        Material::VonMises(p) => f(&mut p.youngs_modulus, &mut p.poisson_ratio),
        Material::DruckerPrager(p) => f(&mut p.youngs_modulus, &mut p.poisson_ratio),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mpm::{BodyConfig, Shape};
    use ratatui::Terminal;
    use ratatui::backend::TestBackend;

    fn app(dim: usize) -> App {
        let mut scene = SceneConfig::new(dim, &vec![1.0; dim], 0.1);
        scene.name = "test".into();
        scene.bodies.push(BodyConfig::new(
            "sand",
            Shape::cuboid(&vec![0.2; dim], &vec![0.6; dim]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, 30.0, 0.0, 0.0),
        ));
        let sim = AnySimulation::new(scene.clone()).unwrap();
        App::new(scene, sim, 0.25)
    }

    fn friction_angle(app: &App) -> f64 {
        match &app.sim.scene().bodies[0].material {
            Material::DruckerPrager(m) => m.friction_angle,
            _ => unreachable!(),
        }
    }

    #[test]
    fn keys_pause_step_nudge_and_reset() {
        let mut app = app(2);
        app.key(KeyCode::Char(' '), false);
        assert!(app.paused);
        app.tick(Duration::from_millis(30));
        assert_eq!(app.sim.steps(), 0, "paused: no steps");
        app.key(KeyCode::Char('s'), false);
        assert_eq!(app.sim.steps(), 1);
        app.key(KeyCode::Char('F'), true);
        assert_eq!(friction_angle(&app), 32.0);
        // push φ past 90°: rejected, unchanged, and the message names the field
        for _ in 0..40 {
            app.key(KeyCode::Char('F'), true);
        }
        assert!(friction_angle(&app) < 90.0);
        assert!(app.status.1);
        assert!(
            app.status
                .0
                .contains("bodies[0].material.drucker_prager.friction_angle"),
            "{}",
            app.status.0
        );
        app.key(KeyCode::Char('r'), false);
        assert_eq!(app.sim.steps(), 0);
        assert!(friction_angle(&app) > 80.0, "reset keeps the parameters");
        app.key(KeyCode::Char('R'), true);
        assert_eq!(friction_angle(&app), 30.0, "R goes back to the file");
        app.key(KeyCode::Char(' '), false);
        app.tick(Duration::from_millis(30));
        assert!(app.sim.steps() > 0);
        app.key(KeyCode::Char('q'), false);
        assert!(app.quit);
    }

    #[test]
    fn the_view_draws_particles_in_both_dimensions() {
        for dim in [2, 3] {
            let mut app = app(dim);
            app.key(KeyCode::Char('m'), false);
            let mut terminal = Terminal::new(TestBackend::new(100, 30)).unwrap();
            terminal.draw(|f| app.draw(f)).unwrap();
            let buffer = terminal.backend().buffer().clone();
            let text: String = buffer.content().iter().map(|c| c.symbol()).collect();
            let braille = text
                .chars()
                .filter(|c| ('\u{2801}'..='\u{28ff}').contains(c))
                .count();
            assert!(braille > 20, "{dim}D: {braille} braille cells");
            assert!(text.contains("mpm play"));
            assert!(text.contains("particles"));
        }
    }
}
