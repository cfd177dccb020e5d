//! The peer benchmark: `bridson` timed beside the published Rust Poisson
//! disk crates and the project's textbook baseline, on the same cases, each
//! output checked.
//!
//! ```text
//! cargo run --release --manifest-path bench/peers/Cargo.toml -- --runs 5 \
//!     --json peers.jsonl > peers.md
//! cargo run --release --manifest-path bench/peers/Cargo.toml -- --cases 3d-1m --peers bridson,textbook
//! ```
//!
//! For each case, every crate first runs once with its output checked
//! (`check.rs`: points inside the box, no pair closer than `r`, exact `f64`,
//! toroidal where periodic). A crate that takes a radius is given the radius
//! that makes its point count match `bridson`'s within 1 % (equal count,
//! hence a comparable amount of work; ρ is reported): up to six checked
//! runs, each rescaling `r` by `(n / target)^(1/N)`. A wrong crate gets
//! "wrong: how" and no timing. Then the timed runs go round by round, every
//! crate once per round, each in a fresh process (this binary, re-executed),
//! so that runs share no heap and a slow spell of the shared host falls on
//! all crates alike. Time is the child's whole-process wall time, measured
//! by the parent; memory is the child's peak RSS (`VmHWM`). The table gives
//! medians, and each crate's median time over `bridson`'s (the issue's
//! measure: the ratio of medians of alternating whole-process runs).
//! `/proc/loadavg` is recorded at the start and end of every case.

mod check;
mod peers;
mod summary;
#[path = "../../../benches/textbook/mod.rs"]
mod textbook;

use crate::peers::{ALL, Job, Outcome, Peer};
use clap::Parser;
use std::fmt::Write as _;
use std::io::Write as _;
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

/// The command line.
#[derive(Debug, Parser)]
#[command(name = "peers")]
struct Args {
    /// Timed runs of each crate per case (alternating; the median is reported)
    #[arg(long, default_value_t = 5)]
    runs: usize,
    /// Run only the cases whose name starts with one of these (comma-separated)
    #[arg(long, value_delimiter = ',')]
    cases: Vec<String>,
    /// Run only these crates (comma-separated; `bridson` always runs, as the reference)
    #[arg(long, value_delimiter = ',')]
    peers: Vec<String>,
    /// Seconds after which a run is stopped and the crate marked too slow
    #[arg(long, default_value_t = 120.0)]
    timeout: f64,
    /// Append one JSON object per (case, crate) to this file
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// Seed of every seeded run
    #[arg(long, default_value_t = 2026)]
    seed: u64,
    /// Print the summary table (docs/peers.md's) of the JSON lines in these files
    /// instead of running anything
    #[arg(long, value_delimiter = ',')]
    summarize: Vec<std::path::PathBuf>,
    /// Internal: run one job in this process and print its figures
    #[arg(long, hide = true, num_args = 5, value_names = ["PEER", "DIM", "PERIODIC", "RADIUS", "CHECK"])]
    child: Vec<String>,
}

/// A case of the table.
struct Case {
    name: &'static str,
    dim: usize,
    periodic: bool,
    /// `bridson`'s radius; the other crates' are fitted to its count.
    radius: f64,
}

const fn case(name: &'static str, dim: usize, periodic: bool, radius: f64) -> Case {
    Case {
        name,
        dim,
        periodic,
        radius,
    }
}

/// Issue 17's sizes (100 k and 1 M points in 2-D and 3-D, 200 k in 4-D) in
/// the unit box and torus, and issue 21's high-dimensional cases.
const CASES: &[Case] = &[
    case("2d-100k", 2, false, 0.00248),
    case("2d-100k-torus", 2, true, 0.00248),
    case("2d-1m", 2, false, 0.000785),
    case("2d-1m-torus", 2, true, 0.000785),
    case("3d-100k", 3, false, 0.018),
    case("3d-100k-torus", 3, true, 0.018),
    case("3d-1m", 3, false, 0.00835),
    case("3d-1m-torus", 3, true, 0.00835),
    case("4d-200k", 4, false, 0.0418),
    case("4d-200k-torus", 4, true, 0.0418),
    case("5d-r0.1", 5, false, 0.1),
    case("6d-r0.2", 6, false, 0.2),
    case("7d-r0.3", 7, false, 0.3),
    case("8d-r0.4", 8, false, 0.4),
    case("8d-r0.4-torus", 8, true, 0.4),
];

