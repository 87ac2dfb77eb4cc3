//! Validation cases: each loads a scene of `scenes/validation/`, overrides the numerical
//! options under study ([`Numerics`]), runs it and compares a measured quantity with a closed
//! form or a published measurement. Shared by the fast tests (`tests/validation.rs`), the long
//! validation run (`cargo bench --bench validate`) and the work–precision study
//! (`cargo bench --bench work_precision`).

// Real is f32 by default, f64 with the `f64` feature: the casts to f64 are no-ops there.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]
#![allow(dead_code)]

use mpm::material::FrictionMatch;
use mpm::math::{Dim, SymTensor, VectorOps};
use mpm::{KernelKind, Material, Real, SceneConfig, Simulation};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The directory of the validation scenes.
pub fn scene_path(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join("validation")
        .join(file)
}

/// The numerical options a case is run with (they replace the scene's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Numerics {
    pub cell_size: f64,
    pub ppc: u32,
    pub kernel: KernelKind,
    /// PIC/FLIP α of the body under test; `None` keeps the scene's.
    pub flip: Option<f64>,
    /// APIC (`Some(true)`) or the plain PIC/FLIP blend (`Some(false)`) for the body under
    /// test; `None` keeps the scene's (by default APIC for sand, PIC for solids).
    pub apic: Option<bool>,
    pub cfl: f64,
    /// Grain diameter (m) of a rate-dependent friction μ(I) for the body under test when it
    /// is sand; `None` keeps the scene's (rate-independent unless the scene says).
    pub mu_i: Option<f64>,
    /// Sand under test takes its cells' averaged volumetric strain rate
    /// (`"volumetric_rate": "cell_average"`) instead of each particle's.
    pub cell_average: bool,
    /// Sand under test takes this friction match (`"friction_match"`, e.g. the steady-flow
    /// match 3 α_φ = tan φ) instead of the scene's.
    pub friction_match: Option<FrictionMatch>,
    /// The body under test updates its stress last (`Some(true)`) or first (`Some(false)`);
    /// `None` keeps the material's default (first for sand).
    pub stress_last: Option<bool>,
}

impl Numerics {
    pub fn new(cell_size: f64, kernel: KernelKind) -> Self {
        Numerics {
            cell_size,
            ppc: 2,
            kernel,
            flip: None,
            apic: None,
            cfl: 0.4,
            mu_i: None,
            cell_average: false,
            friction_match: None,
            stress_last: None,
        }
    }
    /// The body under test with its stress updated last (`true`) or first (`false`).
    pub fn stress_last(mut self, last: bool) -> Self {
        self.stress_last = Some(last);
        self
    }
    /// Sand with the volumetric strain rate averaged over each grid cell.
    pub fn cell_average(mut self) -> Self {
        self.cell_average = true;
        self
    }
    /// Sand with the steady-flow friction match.
    pub fn steady_flow(mut self) -> Self {
        self.friction_match = Some(FrictionMatch::SteadyFlow);
        self
    }
    /// Sand with Eq. 13's cone alone (the paper's friction match).
    pub fn plane_strain(mut self) -> Self {
        self.friction_match = Some(FrictionMatch::PlaneStrain);
        self
    }
    /// Sand with the start–stop friction match (Eq. 13's cone widening with the plastic
    /// strain to the steady-flow cone of the same plane-strain angle).
    pub fn start_stop(mut self) -> Self {
        self.friction_match = Some(FrictionMatch::StartStop);
        self
    }
    /// Sand with the μ(I) friction of grain diameter `d` (m).
    pub fn mu_i(mut self, d: f64) -> Self {
        self.mu_i = Some(d);
        self
    }
    pub fn apic(mut self) -> Self {
        self.apic = Some(true);
        self
    }
    /// The paper's PIC/FLIP blend without APIC (sand's transfer before APIC became its
    /// default).
    pub fn pic(mut self) -> Self {
        self.apic = Some(false);
        self
    }
    pub fn ppc(mut self, ppc: u32) -> Self {
        self.ppc = ppc;
        self
    }
    pub fn flip(mut self, alpha: f64) -> Self {
        self.flip = Some(alpha);
        self
    }
    pub fn cfl(mut self, cfl: f64) -> Self {
        self.cfl = cfl;
        self
    }
    /// Applies the options to a scene: cell size, kernel and CFL for the world, particles per
    /// cell for every body, α for the first body (the material under test).
    pub fn apply(&self, scene: &mut SceneConfig) {
        scene.cell_size = self.cell_size;
        scene.kernel = self.kernel;
        scene.cfl = self.cfl;
        for b in &mut scene.bodies {
            b.particles_per_cell = self.ppc;
        }
        if let Some(a) = self.flip {
            scene.bodies[0].flip = Some(a);
        }
        if self.apic.is_some() {
            scene.bodies[0].apic = self.apic;
        }
        if self.stress_last.is_some() {
            scene.bodies[0].stress_last = self.stress_last;
        }
        if let (Some(d), Material::DruckerPrager(m)) = (self.mu_i, &mut scene.bodies[0].material) {
            m.mu_i = Some(mpm::material::mu_i::MuIParams { grain_diameter: d });
        }
        if let (true, Material::DruckerPrager(m)) =
            (self.cell_average, &mut scene.bodies[0].material)
        {
            m.volumetric_rate = mpm::material::VolumetricRate::CellAverage;
        }
        if let (Some(f), Material::DruckerPrager(m)) =
            (self.friction_match, &mut scene.bodies[0].material)
        {
            m.friction_match = f;
        }
    }
    /// A short label, e.g. `gimp h=0.0125 ppc=2 α=1 cfl=0.4` (and ` apic`, ` μ(I) d=0.5mm`,
    /// ` cell-avg`, ` steady-flow`, ` stress-last`).
    pub fn label(&self) -> String {
        let alpha = self.flip.map_or("scene".to_string(), |a| format!("{a}"));
        format!(
            "{} h={} ppc={} α={alpha} cfl={}{}{}{}{}{}",
            kernel_name(self.kernel),
            self.cell_size,
            self.ppc,
            self.cfl,
            match self.apic {
                Some(true) => " apic",
                Some(false) => " pic",
                None => "",
            },
            self.mu_i
                .map_or(String::new(), |d| format!(" μ(I) d={}mm", 1e3 * d)),
            if self.cell_average { " cell-avg" } else { "" },
            match self.friction_match {
                Some(FrictionMatch::SteadyFlow) => " steady-flow",
                Some(FrictionMatch::StartStop) => " start-stop",
                Some(FrictionMatch::PlaneStrain) => " plane-strain",
                None => "",
            },
            match self.stress_last {
                Some(true) => " stress-last",
                Some(false) => " stress-first",
                None => "",
            }
        )
    }
}

pub fn kernel_name(k: KernelKind) -> &'static str {
    match k {
        KernelKind::Linear => "linear",
        KernelKind::QuadraticBspline => "bspline",
        KernelKind::Gimp => "gimp",
    }
}

/// The cost of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Cost {
    pub wall_seconds: f64,
    pub steps: u64,
    pub particles: usize,
}

/// Loads a validation scene and applies `n`. A domain side that is not a whole number of the
/// chosen cells grows to the next whole number (the walls lie on grid nodes; a column's height
/// over 10, 20 or 40 cells need not divide the box); sides that are whole stay as written.
pub fn load(file: &str, n: &Numerics) -> SceneConfig {
    let mut scene = SceneConfig::load(&scene_path(file))
        .unwrap_or_else(|e| panic!("validation scene {file}: {e}"));
    n.apply(&mut scene);
    let h = scene.cell_size;
    for side in scene.domain.size.iter_mut() {
        let cells = *side / h;
        if (cells - cells.round()).abs() > 1e-6 {
            *side = cells.ceil() * h;
        }
    }
    scene
}

fn cost<D: Dim>(sim: &Simulation<D>, start: Instant) -> Cost {
    Cost {
        wall_seconds: start.elapsed().as_secs_f64(),
        steps: sim.steps(),
        particles: sim.particles().len(),
    }
}

/// Initial positions by particle id (ids are given in creation order and survive reordering).
fn rest_positions<D: Dim>(sim: &Simulation<D>) -> Vec<[f64; 3]> {
    let p = sim.particles();
    let mut rest = vec![[0.0; 3]; p.len()];
    for i in 0..p.len() {
        for a in 0..D::DIM {
            rest[p.id[i] as usize][a] = p.x[i][a] as f64;
        }
    }
    rest
}

/// The comma-separated list at position `i` of an example's arguments, or `default`'s.
pub fn arg_list(args: &[String], i: usize, default: &str) -> Vec<String> {
    args.get(i)
        .map_or(default, |s| s.as_str())
        .split(',')
        .map(str::to_string)
        .collect()
}

/// The cell sizes of such a list, each in [0.001, 0.05] m.
pub fn cell_sizes(list: &[String]) -> Result<Vec<f64>, String> {
    list.iter()
        .map(|a| {
            a.parse()
                .ok()
                .filter(|h| (0.001..=0.05).contains(h))
                .ok_or(format!("h: `{a}` is not a cell size in [0.001, 0.05] m"))
        })
        .collect()
}

/// The particle spacing of body 0 (cell size / particles per cell).
pub fn spacing(scene: &SceneConfig) -> f64 {
    scene.cell_size / scene.bodies[0].particles_per_cell as f64
}

// ---------------------------------------------------------------------------------------------
// Elastic: the free–free bar

/// The first axial mode of a free–free bar, against u(x, t) = (v0/ω) sin ωt cos(π x/L),
/// ω = π c/L, c = √(E/ρ) (ν = 0, so plane strain, plane stress and 3D agree).
#[derive(Clone, Debug)]
pub struct Bar {
    pub period: f64,
    pub period_exact: f64,
    /// Mean peak modal displacement over the run.
    pub amplitude: f64,
    pub amplitude_exact: f64,
    /// The last peak over the first: how much of the amplitude survives the run.
    pub amplitude_kept: f64,
    /// ‖q − q_exact‖₂ / ‖q_exact‖₂ over the run (the modal displacement history).
    pub l2_error: f64,
    /// Why the run stopped early (the solver's error and the time), if it did.
    pub failure: Option<String>,
    pub cost: Cost,
}

