//! Replays the committed fuzz corpus (`fuzz/corpus/<target>/*`) through the
//! fuzz targets' own assertions, so that a regression fails `cargo test`
//! without a fuzzer or a nightly toolchain. The decoding and the checks live
//! in `fuzz/common/`, shared with the targets; see `fuzz/README.md`.

mod common;

#[path = "../fuzz/common/bytes.rs"]
mod bytes;

#[path = "../fuzz/common/batch.rs"]
mod batch;

#[path = "../fuzz/common/streaming.rs"]
mod streaming;

#[path = "../fuzz/common/camera.rs"]
mod camera;

#[path = "../fuzz/common/nets.rs"]
mod nets;

#[path = "../fuzz/common/parts.rs"]
mod parts;

#[path = "../fuzz/common/field.rs"]
mod field;

#[cfg(feature = "serde")]
#[path = "../fuzz/common/config_json.rs"]
mod config_json;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

/// Every file of one target's corpus, in name order.
fn corpus(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let entries = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read the corpus {}: {e}", dir.display()));
    let mut files: Vec<PathBuf> = entries
        .map(|entry| entry.map(|e| e.path()))
        .collect::<Result<_, _>>()
        .unwrap_or_else(|e| panic!("cannot list the corpus {}: {e}", dir.display()));
    files.retain(|p| p.is_file());
    files.sort();
    files
}

/// Runs `check` on every corpus file of `target`; fails naming each file
/// whose input panics.
fn replay(target: &str, check: fn(&[u8])) {
    let files = corpus(target);
    assert!(!files.is_empty(), "the {target} corpus is empty");
    let mut failed = Vec::new();
    for path in &files {
        let data =
            std::fs::read(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        if catch_unwind(AssertUnwindSafe(|| check(&data))).is_err() {
            failed.push(path.display().to_string());
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {} {target} corpus inputs fail (messages above):\n  {}",
        failed.len(),
        files.len(),
        failed.join("\n  ")
    );
}

#[test]
fn batch_corpus() {
    replay("batch", batch::run);
}

#[test]
fn streaming_corpus() {
    replay("streaming", streaming::run);
}

#[test]
fn camera_corpus() {
    replay("camera", camera::run);
}

#[test]
fn nets_corpus() {
    replay("nets", nets::run);
}

#[test]
fn parts_corpus() {
    replay("parts", parts::run);
}

#[test]
fn field_corpus() {
    replay("field", field::run);
}

/// The decoder accepts every input, even an empty one.
#[test]
fn field_decodes_short_inputs() {
    for len in 0..=3 {
        field::run(&vec![0xff; len]);
        field::run(&vec![0; len]);
    }
}

#[cfg(feature = "serde")]
#[test]
fn config_json_corpus() {
    replay("config_json", config_json::run);
}

/// The decoder accepts every input, even an empty one.
#[test]
fn batch_decodes_short_inputs() {
    for len in 0..=3 {
        batch::run(&vec![0xff; len]);
        batch::run(&vec![0; len]);
    }
}

/// The decoder accepts every input, even an empty one.
#[test]
fn streaming_decodes_short_inputs() {
    for len in 0..=3 {
        streaming::run(&vec![0xff; len]);
        streaming::run(&vec![0; len]);
    }
}

/// The decoder accepts every input, even an empty one (both halves: the
/// first byte picks `PoissonPixelSampler` or `CameraPixels`).
#[test]
fn camera_decodes_short_inputs() {
    for len in 0..=3 {
        camera::run(&vec![0xff; len]);
        camera::run(&vec![0; len]);
        camera::run(&vec![1; len]);
    }
}

/// The decoder accepts every input, even an empty one; and a few hundred
/// pseudo-random inputs pass the model (a bounded sweep, not a fuzzer).
#[test]
fn nets_decodes_short_and_random_inputs() {
    for len in 0..=3 {
        nets::run(&vec![0xff; len]);
        nets::run(&vec![0; len]);
        nets::run(&vec![6; len]);
    }
    let mut state = 0x5eed_u64;
    for _ in 0..300 {
        let bytes: Vec<u8> = (0..96)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (state >> 56) as u8
            })
            .collect();
        nets::run(&bytes);
    }
}
