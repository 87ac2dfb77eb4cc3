//! Validation against known answers, at the coarse resolutions the test suite can afford
//! (the long versions: `cargo xtask validate`; see docs/validation.md). Each case runs a
//! scene of `scenes/validation/` and asserts its error against a closed form or a published
//! measurement within a stated tolerance.

#[path = "support/validation.rs"]
mod validation;

use mpm::{D2, D3, KernelKind};
use validation::*;

/// The first axial mode of a free–free bar: period and amplitude of u = (v0/ω) sin ωt
/// cos(πx/L) over three periods, with FLIP (α = 1, energy-conserving transfers) in 2D and 3D.
#[test]
fn vibrating_bar_period_and_amplitude() {
    let n = Numerics::new(0.025, KernelKind::Gimp).flip(1.0);
    let b2 = vibrating_bar::<D2>("vibrating_bar_2d.json", &n, 3.0);
    eprintln!("bar 2D: {b2:?}");
    assert!(b2.failure.is_none(), "2D bar failed {:?}", b2.failure);
    assert!(
        b2.period_error().abs() < 0.01,
        "2D period {} vs {}",
        b2.period,
        b2.period_exact
    );
    assert!(
        b2.amplitude_error().abs() < 0.03,
        "2D amplitude {} vs {}",
        b2.amplitude,
        b2.amplitude_exact
    );
    assert!(b2.l2_error < 0.08, "2D L2 error {}", b2.l2_error);
    let n3 = Numerics::new(0.05, KernelKind::Gimp).flip(1.0);
    let b3 = vibrating_bar::<D3>("vibrating_bar_3d.json", &n3, 2.0);
    eprintln!("bar 3D: {b3:?}");
    assert!(b3.failure.is_none(), "3D bar failed {:?}", b3.failure);
    assert!(
        b3.period_error().abs() < 0.02,
        "3D period {} vs {}",
        b3.period,
        b3.period_exact
    );
    assert!(
        b3.amplitude_error().abs() < 0.05,
        "3D amplitude {} vs {}",
        b3.amplitude,
        b3.amplitude_exact
    );
}

/// PIC (α = 0) damps the vibration; FLIP keeps it. Both converge with the cell size.
#[test]
fn pic_damps_the_bar_and_the_damping_shrinks_with_the_cell_size() {
    let coarse = Numerics::new(0.05, KernelKind::Gimp).flip(0.0);
    let fine = Numerics::new(0.025, KernelKind::Gimp).flip(0.0);
    let flip = Numerics::new(0.05, KernelKind::Gimp).flip(1.0);
    let (c, f, x) = (
        vibrating_bar::<D2>("vibrating_bar_2d.json", &coarse, 3.0),
        vibrating_bar::<D2>("vibrating_bar_2d.json", &fine, 3.0),
        vibrating_bar::<D2>("vibrating_bar_2d.json", &flip, 3.0),
    );
    eprintln!(
        "kept: PIC h=0.05 {}, PIC h=0.025 {}, FLIP h=0.05 {}",
        c.amplitude_kept, f.amplitude_kept, x.amplitude_kept
    );
    assert!(x.amplitude_kept > 0.97, "FLIP lost amplitude: {x:?}");
    assert!(c.amplitude_kept < 0.9, "PIC should damp: {c:?}");
    assert!(
        f.amplitude_kept > c.amplitude_kept,
        "PIC damping should shrink with h: {} vs {}",
        f.amplitude_kept,
        c.amplitude_kept
    );
    assert!(f.l2_error < c.l2_error);
}

/// A Gaussian velocity pulse in a slab between slip walls travels at the dilatational speed
/// √((K + 4G/3)/ρ), not at the bar speed √(E/ρ) (16 % lower for ν = 0.3).
#[test]
fn dilatational_wave_speed() {
    let w = wave_speed(&Numerics::new(0.02, KernelKind::Gimp).flip(1.0));
    eprintln!("wave: {w:?} error {}", w.error());
    assert!(
        w.error().abs() < 0.03,
        "speed {} vs {}",
        w.speed,
        w.speed_exact
    );
    assert!((w.speed - w.speed_exact).abs() < 0.2 * (w.speed_exact - w.bar_speed));
}

