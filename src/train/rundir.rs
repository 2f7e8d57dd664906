//! The files of a run directory and how they are written.
//!
//! | file | what |
//! |---|---|
//! | `config.json` | [`RunConfig`]: stage, settings, network sizes; fixed for the life of the run |
//! | `run.json` | [`RunLog`]: one segment per invocation (exact command line, steps, timings), machine |
//! | `norm.json` | the normalisation statistics the run trains on |
//! | `checkpoint.bin` | latest checkpoint: [`CheckpointMeta`] + burnpack bytes of the networks (f32) |
//! | `ae.bin` | stylizer runs: the frozen autoencoder + regressor checkpoint it trains on (a copy) |
//! | `content-judge.bin` | stylizer runs with `--content-class`: the frozen content classifier (a copy) |
//! | `style-judge.bin` | stylizer runs with `--style-class`: the frozen style classifier (a copy) |
//! | `loss.csv` | one row per step: step, elapsed_s, every loss term of the step report, lr |
//! | `eval.csv` | one row per evaluation: step, elapsed_s, held-out metrics |
//!
//! Files that must never be seen half-written (`checkpoint.bin`, `run.json`, `config.json`,
//! `norm.json`, `ae.bin`, the judges) are written to a temporary name in the same folder, synced, then renamed
//! over the old one.

use anyhow::{Context, bail, ensure};
use burn::module::Module;
use burn::store::ModuleRecord;
use burn::tensor::Bytes;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

use super::Stage;
use super::finetune;
pub use super::logs::{CsvLog, CsvTable, RunLog, Segment, machine_description, unix_now};
use super::losses::StylizerExtras;
use super::sampler::RngState;
use super::settings::{Settings, TrainConfig, TrainOptions};
use crate::dataset::folder::{self, FolderListing};
use crate::dataset::{CONTENTS, STYLES};
use crate::features::NormStats;
use crate::model::ModelConfig;
use crate::model::weights::{FrameError, frame, unframe};

pub const CONFIG: &str = "config.json";
pub const RUN_LOG: &str = "run.json";
pub const NORM: &str = "norm.json";
pub const CHECKPOINT: &str = "checkpoint.bin";
pub const AE_COPY: &str = "ae.bin";
pub const CONTENT_JUDGE: &str = "content-judge.bin";
pub const STYLE_JUDGE: &str = "style-judge.bin";
/// Adam's state at the checkpoint's step: the step (u64 LE), then the trainer's optimizer bytes.
pub const OPTIMIZER: &str = "optimizer.bin";
pub const LOSS_CSV: &str = "loss.csv";
pub const EVAL_CSV: &str = "eval.csv";

const CHECKPOINT_MAGIC: &[u8; 8] = b"MSTCKPT1";

/// Settings of a run, written once when it starts; a resumed run takes them from here.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunConfig {
    /// `"ae"`, `"stylizer"` or `"classifier"`.
    pub stage: String,
    /// Stylizer: supervised (style labels) or not; `None` for the autoencoder.
    pub supervised: Option<bool>,
    /// Seed, width, batch and window.
    #[serde(flatten)]
    pub settings: Settings,
    pub model: ModelConfig,
    pub train: TrainConfig,
    /// Held-out split file, as given.
    pub split: String,
    /// Stylizer: the autoencoder run it was started on (as given) and that run's step.
    pub ae_run: Option<String>,
    pub ae_step: Option<u64>,
    /// How windows are drawn ([`super::sampler`]).
    pub sampler: String,
    /// Training clips (takes + mirrors) used and skipped as shorter than the window; held-out
    /// windows evaluated and held-out takes skipped.
    pub train_clips: usize,
    pub train_clips_skipped: usize,
    pub eval_windows: usize,
    pub heldout_skipped: usize,
    /// Data from a folder of the user's files ([`crate::dataset::folder`]); `None`: the
    /// Bandai-Namco layout (labels [`STYLES`], held-out takes from `split`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub folder: Option<FolderData>,
    /// Fine-tuning: the weights folder the networks started from (as given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<String>,
    /// Stylizer runs with the content-class loss: the content classifier copied in as
    /// `content-judge.bin` (as given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub content_judge: Option<String>,
    /// Stylizer runs with the style-class loss: the style classifier copied in as
    /// `style-judge.bin` (as given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub style_judge: Option<String>,
}

