//! The command line: `mpm run`, `mpm check`, `mpm play`.

use clap::{Args, Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use mpm::io::{Camera, ColorBy, RenderOptions, Snapshot, Summary, ply, render};
use mpm::measure::Footprints;
use mpm::{AnySimulation, Dim, Error, SceneConfig, Simulation};
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Material point method playground: elastic and plastic solids and sand (Jiang et al.).
///
/// Scene files are JSON (see docs/scenes.md); units are SI, angles in degrees. Meshes and vertex
/// lists that a scene references are read relative to the scene file.
#[derive(Parser, Debug)]
#[command(name = "mpm", version, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scene for some simulated time, writing PLY + PNG frames and a JSON summary.
    Run(RunArgs),
    /// Validate a scene; print its particle counts, a memory estimate and the stable time step.
    Check(CheckArgs),
    /// Watch and steer a scene in the terminal (pause, step, reset, nudge the materials).
    Play(PlayArgs),
}

#[derive(Args, Debug)]
pub struct SceneArgs {
    /// The scene file (JSON).
    pub scene: PathBuf,
    /// Override the scene's cell size (m), e.g. for a quick coarse run; the domain must stay a
    /// whole number of cells.
    #[arg(long, value_name = "METRES", allow_negative_numbers = true)]
    pub cell_size: Option<f64>,
    /// Set a live parameter as the page's sliders do, e.g. drucker_prager.friction_angle=25
    /// (repeatable; --help lists the names).
    #[arg(long = "set", value_name = "NAME=VALUE", allow_hyphen_values = true, long_help = set_help())]
    pub set: Vec<String>,
    /// Sample the scene as the page's quality level does (coarser cells, more particles per
    /// cell), after --cell-size: live, balanced, or fine (the file as written).
    #[arg(long, value_name = "LEVEL", default_value = "fine", value_parser = quality_names())]
    pub quality: String,
}

/// The page's quality levels, coarsest first.
fn quality_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(mpm::playground::QUALITIES.iter().map(|q| q.id))
}

#[derive(Args, Debug)]
struct RunArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Simulated time to run (s).
    #[arg(
        long,
        short = 't',
        value_name = "SECONDS",
        allow_negative_numbers = true
    )]
    time: f64,
    /// Number of frames to write, evenly spaced in time, the last at the end [default: 1 when
    /// --out is given, else 0].
    #[arg(long, short = 'n', value_name = "N")]
    frames: Option<u32>,
    /// Directory for the frames (frame_NNNN.ply, frame_NNNN.png), created if missing
    /// [default: out].
    #[arg(long, short = 'o', value_name = "DIR")]
    out: Option<PathBuf>,
    /// Write the JSON summary to this file ("-" for standard output).
    #[arg(long, value_name = "FILE")]
    summary: Option<PathBuf>,
    /// What the PNG colours show.
    #[arg(long, value_enum, default_value_t = ColorArg::Body)]
    color: ColorArg,
    /// Camera of the PNG snapshots of 3D scenes (2D scenes are drawn orthographically).
    #[arg(long, value_enum, default_value_t = CameraArg::Perspective)]
    camera: CameraArg,
    /// PNG size, WIDTHxHEIGHT in pixels.
    #[arg(long, value_name = "WxH", default_value = "960x720", value_parser = parse_size)]
    size: (u32, u32),
    /// Do not write PNG snapshots.
    #[arg(long)]
    no_png: bool,
    /// Do not write PLY frames.
    #[arg(long)]
    no_ply: bool,
    /// No progress bar.
    #[arg(long, short = 'q')]
    quiet: bool,
    /// Let material at rest sleep until something moves the grid around it (off: every
    /// particle is stepped; docs/method.md, "Sleeping: material at rest").
    #[arg(long)]
    sleep: bool,
    /// Run the scene as a soil test (2D) and write its readings, 200 over the run, to this CSV
    /// file; no frames. A scene with a body under a traction is a biaxial test (a moving
    /// kinematic platen): time, axial and volumetric strain, σ3, σ1, the deviator q (Pa) from
    /// the platen's force. Otherwise a direct shear box (sand, an upper half moving along x,
    /// a solid lid): time, displacement δ, τ, σ_n, the lid's support, the lid's rise.
    #[arg(long, value_name = "FILE")]
    lab_csv: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct CheckArgs {
    #[command(flatten)]
    scene: SceneArgs,
}

