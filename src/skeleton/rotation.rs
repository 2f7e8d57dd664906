//! Rotation helpers for retargeting: Euler angles in any BVH channel order, minimal (swing) and
//! two-vector alignments, axis snapping, shortest-path slerp. Everything `f64`, nothing panics.

use crate::bvh::Axis;
use glam::{DMat3, DQuat, DVec3};

/// Rotation about `axis` by `degrees`.
pub fn axis_rotation(axis: Axis, degrees: f64) -> DQuat {
    DQuat::from_axis_angle(axis.unit(), degrees.to_radians())
}

/// Composes rotation channels in file order (intrinsic, `R = R_a1 · R_a2 · …`), angles in degrees —
/// what [`crate::bvh::Bvh::local_transform`] does.
pub fn compose(axes: &[Axis], degrees: &[f64]) -> DQuat {
    axes.iter().zip(degrees).fold(DQuat::IDENTITY, |r, (a, d)| r * axis_rotation(*a, *d))
}

/// Signed angle (radians) that rotates `from` onto `to` about `axis`, both projected on the plane
/// orthogonal to `axis`; 0 when either projection vanishes.
fn angle_about(axis: DVec3, from: DVec3, to: DVec3) -> f64 {
    let f = from - axis * axis.dot(from);
    let t = to - axis * axis.dot(to);
    let (s, c) = (f.cross(t).dot(axis), f.dot(t));
    if s == 0.0 && c == 0.0 { 0.0 } else { s.atan2(c) }
}

/// Euler angles (degrees) of `q` for rotation channels about `axes`, in file order, such that
/// [`compose`]`(axes, angles) == q` (up to sign).
///
/// Exact for three channels about distinct axes (every BVH rotation order) and for one channel when
/// `q` is a rotation about that axis. Otherwise it is the closest such channels can get: one channel
/// keeps the twist of `q` about its axis; two channels keep the first two angles of the three-axis
/// decomposition completed with the missing axis last. No channels: empty.
pub fn decompose(q: DQuat, axes: &[Axis]) -> Vec<f64> {
    let q = if q.is_finite() && q.length_squared() > 0.0 { q.normalize() } else { DQuat::IDENTITY };
    match axes {
        [] => Vec::new(),
        [a] => {
            // Twist about `a`: the angle of the quaternion restricted to (w, a-component).
            let v = DVec3::new(q.x, q.y, q.z).dot(a.unit());
            vec![(2.0 * v.atan2(q.w)).to_degrees()].into_iter().map(wrap_degrees).collect()
        }
        [a, b] => {
            let c = [Axis::X, Axis::Y, Axis::Z].into_iter().find(|x| x != a && x != b).unwrap_or(Axis::Z);
            let t = tait_bryan(q, *a, *b, c);
            vec![t[0], t[1]]
        }
        [a, b, c, ..] => {
            let mut out = if a != b && b != c {
                if a == c { proper_euler(q, *a, *b).to_vec() } else { tait_bryan(q, *a, *b, *c).to_vec() }
            } else {
                // Not produced by the parser (a channel appears at most once); keep something sane.
                vec![0.0; 3]
            };
            out.resize(axes.len(), 0.0);
            out
        }
    }
}

fn wrap_degrees(d: f64) -> f64 {
    let w = (d + 180.0).rem_euclid(360.0) - 180.0;
    if w.is_finite() { w } else { 0.0 }
}

/// `q = R_i(θ1) · R_j(θ2) · R_k(θ3)` with i, j, k distinct; θ2 ∈ [-90°, 90°].
fn tait_bryan(q: DQuat, i: Axis, j: Axis, k: Axis) -> [f64; 3] {
    euler_generic(q, i, j, k, k.unit())
}

/// `q = R_i(θ1) · R_j(θ2) · R_i(θ3)` with i ≠ j; θ2 ∈ [0°, 180°].
fn proper_euler(q: DQuat, i: Axis, j: Axis) -> [f64; 3] {
    // For a small positive θ2, R_j(θ2)·e_i leans towards e_j × e_i.
    euler_generic(q, i, j, i, j.unit().cross(i.unit()))
}

