//! Project tasks (the cargo xtask pattern): `cargo xtask <task>`.
//!
//! - `test`  — every test: formatting, clippy, the native test suite.
//! - `validate` — the long validation runs; writes docs/validation-report.md.
//! - `work-precision` — the run time against error study; writes docs/work-precision-report.md
//!   and the SVG diagrams.
//! - `passes` — the cost of each pass for scenes that need different work; writes
//!   docs/passes-report.md.
//! - `stress` — the long stability sweep (`MPM_LONG=1`: more random scenes, longer resting
//!   runs, more fuzzing).
//!
//! The benchmarks are pinned to one core with `taskset -c 0` where it exists.

use std::process::{Command, ExitCode};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("test") => test(),
        Some("validate") => bench("validate", &args[1..]),
        Some("work-precision") => bench("work_precision", &args[1..]),
        Some("passes") => bench("passes", &args[1..]),
        Some("stress") => stress(),
        _ => {
            eprintln!("usage: cargo xtask <test|validate|work-precision|passes|stress>");
            eprintln!("  test            run every test (fmt, clippy, native tests)");
            eprintln!("  validate        long validation runs -> docs/validation-report.md");
            eprintln!(
                "  work-precision  run time against error -> docs/work-precision-report.md, SVGs"
            );
            eprintln!("  passes          cost of each pass -> docs/passes-report.md");
            eprintln!("  stress          the long stability sweep (MPM_LONG=1)");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs a command from the workspace root, failing on a non-zero exit.
fn run(program: &str, args: &[&str]) -> Result<(), String> {
    eprintln!("xtask: {program} {}", args.join(" "));
    let status = Command::new(program)
        .args(args)
        .current_dir(root())
        .status()
        .map_err(|e| format!("cannot start {program}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{program} {} failed ({status})", args.join(" ")))
    }
}

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

fn test() -> Result<(), String> {
    run("cargo", &["fmt", "--all", "--", "--check"])?;
    run(
        "cargo",
        &[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ],
    )?;
    run("cargo", &["test", "--workspace"])?;
    // the f64 build option: the unit tests (constitutive models, kernels, grid) in double precision
    run("cargo", &["test", "--lib", "--features", "f64"])?;
    Ok(())
}

/// Runs a report-writing benchmark on one core (`taskset -c 0` when available).
fn bench(name: &str, filters: &[String]) -> Result<(), String> {
    let mut args: Vec<&str> = vec!["bench", "--bench", name];
    if !filters.is_empty() {
        args.push("--");
        args.extend(filters.iter().map(String::as_str));
    }
    let pinned = Command::new("taskset")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if pinned {
        let mut all = vec!["-c", "0", "cargo"];
        all.extend(args);
        run("taskset", &all)
    } else {
        run("cargo", &args)
    }
}

/// The long stability sweep.
fn stress() -> Result<(), String> {
    eprintln!("xtask: MPM_LONG=1 cargo test --release --test stability -- --nocapture");
    let status = Command::new("cargo")
        .args([
            "test",
            "--release",
            "--test",
            "stability",
            "--",
            "--nocapture",
        ])
        .env("MPM_LONG", "1")
        .current_dir(root())
        .status()
        .map_err(|e| format!("cannot start cargo: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("the long stability sweep failed ({status})"))
    }
}
