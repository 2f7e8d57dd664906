//! `motion-stylizer train ae|stylizer --data DIR --out DIR [...]`: see [`motion_stylizer::train`].

use clap::{Args, Subcommand};
use motion_stylizer::train::{self, ProgressMode, Stage, TrainOptions};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct TrainArgs {
    #[command(subcommand)]
    stage: StageArgs,
}

#[derive(Subcommand, Debug)]
enum StageArgs {
    /// Stage 1: the motion autoencoder and the global motion regressor.
    Ae(CommonArgs),
    /// Stage 2: content encoder, style encoder and generator on a frozen autoencoder.
    Stylizer {
        #[command(flatten)]
        common: CommonArgs,
        /// The `ae` run (folder, or its checkpoint.bin) whose autoencoder to train on; its latest
        /// checkpoint is copied into the new run. Not needed with --resume.
        #[arg(long, value_name = "DIR")]
        ae: Option<PathBuf>,
        /// Train without style labels (default: supervised, with the unified labels).
        #[arg(long)]
        unsupervised: bool,
    },
    /// The evaluation's style classifier, on the training takes only (`eval` uses it).
    Classifier(CommonArgs),
}

#[derive(Args, Debug)]
struct CommonArgs {
    /// Folder with both archives unpacked: DIR/dataset-1, DIR/dataset-2.
    #[arg(long, value_name = "DIR")]
    data: PathBuf,
    /// Run folder (must not exist or be empty, unless --resume).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Continue the run in --out from its last checkpoint, with its own settings, up to --steps.
    #[arg(long)]
    resume: bool,
    /// Total number of steps.
    #[arg(long, default_value_t = 20_000)]
    steps: u64,
    /// Seed of weights, windows and noise [default: 1].
    #[arg(long)]
    seed: Option<u64>,
    /// Width factor relative to the paper's network sizes [default: 0.5; stylizer: the
    /// autoencoder's].
    #[arg(long)]
    width: Option<f64>,
    /// Batch size [default: 16].
    #[arg(long)]
    batch: Option<usize>,
    /// Training window, frames: a multiple of 8 [default: 64].
    #[arg(long)]
    window: Option<usize>,
    /// Write a checkpoint every N steps (and at the end).
    #[arg(long, default_value_t = 500, value_name = "N")]
    checkpoint_every: u64,
    /// Held-out evaluation every N steps (and at the end; 0: only at the end).
    #[arg(long, default_value_t = 1000, value_name = "N")]
    eval_every: u64,
    /// At most this many held-out windows per evaluation.
    #[arg(long, default_value_t = 512, value_name = "N")]
    eval_windows: usize,
    /// Threads for loading the takes and for the CPU kernels (sets RAYON_NUM_THREADS unless it
    /// is set) [default: all cores].
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Held-out split file.
    #[arg(long, default_value = train::DEFAULT_SPLIT, value_name = "FILE")]
    split: PathBuf,
    /// When stderr is not a terminal: one progress line every N steps.
    #[arg(long, default_value_t = 100, value_name = "N")]
    log_every: u64,
}

pub fn run(args: TrainArgs) -> anyhow::Result<()> {
    let (common, stage) = match args.stage {
        StageArgs::Ae(common) => (common, Stage::Ae),
        StageArgs::Classifier(common) => (common, Stage::Classifier),
        StageArgs::Stylizer { common, ae, unsupervised } => (common, Stage::Stylizer { ae, supervised: !unsupervised }),
    };
    if let Some(w) = common.window {
        train::check_window(w)?;
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = common.threads.unwrap_or(cores).max(1);
    if common.threads.is_some() && std::env::var_os("RAYON_NUM_THREADS").is_none() {
        // SAFETY: still single-threaded here (nothing has started a thread or the rayon pool).
        unsafe { std::env::set_var("RAYON_NUM_THREADS", threads.to_string()) };
    }
    let mut opts = TrainOptions::new(stage, common.data, common.out);
    opts.split = common.split;
    opts.resume = common.resume;
    opts.steps = common.steps;
    opts.seed = common.seed;
    opts.width = common.width;
    opts.batch = common.batch;
    opts.window = common.window;
    opts.checkpoint_every = common.checkpoint_every;
    opts.eval_every = common.eval_every;
    opts.eval_windows = common.eval_windows;
    opts.threads = threads;
    opts.log_every = common.log_every;
    opts.progress = ProgressMode::Auto;
    let summary = train::train(&opts)?;
    let fmt = |v: &[(String, f64)]| v.iter().map(|(n, x)| format!("{n} {x:.4}")).collect::<Vec<_>>().join(", ");
    println!("step {}", summary.step);
    println!("last step: {}", fmt(&summary.losses));
    if !summary.heldout.is_empty() {
        println!("held-out: {}", fmt(&summary.heldout));
    }
    Ok(())
}