fn main() -> ExitCode {
    let args = Args::parse();
    if !args.child.is_empty() {
        return child(&args.child, args.seed);
    }
    let result = if args.summarize.is_empty() {
        parent(&args)
    } else {
        summary::print(&args.summarize)
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("peers: {e}");
            ExitCode::from(1)
        }
    }
}

/// The child: one job, then `count seconds rss_kib min_distance checked_r`
/// on stdout, or the error on stderr with exit code 3.
fn child(fields: &[String], seed: u64) -> ExitCode {
    let parsed = (|| -> Option<Job> {
        Some(Job {
            peer: Peer::from_name(&fields[0])?,
            dim: fields[1].parse().ok()?,
            periodic: fields[2].parse().ok()?,
            radius: fields[3].parse().ok()?,
            seed,
            check: fields[4].parse().ok()?,
        })
    })();
    let Some(job) = parsed else {
        eprintln!("peers: bad --child fields {fields:?}");
        return ExitCode::from(2);
    };
    match peers::run(&job) {
        Ok(o) => {
            println!(
                "{} {} {} {} {}",
                o.count,
                o.sampling_seconds,
                peak_rss_kib().unwrap_or(0),
                o.min_distance.unwrap_or(f64::NAN),
                o.checked_radius
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::from(3)
        }
    }
}

/// This process's peak resident set (`VmHWM`), in KiB (Linux).
fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The 1-minute load average.
fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| l.split_whitespace().next().map(str::to_owned))
        .unwrap_or_else(|| "?".into())
}

/// One child run as the parent saw it.
#[derive(Debug, Clone, Copy)]
struct Run {
    outcome: Outcome,
    wall: f64,
    rss_kib: u64,
}

/// Runs one child and times it as a whole process.
fn spawn(args: &Args, peer: Peer, case: &Case, radius: f64, check: bool) -> Result<Run, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let start = Instant::now();
    let mut child = Command::new(exe)
        .args(["--seed", &args.seed.to_string(), "--child", peer.name()])
        .args([
            case.dim.to_string(),
            case.periodic.to_string(),
            radius.to_string(),
            check.to_string(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let limit = Duration::from_secs_f64(args.timeout);
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            return Err(format!("too slow: stopped after {:.0} s", args.timeout));
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let wall = start.elapsed().as_secs_f64();
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !status.success() {
        let why = stderr
            .trim()
            .lines()
            .last()
            .unwrap_or("no message")
            .to_owned();
        return Err(match status.code() {
            // The child's message says "wrong: …" (the check) or
            // "refused: …" (the crate would not run the job).
            Some(3) => why,
            Some(c) => format!("failed (exit {c}): {why}"),
            None => format!("failed (signal): {why}"),
        });
    }
    let fields: Vec<&str> = stdout.split_whitespace().collect();
    let parse = |i: usize| -> Result<f64, String> {
        fields
            .get(i)
            .and_then(|f| f.parse().ok())
            .ok_or_else(|| format!("unreadable child output {stdout:?}"))
    };
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "counts and KiB printed as integers"
    )]
    let run = Run {
        outcome: Outcome {
            count: parse(0)? as usize,
            sampling_seconds: parse(1)?,
            min_distance: Some(parse(3)?).filter(|d| !d.is_nan()),
            checked_radius: parse(4)?,
        },
        wall,
        rss_kib: parse(2)? as u64,
    };
    Ok(run)
}

/// A crate's result on one case.
struct Entry {
    peer: Peer,
    /// The radius given to the crate, and its checked run.
    radius: f64,
    checked: Result<Run, String>,
    timed: Vec<Run>,
    error: Option<String>,
}

impl Entry {
    fn median_wall(&self) -> Option<f64> {
        median(self.timed.iter().map(|r| r.wall).collect())
    }
}

fn median(mut xs: Vec<f64>) -> Option<f64> {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    (n > 0).then(|| {
        if n % 2 == 1 {
            xs[n / 2]
        } else {
            f64::midpoint(xs[n / 2 - 1], xs[n / 2])
        }
    })
}

