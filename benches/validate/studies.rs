//! The opt-in studies behind the sand model's decisions: where flowing sand stops, volumetric
//! locking, the friction match and the start–stop cone.

use crate::report::*;
use crate::tables::*;
use crate::validation::*;
use mpm::KernelKind;
use std::fmt::Write;

/// The over-steep slope (φ = 32°, θ = 40°, 3 s) under each numerical factor at h = 0.01 and
/// 0.005 m, and at 0.0025 m; the heaps (φ = 32°, 45°) and the a = 2 plane collapse at h = 0.01
/// and 0.005 m; each rate-independent and with μ(I) for a sand grain (d = 0.5 mm) and a coarse
/// one (d = 2 mm).
pub fn stopping_study(md: &mut String, path: &std::path::Path) {
    // Eq. 13's cone alone, as the study was made (the default cone widens as sand flows)
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp).plane_strain();
    let (fine, coarse) = (0.5e-3, 2e-3);
    let mut cases: Vec<(&str, f64, Numerics)> = Vec::new();
    for h in [0.01, 0.005] {
        cases.push(("", 3.5e5, gimp(h)));
        cases.push(("ppc 3", 3.5e5, gimp(h).ppc(3)));
        cases.push(("ppc 4", 3.5e5, gimp(h).ppc(4)));
        cases.push(("E / 3", 3.5e5 / 3.0, gimp(h)));
        cases.push(("E × 3", 3.5e5 * 3.0, gimp(h)));
        cases.push(("CFL 0.2", 3.5e5, gimp(h).cfl(0.2)));
        cases.push(("α = 0", 3.5e5, gimp(h).flip(0.0)));
        cases.push(("μ(I)", 3.5e5, gimp(h).mu_i(fine)));
        cases.push(("μ(I)", 3.5e5, gimp(h).mu_i(coarse)));
    }
    cases.push(("", 3.5e5, gimp(0.0025)));
    cases.push(("μ(I)", 3.5e5, gimp(0.0025).mu_i(fine)));
    let mut rows = Vec::new();
    for (what, e, n) in cases {
        let r = heap_slope(32.0, 40.0, e, &n, 3.0);
        println!("stopping slope {what} E={e} {}: {r:?}", n.label());
        let mut row = vec![n.label(), what.to_string(), format!("{e:.2e}")];
        row.extend(slope_cells(&r));
        rows.push(row);
    }
    let _ = writeln!(
        md,
        "## Where flowing sand stops: the over-steep slope (φ = 32°, φ_ps = 30.4°, θ = 40°, 3 s)\n\nPeak speed: the largest particle speed seen. At apex: the mean fraction of particles at zero pressure (the tension cut-off) over the first second.\n\n{}",
        table(
            &headers(&["numerics", "factor", "E (Pa)"], &slope_headers(3.0)),
            &rows
        )
    );
    std::fs::write(path, &*md).unwrap();
    let mut runs = Vec::new();
    for phi in [32.0, 45.0] {
        for h in [0.01, 0.005] {
            for n in [gimp(h), gimp(h).mu_i(fine), gimp(h).mu_i(coarse)] {
                runs.push((phi, n));
            }
        }
    }
    let _ = writeln!(
        md,
        "## Where flowing sand stops: heaps (lifted walls at {LIFT_SPEED} m/s, floor μ = tan φ)\n\n{}",
        heaps_table("stopping", &runs)
    );
    std::fs::write(path, &*md).unwrap();
    let mut rows = Vec::new();
    for h in [0.01, 0.005] {
        for n in [gimp(h), gimp(h).mu_i(fine), gimp(h).mu_i(coarse)] {
            let c = column_collapse("column_collapse_a2_2d.json", &n, 4.0);
            println!("stopping collapse a=2 {}: {c:?}", n.label());
            let mut row = vec![n.label()];
            row.extend(collapse_cells(&c, 2.0));
            rows.push(row);
        }
    }
    let _ = writeln!(
        md,
        "## Where flowing sand stops: plane collapse a = 2 (Lube 2005: (L∞−L0)/L0 = {:.2}, H∞/H0 = {:.3})\n\n{}",
        lube_runout(2.0),
        lube_height(2.0),
        table(
            &[
                "numerics",
                "(L∞−L0)/L0 farthest / edge",
                "error",
                "H∞/H0",
                "error",
                "at rest (s)",
                "s"
            ],
            &rows
        )
    );
}

