//! The solver's digest: a hash of the trajectory of a short canonical set of runs, one digest
//! per material family, which every generated report records (its "Solver digest:" line) so
//! that a report made by another solver is told apart from one made by today's
//! (`tests/reports.rs`; docs/reports/README.md).
//!
//! A family's digest hashes, after a few hundred substeps of each of its runs, the simulated
//! time and every particle's position, velocity, stress and volume (their bits, particles in
//! the order of their stable identifier): the trajectory, not the diagnostics (energies,
//! plastic strain, timings), and not the order particles are kept in. A change of the energy
//! account or of the memory layout leaves it as it is; a change of what a step computes for a
//! particle changes it.
//!
//! The runs cover what the reports measure: elastic and von Mises solids, Drucker–Prager and
//! Mohr–Coulomb sand; 2D and 3D; the linear, GIMP and B-spline kernels; PIC, FLIP (capped at
//! walls) and APIC; walls with friction, sticking and frictional contact between bodies; the
//! cell-averaged volumetric rate. Sleeping is off in every run (no report is made with it).
//! The digests are those of the default build (f32, no `-C target-cpu`), on x86-64.
#![allow(dead_code)]

use mpm::math::{Dim, SymTensor};
use mpm::{AnySimulation, SceneConfig, Simulation};

/// The material families, each with its own digest: a report records the families it
/// measures. `solid`: elastic and von Mises bodies; `sand`: Drucker–Prager;
/// `mohr_coulomb`: the Mohr–Coulomb model.
pub const FAMILIES: [&str; 3] = ["solid", "sand", "mohr_coulomb"];

/// The canonical runs: (family, name, substeps, scene).
fn runs() -> Vec<(&'static str, &'static str, usize, String)> {
    let elastic =
        r#"{"elastic": {"youngs_modulus": 1.0e5, "poisson_ratio": 0.3, "density": 1000}}"#;
    let von_mises = r#"{"von_mises": {"youngs_modulus": 1.0e5, "poisson_ratio": 0.3, "density": 1000, "yield_stress": 3000}}"#;
    let dp = r#"{"drucker_prager": {"youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200, "friction_angle": 35, "dilatancy_angle": 0, "cohesion": 0}}"#;
    let dp_cell = r#"{"drucker_prager": {"youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200, "friction_angle": 32, "dilatancy_angle": 0, "cohesion": 50, "volumetric_rate": "cell_average"}}"#;
    let mc = r#"{"mohr_coulomb": {"youngs_modulus": 3.5e5, "poisson_ratio": 0.3, "density": 2200, "friction_angle": 30, "dilatancy_angle": 5, "cohesion": 0}}"#;
    let body = |name: &str, shape: &str, material: &str, extra: &str| {
        format!(
            r#"{{"name": "{name}", "shape": {shape}, "material": {material}, "jitter": 0.25, "seed": 7{extra}}}"#
        )
    };
    let scene = |dim: usize, size: &str, h: f64, kernel: &str, extra: &str, bodies: &[String]| {
        format!(
            r#"{{"name": "digest", "dim": {dim}, "domain": {{"size": {size}}}, "cell_size": {h}, "kernel": "{kernel}", "boundary": {{"friction": 0.5}}{extra}, "bodies": [{}]}}"#,
            bodies.join(", ")
        )
    };
    // the 2D runs' domain: 1 m × 0.5 m, h = 0.02 m, walls with friction only
    let plane = |kernel: &str, bodies: &[String]| scene(2, "[1.0, 0.5]", 0.02, kernel, "", bodies);
    let column_2d = r#"{"box": {"min": [0.4, 0.0], "max": [0.6, 0.3]}}"#;
    vec![
        (
            "solid",
            "elastic_2d_gimp_flip",
            300,
            plane(
                "gimp",
                &[body(
                    "block",
                    r#"{"box": {"min": [0.3, 0.1], "max": [0.6, 0.3]}}"#,
                    elastic,
                    r#", "velocity": [1.0, -2.0], "flip": 1.0"#,
                )],
            ),
        ),
        (
            "solid",
            "von_mises_2d_bspline",
            300,
            plane(
                "quadratic_bspline",
                &[body(
                    "ball",
                    r#"{"ball": {"center": [0.5, 0.2], "radius": 0.12}}"#,
                    von_mises,
                    r#", "velocity": [0.0, -3.0], "flip": 0.5"#,
                )],
            ),
        ),
        (
            "solid",
            "elastic_2d_linear_sticking_contact",
            300,
            plane(
                "linear",
                &[
                    body(
                        "base",
                        r#"{"box": {"min": [0.3, 0.0], "max": [0.7, 0.1]}}"#,
                        elastic,
                        "",
                    ),
                    body(
                        "falling",
                        r#"{"box": {"min": [0.42, 0.14], "max": [0.58, 0.26]}}"#,
                        elastic,
                        r#", "velocity": [0.0, -2.0]"#,
                    ),
                ],
            ),
        ),
        (
            "solid",
            "elastic_3d_gimp_frictional_contact",
            200,
            scene(
                3,
                "[1.0, 0.6, 0.6]",
                0.05,
                "gimp",
                r#", "contact": {"friction": 0.3}"#,
                &[
                    body(
                        "base",
                        r#"{"box": {"min": [0.3, 0.0, 0.2], "max": [0.7, 0.1, 0.4]}}"#,
                        elastic,
                        "",
                    ),
                    body(
                        "falling",
                        r#"{"ball": {"center": [0.5, 0.25, 0.3], "radius": 0.1}}"#,
                        von_mises,
                        r#", "velocity": [0.5, -2.0, 0.0], "flip": 1.0"#,
                    ),
                ],
            ),
        ),
        (
            "sand",
            "drucker_prager_2d_gimp_apic",
            400,
            plane("gimp", &[body("column", column_2d, dp, "")]),
        ),
        (
            "sand",
            "drucker_prager_2d_linear_pic_flip",
            400,
            plane("linear", &[body("column", column_2d, dp, "")]),
        ),
        (
            "mohr_coulomb",
            "mohr_coulomb_2d_bspline",
            400,
            plane("quadratic_bspline", &[body("column", column_2d, mc, "")]),
        ),
        (
            "sand",
            "drucker_prager_3d_bspline_cell_average",
            200,
            scene(
                3,
                "[1.0, 0.6, 0.6]",
                0.05,
                "quadratic_bspline",
                "",
                &[body(
                    "column",
                    r#"{"box": {"min": [0.4, 0.0, 0.2], "max": [0.6, 0.3, 0.4]}}"#,
                    dp_cell,
                    "",
                )],
            ),
        ),
    ]
}