/// von Mises in plane strain: elastic at E/(1 − ν²), first yield at σ_y/√(1 − ν + ν²), then
/// towards 2σ_y/√3; in 3D uniaxial stress: E, then flat at σ_y.
#[test]
fn von_mises_squeeze_follows_the_elastic_perfectly_plastic_curve() {
    let n = Numerics::new(0.01, KernelKind::Gimp);
    let s2 = squeeze::<D2>("von_mises_compression_2d.json", &n, 0.03);
    eprintln!(
        "squeeze 2D: max {} plateau {} modulus {} ({} steps)",
        s2.max_error, s2.plateau_error, s2.modulus_error, s2.cost.steps
    );
    assert!(s2.plateau_error.abs() < 0.03, "2D plateau {s2:?}");
    assert!(
        s2.modulus_error.abs() < 0.1,
        "2D modulus {}",
        s2.modulus_error
    );
    assert!(s2.max_error < 0.1, "2D max error {}", s2.max_error);
    let n3 = Numerics::new(0.02, KernelKind::Gimp);
    let s3 = squeeze::<D3>("von_mises_compression_3d.json", &n3, 0.03);
    eprintln!(
        "squeeze 3D: max {} plateau {} modulus {} ({} steps)",
        s3.max_error, s3.plateau_error, s3.modulus_error, s3.cost.steps
    );
    assert!(
        s3.plateau_error.abs() < 0.03,
        "3D plateau {}",
        s3.plateau_error
    );
    assert!(
        s3.modulus_error.abs() < 0.1,
        "3D modulus {}",
        s3.modulus_error
    );
    assert!(s3.max_error < 0.1, "3D max error {}", s3.max_error);
}

/// Plane granular column collapse on a rough floor against Lube et al. (2005), with the
/// sand's defaults (APIC base, α = 0.05, the start–stop cone), at h = 0.01 m (10 cells per
/// H0 at a = 0.5, 20 at a = 2), the bands of docs/validation.md: the run-out where the
/// deposit is one grain thick within −20 % / +25 % of the measured law (of the range its two
/// regimes span at a = 2), the farthest particle at most 2a, the final height within 10 %,
/// and at a = 0.5 the flank in [φ_ps − 6°, φ_ps + 1°] (measured −5.9°) and the top within one
/// cell of H0.
/// (With the plain PIC blend the run-out was 47 % short; with Eq. 13's cone alone the deposit
/// of the a = 2 column stood 11 % low, docs/validation.md.)
#[test]
fn column_collapse_runout_and_height() {
    let mut runouts = Vec::new();
    for (file, a) in [
        ("column_collapse_a0.5_2d.json", 0.5),
        ("column_collapse_a2_2d.json", 2.0),
    ] {
        let c = column_collapse(file, &Numerics::new(0.01, KernelKind::Gimp), 3.0);
        eprintln!(
            "collapse a={a}: {c:?}; Lube: runout {} height {}",
            lube_runout(a),
            lube_height(a)
        );
        assert!((c.aspect_ratio - a).abs() < 1e-6);
        assert!(c.failure.is_none(), "a = {a}: {:?}", c.failure);
        assert!(c.settled_at < 3.0, "a = {a}: still moving at 3 s");
        assert!(
            (c.height / lube_height(a) - 1.0).abs() < 0.1,
            "a = {a}: H∞/H0 = {:.3}, Lube et al. {:.3}",
            c.height,
            lube_height(a)
        );
        let err = plane_runout_error(c.runout_thin, a);
        assert!(
            within(err, RUNOUT_BAND),
            "a = {a}: run-out at one grain {:.3}, {:+.0} % from Lube et al.",
            c.runout_thin,
            100.0 * err
        );
        assert!(farthest_is_sane(c.runout, a), "a = {a}: farthest {c:?}");
        let phi_ps = plane_strain_angle(32.0);
        assert!(
            !flank_band_applies(a) || within(c.flank - phi_ps, FLANK_BAND),
            "a = {a}: flank {:.1}° against φ_ps {phi_ps:.1}°",
            c.flank
        );
        if a < 1.0 {
            assert!(c.height >= 0.9, "a = {a}: top lost, H∞/H0 {:.3}", c.height);
        }
        runouts.push(c.runout_thin);
    }
    assert!(runouts[1] > 2.0 * runouts[0], "run-out should grow with a");
}