/// Volumetric locking of sand: the cases of the stopping study that locking moves, each with
/// the volumetric strain rate averaged over each cell (`"volumetric_rate": "cell_average"`)
/// and, where the stopping report does not already hold them, with each particle's own. The
/// over-steep slopes (φ = 32°, θ = 40° over four cell sizes and three particles per cell;
/// φ = 45°, θ = 50°; φ = 20°, θ = 30°) and the gentle one (φ = 32°, θ = 25°), 3 s; heaps; the
/// plane collapses (a = 2 over four cell sizes, particles per cell, with μ(I) for a sand grain;
/// a = 0.5, 1, 3 at h = 0.01 and 0.005 m).
pub fn locking_study(md: &mut String, path: &std::path::Path) {
    // Eq. 13's cone alone, as the study was made (the default cone widens as sand flows)
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp).plane_strain();
    let avg = |h: f64| gimp(h).cell_average();
    let fine = 0.5e-3;
    let _ = writeln!(
        md,
        "Volumetric locking: `cargo bench --bench validate -- locking`. `cell-avg`: the sand takes its cells' volume-weighted mean volumetric strain rate (`\"volumetric_rate\": \"cell_average\"`); without it, each particle's own (the default).\n"
    );
    let mut cases: Vec<(f64, f64, Numerics)> =
        vec![(32.0, 40.0, gimp(0.02)), (32.0, 40.0, avg(0.02))];
    for ppc in [2, 3, 4] {
        cases.push((32.0, 40.0, gimp(0.01).ppc(ppc)));
        cases.push((32.0, 40.0, avg(0.01).ppc(ppc)));
    }
    for ppc in [2, 3, 4] {
        cases.push((32.0, 40.0, avg(0.005).ppc(ppc)));
    }
    cases.push((32.0, 40.0, avg(0.0025)));
    for (phi, slope) in [(45.0, 50.0), (20.0, 30.0)] {
        for h in [0.01, 0.005] {
            cases.push((phi, slope, gimp(h)));
            cases.push((phi, slope, avg(h)));
        }
    }
    for h in [0.01, 0.005, 0.0025] {
        cases.push((32.0, 25.0, avg(h)));
    }
    let mut rows = Vec::new();
    for (phi, slope, n) in cases {
        let r = heap_slope(phi, slope, 3.5e5, &n, 3.0);
        println!("locking slope φ={phi} θ={slope} {}: {r:?}", n.label());
        let mut row = vec![
            n.label(),
            format!("{phi}"),
            format!("{:.1}", r.plane_strain_angle),
            format!("{slope} ({:.1})", r.initial_angle),
        ];
        row.extend(slope_cells(&r));
        rows.push(row);
    }
    let _ = writeln!(
        md,
        "## Volumetric locking: slopes (3 s, E = 350 kPa)\n\nA trapezoidal heap 0.1 m high released on a floor with μ = tan φ. *Failed at*: when the flanks had come halfway down from their initial angle to φ_ps. Peak speed: the largest particle speed seen. At apex: the mean fraction of particles at zero pressure over the first second.\n\n{}",
        table(
            &headers(
                &[
                    "numerics",
                    "φ (°)",
                    "φ_ps (°)",
                    "flanks at start (°) (fitted)"
                ],
                &slope_headers(3.0)
            ),
            &rows
        )
    );
    std::fs::write(path, &*md).unwrap();
    let runs = [(32.0, 0.01), (32.0, 0.005), (45.0, 0.01)].map(|(phi, h)| (phi, avg(h)));
    let _ = writeln!(
        md,
        "## Volumetric locking: heaps (lifted walls at {LIFT_SPEED} m/s, floor μ = tan φ)\n\nEach particle's own volumetric rate: the stopping report.\n\n{}",
        heaps_table("locking", &runs)
    );
    std::fs::write(path, &*md).unwrap();
    let a2 = "column_collapse_a2_2d.json";
    let mut runs: Vec<(&str, f64, Numerics)> = Vec::new();
    for h in [0.02, 0.01, 0.005, 0.0025] {
        runs.push((a2, 2.0, avg(h)));
    }
    for ppc in [1, 3, 4] {
        runs.push((a2, 2.0, gimp(0.01).ppc(ppc)));
        runs.push((a2, 2.0, avg(0.01).ppc(ppc)));
    }
    // ppc 3 (at h = 0.01 m above) and μ(I) for a sand grain, alone and together
    runs.push((a2, 2.0, avg(0.005).ppc(3)));
    for h in [0.01, 0.005] {
        runs.push((a2, 2.0, avg(h).mu_i(fine)));
        runs.push((a2, 2.0, avg(h).ppc(3).mu_i(fine)));
    }
    for (file, a) in [
        ("column_collapse_a0.5_2d.json", 0.5),
        ("column_collapse_a1_2d.json", 1.0),
        ("column_collapse_a3_2d.json", 3.0),
    ] {
        for h in [0.01, 0.005] {
            runs.push((file, a, avg(h)));
        }
    }
    let _ = writeln!(
        md,
        "## Volumetric locking: plane column collapses (φ = 32°, floor μ = 0.625; Lube et al. 2005)\n\nRun-out as the farthest particle and as the edge of the continuous deposit; each particle's own volumetric rate at ppc 2: the stopping report and validation-report.md.\n\n{}",
        collapses_table("locking", runs)
    );
}