/// FNV-1a, 64 bits.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn real(&mut self, x: mpm::Real) {
        self.bytes(&x.to_le_bytes());
    }
}

/// Hashes the trajectory's end: the time, then each particle's x, v, σ and V, in the order of
/// the particles' identifiers.
fn hash_state<D: Dim>(sim: &Simulation<D>, h: &mut Fnv) {
    h.bytes(&sim.time().to_le_bytes());
    let p = sim.particles();
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.id[i]);
    h.bytes(&(order.len() as u64).to_le_bytes());
    for i in order {
        for a in 0..D::DIM {
            h.real(p.x[i][a]);
        }
        for a in 0..D::DIM {
            h.real(p.v[i][a]);
        }
        for &s in p.stress[i].components() {
            h.real(s);
        }
        h.real(p.volume[i]);
    }
}

/// One canonical run's hash.
fn run_hash(name: &str, steps: usize, json: &str) -> Result<u64, String> {
    let scene = SceneConfig::from_json(json).map_err(|e| format!("digest run {name}: {e}"))?;
    let mut sim = AnySimulation::new(scene).map_err(|e| format!("digest run {name}: {e}"))?;
    for k in 0..steps {
        sim.step()
            .map_err(|e| format!("digest run {name}, substep {k}: {e}"))?;
    }
    let mut h = Fnv::new();
    h.bytes(name.as_bytes());
    match &sim {
        AnySimulation::D2(s) => hash_state(s, &mut h),
        AnySimulation::D3(s) => hash_state(s, &mut h),
    }
    Ok(h.0)
}

/// The digest of one family: its runs' hashes, hashed in order.
pub fn family_digest(family: &str) -> Result<u64, String> {
    let mut h = Fnv::new();
    for (f, name, steps, json) in runs() {
        if f == family {
            h.bytes(&run_hash(name, steps, &json)?.to_le_bytes());
        }
    }
    Ok(h.0)
}

/// Today's digest of each family, in the order of [`FAMILIES`].
pub fn digests() -> Result<Vec<(&'static str, u64)>, String> {
    FAMILIES
        .iter()
        .map(|f| family_digest(f).map(|d| (*f, d)))
        .collect()
}

/// The line a report records its solver with: the digests of `families` and the command that
/// regenerates the report, e.g. "Solver digest: solid `0123456789abcdef`, sand
/// `fedcba9876543210`; regenerate with `cargo xtask work-precision`."
pub fn stamp_line(families: &[&str], regenerate: &str) -> String {
    let today = digests().unwrap_or_else(|e| panic!("the solver's digest: {e}"));
    let parts: Vec<String> = today
        .iter()
        .filter(|(f, _)| families.contains(f))
        .map(|(f, d)| format!("{f} `{d:016x}`"))
        .collect();
    format!(
        "Solver digest: {}; regenerate with `{regenerate}`.",
        parts.join(", ")
    )
}

/// A report's "Solver digest:" line, read back.
#[derive(Debug, PartialEq)]
pub struct Stamp {
    /// The digest of each family the report records.
    pub digests: Vec<(String, u64)>,
    /// The command that regenerates the report.
    pub regenerate: String,
}

/// The "Solver digest:" lines of a report's text; `Err` names a line that does not parse.
pub fn stamps(text: &str) -> Result<Vec<Stamp>, String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let Some(at) = line.find("Solver digest: ") else {
            continue;
        };
        let rest = &line[at + "Solver digest: ".len()..];
        let (list, command) = rest
            .split_once("; regenerate with `")
            .ok_or_else(|| format!("no \"; regenerate with `…`\" in {line:?}"))?;
        let regenerate = command
            .split_once('`')
            .map(|(c, _)| c.to_string())
            .ok_or_else(|| format!("the command is not closed with ` in {line:?}"))?;
        let mut digests = Vec::new();
        for part in list.split(", ") {
            let (family, hex) = part
                .split_once(' ')
                .ok_or_else(|| format!("{part:?} is not `family digest` in {line:?}"))?;
            let digest = u64::from_str_radix(hex.trim_matches('`'), 16)
                .map_err(|e| format!("{hex}: {e} in {line:?}"))?;
            digests.push((family.to_string(), digest));
        }
        out.push(Stamp {
            digests,
            regenerate,
        });
    }
    Ok(out)
}
