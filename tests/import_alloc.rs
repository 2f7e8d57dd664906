//! The importer's memory is bounded by its input (issue 15, point 6): the resampled length is decided
//! from the header, and no file under 1 MB makes the import hold more than ~100 MB. A test binary of
//! its own, with the counting allocator of `alloc_support`, so that no other binary's tests get
//! counted; its tests measure one at a time.
use motion_stylizer::skeleton::{ImportError, import_bvh};
mod alloc_support;
use alloc_support::{Counting, alone, peak_during};

#[global_allocator]
static ALLOC: Counting = Counting;

const MB: usize = 1 << 20;

fn m21_text() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/foreign/m21_walk.bvh")).unwrap()
}

/// The m21 fixture's hierarchy with `frames` copies of its first row and `frame_time`.
fn m21_with(frames: usize, frame_time: f64, max_bytes: usize) -> String {
    let text = m21_text();
    let motion = text.find("MOTION").unwrap();
    let header: String = text[..motion].lines().map(|l| format!("{}\n", l.trim())).collect();
    let mut rows = text[motion..].lines().skip(3);
    let row = rows.next().unwrap().trim().to_string();
    let mut out = format!("{header}MOTION\nFrames: {frames}\nFrame Time: {frame_time}\n");
    for _ in 0..frames {
        out.push_str(&row);
        out.push('\n');
    }
    assert!(out.len() < max_bytes, "{} bytes", out.len());
    out
}

/// The file: two frames, `Frame Time: 16000` (480,001 frames at 30 fps).
#[test]
fn a_sparse_clip_is_refused_before_allocating() {
    let _alone = alone();
    let text = m21_with(2, 16000.0, 4096);
    let h = motion_stylizer::bvh::Bvh::parse_header(&text).unwrap();
    assert_eq!((h.joints, h.channels, h.frames, h.frame_time), (21, 66, 2, 16000.0));
    let (r, peak) = peak_during(|| import_bvh(&text));
    match r {
        Err(e @ ImportError::OverBudget { frames: 2, resampled: 480_001, .. }) => {
            assert_eq!(e.code(), "TOO_LONG");
            assert!(e.to_string().contains("480001"), "{e}");
        }
        other => panic!("{:?}", other.err()),
    }
    assert!(peak < 64 * 1024, "{peak} bytes for a {} byte file", text.len());
}

/// A million frames of a rig without channels: a few hundred bytes of text.
#[test]
fn frames_without_data_are_refused() {
    let _alone = alone();
    let text = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 1000000\nFrame Time: 0.0333333\n";
    let (r, peak) = peak_during(|| import_bvh(text));
    assert!(matches!(r, Err(ImportError::OverBudget { frames: 1_000_000, channels: 0, .. })), "{:?}", r.err());
    assert!(peak < 64 * 1024, "{peak} bytes");
}

/// Files just under 1 MB: a dense clip at 30 fps, and a clip at the lowest rate its data allow; both
/// import, within 100 MB.
#[test]
fn files_under_a_megabyte_import_within_100_mb() {
    let _alone = alone();
    let one = m21_with(1, 1.0 / 30.0, MB);
    let row_bytes = one.lines().last().unwrap().len() + 1;
    let frames = (MB - one.len()) / row_bytes;
    for frame_time in [1.0 / 30.0, 1.0 / 4.0] {
        let text = m21_with(frames, frame_time, MB);
        let (r, peak) = peak_during(|| import_bvh(&text).map(|i| i.motion.frames()));
        eprintln!("{frames} frames at {:.1} fps: {:?}, peak {:.1} MB", 1.0 / frame_time, r, peak as f64 / MB as f64);
        assert!(r.is_ok(), "{:?}", r.err());
        assert!(peak < 100 * MB, "{peak} bytes for a {} byte file", text.len());
    }
    // The worst accepted case: the shortest rows ("0 " per value), as many frames as fit, and the
    // lowest frame rate whose resampled length still fits the budget.
    let zeros = vec!["0"; 66].join(" ");
    let mut text = one.rsplit_once('\n').unwrap().0.rsplit_once('\n').unwrap().0.to_string();
    let n = (MB - text.len()) / (zeros.len() + 1);
    let limit = n * 66 / motion_stylizer::skeleton::resample::VALUES_PER_HELD_FRAME;
    let frame_time = (limit - n - 2) as f64 / ((n - 1) as f64 * 30.0);
    text = text.replace("Frames: 1\n", &format!("Frames: {n}\n"));
    text = text.replacen("Frame Time: 0.03333333333333333", &format!("Frame Time: {frame_time}"), 1);
    for _ in 0..n {
        text.push('\n');
        text.push_str(&zeros);
    }
    text.push('\n');
    assert!(text.len() < MB);
    let (r, peak) = peak_during(|| import_bvh(&text).map(|i| i.motion.frames()));
    eprintln!("{n} zero rows at {:.2} fps: {:?}, peak {:.1} MB", 1.0 / frame_time, r, peak as f64 / MB as f64);
    assert!(r.as_ref().is_ok_and(|&f| f + n > limit - 10), "{:?}", r.err());
    assert!(peak < 100 * MB, "{peak} bytes for a {} byte file", text.len());
    // Slower still: refused, having allocated about the parsed file only.
    let text = m21_with(frames, 1.0, MB);
    let (r, peak) = peak_during(|| import_bvh(&text));
    assert!(matches!(r, Err(ImportError::OverBudget { .. })), "{:?}", r.err());
    assert!(peak < 4 * MB, "{peak} bytes");
}
