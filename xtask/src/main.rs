//! Project tasks (the cargo xtask pattern): `cargo xtask <task>`.
//!
//! - `build`     — the browser playground: adds the wasm32 target if missing, installs
//!   wasm-bindgen-cli at the version in Cargo.lock if that version is not on PATH, builds the
//!   release wasm with simd128, runs `wasm-bindgen --target web` into `www/pkg/`, optimises
//!   the wasm with binaryen's `wasm-opt` (when on PATH) and writes the scene list `www/pkg/scenes.json` from the files in `scenes/`.
//!   It also writes the lesson list `www/pkg/lessons.json` from the files in `lessons/`.
//! - `serve`     — `build`, then serves the repository root on http://127.0.0.1:8080.
//! - `dist`      — `build`, then writes the page as a self-contained static folder,
//!   `target/dist/` (or `--out DIR`): the page, the wasm, the scenes, the lessons and their
//!   files, every URL relative, for any static web host as it is.
//! - `test`      — every test: formatting, clippy (native and wasm), the page's pure modules
//!   under `node --test`, the native test suite, the wasm tests in Node, the end-to-end
//!   tests in headless Chromium (also the classroom's: lessons, save and open, recording,
//!   touch on phone and tablet viewports) and Firefox, and the `dist` folder served alone by
//!   a plain static server under a sub-path and loaded in Chromium.
//! - `bench-web` — benchmarks that print figures: wasm in Node against native on the same
//!   scene, and the page's frame rate in headless Chromium.
//! - `live`      — the real-time factor of every shipped scene at the page's default quality:
//!   stepping alone (wasm in Node, one core) and as seen in headless Chromium (stepping and
//!   rendering), one `live scene=… rtf_step=… rtf_seen=… fps=…` line per scene; with
//!   `--drops`, a body dropped into each settled scene at Balanced and Fine, sleeping on and off.
//! - `quality`   — what the page's quality levels cost in accuracy: the validation cases at
//!   each level's cell factor and particles per cell (the figures of
//!   `src/playground/quality.rs`).
//! - `validate`  — the long validation runs; writes docs/reports/validation-report.md.
//! - `work-precision` — the run time against error study; writes
//!   docs/reports/work-precision-report.md and the SVG diagrams.
//! - `passes`    — the cost of each pass for scenes that need different work; writes
//!   docs/reports/passes-report.md.
//! - `scene-times` — the shipped scenes' run times; rewrites the table in docs/scenes.md.
//! - `screenshot` — the README's picture of the page in headless Chromium: docs/playground.jpg.
//! - `stress`    — the long stability sweep (`MPM_LONG=1`: more random scenes, longer resting
//!   runs, more fuzzing).
//!
//! The report-writing benchmarks are pinned to one core with `taskset -c 0` where it exists.

mod serve;

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const WASM_TARGET: &str = "wasm32-unknown-unknown";
/// Also in `.cargo/config.toml`; set here too so that the build never depends on it.
const WASM_RUSTFLAGS: &str = "-C target-feature=+simd128";
/// The scene the speed benchmarks use (3D, about 21 000 particles).
const BENCH_SCENE: &str = "www/test-scenes/bench_3d.json";
/// The scenes of the wasm-against-native comparison: the benchmark scene, a 2D sand scene
/// and the page's default scene.
const RATIO_SCENES: [&str; 3] = [
    BENCH_SCENE,
    "scenes/notched_sand_block_2d.json",
    DEFAULT_SCENE,
];
/// The scene the page opens with.
const DEFAULT_SCENE: &str = "scenes/bunny_on_sand_heap_3d.json";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rest = args.get(1..).unwrap_or(&[]);
    let result = match args.first().map(String::as_str) {
        Some("build") => build().map(|_| ()),
        Some("serve") => serve_task(rest),
        Some("dist") => dist_task(rest),
        Some("test") => test(),
        Some("bench-web") => bench_web(rest),
        Some("live") => live(rest),
        Some("quality") => report_bench("quality", rest),
        Some("validate") => report_bench("validate", rest),
        Some("work-precision") => report_bench("work_precision", rest),
        Some("passes") => report_bench("passes", rest),
        Some("scene-times") => report_bench("scenes", rest),
        Some("stress") => stress(),
        Some("screenshot") => screenshot(),
        _ => {
            eprintln!(
                "usage: cargo xtask <build|serve|dist|test|bench-web|live|quality|validate|work-precision|passes|scene-times|stress|screenshot>"
            );
            eprintln!(
                "  build              build the browser playground into www/pkg/ (wasm, simd128)"
            );
            eprintln!(
                "  serve [--port N]   build, then serve the playground on http://127.0.0.1:8080"
            );
            eprintln!(
                "  dist [--out DIR]   build, then write the page as a static folder (target/dist/)"
            );
            eprintln!(
                "  test               run every test (fmt, clippy, native, wasm in Node, browser)"
            );
            eprintln!("  bench-web [--steps N] [--seconds S]");
            eprintln!("                     wasm vs native time per step, and fps in Chromium");
            eprintln!(
                "  live [--runs N] [--seconds S] [--quality Q] [--no-page] [--drops] [--root DIR] [SCENE..]"
            );
            eprintln!(
                "                     real-time factor per shipped scene: stepping (Node, one core), as seen (Chromium)"
            );
            eprintln!(
                "  quality            the validation errors at each quality level's resolution"
            );
            eprintln!(
                "  validate [CASE..]  long validation runs -> docs/reports/validation-report.md"
            );
            eprintln!(
                "  work-precision     run time against error -> docs/reports/work-precision-report.md, SVGs"
            );
            eprintln!("  passes             cost of each pass -> docs/reports/passes-report.md");
            eprintln!("  scene-times        the shipped scenes' run times -> docs/scenes.md");
            eprintln!("  stress             the long stability sweep (MPM_LONG=1)");
            eprintln!(
                "  screenshot         the README's picture of the page -> docs/playground.jpg"
            );
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

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Where `cargo install` puts binaries.
fn cargo_bin() -> PathBuf {
    std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))
        .unwrap_or_else(|| PathBuf::from(".cargo"))
        .join("bin")
}

