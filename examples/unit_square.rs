//! The unit square to CSV: points at least `r` apart, printed as `x,y`
//! lines on stdout, from a seed that reproduces them on any machine.
//!
//! ```sh
//! cargo run --release --example unit_square > points.csv
//! cargo run --release --example unit_square -- 0.01 42   # radius, seed
//! ```

use bridson::{Domain, PoissonDisk2};
use std::io::{BufWriter, Write};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let radius: f64 = args.next().map_or(Ok(0.02), |a| a.parse())?;
    let seed: u64 = args.next().map_or(Ok(7), |a| a.parse())?;

    let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, radius)?;
    let points = sampler.generate_seeded(seed)?;

    let mut out = BufWriter::new(std::io::stdout().lock());
    writeln!(out, "x,y")?;
    for [x, y] in &points {
        // `{}` prints the shortest form that reads back to the same f64.
        writeln!(out, "{x},{y}")?;
    }
    out.flush()?;
    eprintln!("{} points at r = {radius}, seed {seed}", points.len());
    Ok(())
}