impl Bar {
    pub fn period_error(&self) -> f64 {
        self.period / self.period_exact - 1.0
    }
    pub fn amplitude_error(&self) -> f64 {
        self.amplitude / self.amplitude_exact - 1.0
    }
}

/// Runs the bar of `file` for `periods` analytic periods with initial modal velocity `v0`.
pub fn vibrating_bar<D: Dim>(file: &str, n: &Numerics, periods: f64) -> Bar {
    let scene = load(file, n);
    let Material::Elastic(m) = scene.bodies[0].material else {
        panic!("the bar is elastic");
    };
    assert_eq!(m.poisson_ratio, 0.0, "the bar's closed form needs ν = 0");
    let c = (m.youngs_modulus / m.density).sqrt();
    let s = spacing(&scene);
    let mut sim = Simulation::<D>::new(scene).expect("bar scene");
    let rest = rest_positions(&sim);
    let lo = rest.iter().map(|r| r[0]).fold(f64::INFINITY, f64::min) - 0.5 * s;
    let hi = rest.iter().map(|r| r[0]).fold(f64::NEG_INFINITY, f64::max) + 0.5 * s;
    let len = hi - lo;
    let omega = std::f64::consts::PI * c / len;
    let v0 = 0.05;
    let mode = |x: f64| (std::f64::consts::PI * (x - lo) / len).cos();
    let norm: f64 = rest.iter().map(|r| mode(r[0]).powi(2)).sum();
    {
        let p = sim.particles_mut();
        for i in 0..p.len() {
            p.v[i][0] = (v0 * mode(rest[p.id[i] as usize][0])) as Real;
        }
    }
    sim.refresh_diagnostics();
    let period_exact = 2.0 * std::f64::consts::PI / omega;
    let amplitude_exact = v0 / omega;
    let start = Instant::now();
    let (mut t, mut q) = (vec![0.0], vec![0.0]);
    let (mut err2, mut ref2) = (0.0, 0.0);
    let mut failure = None;
    while sim.time() < periods * period_exact {
        let dt = sim.stable_dt();
        if let Err(e) = sim.step() {
            failure = Some(format!("at t = {:.4} s: {e}", sim.time()));
            break;
        }
        let p = sim.particles();
        let s: f64 = (0..p.len())
            .map(|i| {
                let r = rest[p.id[i] as usize][0];
                (p.x[i][0] as f64 - r) * mode(r)
            })
            .sum::<f64>()
            / norm;
        let exact = amplitude_exact * (omega * sim.time()).sin();
        err2 += (s - exact).powi(2) * dt;
        ref2 += exact.powi(2) * dt;
        t.push(sim.time());
        q.push(s);
    }
    let cost = cost(&sim, start);
    let zc = zero_crossings(&t, &q);
    // zero crossings after the start (q(0) = 0 is not one)
    let zc: Vec<f64> = zc.into_iter().filter(|&z| z > 0.1 * period_exact).collect();
    let period = if zc.len() >= 2 {
        (zc[zc.len() - 1] - zc[0]) / (zc.len() - 1) as f64 * 2.0
    } else {
        f64::NAN
    };
    let peaks = peaks(&q);
    let amplitude = if peaks.is_empty() {
        f64::NAN
    } else {
        peaks.iter().sum::<f64>() / peaks.len() as f64
    };
    let amplitude_kept = match (peaks.first(), peaks.last()) {
        (Some(a), Some(b)) => b / a,
        _ => f64::NAN,
    };
    Bar {
        period,
        period_exact,
        amplitude,
        amplitude_exact,
        amplitude_kept,
        l2_error: (err2 / ref2).sqrt(),
        failure,
        cost,
    }
}

/// Zero crossings (linear interpolation) of a sampled signal.
pub fn zero_crossings(t: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 1..y.len() {
        if y[i - 1] != 0.0 && (y[i - 1] < 0.0) != (y[i] < 0.0) {
            let f = y[i - 1] / (y[i - 1] - y[i]);
            out.push(t[i - 1] + f * (t[i] - t[i - 1]));
        }
    }
    out
}

