//! The 260-D features on synthetic motions: round trip, invariances, mirroring, views, normalisation,
//! robustness to bad input.

mod features_support;

use features_support::{max_diff, position_errors, round_trip_errors, synthetic_walk};
use glam::{DQuat, DVec3};
use motion_stylizer::Motion;
use motion_stylizer::features::{self, *};
use motion_stylizer::skeleton::canonical::NUM_JOINTS;

fn walk() -> Motion {
    synthetic_walk(180, DVec3::new(130.0, 95.0, -40.0), 2.3)
}

#[test]
fn round_trip_is_within_a_millimetre() {
    let m = walk();
    let (mean, max, drift) = round_trip_errors(&m);
    println!(
        "synthetic walk, 180 frames: mean {:.6} mm, max {:.6} mm, final Hips drift {:.6} mm",
        mean * 10.0,
        max * 10.0,
        drift * 10.0
    );
    assert!(mean < 0.1, "mean error {mean} cm");
    assert!(max < 0.1 && drift < 0.1);
}

#[test]
fn features_of_the_rebuilt_motion_are_the_same_features() {
    let f = extract(&walk());
    let again = extract(&reconstruct(&f).unwrap());
    let (d, frame, dim) = max_diff(&f, &again);
    assert!(d < 1e-3, "differ by {d} at frame {frame} dim {dim}");
}

#[test]
fn feature_shape_and_layout() {
    let m = walk();
    let f = extract(&m);
    assert_eq!(f.frames(), m.frames());
    assert_eq!(f.data().len(), m.frames() * DIM);
    assert_eq!(GROUPS.iter().map(|g| g.len()).sum::<usize>(), DIM);
    for row in f.rows() {
        // Hips' own root-relative position is (0, height, 0).
        let h = position_dim(0);
        assert_eq!((row[h], row[h + 2]), (0.0, 0.0));
        assert!((row[h + 1] - row[ROOT_HEIGHT.start]).abs() < 1e-4);
        assert!(row[CONTACTS].iter().all(|&c| c == 0.0 || c == 1.0));
    }
    // Last frame repeats the previous frame's velocities.
    let n = f.frames();
    assert_eq!(f.frame(n - 1)[0..3], f.frame(n - 2)[0..3]);
    assert_eq!(f.frame(n - 1)[VELOCITIES], f.frame(n - 2)[VELOCITIES]);
    // The walk goes forward: the root's velocity in its own facing frame is mostly +Z.
    let fwd: f32 = f.rows().map(|r| r[ROOT_LIN_VEL.start + 1]).sum::<f32>() / n as f32;
    let side: f32 = f.rows().map(|r| r[ROOT_LIN_VEL.start].abs()).sum::<f32>() / n as f32;
    assert!(fwd > 3.0 && side < 1.0, "forward {fwd}, sideways {side}");
}

#[test]
fn features_do_not_depend_on_where_the_clip_is_or_which_way_it_faces() {
    let a = extract(&synthetic_walk(120, DVec3::new(0.0, 95.0, 0.0), 0.0));
    let b = extract(&synthetic_walk(120, DVec3::new(-500.0, 60.0, 321.0), -2.9));
    let (d, frame, dim) = max_diff(&a, &b);
    println!("invariance: max diff {d} (frame {frame}, dim {dim})");
    assert!(d < 1e-4, "differ by {d} at frame {frame} dim {dim}");
}

#[test]
fn placement_maps_back_to_the_world() {
    let m = walk();
    let (f, placement) = extract_placed(&m);
    let back = reconstruct(&f).unwrap();
    let world = placement.from_canonical_motion(&back).unwrap();
    let (mean, _, drift) = position_errors(&m, &world);
    assert!(mean < 1e-2 && drift < 1e-2, "{mean} {drift}");
    // First frame: Hips above the origin, facing +Z, lowest joint at FLOOR_CLEARANCE.
    let lowest = back.global_positions().iter().flatten().fold(f64::INFINITY, |a, p| a.min(p.y));
    assert!((lowest - FLOOR_CLEARANCE).abs() < 1e-4);
    let r0 = back.root_positions()[0];
    assert!(r0.x.abs() < 1e-9 && r0.z.abs() < 1e-9);
    // Seen again, the rebuilt clip sits at the normalised start: floor 0, origin, facing +Z.
    let again = Placement::of(&back);
    assert!(again.floor.abs() < 1e-4 && again.origin_x.abs() < 1e-9 && again.origin_z.abs() < 1e-9);
    assert!(again.yaw.abs() < 1e-5, "yaw {}", again.yaw);
    let p = DVec3::new(3.0, -2.0, 7.0);
    assert!((placement.to_canonical(placement.from_canonical(p)) - p).length() < 1e-9);
}