/// PATH with cargo's bin directory in front (where wasm-bindgen and its test runner live).
fn path_env() -> std::ffi::OsString {
    let mut paths = vec![cargo_bin()];
    if let Some(p) = std::env::var_os("PATH") {
        paths.extend(std::env::split_paths(&p));
    }
    std::env::join_paths(paths).unwrap_or_default()
}

fn command(program: &str, args: &[&str]) -> Command {
    let mut c = Command::new(program);
    c.args(args).current_dir(root()).env("PATH", path_env());
    c
}

/// Runs a command, failing on a non-zero exit.
fn run_cmd(mut c: Command) -> Result<(), String> {
    let shown = format!(
        "{} {}",
        c.get_program().to_string_lossy(),
        c.get_args()
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ")
    );
    eprintln!("xtask: {shown}");
    let status = c
        .status()
        .map_err(|e| format!("cannot start {shown}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{shown} failed ({status})"))
    }
}

fn run(program: &str, args: &[&str]) -> Result<(), String> {
    run_cmd(command(program, args))
}

/// A command's standard output, if it ran and succeeded.
fn output(program: &str, args: &[&str]) -> Option<String> {
    let out = command(program, args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// A cargo command for the wasm target (simd128 on).
fn wasm_cargo(args: &[&str]) -> Command {
    let mut c = command("cargo", args);
    c.env(
        format!(
            "CARGO_TARGET_{}_RUSTFLAGS",
            WASM_TARGET.to_uppercase().replace('-', "_")
        ),
        WASM_RUSTFLAGS,
    );
    c
}

/// The version of `package` in Cargo.lock.
fn locked_version(package: &str) -> Result<String, String> {
    let lock = std::fs::read_to_string(root().join("Cargo.lock"))
        .map_err(|e| format!("Cargo.lock: {e}"))?;
    let mut lines = lock.lines();
    while let Some(l) = lines.next() {
        if l.trim() == format!("name = \"{package}\"")
            && let Some(v) = lines
                .next()
                .and_then(|v| v.trim().strip_prefix("version = "))
        {
            return Ok(v.trim_matches('"').to_string());
        }
    }
    Err(format!("{package} is not in Cargo.lock"))
}

/// Adds the wasm target and installs wasm-bindgen-cli at the Cargo.lock version when missing.
fn ensure_wasm_tools() -> Result<(), String> {
    let installed = output("rustup", &["target", "list", "--installed"]).unwrap_or_default();
    if !installed.lines().any(|l| l.trim() == WASM_TARGET) {
        run("rustup", &["target", "add", WASM_TARGET])?;
    }
    let want = locked_version("wasm-bindgen")?;
    let have = output("wasm-bindgen", &["--version"]).unwrap_or_default();
    let runner = output("wasm-bindgen-test-runner", &["--version"]).unwrap_or_default();
    let version_of = |s: &str| s.split_whitespace().nth(1).map(str::to_string);
    if version_of(&have).as_deref() != Some(want.as_str())
        || version_of(&runner).as_deref() != Some(want.as_str())
    {
        eprintln!(
            "xtask: wasm-bindgen-cli {want} is needed (found {:?}); installing it (a few minutes)",
            have.trim()
        );
        // Not --locked: one of its locked dependencies is missing from some registry mirrors.
        run(
            "cargo",
            &[
                "install",
                "wasm-bindgen-cli",
                "--version",
                &format!("={want}"),
                "--force",
            ],
        )?;
    }
    Ok(())
}

/// The scene list of the page: every `scenes/*.json`, with its name and dimension.
fn write_scene_list() -> Result<usize, String> {
    let dir = root().join("scenes");
    let mut entries = Vec::new();
    if let Ok(read) = std::fs::read_dir(&dir) {
        let mut files: Vec<PathBuf> = read
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "json"))
            .collect();
        files.sort();
        for p in files {
            let file = p.file_name().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
            let v: serde_json::Value =
                serde_json::from_str(&text).map_err(|e| format!("scenes/{file}: not JSON: {e}"))?;
            let stem = file.trim_end_matches(".json");
            let base = stem
                .strip_suffix("_2d")
                .or_else(|| stem.strip_suffix("_3d"))
                .unwrap_or(stem);
            entries.push(serde_json::json!({
                "path": format!("scenes/{file}"),
                "base": base,
                "dim": v.get("dim").and_then(|d| d.as_u64()).unwrap_or(3),
                "name": v.get("name").and_then(|n| n.as_str()).unwrap_or(base),
            }));
        }
    }
    let n = entries.len();
    let out = root().join("www/pkg/scenes.json");
    std::fs::write(
        &out,
        serde_json::to_string_pretty(&entries).expect("serialisable"),
    )
    .map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(n)
}