/// With the paper's plain PIC/FLIP blend (α = 0.05, no APIC) the same column runs out about
/// half as far as measured: the PIC part of the blend damps the flow. This is why sand takes
/// APIC by default; the bound shows if that damping changes.
#[test]
fn pic_blend_damps_the_column_collapse() {
    let a = 2.0;
    let n = Numerics::new(0.01, KernelKind::Gimp).pic();
    let c = column_collapse("column_collapse_a2_2d.json", &n, 4.0);
    eprintln!("collapse a={a} PIC: {c:?}");
    let ratio = c.runout / lube_runout(a);
    assert!(
        (0.4..0.7).contains(&ratio),
        "PIC run-out {:.3} is {ratio:.2} of Lube et al.'s",
        c.runout
    );
}

/// A heap left by slowly lifted walls stands within 3° of the plane-strain angle φ_ps of the
/// sand's cone at rest (19.6°, 30.4° and 40.9° for φ = 20°, 32°, 45°): where a slope at rest
/// starts to fail, flowing sand with the start–stop cone stops. With Eq. 13's cone alone the
/// flow carried on down to atan(sin φ_ps) and the heaps stood at 19.4°, 24.6° and 31.6°
/// (docs/validation.md). The surface fit on a grid of 1 cm is good to about 2°.
#[test]
fn angle_of_repose() {
    for phi in [20.0, 32.0, 45.0] {
        let p = repose_pile(
            &Numerics::new(0.01, KernelKind::Gimp),
            8.0,
            Some(phi),
            LIFT_SPEED,
        );
        eprintln!("pile φ = {phi}: {p:?}");
        assert!(
            (p.angle - p.plane_strain_angle).abs() < 3.0,
            "φ = {phi}: the heap stands at {:.1}°, φ_ps = {:.1}°",
            p.angle,
            p.plane_strain_angle
        );
        assert!(
            (p.flanks[0] - p.flanks[1]).abs() < 4.0,
            "asymmetric heap {p:?}"
        );
    }
}

/// A cohesionless slope gentler than its plane-strain friction angle stands: a heap with 25°
/// flanks of φ = 32° sand (φ_ps = 30.4°) released on a rough floor neither creeps nor
/// flattens over 2 s (beyond the elastic settling of its stress-free release).
#[test]
fn a_slope_gentler_than_the_friction_angle_stands() {
    let r = heap_slope(
        32.0,
        25.0,
        3.5e5,
        &Numerics::new(0.01, KernelKind::Gimp),
        2.0,
    );
    eprintln!("gentle slope: {r:?}");
    assert!(
        r.creep < 1e-3,
        "the 25° slope crept by {:.2} mm after {CREEP_FROM} s",
        1e3 * r.creep
    );
    assert!(
        (r.angle - r.initial_angle).abs() < 1.0,
        "the 25° slope went from {:.1}° to {:.1}°",
        r.initial_angle,
        r.angle
    );
    assert!(
        r.final_speed < 1e-3,
        "still moving at {} m/s",
        r.final_speed
    );
}

/// A cohesionless slope steeper than its plane-strain friction angle cannot stand: a heap
/// with 40° flanks of φ = 32° sand (φ_ps = 30.4°) avalanches (its flanks come halfway down to
/// φ_ps within half a second) and comes to rest in [φ_ps − 5°, φ_ps + 1°], only slightly
/// under the angle of repose (Siavoshi & Kudrolli 2005). On the finer grid h = 0.005 m: at
/// h = 0.01 m the start–stop cone widens before the avalanche has run its course and the
/// flanks stop at 34° (docs/validation.md).
#[test]
fn a_slope_steeper_than_the_friction_angle_fails() {
    let r = heap_slope(
        32.0,
        40.0,
        3.5e5,
        &Numerics::new(0.005, KernelKind::Gimp),
        2.0,
    );
    eprintln!("steep slope: {r:?}");
    let t = r.failed_at.expect("the 40° slope did not fail");
    assert!(t < 0.5, "the 40° slope took {t:.2} s to fail");
    assert!(
        within(r.angle - r.plane_strain_angle, REST_BAND),
        "the avalanche stopped at {:.1}°, φ_ps = {:.1}°",
        r.angle,
        r.plane_strain_angle
    );
}

