//! Training runs (native only): `motion-stylizer train
//! ae|stylizer|classifier|content-classifier|all` and `motion-stylizer export`, on the Bandai-Namco
//! data or on a folder of one's own BVH files with a `labels.csv` ([`crate::dataset::folder`]; the
//! run keeps the folder's label set and held-out files in its `config.json`). [`all`] runs every
//! stage and the export in one command.
//!
//! Two stages, as the paper: [`Stage::Ae`] trains the motion autoencoder and the global motion
//! regressor ([`AeTrainer`]) on random windows of the training takes; [`Stage::Stylizer`] trains
//! the stylizer — content encoder, style encoder and generator ([`StylizerTrainer`]) — on latents
//! of a frozen autoencoder from an `ae` run, supervised (the unified style labels) or not. A third,
//! [`Stage::Classifier`], trains the evaluation's style classifier ([`ClassifierTrainer`]);
//! [`Stage::ContentClassifier`] the same network on the content classes (`eval`'s content
//! accuracy and FID). [`label_codes`] computes the supervised model's label codes from a trained
//! bundle.
//!
//! The pieces: what a run is asked for and fixed with ([`settings`]); its data ([`data`]: the takes,
//! windows and batches of [`sampler`], the held-out sets of [`eval`]); its folder ([`rundir`]:
//! settings, logs, checkpoints); the loop ([`runner`]), the same for every stage, over a small
//! [`Trainer`] trait each stage's trainer implements; losses ([`losses`]) and the optimizer
//! ([`optim`]). Shipping the results: [`export`].
//!
//! # A run
//!
//! 1. The takes are loaded ([`corpus::load`]) and split by the held-out file; the training clips
//!    (mirrors included) give the normalisation statistics (`norm.json`, written by the `ae` run;
//!    a `stylizer` run copies its autoencoder's). Every clip is normalised once, before batching.
//! 2. Each step draws a batch of windows, runs one Adam step and appends a row to `loss.csv`
//!    (step, elapsed seconds, every term of the step report, learning rates).
//! 3. Every `eval_every` steps and at the end: held-out evaluation → `eval.csv`. Every
//!    `checkpoint_every` steps and at the end: `checkpoint.bin` (atomic), `run.json`.
//!
//! # Resuming
//!
//! A new run refuses an existing non-empty folder. `resume` continues from `checkpoint.bin` up to
//! `steps` in total, with the run's own settings (`config.json`; a differing `--seed`, `--width`,
//! `--batch`, `--window` or stage setting is an error). Restored exactly: the network weights
//! (f32), the step count, the window sampler's generator (the resumed run draws the very batches
//! a straight run would), Adam's moments and step counts (`optimizer.bin`, written before the
//! checkpoint and tagged with its step; a checkpoint from before this existed resumes with fresh
//! moments, with a warning) and the logs (rows after the checkpoint are dropped). Not restored:
//! the trainers' noise generators and Burn's device generator (dropout masks), which restart from
//! a seed derived from the run's seed and the step. A resumed run is therefore statistically
//! equivalent to a straight one, not bit-identical. Progress after the last checkpoint is lost
//! when a run is interrupted (Ctrl-C included; nothing is saved on a signal).
//!
//! [`corpus::load`]: crate::dataset::corpus::load

pub mod ae;
pub mod all;
pub mod classifier;
pub mod data;
pub mod eval;
pub mod export;
pub mod finetune;
pub mod label_codes;
pub mod logs;
pub mod losses;
pub mod optim;
pub mod parallel;
pub mod progress;
pub mod recipe;
pub mod rundir;
pub mod runner;
pub mod sampler;
pub mod settings;
pub mod statistics;
pub mod stylizer;
pub mod trainer;

use crate::model::device::DeviceName;
use crate::stylize::Setting;
use anyhow::{Context, ensure};
use burn::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

pub use ae::{AeNets, AeStepReport, AeTrainer};
pub use classifier::{ClassifierStepReport, ClassifierTrainer};
use data::TrainData;
pub use losses::StylizerWeights;
pub use progress::ProgressMode;
use rundir::{AE_COPY, EVAL_CSV, LOSS_CSV, load_module};
pub use settings::{
    DEFAULT_BATCH, DEFAULT_SEED, DEFAULT_SPLIT, DEFAULT_WIDTH, DEFAULT_WINDOW, SettingChoices, Settings, TrainConfig,
    TrainOptions, check_window,
};
pub use stylizer::{StylizerBatch, StylizerStepReport, StylizerTrainer};
pub use trainer::{PhaseTimes, StepReport, Trainer};

