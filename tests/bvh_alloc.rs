//! The reader's memory is bounded by the input size, not by what the header claims. A test binary of
//! its own, with a counting allocator, so that no other test's allocations get counted.
use motion_stylizer::bvh::{Bvh, BvhError};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Relaxed) + layout.size();
            PEAK.fetch_max(live, Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Bytes allocated at the peak of `f`, above what was live before it.
fn peak_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = LIVE.load(Relaxed);
    PEAK.store(before, Relaxed);
    let out = f();
    (out, PEAK.load(Relaxed) - before)
}

#[test]
fn allocation_is_bounded_by_the_input() {
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
