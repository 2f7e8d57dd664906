//! The 6D rotation representation: the first two columns of the rotation matrix, `[c0.x, c0.y, c0.z,
//! c1.x, c1.y, c1.z]` (Zhou et al. 2019), and its inverse by Gram-Schmidt.

use glam::{DMat3, DQuat, DVec3};

/// The 6D representation of a unit quaternion.
pub fn quat_to_6d(q: DQuat) -> [f64; 6] {
    let (x, y, z, w) = (q.x, q.y, q.z, q.w);
    [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
        2.0 * (x * y - w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z + w * x),
    ]
}

/// The rotation nearest in spirit to a 6D value that may not be orthonormal (a network's output):
/// Gram-Schmidt on the two columns, third column their cross product. Degenerate input (a zero
/// first column, or columns parallel) falls back to a valid rotation; any finite input gives a unit
/// quaternion, and nothing panics. Computed in f64, so squares of any finite f32 cannot overflow.
pub fn quat_from_6d(v: [f64; 6]) -> DQuat {
    let a = DVec3::new(v[0], v[1], v[2]);
    let b = DVec3::new(v[3], v[4], v[5]);
    // Scale each column to ~1 first, so that huge finite inputs cannot overflow.
    let x = normalize_or(a, DVec3::X);
    let b = normalize_or(b, DVec3::Y);
    let mut y = b - x * x.dot(b);
    if y.length_squared().is_nan() || y.length_squared() <= 1e-12 {
        // Parallel columns: any axis perpendicular to x.
        y = x.any_orthonormal_vector();
    }
    let y = normalize_or(y, x.any_orthonormal_vector());
    let z = x.cross(y);
    let q = DQuat::from_mat3(&DMat3::from_cols(x, y, z));
    let n = q.length();
    if n.is_finite() && n > 0.5 { q / n } else { DQuat::IDENTITY }
}

fn normalize_or(v: DVec3, fallback: DVec3) -> DVec3 {
    let m = v.abs().max_element();
    if !m.is_finite() || m <= 1e-300 {
        return fallback;
    }
    let u = v / m;
    let len = u.length();
    if len > 0.0 { u / len } else { fallback }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::EulerRot;

    #[test]
    fn round_trip_and_columns() {
        for i in 0..50 {
            let q = DQuat::from_euler(EulerRot::YXZ, 0.37 * i as f64, -0.21 * i as f64 + 0.3, 0.11 * i as f64 - 2.0);
            let v = quat_to_6d(q);
            let m = DMat3::from_quat(q);
            assert!((DVec3::new(v[0], v[1], v[2]) - m.x_axis).length() < 1e-12);
            assert!((DVec3::new(v[3], v[4], v[5]) - m.y_axis).length() < 1e-12);
            let back = quat_from_6d(v);
            assert!(back.dot(q).abs() > 1.0 - 1e-12);
        }
    }

    #[test]
    fn degenerate_input_gives_a_rotation() {
        for v in [
            [0.0; 6],
            [1.0, 0.0, 0.0, 2.0, 0.0, 0.0],
            [1e300, -1e300, 0.0, 1e-300, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, 5.0, 0.0],
        ] {
            let q = quat_from_6d(v);
            assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-9, "{v:?} -> {q:?}");
        }
    }
}