/// Checked runs allowed for fitting a crate's radius to the count. Counts
/// move in steps of a point or so per seed, so a few tries can straddle a
/// 1 % window in 8-D (2 200 points).
const CALIBRATION_RUNS: usize = 6;

/// Checked runs at radii fitted to `target` points (within 1 %).
fn calibrate(args: &Args, peer: Peer, case: &Case, target: usize) -> (f64, Result<Run, String>) {
    let mut radius = case.radius;
    let mut last = Err("not run".to_owned());
    for _ in 0..CALIBRATION_RUNS {
        last = spawn(args, peer, case, radius, true);
        let Ok(run) = &last else { break };
        #[expect(clippy::cast_precision_loss, reason = "counts, ratio only")]
        let ratio = run.outcome.count as f64 / target as f64;
        if (ratio - 1.0).abs() <= 0.01 {
            return (radius, last);
        }
        #[expect(clippy::cast_precision_loss, reason = "a dimension")]
        let exponent = 1.0 / case.dim as f64;
        radius *= ratio.powf(exponent);
    }
    if let Ok(run) = &last {
        let count = run.outcome.count;
        last = Err(format!(
            "count not within 1 % of {target} after {CALIBRATION_RUNS} radii (last r = {radius}: {count})"
        ));
    }
    (radius, last)
}

fn parent(args: &Args) -> Result<(), String> {
    let wanted: Vec<Peer> = if args.peers.is_empty() {
        ALL.to_vec()
    } else {
        let mut list = vec![Peer::Bridson];
        for name in &args.peers {
            let peer = Peer::from_name(name).ok_or_else(|| format!("unknown crate {name}"))?;
            if !list.contains(&peer) {
                list.push(peer);
            }
        }
        list
    };
    let cases: Vec<&Case> = CASES
        .iter()
        .filter(|c| {
            args.cases.is_empty() || args.cases.iter().any(|p| c.name.starts_with(p.as_str()))
        })
        .collect();
    let mut json = match &args.json {
        Some(path) => Some(
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(path)
                .map_err(|e| format!("{}: {e}", path.display()))?,
        ),
        None => None,
    };
    println!(
        "k = {}, seed {}, unit box, {} timed runs per crate, alternating, one process per run\n",
        peers::K,
        args.seed,
        args.runs
    );
    for peer in &wanted {
        println!("- {}: {}", peer.name(), peer.how());
    }
    println!();
    for case in cases {
        let load_start = load();
        let Ok(reference) = spawn(args, Peer::Bridson, case, case.radius, true) else {
            return Err(format!("bridson failed on {}", case.name));
        };
        let target = reference.outcome.count;
        let mut entries: Vec<Entry> = Vec::new();
        for &peer in &wanted {
            let mut entry = Entry {
                peer,
                radius: case.radius,
                checked: Err("unsupported".into()),
                timed: Vec::new(),
                error: None,
            };
            if let Err(why) = peer.supports(case.dim, case.periodic) {
                entry.error = Some(format!("unsupported: {why}"));
            } else if peer == Peer::Bridson {
                entry.checked = Ok(reference);
            } else {
                let (radius, checked) = calibrate(args, peer, case, target);
                entry.radius = radius;
                entry.checked = checked;
            }
            if let Err(e) = &entry.checked {
                entry.error.get_or_insert_with(|| e.clone());
            }
            entries.push(entry);
        }
        for _ in 0..args.runs {
            for entry in entries.iter_mut().filter(|e| e.error.is_none()) {
                match spawn(args, entry.peer, case, entry.radius, false) {
                    Ok(run) => entry.timed.push(run),
                    Err(e) => entry.error = Some(e),
                }
            }
        }
        let load_end = load();
        print!("{}", table(case, &entries, &load_start, &load_end));
        std::io::stdout().flush().ok();
        if let Some(file) = &mut json {
            for entry in &entries {
                writeln!(file, "{}", json_line(case, entry, &load_start, &load_end))
                    .map_err(|e| e.to_string())?;
            }
        }
    }
    Ok(())
}

