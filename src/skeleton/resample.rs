//! Resampling a motion to [`FPS`] (30 fps): root positions interpolate linearly, rotations by
//! shortest-path slerp.
//!
//! The output covers the source's duration `(frames − 1) / fps`: `floor(duration · 30 + 1e-9) + 1`
//! frames at `t_k = k / 30`. Frame times written with few digits (`0.0333333`, `0.008333`) are read as
//! the whole frame rate they round (30, 120: within 1e-4 relative), else a 120-frame 30-fps take
//! would lose its last frame to rounding.

use super::ImportError;
use super::canonical::FPS;
use super::rotation::slerp;
use glam::{DQuat, DVec3};

/// Most frames a resampled clip may have (about 9 h at 30 fps).
pub const MAX_FRAMES: usize = 1_000_000;

/// Frames per second of a clip with `frame_time`, snapped to the nearest whole rate when within 1e-4
/// relative of it.
pub fn source_fps(frame_time: f64) -> f64 {
    let fps = 1.0 / frame_time;
    let r = fps.round();
    if r >= 1.0 && (fps - r).abs() <= 1e-4 * r { r } else { fps }
}

/// Frames (source and resampled together) an import may hold whatever its data: about 40 MB of
/// working memory. See [`check_budget`].
pub const MIN_HELD_FRAMES: usize = 20_000;

/// Channel values of the source per frame held beyond [`MIN_HELD_FRAMES`].
pub const VALUES_PER_HELD_FRAME: usize = 8;

/// Frames of the resampled clip for `frames` source frames at `fps` (at least 1), or `TooLong`
/// beyond [`MAX_FRAMES`] (or for a non-finite rate).
pub fn output_frames(frames: usize, fps: f64) -> Result<usize, ImportError> {
    if frames <= 1 {
        return Ok(1);
    }
    let duration = (frames - 1) as f64 / fps;
    let n = (duration * FPS + 1e-9).floor() + 1.0;
    if !(n.is_finite() && n <= MAX_FRAMES as f64) {
        return Err(ImportError::TooLong { seconds: duration, limit: MAX_FRAMES });
    }
    Ok((n as usize).max(1))
}

/// Bounds an import's work from the header alone (frames, channels per frame, frame time), before
/// anything proportional to the motion is allocated; returns the resampled frame count.
///
/// The importer holds a few hundred bytes per source frame and per resampled frame (poses, root
/// path, foot heights), so their sum may be at most [`MIN_HELD_FRAMES`] or one frame per
/// [`VALUES_PER_HELD_FRAME`] values of the source, whichever is more. A file's values take at least
/// 2 bytes each, so a file under 1 MB holds at most ~62,500 frames (~100 MB with the features); a
/// full human rig (≥ 60 channels) at ≥ 5 fps always fits. Beyond: [`ImportError::OverBudget`]
/// (e.g. two frames with `Frame Time: 16000`, 480,001 frames at 30 fps, or a million frames of no
/// channels).
pub fn check_budget(frames: usize, channels: usize, frame_time: f64) -> Result<usize, ImportError> {
    let fps = source_fps(frame_time);
    let resampled = output_frames(frames, fps)?;
    let limit = MIN_HELD_FRAMES.max(frames.saturating_mul(channels) / VALUES_PER_HELD_FRAME);
    if frames.saturating_add(resampled) > limit {
        return Err(ImportError::OverBudget { frames, channels, fps, resampled, limit });
    }
    Ok(resampled)
}

/// One output frame: source frames `i` and `i + 1` (clamped) mixed with weight `t` on the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub i: usize,
    pub t: f64,
}

/// The output frames for `frames` source frames at `fps`.
pub fn plan(frames: usize, fps: f64) -> Result<Vec<Sample>, ImportError> {
    if frames <= 1 {
        return Ok(vec![Sample { i: 0, t: 0.0 }]);
    }
    let n = output_frames(frames, fps)?;
    Ok((0..n)
        .map(|k| {
            let s = k as f64 * fps / FPS; // exact for whole multiples of 30 fps
            let i = (s.floor().max(0.0) as usize).min(frames - 1);
            let t = if i + 1 < frames { (s - i as f64).clamp(0.0, 1.0) } else { 0.0 };
            Sample { i, t }
        })
        .collect())
}

