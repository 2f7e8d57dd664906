//! Training runs on the Bandai-Namco data (native only): `motion-stylizer train ae|stylizer` and
//! `motion-stylizer export`.
//!
//! Two stages, as the paper: [`Stage::Ae`] trains the motion autoencoder and the global motion
//! regressor ([`AeTrainer`]) on random windows of the training takes; [`Stage::Stylizer`] trains
//! the content encoder, style encoder and generator ([`StylizerTrainer`]) on latents of a frozen
//! autoencoder from an `ae` run, supervised (the unified style labels) or not. Windows and
//! batches: [`sampler`]. Held-out metrics: [`eval`]. Files of a run folder: [`rundir`].
//! Shipping the results: [`export`].
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

pub mod classifier;
pub mod eval;
pub mod export;
pub mod progress;
pub mod rundir;
pub mod sampler;

use anyhow::{Context, bail, ensure};
use burn::module::Module;
use burn::prelude::*;
use burn::store::ModuleRecord;
use burn::tensor::Bytes;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::dataset::corpus::{self, Clip};
use crate::dataset::{STYLES, Split};
use crate::features::{Features, NormStats};
use crate::model::config::FRAME_MULTIPLE;
use crate::model::train::{AeTrainer, ClassifierTrainer, StylizerBatch, StylizerTrainer};
use crate::model::{GlobalRegressor, ModelConfig, MotionAutoencoder, StylizerNet, TrainConfig};
use eval::HeldoutSet;
pub use progress::ProgressMode;
use progress::{Progress, format_duration};
use rundir::{Checkpoint, CheckpointMeta, CsvLog, RunConfig, RunLog, Segment};
use sampler::{SamplerRng, WindowSampler, batch_tensor};

/// Default training window, frames. Bandai takes are short (set 2's median is 117 frames); at 64
/// frames 84 % of all takes contribute and 48 % are long enough for two disjoint windows.
pub const DEFAULT_WINDOW: usize = 64;
pub const DEFAULT_BATCH: usize = 16;
/// Default width factor relative to the paper's sizes (the paper's width costs ~3× more per step).
pub const DEFAULT_WIDTH: f64 = 0.5;
pub const DEFAULT_SEED: u64 = 1;
pub const DEFAULT_SPLIT: &str = "assets/split/heldout.txt";

/// Salt of the window sampler's seed (so its stream differs from the weight initialisation's,
/// which is seeded with the run's seed itself).
const SAMPLER_SALT: u64 = 0x5a3b_1e00_c0ff_ee00;

const AE_TERMS: [&str; 8] = [
    "ae_loss",
    "reconstruction",
    "sparsity",
    "smoothness",
    "kl",
    "regressor_loss",
    "ae_grad_norm",
    "regressor_grad_norm",
];
const STYLIZER_TERMS: [&str; 9] = [
    "loss",
    "rec_latent",
    "rec_pose",
    "cyc_latent",
    "cyc_pose",
    "kl",
    "hsa",
    "encoders_grad_norm",
    "generator_grad_norm",
];

/// Which stage to train.
#[derive(Clone, Debug, PartialEq)]
pub enum Stage {
    /// Motion autoencoder + global motion regressor.
    Ae,
    /// Stylizer on the frozen autoencoder of an `ae` run (`ae`: its folder or a checkpoint file;
    /// needed for a new run, ignored on resume: the run keeps its own copy).
    Stylizer { ae: Option<PathBuf>, supervised: bool },
    /// The evaluation's style classifier (training takes only; see [`classifier`]).
    Classifier,
}

impl Stage {
    pub fn name(&self) -> &'static str {
        match self {
            Stage::Ae => "ae",
            Stage::Stylizer { .. } => "stylizer",
            Stage::Classifier => "classifier",
        }
    }
}