/// The lesson list of the page: every `lessons/*.json`, with its title, as
/// `[{"id", "path", "title"}]` in file-name order.
fn write_lesson_list() -> Result<usize, String> {
    let mut entries = Vec::new();
    for p in files_in(&root().join("lessons"), &["json"])? {
        let file = p.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("lessons/{file}: not JSON: {e}"))?;
        entries.push(serde_json::json!({
            "id": file.trim_end_matches(".json"),
            "path": format!("lessons/{file}"),
            "title": v.get("title").and_then(|t| t.as_str()).unwrap_or(&file),
        }));
    }
    let out = root().join("www/pkg/lessons.json");
    std::fs::write(
        &out,
        serde_json::to_string_pretty(&entries).expect("serialisable"),
    )
    .map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(entries.len())
}

/// The files directly in `dir` whose extension is one of `exts`, sorted; none if `dir` is
/// missing.
fn files_in(dir: &Path, exts: &[&str]) -> Result<Vec<PathBuf>, String> {
    let read = match std::fs::read_dir(dir) {
        Ok(r) => r,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(format!("{}: {e}", dir.display())),
    };
    let mut files: Vec<PathBuf> = read
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| exts.contains(&e))
        })
        .collect();
    files.sort();
    Ok(files)
}

/// What the static folder holds, relative to the repository root and to the folder alike:
/// the page, its scripts and styles, the built solver and its lists, the scenes with their
/// meshes and outlines, and the lessons.
fn dist_files() -> Result<Vec<PathBuf>, String> {
    let r = root();
    let mut files = vec![PathBuf::from("index.html"), PathBuf::from("www/app.css")];
    for (dir, exts) in [
        ("www/js", &["js"][..]),
        ("www/pkg", &["js", "wasm", "json"][..]),
        ("scenes", &["json", "obj", "txt", "md"][..]),
        // the soil lab's tests (the Lab and its lessons fetch them)
        ("scenes/lab", &["json"][..]),
        ("lessons", &["json"][..]),
    ] {
        for p in files_in(&r.join(dir), exts)? {
            files.push(p.strip_prefix(&r).expect("under the root").to_path_buf());
        }
    }
    for needed in [
        "www/pkg/mpm.js",
        "www/pkg/mpm_bg.wasm",
        "www/pkg/scenes.json",
    ] {
        if !files.iter().any(|f| f == Path::new(needed)) {
            return Err(format!(
                "{needed} is missing: build first (cargo xtask build)"
            ));
        }
    }
    Ok(files)
}

/// Writes the static folder `out` from the built page (see [`dist_files`]), replacing an
/// earlier one; refuses a non-empty directory that is not one.
fn write_dist(out: &Path) -> Result<(), String> {
    if out.exists() {
        let earlier = out.join("index.html").is_file() && out.join("www/pkg/mpm_bg.wasm").is_file();
        let empty = std::fs::read_dir(out)
            .map(|mut d| d.next().is_none())
            .unwrap_or(false);
        if !earlier && !empty {
            return Err(format!(
                "{} exists and is not a static folder of the playground: choose another --out",
                out.display()
            ));
        }
        std::fs::remove_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    }
    let files = dist_files()?;
    let mut bytes = 0;
    for f in &files {
        let to = out.join(f);
        if let Some(dir) = to.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        bytes += std::fs::copy(root().join(f), &to)
            .map_err(|e| format!("{} → {}: {e}", f.display(), to.display()))?;
    }
    eprintln!(
        "xtask: wrote {} ({} files, {:.1} MB): serve it as it is from any static web host, at any path",
        out.display(),
        files.len(),
        bytes as f64 / 1e6
    );
    Ok(())
}

/// The static folder's default place.
fn dist_dir() -> PathBuf {
    root().join("target/dist")
}

fn dist_task(args: &[String]) -> Result<(), String> {
    let out = flag(args, "--out").map_or_else(dist_dir, |o| {
        let p = PathBuf::from(o);
        if p.is_absolute() {
            p
        } else {
            std::env::current_dir().unwrap_or_default().join(p)
        }
    });
    build()?;
    write_dist(&out)
}

/// Builds the playground into `www/pkg/`; returns the size of the wasm file.
fn build() -> Result<u64, String> {
    ensure_wasm_tools()?;
    run_cmd(wasm_cargo(&[
        "build",
        "--release",
        "--lib",
        "--target",
        WASM_TARGET,
        "--package",
        "mpm",
    ]))?;
    let wasm = wasm_opt(&root().join("target/wasm32-unknown-unknown/release/mpm.wasm"))?;
    let pkg = root().join("www/pkg");
    run(
        "wasm-bindgen",
        &[
            "--target",
            "web",
            "--no-typescript",
            "--out-dir",
            &pkg.to_string_lossy(),
            &wasm.to_string_lossy(),
        ],
    )?;
    let scenes = write_scene_list()?;
    write_lesson_list()?;
    let size = std::fs::metadata(pkg.join("mpm_bg.wasm"))
        .map(|m| m.len())
        .unwrap_or(0);
    eprintln!(
        "xtask: built www/pkg/ (mpm_bg.wasm {:.0} KiB, {scenes} scene files listed)",
        size as f64 / 1024.0
    );
    Ok(size)
}