/// Generic decomposition: `v = q·e_k = R_i(θ1)·R_j(θ2)·e_k` fixes θ1 as the angle about i from the
/// reference direction `lean` (where R_j(θ2)·e_k leans for small positive θ2, projected off i) to v;
/// θ2 and θ3 then follow from the residual rotations. Robust at gimbal lock (θ1 = 0 there).
fn euler_generic(q: DQuat, i: Axis, j: Axis, k: Axis, lean: DVec3) -> [f64; 3] {
    let (ei, ej, ek) = (i.unit(), j.unit(), k.unit());
    let v = q * ek;
    let mut t1 = angle_about(ei, lean, v);
    // Tait–Bryan: the projection of v off i is cos θ2 · R_i(θ1)·e_k, always "positive": fine.
    // Proper Euler: it is sin θ2 · R_i(θ1)·lean with sin θ2 ≥ 0: fine as well.
    if !t1.is_finite() {
        t1 = 0.0;
    }
    let r1 = DQuat::from_axis_angle(ei, -t1) * q; // = R_j(θ2) R_k(θ3)
    let w = r1 * ek; // = R_j(θ2) e_k
    let t2 = angle_about(ej, ek, w);
    let r2 = DQuat::from_axis_angle(ej, -t2) * r1; // = R_k(θ3)
    let probe = if i != k { ei } else { ej };
    let t3 = angle_about(ek, probe, r2 * probe);
    [wrap_degrees(t1.to_degrees()), wrap_degrees(t2.to_degrees()), wrap_degrees(t3.to_degrees())]
}

/// The minimal rotation taking direction `from` onto direction `to`; for opposite directions (where
/// the minimal rotation is not unique), a half turn about `hint` made orthogonal to `from`. `None` when
/// a vector is zero or not finite.
pub fn swing(from: DVec3, to: DVec3, hint: DVec3) -> Option<DQuat> {
    let (f, t) = (from.try_normalize()?, to.try_normalize()?);
    let d = f.dot(t).clamp(-1.0, 1.0);
    if d < -1.0 + 1e-12 {
        let axis = (hint - f * f.dot(hint)).try_normalize().unwrap_or_else(|| f.any_orthonormal_vector());
        return Some(DQuat::from_axis_angle(axis, std::f64::consts::PI));
    }
    let c = f.cross(t);
    let q = DQuat::from_xyzw(c.x, c.y, c.z, 1.0 + d);
    let len = q.length();
    (len > 0.0 && len.is_finite()).then(|| q / len)
}

/// The rotation taking `u` exactly onto the direction of `target_u`, and `a` into the half-plane
/// spanned by `target_u` and `target_a` on `target_a`'s side. `None` when a pair is (nearly) parallel
/// or a vector is zero.
pub fn align_two(u: DVec3, a: DVec3, target_u: DVec3, target_a: DVec3) -> Option<DQuat> {
    let from = frame(u, a)?;
    let to = frame(target_u, target_a)?;
    let q = DQuat::from_mat3(&(to * from.transpose()));
    q.is_finite().then(|| q.normalize())
}

/// Orthonormal frame whose first column is `u`, second the part of `a` orthogonal to `u`.
fn frame(u: DVec3, a: DVec3) -> Option<DMat3> {
    let e1 = u.try_normalize()?;
    let a_perp = a - e1 * e1.dot(a);
    if a_perp.length() < 1e-6 * a.length() {
        return None;
    }
    let e2 = a_perp.try_normalize()?;
    Some(DMat3::from_cols(e1, e2, e1.cross(e2)))
}

/// The signed coordinate axis nearest to `v` (ties: X before Y before Z).
pub fn nearest_axis(v: DVec3) -> DVec3 {
    let a = v.abs();
    if a.x >= a.y && a.x >= a.z {
        DVec3::X * v.x.signum()
    } else if a.y >= a.z {
        DVec3::Y * v.y.signum()
    } else {
        DVec3::Z * v.z.signum()
    }
}

