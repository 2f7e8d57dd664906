//! `--map` and `inspect --json` (issue 15, point 5): a rig neither names nor structure settle is
//! described with best guesses, mapped by hand, and the mapping round-trips through `inspect`.

mod support;

use glam::DVec3;
use motion_stylizer::bvh::{Bvh, BvhJoint};
use motion_stylizer::skeleton::{JOINT_NAMES, ManualMap, import, import_with};
use std::path::{Path, PathBuf};
use std::process::Command;
use support::*;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_motion-stylizer"))
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rigs_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn run_json(args: &[&str]) -> serde_json::Value {
    let out = bin().args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The m21 walk with meaningless joint names and a four-joint tail on the hips: five limbs, no
/// names: no automatic match.
fn tailed() -> Bvh {
    let mut b = fixture("foreign", "m21_walk");
    for (k, j) in b.joints.iter_mut().enumerate() {
        j.name = format!("j{k}");
    }
    let n = b.num_channels();
    let mut parent = 0;
    for t in 0..4 {
        b.joints.push(BvhJoint {
            name: format!("tail{t}"),
            parent: Some(parent),
            offset: DVec3::new(0.0, -4.0, -15.0),
            channels: vec![],
            end_site: None,
            channel_offset: n,
        });
        parent = b.joints.len() - 1;
    }
    b
}

#[test]
fn a_manual_map_round_trips_through_inspect() {
    let bvh = tailed();
    assert!(import(&bvh).is_err());
    let file = tmp("tailed.bvh");
    std::fs::write(&file, bvh.to_bvh_string()).unwrap();
    let f = file.to_str().unwrap();

    // Not retargetable: the error, and a `map` with every canonical joint.
    let info = run_json(&["inspect", f, "--json"]);
    assert_eq!(info["retargetable"], false);
    assert_eq!(info["error"]["code"], "RIG_UNMATCHED", "{info}");
    assert_eq!(info["map"].as_object().unwrap().len(), 21);

    // The mapping by hand: m21's own match, under the new names.
    let m21 = fixture("foreign", "m21_walk");
    let by_name = import(&m21).unwrap();
    let mut map = serde_json::Map::new();
    for (j, u) in by_name.rig.joint_map().iter().enumerate() {
        map.insert(JOINT_NAMES[j].into(), u.map_or(serde_json::Value::Null, |u| format!("j{u}").into()));
    }
    let map_file = tmp("map.json");
    std::fs::write(&map_file, serde_json::to_string_pretty(&serde_json::Value::Object(map.clone())).unwrap()).unwrap();
    let m = map_file.to_str().unwrap();
    let info = run_json(&["inspect", f, "--json", "--map", m]);
    assert_eq!(info["retargetable"], true, "{info}");
    assert_eq!(info["rig"], "manual");
    assert_eq!(info["map"], serde_json::Value::Object(map.clone()), "the mapping used is the one given");

    // An essential joint left out: not retargetable, and the map printed is the one given (to edit).
    let mut partial = map.clone();
    partial.insert("Hand_L".into(), serde_json::Value::Null);
    let partial_file = tmp("partial.json");
    std::fs::write(&partial_file, serde_json::Value::Object(partial.clone()).to_string()).unwrap();
    let info_partial = run_json(&["inspect", f, "--json", "--map", partial_file.to_str().unwrap()]);
    assert_eq!(info_partial["retargetable"], false);
    assert_eq!(info_partial["error"]["code"], "RIG_UNMATCHED", "{info_partial}");
    assert_eq!(info_partial["map"], serde_json::Value::Object(partial));

    // inspect's whole output is a mapping file too.
    let again_file = tmp("inspect.json");
    std::fs::write(&again_file, serde_json::to_string(&info).unwrap()).unwrap();
    let again = run_json(&["inspect", f, "--json", "--map", again_file.to_str().unwrap()]);
    assert_eq!(again["map"], info["map"]);

    // retarget with the map: m21's own canonical motion (the tail stays at rest).
    let out = tmp("out.bvh");
    let st = bin().args(["retarget", f, "--map", m, "-o", out.to_str().unwrap()]).status().unwrap();
    assert!(st.success());
    let written = Bvh::parse(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let canonical = import(&written).unwrap().motion;
    assert!(max_position_error(&by_name.motion, &canonical) < 1e-6);
    // The library's entry point agrees.
    let manual = ManualMap::from_json(&std::fs::read_to_string(&map_file).unwrap()).unwrap();
    let lib = import_with(&bvh, Some(&manual)).unwrap();
    assert!(max_position_error(&by_name.motion, &lib.motion) < 1e-9);

    // The same rig as a target (retarget --onto --onto-map) and as a style reference (stylize
    // --style-motion --style-map): refused without the map, used with it.
    let m21_file = tmp("m21.bvh");
    std::fs::write(&m21_file, m21.to_bvh_string()).unwrap();
    let m21_path = m21_file.to_str().unwrap();
    let onto = tmp("onto.bvh");
    let o = onto.to_str().unwrap();
    let refused = bin().args(["retarget", m21_path, "--onto", f, "-o", o]).output().unwrap();
    assert!(!refused.status.success(), "an unmatched --onto rig is refused");
    let st = bin().args(["retarget", m21_path, "--onto", f, "--onto-map", m, "-o", o]).status().unwrap();
    assert!(st.success());
    let on_tailed = Bvh::parse(&std::fs::read_to_string(&onto).unwrap()).unwrap();
    assert_eq!(on_tailed.joints.len(), bvh.joints.len(), "on the tailed rig");
    let back = import_with(&on_tailed, Some(&manual)).unwrap();
    let error = max_position_error(&by_name.motion, &back.motion);
    assert!(error < 1e-3, "m21's motion through the tailed rig: {error} cm");
    let styled = tmp("styled.bvh");
    let args = |extra: &[&str]| {
        let mut a = vec!["stylize", m21_path, "--style-motion", f, "--label", "old", "-o", styled.to_str().unwrap()];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let refused = bin().args(args(&[])).output().unwrap();
    assert!(!refused.status.success(), "an unmatched reference is refused");
    let ok = bin().args(args(&["--style-map", m])).output().unwrap();
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
}

#[test]
fn bad_maps_are_refused_with_their_reason() {
    let file = tmp("m21.bvh");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/foreign/m21_walk.bvh"), &file).unwrap();
    for (map, says) in [
        (r#"{"Pelvis": "Hips"}"#, "no canonical joint"),
        (r#"{"Hips": "NoSuchJoint"}"#, "has no joint"),
        (r#"{"Hand_L": "Hips", "Hand_R": "Hips"}"#, "plays both"),
        (r#"{"Hand_L": "RightHand"}"#, "not below"),
        (r#"{"Hand_L": null}"#, "Hand_L"),
        ("[1, 2]", "expected a JSON object"),
    ] {
        let m = tmp("bad.json");
        std::fs::write(&m, map).unwrap();
        let out =
            bin().args(["inspect", file.to_str().unwrap(), "--json", "--map", m.to_str().unwrap()]).output().unwrap();
        let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(text.contains(says), "{map}: {text}");
    }
}

/// `retargetable` means the import works: a rig without chest and neck (issue 15's complaint) is
/// retargetable, with the joints it synthesises.
#[test]
fn retargetable_means_retarget_works() {
    let f = format!("{}/tests/fixtures/rigs/no_chest_neck.bvh", env!("CARGO_MANIFEST_DIR"));
    let info = run_json(&["inspect", &f, "--json"]);
    assert_eq!(info["retargetable"], true, "{info}");
    assert_eq!(info["missing"], serde_json::json!(["Chest", "Neck"]));
    assert!(info["synthesised"]["Chest"].is_string(), "{info}");
    let out = tmp("nc.bvh");
    assert!(bin().args(["retarget", &f, "-o", out.to_str().unwrap()]).status().unwrap().success());
    // And a quadruped is not.
    let q = format!("{}/tests/fixtures/rigs/quadruped_bip01.bvh", env!("CARGO_MANIFEST_DIR"));
    let info = run_json(&["inspect", &q, "--json"]);
    assert_eq!(info["retargetable"], false);
    assert_eq!(info["error"]["code"], "NOT_HUMAN");
    assert!(!bin().args(["retarget", &q, "-o", out.to_str().unwrap()]).status().unwrap().success());
}
