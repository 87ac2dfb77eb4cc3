//! `mpm play`: the scene in the terminal, drawn with braille dots (orthographic in 2D, an
//! orbiting projection in 3D), with keys to pause, step, reset and nudge the parameters. It
//! drives a [`Playground`], as the browser page does: the keys and their steps come from the
//! parameter table (`mpm::params`), and every change is validated like a scene file; a
//! rejected value leaves the simulation as it was and its message is shown.

use crate::cli::{Failure, PlayArgs, load_scene};
use mpm::params::{MODELS, Param, WORLD, model_index};
use mpm::playground::{ColourMode, Playground};
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
    let quality = mpm::playground::Quality::find(&a.scene.quality)?;
    let pg = Playground::with_quality(scene, quality)
        .map_err(|e| Failure(format!("{}: {e}", a.scene.scene.display())))?;
    if !std::io::stdout().is_terminal() || !std::io::stdin().is_terminal() {
        return Err(Failure(
            "play needs an interactive terminal (use `mpm run` to write frames instead)".into(),
        ));
    }
    let mut app = App::new(pg, a.speed);
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

/// What the colours show, in the order `m` cycles through them.
const COLOURINGS: [ColourMode; 3] = [
    ColourMode::Body,
    ColourMode::PlasticStrain,
    ColourMode::Speed,
];

pub struct App {
    pg: Playground,
    paused: bool,
    quit: bool,
    /// Simulated seconds per real second wanted.
    speed: f64,
    /// The body whose material the keys change.
    selected: usize,
    azimuth: f64,
    elevation: f64,
    colouring: ColourMode,
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

/// Milliseconds since `t0`: the wall clock the playground reads.
fn clock(t0: Instant) -> impl FnMut() -> f64 {
    move || t0.elapsed().as_secs_f64() * 1e3
}

/// A value with its unit, as the panel shows it.
fn show(v: f64, unit: &str) -> String {
    match unit {
        "Pa" => format!("{v:.3e} Pa"),
        "°" => format!("{v:.1}°"),
        "" => format!("{v:.2}"),
        u => format!("{v:.3} {u}"),
    }
}

impl App {
    pub fn new(pg: Playground, speed: f64) -> Self {
        App {
            pg,
            paused: false,
            quit: false,
            speed,
            selected: 0,
            azimuth: 30.0,
            elevation: 20.0,
            colouring: ColourMode::Body,
            status: (
                "space pause · s step · r reset · q quit · h help".into(),
                false,
            ),
            achieved: 0.0,
        }
    }

    fn stopped(&mut self, e: impl std::fmt::Display) {
        self.status = (format!("stopped: {e} (r to reset)"), true);
    }

    /// Advances the simulation for one frame of `frame` real time (within that wall budget).
    pub fn tick(&mut self, frame: Duration) {
        self.achieved = 0.0;
        if self.paused || self.pg.failure().is_some() {
            return;
        }
        let seconds = frame.as_secs_f64();
        match self
            .pg
            .frame(self.speed * seconds, seconds * 1e3, clock(Instant::now()))
        {
            Ok(r) => self.achieved = r.sim_time / seconds,
            Err(e) => self.stopped(e),
        }
    }

    /// The parameter key `key` changes: a world parameter, or a field of the selected body's
    /// model (named for that body alone).
    fn keyed(&self, key: char) -> Option<(String, &'static mpm::params::Field)> {
        if let Some(f) = WORLD.iter().find(|f| f.key == Some(key)) {
            return Some((f.field.to_string(), *f));
        }
        let body = self.pg.scene().bodies.get(self.selected)?;
        let m = model_index(body.material.kind()).ok()?;
        let f = MODELS[m].fields.iter().find(|f| f.key == Some(key))?;
        let name = format!("bodies[{}].{}.{}", self.selected, MODELS[m].id, f.field);
        Some((name, *f))
    }

    /// Handles a key; `shift` (or an upper-case letter) raises instead of lowering.
    pub fn key(&mut self, code: KeyCode, shift: bool) {
        match code {
            KeyCode::Char('q') | KeyCode::Esc => self.quit = true,
            KeyCode::Char(' ') | KeyCode::Char('p') => {
                self.paused = !self.paused;
                self.status = (if self.paused { "paused" } else { "running" }.into(), false);
            }
            KeyCode::Char('s') | KeyCode::Char('.') => {
                self.paused = true;
                if let Err(e) = self.pg.step(clock(Instant::now())) {
                    self.stopped(e);
                }
            }
            KeyCode::Char('r') => self.reset(false),
            KeyCode::Char('R') => self.reset(true),
            KeyCode::Tab => {
                let n = self.pg.body_count().max(1);
                self.selected = (self.selected + 1) % n;
            }
            KeyCode::Char('m') => {
                let i = COLOURINGS.iter().position(|&c| c == self.colouring);
                self.colouring = COLOURINGS[i.map_or(0, |i| (i + 1) % COLOURINGS.len())];
            }
            KeyCode::Char('+') => self.speed = (self.speed * 2.0).min(100.0),
            KeyCode::Char('-') => self.speed = (self.speed / 2.0).max(1e-4),
            KeyCode::Left => self.azimuth -= 10.0,
            KeyCode::Right => self.azimuth += 10.0,
            KeyCode::Up => self.elevation = (self.elevation + 10.0).min(89.0),
            KeyCode::Down => self.elevation = (self.elevation - 10.0).max(-89.0),
            KeyCode::Char('h') | KeyCode::Char('?') => self.status = (help(), false),
            KeyCode::Char(ch) => {
                let up = shift || ch.is_ascii_uppercase();
                let Some((name, field)) = self.keyed(ch.to_ascii_lowercase()) else {
                    return;
                };
                let value = self.pg.parameter(&name).unwrap_or(0.0);
                let next = field.nudge.apply(value, up);
                self.status = match self.pg.set_parameter(&name, next) {
                    Ok(()) => (format!("{} changed", field.label), false),
                    Err(e) => (format!("rejected: {e}"), true),
                };
            }
            _ => {}
        }
    }

