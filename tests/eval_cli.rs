//! `motion-stylizer eval` end to end on a miniature data folder cut from the fixtures (four
//! held-out takes of four styles), with the shipped weights and classifier.
#![cfg(feature = "model")]

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `DIR/dataset-{1,2}/data/*.bvh` named as Bandai takes, and a split holding all of them out.
fn mini_data(dir: &Path) -> PathBuf {
    let fixtures = root().join("tests/fixtures/bandai");
    let takes = [
        ("dataset-1", "dataset-1_walk_tired_001_f90", "dataset-1_walk_tired_001"),
        ("dataset-2", "dataset-2_walk_elderly_001_f120", "dataset-2_walk_elderly_001"),
        ("dataset-2", "dataset-2_walk_normal_001_f120", "dataset-2_walk_normal_001"),
        ("dataset-2", "dataset-2_raise-up-both-hands_active_001", "dataset-2_raise-up-both-hands_active_001"),
    ];
    let mut split = String::new();
    for (set, fixture, take) in takes {
        let data = dir.join(set).join("data");
        std::fs::create_dir_all(&data).unwrap();
        std::fs::copy(fixtures.join(format!("{fixture}.bvh")), data.join(format!("{take}.bvh"))).unwrap();
        split.push_str(take);
        split.push('\n');
    }
    let split_path = dir.join("split.txt");
    std::fs::write(&split_path, split).unwrap();
    split_path
}

fn eval(dir: &Path, extra: &[&str]) -> Value {
    let split = mini_data(dir);
    let json = dir.join("eval.json");
    let out = Command::new(env!("CARGO_BIN_EXE_motion-stylizer"))
        .current_dir(root())
        .args(["eval", "--data", dir.to_str().unwrap(), "--split", split.to_str().unwrap()])
        .args(["--repeats", "2", "--seed", "3", "--json", json.to_str().unwrap()])
        .args(extra)
        .output()
        .unwrap();
    assert!(out.status.success(), "eval failed: {}", String::from_utf8_lossy(&out.stderr));
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("| sup_label |"), "{table}");
    serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ms-eval-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn row<'a>(v: &'a Value, setting: &str) -> &'a Value {
    v["rows"].as_array().unwrap().iter().find(|r| r["setting"] == setting).unwrap_or_else(|| panic!("{setting}"))
}