/// The friction match: the sand cases at the validation resolution (h = 0.01 m) with the
/// paper's cone (Eq. 13 alone), with the steady-flow match (3 α_φ = tan φ), and with
/// the steady-flow match and the cell-averaged volumetric rate. Heaps (φ = 20°, 32°, 45°, and
/// at h = 0.005 m), slopes (gentler and steeper than φ_ps, 2 s, and at h = 0.005 m), plane
/// collapses (a = 0.5, 1, 2, 3, and at h = 0.005 m) and axisymmetric collapses (a = 0.5, 1,
/// 2).
pub fn flowmatch_study(md: &mut String, path: &std::path::Path) {
    // Eq. 13's cone alone, as the study was made (the default cone widens as sand flows)
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp).plane_strain();
    let variants = |h: f64| {
        [
            gimp(h),
            gimp(h).steady_flow(),
            gimp(h).steady_flow().cell_average(),
        ]
    };
    let _ = writeln!(
        md,
        "Friction match: `cargo bench --bench validate -- flowmatch`. `steady-flow`: the cone's α_φ = tan φ / 3 (`\"friction_match\": \"steady_flow\"`), so that a steadily shearing layer mobilises τ/σ_n = tan φ; without it, Eq. 13 alone (the paper's), with which it mobilises 3 α_φ = sin φ_ps. θ* = atan(3 α_φ): the slope on which a flowing layer stops (φ itself with the steady-flow match). `cell-avg`: the sand takes its cells' mean volumetric strain rate (`\"volumetric_rate\": \"cell_average\"`).\n"
    );
    let phis = [20.0, 32.0, 45.0];
    let heaps = |h: f64| -> Vec<(f64, Numerics)> {
        phis.iter()
            .flat_map(|&phi| variants(h).map(|n| (phi, n)))
            .collect()
    };
    let _ = writeln!(
        md,
        "## Friction match: heaps (lifted walls at {LIFT_SPEED} m/s, floor μ = tan φ, h = 0.01 m)\n\nTarget: within 3° of φ_ps.\n\n{}",
        heaps_table("flowmatch", &heaps(0.01))
    );
    std::fs::write(path, &*md).unwrap();
    let runs = plane_runs(&[variants(0.01).to_vec(), variants(0.005).to_vec()]);
    plane_section(md, "Friction match", "flowmatch", runs);
    std::fs::write(path, &*md).unwrap();
    // per friction angle a slope 5° gentler than φ_ps (stands) and one about 10° steeper
    // (fails), as in the validation's slopes; and φ = 32° at 35°, between φ_ps and the
    // steady-flow cone's static limit
    let mut cases = Vec::new();
    for (phi, gentle, steep) in [(20.0, 15.0, 30.0), (32.0, 25.0, 40.0), (45.0, 35.0, 50.0)] {
        for slope in [gentle, steep] {
            cases.extend(variants(0.01).map(|n| (phi, slope, n)));
        }
    }
    cases.extend(variants(0.01).map(|n| (32.0, 35.0, n)));
    // the gentle φ = 32° slope and the steep ones on the finer grid, where locking holds less
    cases.extend(variants(0.005).map(|n| (32.0, 25.0, n)));
    for (phi, steep) in [(20.0, 30.0), (32.0, 40.0), (45.0, 50.0)] {
        cases.extend(variants(0.005).map(|n| (phi, steep, n)));
    }
    slopes_section(md, "Friction match", "flowmatch", cases);
    std::fs::write(path, &*md).unwrap();
    let runs = axi_runs(variants(0.01).to_vec());
    axi_section(md, "Friction match", "", "flowmatch", runs);
    std::fs::write(path, &*md).unwrap();
    let _ = writeln!(
        md,
        "## Friction match: heaps at h = 0.005 m (lifted walls at {LIFT_SPEED} m/s)\n\n{}",
        heaps_table("flowmatch", &heaps(0.005))
    );
}

