//! `motion-stylizer train ae|stylizer|classifier --data DIR --out DIR [...]`: see
//! [`motion_stylizer::train`].

use clap::{Args, Subcommand};
use motion_stylizer::train::{self, Stage, TrainOptions};
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
    },
    /// The evaluation's style classifier, on the training takes only (`eval` uses it).
    Classifier(TrainOptions),
    /// The evaluation's content classifier (the content classes, content-balanced), on the
    /// training takes only (`eval --content-classifier` uses it).
    ContentClassifier(TrainOptions),
}

pub fn run(args: TrainArgs) -> anyhow::Result<()> {
    let (options, stage) = match args.stage {
        StageArgs::Ae(options) => (options, Stage::Ae),
        StageArgs::Classifier(options) => (options, Stage::Classifier),
        StageArgs::ContentClassifier(options) => (options, Stage::ContentClassifier),
        StageArgs::Stylizer { options, ae, unsupervised } => {
            (options, Stage::Stylizer { ae, supervised: !unsupervised })
        }
    };
    options.validate()?;
    if let Some(threads) = options.threads
        && std::env::var_os("RAYON_NUM_THREADS").is_none()
    {
        // SAFETY: still single-threaded here (nothing has started a thread or the rayon pool).
        unsafe { std::env::set_var("RAYON_NUM_THREADS", threads.max(1).to_string()) };
    }
    let summary = train::train(&stage, &options)?;
    let fmt = |v: &[(String, f64)]| v.iter().map(|(n, x)| format!("{n} {x:.4}")).collect::<Vec<_>>().join(", ");
    println!("step {}", summary.step);
    println!("last step: {}", fmt(&summary.losses));
    if !summary.heldout.is_empty() {
        println!("held-out: {}", fmt(&summary.heldout));
    }
    Ok(())
}