/// Resamples root positions and per-frame rotation arrays (any length) along `plan`.
pub fn apply<const N: usize>(
    plan: &[Sample],
    root: &[DVec3],
    rotations: &[[DQuat; N]],
) -> (Vec<DVec3>, Vec<[DQuat; N]>) {
    let last = root.len().saturating_sub(1);
    let mut out_root = Vec::with_capacity(plan.len());
    let mut out_rot = Vec::with_capacity(plan.len());
    for s in plan {
        let (a, b) = (s.i.min(last), (s.i + 1).min(last));
        if s.t <= 1e-12 || a == b {
            out_root.push(root[a]);
            out_rot.push(rotations[a]);
        } else {
            out_root.push(root[a].lerp(root[b], s.t));
            out_rot.push(std::array::from_fn(|j| slerp(rotations[a][j], rotations[b][j], s.t)));
        }
    }
    (out_root, out_rot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snaps_printed_frame_times() {
        assert_eq!(source_fps(0.0333333), 30.0);
        assert_eq!(source_fps(0.008333), 120.0);
        assert_eq!(source_fps(0.016667), 60.0);
        assert_eq!(source_fps(0.041667), 24.0);
        assert!((source_fps(0.0123) - 81.30081).abs() < 1e-4);
    }

    #[test]
    fn frame_counts_and_positions() {
        assert_eq!(plan(120, 30.0).unwrap().len(), 120);
        assert!(plan(120, 30.0).unwrap().iter().enumerate().all(|(k, s)| s.i == k && s.t == 0.0));
        assert_eq!(plan(150, 120.0).unwrap().len(), 38); // 149/120 s = 1.2417 s
        assert_eq!(plan(241, 60.0).unwrap().len(), 121);
        assert_eq!(plan(1, 60.0).unwrap(), vec![Sample { i: 0, t: 0.0 }]);
        let p = plan(11, 24.0).unwrap(); // 10/24 s → 13 frames
        assert_eq!(p.len(), 13);
        assert_eq!((p[1].i, (p[1].t - 0.8).abs() < 1e-12), (0, true));
        assert_eq!(p[12].i, 9);
        assert!((p[12].t - 0.6).abs() < 1e-9);
        assert!(matches!(plan(3, 1e-9), Err(ImportError::TooLong { .. })));
        assert!(matches!(plan(3, 0.0), Err(ImportError::TooLong { .. })));
    }

    #[test]
    fn budget_bounds_sparse_and_empty_clips() {
        // A legit clip: 120 frames of 66 channels at 120 fps → 30 frames.
        assert_eq!(check_budget(120, 66, 1.0 / 120.0).unwrap(), 30);
        // Short clips at any rate fit the floor: 600 frames at 1 fps → 17,971 frames (10 min).
        assert_eq!(check_budget(600, 66, 1.0).unwrap(), 17_971);
        // Two frames 16,000 s apart: 480,001 frames at 30 fps for 2 × 66 values.
        match check_budget(2, 66, 16_000.0) {
            Err(ImportError::OverBudget { frames: 2, resampled: 480_001, limit: MIN_HELD_FRAMES, .. }) => {}
            other => panic!("{other:?}"),
        }
        // A million frames without channels.
        assert!(matches!(check_budget(1_000_000, 0, 1.0 / 30.0), Err(ImportError::OverBudget { .. })));
        // A long, dense clip: bounded by its data (100,000 frames × 66 channels at 30 fps).
        assert_eq!(check_budget(100_000, 66, 1.0 / 30.0).unwrap(), 100_000);
        // Beyond the frame limit stays TooLong.
        assert!(matches!(check_budget(3, 66, 1e9), Err(ImportError::TooLong { .. })));
        assert!(matches!(check_budget(3, 66, f64::NAN), Err(ImportError::TooLong { .. })));
    }

    #[test]
    fn interpolates() {
        let root = vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 4.0)];
        let rot = vec![[DQuat::IDENTITY], [-DQuat::from_rotation_y(1.0)]];
        let (r, q) = apply(&plan(2, 15.0).unwrap(), &root, &rot);
        assert_eq!(r.len(), 3);
        assert!((r[1] - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
        assert!(q[1][0].dot(DQuat::from_rotation_y(0.5)).abs() > 1.0 - 1e-14);
    }
}
