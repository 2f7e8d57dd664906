//! Command-line arguments and dispatch; one file per subcommand.

#[cfg(feature = "model")]
mod eval;
#[cfg(feature = "model")]
mod export;
mod inspect;
#[cfg(feature = "model")]
mod label_codes;
mod output;
mod retarget;
mod split;
#[cfg(feature = "model")]
mod styles;
#[cfg(feature = "model")]
mod stylize;
#[cfg(feature = "model")]
mod train;

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "motion-stylizer",
    version,
    about = "Generative human motion stylization: BVH import, retargeting, stylization"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Show a BVH file's joints, frames, frame rate, detected rig and matched canonical joints.
    Inspect {
        file: PathBuf,
        /// Print one JSON object instead of text (with `map`, the joint mapping used, ready to
        /// edit for --map).
        #[arg(long)]
        json: bool,
        /// Joint mapping, JSON: canonical joint -> this file's joint (or null).
        #[arg(long, value_name = "FILE.json")]
        map: Option<PathBuf>,
    },
    /// Retarget a BVH onto the canonical rig at 30 fps, or onto the skeleton of another BVH.
    Retarget {
        file: PathBuf,
        /// Output path: BVH, or binary glTF when it ends in .glb.
        #[arg(short, long)]
        output: PathBuf,
        /// Put the motion on this BVH's skeleton instead of the canonical rig.
        #[arg(long, value_name = "RIG.bvh")]
        onto: Option<PathBuf>,
        /// Joint mapping of FILE, JSON: canonical joint -> FILE's joint (or null); see
        /// `inspect --json`.
        #[arg(long, value_name = "FILE.json")]
        map: Option<PathBuf>,
        /// Joint mapping of the --onto rig, as --map is FILE's.
        #[arg(long, value_name = "FILE.json", requires = "onto")]
        onto_map: Option<PathBuf>,
    },
    /// Choose the held-out takes of the Bandai-Namco data (writes the committed split file).
    Split {
        /// Folder with both archives unpacked: DIR/dataset-1, DIR/dataset-2.
        #[arg(long)]
        data: PathBuf,
        #[arg(long, default_value_t = 2024)]
        seed: u64,
        #[arg(short, long, default_value = "assets/split/heldout.txt")]
        output: PathBuf,
    },
    /// Stylize a BVH: style from a reference motion, a label or the prior; output on the content's
    /// rig (or the canonical one).
    #[cfg(feature = "model")]
    Stylize(stylize::StylizeArgs),
    /// List the style labels, one per line (from the weights' manifest, else the built-in set).
    #[cfg(feature = "model")]
    Styles {
        /// Trained weights folder (default: assets/weights in the crate).
        #[arg(long, value_name = "DIR")]
        weights: Option<PathBuf>,
    },
    /// Train on the Bandai-Namco data or a folder of your own BVH files (labels.csv): `ae` (motion
    /// autoencoder + regressor), then `stylizer` on its frozen autoencoder; or `all` stages and
    /// the export in one command.
    #[cfg(feature = "model")]
    Train(train::TrainArgs),
    /// Write the shipped weights folder (manifest, norm.json, f16 bundles) from finished runs.
    #[cfg(feature = "model")]
    Export(export::ExportArgs),
    /// Compute the supervised model's label codes (where each label's training takes sit in its
    /// style space; label-based styles are drawn around them) and the unsupervised model's neutral
    /// code (where its `normal` takes sit; guidance measures a reference against it) into the
    /// weights' manifest.
    #[cfg(feature = "model")]
    LabelCodes(label_codes::LabelCodesArgs),
    /// Evaluate the shipped weights: style accuracy, style FID, geodesic distance, diversity and
    /// foot skating per setting, with 95 % confidence intervals over repeats.
    #[cfg(feature = "model")]
    Eval(eval::EvalArgs),
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Inspect { file, json, map } => inspect::run(&file, json, map.as_deref()),
        Command::Retarget { file, output, onto, map, onto_map } => {
            retarget::run(&file, &output, onto.as_deref(), map.as_deref(), onto_map.as_deref())
        }
        Command::Split { data, seed, output } => split::run(&data, seed, &output),
        #[cfg(feature = "model")]
        Command::Stylize(args) => stylize::run(&args),
        #[cfg(feature = "model")]
        Command::Styles { weights } => styles::run(weights.as_deref()),
        #[cfg(feature = "model")]
        Command::Train(args) => train::run(args),
        #[cfg(feature = "model")]
        Command::Export(args) => export::run(&args),
        #[cfg(feature = "model")]
        Command::LabelCodes(args) => label_codes::run(&args),
        #[cfg(feature = "model")]
        Command::Eval(args) => eval::run(&args),
    }
}

/// Reads a text file with the path in the error.
fn read_text(path: &Path) -> anyhow::Result<String> {
    use anyhow::Context;
    std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Reads a joint mapping file (`--map`).
fn read_map(path: Option<&Path>) -> anyhow::Result<Option<motion_stylizer::skeleton::ManualMap>> {
    use anyhow::Context;
    let Some(path) = path else { return Ok(None) };
    let text = read_text(path)?;
    let map = motion_stylizer::skeleton::ManualMap::from_json(&text)
        .with_context(|| format!("cannot use the joint mapping {}", path.display()))?;
    Ok(Some(map))
}

/// Writes a text file with the path in the error.
fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    use anyhow::Context;
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}
