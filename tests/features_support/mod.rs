//! Shared helpers of the `features_*` tests: a synthetic walking motion and error measures.
#![allow(dead_code)]

use glam::{DQuat, DVec3, EulerRot};
use motion_stylizer::Motion;
use motion_stylizer::features::{self, Placement};
use motion_stylizer::skeleton::canonical::{NUM_JOINTS, joint::*};

/// A walk-like motion: the Hips follow a curve (straight, then turning left, then right), placed at
/// `start` with initial heading `heading`, bobbing; the body turns with the path and sways; legs, knees
/// and arms oscillate at the gait frequency; the spine and head wobble.
pub fn synthetic_walk(frames: usize, start: DVec3, heading: f64) -> Motion {
    let mut root = Vec::with_capacity(frames);
    let mut rotations = Vec::with_capacity(frames);
    let (mut x, mut z, mut yaw) = (start.x, start.z, heading);
    for f in 0..frames {
        let t = f as f64 / 30.0;
        let phase = std::f64::consts::TAU * t; // one gait cycle per second
        let turn_rate = if t < 1.5 {
            0.0
        } else if t < 3.5 {
            0.6
        } else {
            -0.9
        }; // rad/s
        root.push(DVec3::new(x, start.y + 2.0 * (2.0 * phase).sin(), z));
        let sway = 0.12 * phase.sin();
        let mut pose = [DQuat::IDENTITY; NUM_JOINTS];
        pose[HIPS] = DQuat::from_rotation_y(yaw + sway) * DQuat::from_rotation_x(0.05 + 0.03 * (2.0 * phase).cos());
        pose[SPINE] = DQuat::from_euler(EulerRot::YXZ, -0.6 * sway, 0.04, 0.02 * phase.cos());
        pose[CHEST] = DQuat::from_euler(EulerRot::YXZ, -0.5 * sway, 0.03, 0.0);
        pose[NECK] = DQuat::from_rotation_x(0.1 * (0.7 * phase).sin());
        pose[HEAD] = DQuat::from_euler(EulerRot::YXZ, 0.2 * (0.3 * phase).sin(), -0.05, 0.0);
        for (side, s) in [(0usize, 1.0f64), (1, -1.0)] {
            let p = phase + side as f64 * std::f64::consts::PI;
            let (hip, knee, ankle, toe) = if side == 0 {
                (UPPER_LEG_L, LOWER_LEG_L, FOOT_L, TOES_L)
            } else {
                (UPPER_LEG_R, LOWER_LEG_R, FOOT_R, TOES_R)
            };
            pose[hip] = DQuat::from_euler(EulerRot::XYZ, -0.45 * p.sin(), 0.05 * s, 0.04 * s * p.cos());
            pose[knee] = DQuat::from_rotation_x(0.6 * (0.5 + 0.5 * (p + 1.0).sin()).powi(2));
            pose[ankle] = DQuat::from_rotation_x(-0.2 * (p - 0.5).sin());
            pose[toe] = DQuat::from_rotation_x(0.15 * (p + 2.0).sin().max(0.0));
            let (sh, ua, la, hand) = if side == 0 {
                (SHOULDER_L, UPPER_ARM_L, LOWER_ARM_L, HAND_L)
            } else {
                (SHOULDER_R, UPPER_ARM_R, LOWER_ARM_R, HAND_R)
            };
            pose[sh] = DQuat::from_rotation_z(0.05 * s);
            // Arms down from the T-pose, swinging against the legs.
            pose[ua] = DQuat::from_rotation_z(-1.3 * s) * DQuat::from_rotation_y(0.4 * s * p.sin());
            pose[la] = DQuat::from_rotation_y(-0.3 * s - 0.1 * s * p.cos());
            pose[hand] = DQuat::from_rotation_x(0.1 * p.sin());
        }
        rotations.push(pose);
        // Advance along the heading at ~1.2 m/s.
        let speed = 4.0 + 0.5 * (2.0 * phase).cos();
        x += speed * yaw.sin();
        z += speed * yaw.cos();
        yaw += turn_rate / 30.0;
    }
    Motion::new(root, rotations).expect("synthetic motion is valid")
}

/// Round-trip errors of `m` through extract → reconstruct, against `m` moved to the normalised frame:
/// (mean joint-position error over all joints and frames, max error, final Hips position error), cm.
pub fn round_trip_errors(m: &Motion) -> (f64, f64, f64) {
    let f = features::extract(m);
    let back = features::reconstruct(&f).expect("reconstruct");
    let aligned = Placement::of(m).to_canonical_motion(m).expect("align");
    position_errors(&aligned, &back)
}

/// (mean, max, final-Hips) position error between two motions of equal length, cm.
pub fn position_errors(a: &Motion, b: &Motion) -> (f64, f64, f64) {
    assert_eq!(a.frames(), b.frames());
    let (pa, pb) = (a.global_positions(), b.global_positions());
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (fa, fb) in pa.iter().zip(&pb) {
        for (x, y) in fa.iter().zip(fb) {
            let e = (*x - *y).length();
            sum += e;
            max = max.max(e);
        }
    }
    let n = (pa.len() * NUM_JOINTS) as f64;
    let last = pa.len() - 1;
    (sum / n, max, (pa[last][HIPS] - pb[last][HIPS]).length())
}

/// Largest absolute difference between two feature arrays, and where (frame, dim).
pub fn max_diff(a: &features::Features, b: &features::Features) -> (f32, usize, usize) {
    assert_eq!(a.frames(), b.frames());
    let mut best = (0.0f32, 0, 0);
    for (i, (x, y)) in a.data().iter().zip(b.data()).enumerate() {
        let d = (x - y).abs();
        if d > best.0 {
            best = (d, i / features::DIM, i % features::DIM);
        }
    }
    best
}