/// What a run on a folder of the user's files fixes at its start.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FolderData {
    /// The label set of `labels.csv`, in one-hot order.
    pub labels: Vec<String>,
    /// The held-out files (relative paths).
    pub heldout: Vec<String>,
}

impl RunConfig {
    /// The label set the run's labels index, in one-hot order.
    pub fn labels(&self) -> Vec<String> {
        match &self.folder {
            Some(f) => f.labels.clone(),
            None => STYLES.iter().map(|s| s.to_string()).collect(),
        }
    }
}

/// The data of `dir` at the start of a run: `None` for the Bandai-Namco layout, else the folder's
/// label set and held-out files.
pub fn folder_data(dir: &Path) -> anyhow::Result<Option<FolderData>> {
    if folder::is_bandai_layout(dir) {
        return Ok(None);
    }
    let listing = FolderListing::read(dir)?;
    let heldout = folder::choose_heldout(&listing);
    Ok(Some(FolderData { labels: listing.labels.names, heldout }))
}

/// What a checkpoint holds besides the network weights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckpointMeta {
    pub stage: String,
    /// Steps done.
    pub step: u64,
    /// Wall seconds of training so far (all segments), for `elapsed_s` in the logs.
    pub elapsed_s: f64,
    /// Position of the window sampler's generator after `step` steps.
    pub sampler: RngState,
    /// Whether `optimizer.bin` holds Adam's state of this step (`false` in checkpoints written
    /// before it existed: such a run resumes with fresh moments).
    pub optimizer_state: bool,
}

/// A checkpoint: metadata and the burnpack bytes of the networks.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    pub meta: CheckpointMeta,
    pub weights: Vec<u8>,
}

impl Checkpoint {
    /// The checkpoint as bytes: [`frame`] with the metadata as header.
    pub fn to_bytes(&self) -> anyhow::Result<Vec<u8>> {
        Ok(frame(CHECKPOINT_MAGIC, &serde_json::to_vec(&self.meta)?, &self.weights))
    }

    pub fn from_bytes(bytes: &[u8]) -> anyhow::Result<Checkpoint> {
        let (json, weights) = unframe(CHECKPOINT_MAGIC, bytes).map_err(|e| match e {
            FrameError::NotOurs => anyhow::anyhow!("not a motion-stylizer training checkpoint"),
            FrameError::Truncated => anyhow::anyhow!("truncated checkpoint"),
        })?;
        let meta = serde_json::from_slice(json).context("checkpoint metadata")?;
        Ok(Checkpoint { meta, weights: weights.to_vec() })
    }

    pub fn read(path: &Path) -> anyhow::Result<Checkpoint> {
        let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
        Checkpoint::from_bytes(&bytes).with_context(|| format!("{}", path.display()))
    }
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, synced, renamed over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let tmp = tmp_path(path);
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}

fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

pub fn write_json<T: Serialize>(path: &Path, value: &T) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    write_atomic(path, text.as_bytes())
}

pub fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> anyhow::Result<T> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("cannot parse {}", path.display()))
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

fn is_nonempty_dir(dir: &Path) -> bool {
    std::fs::read_dir(dir).map(|mut d| d.next().is_some()).unwrap_or(false)
}

