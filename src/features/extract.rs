//! Motion → features.

use super::facing::{Placement, facing_yaws, rotate_y, wrap_angle};
use super::layout::{
    CONTACTS, DIM, Features, ROOT_ANG_VEL, ROOT_HEIGHT, ROOT_LIN_VEL, VELOCITIES, position_dim, rotation_dim,
    velocity_dim,
};
use super::rot6d::quat_to_6d;
use crate::Motion;
use crate::skeleton::canonical::{NUM_JOINTS, joint};
use glam::{DQuat, DVec3};

/// The joints whose contacts are dims [`CONTACTS`], in order.
pub const CONTACT_JOINTS: [usize; 4] = [joint::FOOT_L, joint::TOES_L, joint::FOOT_R, joint::TOES_R];

/// A foot joint is in contact when it moves less than this (cm per frame, 3-D, = 60 cm/s) ...
///
/// Bandai walks at 30 fps: planted feet move 0.0-0.5 cm/frame, a swinging foot 5-14; running
/// contacts stay under 1.5.
pub const CONTACT_SPEED: f64 = 2.0;

/// ... and is lower than this above the floor (cm), per joint of [`CONTACT_JOINTS`]: the joint's
/// height when standing flat (ankle 11.1, toe 3.5 with [`super::FLOOR_CLEARANCE`]) plus 6 cm.
pub const CONTACT_HEIGHT: [f64; 4] = [17.0, 9.5, 17.0, 9.5];

/// The 260-D features of `m` (see the [module documentation](super) for their meaning).
///
/// Never fails: a [`Motion`] is finite. Only absurd coordinates (beyond f32's range, ~3.4e38 cm)
/// would give infinite features, which [`super::reconstruct`] and [`super::NormStats`] refuse.
pub fn extract(m: &Motion) -> Features {
    extract_placed(m).0
}

/// [`extract`], also returning where the clip sat in the world (floor, start, initial facing), so that
/// a clip rebuilt from these features can be put back there with [`Placement::from_canonical_motion`].
pub fn extract_placed(m: &Motion) -> (Features, Placement) {
    let positions = m.global_positions();
    let yaws = facing_yaws(&positions);
    let placement = Placement::from_parts(&positions, &yaws);
    let floor = placement.floor;
    let n = m.frames();
    let mut f = Features::zeros(n);
    let rotations = m.rotations();
    for t in 0..n {
        let (s, c) = yaws[t].sin_cos();
        let local = |v: DVec3| rotate_y(-s, c, v);
        let p = &positions[t];
        let root = p[joint::HIPS];
        let row = f.frame_mut(t);
        row[ROOT_HEIGHT.start] = (root.y - floor) as f32;
        for (j, pj) in p.iter().enumerate() {
            let rel = local(DVec3::new(pj.x - root.x, 0.0, pj.z - root.z));
            let d = position_dim(j);
            row[d] = rel.x as f32;
            row[d + 1] = (pj.y - floor) as f32;
            row[d + 2] = rel.z as f32;
        }
        let pose = &rotations[t];
        for (j, &q) in pose.iter().enumerate() {
            let q = if j == joint::HIPS { DQuat::from_rotation_y(-yaws[t]) * q } else { q };
            let d = rotation_dim(j);
            for (dst, v) in row[d..d + 6].iter_mut().zip(quat_to_6d(q)) {
                *dst = v as f32;
            }
        }
        if t + 1 < n {
            let next = &positions[t + 1];
            row[ROOT_ANG_VEL.start] = wrap_angle(yaws[t + 1] - yaws[t]) as f32;
            let v = local(next[joint::HIPS] - root);
            row[ROOT_LIN_VEL.start] = v.x as f32;
            row[ROOT_LIN_VEL.start + 1] = v.z as f32;
            for j in 0..NUM_JOINTS {
                let v = local(next[j] - p[j]);
                let d = velocity_dim(j);
                row[d] = v.x as f32;
                row[d + 1] = v.y as f32;
                row[d + 2] = v.z as f32;
            }
        }
    }
    // The last frame has no successor: it repeats the previous frame's velocities.
    if n >= 2 {
        let data = f.data_mut();
        let (prev, last) = data[(n - 2) * DIM..].split_at_mut(DIM);
        last[ROOT_ANG_VEL.start..ROOT_HEIGHT.start].copy_from_slice(&prev[ROOT_ANG_VEL.start..ROOT_HEIGHT.start]);
        last[VELOCITIES].copy_from_slice(&prev[VELOCITIES]);
    }
    for row in f.data_mut().chunks_exact_mut(DIM) {
        for (k, &j) in CONTACT_JOINTS.iter().enumerate() {
            let v = velocity_dim(j);
            let speed2 = row[v..v + 3].iter().map(|&x| (x as f64) * (x as f64)).sum::<f64>();
            let height = row[position_dim(j) + 1] as f64;
            let contact = speed2 < CONTACT_SPEED * CONTACT_SPEED && height < CONTACT_HEIGHT[k];
            row[CONTACTS.start + k] = if contact { 1.0 } else { 0.0 };
        }
    }
    (f, placement)
}