#[test]
fn reconstruct_positions_agrees_with_reconstruct() {
    let m = walk();
    let f = extract(&m);
    let from_rot = reconstruct(&f).unwrap().global_positions();
    let from_pos = reconstruct_positions(&f).unwrap();
    let mut worst = 0.0f64;
    for (a, b) in from_rot.iter().zip(&from_pos) {
        for (x, y) in a.iter().zip(b) {
            worst = worst.max((*x - *y).length());
        }
    }
    assert!(worst < 1e-3, "worst {worst} cm");
}

#[test]
fn mirror_on_features_equals_features_of_the_mirrored_motion() {
    let m = walk();
    let direct = mirror(&extract(&m));
    let via_motion = extract(&m.mirrored());
    let (d, frame, dim) = max_diff(&direct, &via_motion);
    println!("mirror: max diff {d} (frame {frame}, dim {dim})");
    assert!(d < 1e-4, "differ by {d} at frame {frame} dim {dim}");
    assert_eq!(mirror(&direct), extract(&m));
}

#[test]
fn single_frame_motion() {
    let m = walk().slice(10, 11);
    let f = extract(&m);
    assert_eq!(f.frames(), 1);
    assert!(f.frame(0)[0..3].iter().chain(&f.frame(0)[VELOCITIES]).all(|&v| v == 0.0));
    let (mean, _, _) = round_trip_errors(&m);
    assert!(mean < 1e-3);
}

#[test]
fn views_for_the_models() {
    let f = extract(&walk());
    let n = f.frames();
    assert_eq!(View::Model.width(), MODEL_DIM);
    assert_eq!(View::Regressor.width(), REGRESSOR_DIM);
    let model = f.view(View::Model);
    assert_eq!(model.len(), n * 256);
    assert_eq!(&model[256..512], &f.frame(1)[..256]);
    let reg = f.view(View::Regressor);
    assert_eq!(reg.len(), n * 254);
    let row = &reg[254 * 5..254 * 6];
    assert_eq!(row[0], f.frame(5)[0]);
    assert_eq!(&row[1..], &f.frame(5)[3..256]);
    let cf = f.view_channels_first(View::Regressor);
    assert_eq!(cf[n * 1 + 5], f.frame(5)[3]);
    assert_eq!(cf[n * 253 + 7], f.frame(7)[255]);
    // Writing a view back; missing dims of from_view are zero.
    let g = Features::from_view(View::Regressor, n, &reg).unwrap();
    assert_eq!(g.view(View::Regressor), reg);
    assert!(g.rows().all(|r| r[1] == 0.0 && r[2] == 0.0 && r[256..].iter().all(|&c| c == 0.0)));
    let mut h = g.clone();
    h.set_root_linear_velocity(&f.rows().flat_map(|r| [r[1], r[2]]).collect::<Vec<_>>()).unwrap();
    assert_eq!(h.view(View::Model), model);
    assert!(matches!(Features::from_view(View::Model, n, &reg), Err(FeatureError::BadLength { .. })));
}

