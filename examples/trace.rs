//! A minimal reference tracer that re-renders the scenes of Ye's
//! "Implementing Bridson's Fast Poisson Disk Sampling in PBRT" with every
//! pixel sampler, and measures the error of each against a high-count
//! reference. It is also the example of how a renderer drives the crate's
//! [`bridson::PixelSampler`]: see `PixelFiller::fill` in
//! `examples/trace/sources.rs` (start a sample, take the camera's values,
//! then the integrator's next pair).
//!
//! Run the study as
//! `cargo run --release --example trace -- --size 128x128 --seeds 8 --reference-dir target/trace-refs --out-dir docs/images/trace --json docs/trace.json`;
//! one render, without a reference, as
//! `cargo run --release --example trace -- --scene checker --sampler poisson-pixel --spp 64 --size 512x512 --seeds 1 --reference-spp 0 --out-dir pics`.
//! `--help` lists every flag. Exit status: 0 on success, 1 if writing
//! fails, 2 for bad arguments.
//!
//! The parts live in `examples/trace/`: `geometry.rs` (vectors, rays, the
//! analytic shapes and their intersections), `camera.rs` (pinhole and thin
//! lens, the concentric mapping), `scene.rs` (textures, the quad light,
//! shading, the four scenes), `sources.rs` (each sampler's samples),
//! `render.rs` (the threaded render loop), `study.rs` (references and
//! errors), `metrics.rs` (blurred RMSE, low-frequency power), `report.rs`
//! (tables, JSON, PNGs, montages) and `args.rs`.

#[cfg(test)]
#[path = "trace/anchors.rs"]
mod anchors;
#[path = "trace/args.rs"]
mod args;
#[path = "trace/camera.rs"]
mod camera;
#[allow(dead_code, reason = "shared with `plot`, which uses all of it")]
#[path = "plot/canvas.rs"]
mod canvas;
#[path = "common/mod.rs"]
mod common;
#[allow(dead_code, reason = "shared with `plot`, which uses all of it")]
#[path = "plot/font.rs"]
mod font;
#[path = "trace/geometry.rs"]
mod geometry;
#[path = "trace/metrics.rs"]
mod metrics;
#[path = "trace/render.rs"]
mod render;
#[path = "trace/report.rs"]
mod report;
#[path = "trace/scene.rs"]
mod scene;
#[path = "trace/sources.rs"]
mod sources;
#[cfg(test)]
#[path = "common/step_area.rs"]
mod step_area;
#[path = "trace/study.rs"]
mod study;

use clap::Parser;
use common::Failure;
use common::progress::Progress;
use std::io::Write;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Bad flags print clap's message and exit 2; --help exits 0.
    let args = args::Args::parse();
    common::finish("trace", run(&args))
}

/// Writes `text` to stdout at once (the table of a scene as it finishes).
fn say(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::Io(format!("writing the table: {e}")))
}

fn run(args: &args::Args) -> Result<(), Failure> {
    if args.seeds < 2 && args.reference_spp > 0 {
        return Err(Failure::Usage(
            "--seeds must be at least 2 to measure errors (or give --reference-spp 0)".to_owned(),
        ));
    }
    let size = args.size;
    let threads = args.thread_count();
    let seeds: Vec<u64> = (0..u64::from(args.seeds))
        .map(|k| args.seed.wrapping_add(k))
        .collect();
    let scenes = args.scenes();
    let samplers = args.samplers();
    // Progress in samples traced, which is roughly the work.
    let pixels = f64::from(size[0]) * f64::from(size[1]);
    let per_scene = f64::from(args.reference_spp)
        + f64::from(args.seeds)
            * samplers.len() as f64
            * args.spp.iter().map(|&n| f64::from(n)).sum::<f64>();
    say(&format!(
        "Size {}x{}, {} seeds, {threads} threads; RMSE against a {} reference at {} spp.\n",
        size[0],
        size[1],
        args.seeds,
        study::REFERENCE_SAMPLER,
        args.reference_spp
    ))?;
    let mut progress = Progress::new("trace", per_scene * pixels * scenes.len() as f64);
    let mut done = 0.0;
    let mut rows = Vec::new();
    let mut references = Vec::new();
    for name in &scenes {
        let scene = scene::Scene::by_name(name, size)
            .ok_or_else(|| Failure::Usage(format!("unknown scene {name:?}")))?;
        let reference = if args.reference_spp > 0 {
            let work = f64::from(args.reference_spp) * pixels;
            let label = format!("{name}: reference, {} spp", args.reference_spp);
            let r = study::reference(
                &scene,
                size,
                args.reference_spp,
                args.reference_dir.as_deref(),
                threads,
                &mut |f| {
                    progress.set(done + f * work, &label);
                },
            )
            .map_err(Failure::Usage)?;
            done += work;
            Some(r)
        } else {
            None
        };
        for &spp in &args.spp {
            let mut firsts = Vec::new();
            for sampler in &samplers {
                let work = f64::from(spp) * pixels * f64::from(args.seeds);
                let (row, first) = study::measure(
                    &scene,
                    sampler,
                    spp,
                    &seeds,
                    size,
                    reference.as_ref(),
                    threads,
                    &mut |f, k| {
                        let label = format!("{name} {sampler} {spp} spp, seed {k}/{}", args.seeds);
                        progress.set(done + f * work, &label);
                    },
                )
                .map_err(Failure::Usage)?;
                done += work;
                if let Some(dir) = &args.out_dir {
                    let path = dir.join(format!("{name}-{sampler}-{spp}.png"));
                    report::save(&report::canvas(&first.image), &path)?;
                }
                firsts.push((row.clone(), first));
                rows.push(row);
            }
            if let (Some(dir), Some(reference)) = (&args.out_dir, &reference) {
                let panels: Vec<report::Panel<'_>> = firsts
                    .iter()
                    .map(|(row, first)| report::Panel {
                        label: row.sampler.clone(),
                        caption: row
                            .errors
                            .map_or_else(String::new, |e| format!("rmse {:.2e}", e.rmse)),
                        image: &first.image,
                    })
                    .collect();
                let montage = report::montage(name, spp, reference, &panels);
                report::save(&montage, &dir.join(format!("montage-{name}-{spp}.png")))?;
            }
        }
        // Each scene's results as soon as they are in, so that a long study
        // stopped part-way keeps what it has measured.
        let scene_rows: Vec<study::Row> =
            rows.iter().filter(|r| &r.scene == name).cloned().collect();
        say(&format!("\n{}", report::table(&scene_rows)))?;
        if let Some(path) = &args.json {
            common::write_results_json(path, &report::json(&rows))?;
        }
        if let Some(r) = reference {
            references.push((name.clone(), r));
        }
    }
    progress.finish();
    if !references.is_empty() {
        say(&format!(
            "\n{}",
            report::reference_table(&references, &rows)
        ))?;
    }
    Ok(())
}