#[derive(Args, Debug)]
pub struct PlayArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Simulated seconds per real second (the view slows down when the machine cannot keep up).
    #[arg(long, default_value_t = 0.25, value_name = "RATIO")]
    pub speed: f64,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum ColorArg {
    Body,
    PlasticStrain,
    Speed,
    Pressure,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum CameraArg {
    Perspective,
    Orthographic,
}

/// The long help of `--set`: every name of the parameter table.
fn set_help() -> String {
    let names: Vec<String> = mpm::params::table()
        .into_iter()
        .map(|p| {
            let unit = match p.field.unit {
                "" => String::new(),
                u => format!(" ({u})"),
            };
            format!("  {}{unit}: {}", p.name, p.field.help)
        })
        .collect();
    format!(
        "Set a live parameter as the page's sliders and the terminal player's keys do: \
         NAME=VALUE, validated like the scene file. Repeatable, applied in order. NAME is one of \
         the names below (a material's applies to every body of that model), or \
         bodies[<i>].<model>.<field> for body i alone:\n{}",
        names.join("\n")
    )
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?}: expected WIDTHxHEIGHT, e.g. 960x720"))?;
    let parse = |v: &str| -> Result<u32, String> {
        match v.trim().parse::<u32>() {
            Ok(n) if (16..=8192).contains(&n) => Ok(n),
            _ => Err(format!(
                "{v:?}: each side must be a whole number in [16, 8192]"
            )),
        }
    };
    Ok((parse(w)?, parse(h)?))
}

/// A failure to report: the message goes to stderr, the code is the exit status.
pub struct Failure(pub String);

/// The message of a write to a closed standard output (`mpm check … | head`): not a failure,
/// the reader has what it wanted, so the command ends quietly.
const CLOSED: &str = "output closed";

/// Writes to standard output; a closed pipe ends the command quietly (see [`CLOSED`]).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*).map_err(crate::cli::write_failure)?
    }};
}

/// A failed write to standard output: quiet when the reader went away.
pub fn write_failure(e: std::io::Error) -> Failure {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        Failure(CLOSED.into())
    } else {
        Failure(format!("cannot write to standard output: {e}"))
    }
}

/// Writes to standard error, ignoring a closed one (there is nowhere left to report to).
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure(e.to_string())
    }
}

