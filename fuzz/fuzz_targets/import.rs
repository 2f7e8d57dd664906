//! Arbitrary bytes through the whole import (issue 15, point 6): parse → bound the work from the
//! header → match the rig (names, structure, or a manual map) → retarget → resample → features and
//! back, and the motion back onto the user's rig. It must return (no panic, no hang: the work is
//! bounded by `resample::check_budget`), and what it accepts must be finite everywhere.
//!
//! A first line starting with `{` is read as a manual joint mapping (JSON) for the rest.
#![no_main]

use libfuzzer_sys::fuzz_target;
use motion_stylizer::features::{extract, reconstruct};
use motion_stylizer::skeleton::{ManualMap, import_bvh_with};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let (map, bvh_text) = match text.split_once('\n') {
        Some((first, rest)) if first.starts_with('{') => (ManualMap::from_json(first).ok(), rest),
        _ => (None, text),
    };
    let Ok(imp) = import_bvh_with(bvh_text, map.as_ref()) else { return };
    let m = &imp.motion;
    assert!(m.frames() >= 1);
    assert!(m.root_positions().iter().all(|p| p.is_finite()));
    assert!(m.rotations().iter().all(|pose| pose.iter().all(|q| q.is_finite())));
    // Features and back: finite, or refused with an error.
    let f = extract(m);
    if f.data().iter().all(|v| v.is_finite()) {
        let _ = reconstruct(&f);
    }
    // Back onto the user's rig and in again.
    let back = imp.rig.from_canonical(m);
    assert!(back.values.iter().all(|v| v.is_finite()));
    assert_eq!(back.values.len(), back.frames * back.num_channels());
    let _ = imp.rig.to_canonical(&back);
    let _ = (imp.rig.report(), imp.rig.synthesised(), imp.rig.notes());
});
