//! Issue 49's entry points (`iter_varying_with`, `for_f32`,
//! `f32_radius`), inputs decoded from raw bytes: see
//! `fuzz/common/parts.rs`.
#![no_main]

#[path = "../common/bytes.rs"]
mod bytes;

#[path = "../common/parts.rs"]
mod parts;

libfuzzer_sys::fuzz_target!(|data: &[u8]| parts::run(data));