#[test]
fn heldout_rows_have_every_metric_where_it_applies_and_null_where_not() {
    let dir = tmp("heldout");
    let v = eval(&dir, &[]);
    let settings: Vec<&str> = v["rows"].as_array().unwrap().iter().map(|r| r["setting"].as_str().unwrap()).collect();
    assert_eq!(settings, ["real", "identity", "sup_motion", "sup_label", "unsup_motion", "unsup_prior"]);
    assert_eq!(v["provenance"]["num_contents"], 4);
    assert_eq!(v["provenance"]["repeats"], 2);

    for metric in ["geodesic", "diversity"] {
        assert!(row(&v, "real")[metric].is_null(), "real {metric}");
    }
    assert_eq!(row(&v, "identity")["geodesic"], 0.0);
    assert!(row(&v, "identity")["diversity"].is_null());
    assert!(row(&v, "unsup_prior")["style_acc"].is_null(), "the prior has no target style");
    for setting in ["sup_motion", "sup_label", "unsup_motion", "unsup_prior"] {
        let r = row(&v, setting);
        let g = r["geodesic"].as_f64().unwrap();
        assert!(g > 0.01 && g < 3.15, "{setting} geodesic {g}");
        assert!(r["diversity"].as_f64().unwrap() > 0.0, "{setting} diversity");
        assert!(r["foot_skate"].as_f64().unwrap() >= 0.0);
        assert!(r["geodesic_ci"].is_f64(), "{setting}: two repeats give an interval");
        if setting != "unsup_prior" {
            let acc = r["style_acc"].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&acc), "{setting} acc {acc}");
        }
    }
    // Foot skating of the real references: present in every row, and the same motions (hence the
    // same value) for every row stylized toward one reference per content.
    for setting in ["real", "identity", "sup_motion", "sup_label", "unsup_motion", "unsup_prior"] {
        let s = row(&v, setting)["foot_skate_ref"].as_f64().unwrap_or_else(|| panic!("{setting}"));
        assert!(s > 0.0, "{setting} reference foot skating {s}");
    }
    let identity_ref = row(&v, "identity")["foot_skate_ref"].as_f64().unwrap();
    for setting in ["sup_motion", "sup_label", "unsup_motion"] {
        assert_eq!(row(&v, setting)["foot_skate_ref"].as_f64().unwrap(), identity_ref, "{setting}");
    }
    // The contents' own takes are never their references: identity is judged against other styles.
    let real = row(&v, "real")["style_acc"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&real));

    // Style shift: the only content with a `normal` take and another style's is set 2's walk
    // (elderly = old), so `old` has a direction from one content and one take; the others none.
    let dirs = v["directions"]["styles"].as_array().unwrap();
    assert_eq!(dirs.len(), 1, "{dirs:?}");
    assert_eq!(dirs[0]["style"], "old");
    assert_eq!((dirs[0]["contents"].as_u64(), dirs[0]["takes"].as_u64()), (Some(1), Some(1)));
    assert!(dirs[0]["length"].as_f64().unwrap() > 0.3 && dirs[0]["scored"] == true);
    assert_eq!(v["directions"]["spread"].as_array().unwrap().len(), 12);
    // Per-label rows: every targeted label of every row with a target, and the real takes of
    // each style (no shift: they define the directions); the identity's shift is 0 and only
    // `old` has one.
    let labels = v["labels"].as_array().unwrap();
    assert!(labels.iter().all(|l| l["setting"] != "unsup_prior"));
    for l in labels {
        let shift = &l["style_shift"];
        assert_eq!(shift.is_f64(), l["style"] == "old" && l["setting"] != "real", "{l}");
        if l["setting"] == "identity" && shift.is_f64() {
            assert_eq!(shift.as_f64(), Some(0.0));
        }
        assert!(l["outputs"].as_u64().unwrap() >= 1 && l["style_acc"].is_f64());
    }
    assert!(row(&v, "real")["style_shift"].is_null() && row(&v, "unsup_prior")["style_shift"].is_null());

    // Content measures, with the committed content classifier: every content here has a content
    // class (walk, raise-up-both-hands); the identity is its own contents (content FID 0), the
    // real takes have no content FID.
    assert!(v["provenance"]["content_classifier"].as_str().unwrap().ends_with("content-classifier.bin"));
    assert!(row(&v, "real")["content_fid"].is_null());
    assert!(row(&v, "identity")["content_fid"].as_f64().unwrap().abs() < 1e-6);
    for setting in ["real", "identity", "sup_motion", "sup_label", "unsup_motion", "unsup_prior"] {
        let acc = row(&v, setting)["content_acc"].as_f64().unwrap_or_else(|| panic!("{setting} content_acc"));
        assert!((0.0..=1.0).contains(&acc), "{setting} content acc {acc}");
        if !["real", "identity"].contains(&setting) {
            assert!(row(&v, setting)["content_fid"].as_f64().unwrap() > 0.0, "{setting} content FID");
        }
    }
    // Per target label, the content accuracy of that label's outputs: weighted by the outputs, the
    // labels of a row give back the row's (every repeat judges every content once).
    for setting in ["real", "identity", "sup_motion", "sup_label", "unsup_motion"] {
        let of_row: Vec<&Value> = labels.iter().filter(|l| l["setting"] == setting).collect();
        let outputs: f64 = of_row.iter().map(|l| l["outputs"].as_f64().unwrap()).sum();
        let pooled: f64 =
            of_row.iter().map(|l| l["content_acc"].as_f64().unwrap() * l["outputs"].as_f64().unwrap()).sum::<f64>()
                / outputs;
        let acc = row(&v, setting)["content_acc"].as_f64().unwrap();
        assert!((pooled - acc).abs() < 1e-9, "{setting}: labels pool to {pooled}, the row says {acc}");
        // The mistakes account for every miss, each a content taken for another class.
        for l in &of_row {
            let mistakes = l["content_mistakes"].as_array().unwrap();
            let missed: u64 = mistakes.iter().map(|m| m["count"].as_u64().unwrap()).sum();
            let judged = l["outputs"].as_f64().unwrap();
            let expected = judged * (1.0 - l["content_acc"].as_f64().unwrap());
            assert!((missed as f64 - expected).abs() < 1e-6, "{setting}: {missed} mistakes, {expected} misses: {l}");
            assert!(mistakes.iter().all(|m| m["content"] != m["taken_for"] && m["count"].as_u64().unwrap() > 0));
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn foreign_rig_contents_are_stylized_zero_shot() {
    let dir = tmp("foreign");
    let foreign = root().join("tests/fixtures/foreign");
    let v = eval(&dir, &["--content", foreign.to_str().unwrap()]);
    assert_eq!(v["provenance"]["num_contents"], 4);
    assert!(row(&v, "sup_label")["style_acc"].is_f64());
    // Foreign files have no content class (no content accuracy) but a content FID to themselves.
    assert!(row(&v, "sup_label")["content_acc"].is_null());
    // Per label too, but for the real (Bandai) takes the outputs are held to.
    for l in v["labels"].as_array().unwrap() {
        assert_eq!(l["content_acc"].is_null(), l["setting"] != "real", "{l}");
    }
    assert!(row(&v, "sup_label")["content_fid"].as_f64().unwrap() > 0.0);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_missing_data_folder_is_a_clear_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_motion-stylizer"))
        .current_dir(root())
        .args(["eval", "--data", "/nonexistent/data"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("/nonexistent/data"), "{err}");
}

#[test]
fn content_prefix_keeps_only_the_contents_named_so() {
    let dir = tmp("prefix");
    // One of the four held-out takes is set 1's: it alone is stylized; the references and the
    // `real` row still come from every held-out take.
    let v = eval(&dir, &["--content-prefix", "dataset-1_"]);
    assert_eq!(v["provenance"]["num_contents"], 1);
    assert_eq!(v["provenance"]["num_heldout"], 4);
    let outputs: u64 = v["labels"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|l| l["setting"] == "sup_label")
        .map(|l| l["outputs"].as_u64().unwrap())
        .sum();
    assert_eq!(outputs, 2, "one content × 2 repeats");

    // A prefix no content has is an error that says so, not an empty evaluation.
    let split = mini_data(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_motion-stylizer"))
        .current_dir(root())
        .args(["eval", "--data", dir.to_str().unwrap(), "--split", split.to_str().unwrap()])
        .args(["--repeats", "1", "--content-prefix", "dataset-3_"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--content-prefix \"dataset-3_\": none of the 4 contents"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}
