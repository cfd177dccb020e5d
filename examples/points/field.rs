//! `--field`: the field sampler (`bridson::Field`), written out of core.
//!
//! The box (or `--region`'s sub-box) is cut into chunks of `--chunk` (64 R
//! by default); a slab is one row of chunks along the last axis. Slab by
//! slab, its chunks are made on `--threads` threads, sorted into the
//! canonical order (last axis slowest, `bridson::field_order`) and written,
//! so only one slab of points is held at a time, and the bytes written do
//! not depend on `--chunk` or `--threads`: slab borders are planes of the
//! last axis, and the order is by that axis first.

use crate::args::{Config, FieldMode, Format};
use crate::common::Failure;
use crate::output::write_values;
use bridson::{Domain, Field, chunk_boxes, field_order};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::time::Instant;

/// A per-point hash for the digest of `--format none`: the coordinates'
/// bits through SplitMix64's finaliser. The digest is the wrapping sum over
/// points, so it does not depend on their order.
fn point_hash<const N: usize>(p: &[f64; N]) -> u64 {
    let mut h: u64 = 0x243f_6a88_85a3_08d3;
    for x in p {
        let mut z = h ^ x.to_bits();
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h = z ^ (z >> 31);
    }
    h
}

fn array<const N: usize>(values: &[f64], flag: &str) -> Result<[f64; N], Failure> {
    values
        .try_into()
        .map_err(|_| Failure::Usage(format!("{flag} needs {N} values")))
}

pub(crate) fn run<const N: usize>(config: &Config, mode: &FieldMode) -> Result<(), Failure> {
    let usage = |e: bridson::Error| Failure::Usage(e.to_string());
    let lo: [f64; N] = match &config.lo {
        Some(v) => array(v, "--lo")?,
        None => [0.0; N],
    };
    let extent: [f64; N] = match &config.extent {
        Some(v) => array(v, "--extent")?,
        None => [1.0; N],
    };
    let hi: [f64; N] = core::array::from_fn(|a| lo[a] + extent[a]);
    let periodic: [bool; N] =
        core::array::from_fn(|a| config.periodic.get(a).copied().unwrap_or(false));
    let domain = Domain::new(lo, hi).map_err(usage)?.with_periodic(periodic);
    let mut field = Field::new(domain, config.radius, config.seed).map_err(usage)?;
    if let Some(bytes) = config.max_grid_bytes {
        field = field.with_max_window_bytes(bytes);
    }
    let (qlo, qhi) = match &mode.region {
        Some((a, b)) => (array::<N>(a, "--region")?, array::<N>(b, "--region")?),
        None => (lo, hi),
    };
    let chunk = mode.chunk.unwrap_or(64.0 * config.radius);
    let threads = config.threads.map_or(1, std::num::NonZeroUsize::get);
    let boxes = chunk_boxes(qlo, qhi, chunk).map_err(usage)?;
    let start = Instant::now();
    let write = |out: &mut dyn Write| -> io::Result<Result<(u64, u64), bridson::Error>> {
        let (mut count, mut digest) = (0u64, 0u64);
        if config.format == Format::Csv {
            let header: Vec<String> = (0..N).map(|i| format!("x{i}")).collect();
            writeln!(out, "{}", header.join(","))?;
        }
        if config.format == Format::Json {
            write!(out, "{{\"dim\":{N},\"radius\":{},\"lo\":[", config.radius)?;
            write_values(out, &qlo)?;
            out.write_all(b"],\"hi\":[")?;
            write_values(out, &qhi)?;
            out.write_all(b"],\"points\":[")?;
        }
        // One slab: the chunks sharing their lower bound on the last axis.
        let mut rest = &boxes[..];
        while let Some(first) = rest.first() {
            let edge = first.0[N - 1];
            let len = rest.iter().take_while(|b| b.0[N - 1] == edge).count();
            let (slab, tail) = rest.split_at(len);
            rest = tail;
            let parts = match field.points_in_boxes(slab, threads) {
                Ok(parts) => parts,
                Err(e) => return Ok(Err(e)),
            };
            let mut points: Vec<[f64; N]> = parts.into_iter().flatten().collect();
            points.sort_by(field_order);
            for p in &points {
                match config.format {
                    Format::Csv => {
                        write_values(out, p)?;
                        out.write_all(b"\n")?;
                    }
                    Format::Json => {
                        out.write_all(if count == 0 { b"[" } else { b",[" })?;
                        write_values(out, p)?;
                        out.write_all(b"]")?;
                    }
                    Format::Binary => {
                        for x in p {
                            out.write_all(&x.to_le_bytes())?;
                        }
                    }
                    Format::None => digest = digest.wrapping_add(point_hash(p)),
                }
                count += 1;
            }
        }
        if config.format == Format::Json {
            out.write_all(b"]}\n")?;
        }
        if config.format == Format::None {
            writeln!(out, "count {count} digest {digest:016x}")?;
        }
        out.flush()?;
        Ok(Ok((count, digest)))
    };
    let result = match (&config.out, config.format) {
        (Some(path), f) if f != Format::None => {
            let file = File::create(path)
                .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", path.display())))?;
            write(&mut BufWriter::new(file))
        }
        _ => write(&mut BufWriter::new(io::stdout().lock())),
    }
    .map_err(|e| Failure::Io(format!("writing the points: {e}")))?;
    let (count, _) = result.map_err(usage)?;
    let seconds = start.elapsed().as_secs_f64();
    let volume: f64 = (0..N)
        .map(|a| qhi[a].min(hi[a]) - qlo[a].max(lo[a]))
        .product();
    let rho = usize::try_from(count)
        .ok()
        .and_then(|n| bridson::relative_radius::<N>(config.radius, n, volume))
        .map_or_else(|| "n/a".to_owned(), |r| format!("{r:.4}"));
    crate::common::report(&format!(
        "points: {count} in {seconds:.3} s, rho {rho}, field, chunk {chunk}, threads {threads}"
    ));
    Ok(())
}