    fn reset(&mut self, to_file: bool) {
        let done = if to_file {
            self.pg.reset_to_scene()
        } else {
            self.pg.reset()
        };
        self.status = match done {
            Ok(()) if to_file => ("reset to the scene file".into(), false),
            Ok(()) => ("reset with the current parameters".into(), false),
            Err(e) => (format!("cannot reset: {e}"), true),
        };
    }

    pub fn draw(&mut self, f: &mut Frame) {
        self.pg.update_colours(self.colouring);
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
        let snap = mpm::io::Snapshot::of(self.pg.simulation());
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
            ColourMode::Body => BODY_COLOURS.len(),
            _ => RAMP.len(),
        };
        let mut buckets: Vec<Vec<(f64, f64)>> = vec![Vec::new(); groups];
        let [_, hi] = self.pg.colour_range();
        for (&p, &c) in snap.position.iter().zip(self.pg.colours()) {
            let g = match self.colouring {
                ColourMode::Body => c as usize % groups,
                _ => bucket(c / hi.max(1e-9), groups),
            };
            buckets[g].push(self.project(p.map(|x| x as f64), dim));
        }
        let edges: Vec<(usize, usize)> = (0..corners.len())
            .flat_map(|i| (0..corners.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| i < j && (i ^ j).count_ones() == 1)
            .collect();
        let d = self.pg.diagnostics();
        let title = format!(
            " {} · t = {:.3} s{} ",
            self.pg.scene().name,
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
                        ColourMode::Body => BODY_COLOURS[g],
                        _ => RAMP[g],
                    };
                    ctx.draw(&Points { coords: pts, color });
                }
            });
        f.render_widget(canvas, area);
    }

    fn panel(&self) -> Paragraph<'_> {
        let scene = self.pg.scene();
        let d = self.pg.diagnostics();
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
        ];
        let keyed = |f: &mpm::params::Field, v: f64| {
            let k = f.key.unwrap_or(' ');
            format!(
                "{:<4}{k}/{}  {}",
                f.symbol,
                k.to_ascii_uppercase(),
                show(v, f.unit)
            )
        };
        for f in WORLD.iter().filter(|f| f.key.is_some()) {
            let v = self.pg.parameter(f.field).unwrap_or(0.0);
            lines.push(Line::from(format!("{}: {}", f.label, keyed(f, v))));
        }
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
            for p in Param::all().filter(|p| p.applies_to(b) && p.field.key.is_some()) {
                let v = p.material_value(&b.material, b.flip).unwrap_or(0.0);
                lines.push(Line::from(format!("  {}", keyed(p.field, v))));
            }
        }
        lines.push(Line::from(""));
        lines.push(Line::from(format!("colours (m): {:?}", self.colouring)).fg(Color::Gray));
        Paragraph::new(lines).block(Block::bordered().title(" mpm play "))
    }
}

/// The keys, from the parameter table.
fn help() -> String {
    let mut keys: Vec<String> = Vec::new();
    let mut seen = Vec::new();
    for p in Param::all() {
        if let Some(k) = p.field.key.filter(|k| !seen.contains(k)) {
            seen.push(k);
            keys.push(format!(
                "{k}/{} {}",
                k.to_ascii_uppercase(),
                p.field.label.to_lowercase()
            ));
        }
    }
    format!(
        "{}, Tab next body, m colours, +/- speed, arrows orbit, r reset (R: as in the file)",
        keys.join(", ")
    )
}

fn bucket(t: f32, n: usize) -> usize {
    if !t.is_finite() {
        return n - 1;
    }
    ((t.clamp(0.0, 1.0) * n as f32) as usize).min(n - 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mpm::{BodyConfig, Material, SceneConfig, Shape};
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
        App::new(Playground::new(scene).unwrap(), 0.25)
    }

    fn friction_angle(app: &App) -> f64 {
        let friction = app.pg.scene().bodies[0].material.behaviour().friction();
        friction.expect("sand").friction_angle
    }

    #[test]
    fn keys_pause_step_nudge_and_reset() {
        let mut app = app(2);
        app.key(KeyCode::Char(' '), false);
        assert!(app.paused);
        app.tick(Duration::from_millis(30));
        assert_eq!(app.pg.simulation().steps(), 0, "paused: no steps");
        app.key(KeyCode::Char('s'), false);
        assert_eq!(app.pg.simulation().steps(), 1);
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
        assert_eq!(app.pg.simulation().steps(), 0);
        assert!(friction_angle(&app) > 80.0, "reset keeps the parameters");
        app.key(KeyCode::Char('R'), true);
        assert_eq!(friction_angle(&app), 30.0, "R goes back to the file");
        app.key(KeyCode::Char(' '), false);
        app.tick(Duration::from_millis(30));
        assert!(app.pg.simulation().steps() > 0);
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
