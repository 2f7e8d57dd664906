//! What a training run is asked to do ([`TrainOptions`], the command line's flags as they are) and
//! the settings that fix a run for its life ([`Settings`], written to `config.json` inside
//! [`RunConfig`](super::rundir::RunConfig)); the optimisation settings ([`TrainConfig`]).

use anyhow::{bail, ensure};
use clap::Args;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use super::losses::StylizerWeights;
use super::progress::ProgressMode;
use crate::model::config::FRAME_MULTIPLE;
use crate::model::device::DeviceName;

/// Default training window, frames. Bandai takes are short (set 2's median is 117 frames); at 64
/// frames 84 % of all takes contribute and 48 % are long enough for two disjoint windows.
pub const DEFAULT_WINDOW: usize = 64;
pub const DEFAULT_BATCH: usize = 16;
/// Default width factor relative to the paper's sizes (the paper's width costs ~3× more per step).
pub const DEFAULT_WIDTH: f64 = 0.5;
pub const DEFAULT_SEED: u64 = 1;
pub const DEFAULT_SPLIT: &str = "assets/split/heldout.txt";

/// The settings that fix a run at its start; a resumed run keeps them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Seed of weights, windows and noise.
    pub seed: u64,
    /// Width factor relative to the paper's network sizes.
    pub width: f64,
    pub batch: usize,
    /// Training window, frames (a multiple of 8).
    pub window: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self { seed: DEFAULT_SEED, width: DEFAULT_WIDTH, batch: DEFAULT_BATCH, window: DEFAULT_WINDOW }
    }
}

/// [`Settings`] as the command line gives them: what is not given takes the default (a new run),
/// the autoencoder's (a stylizer's width) or the run's own (a resumed run, where a differing value
/// is an error).
#[derive(Args, Clone, Debug, Default, PartialEq)]
pub struct SettingChoices {
    /// Seed of weights, windows and noise [default: 1].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Width factor relative to the paper's network sizes [default: 0.5; stylizer: the
    /// autoencoder's].
    #[arg(long)]
    pub width: Option<f64>,
    /// Batch size [default: 16].
    #[arg(long)]
    pub batch: Option<usize>,
    /// Training window, frames: a multiple of 8 [default: 64].
    #[arg(long)]
    pub window: Option<usize>,
}

impl SettingChoices {
    /// Refuses values no run can take.
    pub fn validate(&self) -> anyhow::Result<()> {
        if let Some(w) = self.window {
            check_window(w)?;
        }
        if let Some(b) = self.batch {
            ensure!(b >= 1, "--batch must be at least 1");
        }
        if let Some(w) = self.width {
            ensure!(w.is_finite() && w > 0.0, "--width must be positive");
        }
        Ok(())
    }

    /// `base` with the given choices in place of its values.
    pub fn over(&self, base: Settings) -> Settings {
        Settings {
            seed: self.seed.unwrap_or(base.seed),
            width: self.width.unwrap_or(base.width),
            batch: self.batch.unwrap_or(base.batch),
            window: self.window.unwrap_or(base.window),
        }
    }

    /// Errors if a given choice differs from the run's settings.
    pub fn check_same(&self, run: &Settings) -> anyhow::Result<()> {
        let show = |v: Option<String>, saved: String| v.filter(|v| *v != saved).map(|v| (v, saved));
        let differing = [
            ("--seed", show(self.seed.map(|v| v.to_string()), run.seed.to_string())),
            ("--width", show(self.width.map(|v| v.to_string()), run.width.to_string())),
            ("--batch", show(self.batch.map(|v| v.to_string()), run.batch.to_string())),
            ("--window", show(self.window.map(|v| v.to_string()), run.window.to_string())),
        ];
        if let Some((flag, Some((given, saved)))) = differing.into_iter().find(|(_, d)| d.is_some()) {
            bail!("{flag} {given} differs from the run's {saved}: a resumed run keeps its settings");
        }
        Ok(())
    }
}

/// Checks a window length.
pub fn check_window(window: usize) -> anyhow::Result<()> {
    ensure!(
        window >= FRAME_MULTIPLE && window.is_multiple_of(FRAME_MULTIPLE),
        "--window {window}: the window must be a positive multiple of {FRAME_MULTIPLE} frames"
    );
    Ok(())
}

