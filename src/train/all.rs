//! `motion-stylizer train all --data DIR --out RUN`: the whole pipeline in one command.
//!
//! The stages run in order, each in its own run folder under `RUN` — `ae` (autoencoder +
//! regressor), then the stylizers the labels allow (`sup`: supervised, when at least one file is
//! labelled; `unsup`: unsupervised, always), then `classifier` (the style classifier, with at
//! least two labels) — and the result is exported to `RUN/weights/` ([`super::export`]) with the
//! supervised model's label codes and the classifier (`classifier.bin`, for `eval --classifier`).
//!
//! **Steps.** `--steps N` scales every stage as the shipped weights were trained (autoencoder
//! 12,000, stylizers 16,000, classifier 3,000): `ae` N, each stylizer ⌈4N/3⌉, the classifier
//! ⌈N/4⌉, every stage at least one step.
//!
//! **Resuming.** Running the same command again continues: a stage whose folder holds a run is
//! resumed (with its own settings; a different `--width`, `--seed`, … is an error) up to its step
//! count, a finished one is skipped, and the export is redone.
//!
//! **Fine-tuning** (`--from WEIGHTS`): every stage starts from the weights folder's networks and
//! keeps its width and normalisation statistics; the data's new labels are added after the old
//! ones ([`super::finetune`]). The old labels' codes are merged with the data's by take count
//! ([`super::label_codes::merge_old_codes`]): one without files keeps its code.
//!
//! **Report.** What was used is printed and written to `RUN/report.json` ([`Report`]): the files
//! (found, used, held out, skipped and why), every label's files and minutes, the unlabelled
//! files, each stage's steps and time.

use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::progress::{ProgressMode, format_duration};
use super::settings::{SettingChoices, TrainOptions};
use super::{Stage, rundir};
use crate::dataset::folder::{self, FolderListing};
use crate::dataset::{Split, corpus};
use crate::model::device::DeviceName;

/// Frames per second of imported motion.
const FPS: f64 = 30.0;

/// What `train all` is asked to do.
#[derive(Clone, Debug)]
pub struct AllOptions {
    pub data: PathBuf,
    pub out: PathBuf,
    /// Fine-tuning: every stage starts from this weights folder ([`super::finetune`]).
    pub from: Option<PathBuf>,
    /// Steps of the autoencoder stage; the others are scaled from it (module docs).
    pub steps: u64,
    pub settings: SettingChoices,
    pub threads: Option<usize>,
    /// Held-out split file (Bandai-Namco data only).
    pub split: PathBuf,
    pub checkpoint_every: u64,
    pub eval_every: u64,
    pub eval_windows: usize,
    pub log_every: u64,
    /// Every stage's compute device.
    pub device: DeviceName,
    pub progress: ProgressMode,
    pub command: String,
}

/// One label's share of the data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LabelUse {
    pub label: String,
    /// Files imported (training + held out) and their length, minutes at 30 fps.
    pub files: usize,
    pub heldout: usize,
    pub minutes: f64,
}

/// A file that could not be used.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    pub file: String,
    pub error: String,
}

/// One stage of the pipeline as it ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageUse {
    /// `ae`, `sup`, `unsup`, `classifier`: its folder under RUN.
    pub name: String,
    pub steps: u64,
    /// Wall seconds of this invocation (0 when it was already done).
    pub seconds: f64,
}

/// What `train all` used (`RUN/report.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    pub data: String,
    /// `"folder"` (labels.csv) or `"bandai-namco"`.
    pub layout: String,
    /// BVH files found, imported, held out.
    pub files_found: usize,
    pub files_used: usize,
    pub files_heldout: usize,
    pub minutes: f64,
    /// Per label, in one-hot order, then the unlabelled files (label `""`).
    pub labels: Vec<LabelUse>,
    pub unlabelled: LabelUse,
    pub skipped: Vec<Skipped>,
    pub stages: Vec<StageUse>,
    pub weights: String,
}

