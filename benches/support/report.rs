//! Helpers of the report-writing benches: markdown tables, a log–log SVG plot, least-squares
//! convergence orders.
#![allow(dead_code)]

use std::fmt::Write;

#[path = "../../tests/support/digest.rs"]
pub mod digest;

/// The line a report records its solver with (see `tests/support/digest.rs`): today's digest
/// of each of `families` ("solid", "sand") and the command that regenerates the report.
/// `cargo xtask test` fails, naming that command, once the solver's digest changes.
pub fn solver_line(families: &[&str], regenerate: &str) -> String {
    digest::stamp_line(families, regenerate)
}

/// The families a bench run measures, from its filters: `solid` when every filter names a case
/// of `solid_cases`, `sand` when none does, both otherwise (and for a whole run).
pub fn families_of(filters: &Filters, solid_cases: &[&str]) -> Vec<&'static str> {
    let solid = filters
        .0
        .iter()
        .filter(|f| solid_cases.contains(&f.as_str()))
        .count();
    if filters.0.is_empty() || (solid > 0 && solid < filters.0.len()) {
        vec!["solid", "sand"]
    } else if solid > 0 {
        vec!["solid"]
    } else {
        vec!["sand"]
    }
}

/// The xtask command that reruns a bench with the same filters, e.g. `cargo xtask validate bar`.
pub fn rerun_command(task: &str, filters: &Filters) -> String {
    std::iter::once(format!("cargo xtask {task}"))
        .chain(filters.0.iter().cloned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The bench's name filters (its arguments that are not `--flags`, e.g. `bar column`), and
/// whether the case `name` is wanted (every case when no filter is given).
pub struct Filters(pub Vec<String>);

impl Filters {
    pub fn from_args() -> Self {
        Filters(
            std::env::args()
                .skip(1)
                .filter(|a| !a.starts_with("--"))
                .collect(),
        )
    }
    pub fn want(&self, name: &str) -> bool {
        self.0.is_empty() || self.0.iter().any(|f| f == name)
    }
    /// `docs/reports/<stem>.md`, or `docs/reports/<stem>-<filters>.md` for a partial run (so that a partial
    /// run never overwrites the full report).
    pub fn report_path(&self, stem: &str) -> std::path::PathBuf {
        let name = if self.0.is_empty() {
            format!("{stem}.md")
        } else {
            format!("{stem}-{}.md", self.0.join("-"))
        };
        root().join("docs").join("reports").join(name)
    }
}

/// The commit the figures are measured at, for a report's header: `git rev-parse --short HEAD`,
/// with "plus uncommitted changes" when tracked files other than documents (docs/, *.md)
/// differ from it, or "an unknown commit" outside a git checkout.
pub fn measured_at() -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .current_dir(root())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short", "HEAD"]) {
        None => "an unknown commit".to_string(),
        // changes to documents (reports written while this one runs) do not change the figures
        Some(head) => match git(&[
            "status",
            "--porcelain",
            "--untracked-files=no",
            "--",
            ".",
            ":!docs",
            ":!*.md",
        ]) {
            Some(changes) if changes.is_empty() => format!("`{head}`"),
            _ => format!("`{head}` plus uncommitted changes"),
        },
    }
}

/// Seconds this thread has spent on a core (Linux's schedstat); `None` elsewhere.
pub fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

/// Runs `f` and returns its result with the seconds it took on a core (wall-clock seconds
/// where the system does not say): on a machine shared with other work, the time the run
/// needed rather than the time it also waited for a core.
pub fn on_core<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let (start, c0) = (std::time::Instant::now(), cpu_seconds());
    let out = f();
    let wall = start.elapsed().as_secs_f64();
    (out, c0.zip(cpu_seconds()).map_or(wall, |(a, b)| b - a))
}

/// How the process is placed: "pinned to core N" when it may run on one core only (as
/// `taskset -c N` leaves it), "not pinned to a core" otherwise (Linux; "" elsewhere).
pub fn placement() -> String {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    match status
        .lines()
        .find_map(|l| l.strip_prefix("Cpus_allowed_list:"))
        .map(str::trim)
    {
        Some(cpus) if cpus.parse::<usize>().is_ok() => format!("pinned to core {cpus}"),
        Some(_) => "not pinned to a core".to_string(),
        None => String::new(),
    }
}

