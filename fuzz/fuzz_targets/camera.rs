//! The renderer-side API (`bridson::PoissonPixelSampler`,
//! `bridson::CameraPixels`), inputs decoded from raw bytes: see
//! `fuzz/common/camera.rs`.
#![no_main]

#[path = "../../tests/common/mod.rs"]
mod common;

#[path = "../common/bytes.rs"]
mod bytes;

#[path = "../common/camera.rs"]
mod camera;

libfuzzer_sys::fuzz_target!(|data: &[u8]| camera::run(data));
