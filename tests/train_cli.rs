//! `motion-stylizer train` and `export` end to end on a tiny data folder made from the Bandai
//! fixtures (3 training takes + mirrors, 1 held-out take), tiny networks (width 0.125), window 32,
//! batch 2, a few steps each.
#![cfg(feature = "model")]

use burn::prelude::*;
use motion_stylizer::features::NormStats;
use motion_stylizer::model::weights::{load_style_encoder, load_stylizer_core};
use motion_stylizer::stylize::manifest::Manifest;
use motion_stylizer::train::rundir::{self, Checkpoint, CsvTable, RunLog};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const FIXTURES: [&str; 4] = [
    "dataset-1_walk_tired_001_f90",
    "dataset-2_raise-up-both-hands_active_001",
    "dataset-2_walk_elderly_001_f120",
    "dataset-2_walk_normal_001_f120",
];
const HELDOUT: &str = "dataset-2_walk_normal_001";

/// A fresh folder for one test: `data/dataset-{1,2}/data/*.bvh` (fixtures under their take
/// names) and `split.txt` holding out one take.
fn setup(name: &str) -> PathBuf {
    let root = std::env::temp_dir().join(format!("motion-stylizer-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for f in FIXTURES {
        let take = match f.rfind("_f") {
            Some(i) if f[i + 2..].chars().all(|c| c.is_ascii_digit()) => &f[..i],
            _ => f,
        };
        let set = &take[..9];
        let dir = root.join("data").join(set).join("data");
        std::fs::create_dir_all(&dir).unwrap();
        let src = format!("{}/tests/fixtures/bandai/{f}.bvh", env!("CARGO_MANIFEST_DIR"));
        std::fs::copy(&src, dir.join(format!("{take}.bvh"))).unwrap();
    }
    std::fs::write(root.join("split.txt"), format!("# test split\n{HELDOUT}\n")).unwrap();
    root
}

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_motion-stylizer")).args(args).output().expect("run the CLI")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "failed: {}\n{}", stderr(&o), String::from_utf8_lossy(&o.stdout));
    o
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// `train <stage> …` with the tiny settings.
fn train(stage: &[&str], root: &Path, out: &Path, steps: u64, extra: &[&str]) -> Output {
    let steps = steps.to_string();
    let data = root.join("data");
    let split = root.join("split.txt");
    let mut args = vec!["train"];
    args.extend_from_slice(stage);
    args.extend_from_slice(&[
        "--data",
        p(&data),
        "--out",
        p(out),
        "--split",
        p(&split),
        "--steps",
        &steps,
        "--checkpoint-every",
        "2",
        "--eval-every",
        "2",
        "--threads",
        "1",
    ]);
    args.extend_from_slice(extra);
    cli(&args)
}

const TINY: [&str; 6] = ["--width", "0.125", "--window", "32", "--batch", "2"];

fn steps_of(table: &CsvTable) -> Vec<u64> {
    table.rows.iter().map(|r| r[0] as u64).collect()
}

#[test]
fn ae_trains_checkpoints_resumes_and_refuses_to_overwrite() {
    let root = setup("ae");
    let run = root.join("ae");
    let first = ok(train(&["ae"], &root, &run, 4, &TINY));
    assert!(stderr(&first).contains("1 held-out windows"), "{}", stderr(&first));
    for f in ["config.json", "run.json", "norm.json", "checkpoint.bin", "loss.csv", "eval.csv"] {
        assert!(run.join(f).is_file(), "{f}");
    }
    let loss = CsvTable::read(&run.join("loss.csv")).unwrap();
    assert_eq!(loss.columns[..3], ["step", "elapsed_s", "ae_loss"]);
    assert!(loss.columns.iter().any(|c| c == "regressor_loss") && loss.columns.last().unwrap() == "regressor_lr");
    assert_eq!(steps_of(&loss), [1, 2, 3, 4]);
    assert!(loss.rows.iter().all(|r| r.iter().all(|v| v.is_finite())));
    let evals = CsvTable::read(&run.join("eval.csv")).unwrap();
    assert_eq!(steps_of(&evals), [2, 4]);
    let mpjpe = evals.columns.iter().position(|c| c == "mpjpe_mm").unwrap();
    assert!(evals.rows[1][mpjpe] > 0.0 && evals.rows[1][mpjpe].is_finite());
    assert_eq!(Checkpoint::read(&run.join("checkpoint.bin")).unwrap().meta.step, 4);
    let norm: NormStats = rundir::read_json(&run.join("norm.json")).unwrap();
    assert_eq!(norm.mean().len(), 260);

    // An existing run is never overwritten.
    let again = train(&["ae"], &root, &run, 4, &TINY);
    assert!(!again.status.success());
    assert!(stderr(&again).contains("--resume"), "{}", stderr(&again));
    // A resumed run keeps its settings.
    let other = train(&["ae"], &root, &run, 6, &["--resume", "--width", "0.25"]);
    assert!(!other.status.success() && stderr(&other).contains("differs"), "{}", stderr(&other));

    // Resume to 6 steps: the count goes on, the logs are appended, Adam's state comes back.
    assert!(run.join("optimizer.bin").is_file());
    let resumed_out = ok(train(&["ae"], &root, &run, 6, &["--resume"]));
    assert!(stderr(&resumed_out).contains("resumed Adam's state of step 4"), "{}", stderr(&resumed_out));
    let loss = CsvTable::read(&run.join("loss.csv")).unwrap();
    assert_eq!(steps_of(&loss), [1, 2, 3, 4, 5, 6]);
    assert!(loss.rows.windows(2).all(|w| w[1][1] >= w[0][1]), "elapsed_s grows");
    assert_eq!(steps_of(&CsvTable::read(&run.join("eval.csv")).unwrap()), [2, 4, 6]);
    let resumed = Checkpoint::read(&run.join("checkpoint.bin")).unwrap();
    assert_eq!(resumed.meta.step, 6);
    let log: RunLog = rundir::read_json(&run.join("run.json")).unwrap();
    assert_eq!(log.segments.len(), 2);
    assert!(log.segments[1].command.contains("--resume") && log.segments[0].command.contains("train ae"));
    assert_eq!((log.segments[0].to_step, log.segments[1].from_step, log.segments[1].to_step), (4, 4, 6));
    // Already there: nothing to do.
    ok(train(&["ae"], &root, &run, 6, &["--resume"]));

    // A straight 6-step run: the same losses for the first 4 steps (deterministic from the seed)
    // and the same sampler position at the end (the resumed run drew the same batches). After
    // the resume the autoencoder's dropout masks differ (the device generator is reseeded), but
    // the regressor has no dropout: its losses at steps 5 and 6 match the straight run's only
    // because its weights AND Adam's moments were restored.
    let straight = root.join("ae-straight");
    ok(train(&["ae"], &root, &straight, 6, &TINY));
    let s_loss = CsvTable::read(&straight.join("loss.csv")).unwrap();
    let cols = 2..loss.columns.len();
    for k in 0..4 {
        assert_eq!(s_loss.rows[k][cols.clone()], loss.rows[k][cols.clone()], "step {}", k + 1);
    }
    let col = |name: &str| loss.columns.iter().position(|c| c == name).unwrap();
    for k in 4..6 {
        for name in ["regressor_loss", "regressor_grad_norm"] {
            assert_eq!(s_loss.rows[k][col(name)], loss.rows[k][col(name)], "{name} at step {}", k + 1);
        }
    }
    let s_ckpt = Checkpoint::read(&straight.join("checkpoint.bin")).unwrap();
    assert_eq!(s_ckpt.meta.sampler, resumed.meta.sampler);
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn stylizer_trains_in_both_settings_and_exports() {
    let root = setup("stylizer");
    let ae = root.join("ae");
    ok(train(&["ae"], &root, &ae, 2, &TINY));
    let sup = root.join("sup");
    let unsup = root.join("unsup");
    let small = ["--window", "32", "--batch", "2"];
    ok(train(&["stylizer", "--ae", p(&ae)], &root, &sup, 3, &small));
    let mut args = vec!["--unsupervised", "--hsa", "0.5"];
    args.extend_from_slice(&small);
    ok(train(&["stylizer", "--ae", p(&ae)], &root, &unsup, 3, &args));
    // The homo-style alignment weight given replaces the paper's (unsupervised 0.1) in the run's
    // settings; a run without it keeps the paper's weights (none recorded).
    let weights_of = |run: &Path| {
        let config: serde_json::Value = rundir::read_json(&run.join("config.json")).unwrap();
        config["train"]["stylizer_weights"].clone()
    };
    assert_eq!(weights_of(&unsup)["hsa"], 0.5);
    assert_eq!(weights_of(&unsup)["cyc"], 1.0);
    assert!(weights_of(&sup).is_null());
    for run in [&sup, &unsup] {
        let loss = CsvTable::read(&run.join("loss.csv")).unwrap();
        assert_eq!(steps_of(&loss), [1, 2, 3]);
        assert!(loss.columns.iter().any(|c| c == "hsa"));
        let evals = CsvTable::read(&run.join("eval.csv")).unwrap();
        assert_eq!(steps_of(&evals), [2, 3]);
        assert!(evals.rows.iter().all(|r| r.iter().all(|v| v.is_finite())));
        assert!(run.join("ae.bin").is_file());
    }
    // Resume works for the stylizer too (its autoencoder comes from its own copy).
    ok(train(&["stylizer"], &root, &sup, 4, &["--resume"]));
    assert_eq!(Checkpoint::read(&sup.join("checkpoint.bin")).unwrap().meta.step, 4);

    let weights = root.join("weights");
    ok(cli(&["export", "--sup", p(&sup), "--unsup", p(&unsup), "--ae", p(&ae), "-o", p(&weights)]));
    let manifest: Manifest = rundir::read_json(&weights.join("manifest.json")).unwrap();
    assert_eq!(manifest.window, 32);
    assert_eq!(manifest.heldout_takes, 1);
    assert_eq!(manifest.styles.len(), 16);
    assert!(manifest.licence.contains("CC BY-NC 4.0"));
    let _: NormStats = rundir::read_json(&weights.join(&manifest.norm)).unwrap();
    assert_eq!(manifest.models.len(), 2);
    for (entry, supervised, steps) in [(&manifest.models[0], true, 4), (&manifest.models[1], false, 3)] {
        assert_eq!(entry.width, 0.125);
        let stages: Vec<(&str, u64)> = entry.stages.iter().map(|s| (s.stage.as_str(), s.steps)).collect();
        assert_eq!(stages, [("ae", 2), ("stylizer", steps)]);
        let ae_stage = &entry.stages[0];
        assert!(ae_stage.command.contains("train ae") && ae_stage.seconds > 0.0 && ae_stage.seconds_per_step > 0.0);
        assert!(ae_stage.heldout.contains_key("mpjpe_mm") && ae_stage.final_losses.contains_key("ae_loss"));
        assert!(!ae_stage.final_losses.contains_key("lr"));
        assert!(entry.stages[1].heldout.contains_key("hsa") && !entry.stages[1].machine.is_empty());
        let bytes = std::fs::read(weights.join(&entry.file)).unwrap();
        assert_eq!(entry.bytes, Some(bytes.len() as u64));
        let (config, _core) = load_stylizer_core(&bytes, &Device::flex()).unwrap();
        assert_eq!(config.supervised, supervised);
        assert_eq!(config.num_styles, 16);
        // Format 3: the style encoder in a file of its own, of the same model.
        let style = entry.style_encoder.as_ref().expect("format 3 names the style encoder's file");
        let style_bytes = std::fs::read(weights.join(&style.file)).unwrap();
        assert_eq!(style.bytes, style_bytes.len() as u64);
        assert_eq!(style.fnv1a64, motion_stylizer::model::weights::fnv1a64(&style_bytes));
        let (style_config, _encoder) = load_style_encoder(&style_bytes, &Device::flex()).unwrap();
        assert_eq!(style_config, config);
    }
    // One shared autoencoder + regressor, both settings loadable on it.
    assert_eq!(manifest.shared.as_ref().map(|s| s.file.file.as_str()), Some("shared.bin"));
    let loaded = motion_stylizer::stylize::Weights::load_dir(&weights).unwrap();
    assert_eq!(loaded.settings().len(), 2);
    let _ = std::fs::remove_dir_all(&root);
}

/// Issue 14, the content- and style-class losses: a stylizer run judged by a content and a style
/// classifier keeps a copy of each (a resumed run needs nothing else), logs both terms, and
/// refuses a judge of the wrong classes or of other normalisation statistics.
#[test]
fn stylizer_with_judges_trains_resumes_and_refuses_a_wrong_judge() {
    let root = setup("judged");
    let ae = root.join("ae");
    ok(train(&["ae"], &root, &ae, 2, &TINY));
    let judge_run = root.join("judge");
    ok(train(&["content-classifier"], &root, &judge_run, 2, &TINY));
    let style_run = root.join("style-classifier");
    ok(train(&["classifier"], &root, &style_run, 2, &TINY));
    let (judge, style_judge) = (judge_run.join("classifier.bin"), style_run.join("classifier.bin"));
    let small = ["--window", "32", "--batch", "4"];
    let run = root.join("sup");
    let mut args = vec!["--content-class", "2", "--content-judge", p(&judge)];
    args.extend_from_slice(&["--style-class", "0.5", "--style-judge", p(&style_judge)]);
    args.extend_from_slice(&small);
    ok(train(&["stylizer", "--ae", p(&ae)], &root, &run, 2, &args));
    assert_eq!(std::fs::read(run.join("content-judge.bin")).unwrap(), std::fs::read(&judge).unwrap());
    assert_eq!(std::fs::read(run.join("style-judge.bin")).unwrap(), std::fs::read(&style_judge).unwrap());
    let config: serde_json::Value = rundir::read_json(&run.join("config.json")).unwrap();
    assert_eq!(config["train"]["stylizer_weights"]["content_class"], 2.0);
    assert_eq!(config["train"]["stylizer_weights"]["style_class"], 0.5);
    assert_eq!(config["content_judge"], p(&judge));
    assert_eq!(config["style_judge"], p(&style_judge));
    // A style classifier is not a content judge, nor a content classifier a style judge.
    for (flag, file, refusal) in [
        ("--content-judge", &style_judge, "not the 18 content classes"),
        ("--style-judge", &judge, "not the run's 16 style labels"),
    ] {
        let weight = if flag == "--content-judge" { "--content-class" } else { "--style-class" };
        let mut args = vec![weight, "1", flag, p(file)];
        args.extend_from_slice(&small);
        let o = train(&["stylizer", "--ae", p(&ae)], &root, &root.join("wrong"), 2, &args);
        assert!(!o.status.success() && stderr(&o).contains(refusal), "{}", stderr(&o));
        assert!(!root.join("wrong").exists(), "nothing written for a refused judge");
    }
    // The judges may go away: the run resumes from its copies.
    std::fs::remove_dir_all(&judge_run).unwrap();
    std::fs::remove_dir_all(&style_run).unwrap();
    ok(train(&["stylizer"], &root, &run, 3, &["--resume"]));
    let loss = CsvTable::read(&run.join("loss.csv")).unwrap();
    assert_eq!(steps_of(&loss), [1, 2, 3]);
    for name in ["content_class", "style_class"] {
        let column = loss.columns.iter().position(|c| c == name).expect(name);
        assert!(loss.rows.iter().all(|r| r[column] > 0.0 && r[column].is_finite()), "{name}: {:?}", loss.rows);
    }

    // A judge trained on other statistics (its run's norm.json beside it) is refused.
    let judge_run = root.join("judge2");
    ok(train(&["content-classifier"], &root, &judge_run, 2, &TINY));
    let norm_path = judge_run.join("norm.json");
    let mut norm: serde_json::Value = rundir::read_json(&norm_path).unwrap();
    norm["mean"][0] = serde_json::json!(norm["mean"][0].as_f64().unwrap() + 1.0);
    std::fs::write(&norm_path, serde_json::to_string(&norm).unwrap()).unwrap();
    let judge = judge_run.join("classifier.bin");
    let mut args = vec!["--content-class", "1", "--content-judge", p(&judge)];
    args.extend_from_slice(&small);
    let o = train(&["stylizer", "--ae", p(&ae)], &root, &root.join("other-norm"), 2, &args);
    assert!(!o.status.success() && stderr(&o).contains("other normalisation statistics"), "{}", stderr(&o));
    assert!(!root.join("other-norm").exists(), "nothing written for a refused judge");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn bad_arguments_fail_with_a_clear_message() {
    let root = setup("args");
    let out = root.join("run");
    let o = train(&["ae"], &root, &out, 2, &["--window", "60"]);
    assert!(!o.status.success() && stderr(&o).contains("multiple of 8"), "{}", stderr(&o));
    assert!(!out.exists(), "nothing written on a bad argument");

    let o = cli(&["train", "ae", "--out", p(&out)]);
    assert!(!o.status.success() && stderr(&o).contains("--data"), "{}", stderr(&o));

    let o = train(&["stylizer"], &root, &out, 2, &[]);
    assert!(!o.status.success() && stderr(&o).contains("--ae"), "{}", stderr(&o));

    let o = train(&["stylizer", "--ae", p(&out)], &root, &out, 2, &["--hsa=-1"]);
    assert!(!o.status.success() && stderr(&o).contains("--hsa -1"), "{}", stderr(&o));
    assert!(!out.exists(), "nothing written on a bad argument");
    for (flag, needs) in [("--content-class", "needs --content-judge"), ("--style-class", "needs --style-judge")] {
        let o = train(&["stylizer", "--ae", p(&out)], &root, &out, 2, &[flag, "1"]);
        assert!(!o.status.success() && stderr(&o).contains(needs), "{}", stderr(&o));
    }
    // The pairings that are judged by the style statistics need them.
    for flag in ["--cross-content", "--cross-set"] {
        let o = train(&["stylizer", "--ae", p(&out)], &root, &out, 2, &[flag]);
        let needs = format!("{flag} needs --style-stats above 0");
        assert!(!o.status.success() && stderr(&o).contains(&needs), "{}", stderr(&o));
        assert!(!out.exists(), "nothing written on a bad argument");
    }

    let o = cli(&["train", "ae", "--data", p(&root.join("nowhere")), "--out", p(&out)]);
    assert!(!o.status.success() && stderr(&o).contains("dataset-1"), "{}", stderr(&o));

    let o = train(&["ae"], &root, &out, 2, &["--resume"]);
    assert!(!o.status.success() && stderr(&o).contains("no run to resume"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&root);
}