/// The machine's one-minute load average, e.g. "a load average of 1.2" (Linux; "" elsewhere):
/// wall-clock run times taken under load are longer by about that factor over the cores.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .map_or(String::new(), |l| format!("a load average of {l}"))
}

/// A markdown table.
pub fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "| {} |", header.join(" | "));
    let _ = writeln!(
        s,
        "|{}",
        header.iter().map(|_| " --- |").collect::<String>()
    );
    for r in rows {
        let _ = writeln!(s, "| {} |", r.join(" | "));
    }
    s
}

/// A study's "change per halving of h" subsection: its table, or, from a run of one grid, a
/// line saying the changes need the neighbouring grids' report.
pub fn halving_table(header: &[&str], rows: &[Vec<String>]) -> String {
    if rows.is_empty() {
        "One grid in this run: the change per halving of h needs its neighbours (the full or the coarse sweep).\n".to_string()
    } else {
        format!("### Change per halving of h\n\n{}", table(header, rows))
    }
}

/// The slope of log y against log x (a convergence order when x is the cell size).
pub fn log_slope(x: &[f64], y: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| **a > 0.0 && **b > 0.0 && b.is_finite())
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    let n = pts.len() as f64;
    if n < 2.0 {
        return f64::NAN;
    }
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

/// One series of a plot: points (x, y), drawn as markers joined by a line (a sweep), or as
/// separate markers each with its own label (configurations that are not a sweep).
pub struct Series {
    pub label: String,
    pub colour: &'static str,
    pub points: Vec<(f64, f64)>,
    pub dashed: bool,
    /// When not empty: one label per point, drawn beside it, and no line between the points.
    pub point_labels: Vec<String>,
}

impl Series {
    /// A sweep: markers joined by a line.
    pub fn sweep(
        label: String,
        colour: &'static str,
        points: Vec<(f64, f64)>,
        dashed: bool,
    ) -> Self {
        Series {
            label,
            colour,
            points,
            dashed,
            point_labels: Vec::new(),
        }
    }
    /// Separate configurations: labelled markers, not joined.
    pub fn labelled(
        label: String,
        colour: &'static str,
        points: Vec<(f64, f64)>,
        point_labels: Vec<String>,
    ) -> Self {
        Series {
            label,
            colour,
            points,
            dashed: false,
            point_labels,
        }
    }
}

pub const COLOURS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f",
];