impl Report {
    /// The report as lines of text.
    pub fn text(&self) -> String {
        let mut s = format!(
            "data {} ({}): {} BVH files found, {} used ({:.1} min), {} held out, {} skipped\n",
            self.data,
            self.layout,
            self.files_found,
            self.files_used,
            self.minutes,
            self.files_heldout,
            self.skipped.len()
        );
        for l in self.labels.iter().chain(std::iter::once(&self.unlabelled)) {
            let name = if l.label.is_empty() { "(unlabelled)" } else { &l.label };
            s.push_str(&format!("  {name}: {} files, {:.2} min, {} held out\n", l.files, l.minutes, l.heldout));
        }
        for k in &self.skipped {
            s.push_str(&format!("  skipped {}: {}\n", k.file, k.error));
        }
        for st in &self.stages {
            s.push_str(&format!(
                "  stage {}: {} steps ({} this run)\n",
                st.name,
                st.steps,
                format_duration(st.seconds)
            ));
        }
        s.push_str(&format!("weights -> {}\n", self.weights));
        s
    }
}

/// The steps of each stage for `--steps n` (module docs).
pub fn stage_steps(n: u64) -> [u64; 3] {
    let n = n.max(1);
    [n, (n * 4).div_ceil(3).max(1), n.div_ceil(4).max(1)]
}

/// Imports the data once to say what will be used (and to fail early on bad data).
fn survey(opts: &AllOptions, threads: usize, say: &dyn Fn(String)) -> anyhow::Result<Report> {
    let mut report = Report {
        data: opts.data.display().to_string(),
        layout: String::new(),
        files_found: 0,
        files_used: 0,
        files_heldout: 0,
        minutes: 0.0,
        labels: Vec::new(),
        unlabelled: LabelUse { label: String::new(), files: 0, heldout: 0, minutes: 0.0 },
        skipped: Vec::new(),
        stages: Vec::new(),
        weights: opts.out.join("weights").display().to_string(),
    };
    let progress = |done: usize, total: usize| {
        if done == total {
            say(format!("imported {done}/{total} files"));
        }
    };
    // (label, held out, frames) per file used.
    let mut used: Vec<(Option<usize>, bool, usize)> = Vec::new();
    let names: Vec<String>;
    if folder::is_bandai_layout(&opts.data) {
        report.layout = "bandai-namco".into();
        let text = std::fs::read_to_string(&opts.split)
            .with_context(|| format!("cannot read the split file {} (--split)", opts.split.display()))?;
        let split = Split::parse(&text).with_context(|| format!("split file {}", opts.split.display()))?;
        let c = corpus::load(&opts.data, &split, threads, progress)
            .with_context(|| format!("cannot load the data in {}", opts.data.display()))?;
        report.files_found = c.train.len() / 2 + c.heldout.len() + c.failed.len();
        for clip in c.train.iter().filter(|c| !c.mirrored) {
            used.push((clip.style.map(|s| s.index()), false, clip.features.frames()));
        }
        for clip in &c.heldout {
            used.push((clip.style.map(|s| s.index()), true, clip.features.frames()));
        }
        for (path, why) in c.failed {
            report.skipped.push(Skipped { file: path.display().to_string(), error: why });
        }
        names = c.labels;
    } else {
        report.layout = "folder".into();
        let listing = FolderListing::read(&opts.data)?;
        let heldout: BTreeSet<String> = folder::choose_heldout(&listing).into_iter().collect();
        report.files_found = listing.files.len();
        let (_, files) = folder::load(&opts.data, &listing, &heldout, threads, progress)?;
        for f in files {
            match f.result {
                Ok(frames) => used.push((f.style, f.heldout, frames)),
                Err(error) => report.skipped.push(Skipped { file: f.file, error }),
            }
        }
        names = listing.labels.names;
    }
    report.labels = names.iter().map(|n| LabelUse { label: n.clone(), files: 0, heldout: 0, minutes: 0.0 }).collect();
    for (style, held, frames) in used {
        let slot = match style {
            Some(s) if s < report.labels.len() => &mut report.labels[s],
            _ => &mut report.unlabelled,
        };
        slot.files += 1;
        slot.heldout += usize::from(held);
        slot.minutes += frames as f64 / FPS / 60.0;
        report.files_used += 1;
        report.files_heldout += usize::from(held);
        report.minutes += frames as f64 / FPS / 60.0;
    }
    Ok(report)
}