/// |y| at each local extremum of the half-waves of a signal (one per half-period).
fn peaks(y: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    let mut best = 0.0f64;
    for i in 1..y.len() {
        if (y[i - 1] < 0.0) != (y[i] < 0.0) && y[i - 1] != 0.0 {
            if best > 0.0 {
                out.push(best);
            }
            best = 0.0;
        }
        best = best.max(y[i].abs());
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Elastic: the dilatational wave speed

/// A Gaussian pressure pulse in a slab held between slip walls (uniaxial strain) splits into
/// two compressive pulses travelling at c_p = √((K + 4G/3)/ρ); their kinetic-energy centroids
/// are tracked.
#[derive(Clone, Debug)]
pub struct Wave {
    pub speed: f64,
    pub speed_exact: f64,
    /// The bar speed √(E/ρ), which a wrong constraint would give.
    pub bar_speed: f64,
    pub cost: Cost,
}

impl Wave {
    pub fn error(&self) -> f64 {
        self.speed / self.speed_exact - 1.0
    }
}

pub fn wave_speed(n: &Numerics) -> Wave {
    let scene = load("wave_pulse_2d.json", n);
    let Material::Elastic(m) = scene.bodies[0].material else {
        panic!("the slab is elastic");
    };
    let (e, nu, rho) = (m.youngs_modulus, m.poisson_ratio, m.density);
    let k = e / (3.0 * (1.0 - 2.0 * nu));
    let g = e / (2.0 * (1.0 + nu));
    let speed_exact = ((k + 4.0 * g / 3.0) / rho).sqrt();
    let length = scene.domain.size[0];
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("wave scene");
    let rest = rest_positions(&sim);
    // a compressive pressure pulse in uniaxial strain (σ_yy = σ_zz = ν/(1 − ν) σ_xx), at rest:
    // it splits into two compressive halves, which the slip walls confine laterally
    let (xc, width, s0) = (0.5 * length, 0.1, 1.0e3);
    let lateral = nu / (1.0 - nu);
    {
        let p = sim.particles_mut();
        for i in 0..p.len() {
            let x = rest[p.id[i] as usize][0];
            let sxx = -s0 * (-((x - xc) / width).powi(2)).exp();
            p.stress[i] = mpm::math::Sym2 {
                xx: sxx as Real,
                yy: (lateral * sxx) as Real,
                zz: (lateral * sxx) as Real,
                xy: 0.0,
            };
        }
    }
    sim.refresh_diagnostics();
    // travel 30 % of the half-length: the pulses stay clear of the end walls
    let t_end = 0.3 * 0.5 * length / speed_exact;
    let t_start = 3.0 * width / speed_exact; // the two halves have separated
    let start = Instant::now();
    let (mut ts, mut right, mut left) = (Vec::new(), Vec::new(), Vec::new());
    while sim.time() < t_end {
        sim.step().expect("wave step");
        if sim.time() < t_start {
            continue;
        }
        let p = sim.particles();
        let (mut wr, mut xr, mut wl, mut xl) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..p.len() {
            let x = rest[p.id[i] as usize][0];
            let w = (p.v[i][0] as f64).powi(2) + (p.v[i][1] as f64).powi(2);
            if x > xc {
                wr += w;
                xr += w * x;
            } else {
                wl += w;
                xl += w * x;
            }
        }
        ts.push(sim.time());
        right.push(xr / wr);
        left.push(xl / wl);
    }
    let speed = 0.5 * (slope(&ts, &right) - slope(&ts, &left));
    Wave {
        speed,
        speed_exact,
        bar_speed: (e / rho).sqrt(),
        cost: cost(&sim, start),
    }
}

/// Least-squares slope of y(x).
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    mpm::measure::slope(x, y)
}

// ---------------------------------------------------------------------------------------------
// von Mises: a block squeezed by a driven plate

/// The stress–strain curve of a von Mises block squeezed between a slip floor and a driven
/// frictionless plate, against the closed form (uniaxial stress in 3D: σ = Eε up to σ_y,
/// then σ_y; plane strain in 2D, see [`plane_strain_curve`]).
#[derive(Clone, Debug)]
pub struct Squeeze {
    /// (strain, mean axial stress in the block (compression positive), closed form).
    pub curve: Vec<(f64, f64, f64)>,
    pub yield_stress: f64,
    pub youngs_modulus: f64,
    /// The largest |σ − σ_exact| over the curve, relative to σ_y.
    pub max_error: f64,
    /// Mean relative error of the plastic plateau (strain above twice the yield strain).
    pub plateau_error: f64,
    /// Slope of the elastic part (below 60 % of the yield strain) against the closed form.
    pub modulus_error: f64,
    pub cost: Cost,
}

/// Plate speed (m/s) after the ramp, and the ramp time (s).
pub const PLATE_SPEED: f64 = 0.01;
pub const PLATE_RAMP: f64 = 0.05;

pub fn squeeze<D: Dim>(file: &str, n: &Numerics, max_strain: f64) -> Squeeze {
    let scene = load(file, n);
    let Material::VonMises(m) = scene.bodies[0].material else {
        panic!("the block is von Mises");
    };
    let (e, nu, sy) = (m.youngs_modulus, m.poisson_ratio, m.yield_stress);
    let s = spacing(&scene);
    let mut sim = Simulation::<D>::new(scene).expect("squeeze scene");
    sim.sort_interval = 0; // keep the plate's particles where the driver finds them
    let rest = rest_positions(&sim);
    let block = sim.bodies()[0].range();
    let plate = sim.bodies()[1].range();
    let top = block
        .clone()
        .map(|i| rest[i][1])
        .fold(f64::NEG_INFINITY, f64::max);
    let top_row: Vec<usize> = block
        .clone()
        .filter(|&i| rest[i][1] > top - 0.5 * s)
        .collect();
    let y0 = top_row.iter().map(|&i| rest[i][1]).sum::<f64>() / top_row.len() as f64;
    // the closed form, tabulated up to beyond the largest strain
    let table_max = 1.5 * max_strain;
    let table = plane_strain_curve(e, nu, sy, table_max, 3000);
    let exact = |strain: f64| {
        if D::DIM == 3 {
            (e * strain).min(sy)
        } else {
            let f = (strain.max(0.0) / table_max * (table.len() - 1) as f64)
                .min((table.len() - 1) as f64 - 1e-9);
            let k = f as usize;
            table[k] + (f - k as f64) * (table[k + 1] - table[k])
        }
    };
    // strain at first yield: σ_y/E in 3D; σ_y/√(1 − ν + ν²) over E/(1 − ν²) in plane strain
    let yield_strain = if D::DIM == 3 {
        sy / e
    } else {
        sy / (1.0 - nu + nu * nu).sqrt() * (1.0 - nu * nu) / e
    };
    let start = Instant::now();
    let mut curve = Vec::new();
    loop {
        let v = PLATE_SPEED * (sim.time() / PLATE_RAMP).min(1.0);
        {
            let p = sim.particles_mut();
            for i in plate.clone() {
                p.v[i] = D::Vector::from_fn(|a| if a == 1 { -v as Real } else { 0.0 });
            }
        }
        sim.step().expect("squeeze step");
        let p = sim.particles();
        let y = top_row.iter().map(|&i| p.x[i][1] as f64).sum::<f64>() / top_row.len() as f64;
        let strain = (y0 - y) / y0;
        let (mut sv, mut vol) = (0.0, 0.0);
        for i in block.clone() {
            sv += -(p.stress[i].components()[1] as f64) * p.volume[i] as f64;
            vol += p.volume[i] as f64;
        }
        let stress = sv / vol;
        curve.push((strain, stress, exact(strain)));
        if strain > max_strain {
            break;
        }
    }
    let cost = cost(&sim, start);
    let max_error = curve
        .iter()
        .filter(|c| c.0 > 0.2 * yield_strain)
        .map(|c| (c.1 - c.2).abs() / sy)
        .fold(0.0, f64::max);
    let plateau: Vec<f64> = curve
        .iter()
        .filter(|c| c.0 > 2.0 * yield_strain)
        .map(|c| c.1 / c.2 - 1.0)
        .collect();
    let plateau_error = plateau.iter().sum::<f64>() / plateau.len().max(1) as f64;
    let elastic: Vec<&(f64, f64, f64)> = curve
        .iter()
        .filter(|c| c.0 > 0.1 * yield_strain && c.0 < 0.6 * yield_strain)
        .collect();
    let xs: Vec<f64> = elastic.iter().map(|c| c.0).collect();
    let modulus = slope(&xs, &elastic.iter().map(|c| c.1).collect::<Vec<_>>());
    let modulus_exact = slope(&xs, &elastic.iter().map(|c| c.2).collect::<Vec<_>>());
    Squeeze {
        curve,
        yield_stress: sy,
        youngs_modulus: e,
        max_error,
        plateau_error,
        modulus_error: modulus / modulus_exact - 1.0,
        cost,
    }
}

/// The closed form of plane-strain uniaxial compression of an elastic–perfectly plastic von
/// Mises material (σ_xx = 0, ε_zz = 0, compression ε along y): the axial stress (compression
/// positive) at the strains `k · max_strain / n`, k = 0..=n. Elastic: σ = E/(1 − ν²) ε with
/// σ_zz = ν σ_yy, up to the first yield at σ_y/√(1 − ν + ν²); then the out-of-plane stress
/// relaxes towards the mean of the in-plane ones and σ tends to the plane-strain limit
/// 2σ_y/√3. Integrated with small strain increments (20 per entry) and an independent radial
/// return in principal stresses.
pub fn plane_strain_curve(e: f64, nu: f64, sy: f64, max_strain: f64, n: usize) -> Vec<f64> {
    let g = e / (2.0 * (1.0 + nu));
    let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let sub = 20;
    let de_y = -max_strain / (n * sub) as f64;
    // the stress after a strain increment (dx, de_y, 0) from `s` (xx, yy, zz)
    let update = |s: [f64; 3], dx: f64| -> [f64; 3] {
        let d = [dx, de_y, 0.0];
        let tr = d[0] + d[1] + d[2];
        let mut t = [0.0; 3];
        for a in 0..3 {
            t[a] = s[a] + lam * tr + 2.0 * g * d[a];
        }
        let p = (t[0] + t[1] + t[2]) / 3.0;
        let dev = [t[0] - p, t[1] - p, t[2] - p];
        let q = (1.5 * (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2])).sqrt();
        if q > sy {
            let f = sy / q;
            for a in 0..3 {
                t[a] = p + dev[a] * f;
            }
        }
        t
    };
    let mut s = [0.0f64; 3];
    let mut out = vec![0.0];
    for _ in 0..n {
        for _ in 0..sub {
            // σ_xx = 0: bisection on the lateral strain increment (σ_xx grows with it)
            let (mut lo, mut hi) = (-10.0 * de_y.abs(), 10.0 * de_y.abs());
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if update(s, mid)[0] > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            s = update(s, 0.5 * (lo + hi));
        }
        out.push(-s[1]);
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Drucker–Prager: granular column collapse

/// The plane (2D) collapse of a granular column of half-width L0 and height H0 = a L0 on a
/// rough floor: normalised run-out (L∞ − L0)/L0 and final height H∞/H0.
///
/// Two run-outs are reported, since a deposit ends in a thin tail whose length depends on
/// the resolution: `runout`, the farthest particle of the deposit (its end at the first gap
/// wider than two particle spacings, [`deposit_front`]), and `runout_edge`, the edge of the
/// continuous deposit: the first distance from the axis at which the deposit's thickness,
/// averaged over a window of [`EDGE_WINDOW`], drops below [`EDGE_THICKNESS`] of H0
/// ([`deposit_edge`]).
#[derive(Clone, Debug)]
pub struct Collapse {
    pub aspect_ratio: f64,
    pub runout: f64,
    pub runout_edge: f64,
    /// (L − L0)/L0 (or (R − R0)/R0) with L where the deposit is one grain ([`GRAIN`]) thick
    /// ([`runout_at_thickness`]): the run-out the bands hold.
    pub runout_thin: f64,
    /// The flank: least-squares slope (degrees) of the surface between 20 % and 80 % of the
    /// deposit's height, the mean of the two sides (plane) or of the radial profile (3D).
    pub flank: f64,
    pub height: f64,
    /// Axisymmetric runs: the largest minus the smallest front over the azimuthal sectors,
    /// over R0 (how far the deposit is from round); 0 for plane runs.
    pub spread: f64,
    /// Time at which the deposit came to rest (s).
    pub settled_at: f64,
    /// Why the run stopped early, if it did.
    pub failure: Option<String>,
    pub cost: Cost,
}

/// The plane column collapses of aspect ratio a = 0.5, 1, 2 and 3 (scene file, a).
pub const PLANE_COLLAPSES: [(&str, f64); 4] = [
    ("column_collapse_a0.5_2d.json", 0.5),
    ("column_collapse_a1_2d.json", 1.0),
    ("column_collapse_a2_2d.json", 2.0),
    ("column_collapse_a3_2d.json", 3.0),
];

/// Lube, Huppert, Sparks & Freundt (2005), plane collapses: (L∞ − L0)/L0 = 1.2 a for
/// a ≲ 2.3, 1.9 a^(2/3) above.
pub fn lube_runout(a: f64) -> f64 {
    mpm::laws::lube_runout(a)
}

/// Lube et al. (2005), plane collapses: H∞/H0 = 1 for a ≲ 1.15 (the top is not reached by
/// the failure), H∞/L0 ≈ a^(2/5) above, i.e. H∞/H0 = a^(−3/5).
pub fn lube_height(a: f64) -> f64 {
    mpm::laws::lube_height(a)
}

/// A deposit counts as at rest when no particle is faster than this share of √(g H0): 0.1 %
/// (with 1 % a PIC deposit that still crept was taken for at rest, and its run-out grew
/// by another 6 % before 4 s).
pub const REST_SPEED: f64 = 1e-3;

/// Runs a collapse until every particle is slower than [`REST_SPEED`] √(g H0) (after at
/// least 4 √(H0/g)) or until `t_max`; returns why the run stopped early, if it did. A run
/// whose time step collapses (particles flung out at high speed) is stopped after ten times
/// the steps it would take at the initial time step.
fn run_until_rest<D: Dim>(sim: &mut Simulation<D>, h0: f64, g: f64, t_max: f64) -> Option<String> {
    run_until_rest_with(sim, h0, g, t_max, 0.02, |_| ())
}

/// [`run_until_rest`] advancing `interval` s at a time and calling `between` on the
/// simulation after each interval (to act on the particles as the run goes).
fn run_until_rest_with<D: Dim>(
    sim: &mut Simulation<D>,
    h0: f64,
    g: f64,
    t_max: f64,
    interval: f64,
    mut between: impl FnMut(&mut Simulation<D>),
) -> Option<String> {
    let t_min = 4.0 * (h0 / g).sqrt();
    let rest_speed = REST_SPEED * (g * h0).sqrt();
    let budget = (10.0 * t_max / sim.stable_dt()) as u64;
    loop {
        if let Err(e) = sim.advance(interval) {
            return Some(e.to_string());
        }
        between(sim);
        let t = sim.time();
        if (t > t_min && sim.diagnostics().max_speed < rest_speed) || t >= t_max {
            return None;
        }
        if sim.steps() > budget {
            return Some(format!(
                "stopped after {} steps at {t:.2} s: the time step fell to {:.1e} s (max speed {:.1} m/s)",
                sim.steps(),
                sim.diagnostics().dt,
                sim.diagnostics().max_speed
            ));
        }
    }
}

/// The end of a deposit along a ray: `d` holds the distances of the particles from the
/// centre (any order); the deposit ends at the first gap wider than two particle spacings
/// `s` beyond `from` (gaps nearer the centre are ignored: an axisymmetric run's narrow
/// sectors hold few particles near the axis), and the last particle stands for half a
/// spacing of material beyond its centre.
pub fn deposit_front(d: Vec<f64>, s: f64, from: f64) -> f64 {
    mpm::measure::deposit_front(d, s, from)
}

pub use mpm::measure::{GRAIN, runout_at_thickness};

/// The band of a run-out read at one grain's thickness, relative to the published law
/// (Lube et al. 2005 for plane columns, 2004 for axisymmetric ones): −20 % to +25 %.
pub const RUNOUT_BAND: [f64; 2] = [-0.2, 0.25];
/// The band of a collapse deposit's flank against φ_ps (degrees): real deposits of low
/// columns are concave and rest under the angle of repose.
pub const FLANK_BAND: [f64; 2] = [-6.0, 1.0];
/// The band of a failed slope's or a heap's resting angle against φ_ps (degrees): a failed
/// slope comes to rest only slightly under the angle of repose (Siavoshi & Kudrolli 2005).
pub const REST_BAND: [f64; 2] = [-5.0, 1.0];

/// Whether a plane collapse of aspect ratio `a` is held to [`FLANK_BAND`]: a low column,
/// whose top the failure does not reach (H∞ = H0 for a ≲ 1.15, Lube et al. 2005), rests as a
/// plateau with flanks; a taller one leaves a concave cone whose 20–80 % slope lies well under
/// the angle of repose.
pub fn flank_band_applies(a: f64) -> bool {
    a < 1.15
}

/// Whether `x` lies in `band` (inclusive).
pub fn within(x: f64, band: [f64; 2]) -> bool {
    x >= band[0] && x <= band[1]
}

/// The run-out's relative error against Lube et al. (2005)'s plane law, or against the range
/// its two regimes span at a = 2 (0 inside it).
pub fn plane_runout_error(runout: f64, a: f64) -> f64 {
    let [low, high] = mpm::laws::lube_runout_range(a);
    if runout < low {
        runout / low - 1.0
    } else if runout > high {
        runout / high - 1.0
    } else {
        0.0
    }
}

/// The farthest particle's sanity bound: (L − L0)/L0 at most 2a.
pub fn farthest_is_sane(runout: f64, a: f64) -> bool {
    runout <= 2.0 * a
}

/// Width of the window over which the deposit's thickness is averaged for its edge (m; at
/// least two particle spacings): one hole in a thin tail would otherwise end the deposit.
pub const EDGE_WINDOW: f64 = 0.01;
/// The deposit's edge is where its thickness drops below this share of H0.
pub const EDGE_THICKNESS: f64 = 0.025;

/// The edge of a deposit along a ray: `d` holds the distances of the particles from the axis
/// (any order), each particle standing for the material `amount` gives at its distance (an
/// area s² in a plane deposit, a volume s³ in an axisymmetric one), `band(r0, r1)` is the
/// floor area between distances r0 and r1 (its length in a plane, an annulus's area about an
/// axis). The thickness at r is the material within half a window of r over the window's
/// floor area; the edge is the first r, stepping out from the axis by an eighth of a spacing
/// `s`, where it drops below `min_thickness`.
fn deposit_edge(
    d: Vec<f64>,
    s: f64,
    amount: f64,
    band: impl Fn(f64, f64) -> f64,
    min_thickness: f64,
) -> f64 {
    mpm::measure::deposit_edge(d, s, amount, band, EDGE_WINDOW, min_thickness)
}

/// A plane column's centre x_c and half-width L0 from its particles (spacing `s`: each
/// particle's material reaches half a spacing beyond its centre).
pub fn column_extent<D: Dim>(sim: &Simulation<D>, s: f64) -> (f64, f64) {
    mpm::measure::column_extent(sim.particles().x.iter().map(|x| x[0] as f64), s)
}

pub fn column_collapse(file: &str, n: &Numerics, t_max: f64) -> Collapse {
    let scene = load(file, n);
    let s = spacing(&scene);
    let g = scene.gravity_vector()[1].abs();
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("column scene");
    let rest = rest_positions(&sim);
    let (xc, l0) = column_extent(&sim, s);
    let h0 = rest.iter().map(|r| r[1]).fold(0.0, f64::max) + 0.5 * s;
    let start = Instant::now();
    let failure = run_until_rest(&mut sim, h0, g, t_max);
    let settled_at = sim.time();
    let cost = cost(&sim, start);
    let p = sim.particles();
    let front = |sign: f64| {
        deposit_front(
            (0..p.len())
                .map(|i| sign * (p.x[i][0] as f64 - xc))
                .filter(|&d| d > 0.0)
                .collect(),
            s,
            0.0,
        )
    };
    let l_inf = 0.5 * (front(1.0) + front(-1.0));
    let edge = |sign: f64| {
        deposit_edge(
            (0..p.len())
                .map(|i| sign * (p.x[i][0] as f64 - xc))
                .filter(|&d| d > 0.0)
                .collect(),
            s,
            s * s,
            |r0, r1| r1 - r0,
            EDGE_THICKNESS * h0,
        )
    };
    let l_edge = 0.5 * (edge(1.0) + edge(-1.0));
    let h = sim.cell_size();
    let sides = [1.0, -1.0].map(|sign: f64| {
        let pts: Vec<(f64, f64)> = (0..p.len())
            .map(|i| (sign * (p.x[i][0] as f64 - xc), p.x[i][1] as f64))
            .filter(|q| q.0 >= 0.0)
            .collect();
        measure_deposit(&pts, s, h, l0, h0)
    });
    let h_inf = (0..p.len())
        .filter(|&i| (p.x[i][0] as f64 - xc).abs() < l0)
        .map(|i| p.x[i][1] as f64)
        .fold(0.0, f64::max)
        + 0.5 * s;
    Collapse {
        aspect_ratio: h0 / l0,
        runout: (l_inf - l0) / l0,
        runout_edge: (l_edge - l0) / l0,
        runout_thin: 0.5 * (sides[0].runout_thin + sides[1].runout_thin),
        flank: 0.5 * (sides[0].flank() + sides[1].flank()),
        height: h_inf / h0,
        spread: 0.0,
        settled_at,
        failure,
        cost,
    }
}

/// Lube, Huppert, Sparks & Hallworth (2004) and Lajeunesse, Mangeney-Castelnau & Vilotte
/// (2004), axisymmetric collapses: (R∞ − R0)/R0 = 1.24 a for a ≲ 1.7, 1.6 a^(1/2) above.
pub fn lube_axisymmetric_runout(a: f64) -> f64 {
    mpm::laws::lube_axisymmetric_runout(a)
}

/// Lube et al. (2004), axisymmetric collapses: H∞/R0 = a for a ≲ 0.74 (the top is not
/// reached by the failure), H∞/R0 ≈ 0.88 a^(1/6) above; returned as H∞/H0.
pub fn lube_axisymmetric_height(a: f64) -> f64 {
    mpm::laws::lube_axisymmetric_height(a)
}

/// Lajeunesse, Mangeney-Castelnau & Vilotte (2004), axisymmetric collapses: H∞/R0 = a for
/// a ≲ 0.74, then about 0.74 whatever a; returned as H∞/H0.
pub fn lajeunesse_axisymmetric_height(a: f64) -> f64 {
    mpm::laws::lajeunesse_axisymmetric_height(a)
}

/// Azimuthal sectors over which the front of an axisymmetric deposit is measured.
const SECTORS: usize = 16;

/// The axisymmetric (3D) collapse of a cylindrical column of radius R0 and height H0 = a R0
/// on a rough floor: normalised run-out (R∞ − R0)/R0 (R∞ the mean over [`SECTORS`] azimuthal
/// sectors of the deposit's front; the edge of the continuous deposit from its thickness
/// averaged over annuli about the axis) and final height H∞/H0 (the highest particle within
/// R0 of the axis). R0 is the radius of the cylinder of height H0 holding the sampled volume.
pub fn axisymmetric_collapse(file: &str, n: &Numerics, t_max: f64) -> Collapse {
    let scene = load(file, n);
    let s = spacing(&scene);
    let g = scene.gravity_vector()[1].abs();
    let mut sim = Simulation::<mpm::D3>::new(scene).expect("column scene");
    let rest = rest_positions(&sim);
    let count = rest.len() as f64;
    let (xc, zc) = (
        rest.iter().map(|r| r[0]).sum::<f64>() / count,
        rest.iter().map(|r| r[2]).sum::<f64>() / count,
    );
    let h0 = rest.iter().map(|r| r[1]).fold(0.0, f64::max) + 0.5 * s;
    let r0 = (count * s.powi(3) / (std::f64::consts::PI * h0)).sqrt();
    let start = Instant::now();
    let failure = run_until_rest(&mut sim, h0, g, t_max);
    let settled_at = sim.time();
    let cost = cost(&sim, start);
    let p = sim.particles();
    let mut sectors = vec![Vec::new(); SECTORS];
    let mut h_inf = 0.0f64;
    for i in 0..p.len() {
        let (dx, dz) = (p.x[i][0] as f64 - xc, p.x[i][2] as f64 - zc);
        let r = dx.hypot(dz);
        let k = ((dz.atan2(dx) / std::f64::consts::TAU + 0.5) * SECTORS as f64) as usize;
        sectors[k.min(SECTORS - 1)].push(r);
        if r < r0 {
            h_inf = h_inf.max(p.x[i][1] as f64 + 0.5 * s);
        }
    }
    let all: Vec<f64> = sectors.iter().flatten().copied().collect();
    let r_edge = deposit_edge(
        all,
        s,
        s.powi(3),
        |r0, r1| std::f64::consts::PI * (r1 * r1 - r0 * r0),
        EDGE_THICKNESS * h0,
    );
    let fronts: Vec<f64> = sectors
        .into_iter()
        .map(|d| deposit_front(d, s, r0))
        .collect();
    let r_inf = fronts.iter().sum::<f64>() / SECTORS as f64;
    let points: Vec<[f64; 3]> = (0..p.len())
        .map(|i| [0, 1, 2].map(|a| p.x[i][a] as f64))
        .collect();
    let profile = mpm::measure::radial_profile(&points, [xc, zc]);
    let r_thin = runout_at_thickness(&profile, s, sim.cell_size(), r0, GRAIN);
    let flank = mpm::measure::radial_heap(&points, s, sim.cell_size(), [xc, zc]).flanks[1]
        .map_or(f64::NAN, |f| f.angle);
    let (min, max) = fronts
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &f| (a.min(f), b.max(f)));
    Collapse {
        aspect_ratio: h0 / r0,
        runout: (r_inf - r0) / r0,
        runout_edge: (r_edge - r0) / r0,
        runout_thin: (r_thin - r0) / r0,
        flank,
        height: h_inf / h0,
        spread: (max - min) / r0,
        settled_at,
        failure,
        cost,
    }
}

// ---------------------------------------------------------------------------------------------
// Drucker–Prager: the angle of repose

/// The angle of repose by the lifted-cylinder method: a sand column between two smooth walls
/// that are lifted slowly ([`LIFT_SPEED`], [`SLOW_LIFT_SPEED`]); the sand flows out beneath
/// them and comes to rest as a heap whose flanks stand at the angle of repose.
#[derive(Clone, Debug)]
pub struct Pile {
    pub friction_angle: f64,
    /// The friction angle of the Mohr–Coulomb criterion the model's cone matches in plane
    /// strain with ψ = 0: sin φ_ps = 3 α_φ (Eq. 13's α_φ = tan φ/√(9 + 12 tan² φ)).
    pub plane_strain_angle: f64,
    /// The slope below which a steadily flowing layer of the sand stops, θ* = atan(3 α_φ)
    /// of the body's friction match (degrees; φ itself with the steady-flow match).
    pub stopping_angle: f64,
    /// Mean of the two flanks (degrees).
    pub angle: f64,
    pub flanks: [f64; 2],
    /// Height of the heap (m).
    pub height: f64,
    pub settled_at: f64,
    pub cost: Cost,
}

/// Speed at which the walls are lifted (m/s): √(g H) / 30 for the 0.2 m column.
pub const LIFT_SPEED: f64 = 0.05;
/// A slower lift, √(g H) / 70: closer to the quasi-static limit.
pub const SLOW_LIFT_SPEED: f64 = 0.02;
/// Slower still, √(g H) / 140: to check that [`SLOW_LIFT_SPEED`] is quasi-static.
pub const SLOWEST_LIFT_SPEED: f64 = 0.01;

/// How long a [`repose_pile`] run lasts with the walls lifted at `lift_speed` (m/s): the walls
/// clearing the 0.24 m column with a fifth to spare, then 6 s for the heap to settle.
pub fn repose_duration(lift_speed: f64) -> f64 {
    1.2 * 0.24 / lift_speed + 6.0
}

/// The plane-strain Mohr–Coulomb angle of the paper's Drucker–Prager cone with ψ = 0.
pub fn plane_strain_angle(phi_deg: f64) -> f64 {
    mpm::laws::plane_strain_angle(phi_deg)
}

/// `phi` replaces the scene's friction angle (degrees) when given; the walls rise at
/// `lift_speed` (m/s) until they clear the sand.
pub fn repose_pile(n: &Numerics, t_max: f64, phi: Option<f64>, lift_speed: f64) -> Pile {
    let mut scene = load("repose_pile_2d.json", n);
    // another friction angle, on a floor as rough as the sand (μ = tan φ)
    if let (Some(phi), Material::DruckerPrager(m)) = (phi, &mut scene.bodies[0].material) {
        m.friction_angle = phi;
        scene.boundary.friction = phi.to_radians().tan();
    }
    let Material::DruckerPrager(m) = scene.bodies[0].material else {
        panic!("the pile is sand");
    };
    let s = spacing(&scene);
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("pile scene");
    sim.sort_interval = 0; // the walls' particles stay where the driver finds them
    let walls: Vec<usize> = sim.bodies()[1..].iter().flat_map(|b| b.range()).collect();
    let sand = sim.bodies()[0].range();
    let h0 = sand
        .clone()
        .map(|i| sim.particles().x[i][1] as f64)
        .fold(0.0, f64::max)
        + 0.5 * s;
    let lift = <mpm::D2 as Dim>::Vector::from_fn(|a| if a == 1 { lift_speed as Real } else { 0.0 });
    let start = Instant::now();
    // lift until the walls clear the sand, then let it settle
    let t_clear = 1.2 * h0 / lift_speed;
    loop {
        for _ in 0..50 {
            // lifted until they clear the sand, then held
            let v = if sim.time() < t_clear {
                lift
            } else {
                <mpm::D2 as Dim>::Vector::ZERO
            };
            {
                let p = sim.particles_mut();
                for &i in &walls {
                    p.v[i] = v;
                }
            }
            sim.step().expect("pile step");
        }
        let p = sim.particles();
        let moving = sand
            .clone()
            .map(|i| p.v[i].length() as f64)
            .fold(0.0, f64::max);
        if (sim.time() > t_clear && moving < 0.005) || sim.time() >= t_max {
            break;
        }
    }
    let settled_at = sim.time();
    let cost = cost(&sim, start);
    if std::env::var("MPM_DEBUG_MAP").is_ok() {
        eprintln!("{}", ascii_map(&sim, 100, 25));
    }
    let p = sim.particles();
    let pile: Vec<(f64, f64)> = sand
        .clone()
        .map(|i| (p.x[i][0] as f64, p.x[i][1] as f64))
        .collect();
    let (height, flanks) = flank_angles(&pile, s, sim.cell_size(), sim.scene().domain.size[0]);
    Pile {
        friction_angle: m.friction_angle,
        plane_strain_angle: plane_strain_angle(m.friction_angle),
        stopping_angle: m.steady_shear_friction().atan().to_degrees(),
        angle: 0.5 * (flanks[0] + flanks[1]),
        flanks,
        height,
        settled_at,
        cost,
    }
}

/// The height of a heap of particles (spacing `s`) and the slope angles (degrees) of its two
/// flanks: the surface is the highest particle in columns of width `bin`; each flank's slope
/// is fitted between 20 % and 80 % of the height.
pub fn flank_angles(points: &[(f64, f64)], s: f64, bin: f64, width: f64) -> (f64, [f64; 2]) {
    mpm::measure::flank_angles(points, s, bin, width)
}

// ---------------------------------------------------------------------------------------------
// Elastic: a soft column resting on the floor (the cell-crossing study)

/// A soft elastic column (ν = 0) released stress-free on a frictionless floor settles to
/// u(Y) = −ρ g (H Y − Y²/2)/E; the top sinks by δ = ρ g H²/(2E).
#[derive(Clone, Debug)]
pub struct Resting {
    /// Top settlement (m), simulated (mean of the last tenth of the run) and exact.
    pub settlement: f64,
    pub settlement_exact: f64,
    /// Sinking rate of the top over the second half of the run (m/s; positive: sinking).
    pub drift_rate: f64,
    pub final_kinetic: f64,
    pub max_speed: f64,
    /// The error that stopped the run, if any.
    pub failure: Option<String>,
    pub cost: Cost,
}

impl Resting {
    pub fn error(&self) -> f64 {
        if self.failure.is_some() {
            return f64::INFINITY;
        }
        (self.settlement / self.settlement_exact - 1.0).abs()
    }
}

pub fn resting_column(n: &Numerics, duration: f64) -> Resting {
    let scene = load("resting_column_2d.json", n);
    let Material::Elastic(m) = scene.bodies[0].material else {
        panic!("the column is elastic");
    };
    assert_eq!(m.poisson_ratio, 0.0, "the closed form needs ν = 0");
    let s = spacing(&scene);
    let g = scene.gravity_vector()[1].abs();
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("resting scene");
    let rest = rest_positions(&sim);
    let h = rest.iter().map(|r| r[1]).fold(0.0, f64::max) + 0.5 * s;
    let top_row: Vec<u32> = (0..rest.len() as u32)
        .filter(|&i| rest[i as usize][1] > h - s)
        .collect();
    let y_top = rest[top_row[0] as usize][1];
    let exact = m.density * g * (h * y_top - 0.5 * y_top * y_top) / m.youngs_modulus;
    let start = Instant::now();
    let (mut ts, mut ds) = (Vec::new(), Vec::new());
    let mut failure = None;
    let sample = duration / 400.0;
    while sim.time() < duration {
        if let Err(e) = sim.advance(sample) {
            failure = Some(e.to_string());
            break;
        }
        let p = sim.particles();
        let mut sum = 0.0;
        let mut count = 0;
        for i in 0..p.len() {
            if rest[p.id[i] as usize][1] > h - s {
                sum += rest[p.id[i] as usize][1] - p.x[i][1] as f64;
                count += 1;
            }
        }
        ts.push(sim.time());
        ds.push(sum / count as f64);
    }
    let cost = cost(&sim, start);
    let n = ts.len();
    let tail = &ds[n - (n / 10).max(1)..];
    let half = n / 2;
    Resting {
        settlement: tail.iter().sum::<f64>() / tail.len() as f64,
        settlement_exact: exact,
        drift_rate: if n >= 4 {
            slope(&ts[half..], &ds[half..])
        } else {
            f64::NAN
        },
        final_kinetic: sim.diagnostics().kinetic,
        max_speed: sim.diagnostics().max_speed,
        failure,
        cost,
    }
}

/// A coarse character map of particle positions (for looking at a state while debugging).
pub fn ascii_map<D: Dim>(sim: &Simulation<D>, cols: usize, rows: usize) -> String {
    let size = &sim.scene().domain.size;
    let mut grid = vec![vec![b' '; cols]; rows];
    let p = sim.particles();
    for i in 0..p.len() {
        let c = ((p.x[i][0] as f64 / size[0]) * cols as f64) as usize;
        let r = ((p.x[i][1] as f64 / size[1]) * rows as f64) as usize;
        grid[rows - 1 - r.min(rows - 1)][c.min(cols - 1)] = b'#';
    }
    grid.into_iter()
        .map(|r| String::from_utf8(r).unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

// ---------------------------------------------------------------------------------------------
// Drucker–Prager: slopes that stand and slopes that fail

/// A symmetric heap (flat top 0.1 m wide, 0.1 m high, flanks at `slope` degrees) of sand with
/// friction angle `phi` released on a floor as rough as the sand (μ = tan φ). A cohesionless
/// slope gentler than the plane-strain friction angle φ_ps stands still; a steeper one cannot
/// stand: its surface layer accelerates at g (sin θ − cos θ tan φ_ps) and the flanks avalanche
/// down to about φ_ps.
#[derive(Clone, Debug)]
pub struct HeapSlope {
    /// The flank angle fitted at the start (the sampled staircase), after `duration`, and the
    /// plane-strain friction angle (degrees).
    pub initial_angle: f64,
    pub angle: f64,
    pub plane_strain_angle: f64,
    /// θ* = atan(3 α_φ) of the body's friction match (degrees; [`Pile::stopping_angle`]).
    pub stopping_angle: f64,
    /// When the flanks had come down halfway from their initial angle to φ_ps (s; `None` if
    /// they never did).
    pub failed_at: Option<f64>,
    /// The largest particle displacement between [`CREEP_FROM`] and the end (m): a slope that
    /// stands does not creep.
    pub creep: f64,
    /// Largest particle speed seen, and the speed at the end (m/s).
    pub peak_speed: f64,
    pub final_speed: f64,
    /// Widening of the heap (m).
    pub widening: f64,
    /// Mean over the first second (sampled every 0.01 s) of the fraction of the heap's
    /// particles whose stress the tension cut-off has returned to the cone's apex (zero
    /// pressure).
    pub apex_fraction: f64,
    pub cost: Cost,
}

/// The creep of a standing heap is measured from this time on (s), after the elastic settling
/// of the stress-free release.
pub const CREEP_FROM: f64 = 0.5;

/// The scene of [`heap_slope`]: a trapezoidal sand heap 0.1 m high with a 0.1 m top and flanks
/// at `slope` degrees, on a floor with μ = tan φ, under the numerics `n`.
pub fn heap_slope_scene(phi: f64, slope: f64, youngs_modulus: f64, n: &Numerics) -> SceneConfig {
    let (height, top) = (0.1, 0.05);
    let run = height / slope.to_radians().tan();
    let mut scene = SceneConfig::new(2, &[1.2, 0.4], n.cell_size);
    scene.boundary.friction = phi.to_radians().tan();
    scene.bodies.push(mpm::BodyConfig::new(
        "heap",
        mpm::Shape::polygon(&[
            [0.6 - top - run, 0.0],
            [0.6 + top + run, 0.0],
            [0.6 + top, height],
            [0.6 - top, height],
        ]),
        Material::drucker_prager(youngs_modulus, 0.3, 2200.0, phi, 0.0, 0.0),
    ));
    n.apply(&mut scene);
    scene
}

pub fn heap_slope(
    phi: f64,
    slope: f64,
    youngs_modulus: f64,
    n: &Numerics,
    duration: f64,
) -> HeapSlope {
    let scene = heap_slope_scene(phi, slope, youngs_modulus, n);
    let Material::DruckerPrager(m) = scene.bodies[0].material else {
        unreachable!("the heap is sand");
    };
    let stopping_angle = m.steady_shear_friction().atan().to_degrees();
    let s = spacing(&scene);
    let phi_ps = plane_strain_angle(phi);
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("heap scene");
    let flank = |sim: &Simulation<mpm::D2>| {
        let p = sim.particles();
        let pts: Vec<(f64, f64)> = (0..p.len())
            .map(|i| (p.x[i][0] as f64, p.x[i][1] as f64))
            .collect();
        let (_, f) = flank_angles(&pts, s, sim.cell_size(), 1.2);
        0.5 * (f[0] + f[1])
    };
    let width = |sim: &Simulation<mpm::D2>| {
        let b = sim.bodies()[0].stats();
        b.bbox_max[0] - b.bbox_min[0]
    };
    let w0 = width(&sim);
    let initial_angle = flank(&sim);
    let halfway = 0.5 * (initial_angle + phi_ps);
    let start = Instant::now();
    let (mut peak_speed, mut failed_at) = (0.0f64, None);
    let mut creep_start: Option<Vec<[f64; 3]>> = None;
    let (mut apex_sum, mut apex_samples) = (0.0, 0usize);
    while sim.time() < duration - 1e-9 {
        sim.advance(0.01).expect("heap step");
        peak_speed = peak_speed.max(sim.diagnostics().max_speed);
        if sim.time() <= 1.0 + 1e-9 {
            let p = sim.particles();
            let at_apex = p.stress.iter().filter(|s| s.trace() > -1e-3).count();
            apex_sum += at_apex as f64 / p.len() as f64;
            apex_samples += 1;
        }
        if failed_at.is_none() && initial_angle > phi_ps && flank(&sim) <= halfway {
            failed_at = Some(sim.time());
        }
        if creep_start.is_none() && sim.time() >= CREEP_FROM - 1e-9 {
            creep_start = Some(rest_positions(&sim));
        }
    }
    let cost = cost(&sim, start);
    let creep = match &creep_start {
        Some(x0) => {
            let p = sim.particles();
            (0..p.len())
                .map(|i| {
                    let r = x0[p.id[i] as usize];
                    (p.x[i][0] as f64 - r[0]).hypot(p.x[i][1] as f64 - r[1])
                })
                .fold(0.0, f64::max)
        }
        None => f64::NAN,
    };
    HeapSlope {
        initial_angle,
        angle: flank(&sim),
        plane_strain_angle: phi_ps,
        stopping_angle,
        failed_at,
        creep,
        peak_speed,
        final_speed: sim.diagnostics().max_speed,
        widening: width(&sim) - w0,
        apex_fraction: apex_sum / apex_samples.max(1) as f64,
        cost,
    }
}

// ---------------------------------------------------------------------------------------------
// Sand on a rough floor: friction proportional to the pressure

/// A thin sheet of sand (`thickness` m, 0.3 m long) thrown along a floor of Coulomb friction μ
/// at `v0`: its centre of mass travels v0²/(2 μ g) before it stops, if the floor's friction is
/// proportional to the weight it carries, however few particle rows the sheet has.
#[derive(Clone, Debug)]
pub struct Slide {
    pub travel: f64,
    pub travel_exact: f64,
    pub final_speed: f64,
    pub cost: Cost,
}

pub fn sand_sheet_slide(thickness: f64, mu: f64, v0: f64, n: &Numerics) -> Slide {
    let g = 9.81;
    let mut scene = SceneConfig::new(2, &[2.0, 0.2], n.cell_size);
    scene.boundary.friction = mu;
    scene.bodies.push(
        mpm::BodyConfig::new(
            "sheet",
            mpm::Shape::cuboid(&[0.2, 0.0], &[0.5, thickness]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, 32.0, 0.0, 0.0),
        )
        .with_velocity(&[v0, 0.0]),
    );
    n.apply(&mut scene);
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("sheet scene");
    let x0 = sim.bodies()[0].stats().center_of_mass[0];
    let start = Instant::now();
    let stop = v0 / (mu * g);
    sim.advance(stop + 0.3).expect("sheet step");
    Slide {
        travel: sim.bodies()[0].stats().center_of_mass[0] - x0,
        travel_exact: v0 * v0 / (2.0 * mu * g),
        final_speed: sim.diagnostics().max_speed,
        cost: cost(&sim, start),
    }
}

// ---------------------------------------------------------------------------------------------
// FLIP at walls and between bodies

/// Stiff elastic boxes (0.08 m, E = 10.5 MPa, ν = 0, ρ = 300 kg/m³) in zero gravity, thrown at
/// the ceiling at 9.14 m/s (one box) or at each other at ±5 m/s (two boxes, the paper's
/// sticking contact), with PIC/FLIP ratio `alpha`, for `duration` seconds: the largest rise of
/// the total energy over its initial value, and how much of it is left at the end. Walls and
/// contacts may only take energy out.
/// How long the impact cases run (s): the box crosses the domain about five times.
pub const IMPACT_TIME: f64 = 0.25;

#[derive(Clone, Debug)]
pub struct Impacts {
    /// max_t (E(t)/E(0) − 1), never below 0 (the energy at the start counts).
    pub energy_rise: f64,
    /// E(end)/E(0).
    pub energy_kept: f64,
    /// Sign changes of the first body's momentum along its flight (impacts, and the
    /// oscillations of a body that comes to rest against a wall).
    pub impacts: usize,
    /// The error that stopped the run (a run that diverged), if any.
    pub failure: Option<String>,
    pub cost: Cost,
}

pub fn flip_impacts<D: Dim>(n: &Numerics, alpha: f64, two: bool, duration: f64) -> Impacts {
    let box_at = |name: &str, x: f64, vx: f64, vy: f64| {
        let (lo, hi) = ([x, 0.285, 0.21], [x + 0.08, 0.365, 0.29]);
        let v = [vx, vy, 0.0];
        mpm::BodyConfig::new(
            name,
            mpm::Shape::cuboid(&lo[..D::DIM], &hi[..D::DIM]),
            Material::elastic(1.05e7, 0.0, 300.0),
        )
        .with_velocity(&v[..D::DIM])
        .with_flip(alpha)
    };
    let mut scene = SceneConfig::new(D::DIM, &[0.5; 3][..D::DIM], n.cell_size);
    scene.gravity = Some(vec![0.0; D::DIM]);
    if two {
        scene.bodies.push(box_at("left", 0.1, 5.0, 0.0));
        scene.bodies.push(box_at("right", 0.32, -5.0, 0.0));
    } else {
        scene.bodies.push(box_at("box", 0.21, 0.0, 9.14));
    }
    scene.kernel = n.kernel;
    scene.cfl = n.cfl;
    for b in &mut scene.bodies {
        b.particles_per_cell = n.ppc;
        if n.apic.is_some() {
            b.apic = n.apic;
        }
    }
    let mut sim = Simulation::<D>::new(scene).expect("impact scene");
    let e0 = sim.diagnostics().total_energy();
    // impacts: sign changes of the first body's momentum along the motion
    let axis = if two { 0 } else { 1 };
    let momentum = |sim: &Simulation<D>| sim.bodies()[0].stats().momentum[axis];
    let (mut worst, mut impacts, mut last) = (0.0f64, 0, momentum(&sim));
    let start = Instant::now();
    let mut failure = None;
    while sim.time() < duration {
        let d = match sim.step() {
            Ok(d) => d,
            Err(e) => {
                failure = Some(e.to_string());
                worst = f64::INFINITY;
                break;
            }
        };
        worst = worst.max(d.total_energy() / e0 - 1.0);
        let now = momentum(&sim);
        if now * last < 0.0 {
            impacts += 1;
        }
        last = now;
    }
    Impacts {
        energy_rise: worst,
        energy_kept: sim.diagnostics().total_energy() / e0,
        impacts,
        failure,
        cost: cost(&sim, start),
    }
}

// ---------------------------------------------------------------------------------------------
// Drucker–Prager: a low column on a rough floor (how flowing sand comes to rest)

/// The floor friction of the low column and of Bui et al.'s set-up: rough, above tan φ_ps of
/// every friction angle studied (μ = 0.6 > tan 28.7°).
pub const ROUGH_FLOOR: f64 = 0.6;

/// The deposit of a plane column collapse measured as a sand deposit: its run-out two ways,
/// its flanks, the flanks' foot, the toe beyond it, its top plateau and its height. Lengths
/// are shares of the column's half-width (or width, against a back wall) L0.
#[derive(Clone, Debug, Default)]
pub struct Deposit {
    /// (L − L0)/L0 with L the farthest particle of the deposit ([`deposit_front`]).
    pub runout: f64,
    /// (L − L0)/L0 with L the edge of the continuous deposit ([`deposit_edge`]: thinner
    /// than [`EDGE_THICKNESS`] of H0).
    pub runout_edge: f64,
    /// (L − L0)/L0 with L where the deposit is one grain ([`GRAIN`]) thick
    /// ([`runout_at_thickness`]).
    pub runout_thin: f64,
    /// The flank: least-squares slope (degrees) of the surface between 20 % and 80 % of the
    /// deposit's height ([`flank_angles`]); one per side (one side against a back wall).
    pub flanks: Vec<f64>,
    /// (x_foot − L0)/L0: where the fitted flank line meets the floor.
    pub foot: f64,
    /// (L − x_foot)/L0 with L the farthest particle: how far the deposit reaches beyond the
    /// flank's foot (thin material: the flank line is at the floor there).
    pub toe: f64,
    /// The thickest the deposit is beyond the foot, in particle rows (spacing s).
    pub toe_rows: f64,
    /// Half-width (or width) of the top left within one cell of H0, over L0.
    pub plateau: f64,
    /// H∞/H0: the highest particle within L0 of the axis (of the wall).
    pub height: f64,
}

impl Deposit {
    pub fn flank(&self) -> f64 {
        self.flanks.iter().sum::<f64>() / self.flanks.len() as f64
    }
}

/// A low-column driver's case argument as a friction angle in degrees (`bui` is handled by
/// the caller).
pub fn case_friction_angle(case: &str) -> Result<f64, String> {
    case.parse()
        .ok()
        .filter(|p| (0.0..60.0).contains(p))
        .ok_or(format!("φ: `{case}` is not `bui` or an angle in [0, 60)"))
}

/// Every particle's (x − xc, y) in seeding order (by id): a plane deposit about its axis `xc`.
pub fn positions_by_id(sim: &mpm::Simulation<mpm::D2>, xc: f64) -> Vec<(f64, f64)> {
    let p = sim.particles();
    let mut pos = vec![(0.0, 0.0); p.len()];
    for i in 0..p.len() {
        pos[p.id[i] as usize] = (p.x[i][0] as f64 - xc, p.x[i][1] as f64);
    }
    pos
}

/// Measures a plane deposit of particles at distances `d` ≥ 0 from the column's axis (or its
/// back wall) and heights `y` (particle spacing `s`, cell size `h`), from a column of
/// half-width (or width) `l0` and height `h0`. `d` and `y` are paired.
pub fn measure_deposit(pts: &[(f64, f64)], s: f64, h: f64, l0: f64, h0: f64) -> Deposit {
    let d: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let front = deposit_front(d.clone(), s, 0.0);
    let edge = deposit_edge(d, s, s * s, |r0, r1| r1 - r0, EDGE_THICKNESS * h0);
    let thin = runout_at_thickness(pts, s, h, l0, GRAIN);
    // the surface in columns of width h from the axis out; the flank falls away from it
    let width = front + 2.0 * h;
    let heap = mpm::measure::heap(pts, s, h, 0.0, width);
    let (flank, foot) = match heap.flanks[1] {
        // where the fitted line meets the floor
        Some(f) => (
            f.angle,
            f.to[0] + f.to[1] * (f.to[0] - f.from[0]) / (f.from[1] - f.to[1]),
        ),
        None => (f64::NAN, f64::NAN),
    };
    let nbins = (width / h).round() as usize;
    let mut top = vec![0.0f64; nbins];
    for &(x, y) in pts {
        let b = ((x / h) as usize).min(nbins - 1);
        top[b] = top[b].max(y + 0.5 * s);
    }
    let toe_rows = (0..nbins)
        .filter(|&b| (b as f64 + 0.5) * h > foot)
        .map(|b| top[b] / s)
        .fold(0.0, f64::max);
    let plateau = top
        .iter()
        .position(|&t| t < h0 - h)
        .map_or(width, |b| b as f64 * h);
    let h_inf = pts
        .iter()
        .filter(|p| p.0 < l0)
        .map(|p| p.1)
        .fold(0.0, f64::max)
        + 0.5 * s;
    Deposit {
        runout: (front - l0) / l0,
        runout_edge: (edge - l0) / l0,
        runout_thin: (thin - l0) / l0,
        flanks: vec![flank],
        foot: (foot - l0) / l0,
        toe: ((front - foot) / l0).max(0.0),
        toe_rows,
        plateau: plateau / l0,
        height: h_inf / h0,
    }
}

/// A low plane column on a rough floor: the deposit of each side, averaged, when it has come
/// to rest ([`run_until_rest`]).
#[derive(Clone, Debug)]
pub struct LowColumn {
    pub friction_angle: f64,
    pub plane_strain_angle: f64,
    pub aspect_ratio: f64,
    pub deposit: Deposit,
    pub settled_at: f64,
    pub failure: Option<String>,
    pub cost: Cost,
}

/// The scene of [`low_column`]: the a = 0.5 plane column of `scenes/validation/` (L0 = 0.2 m,
/// H0 = 0.1 m, collapsing both ways) of friction angle `phi` on a floor of friction
/// [`ROUGH_FLOOR`], under the numerics `n`.
pub fn low_column_scene(phi: f64, n: &Numerics) -> SceneConfig {
    let mut scene = load("column_collapse_a0.5_2d.json", n);
    scene.boundary.friction = ROUGH_FLOOR;
    if let Material::DruckerPrager(m) = &mut scene.bodies[0].material {
        m.friction_angle = phi;
    }
    scene
}

/// The floor friction of Bui et al. (2008)'s set-up (the walls share it: one friction for
/// every wall).
pub const BUI_FLOOR: f64 = 0.5;

/// Bui, Fukagawa, Sako & Ohno (2008)'s set-up: aluminium rods 0.2 m wide and 0.1 m high
/// against the left wall, φ = 19.8°, ψ = 0, c = 0, E = 0.84 MPa, ν = 0.3, ρ = 2650 kg/m³, on a
/// floor (and wall) of friction [`BUI_FLOOR`], under the numerics `n`.
pub fn bui_scene(n: &Numerics) -> SceneConfig {
    let mut scene = SceneConfig::new(2, &[0.8, 0.2], n.cell_size);
    scene.boundary.friction = BUI_FLOOR;
    scene.bodies.push(mpm::BodyConfig::new(
        "aluminium rods",
        mpm::Shape::polygon(&[[0.0, 0.0], [0.2, 0.0], [0.2, 0.1], [0.0, 0.1]]),
        Material::drucker_prager(0.84e6, 0.3, 2650.0, 19.8, 0.0, 0.0),
    ));
    n.apply(&mut scene);
    scene
}

/// A plane column set up to run: the simulation of its `scene` and what its deposit is
/// measured against (the column's axis, or its back wall when `walled`; its half-width, or
/// width, L0; its height H0).
struct PlaneColumn {
    sim: Simulation<mpm::D2>,
    friction_angle: f64,
    walled: bool,
    s: f64,
    h: f64,
    g: f64,
    x0: f64,
    l0: f64,
    h0: f64,
}

impl PlaneColumn {
    fn new(scene: SceneConfig, walled: bool) -> Self {
        let Material::DruckerPrager(m) = scene.bodies[0].material else {
            panic!("the column is sand");
        };
        let (s, h) = (spacing(&scene), scene.cell_size);
        let g = scene.gravity_vector()[1].abs();
        let sim = Simulation::<mpm::D2>::new(scene).expect("column scene");
        let (xc, half) = column_extent(&sim, s);
        let (x0, l0) = if walled { (0.0, xc + half) } else { (xc, half) };
        let h0 = sim
            .particles()
            .x
            .iter()
            .map(|x| x[1] as f64)
            .fold(0.0, f64::max)
            + 0.5 * s;
        PlaneColumn {
            sim,
            friction_angle: m.friction_angle,
            walled,
            s,
            h,
            g,
            x0,
            l0,
            h0,
        }
    }

    /// Measures the deposit as the simulation stands, the run having started at `start` and
    /// stopped for `failure`, if it did.
    fn measure(&self, start: Instant, failure: Option<String>) -> LowColumn {
        let settled_at = self.sim.time();
        let cost = cost(&self.sim, start);
        let sides: &[f64] = if self.walled { &[1.0] } else { &[1.0, -1.0] };
        let deposits: Vec<Deposit> = sides
            .iter()
            .map(|&sign| {
                let p = self.sim.particles();
                let pts: Vec<(f64, f64)> = (0..p.len())
                    .map(|i| (sign * (p.x[i][0] as f64 - self.x0), p.x[i][1] as f64))
                    .filter(|q| q.0 >= 0.0)
                    .collect();
                measure_deposit(&pts, self.s, self.h, self.l0, self.h0)
            })
            .collect();
        let k = deposits.len() as f64;
        let mean = |f: fn(&Deposit) -> f64| deposits.iter().map(f).sum::<f64>() / k;
        let deposit = Deposit {
            runout: mean(|d| d.runout),
            runout_edge: mean(|d| d.runout_edge),
            runout_thin: mean(|d| d.runout_thin),
            flanks: deposits.iter().map(|d| d.flanks[0]).collect(),
            foot: mean(|d| d.foot),
            toe: mean(|d| d.toe),
            toe_rows: mean(|d| d.toe_rows),
            plateau: mean(|d| d.plateau),
            height: mean(|d| d.height),
        };
        LowColumn {
            friction_angle: self.friction_angle,
            plane_strain_angle: plane_strain_angle(self.friction_angle),
            aspect_ratio: self.h0 / self.l0,
            deposit,
            settled_at,
            failure,
            cost,
        }
    }
}

/// Runs a plane column `scene` (its first body; `walled`: against the domain's left wall,
/// else free on both sides about its centre) until it rests, and measures its deposit.
pub fn plane_deposit(scene: SceneConfig, walled: bool, t_max: f64) -> LowColumn {
    let mut c = PlaneColumn::new(scene, walled);
    let start = Instant::now();
    let failure = run_until_rest(&mut c.sim, c.h0, c.g, t_max);
    c.measure(start, failure)
}

/// The points `(x, y)` (m) of a digitised curve of `tests/data/` (lines starting with `#` and
/// the header `x,y` skipped).
pub fn digitised(file: &str) -> Vec<(f64, f64)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('x') && !l.trim().is_empty())
        .map(|l| {
            let (x, y) = l.split_once(',').expect("x,y");
            (x.trim().parse().unwrap(), y.trim().parse().unwrap())
        })
        .collect()
}

/// Where a surface given as points `(x, y)` ordered in x first drops below `thickness`,
/// interpolated linearly between its points.
pub fn polyline_runout(surface: &[(f64, f64)], thickness: f64) -> f64 {
    surface
        .windows(2)
        .find(|w| w[0].1 >= thickness && w[1].1 < thickness)
        .map_or(f64::NAN, |w| {
            w[0].0 + (w[0].1 - thickness) / (w[0].1 - w[1].1) * (w[1].0 - w[0].0)
        })
}

/// The angle (degrees) of a failure line through points `(x, y)`: x fitted on y by least
/// squares (the line is steep), as the angle to the floor.
pub fn failure_line_angle(points: &[(f64, f64)]) -> f64 {
    let (ys, xs): (Vec<f64>, Vec<f64>) = points.iter().map(|p| (p.1, p.0)).unzip();
    (1.0 / slope(&ys, &xs).abs()).atan().to_degrees()
}

/// Bui et al. (2008)'s collapse against the experiment's final surface and failure line
/// (`tests/data/bui2008_*.csv`): the deposit as [`plane_deposit`] measures it against the back
/// wall, and the comparison.
#[derive(Clone, Debug)]
pub struct BuiComparison {
    pub run: LowColumn,
    /// RMS over the experiment's surface markers of the model's surface height minus theirs
    /// (m); the model's surface is the highest particle plus half a spacing per cell-wide
    /// column, linear between column centres, 0 where no particle lies.
    pub rms: f64,
    /// Where the model's and the experiment's deposits are one grain thick (m from the wall).
    pub runout_thin: f64,
    pub experiment_runout_thin: f64,
    /// The model's farthest particle (m from the wall).
    pub farthest: f64,
    /// The model's flank and the experiment's (20–80 % least-squares slope, degrees).
    pub flank: f64,
    pub experiment_flank: f64,
    /// The failure line's angle (degrees): the model's is fitted through, in each row of
    /// particles one cell high between 10 % and 90 % of H0, the farthest particle from the
    /// wall that moved less than one grain ([`GRAIN`]); the experiment's through its markers.
    pub failure_angle: f64,
    pub experiment_failure_angle: f64,
}

/// Runs [`bui_scene`] under `n` to rest (at most `t_max` s) and compares it with the
/// experiment.
pub fn bui_2008(n: &Numerics, t_max: f64) -> BuiComparison {
    let mut c = PlaneColumn::new(bui_scene(n), true);
    let x0 = rest_positions(&c.sim);
    let start = Instant::now();
    let failure = run_until_rest(&mut c.sim, c.h0, c.g, t_max);
    let run = c.measure(start, failure);
    let (s, h, h0) = (c.s, c.h, c.h0);
    let p = c.sim.particles();
    let pts: Vec<(f64, f64)> = (0..p.len())
        .map(|i| (p.x[i][0] as f64, p.x[i][1] as f64))
        .collect();
    let surface = digitised("bui2008_surface.csv");
    let line = digitised("bui2008_failure_line.csv");
    // the model's surface, column by column
    let width = 0.8;
    let nbins = (width / h).round() as usize;
    let mut top = vec![0.0f64; nbins];
    for &(x, y) in &pts {
        let b = ((x / h) as usize).min(nbins - 1);
        top[b] = top[b].max(y + 0.5 * s);
    }
    let at = |x: f64| {
        let u = (x / h - 0.5).clamp(0.0, (nbins - 1) as f64);
        let b = (u.floor() as usize).min(nbins - 2);
        let f = u - b as f64;
        top[b] * (1.0 - f) + top[b + 1] * f
    };
    let rms = (surface
        .iter()
        .map(|&(x, y)| (at(x) - y).powi(2))
        .sum::<f64>()
        / surface.len() as f64)
        .sqrt();
    let fit = |pts: &[(f64, f64)]| {
        let (xs, ys): (Vec<f64>, Vec<f64>) = pts
            .iter()
            .filter(|q| q.1 > mpm::measure::FIT_FROM * h0 && q.1 < mpm::measure::FIT_TO * h0)
            .copied()
            .unzip();
        slope(&xs, &ys).abs().atan().to_degrees()
    };
    // the failure line: the farthest particle of each row that has not moved
    let rows = (h0 / h).ceil() as usize;
    let mut edge = vec![f64::NEG_INFINITY; rows];
    for i in 0..p.len() {
        let r = x0[p.id[i] as usize];
        let (x, y) = (p.x[i][0] as f64, p.x[i][1] as f64);
        if (x - r[0]).hypot(y - r[1]) < GRAIN {
            let k = ((y / h) as usize).min(rows - 1);
            edge[k] = edge[k].max(x + 0.5 * s);
        }
    }
    let model_line: Vec<(f64, f64)> = edge
        .iter()
        .enumerate()
        .map(|(k, &x)| (x, (k as f64 + 0.5) * h))
        .filter(|q| q.0.is_finite() && q.1 > 0.1 * h0 && q.1 < 0.9 * h0)
        .collect();
    let thin = runout_at_thickness(&pts, s, h, c.l0, GRAIN);
    let farthest = c.l0 * (1.0 + run.deposit.runout);
    BuiComparison {
        rms,
        runout_thin: thin,
        experiment_runout_thin: polyline_runout(&surface, GRAIN),
        farthest,
        flank: run.deposit.flank(),
        experiment_flank: fit(&surface),
        failure_angle: failure_line_angle(&model_line),
        experiment_failure_angle: failure_line_angle(&line),
        run,
    }
}

/// The low column of [`low_column_scene`] run to rest.
pub fn low_column(phi: f64, n: &Numerics, t_max: f64) -> LowColumn {
    plane_deposit(low_column_scene(phi, n), false, t_max)
}

/// How often [`low_column_without_momentum`] clamps the particles' speed (s of simulated
/// time).
pub const CAP_INTERVAL: f64 = 1e-3;

/// The low column of [`low_column_scene`] collapsing without momentum: every
/// [`CAP_INTERVAL`] each particle faster than `cap` m/s has its velocity (and its APIC affine
/// velocity, by the same factor) scaled down to `cap`, so the column falls quasi-statically
/// (kinetic energy per unit mass at most cap²/2, against g H0 released), then runs to rest
/// and is measured as [`low_column`]'s deposit is. Between clamps gravity adds at most
/// g [`CAP_INTERVAL`] ≈ 0.01 m/s.
pub fn low_column_without_momentum(phi: f64, n: &Numerics, cap: f64, t_max: f64) -> LowColumn {
    let mut c = PlaneColumn::new(low_column_scene(phi, n), false);
    let start = Instant::now();
    let cap = cap as f32;
    let failure = run_until_rest_with(&mut c.sim, c.h0, c.g, t_max, CAP_INTERVAL, |sim| {
        let p = sim.particles_mut();
        let apic = p.affine.len() == p.v.len();
        for i in 0..p.v.len() {
            let speed = p.v[i].length();
            if speed > cap {
                let f = cap / speed;
                p.v[i] *= f;
                if apic {
                    p.affine[i] *= f;
                }
            }
        }
    });
    c.measure(start, failure)
}

/// A flowing sand layer coming to rest on a slope: a layer `thickness` m thick and 0.3 m long
/// of φ = `phi` sand sent at `v0` down a rough floor (μ = [`ROUGH_FLOOR`], above tan φ_ps)
/// inclined at `slope` degrees (gravity tilted). The floor holds its base, so it must shear
/// inside; sand that flows stops at φ_ps, so its centre of mass should travel about the
/// distance v0² / (2 g (cos θ tan φ_ps − sin θ)) that a rigid block on the plane-strain
/// friction needs.
#[derive(Clone, Debug)]
pub struct SlopeLayer {
    pub travel: f64,
    pub block_travel: f64,
    pub stopped_at: f64,
    pub final_speed: f64,
    pub cost: Cost,
}

pub fn slope_layer(phi: f64, slope: f64, thickness: f64, v0: f64, n: &Numerics) -> SlopeLayer {
    let g = 9.81;
    let th = slope.to_radians();
    let mu_ps = plane_strain_angle(phi).to_radians().tan();
    let decel = g * (th.cos() * mu_ps - th.sin());
    let block_travel = v0 * v0 / (2.0 * decel);
    let length = ((0.6 + 3.0 * block_travel) / 0.1).ceil() * 0.1;
    let mut scene = SceneConfig::new(2, &[length, 0.2], n.cell_size);
    scene.boundary.friction = ROUGH_FLOOR;
    scene.gravity = Some(vec![g * th.sin(), -g * th.cos()]);
    scene.bodies.push(
        mpm::BodyConfig::new(
            "layer",
            mpm::Shape::cuboid(&[0.1, 0.0], &[0.4, thickness]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, phi, 0.0, 0.0),
        )
        .with_velocity(&[v0, 0.0]),
    );
    n.apply(&mut scene);
    let mut sim = Simulation::<mpm::D2>::new(scene).expect("slope layer scene");
    let x0 = sim.bodies()[0].stats().center_of_mass[0];
    let start = Instant::now();
    let t_max = 4.0 * v0 / decel;
    let mut stopped_at = f64::NAN;
    while sim.time() < t_max {
        sim.advance(0.01).expect("slope layer step");
        if sim.diagnostics().max_speed < 0.01 * v0 {
            stopped_at = sim.time();
            break;
        }
    }
    SlopeLayer {
        travel: sim.bodies()[0].stats().center_of_mass[0] - x0,
        block_travel,
        stopped_at,
        final_speed: sim.diagnostics().max_speed,
        cost: cost(&sim, start),
    }
}
