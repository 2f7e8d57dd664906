//! `motion-stylizer train ae|stylizer|classifier|all --data DIR --out DIR [...]`: see
//! [`motion_stylizer::train`].

use clap::{Args, Subcommand};
use motion_stylizer::model::device::DeviceName;
use motion_stylizer::train::all::AllOptions;
use motion_stylizer::train::{self, ProgressMode, SettingChoices, Stage, TrainOptions};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct TrainArgs {
    #[command(subcommand)]
    stage: StageArgs,
}

#[derive(Subcommand, Debug)]
enum StageArgs {
    /// Stage 1: the motion autoencoder and the global motion regressor.
    Ae(TrainOptions),
    /// Stage 2: the stylizer (content encoder, style encoder and generator) on a frozen autoencoder.
    Stylizer {
        #[command(flatten)]
        options: TrainOptions,
        /// The `ae` run (folder, or its checkpoint.bin) whose autoencoder to train on; its latest
        /// checkpoint is copied into the new run. Not needed with --resume.
        #[arg(long, value_name = "DIR")]
        ae: Option<PathBuf>,
        /// Train without style labels (default: supervised, with the unified labels).
        #[arg(long)]
        unsupervised: bool,
        #[command(flatten)]
        extra: train::losses::StylizerExtras,
    },
    /// The evaluation's style classifier, on the training takes only (`eval` uses it).
    Classifier(TrainOptions),
    /// The evaluation's content classifier (the content classes, content-balanced), on the
    /// training takes only (`eval --content-classifier` uses it).
    ContentClassifier(TrainOptions),
    /// Every stage in order (autoencoder + regressor, the stylizers the labels allow, the style
    /// classifier) and the export to OUT/weights/; run it again to resume.
    All(AllArgs),
}

#[derive(Args, Debug)]
struct AllArgs {
    /// The data: a folder of BVH files (searched recursively) with an optional labels.csv
    /// (`file,style[,content]`), or the Bandai-Namco layout (DIR/dataset-1, DIR/dataset-2).
    #[arg(long, value_name = "DIR")]
    data: PathBuf,
    /// Run folder: one sub-folder per stage, weights/ and report.json.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Fine-tuning: start every stage from this weights folder (e.g. assets/weights); the data's
    /// new labels are added to its label set.
    #[arg(long, value_name = "WEIGHTS")]
    from: Option<PathBuf>,
    /// Steps of the autoencoder stage; the stylizers get 4/3 of it, the classifier 1/4.
    #[arg(long, default_value_t = 12_000, value_name = "N")]
    steps: u64,
    #[command(flatten)]
    settings: SettingChoices,
    /// Threads for loading and for the CPU kernels [default: all cores].
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Held-out split file (Bandai-Namco data only).
    #[arg(long, default_value = train::DEFAULT_SPLIT, value_name = "FILE")]
    split: PathBuf,
    /// Write a checkpoint every N steps (and at the end of each stage).
    #[arg(long, default_value_t = 500, value_name = "N")]
    checkpoint_every: u64,
    /// Held-out evaluation every N steps (and at the end; 0: only at the end).
    #[arg(long, default_value_t = 1000, value_name = "N")]
    eval_every: u64,
    /// At most this many held-out windows per evaluation.
    #[arg(long, default_value_t = 512, value_name = "N")]
    eval_windows: usize,
    /// When stderr is not a terminal: one progress line every N steps.
    #[arg(long, default_value_t = 100, value_name = "N")]
    log_every: u64,
    /// Compute device of every stage: cpu (flex) or wgpu (cargo feature `wgpu`; cuda is not
    /// built, see `src/model/device.rs`). The export runs on the CPU.
    #[arg(long, default_value_t = DeviceName::Cpu, value_name = "cpu|wgpu|cuda")]
    device: DeviceName,
}

fn set_threads(threads: Option<usize>) {
    if let Some(threads) = threads
        && std::env::var_os("RAYON_NUM_THREADS").is_none()
    {
        // SAFETY: still single-threaded here (nothing has started a thread or the rayon pool).
        unsafe { std::env::set_var("RAYON_NUM_THREADS", threads.max(1).to_string()) };
    }
}

fn run_all(args: AllArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.checkpoint_every >= 1, "--checkpoint-every must be at least 1");
    set_threads(args.threads);
    let opts = AllOptions {
        data: args.data,
        out: args.out,
        from: args.from,
        steps: args.steps,
        settings: args.settings,
        threads: args.threads,
        split: args.split,
        checkpoint_every: args.checkpoint_every,
        eval_every: args.eval_every,
        eval_windows: args.eval_windows,
        log_every: args.log_every,
        device: args.device,
        progress: ProgressMode::Auto,
        command: std::env::args().collect::<Vec<_>>().join(" "),
    };
    let report = train::all::train_all(&opts)?;
    print!("{}", report.text());
    Ok(())
}

pub fn run(args: TrainArgs) -> anyhow::Result<()> {
    let (options, stage) = match args.stage {
        StageArgs::All(all) => return run_all(all),
        StageArgs::Ae(options) => (options, Stage::Ae),
        StageArgs::Classifier(options) => (options, Stage::Classifier),
        StageArgs::ContentClassifier(options) => (options, Stage::ContentClassifier),
        StageArgs::Stylizer { options, ae, unsupervised, extra } => {
            extra.validate().map_err(anyhow::Error::msg)?;
            (options, Stage::Stylizer { ae, supervised: !unsupervised, extra })
        }
    };
    options.validate()?;
    set_threads(options.threads);
    let summary = train::train(&stage, &options)?;
    let fmt = |v: &[(String, f64)]| v.iter().map(|(n, x)| format!("{n} {x:.4}")).collect::<Vec<_>>().join(", ");
    println!("step {}", summary.step);
    println!("last step: {}", fmt(&summary.losses));
    if !summary.heldout.is_empty() {
        println!("held-out: {}", fmt(&summary.heldout));
    }
    Ok(())
}