/// Options of a training run: the flags of `motion-stylizer train STAGE`.
#[derive(Args, Clone, Debug)]
pub struct TrainOptions {
    /// The data: the Bandai-Namco archives unpacked (DIR/dataset-1, DIR/dataset-2), or any folder
    /// of BVH files (searched recursively) with an optional labels.csv (`file,style[,content]`).
    #[arg(long, value_name = "DIR")]
    pub data: PathBuf,
    /// Run folder (must not exist or be empty, unless --resume).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Continue the run in --out from its last checkpoint, with its own settings, up to --steps.
    #[arg(long)]
    pub resume: bool,
    /// Fine-tuning: start a new run from this weights folder's networks (its width, network sizes
    /// and normalisation statistics; labels the data adds to its label set get new rows).
    #[arg(long, value_name = "WEIGHTS")]
    pub from: Option<PathBuf>,
    /// Total number of steps.
    #[arg(long, default_value_t = 20_000)]
    pub steps: u64,
    #[command(flatten)]
    pub settings: SettingChoices,
    /// Write a checkpoint every N steps (and at the end).
    #[arg(long, default_value_t = 500, value_name = "N")]
    pub checkpoint_every: u64,
    /// Held-out evaluation every N steps (and at the end; 0: only at the end).
    #[arg(long, default_value_t = 1000, value_name = "N")]
    pub eval_every: u64,
    /// At most this many held-out windows per evaluation.
    #[arg(long, default_value_t = 512, value_name = "N")]
    pub eval_windows: usize,
    /// Threads for loading the takes and for the CPU kernels (sets RAYON_NUM_THREADS unless it
    /// is set) [default: all cores].
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Compute device: cpu (flex) or wgpu (cargo feature `wgpu`; cuda is not built, see
    /// `src/model/device.rs`). Not a setting of the run: a resumed run may continue on another.
    #[arg(long, default_value_t = DeviceName::Cpu, value_name = "cpu|wgpu|cuda")]
    pub device: DeviceName,
    /// Held-out split file (new runs; a resumed run uses its own).
    #[arg(long, default_value = DEFAULT_SPLIT, value_name = "FILE")]
    pub split: PathBuf,
    /// When stderr is not a terminal: one progress line every N steps.
    #[arg(long, default_value_t = 100, value_name = "N")]
    pub log_every: u64,
    /// How progress is shown.
    #[arg(skip = ProgressMode::Auto)]
    pub progress: ProgressMode,
    /// The command line, recorded in `run.json`.
    #[arg(skip = std::env::args().collect::<Vec<_>>().join(" "))]
    pub command: String,
}

impl TrainOptions {
    /// Threads of the corpus loader: `--threads`, else every core.
    pub fn loader_threads(&self) -> usize {
        self.threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).max(1)
    }

    /// Refuses options no run can take.
    pub fn validate(&self) -> anyhow::Result<()> {
        ensure!(self.steps >= 1, "--steps must be at least 1");
        ensure!(self.checkpoint_every >= 1, "--checkpoint-every must be at least 1");
        self.settings.validate()
    }
}

/// [`TrainConfig::batch_chunks`] of a new run (and of one from before the setting existed).
pub const DEFAULT_BATCH_CHUNKS: usize = 2;

/// Training settings from the paper / its code (the model facts' "Training").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TrainConfig {
    /// Adam learning rate of the autoencoder and the stylizer (1e-4).
    pub lr: f64,
    /// Adam learning rate of the global motion regressor (2e-4).
    pub regressor_lr: f64,
    /// Global gradient-norm clip, applied per network as `torch.nn.utils.clip_grad_norm_` (0.5).
    pub grad_clip_norm: f32,
    /// Autoencoder latent L1 sparsity weight (0.001).
    pub lambda_l1: f32,
    /// Autoencoder latent L1 smoothness weight (0.001).
    pub lambda_smooth: f32,
    /// VAE autoencoder KL weight (0.001).
    pub lambda_ae_kl: f32,
    /// Stylizer loss weights; `None` means the paper's for the model's (un)supervised mode.
    pub stylizer_weights: Option<StylizerWeights>,
    /// Row groups of a training step's batch (autoencoder + regressor, stylizer), run side by
    /// side on the CPU's threads ([`super::parallel`]; 2: one per core of a 2-core machine). The
    /// same step up to float rounding whatever the value; a run's numbers depend on it, not on
    /// the thread count. 1: the whole batch at once (as before this setting). GPU devices always
    /// take the whole batch.
    pub batch_chunks: usize,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            lr: 1e-4,
            regressor_lr: 2e-4,
            grad_clip_norm: 0.5,
            lambda_l1: 0.001,
            lambda_smooth: 0.001,
            lambda_ae_kl: 0.001,
            stylizer_weights: None,
            batch_chunks: DEFAULT_BATCH_CHUNKS,
        }
    }
}