/// Volumetric locking and its cure: at h = 0.01 m with 3 particles per cell a 40° slope of
/// φ = 32° sand (φ_ps = 30.4°) is held up by the grid when each particle takes its own
/// volumetric strain rate (it does not come halfway down to φ_ps in a second), and fails
/// within half a second, down to below φ_ps, when the rate is averaged over each cell
/// (docs/validation.md, "The sand model behind the figures").
#[test]
fn the_cell_averaged_volumetric_rate_unlocks_the_over_steep_slope() {
    let n = Numerics::new(0.01, KernelKind::Gimp).ppc(3);
    let locked = heap_slope(32.0, 40.0, 3.5e5, &n, 1.0);
    eprintln!("each particle's volumetric rate: {locked:?}");
    let free = heap_slope(32.0, 40.0, 3.5e5, &n.cell_average(), 1.0);
    eprintln!("cell-averaged: {free:?}");
    assert!(
        locked.failed_at.is_none() && locked.angle > locked.plane_strain_angle + 4.0,
        "the locked 40° slope came down to {:.1}°",
        locked.angle
    );
    let t = free
        .failed_at
        .expect("the 40° slope did not fail with the cell average");
    assert!(t < 0.5, "with the cell average it took {t:.2} s to fail");
    assert!(
        free.angle < free.plane_strain_angle,
        "with the cell average it stopped at {:.1}°, above φ_ps = {:.1}°",
        free.angle,
        free.plane_strain_angle
    );
}

/// Axisymmetric collapse of a column with a = 1 against Lube et al. (2004), at the validation
/// resolution's coarse neighbour (R0 = 10 cells), what holds there: the run-out where the
/// deposit is one grain thick no more than 30 % short and the farthest particle no more than
/// 25 % short (the −20 % / +25 % band holds only at 20 cells per R0, docs/validation.md), the
/// farthest particle at most 2a.
/// The final height within the ±15 % band of Lube et al.'s or Lajeunesse et al.'s (2004) law
/// (−0.3 % from Lajeunesse et al.'s), and a round deposit.
#[test]
fn axisymmetric_column_collapse() {
    let a = 1.0;
    let c = axisymmetric_collapse(
        "column_collapse_axi_a1_3d.json",
        &Numerics::new(0.01, KernelKind::Gimp),
        4.0,
    );
    eprintln!("axisymmetric collapse a = {a}: {c:?}");
    assert!(c.failure.is_none(), "{:?}", c.failure);
    assert!(c.spread < 0.2, "the deposit is not round: {c:?}");
    let r = lube_axisymmetric_runout(a);
    assert!(
        (c.runout / r - 1.0).abs() < 0.25,
        "run-out {:.3}, Lube et al. {r:.2}",
        c.runout
    );
    assert!(
        within(c.runout_thin / r - 1.0, [-0.3, RUNOUT_BAND[1]]),
        "run-out at one grain {:.3}, Lube et al. {r:.2}",
        c.runout_thin
    );
    assert!(farthest_is_sane(c.runout, a), "farthest {c:?}");
    // the two published final-height laws differ by 20 % at a = 1 (0.88 and 0.74)
    let (h1, h2) = (
        lube_axisymmetric_height(a),
        lajeunesse_axisymmetric_height(a),
    );
    assert!(
        (c.height / h1 - 1.0).abs() < 0.15 || (c.height / h2 - 1.0).abs() < 0.15,
        "H∞/H0 = {:.3}, Lube et al. {h1:.3}, Lajeunesse et al. {h2:.3}",
        c.height
    );
}