/// ρ of a run, or NaN.
fn rho(dim: usize, radius: f64, count: usize) -> f64 {
    let f: fn(f64, usize, f64) -> Option<f64> = match dim {
        2 => bridson::relative_radius::<2>,
        3 => bridson::relative_radius::<3>,
        4 => bridson::relative_radius::<4>,
        5 => bridson::relative_radius::<5>,
        6 => bridson::relative_radius::<6>,
        7 => bridson::relative_radius::<7>,
        8 => bridson::relative_radius::<8>,
        _ => return f64::NAN,
    };
    f(radius, count, 1.0).unwrap_or(f64::NAN)
}

/// The markdown table of one case.
fn table(case: &Case, entries: &[Entry], load_start: &str, load_end: &str) -> String {
    let mut out = String::new();
    let shape = if case.periodic { "torus" } else { "box" };
    let _ = writeln!(
        out,
        "#### {} ({}-D unit {shape}, r = {}; load {load_start} → {load_end})\n",
        case.name, case.dim, case.radius
    );
    out.push_str(
        "| crate | points | r | ρ | seconds | M points/s | peak MiB | time / bridson's | note |\n",
    );
    out.push_str("|---|--:|--:|--:|--:|--:|--:|--:|---|\n");
    let reference = entries
        .iter()
        .find(|e| e.peer == Peer::Bridson)
        .and_then(Entry::median_wall);
    for entry in entries {
        let name = entry.peer.name();
        match (&entry.error, &entry.checked, entry.median_wall()) {
            (None, Ok(checked), Some(wall)) => {
                let count = checked.outcome.count;
                #[expect(clippy::cast_precision_loss, reason = "KiB, far below 2^52")]
                let rss = median(
                    entry
                        .timed
                        .iter()
                        .map(|r| r.rss_kib as f64 / 1024.0)
                        .collect(),
                )
                .unwrap_or(f64::NAN);
                #[expect(clippy::cast_precision_loss, reason = "a count, rate only")]
                let rate = count as f64 / wall / 1e6;
                let ratio = reference.map_or("–".into(), |b| format!("{:.2}×", wall / b));
                let _ = writeln!(
                    out,
                    "| {name} | {count} | {:.6} | {:.4} | {wall:.3} | {rate:.3} | {rss:.1} | {ratio} | min distance {:.7} |",
                    checked.outcome.checked_radius,
                    rho(case.dim, checked.outcome.checked_radius, count),
                    checked.outcome.min_distance.unwrap_or(f64::NAN),
                );
            }
            (error, _, _) => {
                let why = error.clone().unwrap_or_else(|| "no timed run".into());
                let _ = writeln!(out, "| {name} | | | | | | | | {} |", why.replace('|', "/"));
            }
        }
    }
    out.push('\n');
    out
}

/// One JSON object: the case, the crate, every run.
fn json_line(case: &Case, entry: &Entry, load_start: &str, load_end: &str) -> String {
    let walls: Vec<String> = entry
        .timed
        .iter()
        .map(|r| format!("{:.4}", r.wall))
        .collect();
    let rss: Vec<String> = entry.timed.iter().map(|r| r.rss_kib.to_string()).collect();
    let sampling: Vec<String> = entry
        .timed
        .iter()
        .map(|r| format!("{:.4}", r.outcome.sampling_seconds))
        .collect();
    let (count, min_distance, checked_radius) = match &entry.checked {
        Ok(run) => (
            run.outcome.count.to_string(),
            run.outcome
                .min_distance
                .map_or("null".into(), |d| format!("{d}")),
            format!("{}", run.outcome.checked_radius),
        ),
        Err(_) => ("null".into(), "null".into(), "null".into()),
    };
    let error = entry
        .error
        .as_ref()
        .map_or("null".into(), |e| format!("{:?}", e));
    format!(
        "{{\"case\":\"{}\",\"dim\":{},\"periodic\":{},\"crate\":\"{}\",\"radius\":{},\"checked_radius\":{checked_radius},\"points\":{count},\"min_distance\":{min_distance},\"wall_seconds\":[{}],\"sampling_seconds\":[{}],\"peak_rss_kib\":[{}],\"error\":{error},\"load_start\":{load_start},\"load_end\":{load_end}}}",
        case.name,
        case.dim,
        case.periodic,
        entry.peer.name(),
        entry.radius,
        walls.join(","),
        sampling.join(","),
        rss.join(","),
    )
}