/// Parses the command line and runs its command; `play` runs the terminal player (its own
/// module, which takes the scene arguments and failures from this one).
pub fn main(play: fn(PlayArgs) -> Result<(), Failure>) -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => run(a),
        Command::Check(a) => check(a),
        Command::Play(a) => play(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(msg)) if msg == CLOSED => ExitCode::SUCCESS,
        Err(Failure(msg)) => {
            note!("mpm: error: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// Loads and validates a scene, applying the command-line overrides; errors name the file.
pub fn load_scene(args: &SceneArgs) -> Result<SceneConfig, Failure> {
    let name = args.scene.display();
    let mut scene = SceneConfig::load(&args.scene).map_err(|e| match e {
        Error::Io { .. } => Failure(format!("cannot read the scene file: {e}")),
        e => Failure(format!("{name}: {e}")),
    })?;
    if let Some(h) = args.cell_size {
        scene.cell_size = h;
        scene
            .validate()
            .map_err(|e| Failure(format!("--cell-size: {e}")))?;
    }
    mpm::params::apply_assignments(&mut scene, &args.set)
        .map_err(|e| Failure(format!("--set: {e}")))?;
    Ok(scene)
}

/// The scene sampled at the `--quality` level as the page samples it
/// ([`mpm::playground::sample_at`]), and what that sampling is (`None` at `fine`: the file as
/// written).
pub fn at_quality(
    scene: SceneConfig,
    args: &SceneArgs,
) -> Result<(SceneConfig, Option<mpm::playground::Resolution>), Failure> {
    let q = mpm::playground::Quality::find(&args.quality)?;
    if q.id == mpm::playground::Quality::fine().id {
        return Ok((scene, None));
    }
    let (sampled, resolution) = mpm::playground::sample_at(&scene, q)
        .map_err(|e| Failure(format!("--quality {}: {e}", q.id)))?;
    Ok((sampled, Some(resolution)))
}

/// What a quality level sampled: its cell and particles per cell against the file's.
fn sampling(r: &mpm::playground::Resolution) -> String {
    format!(
        "sampled at quality {}: cell {} m (the file's {} m), {} particles per cell per axis",
        r.quality, r.cell_size, r.scene_cell_size, r.particles_per_cell
    )
}

/// Builds the simulation (samples the shapes); errors name the file.
pub fn build(scene: SceneConfig, path: &Path) -> Result<AnySimulation, Failure> {
    AnySimulation::new(scene).map_err(|e| Failure(format!("{}: {e}", path.display())))
}

fn run(a: RunArgs) -> Result<(), Failure> {
    mpm::error::check_positive("--time", a.time, "s")?;
    if a.time > 1e6 {
        return Err(Failure(format!(
            "--time = {}: must be at most 1e6 s",
            a.time
        )));
    }
    let frames = a.frames.unwrap_or(if a.out.is_some() { 1 } else { 0 });
    if frames > 100_000 {
        return Err(Failure(format!(
            "--frames = {frames}: must be at most 100000"
        )));
    }
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out"));
    let write_frames = frames > 0 && !(a.no_png && a.no_ply);
    if write_frames {
        fs::create_dir_all(&out)
            .map_err(|e| Failure(format!("cannot create {}: {e}", out.display())))?;
    }
    let scene = load_scene(&a.scene)?;
    let (scene, resolution) = at_quality(scene, &a.scene)?;
    if let (Some(r), false) = (&resolution, a.quiet) {
        note!("{}", sampling(r));
    }
    let mut sim = build(scene, &a.scene.scene)?;
    sim.set_sleeping_at_rest(a.sleep);
    for w in sim.warnings(Some(a.time)) {
        note!("warning: {w}");
    }
    let dt = sim.stable_dt();
    let estimate = a.time / dt;
    if estimate > mpm::sim::MAX_STEPS {
        return Err(Failure(format!(
            "--time = {} s at the stable step of {dt:.3e} s is about {estimate:.2e} steps, more than the {:.0e} a run takes: a shorter --time, a softer or denser material, slower bodies or a coarser cell_size",
            a.time,
            mpm::sim::MAX_STEPS
        )));
    }
    if let Some(csv) = &a.lab_csv {
        return run_lab(sim, &a, csv);
    }
    let render_options = RenderOptions {
        width: a.size.0,
        height: a.size.1,
        camera: match a.camera {
            CameraArg::Perspective => Camera::Perspective,
            CameraArg::Orthographic => Camera::Orthographic,
        },
        color_by: match a.color {
            ColorArg::Body => ColorBy::Body,
            ColorArg::PlasticStrain => ColorBy::PlasticStrain,
            ColorArg::Speed => ColorBy::Speed,
            ColorArg::Pressure => ColorBy::Pressure,
        },
        ..Default::default()
    };

    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(
            Some((a.time * 1e6).round() as u64),
            ProgressDrawTarget::stderr(),
        );
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner:.green} [{elapsed_precise}] {wide_bar:.cyan/blue} {msg} ETA {eta}",
            )
            .expect("a valid template")
            .progress_chars("=> "),
        );
        bar
    };
    let mut footprints = Footprints::default();
    footprints.update_any(&sim);
    let started = Instant::now();
    let mut last_draw = Instant::now() - Duration::from_secs(1);
    let segments = frames.max(1);
    let mut result: Result<(), Failure> = Ok(());
    for k in 1..=segments {
        let target = a.time * k as f64 / segments as f64;
        // step to each body's appearance on the way, so that its footprint (for the
        // summary's run-outs) is where it entered
        let mut stepped = Ok(0);
        while stepped.is_ok() {
            let stop = sim
                .next_appearance()
                .filter(|&t| t > sim.time() && t < target)
                .unwrap_or(target);
            stepped = sim.advance_until(stop, |d| {
                if last_draw.elapsed() > Duration::from_millis(50) {
                    last_draw = Instant::now();
                    progress(&bar, d, a.time, started);
                }
                true
            });
            footprints.update_any(&sim);
            if stop == target {
                break;
            }
        }
        if let Err(e) = stepped {
            result = Err(Failure(format!(
                "{}: the simulation stopped at t = {:.6} s: {e}",
                a.scene.scene.display(),
                sim.time()
            )));
            break;
        }
        if write_frames
            && k <= frames
            && let Err(e) = write_frame(&sim, &out, k, &a, &render_options)
        {
            result = Err(e);
            break;
        }
    }
    progress(&bar, sim.diagnostics(), a.time, started);
    bar.finish();
    let wall = started.elapsed().as_secs_f64();
    if let Some(path) = &a.summary {
        let summary = Summary::of(&sim, wall, &footprints);
        let text = serde_json::to_string_pretty(&summary).expect("the summary serialises") + "\n";
        if path.as_os_str() == "-" {
            std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes())
                .map_err(write_failure)?;
        } else {
            fs::write(path, text)
                .map_err(|e| Failure(format!("cannot write {}: {e}", path.display())))?;
        }
    }
    if !a.quiet {
        let d = sim.diagnostics();
        note!(
            "{} particles, {} steps to t = {:.4} s in {:.2} s ({:.0} steps/s, {:.2} M particle-steps/s)",
            sim.particle_count(),
            sim.steps(),
            sim.time(),
            wall,
            sim.steps() as f64 / wall.max(1e-9),
            sim.steps() as f64 * sim.particle_count() as f64 / wall.max(1e-9) / 1e6
        );
        note!(
            "energy: kinetic {:.4e}, gravitational {:.4e}, elastic {:.4e}, dissipated {:.4e} J{}",
            d.kinetic,
            d.gravitational,
            d.elastic,
            d.dissipated(),
            if sim.dim() == 2 { "/m" } else { "" }
        );
        let error = d.energy_error();
        if error.abs() > mpm::sim::ACCOUNT_TOLERANCE {
            note!(
                "warning: the energy account does not close: the sum is {:+.1} % off the energy brought in (allowed ±{:.0} %)",
                100.0 * error,
                100.0 * mpm::sim::ACCOUNT_TOLERANCE
            );
        }
    }
    result
}