/// A log–log plot as a standalone SVG document.
pub fn loglog_svg(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> String {
    let (w, h) = (760.0, 520.0);
    let (left, right, top, bottom) = (80.0, 230.0, 40.0, 60.0);
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().cloned())
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .collect();
    let lx: Vec<f64> = pts.iter().map(|p| p.0.log10()).collect();
    let ly: Vec<f64> = pts.iter().map(|p| p.1.log10()).collect();
    let (x0, x1) = (
        lx.iter().cloned().fold(f64::INFINITY, f64::min).floor(),
        lx.iter().cloned().fold(f64::NEG_INFINITY, f64::max).ceil(),
    );
    let (y0, y1) = (
        ly.iter().cloned().fold(f64::INFINITY, f64::min).floor(),
        ly.iter().cloned().fold(f64::NEG_INFINITY, f64::max).ceil(),
    );
    let (x1, y1) = (x1.max(x0 + 1.0), y1.max(y0 + 1.0));
    let pw = w - left - right;
    let ph = h - top - bottom;
    let sx = |x: f64| left + (x.log10() - x0) / (x1 - x0) * pw;
    let sy = |y: f64| top + (1.0 - (y.log10() - y0) / (y1 - y0)) * ph;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="15">{}</text>"#,
        left + pw / 2.0,
        esc(title)
    );
    // grid and ticks: decades, with 2 and 5 between
    for d in (x0 as i32)..=(x1 as i32) {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(d);
            if v.log10() > x1 + 1e-9 {
                continue;
            }
            let x = sx(v);
            let major = m == 1.0;
            let _ = writeln!(
                s,
                r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{}" stroke="{}" />"##,
                top + ph,
                if major { "#ccc" } else { "#eee" }
            );
            if major || x1 - x0 <= 2.0 {
                let _ = writeln!(
                    s,
                    r#"<text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"#,
                    top + ph + 16.0,
                    num(v)
                );
            }
        }
    }
    for d in (y0 as i32)..=(y1 as i32) {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(d);
            if v.log10() > y1 + 1e-9 {
                continue;
            }
            let y = sy(v);
            let major = m == 1.0;
            let _ = writeln!(
                s,
                r##"<line x1="{left}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="{}" />"##,
                left + pw,
                if major { "#ccc" } else { "#eee" }
            );
            if major || y1 - y0 <= 2.0 {
                let _ = writeln!(
                    s,
                    r#"<text x="{}" y="{:.1}" text-anchor="end">{}</text>"#,
                    left - 6.0,
                    y + 4.0,
                    num(v)
                );
            }
        }
    }
    let _ = writeln!(
        s,
        r#"<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="black"/>"#
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        left + pw / 2.0,
        h - 18.0,
        esc(xlabel)
    );
    let _ = writeln!(
        s,
        r#"<text x="20" y="{}" text-anchor="middle" transform="rotate(-90 20 {})">{}</text>"#,
        top + ph / 2.0,
        top + ph / 2.0,
        esc(ylabel)
    );
    for (k, se) in series.iter().enumerate() {
        let keep = |&(x, y): &(f64, f64)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite();
        let p: Vec<(f64, f64)> = se.points.iter().cloned().filter(keep).collect();
        let labelled = !se.point_labels.is_empty();
        let path: Vec<String> = p
            .iter()
            .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
            .collect();
        if path.len() > 1 && !labelled {
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.5"{}/>"#,
                path.join(" "),
                se.colour,
                if se.dashed {
                    r#" stroke-dasharray="5,3""#
                } else {
                    ""
                }
            );
        }
        for &(x, y) in &p {
            let _ = writeln!(
                s,
                r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{}"/>"#,
                sx(x),
                sy(y),
                se.colour
            );
        }
        for (&pt, text) in se.points.iter().zip(&se.point_labels) {
            if keep(&pt) {
                let _ = writeln!(
                    s,
                    r#"<text x="{:.1}" y="{:.1}" font-size="10" fill="{}">{}</text>"#,
                    sx(pt.0) + 5.0,
                    sy(pt.1) - 4.0,
                    se.colour,
                    esc(text)
                );
            }
        }
        let ly = top + 10.0 + 18.0 * k as f64;
        let lx = left + pw + 12.0;
        if labelled {
            let _ = writeln!(
                s,
                r#"<circle cx="{}" cy="{ly}" r="3.5" fill="{}"/>"#,
                lx + 11.0,
                se.colour
            );
        } else {
            let _ = writeln!(
                s,
                r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{}" stroke-width="2"{}/>"#,
                lx + 22.0,
                se.colour,
                if se.dashed {
                    r#" stroke-dasharray="5,3""#
                } else {
                    ""
                }
            );
        }
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}">{}</text>"#,
            lx + 28.0,
            ly + 4.0,
            esc(&se.label)
        );
    }
    s.push_str("</svg>\n");
    s
}

fn esc(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn num(v: f64) -> String {
    if (1e-3..1e4).contains(&v) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// A copy of validation scene `file` (in `scenes/validation/`) with `max_dt` scaled by
/// `factor` (as the page scales it with the cells), written to `target/<dir>/`, as a path the
/// validation helpers take (relative to `scenes/validation/`).
pub fn scaled(file: &str, factor: f64, dir: &str) -> String {
    let text = std::fs::read_to_string(root().join("scenes/validation").join(file)).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let dt = v["max_dt"].as_f64().unwrap_or(0.001);
    v["max_dt"] = serde_json::json!(dt * factor);
    let out = root().join("target").join(dir);
    std::fs::create_dir_all(&out).unwrap();
    let name = format!("{}-{factor}.json", file.trim_end_matches(".json"));
    std::fs::write(out.join(&name), v.to_string()).unwrap();
    format!("../../target/{dir}/{name}")
}

/// The repository root.
pub fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}