/// The wasm-opt level of the page's wasm: smaller than none at the same speed in Node
/// (docs/performance.md, *Page weight (wasm-opt)*); -O3 inlines the pass functions the wasm
/// build keeps apart and runs slower.
const WASM_OPT_LEVEL: &str = "-O1";
/// The wasm features the build uses (wasm-opt must neither reject nor add others): rustc's
/// defaults for wasm32-unknown-unknown and simd128.
const WASM_OPT_FEATURES: [&str; 7] = [
    "--enable-simd",
    "--enable-bulk-memory",
    "--enable-sign-ext",
    "--enable-mutable-globals",
    "--enable-nontrapping-float-to-int",
    "--enable-reference-types",
    "--enable-multivalue",
];

/// rustc's `wasm` optimised by binaryen's wasm-opt at [`WASM_OPT_LEVEL`], debug information
/// stripped, as `opt/mpm.wasm` beside it (the name wasm-bindgen's output is named after); without
/// wasm-opt on PATH it installs Debian's `binaryen` when it runs as root, else says so and
/// returns `wasm` itself. It
/// runs before wasm-bindgen: Debian's binaryen 108 predates the externref table wasm-bindgen
/// emits, and a module it optimised after wasm-bindgen no longer instantiates.
fn wasm_opt(wasm: &Path) -> Result<PathBuf, String> {
    if output("wasm-opt", &["--version"]).is_none() {
        // Installed as the browsers are (Debian's package, as root); elsewhere the page is
        // served unoptimised, and says why.
        if let Err(e) = install_debian_package("binaryen", "the page's optimised wasm") {
            eprintln!("xtask: wasm-opt not found ({e}): mpm_bg.wasm left unoptimised");
            return Ok(wasm.to_path_buf());
        }
    }
    let dir = wasm.with_file_name("opt");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let out = dir.join("mpm.wasm");
    let (from, to) = (wasm.to_string_lossy(), out.to_string_lossy());
    let mut args = vec![WASM_OPT_LEVEL, "--strip-debug"];
    args.extend(WASM_OPT_FEATURES);
    args.extend([from.as_ref(), "-o", to.as_ref()]);
    run("wasm-opt", &args)?;
    Ok(out)
}

fn flag<'a>(args: &'a [String], name: &str) -> Option<&'a str> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(String::as_str)
}

fn serve_task(args: &[String]) -> Result<(), String> {
    let port: u16 = flag(args, "--port")
        .unwrap_or("8080")
        .parse()
        .map_err(|e| format!("--port: {e}"))?;
    if !args.iter().any(|a| a == "--no-build") {
        build()?;
    }
    let listener = TcpListener::bind(("127.0.0.1", port)).map_err(|e| {
        format!("cannot listen on 127.0.0.1:{port}: {e} (another server running? try --port)")
    })?;
    let addr = listener.local_addr().map_err(|e| e.to_string())?;
    println!("Serving the MPM playground at http://{addr}/  (Ctrl-C to stop)");
    serve::run(listener, root(), false);
    Ok(())
}

/// Starts the file server on a free loopback port in this process; returns its URL.
fn background_server() -> Result<String, String> {
    background_server_of(root())
}

/// The same, serving the folder `dir`.
fn background_server_of(dir: PathBuf) -> Result<String, String> {
    let listener = TcpListener::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let addr = listener.local_addr().map_err(|e| e.to_string())?;
    std::thread::spawn(move || serve::run(listener, dir, true));
    Ok(format!("http://{addr}/"))
}

/// Node.js, the npm packages of package-lock.json and Chromium, for the browser tests.
fn ensure_browser_tools() -> Result<String, String> {
    let node = output("node", &["--version"])
        .ok_or("Node.js is needed for the wasm and browser tests (apt-get install nodejs)")?;
    let major: u32 = node
        .trim()
        .trim_start_matches('v')
        .split('.')
        .next()
        .and_then(|m| m.parse().ok())
        .unwrap_or(0);
    // The oldest Node the locked npm packages support (package-lock.json's `engines`).
    if major < 20 {
        return Err(format!(
            "Node.js 20 or newer is needed, found {}",
            node.trim()
        ));
    }
    let r = root();
    let installed = r.join("node_modules/.package-lock.json");
    let stale = match (
        std::fs::metadata(r.join("package-lock.json")).and_then(|m| m.modified()),
        std::fs::metadata(&installed).and_then(|m| m.modified()),
    ) {
        (Ok(lock), Ok(inst)) => lock > inst,
        _ => true,
    };
    if stale
        || !r.join("node_modules/playwright-core").exists()
        || !r.join("node_modules/puppeteer-core").exists()
    {
        run("npm", &["ci", "--no-audit", "--no-fund"])?;
    }
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    ensure_debian_browser(&chromium, "chromium", "CHROMIUM")?;
    Ok(chromium)
}