#[test]
fn six_d_input_need_not_be_orthonormal() {
    let m = walk();
    let f = extract(&m);
    let clean = reconstruct(&f).unwrap();
    // Scale the columns and add a little of one to the other: same rotations after Gram-Schmidt.
    let mut g = f.clone();
    for t in 0..g.frames() {
        let row = g.frame_mut(t);
        for j in 0..NUM_JOINTS {
            let d = rotation_dim(j);
            for k in 0..3 {
                let c0 = row[d + k];
                row[d + k] = 3.0 * c0;
                row[d + 3 + k] = 0.5 * row[d + 3 + k] + 0.2 * c0;
            }
        }
    }
    let skewed = reconstruct(&g).unwrap();
    let (mean, max, _) = position_errors(&clean, &skewed);
    assert!(mean < 1e-3 && max < 1e-2, "{mean} {max}");
    // Noise (as from a network) still gives a valid motion close to the clean one.
    let mut noisy = f.clone();
    for (i, v) in noisy.data_mut()[..].iter_mut().enumerate() {
        *v += 0.01 * (((i * 7919) % 1000) as f32 / 500.0 - 1.0);
    }
    let noisy = reconstruct(&noisy).unwrap();
    for pose in noisy.rotations() {
        assert!(pose.iter().all(|q| q.is_finite() && (q.length() - 1.0).abs() < 1e-9));
    }
    // Degenerate 6D (zeros) and huge finite values: still a motion, no panic.
    let mut zero = f.clone();
    zero.data_mut()[ROTATIONS].iter_mut().for_each(|v| *v = 0.0);
    assert!(reconstruct(&zero).is_ok());
    let mut huge = f.clone();
    huge.data_mut().iter_mut().enumerate().for_each(|(i, v)| *v = if i % 3 == 0 { f32::MAX } else { -f32::MAX });
    let _ = reconstruct(&huge); // Ok or Err, never a panic
    let _ = reconstruct_positions(&huge);
    // quat_from_6d on its own.
    let q = quat_from_6d([0.0, 2.0, 0.0, -1.0, 0.0, 0.0]); // x → +Y, y → −X: 90° about Z
    assert!(q.dot(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2)).abs() > 1.0 - 1e-12);
}

#[test]
fn bad_input_is_an_error() {
    assert!(matches!(Features::new(2, vec![0.0; 2 * DIM - 1]), Err(FeatureError::BadLength { .. })));
    assert!(matches!(Features::new(0, vec![]), Err(FeatureError::Empty)));
    assert!(matches!(Features::from_rows(vec![0.0; 3 * 256]), Err(FeatureError::BadLength { .. })));
    assert!(matches!(Features::from_rows(vec![]), Err(FeatureError::Empty)));
    let f = extract(&walk());
    for (t, d, v) in [(0, 0, f32::NAN), (17, ROTATIONS.start + 5, f32::INFINITY), (179, 2, f32::NEG_INFINITY)] {
        let mut g = f.clone();
        g.frame_mut(t)[d] = v;
        assert_eq!(reconstruct(&g), Err(FeatureError::NonFinite { frame: t, dim: d }));
        assert_eq!(reconstruct_positions(&g), Err(FeatureError::NonFinite { frame: t, dim: d }));
        assert!(matches!(NormStats::compute([&g]), Err(FeatureError::NonFinite { .. })));
    }
    // Features of all zeros: a valid (if odd) motion.
    assert!(reconstruct(&Features::new(3, vec![0.0; 3 * DIM]).unwrap()).is_ok());
}