/// The world basis change taking a user world, in which the character's up and left are `up` and
/// `left`, to the canonical one (left = +X, up = +Y, forward = +Z). Both directions are snapped to the
/// nearest coordinate axes first (worlds are axis-aligned; an unsnapped basis would tilt the floor by
/// the lean of the rest pose), so the result is a signed permutation. `None` when degenerate.
pub fn world_basis(up: DVec3, left: DVec3) -> Option<DQuat> {
    if !up.is_finite() || !left.is_finite() || up.length() == 0.0 {
        return None;
    }
    let up = nearest_axis(up);
    let left_perp = left - up * up.dot(left);
    if left_perp.length() < 1e-6 * left.length() || left_perp.length() == 0.0 {
        return None;
    }
    let left = nearest_axis(left_perp);
    let fwd = left.cross(up);
    // Rows are the user's left, up, forward: maps them onto X, Y, Z.
    let m = DMat3::from_cols(left, up, fwd).transpose();
    Some(DQuat::from_mat3(&m).normalize())
}

/// Shortest-path spherical interpolation, exact angles (glam's `slerp` approximates `acos`).
pub fn slerp(a: DQuat, b: DQuat, s: f64) -> DQuat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    if s == 0.0 {
        return a;
    }
    if s == 1.0 {
        return b;
    }
    // Half-angle between a and b, stable for small and large angles.
    let theta = 2.0 * (a - b).length().atan2((a + b).length());
    if theta < 1e-9 {
        return (a * (1.0 - s) + b * s).normalize();
    }
    let st = theta.sin();
    let q = a * (((1.0 - s) * theta).sin() / st) + b * ((s * theta).sin() / st);
    q.normalize()
}