/// Debian's Firefox ESR for the Firefox test and Xvfb: their paths (`FIREFOX` or
/// /usr/bin/firefox-esr, `XVFB` or /usr/bin/Xvfb). Also Mesa's software OpenGL (llvmpipe):
/// Firefox makes WebGL contexts with EGL on an X display, so without one it offers no WebGL2,
/// even headless.
fn ensure_firefox() -> Result<(String, String), String> {
    let firefox = std::env::var("FIREFOX").unwrap_or_else(|_| "/usr/bin/firefox-esr".into());
    ensure_debian_browser(&firefox, "firefox-esr", "FIREFOX")?;
    let xvfb = std::env::var("XVFB").unwrap_or_else(|_| "/usr/bin/Xvfb".into());
    ensure_debian_browser(&xvfb, "xvfb", "XVFB")?;
    // Debian's package of the DRI drivers (llvmpipe); elsewhere the test says what is missing.
    let dri = || output("dpkg-query", &["-W", "-f=${Status}", "libgl1-mesa-dri"]);
    if Path::new("/usr/bin/dpkg-query").exists()
        && !dri().is_some_and(|s| s.contains("ok installed"))
    {
        install_debian_package(
            "libgl1-mesa-dri",
            "Mesa's software OpenGL for Firefox's WebGL2",
        )?;
    }
    Ok((firefox, xvfb))
}

/// Installs Debian's `package` with apt-get when the program at `path` is missing and this
/// runs as root; otherwise says what to install (or which variable to set).
fn ensure_debian_browser(path: &str, package: &str, variable: &str) -> Result<(), String> {
    if Path::new(path).exists() {
        return Ok(());
    }
    install_debian_package(package, "the browser tests")
        .map_err(|e| format!("{path} not found: {e}, or set {variable}"))
}

/// Installs Debian's `package` (needed for `what`) with apt-get when this runs as root.
fn install_debian_package(package: &str, what: &str) -> Result<(), String> {
    let root_user = output("id", &["-u"]).is_some_and(|u| u.trim() == "0");
    if root_user && Path::new("/usr/bin/apt-get").exists() {
        eprintln!("xtask: installing Debian's {package} for {what}");
        run("apt-get", &["update", "-qq"])?;
        run("apt-get", &["install", "-y", "-qq", package])
    } else {
        Err(format!("install Debian's `{package}` package ({what})"))
    }
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
    page_unit_tests()?;
    run("cargo", &["test", "--workspace"])?;
    // the f64 build option: the unit tests (constitutive models, kernels, grid) in double precision
    run("cargo", &["test", "--lib", "--features", "f64"])?;
    build()?;
    run_cmd(wasm_cargo(&[
        "clippy",
        "--package",
        "mpm",
        "--target",
        WASM_TARGET,
        "--lib",
        "--test",
        "wasm",
        "--",
        "-D",
        "warnings",
    ]))?;
    // The wasm tests in Node, through wasm-bindgen-test-runner (.cargo/config.toml).
    run_cmd(wasm_cargo(&[
        "test",
        "--package",
        "mpm",
        "--target",
        WASM_TARGET,
        "--test",
        "wasm",
    ]))?;
    let chromium = ensure_browser_tools()?;
    let url = background_server()?;
    // The page in Chromium, one file at a time: the page itself (e2e), pouring sand with the
    // Pour tool, the page in a classroom (lessons, save and open, recording, touch and small
    // screens), measuring on the page (the HUD's layouts, readouts, law markers, Mohr circles,
    // the lessons' questions), and the soil lab (the shear box and the biaxial test, the
    // envelope, the soil-lab lessons).
    for file in [
        "www/tests/e2e.test.mjs",
        "www/tests/pour.test.mjs",
        "www/tests/classroom.test.mjs",
        "www/tests/measure.test.mjs",
        "www/tests/lab.test.mjs",
    ] {
        let mut browser = command("node", &["--test", "--test-reporter=spec", file]);
        browser
            .env("MPM_URL", &url)
            .env("CHROMIUM", &chromium)
            .env("MPM_OUT", root().join("target/e2e"));
        run_cmd(browser)?;
    }
    // The static folder alone, served by a plain static server under a sub-path.
    write_dist(&dist_dir())?;
    let mut dist = command(
        "node",
        &["--test", "--test-reporter=spec", "www/tests/dist.test.mjs"],
    );
    dist.env("MPM_DIST", dist_dir()).env("CHROMIUM", &chromium);
    run_cmd(dist)?;
    // The same page in Firefox (Debian's firefox-esr through puppeteer-core), WebGL2 drawn by
    // llvmpipe on an Xvfb display the test starts.
    let (firefox, xvfb) = ensure_firefox()?;
    let mut ff = command(
        "node",
        &[
            "--test",
            "--test-reporter=spec",
            "www/tests/firefox.test.mjs",
        ],
    );
    ff.env("MPM_URL", &url)
        .env("FIREFOX", &firefox)
        .env("XVFB", &xvfb)
        .env("MPM_OUT", root().join("target/e2e"));
    run_cmd(ff)?;
    eprintln!("xtask: every test passed");
    Ok(())
}

/// The page's pure modules (the link's format, slider scales, plot scales, the quality
/// governor) under `node --test`, without a browser or the wasm build.
fn page_unit_tests() -> Result<(), String> {
    let dir = root().join("www/tests/unit");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".test.mjs"))
        .map(|n| format!("www/tests/unit/{n}"))
        .collect();
    files.sort();
    let mut args = vec!["--test", "--test-reporter=spec"];
    args.extend(files.iter().map(String::as_str));
    run("node", &args)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// The `median_ms_per_step=` figure of a benchmark's output.