fn progress(bar: &ProgressBar, d: &mpm::Diagnostics, total: f64, started: Instant) {
    let wall = started.elapsed().as_secs_f64().max(1e-9);
    bar.set_position((d.time * 1e6).round() as u64);
    bar.set_message(format!(
        "t = {:.3}/{:.3} s, {} steps, {:.0} steps/s",
        d.time,
        total,
        d.step,
        d.step as f64 / wall
    ));
}

fn write_frame(
    sim: &AnySimulation,
    out: &Path,
    k: u32,
    a: &RunArgs,
    options: &RenderOptions,
) -> Result<(), Failure> {
    let snap = Snapshot::of(sim);
    let io_err =
        |p: &Path, e: std::io::Error| Failure(format!("cannot write {}: {e}", p.display()));
    if !a.no_ply {
        let path = out.join(format!("frame_{k:04}.ply"));
        let file = fs::File::create(&path).map_err(|e| io_err(&path, e))?;
        let mut w = BufWriter::new(file);
        ply::write(&mut w, &snap)
            .and_then(|_| w.flush())
            .map_err(|e| io_err(&path, e))?;
    }
    if !a.no_png {
        let path = out.join(format!("frame_{k:04}.png"));
        let file = fs::File::create(&path).map_err(|e| io_err(&path, e))?;
        render(&snap, options)
            .write_png(BufWriter::new(file))
            .map_err(|e| io_err(&path, e))?;
    }
    Ok(())
}