/// Runs the pipeline (module docs); returns the report.
pub fn train_all(opts: &AllOptions) -> anyhow::Result<Report> {
    anyhow::ensure!(opts.steps >= 1, "--steps must be at least 1");
    opts.settings.validate()?;
    let say = |line: String| {
        if opts.progress != ProgressMode::Quiet {
            eprintln!("{line}");
        }
    };
    let threads = opts.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).max(1);
    let mut report = survey(opts, threads, &say)?;
    say(report
        .text()
        .lines()
        .filter(|l| !l.starts_with("weights") && !l.contains("stage "))
        .collect::<Vec<_>>()
        .join("\n"));
    let labelled: usize = report.labels.iter().map(|l| l.files).sum();
    let with_files = report.labels.iter().filter(|l| l.files > 0).count();

    std::fs::create_dir_all(&opts.out).with_context(|| format!("cannot create {}", opts.out.display()))?;
    let [ae_steps, stylizer_steps, classifier_steps] = stage_steps(opts.steps);
    let ae_dir = opts.out.join("ae");
    let mut plan: Vec<(&str, Stage, u64)> = vec![("ae", Stage::Ae, ae_steps)];
    if labelled > 0 {
        plan.push((
            "sup",
            Stage::Stylizer { ae: Some(ae_dir.clone()), supervised: true, extra: Default::default() },
            stylizer_steps,
        ));
    } else {
        say("no labelled files: no supervised stylizer (label- and motion-based with labels need labels.csv)".into());
    }
    plan.push((
        "unsup",
        Stage::Stylizer { ae: Some(ae_dir.clone()), supervised: false, extra: Default::default() },
        stylizer_steps,
    ));
    if with_files >= 2 {
        plan.push(("classifier", Stage::Classifier, classifier_steps));
    } else {
        say("fewer than two labels with files: no style classifier".into());
    }
    let total = plan.len();
    for (i, (name, stage, steps)) in plan.into_iter().enumerate() {
        let dir = opts.out.join(name);
        let resume = dir.join(rundir::CONFIG).is_file();
        say(format!(
            "[{}/{total}] {name}: {} steps{} -> {}",
            i + 1,
            steps,
            if resume { " (resuming)" } else { "" },
            dir.display()
        ));
        let stage_opts = TrainOptions {
            data: opts.data.clone(),
            out: dir,
            resume,
            from: opts.from.clone(),
            steps,
            settings: opts.settings.clone(),
            checkpoint_every: opts.checkpoint_every,
            eval_every: opts.eval_every,
            eval_windows: opts.eval_windows,
            threads: opts.threads,
            split: opts.split.clone(),
            log_every: opts.log_every,
            device: opts.device,
            progress: opts.progress,
            command: opts.command.clone(),
        };
        let t = Instant::now();
        super::train(&stage, &stage_opts).with_context(|| format!("stage {name}"))?;
        report.stages.push(StageUse { name: name.into(), steps, seconds: t.elapsed().as_secs_f64() });
    }

    let weights = opts.out.join("weights");
    let has = |name: &str| report.stages.iter().any(|s| s.name == name);
    let (sup, unsup) = (opts.out.join("sup"), opts.out.join("unsup"));
    say(format!("exporting -> {}", weights.display()));
    let encodings = super::export::Encodings::default();
    super::export::export_runs(
        &ae_dir,
        has("sup").then_some(sup.as_path()),
        Some(unsup.as_path()),
        &weights,
        encodings,
    )?;
    if has("classifier") {
        let bundle = opts.out.join("classifier").join(super::classifier::BUNDLE);
        let bytes = std::fs::read(&bundle).with_context(|| format!("cannot read {}", bundle.display()))?;
        rundir::write_atomic(&weights.join(super::classifier::BUNDLE), &bytes)?;
    }
    if has("sup") {
        write_label_codes(opts, &weights, threads, &say)?;
    }
    rundir::write_json(&opts.out.join("report.json"), &report)?;
    Ok(report)
}