fn parse_median(out: &str) -> Option<f64> {
    out.split_whitespace()
        .find_map(|w| w.strip_prefix("median_ms_per_step="))
        .and_then(|v| v.parse().ok())
}

fn captured(mut c: Command) -> Result<String, String> {
    let shown = format!("{:?}", c);
    eprintln!("xtask: {shown}");
    let out = c.output().map_err(|e| format!("{shown}: {e}"))?;
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    print!("{text}");
    if out.status.success() {
        Ok(text)
    } else {
        Err(format!("{shown} failed ({})", out.status))
    }
}

fn bench_web(args: &[String]) -> Result<(), String> {
    let steps = flag(args, "--steps").unwrap_or("200");
    let seconds = flag(args, "--seconds").unwrap_or("10");
    let runs: usize = flag(args, "--runs").unwrap_or("5").parse().unwrap_or(5);
    let size = build()?;
    // Native and wasm in turn, pair by pair, so that both see the same machine: on a shared
    // machine a process's speed drifts by ±20 % from one run to the next.
    let mut summary = Vec::new();
    for scene in RATIO_SCENES {
        let (mut native, mut wasm, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..runs {
            let bench = [
                "bench",
                "--quiet",
                "--package",
                "mpm",
                "--bench",
                "playground",
                "--",
                scene,
                steps,
            ];
            let n = parse_median(&captured(command("cargo", &bench))?);
            let node = ["www/bench/node-bench.mjs", scene, steps];
            let w = parse_median(&captured(command("node", &node))?);
            if let (Some(n), Some(w)) = (n, w) {
                native.push(n);
                wasm.push(w);
                ratios.push(w / n);
            }
        }
        let best = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let (bn, bw) = (best(&native), best(&wasm));
        summary.push(format!(
            "bench-web: {scene}: native {:.3} ms/step, wasm in Node {:.3} ms/step; ratio {:.2} (median of {} pairs), {:.2} (best against best)",
            median(&mut native),
            median(&mut wasm),
            median(&mut ratios),
            ratios.len(),
            bw / bn,
        ));
    }
    for line in &summary {
        println!("{line}");
    }
    println!(
        "bench-web: {steps} steps per run after a 3 s warm-up; mpm_bg.wasm {:.0} KiB",
        size as f64 / 1024.0
    );
    let chromium = ensure_browser_tools()?;
    let url = background_server()?;
    // The benchmark scene (≥ 20 000 particles) and the page's default 3D scene.
    for scene in [BENCH_SCENE, DEFAULT_SCENE] {
        let mut fps = command("node", &["www/bench/fps.mjs"]);
        fps.env("MPM_URL", &url)
            .env("CHROMIUM", &chromium)
            .env("MPM_SCENE", scene)
            .env("MPM_SECONDS", seconds);
        run_cmd(fps)?;
    }
    Ok(())
}

/// The `key=value` figures of a benchmark's output line.
fn fields(line: &str) -> std::collections::HashMap<&str, &str> {
    line.split_whitespace()
        .filter_map(|w| w.split_once('='))
        .collect()
}

/// The real-time factor of every shipped scene (`scenes/*.json`, or those whose file name
/// contains one of the given words) at the page's default quality: simulated seconds per
/// wall-clock second of stepping alone (the release wasm in Node, pinned to one core with
/// `taskset -c 0` where it exists) and as seen in headless Chromium (stepping and rendering),
/// each the median of `--runs` runs (default 3). Prints one line per scene:
/// `live scene=<name> dim=<d> particles=<n> rtf_step=<x> rtf_seen=<y> fps=<z> quality=<q>`,
/// followed by the settled phase (stepping alone, see `www/bench/live-node.mjs`): the real-time
/// factor at rest and during the 2 s after a bunny is dropped, with sleeping on and off
/// (`rtf_settled rtf_settled_awake rtf_drop rtf_drop_awake`) and the fraction of particles
/// asleep at rest (`asleep`), and as seen in the page with sleeping on (`rtf_seen_settled
/// rtf_seen_drop`, see `www/bench/live-page.mjs`); `--no-settled` leaves them out.
/// `--quality Q` measures another quality level. `--root DIR` measures another tree instead (a checkout of an earlier commit with its
/// `www/pkg/` built, and this one's `www/bench/live-*.mjs` copied in): the figures before a
/// change.
fn live(args: &[String]) -> Result<(), String> {
    if args.iter().any(|a| a == "--drops") {
        return live_drops(args);
    }
    let tree = flag(args, "--root").map_or_else(root, PathBuf::from);
    let runs: usize = flag(args, "--runs")
        .unwrap_or("3")
        .parse()
        .map_err(|e| format!("--runs: {e}"))?;
    let seconds = flag(args, "--seconds").unwrap_or("8");
    let with_page = !args.iter().any(|a| a == "--no-page");
    if !args.iter().any(|a| a == "--no-build") && flag(args, "--root").is_none() {
        build()?;
    }
    let scenes = live_scenes(&tree, args)?;
    // Per scene: (dim, particles and quality, rtf_step runs, rtf_seen runs, fps runs, settled
    // figures' runs by name).
    type Figures = (
        String,
        String,
        Vec<f64>,
        Vec<f64>,
        Vec<f64>,
        std::collections::BTreeMap<&'static str, Vec<f64>>,
    );
    const SETTLED: [&str; 5] = [
        "rtf_settled",
        "rtf_settled_awake",
        "rtf_drop",
        "rtf_drop_awake",
        "asleep",
    ];
    const SEEN_SETTLED: [&str; 2] = ["rtf_seen_settled", "rtf_seen_drop"];
    let with_settled = !args.iter().any(|a| a == "--no-settled");
    let mut table: std::collections::BTreeMap<String, Figures> = Default::default();
    let number = |f: &std::collections::HashMap<&str, &str>, k: &str| {
        f.get(k).and_then(|v| v.parse::<f64>().ok())
    };
    let pinned = output("taskset", &["--version"]).is_some();
    let chromium = if with_page {
        Some(ensure_browser_tools()?)
    } else {
        None
    };
    let url = if with_page {
        Some(background_server_of(tree.clone())?)
    } else {
        None
    };
    for _ in 0..runs {
        let mut node_args = vec!["node", "www/bench/live-node.mjs"];
        if let Some(q) = flag(args, "--quality") {
            node_args.extend(["--quality", q]);
        }
        if !with_settled {
            node_args.push("--no-settled");
        }
        node_args.extend(scenes.iter().map(String::as_str));
        let mut c = if pinned {
            let mut all = vec!["-c", "0"];
            all.extend(node_args);
            command("taskset", &all)
        } else {
            command(node_args[0], &node_args[1..])
        };
        c.current_dir(&tree);
        let out = captured(c)?;
        for line in out.lines().filter(|l| l.starts_with("step ")) {
            let f = fields(line);
            let e = table.entry(f["scene"].to_string()).or_default();
            e.0 = f["dim"].to_string();
            e.1 = format!("{} quality={}", f["particles"], f["quality"]);
            e.2.extend(number(&f, "rtf_step"));
        }
        for line in out.lines().filter(|l| l.starts_with("settled ")) {
            let f = fields(line);
            let e = table.entry(f["scene"].to_string()).or_default();
            for k in SETTLED {
                e.5.entry(k).or_default().extend(number(&f, k));
            }
        }
        if let (Some(chromium), Some(url)) = (&chromium, &url) {
            let mut page_args = vec!["www/bench/live-page.mjs", "--seconds", seconds];
            if let Some(q) = flag(args, "--quality") {
                page_args.extend(["--quality", q]);
            }
            if !with_settled {
                page_args.push("--no-settled");
            }
            page_args.extend(scenes.iter().map(String::as_str));
            let mut c = command("node", &page_args);
            c.env("MPM_URL", url)
                .env("CHROMIUM", chromium)
                .current_dir(&tree);
            let out = captured(c)?;
            for line in out.lines().filter(|l| l.starts_with("seen_settled ")) {
                let f = fields(line);
                let e = table.entry(f["scene"].to_string()).or_default();
                for k in SEEN_SETTLED {
                    e.5.entry(k).or_default().extend(number(&f, k));
                }
            }
            for line in out.lines().filter(|l| l.starts_with("seen ")) {
                let f = fields(line);
                let e = table.entry(f["scene"].to_string()).or_default();
                e.3.extend(number(&f, "rtf_seen"));
                e.4.extend(number(&f, "fps"));
            }
        }
    }
    let commit = if flag(args, "--root").is_some() {
        format!("(the tree {})", tree.display())
    } else {
        output("git", &["rev-parse", "--short", "HEAD"]).unwrap_or_default()
    };
    println!(
        "live: medians of {runs} runs at commit {}; stepping: wasm in Node{}; seen: headless Chromium, {seconds} s per scene",
        commit.trim(),
        if pinned { " under taskset -c 0" } else { "" }
    );
    for (path, (dim, particles, mut step, mut seen, mut fps, mut settled)) in table {
        let name = path.trim_start_matches("scenes/").trim_end_matches(".json");
        let show = |v: &mut Vec<f64>, digits: usize| {
            if v.is_empty() {
                "-".to_string()
            } else {
                format!("{:.*}", digits, median(v))
            }
        };
        let (particles, quality) = particles.split_once(' ').unwrap_or((&particles, ""));
        let settled: String = settled
            .iter_mut()
            .filter(|(_, v)| !v.is_empty())
            .map(|(k, v)| format!(" {k}={}", show(v, 3)))
            .collect();
        println!(
            "live scene={name} dim={dim} particles={particles} rtf_step={} rtf_seen={} fps={} {quality}{settled}",
            show(&mut step, 3),
            show(&mut seen, 3),
            show(&mut fps, 1),
        );
    }
    Ok(())
}

/// The shipped scenes `live` measures: `scenes/*.json` of `tree`, sorted, or those whose file
/// name contains one of the words among `args` (the words that are neither flags nor a
/// flag's value).
fn live_scenes(tree: &Path, args: &[String]) -> Result<Vec<String>, String> {
    let mut skip = false;
    let words: Vec<&String> = args
        .iter()
        .filter(|a| {
            let keep = !skip && !a.starts_with("--");
            skip = matches!(a.as_str(), "--runs" | "--seconds" | "--root" | "--quality");
            keep
        })
        .collect();
    let mut scenes: Vec<String> = std::fs::read_dir(tree.join("scenes"))
        .map_err(|e| format!("scenes/: {e}"))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".json"))
        .filter(|n| words.is_empty() || words.iter().any(|w| n.contains(w.as_str())))
        .map(|n| format!("scenes/{n}"))
        .collect();
    scenes.sort();
    if scenes.is_empty() {
        return Err(format!("no scene file matches {words:?}"));
    }
    Ok(scenes)
}

