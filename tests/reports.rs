//! The generated reports are today's solver's: each report in docs/reports/ (and the figures
//! of docs/work-precision.md and of scenes.md's run-time table) records the digest of the
//! solver it was made with (`tests/support/digest.rs`), and this test fails, naming the
//! command that regenerates it, when that digest is not today's. A report kept as the record
//! of a decision says so on an "Archive:" line instead; docs/reports/README.md indexes them
//! all.

#[path = "support/digest.rs"]
mod digest;

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The files that hold generated figures: every report in docs/reports/ but its index, and the
/// two documents whose tables are generated.
fn report_files() -> Vec<PathBuf> {
    let dir = root().join("docs/reports");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .filter(|p| p.file_name().is_some_and(|n| n != "README.md"))
        .collect();
    files.sort();
    files.push(root().join("docs/work-precision.md"));
    files.push(root().join("docs/scenes.md"));
    files
}

fn shown(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

/// Whether a report declares itself an archive (the record of a decision, made by an earlier
/// solver and not regenerated).
fn is_archive(text: &str) -> bool {
    text.lines().any(|l| l.starts_with("Archive: "))
}

#[cfg(all(not(feature = "f64"), target_arch = "x86_64"))]
#[test]
fn every_report_records_todays_solver() {
    let today = digest::digests().expect("the canonical runs run");
    let mut stale = Vec::new();
    for file in report_files() {
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{file:?}: {e}"));
        let stamps = digest::stamps(&text).unwrap_or_else(|e| panic!("{}: {e}", shown(&file)));
        if stamps.is_empty() {
            if !is_archive(&text) {
                stale.push(format!(
                    "{} records no solver (no \"Solver digest:\" line and no \"Archive:\" line)",
                    shown(&file)
                ));
            }
            continue;
        }
        for stamp in stamps {
            let mut changed = Vec::new();
            for (family, recorded) in &stamp.digests {
                match today.iter().find(|(f, _)| f == family) {
                    None => changed.push(format!("{family}: not a family of the digest")),
                    Some((_, now)) if now != recorded => {
                        changed.push(format!("{family} {recorded:016x}, today {now:016x}"))
                    }
                    Some(_) => {}
                }
            }
            if !changed.is_empty() {
                stale.push(format!(
                    "{} was made by another solver ({}): regenerate it with `{}`",
                    shown(&file),
                    changed.join("; "),
                    stamp.regenerate
                ));
            }
        }
    }
    let listed: Vec<String> = today.iter().map(|(f, d)| format!("{f} {d:016x}")).collect();
    assert!(
        stale.is_empty(),
        "today's solver digest: {}\n{}",
        listed.join(", "),
        stale.join("\n")
    );
}

/// The index lists every report, so none is made or left without a word on what made it.
#[test]
fn the_index_lists_every_report() {
    let index = std::fs::read_to_string(root().join("docs/reports/README.md")).unwrap();
    let dir = root().join("docs/reports");
    let mut missing = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name != "README.md" && !index.contains(&format!("({name})")) {
            missing.push(name);
        }
    }
    assert!(
        missing.is_empty(),
        "docs/reports/README.md does not link {missing:?}"
    );
}

/// A stamp reads back as written, and the digest of a family is a pure function of the
/// solver: two computations agree bit for bit (a digest that varied from run to run would
/// fail every report).
#[cfg(not(feature = "f64"))]
#[test]
fn a_stamp_reads_back_and_the_digest_repeats() {
    let line = digest::stamp_line(&["sand"], "cargo xtask validate grids");
    let stamps = digest::stamps(&format!("# A report\n\n{line}\n")).unwrap();
    let again = digest::digests().unwrap();
    assert_eq!(stamps.len(), 1);
    assert_eq!(stamps[0].regenerate, "cargo xtask validate grids");
    let sand = again.iter().find(|(f, _)| *f == "sand").unwrap().1;
    assert_eq!(stamps[0].digests, vec![("sand".to_string(), sand)]);
    assert!(digest::stamps("Solver digest: sand 12; no command").is_err());
}