/// Sand sheets one and two cells thick (two and four particle rows) thrown along a floor with
/// μ = 0.5 stop after v0²/(2 μ g): the floor's friction is proportional to the weight it
/// carries, for the rows that straddle the floor nodes too (the particles' half-width). With
/// the paper's plain blend the sheets slide as rigid slabs (within 2 %); with the sand's
/// default transfer (APIC) the thicker sheet also shears internally and its centre of mass
/// travels 3 % further (docs/validation.md), so the bound there is 5 %.
#[test]
fn sand_sheets_slide_the_coulomb_distance() {
    for (n, tolerance) in [
        (Numerics::new(0.01, KernelKind::Gimp).pic(), 0.02),
        (Numerics::new(0.01, KernelKind::Gimp), 0.05),
    ] {
        for thickness in [0.01, 0.02] {
            let r = sand_sheet_slide(thickness, 0.5, 1.0, &n);
            eprintln!("sheet {thickness} m {}: {r:?}", n.label());
            assert!(
                (r.travel / r.travel_exact - 1.0).abs() < tolerance,
                "a {thickness} m sheet ({}) slid {:.4} m, Coulomb {:.4} m",
                n.label(),
                r.travel,
                r.travel_exact
            );
            assert!(
                r.final_speed < 0.01,
                "still sliding at {} m/s",
                r.final_speed
            );
        }
    }
}

/// The low plane column (a = 0.5, H0 = 0.1 m) of φ = 30° sand on a rough floor (μ = 0.6) at
/// 10 and 20 cells per height holds the bands of docs/validation.md: the run-out where the
/// deposit is one grain thick within −20 % / +25 % of Lube et al. (2005)'s 1.2 a, the
/// farthest particle at most 2a, the flank (the surface between 20 % and 80 % of the
/// deposit's height) in [φ_ps − 6°, φ_ps + 1°] (φ_ps = 28.7°) and the same within 1° on both
/// grids, the top within one cell of H0.
#[test]
fn a_low_column_at_two_grids() {
    let a = 0.5;
    let mut flanks = Vec::new();
    for h in [0.01, 0.005] {
        let r = low_column(30.0, &Numerics::new(h, KernelKind::Gimp), 3.0);
        let d = &r.deposit;
        eprintln!("low column h = {h}: {r:?}");
        assert!(r.failure.is_none() && r.settled_at < 3.0, "h = {h}: {r:?}");
        assert!(
            within(d.runout_thin / lube_runout(a) - 1.0, RUNOUT_BAND),
            "h = {h}: run-out at one grain {:.3} against Lube et al.'s {:.2}",
            d.runout_thin,
            lube_runout(a)
        );
        assert!(farthest_is_sane(d.runout, a), "h = {h}: farthest {d:?}");
        assert!(
            d.height >= 1.0 - h / 0.1,
            "h = {h}: top lost, H∞/H0 {:.3}",
            d.height
        );
        let gap = d.flank() - r.plane_strain_angle;
        assert!(
            within(gap, FLANK_BAND),
            "h = {h}: flank {:.1}° against φ_ps {:.1}°",
            d.flank(),
            r.plane_strain_angle
        );
        flanks.push(d.flank());
    }
    assert!(
        (flanks[1] - flanks[0]).abs() < 1.0,
        "the flank moved from {:.1}° to {:.1}° with the grid",
        flanks[0],
        flanks[1]
    );
}

/// The plane collapse a = 2 at the validation resolution's coarse neighbour, 10 cells per
/// column height (h = 0.02 m), against Lube et al. (2005): a = 2 lies between their two
/// regimes, so the run-out where the deposit is one grain thick is checked against the range
/// 1.2 a … 1.9 a^(2/3) = 2.40 … 3.02 within −20 % / +25 %, the farthest particle at most 2a,
/// the final height within ±10 %.
#[test]
fn plane_collapse_at_ten_cells_per_height() {
    let a = 2.0;
    let c = column_collapse(
        "column_collapse_a2_2d.json",
        &Numerics::new(0.02, KernelKind::Gimp),
        4.0,
    );
    eprintln!("collapse a = {a}, 10 cells per H0: {c:?}");
    assert!(c.failure.is_none(), "{:?}", c.failure);
    let err = plane_runout_error(c.runout_thin, a);
    assert!(
        within(err, RUNOUT_BAND),
        "run-out at one grain {:.3}, {:+.0} % from Lube et al.'s range",
        c.runout_thin,
        100.0 * err
    );
    assert!(farthest_is_sane(c.runout, a), "farthest {c:?}");
    assert!(
        (c.height / lube_height(a) - 1.0).abs() < 0.1,
        "H∞/H0 = {:.3}, Lube et al. {:.3}",
        c.height,
        lube_height(a)
    );
}