/// Options of a training run. `None` settings take the defaults (new run) or the run's own
/// (resume).
#[derive(Clone, Debug)]
pub struct TrainOptions {
    pub stage: Stage,
    /// Folder with `dataset-1/` and `dataset-2/` unpacked.
    pub data: PathBuf,
    /// The run folder.
    pub out: PathBuf,
    /// Held-out split file (new runs; a resumed run uses its own).
    pub split: PathBuf,
    pub resume: bool,
    /// Total steps to reach.
    pub steps: u64,
    pub seed: Option<u64>,
    pub width: Option<f64>,
    pub batch: Option<usize>,
    pub window: Option<usize>,
    pub checkpoint_every: u64,
    /// 0: only at the end.
    pub eval_every: u64,
    /// At most this many held-out windows (and pairs).
    pub eval_windows: usize,
    /// Threads of the corpus loader.
    pub threads: usize,
    /// Plain progress lines every this many steps.
    pub log_every: u64,
    pub progress: ProgressMode,
    /// The command line, recorded in `run.json`.
    pub command: String,
}

impl TrainOptions {
    /// Defaults for `stage` with the given data and run folders.
    pub fn new(stage: Stage, data: impl Into<PathBuf>, out: impl Into<PathBuf>) -> Self {
        Self {
            stage,
            data: data.into(),
            out: out.into(),
            split: PathBuf::from(DEFAULT_SPLIT),
            resume: false,
            steps: 20_000,
            seed: None,
            width: None,
            batch: None,
            window: None,
            checkpoint_every: 500,
            eval_every: 1000,
            eval_windows: 512,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            log_every: 100,
            progress: ProgressMode::Auto,
            command: std::env::args().collect::<Vec<_>>().join(" "),
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

/// Autoencoder + regressor: what an `ae` checkpoint holds.
#[derive(Module, Debug)]
pub struct AeNets {
    pub autoencoder: MotionAutoencoder,
    pub regressor: GlobalRegressor,
}

impl AeNets {
    /// Lazily initialised networks (a template to load weights into).
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self { autoencoder: MotionAutoencoder::new(cfg, device), regressor: GlobalRegressor::new(cfg, device) }
    }
}

/// Burnpack bytes (f32) of a module.
pub fn module_bytes<M: Module>(module: M) -> anyhow::Result<Vec<u8>> {
    Ok(module.into_record().into_bytes().map_err(|e| anyhow::anyhow!("cannot serialise weights: {e}"))?.to_vec())
}

/// Loads [`module_bytes`] into `template` (same architecture).
pub fn load_module<M: Module>(template: M, bytes: &[u8]) -> anyhow::Result<M> {
    let record = ModuleRecord::from_bytes(Bytes::from_bytes_vec(bytes.to_vec()))
        .map_err(|e| anyhow::anyhow!("cannot read weights: {e}"))?;
    template.try_load_record(record).map_err(|e| anyhow::anyhow!("weights do not fit the network: {e}"))
}

/// The run's configuration and the autoencoder checkpoint of a stylizer run.
pub fn read_run(dir: &Path) -> anyhow::Result<(RunConfig, Checkpoint)> {
    let config: RunConfig = rundir::read_json(&dir.join(rundir::CONFIG))
        .with_context(|| format!("{} is not a training run folder", dir.display()))?;
    let ckpt = Checkpoint::read(&dir.join(rundir::CHECKPOINT))?;
    Ok((config, ckpt))
}

/// Checks a window length.
pub fn check_window(window: usize) -> anyhow::Result<()> {
    ensure!(
        window >= FRAME_MULTIPLE && window.is_multiple_of(FRAME_MULTIPLE),
        "--window {window}: the window must be a positive multiple of {FRAME_MULTIPLE} frames"
    );
    Ok(())
}

fn seed_for_segment(seed: u64, step: u64) -> u64 {
    if step == 0 { seed } else { seed ^ step.wrapping_mul(0x9e37_79b9_7f4a_7c15) }
}

fn check_same<T: PartialEq + std::fmt::Debug>(what: &str, given: Option<T>, saved: T) -> anyhow::Result<()> {
    if let Some(g) = given
        && g != saved
    {
        bail!("{what} {g:?} differs from the run's {saved:?}: a resumed run keeps its settings");
    }
    Ok(())
}

fn is_nonempty_dir(dir: &Path) -> bool {
    std::fs::read_dir(dir).map(|mut d| d.next().is_some()).unwrap_or(false)
}

/// Where the autoencoder of a stylizer run comes from: a run folder or its checkpoint file.
fn ae_source(path: &Path) -> anyhow::Result<(RunConfig, Vec<u8>, NormStats)> {
    let dir = if path.is_file() { path.parent().unwrap_or(Path::new(".")) } else { path };
    let ckpt_path = if path.is_file() { path.to_path_buf() } else { dir.join(rundir::CHECKPOINT) };
    let config: RunConfig = rundir::read_json(&dir.join(rundir::CONFIG))
        .with_context(|| format!("--ae {}: not an `ae` run folder", path.display()))?;
    ensure!(config.stage == "ae", "--ae {}: a {} run, not an `ae` run", path.display(), config.stage);
    let bytes = std::fs::read(&ckpt_path)
        .with_context(|| format!("--ae {}: no checkpoint yet ({})", path.display(), ckpt_path.display()))?;
    let norm = rundir::read_json(&dir.join(rundir::NORM))?;
    Ok((config, bytes, norm))
}

/// Trains a stage (see the module docs).
pub fn train(opts: &TrainOptions) -> anyhow::Result<TrainSummary> {
    let t_segment = Instant::now();
    ensure!(opts.steps >= 1, "--steps must be at least 1");
    ensure!(opts.checkpoint_every >= 1, "--checkpoint-every must be at least 1");
    if let Some(w) = opts.window {
        check_window(w)?;
    }
    if let Some(b) = opts.batch {
        ensure!(b >= 1, "--batch must be at least 1");
    }
    if let Some(w) = opts.width {
        ensure!(w.is_finite() && w > 0.0, "--width must be positive");
    }
    let out = &opts.out;

    // ---- The run's settings, fixed at its start.
    let (config, resume_from, ae_copy, norm) = if opts.resume {
        let config: RunConfig = rundir::read_json(&out.join(rundir::CONFIG))
            .with_context(|| format!("--resume: {} holds no run to resume", out.display()))?;
        ensure!(
            config.stage == opts.stage.name(),
            "--resume: {} is a {} run, not {}",
            out.display(),
            config.stage,
            opts.stage.name()
        );
        if let Stage::Stylizer { supervised, .. } = &opts.stage {
            check_same("supervised", Some(*supervised), config.supervised.unwrap_or(true))?;
        }
        check_same("--seed", opts.seed, config.seed)?;
        check_same("--width", opts.width, config.width)?;
        check_same("--batch", opts.batch, config.batch)?;
        check_same("--window", opts.window, config.window)?;
        let ckpt_path = out.join(rundir::CHECKPOINT);
        let ckpt = if ckpt_path.exists() { Some(Checkpoint::read(&ckpt_path)?) } else { None };
        let ae_copy =
            if config.stage == "stylizer" { Some(Checkpoint::read(&out.join(rundir::AE_COPY))?) } else { None };
        let norm: NormStats = rundir::read_json(&out.join(rundir::NORM))?;
        (config, ckpt, ae_copy, Some(norm))
    } else {
        ensure!(
            !is_nonempty_dir(out),
            "{} exists and is not empty: pass --resume to continue that run, or choose another --out",
            out.display()
        );
        let seed = opts.seed.unwrap_or(DEFAULT_SEED);
        let batch = opts.batch.unwrap_or(DEFAULT_BATCH);
        let window = opts.window.unwrap_or(DEFAULT_WINDOW);
        let base = RunConfig {
            stage: opts.stage.name().into(),
            supervised: None,
            seed,
            width: opts.width.unwrap_or(DEFAULT_WIDTH),
            batch,
            window,
            model: ModelConfig::scaled(opts.width.unwrap_or(DEFAULT_WIDTH)).with_num_styles(STYLES.len()),
            train: TrainConfig::default(),
            split: opts.split.display().to_string(),
            ae_run: None,
            ae_step: None,
            sampler: String::new(),
            train_clips: 0,
            train_clips_skipped: 0,
            eval_windows: 0,
            heldout_skipped: 0,
        };
        match &opts.stage {
            Stage::Ae => (
                RunConfig {
                    sampler: "uniform over all windows of the training clips (clips weighted by window starts)".into(),
                    ..base
                },
                None,
                None,
                None,
            ),
            Stage::Classifier => (
                RunConfig {
                    sampler: "style-balanced: a style uniformly, a clip of it uniformly, a window of that clip".into(),
                    ..base
                },
                None,
                None,
                None,
            ),
            Stage::Stylizer { ae, supervised } => {
                let ae = ae.as_ref().context("the stylizer stage needs --ae DIR (an `ae` run)")?;
                let (ae_config, ae_bytes, norm) = ae_source(ae)?;
                check_same("--width", opts.width, ae_config.width)?;
                let ae_ckpt = Checkpoint::from_bytes(&ae_bytes)?;
                if opts.split.display().to_string() != ae_config.split {
                    eprintln!(
                        "warning: split {} differs from the autoencoder run's {}",
                        opts.split.display(),
                        ae_config.split
                    );
                }
                let config = RunConfig {
                    supervised: Some(*supervised),
                    width: ae_config.width,
                    model: ae_config.model.clone().with_supervised(*supervised).with_num_styles(STYLES.len()),
                    ae_run: Some(ae.display().to_string()),
                    ae_step: Some(ae_ckpt.meta.step),
                    sampler: "style-balanced: a style uniformly, a clip of it uniformly, two windows of that clip at \
                              independent uniform offsets"
                        .into(),
                    ..base
                };
                (config, None, Some(ae_ckpt), Some(norm))
            }
        }
    };
    let start_step = resume_from.as_ref().map_or(0, |c| c.meta.step);
    if opts.resume && start_step >= opts.steps {
        eprintln!("{}: already at step {start_step} (--steps {}); nothing to do", out.display(), opts.steps);
        return summary_from_logs(out, start_step);
    }

    // ---- Data.
    let t_load = Instant::now();
    let split_text = std::fs::read_to_string(&config.split)
        .with_context(|| format!("cannot read the split file {} (--split)", config.split))?;
    let split = Split::parse(&split_text).with_context(|| format!("split file {}", config.split))?;
    let mut last_report = Instant::now();
    let corpus = corpus::load(&opts.data, &split, opts.threads, |done, total| {
        if opts.progress != ProgressMode::Quiet && (done == total || last_report.elapsed().as_secs_f64() > 5.0) {
            eprintln!("loading takes: {done}/{total}");
            last_report = Instant::now();
        }
    })
    .with_context(|| format!("cannot load the data in {}", opts.data.display()))?;
    for (path, why) in &corpus.failed {
        eprintln!("warning: skipped {}: {why}", path.display());
    }
    let norm = match norm {
        Some(n) => n,
        None => corpus.norm_stats().context("normalisation statistics")?,
    };
    let mut config = config;
    let (clips, styles, sampler) = prepare_training(&corpus.train, &norm, config.window);
    ensure!(
        sampler.eligible() > 0,
        "no training take has {} frames or more (--window {})",
        config.window,
        config.window
    );
    let heldout = HeldoutSet::new(&corpus.heldout, &norm, config.window, opts.eval_windows);
    config.train_clips = sampler.eligible();
    config.train_clips_skipped = sampler.skipped();
    config.eval_windows = heldout.len();
    config.heldout_skipped = heldout.skipped;
    let load_s = t_load.elapsed().as_secs_f64();
    let say = |line: String| {
        if opts.progress != ProgressMode::Quiet {
            eprintln!("{line}");
        }
    };
    let (train_frames, heldout_frames) = corpus.frames();
    say(format!(
        "data: {} training clips (takes + mirrors, {train_frames} frames), {} held-out takes ({heldout_frames} \
         frames), loaded in {load_s:.1} s",
        corpus.train.len(),
        corpus.heldout.len()
    ));
    say(format!(
        "window {} frames: {} training clips used, {} skipped as shorter ({} distinct windows); {} held-out \
         windows, {} held-out takes skipped",
        config.window,
        sampler.eligible(),
        sampler.skipped(),
        sampler.windows(),
        heldout.len(),
        heldout.skipped
    ));
    if matches!(opts.stage, Stage::Stylizer { .. } | Stage::Classifier) {
        let names: Vec<String> = sampler.styles().iter().map(|(s, n)| format!("{} {n}", STYLES[*s])).collect();
        say(format!("styles (clips): {}", names.join(", ")));
    }

    // ---- The run folder.
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    if !opts.resume {
        rundir::write_json(&out.join(rundir::NORM), &norm)?;
        if let Some(ae) = &ae_copy {
            rundir::write_atomic(&out.join(rundir::AE_COPY), &ae.to_bytes()?)?;
        }
    }
    rundir::write_json(&out.join(rundir::CONFIG), &config)?;
    let mut log: RunLog =
        if opts.resume { rundir::read_json(&out.join(rundir::RUN_LOG)).unwrap_or_default() } else { RunLog::default() };
    // Segments past the checkpoint being resumed did not happen as far as this run is concerned.
    log.segments.retain(|s| s.from_step < start_step);
    for s in &mut log.segments {
        s.to_step = s.to_step.min(start_step);
    }
    log.machine = rundir::machine_description();
    log.threads = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    log.segments.push(Segment {
        command: opts.command.clone(),
        started_unix: rundir::unix_now(),
        from_step: start_step,
        to_step: start_step,
        load_s,
        step_s: 0.0,
        eval_s: 0.0,
        wall_s: 0.0,
    });
    rundir::write_json(&out.join(rundir::RUN_LOG), &log)?;

    // ---- Networks.
    let device = Device::flex();
    let trainer_seed = seed_for_segment(config.seed, start_step);
    let mut runner: Box<dyn Runner> = match &opts.stage {
        Stage::Ae => {
            let mut trainer = AeTrainer::new(config.model.clone(), config.train.clone(), &device, trainer_seed);
            if let Some(ckpt) = &resume_from {
                let nets = load_module(AeNets::new(&config.model, trainer.device()), &ckpt.weights)?;
                trainer.autoencoder = nets.autoencoder;
                trainer.regressor = nets.regressor;
            }
            Box::new(AeRunner {
                trainer,
                clips,
                sampler,
                heldout,
                norm,
                batch: config.batch,
                window: config.window,
                device,
            })
        }
        Stage::Stylizer { .. } => {
            let ae = ae_copy.as_ref().expect("stylizer runs have an autoencoder");
            let nets = load_module(AeNets::new(&config.model, &device), &ae.weights)
                .context("the autoencoder checkpoint does not fit the run's configuration")?;
            let mut trainer = StylizerTrainer::new(
                config.model.clone(),
                config.train.clone(),
                nets.autoencoder,
                &device,
                trainer_seed,
            );
            if let Some(ckpt) = &resume_from {
                trainer.net = load_module(StylizerNet::new(&config.model, trainer.device()), &ckpt.weights)?;
            }
            Box::new(StylizerRunner {
                trainer,
                clips,
                styles,
                sampler,
                heldout,
                batch: config.batch,
                window: config.window,
                device,
            })
        }
        Stage::Classifier => {
            let mut trainer =
                ClassifierTrainer::new(config.model.clone(), config.train.clone(), &device, trainer_seed);
            if let Some(ckpt) = &resume_from {
                trainer.classifier =
                    load_module(crate::model::StyleClassifier::new(&config.model, trainer.device()), &ckpt.weights)?;
            }
            Box::new(classifier::ClassifierRunner {
                trainer,
                clips,
                styles,
                sampler,
                heldout: classifier::ClassifierRunner::heldout_takes(&corpus.heldout, &norm),
                norm,
                batch: config.batch,
                window: config.window,
                device,
            })
        }
    };

    if let Some(ckpt) = &resume_from {
        restore_optimizer(runner.as_mut(), out, ckpt, &say)?;
    }
    let mut rng = match &resume_from {
        Some(c) => SamplerRng::from_state(&c.meta.sampler).map_err(anyhow::Error::msg)?,
        None => SamplerRng::new(config.seed ^ SAMPLER_SALT),
    };
    let elapsed0 = resume_from.as_ref().map_or(0.0, |c| c.meta.elapsed_s);
    let lr_columns: Vec<&str> = runner.lrs().iter().map(|(n, _)| *n).collect();
    let loss_columns: Vec<&str> =
        ["step", "elapsed_s"].into_iter().chain(runner.terms().iter().copied()).chain(lr_columns).collect();
    let eval_columns: Vec<&str> = ["step", "elapsed_s"].into_iter().chain(runner.metrics().iter().copied()).collect();
    let mut loss_csv = CsvLog::open(&out.join(rundir::LOSS_CSV), &loss_columns, start_step)?;
    let mut eval_csv = CsvLog::open(&out.join(rundir::EVAL_CSV), &eval_columns, start_step)?;
    let lrs: Vec<f64> = runner.lrs().iter().map(|(_, v)| *v).collect();

    say(format!(
        "{} run {}: steps {start_step} -> {}, width {}, batch {}, window {}, seed {}{}",
        config.stage,
        out.display(),
        opts.steps,
        config.width,
        config.batch,
        config.window,
        config.seed,
        match config.supervised {
            Some(true) => ", supervised",
            Some(false) => ", unsupervised",
            None => "",
        }
    ));
    let mut progress = Progress::new(opts.progress, start_step, opts.steps, opts.log_every, runner.shown());
    let t_loop = Instant::now();
    let (mut step_s, mut eval_s) = (0.0f64, 0.0f64);
    let mut last_terms = Vec::new();
    let mut last_eval: Option<Vec<f64>> = None;
    for step in start_step + 1..=opts.steps {
        let t = Instant::now();
        let terms = runner.step(&mut rng).with_context(|| format!("step {step}"))?;
        step_s += t.elapsed().as_secs_f64();
        ensure!(
            terms[0].is_finite(),
            "step {step}: the loss is not finite ({}); stopping without checkpointing it",
            terms[0]
        );
        let elapsed = elapsed0 + t_loop.elapsed().as_secs_f64();
        let row: Vec<f64> = [elapsed].into_iter().chain(terms.iter().copied()).chain(lrs.iter().copied()).collect();
        loss_csv.row(step, &row)?;
        progress.step(step, &terms);
        last_terms = terms;

        let last = step == opts.steps;
        if last || (opts.eval_every > 0 && step.is_multiple_of(opts.eval_every)) {
            let t = Instant::now();
            let metrics = runner.evaluate();
            eval_s += t.elapsed().as_secs_f64();
            let row: Vec<f64> =
                [elapsed0 + t_loop.elapsed().as_secs_f64()].into_iter().chain(metrics.iter().copied()).collect();
            eval_csv.row(step, &row)?;
            let text: Vec<String> = runner.metrics().iter().zip(&metrics).map(|(n, v)| format!("{n} {v:.4}")).collect();
            progress.println(&format!("held-out @ {step}: {}", text.join(" ")));
            last_eval = Some(metrics);
        }
        if last || step.is_multiple_of(opts.checkpoint_every) {
            loss_csv.flush()?;
            eval_csv.flush()?;
            let elapsed = elapsed0 + t_loop.elapsed().as_secs_f64();
            let mut optimizer = step.to_le_bytes().to_vec();
            optimizer.extend(runner.optimizer_state()?);
            rundir::write_atomic(&out.join(rundir::OPTIMIZER), &optimizer)?;
            let ckpt = Checkpoint {
                meta: CheckpointMeta {
                    stage: config.stage.clone(),
                    step,
                    elapsed_s: elapsed,
                    sampler: rng.state(),
                    optimizer_state: true,
                },
                weights: runner.weights()?,
            };
            rundir::write_atomic(&out.join(rundir::CHECKPOINT), &ckpt.to_bytes()?)?;
            for (name, bytes) in runner.artifacts()? {
                rundir::write_atomic(&out.join(name), &bytes)?;
            }
            let seg = log.segments.last_mut().expect("a segment");
            seg.to_step = step;
            seg.step_s = step_s;
            seg.eval_s = eval_s;
            seg.wall_s = t_segment.elapsed().as_secs_f64();
            rundir::write_json(&out.join(rundir::RUN_LOG), &log)?;
        }
    }
    progress.finish();
    let done = opts.steps - start_step;
    say(format!(
        "{}: step {} reached; {done} steps in {} ({:.3} s/step training, {} held-out evaluation)",
        out.display(),
        opts.steps,
        format_duration(t_loop.elapsed().as_secs_f64()),
        step_s / done.max(1) as f64,
        format_duration(eval_s)
    ));
    Ok(TrainSummary {
        step: opts.steps,
        losses: runner.terms().iter().map(|s| s.to_string()).zip(last_terms).collect(),
        heldout: runner.metrics().iter().map(|s| s.to_string()).zip(last_eval.unwrap_or_default()).collect(),
    })
}

/// Loads `optimizer.bin` into the runner when it belongs to the checkpoint being resumed.
fn restore_optimizer(runner: &mut dyn Runner, out: &Path, ckpt: &Checkpoint, say: &dyn Fn(String)) -> anyhow::Result<()> {
    let path = out.join(rundir::OPTIMIZER);
    let bytes = if ckpt.meta.optimizer_state { std::fs::read(&path).ok() } else { None };
    match bytes.as_deref().and_then(|b| b.split_first_chunk::<8>()) {
        Some((step, state)) if u64::from_le_bytes(*step) == ckpt.meta.step => {
            runner.load_optimizer_state(state).with_context(|| format!("cannot restore {}", path.display()))?;
            say(format!("resumed Adam's state of step {}", ckpt.meta.step));
        }
        _ => eprintln!(
            "warning: no optimizer state for step {} (a checkpoint from an older version?): Adam restarts with fresh moments",
            ckpt.meta.step
        ),
    }
    Ok(())
}

/// The summary of a run that is already done, from its logs.
fn summary_from_logs(out: &Path, step: u64) -> anyhow::Result<TrainSummary> {
    let named = |path: PathBuf| -> anyhow::Result<Vec<(String, f64)>> {
        let t = rundir::CsvTable::read(&path)?;
        Ok(match t.up_to(step).last() {
            Some(row) => t.columns.iter().cloned().zip(row.iter().copied()).skip(2).collect(),
            None => Vec::new(),
        })
    };
    Ok(TrainSummary { step, losses: named(out.join(rundir::LOSS_CSV))?, heldout: named(out.join(rundir::EVAL_CSV))? })
}

/// Normalised copies of the clips, their style labels and the window sampler.
fn prepare_training(train: &[Clip], norm: &NormStats, window: usize) -> (Vec<Features>, Vec<usize>, WindowSampler) {
    let clips: Vec<Features> = train
        .iter()
        .map(|c| {
            let mut f = c.features.clone();
            norm.normalize(&mut f);
            f
        })
        .collect();
    let styles: Vec<usize> = train.iter().map(|c| c.style.index()).collect();
    let frames: Vec<usize> = clips.iter().map(Features::frames).collect();
    let sampler = WindowSampler::new(&frames, &styles, window);
    (clips, styles, sampler)
}

/// One stage's step, evaluation and weights, behind one interface for the loop.
trait Runner {
    /// Names of the step's loss terms (`loss.csv` columns after step and elapsed_s).
    fn terms(&self) -> &'static [&'static str];
    /// Terms shown by the progress display: (name, index in `terms`).
    fn shown(&self) -> Vec<(&'static str, usize)>;
    /// Learning rates, logged as the last columns.
    fn lrs(&self) -> Vec<(&'static str, f64)>;
    /// Held-out metric names.
    fn metrics(&self) -> &'static [&'static str];
    fn step(&mut self, rng: &mut SamplerRng) -> anyhow::Result<Vec<f64>>;
    fn evaluate(&self) -> Vec<f64>;
    /// Burnpack bytes of the trained networks (f32).
    fn weights(&self) -> anyhow::Result<Vec<u8>>;
    /// The optimizers' state (see `optimizer.bin`) and its restoration.
    fn optimizer_state(&self) -> anyhow::Result<Vec<u8>>;
    fn load_optimizer_state(&mut self, bytes: &[u8]) -> anyhow::Result<()>;
    /// Other files written beside each checkpoint: (file name, bytes).
    fn artifacts(&self) -> anyhow::Result<Vec<(&'static str, Vec<u8>)>> {
        Ok(Vec::new())
    }
}

struct AeRunner {
    trainer: AeTrainer,
    clips: Vec<Features>,
    sampler: WindowSampler,
    heldout: HeldoutSet,
    norm: NormStats,
    batch: usize,
    window: usize,
    device: Device,
}

impl Runner for AeRunner {
    fn terms(&self) -> &'static [&'static str] {
        &AE_TERMS
    }

    fn shown(&self) -> Vec<(&'static str, usize)> {
        vec![("loss", 0), ("rec", 1), ("reg", 5)]
    }

    fn lrs(&self) -> Vec<(&'static str, f64)> {
        vec![("lr", self.trainer.train.lr), ("regressor_lr", self.trainer.train.regressor_lr)]
    }

    fn metrics(&self) -> &'static [&'static str] {
        &eval::AE_METRICS
    }

