//! Arbitrary bytes into the BVH reader: it must return (never panic, hang or overflow the stack), and
//! whatever it accepts must survive our writer and read back identically.
#![no_main]

use libfuzzer_sys::fuzz_target;
use motion_stylizer::bvh::{Bvh, Limits};

fuzz_target!(|data: &[u8]| {
    // Default limits but for the frame count, so that `Frames: 999999` with `CHANNELS 0` stays quick.
    let limits = Limits { max_frames: 10_000, ..Limits::default() };
    let Ok(bvh) = Bvh::parse_bytes(data, &limits) else { return };
    assert!(bvh.frames >= 1 && bvh.frame_time > 0.0);
    assert_eq!(bvh.values.len(), bvh.frames * bvh.num_channels());
    assert!(bvh.values.iter().all(|v| v.is_finite()));

    let text = bvh.to_bvh_string();
    let again = match Bvh::parse(&text) {
        Ok(b) => b,
        Err(e) => panic!("our own output does not parse: {e}\n{text}"),
    };
    assert_eq!(again.joints.len(), bvh.joints.len());
    assert_eq!(again.frames, bvh.frames);
    assert_eq!(again.frame_time.to_bits(), bvh.frame_time.to_bits());
    for (a, b) in again.joints.iter().zip(&bvh.joints) {
        assert_eq!(
            (&a.name, a.parent, &a.channels, a.channel_offset),
            (&b.name, b.parent, &b.channels, b.channel_offset)
        );
        assert_eq!(a.end_site, b.end_site);
    }
    let same = again.values.iter().zip(&bvh.values).all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(same, "values changed in the round trip");
    // The pose is the same (offsets overridden by position channels are written as 0).
    for f in [0, bvh.frames - 1] {
        assert_eq!(again.global_pose(f), bvh.global_pose(f));
    }
});