/// H∞/H0 of the plane collapse of aspect ratio `a` (scene `file`, column height `h0`) at 20
/// and 40 cells per column height.
fn heights_at_20_and_40_cells(file: &str, h0: f64) -> [f64; 2] {
    [20.0, 40.0].map(|k| {
        let c = column_collapse(file, &Numerics::new(h0 / k, KernelKind::Gimp), 4.0);
        assert!(
            c.failure.is_none(),
            "{file} at {k} cells per H0: {:?}",
            c.failure
        );
        c.height
    })
}

/// Final heights converge: the plane collapses a = 1 and 2 change H∞/H0 by at most 2 points
/// between 20 and 40 cells per column height, the two finest grids of the validation sweep
/// (measured +1.2 and −0.1 points; `cargo xtask validate grids` checks every collapse).
#[test]
fn plane_collapse_heights_converge() {
    for (file, a, h0) in [
        ("column_collapse_a1_2d.json", 1.0, 0.15),
        ("column_collapse_a2_2d.json", 2.0, 0.2),
    ] {
        let [h20, h40] = heights_at_20_and_40_cells(file, h0);
        eprintln!("a = {a}: H∞/H0 {h20:.3} → {h40:.3}");
        assert!(
            (h40 - h20).abs() <= 0.02,
            "a = {a}: H∞/H0 {h20:.3} at 20 cells per H0, {h40:.3} at 40"
        );
    }
}

/// The same 2-point convergence for the tallest plane column, a = 3: not met (0.476 at 20
/// cells per H0, 0.453 at 40: −2.3 points; docs/validation.md, the plane collapse).
#[test]
#[ignore = "not met: a = 3 H∞/H0 0.476 → 0.453 (−2.3 points) from 20 to 40 cells per H0"]
fn the_tallest_plane_collapse_height_converges() {
    let [h20, h40] = heights_at_20_and_40_cells("column_collapse_a3_2d.json", 0.3);
    assert!(
        (h40 - h20).abs() <= 0.02,
        "a = 3: H∞/H0 {h20:.3} at 20 cells per H0, {h40:.3} at 40"
    );
}

/// The same low column (φ = 30°) at 40 cells per height (h = 0.0025 m), the fine grid's
/// target: the run-out where the deposit is one grain thick within −20 % / +25 % of 1.2 a and
/// the flank in [φ_ps − 6°, φ_ps + 1°]. The run-out is not met: a toe a few particle rows
/// thick runs out too far on fine grids (docs/validation.md, the low column).
#[test]
#[ignore = "not met: at 40 cells per H0 the run-out at one grain is 0.762, +27 % of 1.2 a (flank −4.3°, within its band); docs/validation.md, a low column on a rough floor"]
fn a_low_column_holds_its_bands_at_forty_cells() {
    let a = 0.5;
    let r = low_column(30.0, &Numerics::new(0.0025, KernelKind::Gimp), 3.0);
    let d = &r.deposit;
    eprintln!("low column h = 0.0025: {r:?}");
    assert!(r.failure.is_none(), "{r:?}");
    assert!(
        within(d.runout_thin / lube_runout(a) - 1.0, RUNOUT_BAND),
        "run-out at one grain {:.3} against Lube et al.'s {:.2}",
        d.runout_thin,
        lube_runout(a)
    );
    assert!(farthest_is_sane(d.runout, a), "farthest {d:?}");
    assert!(
        within(d.flank() - r.plane_strain_angle, FLANK_BAND),
        "flank {:.1}° against φ_ps {:.1}°",
        d.flank(),
        r.plane_strain_angle
    );
}

