//! The 260-D features on real clips (tests/fixtures): round trip, contacts, mirroring, normalisation.
//! Run with `--nocapture` to see the measured errors.

mod features_support;

use features_support::{max_diff, round_trip_errors};
use motion_stylizer::Motion;
use motion_stylizer::features::*;
use motion_stylizer::skeleton;
use std::path::{Path, PathBuf};

const FOREIGN_REQUIRED: &str = "m21_walk.bvh";

fn fixtures(dir: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(dir);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("fixture folder")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "bvh"))
        .collect();
    files.sort();
    files
}

fn load(path: &Path) -> Result<Motion, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    skeleton::import_bvh(&text).map(|i| i.motion).map_err(|e| e.to_string())
}

fn name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Every Bandai fixture and the required foreign one; other foreign fixtures when import takes them.
fn clips() -> Vec<(String, Motion)> {
    let mut out = Vec::new();
    for p in fixtures("bandai") {
        out.push((name(&p), load(&p).unwrap_or_else(|e| panic!("{}: {e}", name(&p)))));
    }
    for p in fixtures("foreign") {
        match load(&p) {
            Ok(m) => out.push((name(&p), m)),
            Err(e) if name(&p) == FOREIGN_REQUIRED => panic!("{}: {e}", name(&p)),
            Err(e) => println!("{}: not imported ({e}); skipped", name(&p)),
        }
    }
    out
}

#[test]
fn round_trip_on_real_clips() {
    let clips = clips();
    assert!(clips.len() >= 5);
    println!("{:<48} {:>6} {:>12} {:>12} {:>14}", "fixture", "frames", "mean (mm)", "max (mm)", "Hips drift (mm)");
    for (name, m) in &clips {
        let (mean, max, drift) = round_trip_errors(m);
        println!("{name:<48} {:>6} {:>12.6} {:>12.6} {:>14.6}", m.frames(), mean * 10.0, max * 10.0, drift * 10.0);
        assert!(mean < 0.1, "{name}: mean joint error {mean} cm");
        assert!(drift < 1.0, "{name}: final Hips drift {drift} cm");
    }
}

#[test]
fn contacts_alternate_on_walks() {
    for (name, m) in clips() {
        if !name.contains("walk") {
            continue;
        }
        let f = extract(&m);
        let n = f.frames() as f64;
        // A foot is down when its ankle or its toe is.
        let down = |k: usize| -> Vec<bool> {
            f.rows().map(|r| r[CONTACTS.start + k] > 0.5 || r[CONTACTS.start + k + 1] > 0.5).collect()
        };
        let (left, right) = (down(0), down(2));
        let frac = |v: &[bool]| v.iter().filter(|&&b| b).count() as f64 / n;
        let strip = |v: &[bool]| v.iter().map(|&b| if b { '|' } else { '.' }).collect::<String>();
        println!("{name}: left down {:.0} %, right down {:.0} %", 100.0 * frac(&left), 100.0 * frac(&right));
        println!("  L {}\n  R {}", strip(&left), strip(&right));
        for (side, v) in [("left", &left), ("right", &right)] {
            assert!((0.3..=0.9).contains(&frac(v)), "{name}: {side} foot down {:.2} of frames", frac(v));
        }
        assert_ne!(left, right, "{name}: both feet identical");
        // Each foot lifts and lands at least once.
        for v in [&left, &right] {
            assert!(v.windows(2).any(|w| w[0] && !w[1]) && v.windows(2).any(|w| !w[0] && w[1]), "{name}");
        }
    }
}

#[test]
fn mirror_on_real_clips() {
    for (name, m) in clips() {
        let direct = mirror(&extract(&m));
        let via_motion = extract(&m.mirrored());
        let (d, frame, dim) = max_diff(&direct, &via_motion);
        println!("{name}: mirror(features) vs features(mirrored): max diff {d:.2e}");
        assert!(d < 1e-3, "{name}: differ by {d} at frame {frame}, dim {dim}");
    }
}

#[test]
fn normalisation_on_real_clips() {
    let feats: Vec<Features> = clips().iter().map(|(_, m)| extract(m)).collect();
    let stats = NormStats::compute(&feats).unwrap();
    for (g, r) in
        GROUPS.iter().zip(["ang vel", "lin vel", "height", "positions", "rotations", "velocities", "contacts"])
    {
        println!("{r:<11} std {:.4}", stats.std()[g.start]);
    }
    let json = serde_json::to_string(&stats).unwrap();
    assert_eq!(serde_json::from_str::<NormStats>(&json).unwrap(), stats);
    for f in &feats {
        let mut g = f.clone();
        stats.normalize(&mut g);
        assert!(g.first_non_finite().is_none());
        stats.denormalize(&mut g);
        let (d, _, _) = max_diff(&g, f);
        assert!(d < 1e-3, "{d}");
    }
}

#[test]
fn throughput_parse_import_extract() {
    let files: Vec<(String, String)> =
        fixtures("bandai").iter().map(|p| (name(p), std::fs::read_to_string(p).expect("read"))).collect();
    let start = std::time::Instant::now();
    let mut frames = 0;
    for (_, text) in &files {
        let m = skeleton::import_bvh(text).expect("import").motion;
        frames += extract(&m).frames();
    }
    let s = start.elapsed().as_secs_f64();
    println!(
        "parse + import + extract: {frames} frames in {:.1} ms = {:.0} frames/s (this build's profile)",
        s * 1e3,
        frames as f64 / s
    );
}
