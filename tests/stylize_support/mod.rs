//! Shared helpers of the stylization tests: a weights folder built from *untrained* networks.
//!
//! There are no trained weights yet, so these tests check the plumbing (lengths, rigs, seeds,
//! errors), not the quality of the styles; see `tests/stylize_quality.rs` for the quality test
//! that runs once trained weights are committed under `assets/weights`.
#![allow(dead_code)]

use burn::prelude::*;
use motion_stylizer::dataset::STYLES;
use motion_stylizer::features::{NormStats, extract};
use motion_stylizer::model::weights::save_bundle;
use motion_stylizer::model::{ModelConfig, MotionModel};
use motion_stylizer::skeleton::{self, Imported};
use motion_stylizer::stylize::{Manifest, ModelEntry, StageRecord, Weights};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

pub const BANDAI: [&str; 4] = [
    "dataset-1_walk_tired_001_f90",
    "dataset-2_raise-up-both-hands_active_001",
    "dataset-2_walk_elderly_001_f120",
    "dataset-2_walk_normal_001_f120",
];
pub const FOREIGN: [&str; 4] = ["cmu31_rest", "cmu31_xia_neutral_16_000", "m21_walk", "iclone100_cmu_002_04"];

/// 38 frames: not a multiple of 8.
pub const SHORT: &str = "dataset-2_raise-up-both-hands_active_001";
pub const WALK: &str = "dataset-2_walk_normal_001_f120";

/// Width factor of the test networks.
pub const WIDTH: f64 = 0.125;

pub fn fixture_path(dir: &str, name: &str) -> PathBuf {
    PathBuf::from(format!("{}/tests/fixtures/{dir}/{name}.bvh", env!("CARGO_MANIFEST_DIR")))
}

pub fn fixture_text(dir: &str, name: &str) -> String {
    let path = fixture_path(dir, name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

pub fn import(dir: &str, name: &str) -> Imported {
    skeleton::import_bvh(&fixture_text(dir, name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

pub fn config(supervised: bool) -> ModelConfig {
    ModelConfig::scaled(WIDTH).with_num_styles(STYLES.len()).with_supervised(supervised)
}

/// The bundle of an untrained model (seeded, so every run builds the same bytes).
pub fn bundle(supervised: bool) -> Vec<u8> {
    let cfg = config(supervised);
    let model = MotionModel::seeded(&cfg, &Device::flex(), if supervised { 11 } else { 12 });
    save_bundle(&cfg, model).unwrap()
}

/// Normalisation statistics over the features of every fixture.
pub fn norm() -> NormStats {
    let feats: Vec<_> = BANDAI
        .iter()
        .map(|n| ("bandai", *n))
        .chain(FOREIGN.iter().map(|n| ("foreign", *n)))
        .map(|(d, n)| extract(&import(d, n).motion))
        .collect();
    NormStats::compute(&feats).unwrap()
}

fn stage(stage: &str) -> StageRecord {
    StageRecord {
        stage: stage.into(),
        command: "test".into(),
        steps: 0,
        seed: 0,
        batch: 1,
        window: 160,
        seconds: 0.0,
        seconds_per_step: 0.0,
        machine: "test".into(),
        final_losses: Default::default(),
        heldout: Default::default(),
    }
}

pub fn manifest() -> Manifest {
    let entry = |setting: &str| ModelEntry {
        setting: setting.into(),
        file: format!("{setting}.bin"),
        bytes: None,
        fnv1a64: None,
        encoding: None,
        style_encoder: None,
        width: WIDTH,
        stages: vec![stage("ae"), stage("stylizer")],
        label_codes: None,
        neutral_code: None,
    };
    Manifest {
        // Format 1 (one whole f16 bundle per setting): tests/weights_parts.rs writes format 2 from it.
        format: 1,
        licence: "test weights (untrained)".into(),
        styles: STYLES.iter().map(|s| s.to_string()).collect(),
        norm: "norm.json".into(),
        norm_bytes: None,
        norm_fnv1a64: None,
        window: 160,
        split: "assets/split/heldout.txt".into(),
        heldout_takes: 0,
        shared: None,
        models: vec![entry("supervised"), entry("unsupervised")],
    }
}

/// The files of the test weights folder: manifest, norm, supervised and unsupervised bundles.
pub struct Files {
    pub manifest: Vec<u8>,
    pub norm: Vec<u8>,
    pub supervised: Vec<u8>,
    pub unsupervised: Vec<u8>,
}

pub fn files() -> &'static Files {
    static FILES: OnceLock<Files> = OnceLock::new();
    FILES.get_or_init(|| Files {
        manifest: serde_json::to_vec_pretty(&manifest()).unwrap(),
        norm: serde_json::to_vec(&norm()).unwrap(),
        supervised: bundle(true),
        unsupervised: bundle(false),
    })
}

/// The test weights, both settings.
pub fn weights() -> Weights {
    let f = files();
    Weights::from_bytes(&f.manifest, &f.norm, Some(&f.supervised), Some(&f.unsupervised)).unwrap()
}

/// A weights folder in the target's temporary directory, written once per test binary.
pub fn weights_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("stylize-weights-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = files();
        std::fs::write(dir.join("manifest.json"), &f.manifest).unwrap();
        std::fs::write(dir.join("norm.json"), &f.norm).unwrap();
        std::fs::write(dir.join("supervised.bin"), &f.supervised).unwrap();
        std::fs::write(dir.join("unsupervised.bin"), &f.unsupervised).unwrap();
        dir
    })
}

/// A fresh empty directory in the target's temporary directory.
pub fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("stylize-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
