//! docs/peers.md's table: one row per case, one column per crate, from the JSON
//! lines of one or more runs (the last line of a (case, crate) wins).

use crate::peers::ALL;
use serde_json::Value;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Prints the summary of the JSON lines in `files`.
///
/// # Errors
/// A file cannot be read or holds a line that is not JSON.
pub(crate) fn print(files: &[PathBuf]) -> Result<(), String> {
    let mut lines: Vec<Value> = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            lines.push(serde_json::from_str(line).map_err(|e| format!("{}: {e}", file.display()))?);
        }
    }
    let mut cases: Vec<String> = Vec::new();
    for line in &lines {
        let case = line["case"].as_str().unwrap_or("?").to_owned();
        if !cases.contains(&case) {
            cases.push(case);
        }
    }
    print!("{}", render(&cases, &lines));
    Ok(())
}

fn median(values: &Value) -> Option<f64> {
    crate::median(
        values
            .as_array()?
            .iter()
            .filter_map(Value::as_f64)
            .collect(),
    )
}

fn render(cases: &[String], lines: &[Value]) -> String {
    let find = |case: &str, name: &str| {
        lines
            .iter()
            .rev()
            .find(|l| l["case"] == case && l["crate"] == name)
    };
    let mut out = String::from("| case | points | load (1 min) |");
    let mut rule = String::from("|---|--:|---|");
    for peer in ALL {
        let _ = write!(out, " {} |", peer.name());
        rule.push_str("--:|");
    }
    let _ = writeln!(out, "\n{rule}");
    let mut notes: Vec<String> = Vec::new();
    for case in cases {
        let reference = find(case, "bridson");
        let bridson_wall = reference.and_then(|l| median(&l["wall_seconds"]));
        let points = reference.and_then(|l| l["points"].as_u64()).unwrap_or(0);
        let load = reference.map_or(String::new(), |l| {
            format!("{}–{}", l["load_start"], l["load_end"])
        });
        let _ = write!(out, "| {case} | {points} | {load} |");
        for peer in ALL {
            let cell = match find(case, peer.name()) {
                None => "·".to_owned(),
                Some(line) => cell(line, bridson_wall, case, &mut notes),
            };
            let _ = write!(out, " {cell} |");
        }
        out.push('\n');
    }
    out.push('\n');
    for note in notes {
        let _ = writeln!(out, "{note}");
    }
    out
}

/// One cell: `M points/s (time / bridson's)`, or why there is none.
fn cell(line: &Value, bridson_wall: Option<f64>, case: &str, notes: &mut Vec<String>) -> String {
    let name = line["crate"].as_str().unwrap_or("?");
    if let Some(error) = line["error"].as_str() {
        if error.starts_with("unsupported") {
            return "–".into();
        }
        if let Some(rest) = error.strip_prefix("too slow: stopped after ") {
            return format!("> {}", rest.trim_end_matches(" s").to_owned() + " s");
        }
        let kind = if error.starts_with("wrong") {
            "wrong"
        } else if error.starts_with("count not within") {
            "count off"
        } else if error.starts_with("refused") {
            "refused"
        } else {
            "failed"
        };
        notes.push(format!("- {name}, {case}: {error}"));
        return format!("{kind} ({})", notes.len());
    }
    let (Some(wall), Some(points)) = (median(&line["wall_seconds"]), line["points"].as_f64())
    else {
        return "?".into();
    };
    let rate = significant(points / wall / 1e6);
    match bridson_wall {
        Some(b) if name != "bridson" => format!("{rate} ({:.1}×)", wall / b),
        _ => rate,
    }
}

/// Three significant digits (down to 10⁻⁶), so slow rates stay readable.
fn significant(x: f64) -> String {
    let mut decimals = 2;
    while decimals < 6 && x.abs() < 10f64.powi(2 - decimals) * 0.9995 {
        decimals += 1;
    }
    format!("{x:.*}", usize::try_from(decimals).unwrap_or(6))
}
