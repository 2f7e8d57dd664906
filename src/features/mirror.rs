//! Left/right mirroring on the features (data augmentation), without going back to a motion.

use super::layout::{
    CONTACTS, DIM, Features, ROOT_ANG_VEL, ROOT_HEIGHT, ROOT_LIN_VEL, position_dim, rotation_dim, velocity_dim,
};
use crate::skeleton::canonical::MIRROR;

/// The features of the mirrored motion: `mirror(&extract(m)) == extract(&m.mirrored())` up to float
/// rounding.
///
/// A reflection x → −x negates the yaw velocity and the x of every root-frame vector, swaps left and
/// right joints (and contacts), and turns each rotation matrix R into M·R·M with M = diag(−1, 1, 1):
/// column 0 becomes (r00, −r10, −r20), column 1 (−r01, r11, r21).
pub fn mirror(f: &Features) -> Features {
    let mut out = f.clone();
    for (src, dst) in f.rows().zip(out.data_mut().chunks_exact_mut(DIM)) {
        mirror_row(src, dst);
    }
    out
}

fn mirror_row(src: &[f32], dst: &mut [f32]) {
    dst[ROOT_ANG_VEL.start] = -src[ROOT_ANG_VEL.start];
    dst[ROOT_LIN_VEL.start] = -src[ROOT_LIN_VEL.start];
    dst[ROOT_LIN_VEL.start + 1] = src[ROOT_LIN_VEL.start + 1];
    dst[ROOT_HEIGHT.start] = src[ROOT_HEIGHT.start];
    for (j, &m) in MIRROR.iter().enumerate() {
        for base in [position_dim as fn(usize) -> usize, velocity_dim] {
            let (d, s) = (base(j), base(m));
            dst[d] = -src[s];
            dst[d + 1] = src[s + 1];
            dst[d + 2] = src[s + 2];
        }
        let (d, s) = (rotation_dim(j), rotation_dim(m));
        let sign = [1.0, -1.0, -1.0, -1.0, 1.0, 1.0];
        for k in 0..6 {
            dst[d + k] = sign[k] * src[s + k];
        }
    }
    // Foot_L, Toes_L, Foot_R, Toes_R.
    for k in 0..4 {
        dst[CONTACTS.start + k] = src[CONTACTS.start + (k + 2) % 4];
    }
}
