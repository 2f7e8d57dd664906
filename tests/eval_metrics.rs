//! The evaluation's metrics on constructed inputs with known answers.
#![cfg(feature = "model")]

use glam::{DQuat, DVec3};
use motion_stylizer::Motion;
use motion_stylizer::eval::metrics::{fid, foot_skate, geodesic, mean_ci, position_distance};
use motion_stylizer::skeleton::canonical::NUM_JOINTS;
use motion_stylizer::stylize::feet::pin_feet;

/// A T-pose whose root moves `step` cm along +X per frame, feet on the floor.
fn gliding(frames: usize, step: f64) -> Motion {
    let root = (0..frames).map(|t| DVec3::new(step * t as f64, 90.0, 0.0)).collect();
    Motion::new(root, vec![[DQuat::IDENTITY; NUM_JOINTS]; frames]).unwrap()
}

#[test]
fn geodesic_is_zero_to_itself_and_the_angle_of_a_uniform_rotation() {
    let a = gliding(5, 1.0);
    assert_eq!(geodesic(&a, &a), Some(0.0));
    let turned = Motion::new(a.root_positions().to_vec(), vec![[DQuat::from_rotation_y(0.5); NUM_JOINTS]; 5]).unwrap();
    let g = geodesic(&a, &turned).unwrap();
    assert!((g - 0.5).abs() < 1e-9, "{g}");
}

#[test]
fn foot_skate_is_the_sliding_speed_and_zero_once_the_feet_are_pinned() {
    // 2 cm per frame at 30 fps with every foot joint at its lowest height: 60 cm/s.
    let m = gliding(20, 2.0);
    let skate = foot_skate([&m]).unwrap();
    assert!((skate - 60.0).abs() < 1e-9, "{skate}");
    let pinned = pin_feet(&m, &vec![[true; 4]; 20]).unwrap();
    assert!(foot_skate([&pinned]).unwrap() < 1e-9);
    // Pinning moved the root, not the pose.
    assert_eq!(pinned.rotations(), m.rotations());
    assert!((position_distance(&m, &pinned).unwrap() - 19.0).abs() < 1e-9, "mean shift 0, 2, ..., 38 cm");
}

#[test]
fn fid_is_zero_for_equal_sets_and_the_squared_mean_shift_for_shifted_ones() {
    let a: Vec<Vec<f32>> = (0..40).map(|i| vec![(i % 7) as f32, (i % 5) as f32 * 0.5, (i % 3) as f32]).collect();
    assert!(fid(&a, &a).unwrap() < 1e-6);
    let b: Vec<Vec<f32>> = a.iter().map(|v| vec![v[0] + 3.0, v[1], v[2] - 4.0]).collect();
    let d = fid(&a, &b).unwrap();
    assert!((d - 25.0).abs() < 1e-6, "{d}");
    // Doubling the spread of a set adds trace terms: (2σ − σ)² per dimension.
    let c: Vec<Vec<f32>> = (0..40).map(|i| vec![if i % 2 == 0 { 1.0 } else { -1.0 }; 1]).collect();
    let c2: Vec<Vec<f32>> = c.iter().map(|v| vec![v[0] * 2.0]).collect();
    let var = 40.0 / 39.0;
    assert!((fid(&c, &c2).unwrap() - var).abs() < 1e-6);
    assert_eq!(fid(&a[..1], &a), None, "a single vector has no covariance");
}

#[test]
fn confidence_interval_is_the_normal_approximation() {
    assert_eq!(mean_ci(&[]), None);
    assert_eq!(mean_ci(&[0.5]), Some((0.5, None)));
    let (m, ci) = mean_ci(&[1.0, 2.0, 3.0, 4.0]).unwrap();
    assert_eq!(m, 2.5);
    let sd = (5.0f64 / 3.0).sqrt();
    assert!((ci.unwrap() - 1.96 * sd / 2.0).abs() < 1e-12);
}