/// `cargo xtask live --drops [--runs N] [--quality Q] [--no-build] [--root DIR] [SCENE..]`:
/// the drop figures as seen in headless Chromium on one core (`taskset -c 0` where it exists;
/// `www/bench/live-page.mjs --drops`): each shipped scene (or those whose file name contains
/// one of the given words) run 3 s simulated, an elastic bunny of the default size dropped on
/// the middle of the floor, and the real-time factor of the 4 s after it, with sleeping on
/// and off, at Balanced and Fine (or the level `--quality` names), each the median of `--runs`
/// runs (default 1). Prints one line per scene and level:
/// `drop scene=<name> quality=<q> rtf_drop=<sleeping on> rtf_drop_awake=<off> asleep_before=<fraction>`.
fn live_drops(args: &[String]) -> Result<(), String> {
    let tree = flag(args, "--root").map_or_else(root, PathBuf::from);
    let runs: usize = flag(args, "--runs")
        .unwrap_or("1")
        .parse()
        .map_err(|e| format!("--runs: {e}"))?;
    let levels: Vec<&str> = flag(args, "--quality").map_or(vec!["balanced", "fine"], |q| vec![q]);
    if !args.iter().any(|a| a == "--no-build") && flag(args, "--root").is_none() {
        build()?;
    }
    let scenes = live_scenes(&tree, args)?;
    let chromium = ensure_browser_tools()?;
    let url = background_server_of(tree.clone())?;
    let pinned = output("taskset", &["--version"]).is_some();
    // (scene, level) → (sleeping on runs, off runs, asleep before the drop runs)
    type Runs = (Vec<f64>, Vec<f64>, Vec<f64>);
    let mut table: std::collections::BTreeMap<(String, String), Runs> = Default::default();
    for _ in 0..runs {
        for level in &levels {
            let mut page_args = vec![
                "node",
                "www/bench/live-page.mjs",
                "--drops",
                "--quality",
                level,
            ];
            page_args.extend(scenes.iter().map(String::as_str));
            let mut c = if pinned {
                let mut all = vec!["-c", "0"];
                all.extend(page_args);
                command("taskset", &all)
            } else {
                command(page_args[0], &page_args[1..])
            };
            c.env("MPM_URL", &url)
                .env("CHROMIUM", &chromium)
                .current_dir(&tree);
            let out = captured(c)?;
            for line in out.lines() {
                if line.starts_with("page errors") {
                    eprintln!("{line}");
                }
                if !line.starts_with("seen_drop ") {
                    continue;
                }
                let f = fields(line);
                let e = table
                    .entry((f["scene"].to_string(), f["quality"].to_string()))
                    .or_default();
                let rtf = f.get("rtf_drop").and_then(|v| v.parse::<f64>().ok());
                if f.get("sleeping") == Some(&"on") {
                    e.0.extend(rtf);
                    e.2.extend(f.get("asleep_before").and_then(|v| v.parse::<f64>().ok()));
                } else {
                    e.1.extend(rtf);
                }
            }
        }
    }
    let commit = output("git", &["rev-parse", "--short", "HEAD"]).unwrap_or_default();
    println!(
        "live --drops: medians of {runs} runs at commit {}; headless Chromium{}; 4 s simulated after the drop (60 wall-clock seconds at most)",
        commit.trim(),
        if pinned { " under taskset -c 0" } else { "" }
    );
    for ((path, level), (mut on, mut off, mut asleep)) in table {
        let name = path.trim_start_matches("scenes/").trim_end_matches(".json");
        let show = |v: &mut Vec<f64>| {
            if v.is_empty() {
                "-".to_string()
            } else {
                format!("{:.3}", median(v))
            }
        };
        println!(
            "drop scene={name} quality={level} rtf_drop={} rtf_drop_awake={} asleep_before={}",
            show(&mut on),
            show(&mut off),
            show(&mut asleep)
        );
    }
    Ok(())
}

