//! `train all` on a folder of one's own BVH files: a tiny folder of generated clips on two rigs
//! (the Bandai-Namco rig and the 21-joint m21 rig) with two new labels, a few unlabelled clips
//! and a broken file; tiny networks, a handful of steps. Then the exported weights are used by
//! `styles --weights` and `stylize --weights --label` with a label the shipped weights do not know.
#![cfg(feature = "model")]

use motion_stylizer::stylize::manifest::Manifest;
use motion_stylizer::train::all::Report;
use motion_stylizer::train::rundir;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

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

fn fixture(rel: &str) -> String {
    std::fs::read_to_string(format!("{}/tests/fixtures/{rel}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// A BVH's header (through `MOTION`), frame time and frame rows.
fn split_bvh(text: &str) -> (String, f64, Vec<String>) {
    let at = text.find("MOTION").expect("a MOTION section");
    let header = text[..at].to_string() + "MOTION\n";
    let mut lines = text[at..].lines().skip(1).filter(|l| !l.trim().is_empty());
    let _frames = lines.next().expect("Frames:");
    let time_line = lines.next().expect("Frame Time:");
    let dt: f64 = time_line.split(':').nth(1).unwrap().trim().parse().unwrap();
    (header, dt, lines.map(str::to_string).collect())
}

fn join_bvh(header: &str, dt: f64, rows: &[String]) -> String {
    format!("{header}Frames: {}\nFrame Time: {dt}\n{}\n", rows.len(), rows.join("\n"))
}

/// A generated clip: the source's frames from `start`, played at `speed` (frames dropped to speed
/// up, each frame repeated to slow down), as a new BVH on the same rig.
fn generate(source: &str, start: usize, speed: f64) -> String {
    let (header, dt, rows) = split_bvh(source);
    let src = &rows[start.min(rows.len() - 1)..];
    let n = ((src.len() as f64) / speed).floor() as usize;
    let out: Vec<String> = (0..n).map(|i| src[((i as f64 * speed) as usize).min(src.len() - 1)].clone()).collect();
    join_bvh(&header, dt, &out)
}

/// The test folder: per rig, two takes of `slowmo` (half speed) and two of `hurried` (double
/// speed) in labelled sub-folders, the plain clip unlabelled, and one broken file.
fn make_folder(root: &Path) -> PathBuf {
    let data = root.join("data");
    let rigs =
        [("bandai", fixture("bandai/dataset-2_walk_normal_001_f120.bvh")), ("m21", fixture("foreign/m21_walk.bvh"))];
    let mut csv = String::from("file,style,content\n");
    for (rig, source) in &rigs {
        for (label, speed) in [("slowmo", 0.5), ("hurried", 2.0)] {
            let dir = data.join(rig).join(label);
            std::fs::create_dir_all(&dir).unwrap();
            for (take, start) in [0usize, 10].into_iter().enumerate() {
                let name = format!("{label}_{take}.bvh");
                std::fs::write(dir.join(&name), generate(source, start, speed)).unwrap();
                csv.push_str(&format!("{rig}/{label}/{name},{label},walk\n"));
            }
        }
        let raw = data.join("raw");
        std::fs::create_dir_all(&raw).unwrap();
        std::fs::write(raw.join(format!("{rig}_plain.BVH")), generate(source, 0, 1.0)).unwrap();
    }
    std::fs::write(data.join("raw").join("broken.bvh"), "HIERARCHY\nROOT Hips\n{\n").unwrap();
    std::fs::write(data.join("labels.csv"), csv).unwrap();
    data
}

fn fresh(name: &str) -> PathBuf {
    let root = std::env::temp_dir().join(format!("motion-stylizer-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    root
}

const TINY: [&str; 12] =
    ["--steps", "2", "--width", "0.125", "--window", "32", "--batch", "2", "--threads", "1", "--seed", "3"];

fn train_all(data: &Path, run: &Path) -> Output {
    let mut args = vec!["train", "all", "--data", p(data), "--out", p(run)];
    args.extend_from_slice(&TINY);
    cli(&args)
}

#[test]
fn train_all_on_a_labelled_folder_of_two_rigs_exports_weights_that_stylize_with_a_new_label() {
    let root = fresh("train-folder");
    let data = make_folder(&root);
    let run = root.join("run");
    let first = ok(train_all(&data, &run));
    let err = stderr(&first);
    for stage in ["[1/4] ae", "[2/4] sup", "[3/4] unsup", "[4/4] classifier"] {
        assert!(err.contains(stage), "{stage}: {err}");
    }

    // The report: every file found, the broken one skipped with its error, the labels' shares.
    let report: Report = rundir::read_json(&run.join("report.json")).unwrap();
    assert_eq!(report.layout, "folder");
    assert_eq!((report.files_found, report.files_used), (11, 10), "{report:?}");
    assert_eq!(report.skipped.len(), 1);
    assert!(report.skipped[0].file.ends_with("broken.bvh"), "{:?}", report.skipped);
    assert!(report.skipped[0].error.contains("BVH_PARSE"), "{:?}", report.skipped);
    let labels: Vec<(&str, usize)> = report.labels.iter().map(|l| (l.label.as_str(), l.files)).collect();
    assert_eq!(labels, [("hurried", 4), ("slowmo", 4)]);
    assert_eq!(report.unlabelled.files, 2);
    // Half speed doubles a clip's length: slowmo has about four times hurried's minutes.
    let (hurried, slowmo) = (report.labels[0].minutes, report.labels[1].minutes);
    assert!(slowmo > 3.0 * hurried && hurried > 0.0, "{hurried} {slowmo}");
    let stdout = String::from_utf8_lossy(&first.stdout);
    assert!(
        stdout.contains("skipped") && stdout.contains("broken.bvh") && stdout.contains("slowmo: 4 files"),
        "{stdout}"
    );
    let steps: Vec<(&str, u64)> = report.stages.iter().map(|s| (s.name.as_str(), s.steps)).collect();
    assert_eq!(steps, [("ae", 2), ("sup", 3), ("unsup", 3), ("classifier", 1)]);

    // The weights folder: both bundles, the classifier, the new label set with its label codes.
    let weights = run.join("weights");
    for f in ["manifest.json", "norm.json", "supervised.bin", "unsupervised.bin", "classifier.bin"] {
        assert!(weights.join(f).is_file(), "{f}");
    }
    let manifest: Manifest = rundir::read_json(&weights.join("manifest.json")).unwrap();
    assert_eq!(manifest.styles, ["hurried", "slowmo"]);
    let sup = manifest.models.iter().find(|m| m.setting == "supervised").unwrap();
    let codes = sup.label_codes.as_ref().expect("label codes");
    assert_eq!(codes.takes, [4, 4]);
    assert!(codes.codes.iter().all(|c| c.iter().all(|v| v.is_finite())));
    assert_eq!(sup.stages.len(), 2);
    // No `normal` label in the folder: no neutral code (guidance measures against 0).
    let unsup = manifest.models.iter().find(|m| m.setting == "unsupervised").unwrap();
    assert!(unsup.neutral_code.is_none());

    // `styles --weights` lists the folder's labels, one per line.
    let styles = ok(cli(&["styles", "--weights", p(&weights)]));
    assert_eq!(String::from_utf8_lossy(&styles.stdout), "hurried\nslowmo\n");

    // Stylize a clip of either rig with a new label, and motion-based unsupervised.
    for (content, frames_at_30) in [("raw/m21_plain.BVH", 81usize), ("raw/bandai_plain.BVH", 120)] {
        let out = root.join(format!("out_{}.bvh", frames_at_30));
        let content = data.join(content);
        ok(cli(&["stylize", p(&content), "--label", "slowmo", "--weights", p(&weights), "-o", p(&out), "--seed", "1"]));
        let text = std::fs::read_to_string(&out).unwrap();
        let source = std::fs::read_to_string(&content).unwrap();
        assert_eq!(text.matches("JOINT").count(), source.matches("JOINT").count(), "on the content's own rig");
        let (_, _, rows) = split_bvh(&text);
        assert!(rows.len() >= frames_at_30 - 1, "{} rows", rows.len());
        assert!(rows.iter().all(|r| r.split_whitespace().all(|v| v.parse::<f64>().is_ok_and(f64::is_finite))));
    }
    let out = root.join("unsup.bvh");
    let reference = data.join("bandai/slowmo/slowmo_0.bvh");
    ok(cli(&[
        "stylize",
        p(&data.join("raw/m21_plain.BVH")),
        "--style-motion",
        p(&reference),
        "--unsupervised",
        "--weights",
        p(&weights),
        "-o",
        p(&out),
    ]));
    // A label of the shipped set is unknown to these weights.
    let unknown = cli(&["stylize", p(&reference), "--label", "old", "--weights", p(&weights), "-o", p(&out)]);
    assert!(!unknown.status.success() && stderr(&unknown).contains("slowmo"), "{}", stderr(&unknown));

    // Running the command again resumes: every stage is already done, the export is redone.
    let before = std::fs::read(weights.join("supervised.bin")).unwrap();
    let again = ok(train_all(&data, &run));
    assert!(stderr(&again).contains("(resuming)") && stderr(&again).contains("nothing to do"), "{}", stderr(&again));
    assert_eq!(std::fs::read(weights.join("supervised.bin")).unwrap(), before, "the same weights");
    // A different setting on resume is refused.
    let mut args = vec!["train", "all", "--data", p(&data), "--out", p(&run)];
    args.extend(TINY.iter().map(|a| if *a == "0.125" { "0.25" } else { a }));
    let other = cli(&args);
    assert!(!other.status.success() && stderr(&other).contains("differs"), "{}", stderr(&other));

    // Fine-tuning from these weights on a second folder: one old label, one new one.
    let second = root.join("data2");
    std::fs::create_dir_all(&second).unwrap();
    let m21 = fixture("foreign/m21_walk.bvh");
    let bandai = fixture("bandai/dataset-2_walk_normal_001_f120.bvh");
    std::fs::write(second.join("tip_0.bvh"), generate(&m21, 0, 0.75)).unwrap();
    std::fs::write(second.join("tip_1.bvh"), generate(&bandai, 5, 0.75)).unwrap();
    std::fs::write(second.join("slow.bvh"), generate(&bandai, 3, 0.5)).unwrap();
    std::fs::write(second.join("labels.csv"), "file,style\ntip_0.bvh,tiptoe\ntip_1.bvh,tiptoe\nslow.bvh,SlowMo\n")
        .unwrap();
    let tuned = root.join("tuned");
    let mut args = vec!["train", "all", "--data", p(&second), "--out", p(&tuned), "--from", p(&weights)];
    args.extend(TINY.iter().filter(|a| **a != "--width" && **a != "0.125"));
    let tune = ok(cli(&args));
    let err = stderr(&tune);
    assert!(err.contains("start from") && err.contains("grown for the new labels"), "{err}");
    let tuned_weights = tuned.join("weights");
    let manifest: Manifest = rundir::read_json(&tuned_weights.join("manifest.json")).unwrap();
    assert_eq!(manifest.styles, ["hurried", "slowmo", "tiptoe"], "old labels first, the new one added");
    assert_eq!(manifest.models[0].width, 0.125, "the width of the weights started from");
    let tuned_codes = manifest.models.iter().find(|m| m.setting == "supervised").unwrap().label_codes.clone().unwrap();
    assert_eq!(tuned_codes.takes, [4, 5, 2], "hurried keeps its codes, slowmo's merged with its new file's");
    assert_eq!(tuned_codes.codes[0], codes.codes[0]);
    assert_ne!(tuned_codes.codes[1], codes.codes[1], "slowmo's code moved by its new take");
    let norm_before = std::fs::read_to_string(weights.join("norm.json")).unwrap();
    assert_eq!(std::fs::read_to_string(tuned_weights.join("norm.json")).unwrap(), norm_before, "statistics kept");
    let styles = ok(cli(&["styles", "--weights", p(&tuned_weights)]));
    assert_eq!(String::from_utf8_lossy(&styles.stdout), "hurried\nslowmo\ntiptoe\n");
    for label in ["tiptoe", "hurried"] {
        let out = root.join(format!("tuned_{label}.bvh"));
        let content = data.join("raw/bandai_plain.BVH");
        ok(cli(&["stylize", p(&content), "--label", label, "--weights", p(&tuned_weights), "-o", p(&out)]));
        assert!(std::fs::read_to_string(&out).unwrap().contains("MOTION"));
    }
    // --from is fixed at a run's start.
    let mut args = vec!["train", "all", "--data", p(&second), "--out", p(&tuned), "--from", p(&run)];
    args.extend(TINY.iter().filter(|a| **a != "--width" && **a != "0.125"));
    assert!(!cli(&args).status.success());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_folder_without_labels_trains_the_unsupervised_model_only() {
    let root = fresh("train-folder-unlabelled");
    let data = make_folder(&root);
    std::fs::remove_file(data.join("labels.csv")).unwrap();
    let run = root.join("run");
    let o = ok(train_all(&data, &run));
    assert!(stderr(&o).contains("no supervised stylizer"), "{}", stderr(&o));
    let weights = run.join("weights");
    assert!(weights.join("unsupervised.bin").is_file() && !weights.join("supervised.bin").exists());
    let styles = ok(cli(&["styles", "--weights", p(&weights)]));
    assert_eq!(String::from_utf8_lossy(&styles.stdout), "");
    let out = root.join("prior.bvh");
    let content = data.join("raw/m21_plain.BVH");
    ok(cli(&["stylize", p(&content), "--prior", "--unsupervised", "--weights", p(&weights), "-o", p(&out)]));
    assert!(out.is_file());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_malformed_labels_csv_is_refused_with_its_line() {
    let root = fresh("train-folder-bad");
    let data = make_folder(&root);
    let run = root.join("run");
    for (csv, wanted) in [
        ("file,style\nm21/slowmo/slowmo_0.bvh,slowmo\nm21/nope.bvh,slowmo\n", "line 3"),
        ("file,content\n", "lacks the column `style`"),
        ("file,label\n", "unknown column `label`"),
        ("file,style\nm21/slowmo/slowmo_0.bvh\n", "line 2: 1 fields"),
        ("file,style\n../x.bvh,slowmo\n", "line 2"),
    ] {
        std::fs::write(data.join("labels.csv"), csv).unwrap();
        let o = train_all(&data, &run);
        assert!(!o.status.success(), "{csv}");
        assert!(stderr(&o).contains(wanted), "{csv}: {}", stderr(&o));
        assert_eq!(stderr(&o).matches(wanted).count(), 1, "said once: {}", stderr(&o));
        assert!(!run.join("ae").exists(), "nothing trained");
    }
    let _ = std::fs::remove_dir_all(&root);
}

/// `train stylizer --from WEIGHTS --style-stats W --content-shape W --content-posture` without an
/// `ae` run (the weights' autoencoder),
/// then `export --from WEIGHTS --sup RUN`: the fine-tuned stylizer replaces the folder's, the
/// shared networks and the other model are written again unchanged (byte for byte: the folder's
/// encodings are kept, re-encoding dequantised weights in their own encoding is exact, and the
/// posture path, a stylizer's option, stays out of the shared part's header).
#[test]
fn a_stylizer_fine_tuned_with_the_style_statistics_loss_replaces_the_weights_stylizer() {
    let root = fresh("style-stats");
    let data = root.join("data");
    let source = fixture("bandai/dataset-2_walk_normal_001_f120.bvh");
    // Labels the shipped weights know, one content: every row pair can be content-paired.
    let mut csv = String::from("file,style,content\n");
    for (label, speed) in [("old", 0.5), ("angry", 2.0)] {
        std::fs::create_dir_all(data.join(label)).unwrap();
        for (take, start) in [0usize, 10].into_iter().enumerate() {
            let name = format!("{label}/{label}_{take}.bvh");
            std::fs::write(data.join(&name), generate(&source, start, speed)).unwrap();
            csv.push_str(&format!("{name},{label},walk\n"));
        }
    }
    std::fs::write(data.join("labels.csv"), csv).unwrap();
    let weights = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/weights");
    let run = root.join("run");
    let common = ["--steps", "2", "--window", "32", "--batch", "4", "--threads", "1", "--eval-every", "0"];
    let mut args = vec!["train", "stylizer", "--data", p(&data), "--out", p(&run), "--from", p(&weights)];
    args.extend_from_slice(&common);
    args.extend_from_slice(&["--style-stats", "1", "--content-shape", "1", "--content-posture"]);
    ok(cli(&args));
    let losses = rundir::CsvTable::read(&run.join(rundir::LOSS_CSV)).unwrap();
    let col = |name: &str| losses.columns.iter().position(|c| c == name).unwrap_or_else(|| panic!("a {name} column"));
    let (stats, shape) = (col("style_stats"), col("content_shape"));
    let rows = losses.up_to(2);
    assert_eq!(rows.len(), 2);
    assert!(rows.iter().all(|r| r[stats] > 0.0), "every step had content-paired swaps: {rows:?}");
    assert!(rows.iter().all(|r| r[shape] > 0.0), "every step judged the swaps' shapes: {rows:?}");
    let config: serde_json::Value = rundir::read_json(&run.join("config.json")).unwrap();
    let w = &config["train"]["stylizer_weights"];
    assert_eq!((w["style_stats"].as_f64(), w["content_shape"].as_f64()), (Some(1.0), Some(1.0)), "{config}");
    assert_eq!(config["model"]["content_posture"], true, "{config}");

    let out = root.join("weights");
    ok(cli(&["export", "--from", p(&weights), "--sup", p(&run), "-o", p(&out)]));
    let bytes = |dir: &Path, f: &str| std::fs::read(dir.join(f)).unwrap();
    assert!(bytes(&out, "shared.bin") == bytes(&weights, "shared.bin"), "the shared networks are unchanged");
    assert!(bytes(&out, "unsupervised.bin") == bytes(&weights, "unsupervised.bin"));
    assert!(bytes(&out, "supervised.bin") != bytes(&weights, "supervised.bin"), "the stylizer is the run's");
    let exported = motion_stylizer::stylize::Weights::load_dir(&out).unwrap();
    assert!(
        exported.model(motion_stylizer::stylize::Setting::Supervised).unwrap().config.content_posture,
        "the run's posture path is exported"
    );
    let manifest: Manifest = rundir::read_json(&out.join("manifest.json")).unwrap();
    let old: Manifest = rundir::read_json(&weights.join("manifest.json")).unwrap();
    let (sup, old_sup) = (&manifest.models[0], &old.models[0]);
    assert_eq!(sup.setting, "supervised");
    assert_eq!(sup.stages.len(), old_sup.stages.len() + 1, "the fine-tune is one more stage");
    assert!(sup.label_codes.is_none(), "new networks need new label codes");
    let (unsup, old_unsup) = (&manifest.models[1], &old.models[1]);
    assert!(old_unsup.neutral_code.is_some(), "the shipped unsupervised model has its neutral code");
    assert_eq!(unsup.neutral_code, old_unsup.neutral_code, "the unchanged unsupervised model keeps its code");
    // No encoding flags: the folder's own encodings are kept (the shipped weights are 8-bit).
    assert_eq!(sup.encoding, old_sup.encoding, "the fine-tuned stylizer is written in the folder's encoding");
    assert_eq!(manifest.shared.as_ref().map(|s| &s.encoding), old.shared.as_ref().map(|s| &s.encoding));
    // Fine-tuning with the paper's losses on an `ae` run of other weights is refused by export.
    let other = root.join("other");
    let mut args = vec!["train", "stylizer", "--data", p(&data), "--out", p(&other)];
    args.extend_from_slice(&common);
    let refused = cli(&args);
    assert!(!refused.status.success() && stderr(&refused).contains("--from WEIGHTS"), "{}", stderr(&refused));
    let _ = std::fs::remove_dir_all(&root);
}