fn check(a: CheckArgs) -> Result<(), Failure> {
    let scene = load_scene(&a.scene)?;
    let (scene, resolution) = at_quality(scene, &a.scene)?;
    let path = &a.scene.scene;
    let started = Instant::now();
    let sim = build(scene, path)?;
    let sampled_in = started.elapsed().as_secs_f64();
    out!("{}: valid", path.display());
    if let Some(r) = &resolution {
        out!("{}", sampling(r));
    }
    for w in sim.warnings(None) {
        note!("warning: {w}");
    }
    match &sim {
        AnySimulation::D2(s) => report(s, sampled_in),
        AnySimulation::D3(s) => report(s, sampled_in),
    }
}

fn report<D: Dim>(sim: &Simulation<D>, sampling: f64) -> Result<(), Failure> {
    let scene = sim.scene();
    let cells: Vec<String> = scene
        .domain
        .size
        .iter()
        .map(|s| format!("{}", (s / scene.cell_size).round()))
        .collect();
    let sizes: Vec<String> = scene.domain.size.iter().map(|s| format!("{s}")).collect();
    out!(
        "scene {:?}: {}D{}, domain {} m, cell {} m ({} cells), kernel {:?}",
        scene.name,
        D::DIM,
        if D::DIM == 2 { " (plane strain)" } else { "" },
        sizes.join(" × "),
        scene.cell_size,
        cells.join(" × "),
        scene.kernel
    );
    let per_depth = if D::DIM == 2 { "/m" } else { "" };
    let mut poured = 0;
    for (i, (b, cfg)) in sim.bodies().iter().zip(&scene.bodies).enumerate() {
        out!(
            "  body {i} {:?}: {}, {} particles, mass {:.4} kg{per_depth}, wave speed {:.2} m/s, flip {}",
            cfg.name,
            cfg.material.kind(),
            b.range().len(),
            b.stats().mass,
            b.wave_speed(),
            b.recipe().flip
        );
        poured += pour_report::<D>(cfg, scene.cell_size)?;
    }
    let present = sim.bodies().len();
    let mut later = 0;
    for (k, (cfg, n)) in sim.bodies_to_come().enumerate() {
        out!(
            "  body {} {:?}: {}, {n} particles, enters at t = {} s",
            present + k,
            cfg.name,
            cfg.material.kind(),
            cfg.appear_time()
        );
        later += n;
        poured += pour_report::<D>(cfg, scene.cell_size)?;
    }
    let n = sim.particles().len();
    let poured = if poured > 0 {
        format!(", {poured} to be poured")
    } else {
        String::new()
    };
    if later > 0 {
        out!("particles: {n} at the start, {later} to come{poured} (sampled in {sampling:.3} s)");
    } else {
        out!("particles: {n}{poured} (sampled in {:.3} s)", sampling);
    }
    // one step on a copy allocates the grids: the memory that the run will need at first
    let mut probe = sim.clone();
    let step_wall = Instant::now();
    let stepped = probe.step().map(|_| ());
    let step_wall = step_wall.elapsed().as_secs_f64();
    let particle_bytes = n * mpm::sim::Particles::<D>::bytes_per_particle();
    out!(
        "memory: about {} ({} of particles, {} of grid after the first step)",
        bytes(probe.memory_bytes()),
        bytes(particle_bytes),
        bytes(probe.memory_bytes().saturating_sub(particle_bytes))
    );
    let dt = sim.stable_dt();
    out!(
        "stable dt: {dt:.4e} s (CFL {}, max_dt {} s): about {:.0} steps per simulated second",
        scene.cfl,
        scene.max_dt,
        1.0 / dt
    );
    out!(
        "first step: {:.1} ms ({:.2} M particle-steps/s)",
        step_wall * 1e3,
        n as f64 / step_wall.max(1e-9) / 1e6
    );
    stepped.map_err(|e| Failure(format!("the first step failed: {e}")))
}