/// The supervised model's label codes from the labelled training files, into the exported
/// manifest.
fn write_label_codes(
    opts: &AllOptions,
    weights_dir: &Path,
    threads: usize,
    say: &dyn Fn(String),
) -> anyhow::Result<()> {
    use super::label_codes::{LabelledMotion, label_codes_of};
    use crate::dataset::Style;
    use crate::stylize::{Manifest, Setting, Weights};
    let weights = Weights::load_dir(weights_dir).with_context(|| format!("cannot load {}", weights_dir.display()))?;
    let mut motions: Vec<(String, usize, Style, crate::Motion)> = Vec::new();
    if folder::is_bandai_layout(&opts.data) {
        let text = std::fs::read_to_string(&opts.split)
            .with_context(|| format!("cannot read the split file {}", opts.split.display()))?;
        let split = Split::parse(&text).with_context(|| format!("split file {}", opts.split.display()))?;
        for (take, m) in crate::eval::import_takes(&opts.data, threads, |t| !split.is_heldout(t))? {
            if let Ok(m) = m {
                motions.push((take.stem(), usize::from(take.set), take.style(), m));
            }
        }
    } else {
        let read = FolderListing::read(&opts.data)?;
        let heldout: BTreeSet<String> = folder::choose_heldout(&read).into_iter().collect();
        // Indices of the exported label set (a fine-tuned run's has the old labels first).
        let listing = read.relabelled(weights.styles()).context("the exported labels lack a label of labels.csv")?;
        let items: Vec<(String, usize)> = listing
            .annotations()
            .into_iter()
            .zip(&listing.files)
            .filter_map(|((style, _), f)| style.filter(|_| !heldout.contains(f)).map(|s| (f.clone(), s)))
            .collect();
        let imported = corpus::par_map(
            &items,
            threads,
            |(f, _)| {
                let text = std::fs::read_to_string(opts.data.join(f)).map_err(|e| e.to_string())?;
                crate::skeleton::import_bvh(&text).map(|i| i.motion).map_err(|e| e.to_string())
            },
            |_, _| {},
        );
        for ((f, s), m) in items.into_iter().zip(imported) {
            if let Ok(m) = m {
                motions.push((f, 0, Style(s as u8), m));
            }
        }
    }
    let items: Vec<LabelledMotion> = motions
        .iter()
        .map(|(name, group, style, motion)| LabelledMotion { name: name.clone(), group: *group, style: *style, motion })
        .collect();
    let mut codes = label_codes_of(&weights, &items, opts.command.clone(), |_, _| {})?;
    // Fine-tuned: the old labels' codes merged with the new takes' by take count.
    if let Some(from) = &opts.from {
        let old: Manifest = rundir::read_json(&from.join("manifest.json"))?;
        let old_codes = old.entry(Setting::Supervised).and_then(|m| m.label_codes.as_ref());
        if let Some(old_codes) = old_codes {
            super::label_codes::merge_old_codes(&mut codes, old_codes);
        }
    }
    say(format!("label codes from {} labelled training files", items.len()));
    let path = weights_dir.join("manifest.json");
    let mut manifest: Manifest = rundir::read_json(&path)?;
    let entry = manifest.entry_mut(Setting::Supervised).context("the exported manifest lists no supervised model")?;
    entry.label_codes = Some(codes);
    // The unsupervised model's neutral code, where its network is new (an export clears it with
    // the network it belongs to; kept where the network is the `--from` weights').
    if let Some(entry) = manifest.entry_mut(Setting::Unsupervised).filter(|m| m.neutral_code.is_none()) {
        entry.neutral_code = super::label_codes::neutral_code_of(&weights, &items, opts.command.clone())?;
    }
    rundir::write_atomic(&path, manifest.to_json()?.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::stage_steps;

    #[test]
    fn steps_scale_like_the_shipped_runs_and_never_reach_zero() {
        assert_eq!(stage_steps(12_000), [12_000, 16_000, 3_000]);
        assert_eq!(stage_steps(1), [1, 2, 1]);
        assert_eq!(stage_steps(0), [1, 2, 1]);
        assert_eq!(stage_steps(3), [3, 4, 1]);
    }
}
