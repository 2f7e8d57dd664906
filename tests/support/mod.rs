//! Shared helpers for the retargeting tests.
#![allow(dead_code)]

use glam::DVec3;
use motion_stylizer::Motion;
use motion_stylizer::bvh::Bvh;
use motion_stylizer::skeleton::canonical::joint::*;
use motion_stylizer::skeleton::{UserRig, resample};

pub const FOREIGN: [&str; 4] = ["cmu31_rest", "cmu31_xia_neutral_16_000", "m21_walk", "iclone100_cmu_002_04"];
pub const BANDAI: [&str; 4] = [
    "dataset-1_walk_tired_001_f90",
    "dataset-2_raise-up-both-hands_active_001",
    "dataset-2_walk_elderly_001_f120",
    "dataset-2_walk_normal_001_f120",
];

/// Text of `tests/fixtures/<dir>/<name>.bvh`.
pub fn fixture_text(dir: &str, name: &str) -> String {
    let path = format!("{}/tests/fixtures/{dir}/{name}.bvh", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

pub fn fixture(dir: &str, name: &str) -> Bvh {
    Bvh::parse(&fixture_text(dir, name)).unwrap()
}

/// Every fixture as (dir, name).
pub fn all_fixtures() -> Vec<(&'static str, &'static str)> {
    FOREIGN.iter().map(|n| ("foreign", *n)).chain(BANDAI.iter().map(|n| ("bandai", *n))).collect()
}

/// The five end effectors: head, hands, feet.
pub const EFFECTORS: [usize; 5] = [HEAD, HAND_L, HAND_R, FOOT_L, FOOT_R];

/// Positions of the effectors of the source, on its own joints, resampled to the 30-fps times of the
/// imported motion (linear interpolation), in source units.
pub fn source_effectors(bvh: &Bvh, rig: &UserRig, frames: usize) -> Vec<[DVec3; 5]> {
    let map = rig.joint_map();
    let fps = resample::source_fps(bvh.frame_time);
    let pos: Vec<Vec<DVec3>> = (0..bvh.frames).map(|f| bvh.global_pose(f).0).collect();
    let at = |f: usize| -> [DVec3; 5] { std::array::from_fn(|k| pos[f][map[EFFECTORS[k]].unwrap()]) };
    (0..frames)
        .map(|k| {
            let s = k as f64 * fps / 30.0;
            let i = (s.floor() as usize).min(bvh.frames - 1);
            let t = s - i as f64;
            let (a, b) = (at(i), at((i + 1).min(bvh.frames - 1)));
            std::array::from_fn(|e| a[e].lerp(b[e], t))
        })
        .collect()
}

pub fn canonical_effectors(m: &Motion) -> Vec<[DVec3; 5]> {
    m.global_positions().iter().map(|p| std::array::from_fn(|k| p[EFFECTORS[k]])).collect()
}

/// The pairs of effectors compared: all 10.
pub fn pairs() -> Vec<(usize, usize)> {
    let mut v = Vec::new();
    for a in 0..5 {
        for b in a + 1..5 {
            v.push((a, b));
        }
    }
    v
}

pub const EFFECTOR_NAMES: [&str; 5] = ["head", "hand_l", "hand_r", "foot_l", "foot_r"];

/// Time series of the distance between effectors `a` and `b`, divided by `height`.
pub fn distance_series(e: &[[DVec3; 5]], a: usize, b: usize, height: f64) -> Vec<f64> {
    e.iter().map(|p| (p[a] - p[b]).length() / height).collect()
}

pub fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    sxy / (sxx * syy).sqrt()
}

pub fn std_dev(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    (x.iter().map(|a| (a - m) * (a - m)).sum::<f64>() / n).sqrt()
}

/// Body height of a pose set: mean over frames of head height above the lowest foot, along `up`.
pub fn body_height(e: &[[DVec3; 5]], up: DVec3) -> f64 {
    e.iter().map(|p| up.dot(p[0]) - up.dot(p[3]).min(up.dot(p[4]))).sum::<f64>() / e.len() as f64
}

/// The same clip in another world: every position turned by `q` and scaled by `s` (offsets, End
/// Sites, position channels), every local rotation conjugated by `q` (so global rotations become
/// `q · G · q⁻¹` and the zero-rotation rest pose turns with the world). Channel layout unchanged.
pub fn transform_world(bvh: &Bvh, q: glam::DQuat, s: f64) -> Bvh {
    use motion_stylizer::bvh::Channel;
    use motion_stylizer::skeleton::rotation::decompose;
    let mut out = bvh.clone();
    for j in &mut out.joints {
        j.offset = s * (q * j.offset);
        j.end_site = j.end_site.map(|e| s * (q * e));
    }
    let n = bvh.num_channels();
    for f in 0..bvh.frames {
        for (u, j) in bvh.joints.iter().enumerate() {
            let (t, r) = bvh.local_transform(f, u);
            let (t, r) = (s * (q * t), q * r * q.inverse());
            let axes: Vec<_> =
                j.channels.iter().filter_map(|c| if let Channel::Rotation(a) = c { Some(*a) } else { None }).collect();
            let mut angles = decompose(r, &axes).into_iter();
            for (k, c) in j.channels.iter().enumerate() {
                out.values[f * n + j.channel_offset + k] = match c {
                    Channel::Position(a) => t[a.index()],
                    Channel::Rotation(_) => angles.next().unwrap(),
                };
            }
        }
    }
    out
}

/// `bvh` without the joints for which `drop` is true and their descendants.
pub fn drop_joints(bvh: &Bvh, drop: impl Fn(&str) -> bool) -> Bvh {
    let n = bvh.num_channels();
    let mut keep = vec![false; bvh.joints.len()];
    let mut new_index = vec![usize::MAX; bvh.joints.len()];
    let mut joints = Vec::new();
    let mut channel_offset = 0;
    for (u, j) in bvh.joints.iter().enumerate() {
        keep[u] = !drop(&j.name) && j.parent.is_none_or(|p| keep[p]);
        if keep[u] {
            new_index[u] = joints.len();
            let mut nj = j.clone();
            nj.parent = j.parent.map(|p| new_index[p]);
            nj.channel_offset = channel_offset;
            channel_offset += j.channels.len();
            joints.push(nj);
        }
    }
    let mut values = Vec::new();
    for f in 0..bvh.frames {
        for (u, j) in bvh.joints.iter().enumerate() {
            if keep[u] {
                values.extend_from_slice(
                    &bvh.values[f * n + j.channel_offset..f * n + j.channel_offset + j.channels.len()],
                );
            }
        }
    }
    Bvh { joints, frame_time: bvh.frame_time, frames: bvh.frames, values }
}

/// `bvh` with joints renamed by `f` (names it returns `None` for are kept).
pub fn rename(bvh: &Bvh, f: impl Fn(&str) -> Option<String>) -> Bvh {
    let mut out = bvh.clone();
    for j in &mut out.joints {
        if let Some(n) = f(&j.name) {
            j.name = n;
        }
    }
    out
}

/// Largest distance between the canonical joint positions of two motions (same frame count).
pub fn max_position_error(a: &Motion, b: &Motion) -> f64 {
    assert_eq!(a.frames(), b.frames());
    let mut e = 0.0f64;
    for (x, y) in a.global_positions().iter().zip(b.global_positions()) {
        for j in 0..x.len() {
            e = e.max((x[j] - y[j]).length());
        }
    }
    e
}

/// Pearson correlations of the 10 normalised effector-distance series (imported vs source), with the
/// source series' standard deviation (in body heights).
pub fn effector_correlations(bvh: &Bvh, rig: &UserRig, m: &Motion) -> Vec<(String, f64, f64)> {
    let src = source_effectors(bvh, rig, m.frames());
    let can = canonical_effectors(m);
    let (hs, hc) = (body_height(&src, rig.up()), body_height(&can, DVec3::Y));
    pairs()
        .into_iter()
        .map(|(a, b)| {
            let x = distance_series(&src, a, b, hs);
            let y = distance_series(&can, a, b, hc);
            (format!("{}-{}", EFFECTOR_NAMES[a], EFFECTOR_NAMES[b]), pearson(&x, &y), std_dev(&x))
        })
        .collect()
}

/// `bvh` with each joint's channels replaced by `channels(joint)`; values recomputed from the local
/// transforms (exact when three rotation channels remain and positions are kept where they moved).
pub fn relayout(
    bvh: &Bvh,
    channels: impl Fn(&motion_stylizer::bvh::BvhJoint) -> Vec<motion_stylizer::bvh::Channel>,
) -> Bvh {
    use motion_stylizer::bvh::Channel;
    use motion_stylizer::skeleton::rotation::decompose;
    let mut out = bvh.clone();
    let mut off = 0;
    for j in &mut out.joints {
        j.channels = channels(j);
        j.channel_offset = off;
        off += j.channels.len();
    }
    out.values = Vec::with_capacity(off * bvh.frames);
    for f in 0..bvh.frames {
        for (u, j) in out.joints.iter().enumerate() {
            let (t, r) = bvh.local_transform(f, u);
            let axes: Vec<_> =
                j.channels.iter().filter_map(|c| if let Channel::Rotation(a) = c { Some(*a) } else { None }).collect();
            let mut angles = decompose(r, &axes).into_iter();
            for c in &j.channels {
                out.values.push(match c {
                    Channel::Position(a) => t[a.index()],
                    Channel::Rotation(_) => angles.next().unwrap(),
                });
            }
        }
    }
    out
}
