//! The reader's memory is bounded by the input size, not by what the header claims. A test binary of
//! its own, with the counting allocator of `alloc_support`, so that no other binary's tests get
//! counted; its tests measure one at a time.
use motion_stylizer::bvh::{Bvh, BvhError};
use std::path::Path;
mod alloc_support;
use alloc_support::{Counting, alone, peak_during};

#[global_allocator]
static ALLOC: Counting = Counting;

#[test]
fn allocation_is_bounded_by_the_input() {
    let _alone = alone();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bandai/dataset-1_walk_tired_001_f90.bvh");
    let text = std::fs::read_to_string(path).unwrap();
    // A well-formed file: the values (90 × 132 f64 = 95 KB) plus the hierarchy.
    let (ok, peak) = peak_during(|| Bvh::parse(&text));
    assert!(ok.is_ok());
    assert!(peak < 200_000, "{peak} bytes for a {} byte file", text.len());

    // `Frames: 1000000` (the limit) on a 132-channel rig claims 1 GB of values; only 90 rows follow.
    let claim = text.replace("Frames:\t90", "Frames:\t1000000");
    let (err, peak) = peak_during(|| Bvh::parse(&claim));
    assert_eq!(err, Err(BvhError::TooFewFrames { line: 225, expected: 1_000_000, found: 90 }));
    assert!(peak <= 8 * text.len(), "{peak} bytes for a {} byte file", text.len());
}