/// Where the autoencoder of a stylizer run comes from: a run folder or its checkpoint file.
fn ae_source(path: &Path) -> anyhow::Result<(RunConfig, Checkpoint, NormStats)> {
    let dir = if path.is_file() { path.parent().unwrap_or(Path::new(".")) } else { path };
    let ckpt_path = if path.is_file() { path.to_path_buf() } else { dir.join(CHECKPOINT) };
    let config: RunConfig =
        read_json(&dir.join(CONFIG)).with_context(|| format!("--ae {}: not an `ae` run folder", path.display()))?;
    ensure!(config.stage == "ae", "--ae {}: a {} run, not an `ae` run", path.display(), config.stage);
    let bytes = std::fs::read(&ckpt_path)
        .with_context(|| format!("--ae {}: no checkpoint yet ({})", path.display(), ckpt_path.display()))?;
    let norm = read_json(&dir.join(NORM))?;
    Ok((config, Checkpoint::from_bytes(&bytes)?, norm))
}

/// How a stylizer run draws its batches (recorded in `config.json`).
fn stylizer_sampler(extra: &StylizerExtras) -> String {
    let mut s = "style-balanced: a style uniformly, a clip of it uniformly, two windows of that clip at independent \
                 uniform offsets"
        .to_string();
    if extra.style_stats > 0.0 {
        s.push_str(
            "; rows 4k+1 (when the data has one): a clip of row 4k's content group in another style (a style \
             uniformly among the group's others, a clip of it uniformly)",
        );
    }
    if extra.style_stats > 0.0 && extra.cross_content {
        s.push_str(
            "; cross-content: rows 4k+2 and 4k+3 (when the data has them): a clip of row 4k+1's style and one of row \
             4k's, each uniformly among the style's clips of another content, the style sources of rows 4k and 4k+1",
        );
    }
    if extra.style_stats > 0.0 && extra.cross_set {
        s.push_str(
            "; content groups across the data sets: row 4k+1 may be the same content in a style of the other set",
        );
    }
    if extra.style_stats > 0.0 && extra.cross_set && extra.cross_set_relative {
        s.push_str(
            "; a pair across the sets is judged by the partner's statistics plus (the row's set's normal - the \
             partner's set's normal) of the content",
        );
    }
    s
}

/// A stylizer run's optimisation settings: the defaults, with the paper's loss weights and the
/// extra losses' weights when they are used.
fn stylizer_train(supervised: bool, extra: &StylizerExtras) -> TrainConfig {
    let paper = super::losses::StylizerWeights::paper(supervised);
    let weights = extra.any().then_some(super::losses::StylizerWeights {
        style_stats: extra.style_stats,
        content_shape: extra.content_shape,
        cross_content: extra.cross_content,
        cross_set: extra.cross_set,
        cross_set_relative: extra.cross_set_relative,
        content_class: extra.content_class,
        style_class: extra.style_class,
        hsa: extra.hsa.unwrap_or(paper.hsa),
        ..paper
    });
    TrainConfig { stylizer_weights: weights, ..TrainConfig::default() }
}

/// A run folder opened for a segment: the run's settings and what it starts from.
pub struct OpenRun {
    pub config: RunConfig,
    /// The checkpoint a resumed run continues from (none before its first checkpoint).
    pub resume_from: Option<Checkpoint>,
    /// Stylizer runs: the frozen autoencoder + regressor checkpoint it trains on.
    pub ae: Option<Checkpoint>,
    /// The statistics the run trains on; `None` for a new `ae` or `classifier` run (computed from
    /// the training clips).
    pub norm: Option<NormStats>,
    /// Stylizer runs with the content-class loss: the content classifier that judges the swaps.
    pub content_judge: Option<JudgeFile>,
    /// Stylizer runs with the style-class loss: the style classifier that judges the swaps.
    pub style_judge: Option<JudgeFile>,
}

/// A classifier that judges a stylizer run's swaps (the content- or style-class loss).
pub struct JudgeFile {
    /// Its file's bytes ([`crate::model::weights::save_classifier`]).
    pub bytes: Vec<u8>,
    /// The statistics it was trained on, when its run folder holds them (a new run's judge must
    /// read features normalised as the stylizer's).
    pub norm: Option<NormStats>,
}