/// Start–stop against Eq. 13 alone: heaps, slopes and plane collapses at h = 0.01 and 0.005 m,
/// axisymmetric collapses at h = 0.01 m.
pub fn startstop_study(md: &mut String, path: &std::path::Path) {
    let gimp = |h: f64| Numerics::new(h, KernelKind::Gimp);
    let variants = |h: f64| [gimp(h).plane_strain(), gimp(h).start_stop()];
    let _ = writeln!(
        md,
        "Start–stop cone: `cargo bench --bench validate -- startstop`. `plane-strain`: Eq. 13's cone alone (`\"friction_match\": \"plane_strain\"`, the paper's); `start-stop`: Eq. 13's cone widening with the plastic strain to 3 α = tan φ_ps (the default). θ* = atan of the friction a steadily flowing layer carries: the slope on which it stops.\n"
    );
    let phis = [20.0, 32.0, 45.0];
    for h in [0.01, 0.005] {
        let runs: Vec<(f64, Numerics)> = phis
            .iter()
            .flat_map(|&phi| variants(h).map(|n| (phi, n)))
            .collect();
        let _ = writeln!(
            md,
            "## Start–stop: heaps (lifted walls at {LIFT_SPEED} m/s, floor μ = tan φ, h = {h} m)\n\nTarget: within 3° of φ_ps.\n\n{}",
            heaps_table("startstop", &runs)
        );
        std::fs::write(path, &*md).unwrap();
    }
    let mut cases = Vec::new();
    for h in [0.01, 0.005] {
        for (phi, gentle, steep) in [(20.0, 15.0, 30.0), (32.0, 25.0, 40.0), (45.0, 35.0, 50.0)] {
            for slope in [gentle, steep] {
                cases.extend(variants(h).map(|n| (phi, slope, n)));
            }
        }
    }
    slopes_section(md, "Start–stop", "startstop", cases);
    std::fs::write(path, &*md).unwrap();
    let runs = plane_runs(&[variants(0.01).to_vec(), variants(0.005).to_vec()]);
    plane_section(md, "Start–stop", "startstop", runs);
    std::fs::write(path, &*md).unwrap();
    let runs = axi_runs(variants(0.01).to_vec());
    axi_section(md, "Start–stop", ", h = 0.01 m", "startstop", runs);
}

/// The default (start–stop) sand at h = 0.0025 m: the plane collapses, the over-steep slopes,
/// then the heaps at the two faster lift speeds; the coarser grids are in the `startstop` and `repose` studies.
pub fn startstop_fine_study(md: &mut String, path: &std::path::Path) {
    let n = Numerics::new(0.0025, KernelKind::Gimp).start_stop();
    let runs = PLANE_COLLAPSES
        .iter()
        .map(|&(file, a)| (file, a, n))
        .collect();
    let _ = writeln!(
        md,
        "## Start–stop: plane column collapses at h = 0.0025 m (φ = 32°, floor μ = 0.625; Lube et al. 2005)\n\nRun-out as the farthest particle and as the edge of the continuous deposit. Target: run-out within 20 %, H∞ within 10 %.\n\n{}",
        collapses_table("startstop-fine", runs)
    );
    std::fs::write(path, &*md).unwrap();
    let cases = [(20.0, 30.0), (32.0, 40.0), (45.0, 50.0)]
        .map(|(phi, steep)| (phi, steep, n))
        .to_vec();
    let _ = writeln!(
        md,
        "## Start–stop: over-steep slopes at h = 0.0025 m (2 s, E = 350 kPa)\n\nTarget: a slope steeper than φ_ps fails within a fraction of a second and stops near φ_ps.\n\n{}",
        slopes_table("startstop-fine", cases)
    );
    std::fs::write(path, &*md).unwrap();
    for lift in [LIFT_SPEED, SLOW_LIFT_SPEED] {
        let runs: Vec<(f64, Numerics)> = [20.0, 32.0, 45.0].map(|phi| (phi, n)).to_vec();
        let _ = writeln!(
            md,
            "## Start–stop: heaps at h = 0.0025 m (walls lifted at {lift} m/s, floor μ = tan φ)\n\nTarget: within 3° of φ_ps.\n\n{}",
            heaps_table_lifted("startstop-fine", &runs, lift)
        );
        std::fs::write(path, &*md).unwrap();
    }
}