/// Angle of a rotation, radians in [0, π].
pub fn angle(q: DQuat) -> f64 {
    2.0 * DVec3::new(q.x, q.y, q.z).length().atan2(q.w.abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{Bvh, BvhJoint, Channel};

    const AXES: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    fn orders() -> Vec<[Axis; 3]> {
        let mut v = Vec::new();
        for a in AXES {
            for b in AXES {
                for c in AXES {
                    if a != b && b != c {
                        v.push([a, b, c]);
                    }
                }
            }
        }
        v
    }

    fn close(a: DQuat, b: DQuat, tol: f64) -> bool {
        a.dot(b).abs() > 1.0 - tol
    }

    /// Deterministic pseudo-random numbers in [-1, 1).
    fn rng(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn euler_round_trips_all_twelve_orders_and_matches_bvh_kinematics() {
        let mut seed = 7;
        for order in orders() {
            for n in 0..300 {
                let angles: Vec<f64> = if n < 20 {
                    // Gimbal lock and friends.
                    let m = if order[0] == order[2] { [0.0, 180.0][n % 2] } else { [90.0, -90.0][n % 2] };
                    vec![rng(&mut seed) * 180.0, m + 1e-9 * (n / 2) as f64, rng(&mut seed) * 180.0]
                } else {
                    (0..3).map(|_| rng(&mut seed) * 400.0).collect()
                };
                let q = compose(&order, &angles);
                let back = decompose(q, &order);
                assert!(close(compose(&order, &back), q, 1e-13), "{order:?} {angles:?} -> {back:?}");
                // Against the BVH kinematics, channels written as in a file.
                let joint = BvhJoint {
                    name: "j".into(),
                    parent: None,
                    offset: DVec3::ZERO,
                    channels: order.iter().map(|a| Channel::Rotation(*a)).collect(),
                    end_site: None,
                    channel_offset: 0,
                };
                let bvh = Bvh { joints: vec![joint], frame_time: 1.0, frames: 1, values: back.clone() };
                assert!(close(bvh.local_transform(0, 0).1, q, 1e-13));
                // Middle angle range.
                if order[0] == order[2] {
                    assert!((-1e-9..=180.0 + 1e-9).contains(&back[1]) || back[1] + 180.0 < 1e-6, "{back:?}");
                } else {
                    assert!(back[1].abs() <= 90.0 + 1e-9, "{back:?}");
                }
            }
        }
    }

    #[test]
    fn fewer_channels_keep_what_they_can() {
        assert!(decompose(DQuat::IDENTITY, &[]).is_empty());
        let q = axis_rotation(Axis::Y, 33.0);
        assert!((decompose(q, &[Axis::Y])[0] - 33.0).abs() < 1e-12);
        let q2 = compose(&[Axis::Z, Axis::X], &[20.0, -70.0]);
        let d = decompose(q2, &[Axis::Z, Axis::X]);
        assert!((d[0] - 20.0).abs() < 1e-9 && (d[1] + 70.0).abs() < 1e-9, "{d:?}");
        // Non-finite input never escapes.
        assert_eq!(decompose(DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0), &AXES), vec![0.0; 3]);
    }

    #[test]
    fn swing_and_two_vector_alignment() {
        let q = swing(DVec3::new(1.0, 2.0, 3.0), DVec3::new(-2.0, 0.5, 1.0), DVec3::Y).unwrap();
        assert!((q * DVec3::new(1.0, 2.0, 3.0).normalize() - DVec3::new(-2.0, 0.5, 1.0).normalize()).length() < 1e-12);
        let h = swing(DVec3::X, -DVec3::X, DVec3::Y).unwrap();
        assert!((h * DVec3::X + DVec3::X).length() < 1e-12);
        assert!((h * DVec3::Y - DVec3::Y).length() < 1e-12, "half turn about the hint");
        assert!(swing(DVec3::ZERO, DVec3::X, DVec3::Y).is_none());

        let r = DQuat::from_euler(glam::EulerRot::YXZ, 0.3, -1.1, 2.0);
        let (u, a) = (DVec3::new(0.2, 1.0, 0.1), DVec3::new(1.0, 0.3, -0.2));
        let q = align_two(u, a, r * u, r * a).unwrap();
        assert!(close(q, r, 1e-13));
        assert!(align_two(u, 2.0 * u, DVec3::Y, DVec3::X).is_none());
    }

    #[test]
    fn world_basis_snaps_to_axes() {
        let id = world_basis(DVec3::new(0.05, 1.0, 0.1), DVec3::new(1.0, 0.0, 0.2)).unwrap();
        assert!(close(id, DQuat::IDENTITY, 1e-15));
        // Z up, facing -Y (left = +X): forward = X × Z = -Y.
        let zup = world_basis(DVec3::Z, DVec3::X).unwrap();
        assert!((zup * DVec3::Z - DVec3::Y).length() < 1e-12);
        assert!((zup * -DVec3::Y - DVec3::Z).length() < 1e-12);
        // Facing -Z: left = -X.
        let back = world_basis(DVec3::Y, -DVec3::X).unwrap();
        assert!((back * -DVec3::Z - DVec3::Z).length() < 1e-12);
        assert!(world_basis(DVec3::Y, DVec3::Y).is_none());
        assert!(world_basis(DVec3::ZERO, DVec3::X).is_none());
    }

    #[test]
    fn slerp_is_shortest_and_exact_at_ends() {
        let a = DQuat::from_axis_angle(DVec3::Y, 0.2);
        let b = -DQuat::from_axis_angle(DVec3::Y, 1.0);
        assert!(close(slerp(a, b, 0.5), DQuat::from_axis_angle(DVec3::Y, 0.6), 1e-15));
        assert_eq!(slerp(a, b, 0.0), a);
        assert!(close(slerp(a, b, 1.0), b, 1e-15));
        assert!((angle(DQuat::from_axis_angle(DVec3::X, 3.0)) - 3.0).abs() < 1e-12);
    }
}