impl JudgeFile {
    /// A classifier file and, when beside it, its run's `norm.json`.
    fn read(path: &Path) -> anyhow::Result<JudgeFile> {
        let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read the judge", path.display()))?;
        let norm_path = path.parent().unwrap_or(Path::new(".")).join(NORM);
        let norm = norm_path.is_file().then(|| read_json(&norm_path)).transpose()?;
        Ok(JudgeFile { bytes, norm })
    }
}

impl OpenRun {
    /// The step this segment starts from.
    pub fn start_step(&self) -> u64 {
        self.resume_from.as_ref().map_or(0, |c| c.meta.step)
    }
}

/// Opens `opts.out` for `stage`: a resumed run's own settings (a differing setting is an error),
/// or a new run's from the options (a non-empty folder is refused).
pub fn open(stage: &Stage, opts: &TrainOptions) -> anyhow::Result<OpenRun> {
    let out = &opts.out;
    if opts.resume {
        let config: RunConfig = read_json(&out.join(CONFIG))
            .with_context(|| format!("--resume: {} holds no run to resume", out.display()))?;
        ensure!(
            config.stage == stage.name(),
            "--resume: {} is a {} run, not {}",
            out.display(),
            config.stage,
            stage.name()
        );
        if let Stage::Stylizer { supervised, .. } = stage
            && *supervised != config.supervised.unwrap_or(true)
        {
            let (run, flag) = if *supervised { ("an unsupervised", "with") } else { ("a supervised", "without") };
            bail!("--resume: {} is {run} stylizer run: resume it {flag} --unsupervised", out.display());
        }
        opts.settings.check_same(&config.settings)?;
        if let Some(from) = &opts.from
            && config.from.as_deref() != Some(from.display().to_string().as_str())
        {
            bail!(
                "--from {}: the run did not start from these weights (a resumed run keeps its start)",
                from.display()
            );
        }
        let ckpt_path = out.join(CHECKPOINT);
        let resume_from = if ckpt_path.exists() { Some(Checkpoint::read(&ckpt_path)?) } else { None };
        let ae = if config.stage == "stylizer" { Some(Checkpoint::read(&out.join(AE_COPY))?) } else { None };
        let norm: NormStats = read_json(&out.join(NORM))?;
        let weights = config.train.stylizer_weights;
        let copy = |judged: bool, name: &str| -> anyhow::Result<Option<JudgeFile>> {
            judged
                .then(|| {
                    let bytes = std::fs::read(out.join(name))
                        .with_context(|| format!("--resume: {} holds no {name}", out.display()))?;
                    Ok(JudgeFile { bytes, norm: None })
                })
                .transpose()
        };
        let content_judge = copy(weights.is_some_and(|w| w.content_class > 0.0), CONTENT_JUDGE)?;
        let style_judge = copy(weights.is_some_and(|w| w.style_class > 0.0), STYLE_JUDGE)?;
        return Ok(OpenRun { config, resume_from, ae, norm: Some(norm), content_judge, style_judge });
    }
    ensure!(
        !is_nonempty_dir(out),
        "{} exists and is not empty: pass --resume to continue that run, or choose another --out",
        out.display()
    );
    let mut settings = opts.settings.over(Settings::default());
    let mut folder = folder_data(&opts.data)?;
    let from = opts.from.as_deref().map(finetune::read_from).transpose()?;
    if let Some(f) = &from {
        match &mut folder {
            Some(data) => data.labels = finetune::merged_labels(&f.labels, &data.labels),
            None => ensure!(
                f.labels.iter().map(String::as_str).eq(STYLES),
                "--from: fine-tuning on the Bandai-Namco data needs weights with its label set"
            ),
        }
        if let Some(w) = opts.settings.width
            && w != f.width
        {
            bail!("--width {w} differs from the width {} of the weights to start from (--from)", f.width);
        }
        settings.width = f.width;
    }
    let labels = folder.as_ref().map_or(STYLES.len(), |f| f.labels.len());
    // Networks need at least one class (an unlabelled folder: only the unsupervised stages run).
    let classes = labels.max(1);
    let needs_labels = matches!(stage, Stage::Classifier | Stage::Stylizer { supervised: true, .. });
    if needs_labels && labels == 0 {
        bail!(
            "{}: the {} stage needs labelled files, and the folder has no labels.csv or it labels none",
            opts.data.display(),
            if matches!(stage, Stage::Classifier) { "classifier" } else { "supervised stylizer" }
        );
    }
    let base = RunConfig {
        stage: stage.name().into(),
        supervised: None,
        model: match &from {
            Some(f) if matches!(stage, Stage::Classifier) => {
                f.classifier.clone().unwrap_or_else(|| ModelConfig::scaled(f.width)).with_num_styles(classes)
            }
            Some(f) => f.config.clone().with_num_styles(classes),
            None => ModelConfig::scaled(settings.width).with_num_styles(classes),
        },
        settings,
        train: TrainConfig::default(),
        split: opts.split.display().to_string(),
        ae_run: None,
        ae_step: None,
        sampler: String::new(),
        train_clips: 0,
        train_clips_skipped: 0,
        eval_windows: 0,
        heldout_skipped: 0,
        folder,
        from: opts.from.as_ref().map(|p| p.display().to_string()),
        content_judge: None,
        style_judge: None,
    };
    let start_norm = from.map(|f| f.norm);
    Ok(match stage {
        Stage::Ae => OpenRun {
            config: RunConfig {
                sampler: "uniform over all windows of the training clips (clips weighted by window starts)".into(),
                ..base
            },
            resume_from: None,
            ae: None,
            norm: start_norm,
            content_judge: None,
            style_judge: None,
        },
        Stage::Classifier => OpenRun {
            config: RunConfig {
                sampler: "style-balanced: a style uniformly, a clip of it uniformly, a window of that clip".into(),
                ..base
            },
            resume_from: None,
            ae: None,
            norm: start_norm,
            content_judge: None,
            style_judge: None,
        },
        Stage::ContentClassifier => OpenRun {
            config: RunConfig {
                model: base.model.clone().with_num_styles(CONTENTS.len()),
                sampler: "content-balanced: a content class uniformly, a clip of it uniformly, a window of that clip"
                    .into(),
                ..base
            },
            resume_from: None,
            ae: None,
            norm: None,
            content_judge: None,
            style_judge: None,
        },
        Stage::Stylizer { ae: None, supervised, extra } if opts.from.is_some() => {
            // Fine-tuning a stylizer alone: the frozen autoencoder and regressor are the weights
            // folder's, as they were trained with (its `shared` networks).
            let dir = opts.from.as_deref().context("--from")?;
            let m = finetune::load_model(dir, None)?;
            let nets = super::AeNets { autoencoder: m.autoencoder, regressor: m.regressor };
            let ae_ckpt = Checkpoint {
                meta: CheckpointMeta {
                    stage: "ae".into(),
                    step: 0,
                    elapsed_s: 0.0,
                    sampler: super::sampler::SamplerRng::new(0).state(),
                    optimizer_state: false,
                },
                weights: module_bytes(nets)?,
            };
            let norm = start_norm.context("--from: the weights' normalisation statistics")?;
            let config = RunConfig {
                supervised: Some(*supervised),
                model: base.model.clone().with_supervised(*supervised).with_content_posture(extra.content_posture),
                ae_run: Some(format!("{} (its autoencoder and regressor)", dir.display())),
                sampler: stylizer_sampler(extra),
                train: stylizer_train(*supervised, extra),
                content_judge: extra.content_judge.as_ref().map(|p| p.display().to_string()),
                style_judge: extra.style_judge.as_ref().map(|p| p.display().to_string()),
                ..base
            };
            let content_judge = extra.content_judge.as_deref().map(JudgeFile::read).transpose()?;
            let style_judge = extra.style_judge.as_deref().map(JudgeFile::read).transpose()?;
            OpenRun { config, resume_from: None, ae: Some(ae_ckpt), norm: Some(norm), content_judge, style_judge }
        }
        Stage::Stylizer { ae, supervised, extra } => {
            let ae = ae.as_ref().context("the stylizer stage needs --ae DIR (an `ae` run), or --from WEIGHTS")?;
            let (ae_config, ae_ckpt, norm) = ae_source(ae)?;
            if let Some(w) = opts.settings.width
                && w != ae_config.settings.width
            {
                bail!("--width {w} differs from the autoencoder run's {}", ae_config.settings.width);
            }
            ensure!(
                ae_config.folder.as_ref().map(|f| &f.heldout) == base.folder.as_ref().map(|f| &f.heldout),
                "--ae {}: the autoencoder run was trained on other data (its held-out files differ)",
                ae.display()
            );
            if base.folder.is_none() && opts.split.display().to_string() != ae_config.split {
                eprintln!(
                    "warning: split {} differs from the autoencoder run's {}",
                    opts.split.display(),
                    ae_config.split
                );
            }
            let config = RunConfig {
                supervised: Some(*supervised),
                settings: Settings { width: ae_config.settings.width, ..base.settings.clone() },
                model: ae_config
                    .model
                    .clone()
                    .with_supervised(*supervised)
                    .with_num_styles(classes)
                    .with_content_posture(extra.content_posture),
                ae_run: Some(ae.display().to_string()),
                ae_step: Some(ae_ckpt.meta.step),
                sampler: stylizer_sampler(extra),
                train: stylizer_train(*supervised, extra),
                content_judge: extra.content_judge.as_ref().map(|p| p.display().to_string()),
                style_judge: extra.style_judge.as_ref().map(|p| p.display().to_string()),
                ..base
            };
            let content_judge = extra.content_judge.as_deref().map(JudgeFile::read).transpose()?;
            let style_judge = extra.style_judge.as_deref().map(JudgeFile::read).transpose()?;
            OpenRun { config, resume_from: None, ae: Some(ae_ckpt), norm: Some(norm), content_judge, style_judge }
        }
    })
}