/// Prints what a poured body's spout pours on a grid of `cell_size` (nothing for another
/// body); returns how many particles it pours in all.
fn pour_report<D: Dim>(cfg: &mpm::BodyConfig, cell_size: f64) -> Result<u64, Failure> {
    let Some(pour) = &cfg.pour else {
        return Ok(0);
    };
    let spout = mpm::sim::Spout::new(
        pour,
        D::DIM,
        cell_size,
        cfg.particles_per_cell,
        cfg.jitter,
        cfg.seed,
        cfg.appear_time(),
    );
    let (rate, area) = if D::DIM == 2 {
        ("m²/s per metre of depth", "m")
    } else {
        ("m³/s", "m²")
    };
    let spout_at: Vec<String> = pour.spout.iter().map(|x| format!("{x}")).collect();
    out!(
        "    poured from a spout at [{}] m, radius {} m, for {} s from t = {} s: rate {} {rate}, exit area {:.4e} {area} ({} particles a layer), exit speed {:.3} m/s, {:.0} particles/s, {} particles in all",
        spout_at.join(", "),
        pour.radius,
        pour.duration,
        cfg.appear_time(),
        pour.rate,
        pour.exit_area(D::DIM, spout.spacing()),
        spout.per_layer(),
        spout.exit_speed(),
        spout.particles_per_second(),
        spout.particles()
    );
    Ok(spout.particles())
}

/// A byte count in kB, MB or GB.
fn bytes(n: usize) -> String {
    let n = n as f64;
    if n < 1e6 {
        format!("{:.1} kB", n / 1e3)
    } else if n < 1e9 {
        format!("{:.1} MB", n / 1e6)
    } else {
        format!("{:.2} GB", n / 1e9)
    }
}

/// `mpm run --lab-csv`: the scene as a biaxial test or a shear box, its readings as CSV.
fn run_lab(sim: AnySimulation, a: &RunArgs, csv: &Path) -> Result<(), Failure> {
    let scene = a.scene.scene.display();
    let AnySimulation::D2(mut sim) = sim else {
        return Err(Failure(format!(
            "--lab-csv: {scene}: the soil tests are plane strain: the scene must have dim 2"
        )));
    };
    let lab = |e: mpm::Error| Failure(format!("--lab-csv: {scene}: {e}"));
    let stopped = |e: mpm::Error, t: f64| {
        Failure(format!(
            "{scene}: the simulation stopped at t = {t:.6} s: {e}"
        ))
    };
    let started = Instant::now();
    let every = a.time / 200.0;
    let biaxial = mpm::lab::is_biaxial(sim.scene());
    let (text, peak) = if biaxial {
        let mut test = mpm::lab::Biaxial::new(&sim).map_err(lab)?;
        test.read(&sim);
        let run = test.run(&mut sim, a.time, every);
        run.map_err(|e| stopped(e, sim.time()))?;
        let peak = test.failure().map(|(s1, s3)| {
            format!(
                "peak deviator {:.1} Pa at σ3 = {s3:.1} Pa: a circle of angle {:.2}° through the origin",
                s1 - s3,
                ((s1 - s3) / (s1 + s3)).asin().to_degrees()
            )
        });
        (test.csv(), peak)
    } else {
        let mut test = mpm::lab::ShearBox::new(&sim).map_err(lab)?;
        test.read(&sim);
        let run = test.run(&mut sim, a.time, every);
        run.map_err(|e| stopped(e, sim.time()))?;
        let peak = test.failure().map(|(sn, tau)| {
            format!(
                "failure (the last quarter of the travel): τ = {tau:.1} Pa at σ_n = {sn:.1} Pa on the shear plane: τ/σ_n = tan {:.2}°",
                (tau / sn).atan().to_degrees()
            )
        });
        (test.csv(), peak)
    };
    fs::write(csv, text).map_err(|e| Failure(format!("cannot write {}: {e}", csv.display())))?;
    if !a.quiet
        && let Some(peak) = peak
    {
        note!(
            "{peak}; {} steps in {:.2} s",
            sim.diagnostics().step,
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