    fn step(&mut self, rng: &mut SamplerRng) -> anyhow::Result<Vec<f64>> {
        let windows: Vec<_> = (0..self.batch).map(|_| self.sampler.window(rng)).collect();
        let x = batch_tensor(&self.clips, &windows, self.window, &self.device);
        let r = self.trainer.step(x)?;
        Ok([
            r.ae_loss,
            r.reconstruction,
            r.sparsity,
            r.smoothness,
            r.kl,
            r.regressor_loss,
            r.ae_grad_norm,
            r.regressor_grad_norm,
        ]
        .map(f64::from)
        .to_vec())
    }

    fn evaluate(&self) -> Vec<f64> {
        let ae = self.trainer.autoencoder.clone().valid();
        let regressor = self.trainer.regressor.clone().valid();
        eval::evaluate_ae(&ae, &regressor, &self.heldout, &self.norm, self.batch, &self.device)
    }

    fn optimizer_state(&self) -> anyhow::Result<Vec<u8>> {
        Ok(self.trainer.optimizer_state()?)
    }

    fn load_optimizer_state(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        Ok(self.trainer.load_optimizer_state(bytes)?)
    }

    fn weights(&self) -> anyhow::Result<Vec<u8>> {
        module_bytes(AeNets {
            autoencoder: self.trainer.autoencoder.clone().valid(),
            regressor: self.trainer.regressor.clone().valid(),
        })
    }
}

