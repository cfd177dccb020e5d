//! What the study writes: the markdown table on stdout, the JSON file and
//! one log-log PNG per integrand.

use crate::chart::{Curve, LogLogChart, PALETTE};
use crate::common::Failure;
use crate::integrand::Kind;
use crate::study::fit_slope;
use std::fmt::Write as _;
use std::path::Path;

/// The slopes are fitted over N at least this.
pub(crate) const FIT_FROM: u32 = 16;
/// The N of the table's MSE columns.
const TABLE_N: [u32; 3] = [4, 16, 64];
/// The reference slopes drawn on the charts.
const REFERENCE_SLOPES: [f64; 3] = [-1.0, -1.5, -2.0];
/// The size of the charts.
const CHART_SIZE: (u32, u32) = (900, 520);

/// One sampler's curve on one integrand: `(n, mse)` for every N.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Series {
    pub(crate) sampler: String,
    pub(crate) kind: Kind,
    pub(crate) points: Vec<(u32, f64)>,
}

impl Series {
    fn slope(&self) -> Option<f64> {
        fit_slope(&self.points, FIT_FROM)
    }

    fn mse_at(&self, n: u32) -> Option<f64> {
        self.points.iter().find(|p| p.0 == n).map(|p| p.1)
    }
}

/// The markdown table: per integrand, a row per sampler with the MSE at
/// N = 4, 16, 64 and the fitted slope ("–" where the run has no such N).
pub(crate) fn table(series: &[Series], kinds: &[Kind]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| integrand | sampler | MSE N=4 | MSE N=16 | MSE N=64 | slope (N >= {FIT_FROM}) |"
    );
    let _ = writeln!(out, "|---|---|---:|---:|---:|---:|");
    for &kind in kinds {
        for s in series.iter().filter(|s| s.kind == kind) {
            let cells: Vec<String> = TABLE_N
                .iter()
                .map(|&n| s.mse_at(n).map_or("–".to_owned(), |m| format!("{m:.3e}")))
                .collect();
            let slope = s.slope().map_or("–".to_owned(), |k| format!("{k:.2}"));
            let _ = writeln!(
                out,
                "| {} | {} | {} | {slope} |",
                kind.name(),
                s.sampler,
                cells.join(" | ")
            );
        }
    }
    out
}

/// The JSON document: every (sampler, integrand, N) with its MSE and the
/// number of trials it averages.
pub(crate) fn json(series: &[Series], trials: u32) -> serde_json::Value {
    let results: Vec<serde_json::Value> = series
        .iter()
        .flat_map(|s| {
            s.points.iter().map(move |&(n, mse)| {
                serde_json::json!({
                    "sampler": s.sampler,
                    "integrand": s.kind.name(),
                    "n": n,
                    "mse": mse,
                    "trials": trials,
                })
            })
        })
        .collect();
    serde_json::json!({ "results": results })
}

/// Writes the JSON document to `path`, one result a line.
///
/// # Errors
/// [`Failure::Io`] if writing fails.
pub(crate) fn write_json(path: &Path, series: &[Series], trials: u32) -> Result<(), Failure> {
    let doc = json(series, trials);
    let results = doc["results"].as_array().cloned().unwrap_or_default();
    crate::common::write_results_json(path, &results)
}

/// The chart of one integrand: every sampler's curve, labelled with its
/// slope, and the reference slopes drawn from the largest MSE at N = 1.
pub(crate) fn chart(series: &[Series], kind: Kind, trials: u32) -> LogLogChart {
    let curves: Vec<Curve> = series
        .iter()
        .filter(|s| s.kind == kind)
        .zip(PALETTE.iter().cycle())
        .map(|(s, &colour)| Curve {
            label: format!(
                "{} {}",
                s.sampler,
                s.slope().map_or("-".to_owned(), |k| format!("{k:.2}"))
            ),
            points: s.points.iter().map(|&(n, m)| [f64::from(n), m]).collect(),
            colour,
        })
        .collect();
    let top = series
        .iter()
        .filter(|s| s.kind == kind)
        .filter_map(|s| s.mse_at(1))
        .fold(f64::MIN_POSITIVE, f64::max);
    LogLogChart {
        title: format!(
            "{}: MSE of the mean of N samples, {trials} trials",
            kind.name()
        ),
        x_label: "N (samples per pixel)".to_owned(),
        y_label: "mean squared error".to_owned(),
        curves,
        reference_slopes: REFERENCE_SLOPES.to_vec(),
        anchor: [1.0, top],
    }
}

/// Writes `DIR/convergence-INTEGRAND.png` for each integrand.
///
/// # Errors
/// [`Failure::Io`] if a file cannot be written.
pub(crate) fn write_charts(
    dir: &Path,
    series: &[Series],
    kinds: &[Kind],
    trials: u32,
) -> Result<(), Failure> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Failure::Io(format!("creating {}: {e}", dir.display())))?;
    for &kind in kinds {
        let path = dir.join(format!("convergence-{}.png", kind.name()));
        chart(series, kind, trials)
            .render(CHART_SIZE.0, CHART_SIZE.1)
            .save(&path)
            .map_err(|e| Failure::Io(format!("writing {}: {e}", path.display())))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::font;

    fn two_series() -> Vec<Series> {
        [("independent", 1.0), ("sobol-owen", 1.5)]
            .into_iter()
            .map(|(name, k)| Series {
                sampler: name.to_owned(),
                kind: Kind::Disk,
                points: (1..=64).map(|n| (n, 0.1 * f64::from(n).powf(-k))).collect(),
            })
            .collect()
    }

    #[test]
    fn table_json_and_chart_agree() {
        let series = two_series();
        let text = table(&series, &[Kind::Disk]);
        assert!(
            text.contains("| disk | independent | 2.500e-2 | 6.250e-3 | 1.563e-3 | -1.00 |"),
            "{text}"
        );
        assert!(text.contains("| disk | sobol-owen |"), "{text}");
        let doc = json(&series, 20);
        let results = doc["results"].as_array().expect("array");
        assert_eq!(results.len(), 128, "every point");
        assert_eq!(results[3]["n"], 4, "n");
        assert_eq!(results[3]["trials"], 20, "trials");
        assert_eq!(results[3]["integrand"], "disk", "integrand");
        let c = chart(&series, Kind::Disk, 20);
        assert_eq!(c.curves[1].label, "sobol-owen -1.50", "slope in the legend");
        assert!(c.texts().iter().all(|t| font::covers(t)), "{:?}", c.texts());
    }

    #[test]
    fn the_json_file_parses_back() {
        let series = two_series();
        let path =
            std::env::temp_dir().join(format!("convergence-test-{}.json", std::process::id()));
        write_json(&path, &series, 20).expect("writes");
        let text = std::fs::read_to_string(&path).expect("reads");
        let _ = std::fs::remove_file(&path);
        let doc: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(doc, json(&series, 20), "the same document");
        assert_eq!(text.lines().count(), 130, "one result a line, plus two");
    }
}