/// Writes the run folder's fixed files (a new run: `norm.json` and the autoencoder copy; always
/// `config.json`) and `run.json` with a new segment for this invocation; returns the run log.
/// `device`: the compute device when not the CPU (see [`super::logs::Segment::device`]).
pub fn begin_segment(
    opts: &TrainOptions,
    run: &OpenRun,
    norm: &NormStats,
    load_s: f64,
    device: Option<String>,
) -> anyhow::Result<RunLog> {
    let out = &opts.out;
    let start_step = run.start_step();
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    if !opts.resume {
        write_json(&out.join(NORM), norm)?;
        if let Some(ae) = &run.ae {
            write_atomic(&out.join(AE_COPY), &ae.to_bytes()?)?;
        }
        for (judge, name) in [(&run.content_judge, CONTENT_JUDGE), (&run.style_judge, STYLE_JUDGE)] {
            if let Some(judge) = judge {
                write_atomic(&out.join(name), &judge.bytes)?;
            }
        }
    }
    write_json(&out.join(CONFIG), &run.config)?;
    let mut log: RunLog =
        if opts.resume { read_json(&out.join(RUN_LOG)).unwrap_or_default() } else { RunLog::default() };
    // Segments past the checkpoint being resumed did not happen as far as this run is concerned.
    log.segments.retain(|s| s.from_step < start_step);
    for s in &mut log.segments {
        s.to_step = s.to_step.min(start_step);
    }
    log.machine = machine_description();
    log.threads = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    log.segments.push(Segment {
        command: opts.command.clone(),
        started_unix: unix_now(),
        from_step: start_step,
        to_step: start_step,
        load_s,
        step_s: 0.0,
        eval_s: 0.0,
        wall_s: 0.0,
        device,
    });
    write_json(&out.join(RUN_LOG), &log)?;
    Ok(log)
}
