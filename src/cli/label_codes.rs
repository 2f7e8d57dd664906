//! `motion-stylizer label-codes --data data`: see [`motion_stylizer::train::label_codes`].

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use motion_stylizer::dataset::Split;
use motion_stylizer::eval::import_takes;
use motion_stylizer::stylize::{Manifest, Setting};

#[derive(Args, Debug)]
pub struct LabelCodesArgs {
    /// Folder with both Bandai-Namco archives unpacked (DIR/dataset-1, DIR/dataset-2): the
    /// training takes (those not in the split) are encoded.
    #[arg(long, value_name = "DIR")]
    data: PathBuf,
    /// Weights folder whose manifest.json gets the supervised model's label codes. Default:
    /// assets/weights in the crate.
    #[arg(long, value_name = "DIR")]
    weights: Option<PathBuf>,
    /// Held-out split file (its takes are left out).
    #[arg(long, default_value = "assets/split/heldout.txt", value_name = "FILE")]
    split: PathBuf,
}

pub fn run(args: &LabelCodesArgs) -> anyhow::Result<()> {
    let dir = args.weights.clone().unwrap_or_else(super::stylize::default_weights_dir);
    let weights = super::stylize::load_weights(&dir)?;
    let split_text = super::read_text(&args.split)?;
    let split = Split::parse(&split_text).with_context(|| format!("split file {}", args.split.display()))?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    eprintln!("importing the training takes under {}", args.data.display());
    let imported = import_takes(&args.data, threads, |t| !split.is_heldout(t))?;
    let mut takes = Vec::with_capacity(imported.len());
    for (take, motion) in &imported {
        match motion {
            Ok(m) => takes.push((take.clone(), m)),
            Err(e) => eprintln!("warning: skipped {e}"),
        }
    }
    anyhow::ensure!(!takes.is_empty(), "no training take under {}", args.data.display());
    let bar = ProgressBar::with_draw_target(Some(takes.len() as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} takes | ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let codes = motion_stylizer::train::label_codes::label_codes(&weights, &takes, command.clone(), |done, _| {
        bar.set_position(done as u64)
    })?;
    bar.finish_and_clear();
    let items = motion_stylizer::train::label_codes::bandai_items(&takes);
    let neutral = motion_stylizer::train::label_codes::neutral_code_of(&weights, &items, command)?;

    let path = dir.join("manifest.json");
    let mut manifest: Manifest = serde_json::from_str(&super::read_text(&path)?)
        .with_context(|| format!("{} is not a weights manifest", path.display()))?;
    let entry = manifest.entry_mut(Setting::Supervised).context("the manifest lists no supervised model")?;
    eprintln!("{} training takes encoded; per label: {:?}", takes.len(), codes.takes);
    entry.label_codes = Some(codes);
    if let Some(neutral) = neutral {
        eprintln!("unsupervised model's neutral code: {} `normal` training takes encoded", neutral.takes);
        if let Some(entry) = manifest.entry_mut(Setting::Unsupervised) {
            entry.neutral_code = Some(neutral);
        }
    }
    super::write_text(&path, &manifest.to_json()?)?;
    eprintln!("label codes -> {}", path.display());
    Ok(())
}
