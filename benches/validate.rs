//! The long validation runs: every case of `scenes/validation/` at finer resolutions than the
//! test suite affords, compared with its closed form or published measurement. Writes
//! `docs/reports/validation-report.md`.
//!
//! `taskset -c 0 cargo bench --bench validate` (or `cargo xtask validate`; about 10 minutes
//! on one core). Arguments filter the cases: `bar`, `wave`, `squeeze`, `collapse`, `axi`,
//! `repose`, `slopes`, `flip`, `resting`; `stopping` (where flowing sand comes to rest, with
//! and without μ(I): about 25 minutes) runs only when named and writes
//! `docs/reports/validation-report-stopping.md`; so does `locking` (sand with its volumetric strain
//! rate averaged over each cell against each particle's own: about 12 minutes), which writes
//! `docs/reports/validation-report-locking.md`; and `flowmatch` (the sand cases with the cone matched
//! to steady flow, 3 α_φ = tan φ, against Eq. 13's, with and without the cell-averaged
//! volumetric rate: about 20 minutes), which writes `docs/reports/validation-report-flowmatch.md`.
//! `lowcolumn` (part of the full run, about 10 minutes) is the low column on a rough floor at
//! φ = 20°, 30°, 40° and Bui et al. (2008)'s set-up against the experiment at 10, 20 and 40
//! cells per height (`bui` alone runs the latter).
//! `grids` (part of the full run, about 40 minutes) is the validation claim: the plane and
//! axisymmetric collapses, the heaps and the slopes at 10, 20 and 40 cells per column height
//! (10 and 20 per initial radius in 3D), and the low columns, against their bands, with the change per halving; it
//! fails, after writing its report, when a collapse's H∞/H0 changes by more than 2 points
//! between its two finest grids. With `coarse` it runs 10 and 20 cells only, with `fine` 40
//! only; `stress-last` runs the sweep (and `lowcolumn`) with the sand's stress updated last.
//!
//! One module per case family: `solids` (bar, wave, squeeze, FLIP, resting column), `sand`
//! (collapses, heaps and slopes at the validation's own resolutions), `lowcolumn`, `grids`, the
//! opt-in `studies`, and the report `tables` they share.

#[path = "support/report.rs"]
mod report;
#[path = "../tests/support/validation.rs"]
mod validation;

#[path = "validate/grids.rs"]
mod grids;
#[path = "validate/lowcolumn.rs"]
mod lowcolumn;
#[path = "validate/sand.rs"]
mod sand;
#[path = "validate/solids.rs"]
mod solids;
#[path = "validate/studies.rs"]
mod studies;
#[path = "validate/tables.rs"]
mod tables;

use report::*;
use std::fmt::Write;

fn main() {
    let filters = Filters::from_args();
    let want = |s: &str| filters.want(s);
    let opt_in = |s: &str| filters.0.iter().any(|f| f == s);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Validation report (generated)\n\nRegenerate with `taskset -c 0 cargo bench --bench validate` (or `cargo xtask validate`). Written by `benches/validate.rs`; the cases, references and discussion are in [validation.md](../validation.md). Run times are wall-clock seconds on one core. Measured at {}, {}, with {} on the machine's two cores when the run began.\n\n{}\n",
        measured_at(),
        placement(),
        load_average(),
        solver_line(
            &families_of(&filters, &["bar", "wave", "squeeze", "resting", "flip"]),
            &rerun_command("validate", &filters)
        )
    );
    // the report is rewritten after each case, so that an interrupted run keeps its results
    let path = filters.report_path("validation-report");
    if want("bar") {
        solids::bar(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("wave") {
        solids::wave(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("squeeze") {
        solids::squeeze(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("collapse") {
        sand::collapse(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("axi") {
        sand::axi(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("repose") {
        sand::repose(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("slopes") {
        sand::slopes(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    // the low columns are part of `grids`; alone when `lowcolumn` is named without it
    if want("lowcolumn") && !want("grids") {
        lowcolumn::lowcolumn_study(&mut md, &path, &grids::Grids::from_filters(&filters));
    }
    std::fs::write(&path, &md).unwrap();
    if want("lowcolumn") || opt_in("bui") {
        lowcolumn::bui_study(&mut md, &path);
    }
    std::fs::write(&path, &md).unwrap();
    // the collapses whose final height did not converge (checked once every case has run)
    let mut unconverged = Vec::new();
    if want("grids") {
        unconverged = grids::grids_study(&mut md, &path, &grids::Grids::from_filters(&filters));
    }
    std::fs::write(&path, &md).unwrap();
    // Opt-in (`cargo bench --bench validate -- stopping`): where flowing sand comes to rest,
    // over the cell size and the numerical and constitutive options, with and without the
    // rate-dependent friction μ(I).
    if opt_in("stopping") {
        studies::stopping_study(&mut md, &path);
    }
    // Opt-in (`cargo bench --bench validate -- locking`): volumetric locking of sand, each
    // particle's volumetric strain rate against its cell's average.
    if opt_in("locking") {
        studies::locking_study(&mut md, &path);
    }
    // Opt-in (`cargo bench --bench validate -- flowmatch`): the sand cases with the cone
    // matched to steady flow against Eq. 13.
    if opt_in("flowmatch") {
        studies::flowmatch_study(&mut md, &path);
    }
    // Opt-in (`-- flowmatch-axi`): the a = 1 axisymmetric collapse refined to h = 0.005 m, with
    // Eq. 13 and with the steady-flow match (about 20 minutes).
    if opt_in("flowmatch-axi") {
        studies::flowmatch_axi_study(&mut md);
    }
    // Opt-in (`-- startstop`): the sand cases with the default start–stop cone against
    // Eq. 13's alone, at two resolutions (about 40 minutes).
    if opt_in("startstop") {
        studies::startstop_study(&mut md, &path);
    }
    // Opt-in (`-- startstop-axi`): the axisymmetric collapses refined to h = 0.005 m with the
    // start–stop cone (about an hour; Eq. 13's is in `-- flowmatch-axi`).
    if opt_in("startstop-axi") {
        studies::startstop_axi_study(&mut md);
    }
    // Opt-in (`-- startstop-fine`): the default's plane collapses, over-steep slopes and heaps
    // refined once more, to h = 0.0025 m (about an hour): do they converge, which way, how fast.
    if opt_in("startstop-fine") {
        studies::startstop_fine_study(&mut md, &path);
    }
    std::fs::write(&path, &md).unwrap();
    if want("flip") {
        solids::flip(&mut md);
    }
    std::fs::write(&path, &md).unwrap();
    if want("resting") {
        solids::resting(&mut md);
    }
    std::fs::write(&path, md).unwrap();
    println!("wrote {}", path.display());
    assert!(
        unconverged.is_empty(),
        "final heights changed by more than 2 points between the two finest grids: {unconverged:?}"
    );
}