#[test]
fn normalisation() {
    let a = extract(&walk());
    let b = extract(&synthetic_walk(75, DVec3::new(0.0, 80.0, 0.0), 1.0));
    let stats = NormStats::compute([&a, &b]).unwrap();
    assert_eq!((stats.mean().len(), stats.std().len()), (DIM, DIM));
    // Means are exact per-dim means over all frames.
    let n = (a.frames() + b.frames()) as f64;
    let mean3 = a.rows().chain(b.rows()).map(|r| r[3] as f64).sum::<f64>() / n;
    assert!((stats.mean()[3] as f64 - mean3).abs() < 1e-4);
    // One std per group, floored.
    for g in GROUPS {
        assert!(stats.std()[g.clone()].iter().all(|&s| s == stats.std()[g.start] && s >= STD_FLOOR));
    }
    // Streaming equals all at once.
    let mut acc = NormAccumulator::new();
    acc.push(&a.slice(0, 50)).unwrap();
    acc.push(&a.slice(50, 180)).unwrap();
    acc.push(&b).unwrap();
    assert_eq!(acc.count(), n as u64);
    let streamed = acc.finish().unwrap();
    for (x, y) in streamed.mean().iter().zip(stats.mean()).chain(streamed.std().iter().zip(stats.std())) {
        assert!((x - y).abs() <= 1e-5 * (1.0 + y.abs()), "{x} vs {y}");
    }
    // normalize → denormalize is the identity; normalised data has ~zero mean.
    let mut g = a.clone();
    stats.normalize(&mut g);
    assert_ne!(g, a);
    stats.denormalize(&mut g);
    let (d, _, _) = max_diff(&g, &a);
    assert!(d < 1e-3, "{d}");
    // The view versions agree with the full one.
    let mut v = a.view(View::Regressor);
    stats.normalize_view(View::Regressor, &mut v).unwrap();
    let mut full = a.clone();
    stats.normalize(&mut full);
    assert_eq!(v, full.view(View::Regressor));
    stats.denormalize_view(View::Regressor, &mut v).unwrap();
    assert!(v.iter().zip(a.view(View::Regressor)).all(|(x, y)| (x - y).abs() < 1e-3));
    assert!(stats.normalize_view(View::Model, &mut [0.0; 255]).is_err());
    // serde round trip, and validation on the way in.
    let json = serde_json::to_string(&stats).unwrap();
    let back: NormStats = serde_json::from_str(&json).unwrap();
    assert_eq!(back, stats);
    assert!(serde_json::from_str::<NormStats>(r#"{"mean":[0.0],"std":[1.0]}"#).is_err());
    let zero_std = serde_json::to_string(&serde_json::json!({"mean": vec![0.0; DIM], "std": vec![0.0; DIM]})).unwrap();
    assert!(serde_json::from_str::<NormStats>(&zero_std).is_err());
    assert_eq!(NormStats::compute([]), Err(FeatureError::Empty));
    // A constant clip: every group hits the floor, and normalising stays finite.
    let still = extract(&walk().slice(0, 1));
    let s = NormStats::compute([&still, &still]).unwrap();
    assert!(s.std().iter().all(|&x| x == STD_FLOOR));
    let mut t = still.clone();
    s.normalize(&mut t);
    assert!(t.first_non_finite().is_none());
}

#[test]
fn extraction_speed() {
    let m = synthetic_walk(3000, DVec3::new(0.0, 95.0, 0.0), 0.0);
    let start = std::time::Instant::now();
    let f = features::extract(&m);
    let t_extract = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    let back = reconstruct(&f).unwrap();
    let t_back = start.elapsed().as_secs_f64();
    println!(
        "3000 frames: extract {:.0} frames/s, reconstruct {:.0} frames/s (this build's profile)",
        3000.0 / t_extract,
        3000.0 / t_back
    );
    assert_eq!(back.frames(), 3000);
}

#[test]
fn no_facing_direction_falls_back_to_the_previous_one() {
    // From frame 40 on the body lies on its side (left-right axis vertical): the across vector
    // vanishes on the ground and the last valid facing is kept.
    let m = walk();
    let mut rotations = m.rotations().to_vec();
    for pose in rotations.iter_mut().skip(40) {
        *pose = [DQuat::IDENTITY; NUM_JOINTS];
        pose[0] = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    }
    let m = Motion::new(m.root_positions().to_vec(), rotations).unwrap();
    let f = extract(&m);
    assert!(f.first_non_finite().is_none());
    // (Past the smoothing kernel's reach of the last upright frame.)
    assert!(f.rows().skip(40 + 4 * FACING_SIGMA as usize + 1).all(|r| r[ROOT_ANG_VEL.start] == 0.0));
    let (mean, _, _) = round_trip_errors(&m);
    assert!(mean < 1e-2, "{mean}");
    // Lying from the first frame: yaw 0 throughout.
    let still = m.slice(50, 90);
    assert_eq!(Placement::of(&still).yaw, 0.0);
    assert!(round_trip_errors(&still).0 < 1e-2);
}