/// Runs a report-writing benchmark on one core (`taskset -c 0` when available); `filters`
/// select parts of it.
fn report_bench(name: &str, filters: &[String]) -> Result<(), String> {
    let mut args: Vec<&str> = vec!["bench", "--bench", name];
    if !filters.is_empty() {
        args.push("--");
        args.extend(filters.iter().map(String::as_str));
    }
    if output("taskset", &["--version"]).is_some() {
        let mut all = vec!["-c", "0", "cargo"];
        all.extend(args);
        run("taskset", &all)
    } else {
        run("cargo", &args)
    }
}

/// The README's picture: the page in headless Chromium, written to docs/playground.jpg.
fn screenshot() -> Result<(), String> {
    build()?;
    let chromium = ensure_browser_tools()?;
    let url = background_server()?;
    let mut shot = command("node", &["www/tools/screenshot.mjs", "docs/playground.jpg"]);
    shot.env("MPM_URL", &url).env("CHROMIUM", &chromium);
    run_cmd(shot)
}

/// The long stability sweep: `MPM_LONG=1 cargo test --test stability -- --nocapture`.
fn stress() -> Result<(), String> {
    let mut c = command(
        "cargo",
        &["test", "--test", "stability", "--", "--nocapture"],
    );
    c.env("MPM_LONG", "1");
    run_cmd(c)
}