/// Salt of the window sampler's seed (so its stream differs from the weight initialisation's,
/// which is seeded with the run's seed itself).
const SAMPLER_SALT: u64 = 0x5a3b_1e00_c0ff_ee00;

/// Which stage to train.
#[derive(Clone, Debug, PartialEq)]
pub enum Stage {
    /// Motion autoencoder + global motion regressor.
    Ae,
    /// Stylizer on the frozen autoencoder of an `ae` run (`ae`: its folder or a checkpoint file;
    /// needed for a new run, ignored on resume: the run keeps its own copy).
    /// `extra`: what the run adds to the paper's recipe ([`losses::StylizerExtras`]: the weights of
    /// the style-statistics loss on content-paired swaps and the content-shape loss on every swap,
    /// 0: the paper's losses only; the cross-content swaps; the posture path).
    Stylizer { ae: Option<PathBuf>, supervised: bool, extra: losses::StylizerExtras },
    /// The evaluation's style classifier (training takes only; see [`classifier`]).
    Classifier,
    /// The evaluation's content classifier: the same network and training on the content classes
    /// ([`crate::dataset::CONTENTS`]) instead of the styles, content-balanced.
    ContentClassifier,
}

impl Stage {
    pub fn name(&self) -> &'static str {
        match self {
            Stage::Ae => "ae",
            Stage::Stylizer { .. } => "stylizer",
            Stage::Classifier => "classifier",
            Stage::ContentClassifier => "content-classifier",
        }
    }
}

/// What a run reached.
#[derive(Clone, Debug, PartialEq)]
pub struct TrainSummary {
    pub step: u64,
    /// The last step's loss terms and the last evaluation, by name.
    pub losses: Vec<(String, f64)>,
    pub heldout: Vec<(String, f64)>,
}

fn seed_for_segment(seed: u64, step: u64) -> u64 {
    if step == 0 { seed } else { seed ^ step.wrapping_mul(0x9e37_79b9_7f4a_7c15) }
}

/// The summary of a run that is already done, from its logs.
fn summary_from_logs(out: &std::path::Path, step: u64) -> anyhow::Result<TrainSummary> {
    let named = |path: PathBuf| -> anyhow::Result<Vec<(String, f64)>> {
        let t = rundir::CsvTable::read(&path)?;
        Ok(match t.up_to(step).last() {
            Some(row) => t.columns.iter().cloned().zip(row.iter().copied()).skip(2).collect(),
            None => Vec::new(),
        })
    };
    Ok(TrainSummary { step, losses: named(out.join(LOSS_CSV))?, heldout: named(out.join(EVAL_CSV))? })
}

/// The judges of a stylizer run's swaps, checked before the run folder is written: each names
/// what its loss needs ([`stylizer::read_judge`]) and, for a new run whose judge has its run's
/// `norm.json` beside it, reads features normalised as the stylizer's (a resumed run's were
/// checked when it started).
fn check_judges(run: &rundir::OpenRun, norm: &crate::features::NormStats) -> anyhow::Result<()> {
    for (judge, judged, flag) in [
        (&run.content_judge, stylizer::Judged::Content, "--content-judge"),
        (&run.style_judge, stylizer::Judged::Style, "--style-judge"),
    ] {
        let Some(judge) = judge else { continue };
        stylizer::read_judge(&judge.bytes, judged, &run.config.model).with_context(|| flag.to_string())?;
        if let Some(own) = &judge.norm {
            ensure!(
                own == norm,
                "{flag}: the classifier was trained on other normalisation statistics than the stylizer's (its run's \
                 norm.json differs)"
            );
        }
    }
    Ok(())
}