struct StylizerRunner {
    trainer: StylizerTrainer,
    clips: Vec<Features>,
    styles: Vec<usize>,
    sampler: WindowSampler,
    heldout: HeldoutSet,
    batch: usize,
    window: usize,
    device: Device,
}

impl Runner for StylizerRunner {
    fn terms(&self) -> &'static [&'static str] {
        &STYLIZER_TERMS
    }

    fn shown(&self) -> Vec<(&'static str, usize)> {
        vec![("loss", 0), ("rec_pose", 2), ("hsa", 6)]
    }

    fn lrs(&self) -> Vec<(&'static str, f64)> {
        vec![("lr", self.trainer.train.lr)]
    }

    fn metrics(&self) -> &'static [&'static str] {
        &eval::STYLIZER_METRICS
    }

    fn step(&mut self, rng: &mut SamplerRng) -> anyhow::Result<Vec<f64>> {
        let pairs: Vec<_> = (0..self.batch).map(|_| self.sampler.pair(rng)).collect();
        let first: Vec<_> = pairs.iter().map(|p| p.0).collect();
        let second: Vec<_> = pairs.iter().map(|p| p.1).collect();
        debug_assert!(pairs.iter().all(|p| self.styles[p.0.clip] == p.2));
        let batch = StylizerBatch {
            motion1: batch_tensor(&self.clips, &first, self.window, &self.device),
            motion2: batch_tensor(&self.clips, &second, self.window, &self.device),
            labels: self.trainer.config.supervised.then(|| pairs.iter().map(|p| p.2).collect()),
        };
        let r = self.trainer.step(&batch)?;
        Ok([
            r.loss,
            r.rec_latent,
            r.rec_pose,
            r.cyc_latent,
            r.cyc_pose,
            r.kl,
            r.hsa,
            r.encoders_grad_norm,
            r.generator_grad_norm,
        ]
        .map(f64::from)
        .to_vec())
    }

    fn evaluate(&self) -> Vec<f64> {
        let net = self.trainer.net.clone().valid();
        let ae = self.trainer.autoencoder.clone().valid();
        let styles = self.trainer.config.supervised.then_some(self.trainer.config.num_styles);
        eval::evaluate_stylizer(&net, &ae, &self.trainer.weights, styles, &self.heldout, self.batch, &self.device)
    }

    fn weights(&self) -> anyhow::Result<Vec<u8>> {
        module_bytes(self.trainer.net.clone().valid())
    }

    fn optimizer_state(&self) -> anyhow::Result<Vec<u8>> {
        Ok(self.trainer.optimizer_state()?)
    }

    fn load_optimizer_state(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        Ok(self.trainer.load_optimizer_state(bytes)?)
    }
}