/// The a = 1 axisymmetric collapse refined to h = 0.005 m, with Eq. 13 and with the
/// steady-flow match.
pub fn flowmatch_axi_study(md: &mut String) {
    let gimp = Numerics::new(0.005, KernelKind::Gimp).plane_strain();
    let runs = [gimp, gimp.steady_flow()].map(|n| ("column_collapse_axi_a1_3d.json", 1.0, n));
    let _ = writeln!(
        md,
        "## Friction match: the axisymmetric collapse a = 1 at h = 0.005 m\n\n{}",
        axi_table("flowmatch", runs.to_vec())
    );
}

/// The axisymmetric collapses refined to h = 0.005 m with the start–stop cone.
pub fn startstop_axi_study(md: &mut String) {
    let n = Numerics::new(0.005, KernelKind::Gimp).start_stop();
    let _ = writeln!(
        md,
        "## Start–stop: the axisymmetric collapses at h = 0.005 m\n\n{}",
        axi_table(
            "startstop",
            vec![
                ("column_collapse_axi_a0.5_3d.json", 0.5, n),
                ("column_collapse_axi_a1_3d.json", 1.0, n),
                ("column_collapse_axi_a2_3d.json", 2.0, n),
            ]
        )
    );
}

/// The study's slopes (`title`: its name in the heading, `study`: its key in the table) under
/// their heading and bound.
fn slopes_section(md: &mut String, title: &str, study: &str, cases: Vec<(f64, f64, Numerics)>) {
    let _ = writeln!(
        md,
        "## {title}: slopes (2 s, E = 350 kPa)\n\nA trapezoidal heap 0.1 m high released on a floor with μ = tan φ. *Failed at*: when the flanks had come halfway down from their initial angle to φ_ps. Target: a slope gentler than φ_ps stands (no creep over 2 s), a steeper one fails within a fraction of a second and stops near φ_ps.\n\n{}",
        slopes_table(study, cases)
    );
}

/// Every axisymmetric collapse under each of the numerics `variants`.
fn axi_runs(variants: Vec<Numerics>) -> Vec<(&'static str, f64, Numerics)> {
    AXI_COLLAPSES
        .iter()
        .flat_map(|&(file, a)| variants.iter().map(move |&n| (file, a, n)))
        .collect()
}

/// The study's axisymmetric collapses under their heading (`grid`: what the heading adds
/// after the floor, e.g. `, h = 0.01 m`) and bound.
fn axi_section(
    md: &mut String,
    title: &str,
    grid: &str,
    study: &str,
    runs: Vec<(&str, f64, Numerics)>,
) {
    let _ = writeln!(
        md,
        "## {title}: axisymmetric collapses (3D, φ = 32°, floor μ = 0.625{grid}; Lube et al. 2004, Lajeunesse et al. 2004)\n\nRun-out as the mean over 16 azimuthal sectors of the farthest particle, and as the edge of the continuous deposit. Target: run-out within 25 %, H∞ within 15 %.\n\n{}",
        axi_table(study, runs)
    );
}

/// Every plane collapse under each numerics of each grid's `variants`, grid by grid.
fn plane_runs(variants: &[Vec<Numerics>]) -> Vec<(&'static str, f64, Numerics)> {
    let mut runs = Vec::new();
    for grid in variants {
        for (file, a) in PLANE_COLLAPSES {
            runs.extend(grid.iter().map(|&n| (file, a, n)));
        }
    }
    runs
}

/// The study's plane collapses under their heading and bound.
fn plane_section(md: &mut String, title: &str, study: &str, runs: Vec<(&str, f64, Numerics)>) {
    let _ = writeln!(
        md,
        "## {title}: plane column collapses (φ = 32°, floor μ = 0.625; Lube et al. 2005)\n\nRun-out as the farthest particle and as the edge of the continuous deposit. Target: run-out within 20 %, H∞ within 10 %.\n\n{}",
        collapses_table(study, runs)
    );
}