/// Trains `stage` as `opts` asks (see the module docs).
pub fn train(stage: &Stage, opts: &TrainOptions) -> anyhow::Result<TrainSummary> {
    let started = Instant::now();
    opts.validate()?;
    let device = crate::model::device::open(opts.device)?;
    let mut run = rundir::open(stage, opts)?;
    let start_step = run.start_step();
    if opts.resume && start_step >= opts.steps {
        eprintln!("{}: already at step {start_step} (--steps {}); nothing to do", opts.out.display(), opts.steps);
        return summary_from_logs(&opts.out, start_step);
    }
    let say = |line: String| {
        if opts.progress != ProgressMode::Quiet {
            eprintln!("{line}");
        }
    };
    let device_name = (opts.device != DeviceName::Cpu).then(|| {
        let adapter = crate::model::device::adapter_name(&device).unwrap_or_else(|| "?".into());
        format!("{} ({adapter})", opts.device)
    });
    if let Some(name) = &device_name {
        say(format!("device: {name}"));
    }
    let t_load = Instant::now();
    let data = TrainData::load(opts, &mut run.config, run.norm.take(), &device, &say)?;
    check_judges(&run, &data.norm)?;
    let log = rundir::begin_segment(opts, &run, &data.norm, t_load.elapsed().as_secs_f64(), device_name)?;
    let start = runner::Start { resume_from: run.resume_from.as_ref(), log, started };

    let config = &run.config;
    let (model, train) = (config.model.clone(), config.train.clone());
    let seed = seed_for_segment(config.settings.seed, start_step);
    // Fine-tuning: a run's first segment starts from the weights folder's networks.
    let from = config.from.as_deref().filter(|_| start_step == 0).map(std::path::Path::new);
    let report_grown = |grown: Vec<String>| {
        if !grown.is_empty() {
            say(format!("grown for the new labels or added: {}", grown.join(", ")));
        }
    };
    match stage {
        Stage::Ae => {
            let mut trainer = AeTrainer::new(model, train, &device, seed);
            if let Some(dir) = from {
                let m = finetune::load_model(dir, None)?;
                let (nets, grown) = finetune::grow(
                    &AeNets { autoencoder: m.autoencoder, regressor: m.regressor },
                    AeNets {
                        autoencoder: trainer.autoencoder.clone().valid(),
                        regressor: trainer.regressor.clone().valid(),
                    },
                )?;
                report_grown(grown);
                trainer.load_weights(&rundir::module_bytes(nets)?)?;
                say(format!("autoencoder and regressor start from {}", dir.display()));
            }
            runner::run(trainer, &data, config, opts, start, &say)
        }
        Stage::Stylizer { .. } => {
            let ae =
                run.ae.as_ref().with_context(|| format!("{} holds no autoencoder ({AE_COPY})", opts.out.display()))?;
            let nets = load_module(AeNets::new(&model, &device), &ae.weights)
                .context("the autoencoder checkpoint does not fit the run's configuration")?;
            let supervised = model.supervised;
            let mut trainer = StylizerTrainer::new(model, train, nets.autoencoder, &device, seed);
            if let Some(judge) = &run.content_judge {
                trainer.set_content_judge(&judge.bytes, &device).context("--content-judge")?;
                say("the swaps are judged by the content classifier (content-class loss)".to_string());
            }
            if let Some(judge) = &run.style_judge {
                trainer.set_style_judge(&judge.bytes, &device).context("--style-judge")?;
                say("the swaps are judged by the style classifier (style-class loss)".to_string());
            }
            if let Some(dir) = from {
                let setting = if supervised { Setting::Supervised } else { Setting::Unsupervised };
                let m = finetune::load_model(dir, Some(setting))?;
                let (net, grown) = finetune::grow(&m.stylizer, trainer.net.clone().valid())?;
                report_grown(grown);
                trainer.load_weights(&rundir::module_bytes(net)?)?;
                say(format!("the {setting} stylizer starts from {}", dir.display()));
            }
            runner::run(trainer, &data, config, opts, start, &say)
        }
        Stage::Classifier | Stage::ContentClassifier => {
            let mut trainer = ClassifierTrainer::new(model, train, &device, seed);
            if let Some(dir) = from.filter(|_| *stage == Stage::Classifier) {
                match finetune::load_old_classifier(dir)? {
                    Some((_, old)) => {
                        let (net, grown) = finetune::grow(&old, trainer.classifier.clone().valid())?;
                        report_grown(grown);
                        trainer.load_weights(&rundir::module_bytes(net)?)?;
                        say(format!("the classifier starts from {}", dir.display()));
                    }
                    None => say(format!("{} has no classifier.bin: the classifier starts fresh", dir.display())),
                }
            }
            runner::run(trainer, &data, config, opts, start, &say)
        }
    }
}