/// The low column's flank rests under φ_ps because of its collapse's momentum, not because of
/// the cone's static angle: the same column (φ = 20° and 30°, h = 0.01 m) collapsing with every
/// particle's speed clamped to 0.05 m/s (quasi-static: kinetic energy at most 1/800 of g H0 per
/// unit mass) rests with its flank within 3° of φ_ps, while the free collapse's flank rests
/// more than 2° lower than the quasi-static one (measured +1.3° / −0.6° against φ_ps, free
/// 4.6° / 3.6° lower; docs/validation.md, what the flank's deficit comes from).
#[test]
fn a_low_column_without_momentum_rests_at_its_friction_angle() {
    let n = Numerics::new(0.01, KernelKind::Gimp);
    let t_max = 20.0;
    for phi in [20.0, 30.0] {
        let free = low_column(phi, &n, t_max);
        let slow = low_column_without_momentum(phi, &n, 0.05, t_max);
        eprintln!("φ = {phi}°: free {free:?}\ncapped {slow:?}");
        for (what, r) in [("free", &free), ("capped", &slow)] {
            assert!(
                r.failure.is_none() && r.settled_at < t_max,
                "φ = {phi}°, {what}: not at rest: {r:?}"
            );
        }
        let (f, q) = (free.deposit.flank(), slow.deposit.flank());
        assert!(
            (q - slow.plane_strain_angle).abs() < 3.0,
            "φ = {phi}°: the quasi-static flank {q:.1}° against φ_ps {:.1}°",
            slow.plane_strain_angle
        );
        assert!(
            q - f > 2.0,
            "φ = {phi}°: the free flank {f:.1}° is not more than 2° under the quasi-static {q:.1}°"
        );
    }
}

/// A sand layer (φ = 30°, two and four cells thick at h = 0.005 m) sent at 1 m/s down a rough
/// floor (μ = 0.6) inclined at 10° and 20° comes to rest, its centre of mass within 20 % of
/// the distance v0² / (2 g (cos θ tan φ_ps − sin θ)) a rigid block on the plane-strain
/// friction needs (measured −11 … −1 %; docs/validation.md, a low column on a rough floor).
#[test]
fn a_flowing_layer_comes_to_rest_on_a_slope() {
    let n = Numerics::new(0.005, KernelKind::Gimp);
    for slope in [10.0, 20.0] {
        for cells in [2.0, 4.0] {
            let r = slope_layer(30.0, slope, cells * n.cell_size, 1.0, &n);
            eprintln!("layer θ = {slope}°, {cells} cells: {r:?}");
            assert!(
                r.stopped_at.is_finite(),
                "θ = {slope}°, {cells} cells: still moving at {} m/s",
                r.final_speed
            );
            assert!(
                (r.travel / r.block_travel - 1.0).abs() < 0.2,
                "θ = {slope}°, {cells} cells: travelled {:.3} m, a block {:.3} m",
                r.travel,
                r.block_travel
            );
        }
    }
}

/// Bui, Fukagawa, Sako & Ohno (2008)'s aluminium-rod collapse (φ = 19.8°, 0.2 m × 0.1 m
/// against a wall, floor μ = 0.5) at 10 cells per height against the experiment's digitised
/// final surface (`tests/data/bui2008_surface.csv`, about 1 mm digitising error): the model's
/// surface within 5 mm RMS of the experiment's (measured 3.3 mm), its flank (20–80 %
/// least-squares slope) within the collapse band [φ_ps − 6°, φ_ps + 1°] and within 2° of the
/// experiment's 16.1° (measured 16.2°). The run-out at one grain's thickness (0.374 m against
/// 0.438 m) and the failure line (33.2° against 32.8°) are reported, not asserted here
/// (docs/validation.md, Bui et al.).
#[test]
fn bui_et_al_2008_final_surface() {
    let b = bui_2008(&Numerics::new(0.01, KernelKind::Gimp), 4.0);
    eprintln!("Bui et al. (2008) at h = 0.01 m: {b:?}");
    assert!(b.run.failure.is_none(), "{:?}", b.run.failure);
    assert!(
        b.rms < 0.005,
        "surface {:.1} mm RMS from the experiment's",
        1e3 * b.rms
    );
    let phi_ps = b.run.plane_strain_angle;
    assert!(
        within(b.flank - phi_ps, FLANK_BAND),
        "flank {:.1}° against φ_ps {phi_ps:.1}°",
        b.flank
    );
    assert!(
        (b.flank - b.experiment_flank).abs() < 2.0,
        "flank {:.1}° against the experiment's {:.1}°",
        b.flank,
        b.experiment_flank
    );
}
