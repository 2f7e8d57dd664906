//! `motion-stylizer stylize CONTENT.bvh (--style-motion REF.bvh [--label NAME] | --label NAME |
//! --prior) [--unsupervised] [--samples N] [--seed S] [--canonical] [--weights DIR] -o OUT.bvh`.

use super::output::Rig;
use anyhow::{Context, bail};
use clap::Args;
use motion_stylizer::skeleton::{self, Imported};
use motion_stylizer::stylize::{self, Request, Setting, StyleSource, Weights};
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct StylizeArgs {
    /// The motion to stylize (BVH, any rig the importer knows).
    content: PathBuf,
    /// Motion-based: take the style of this motion (BVH, any rig). The supervised model takes its
    /// style label from --label, or infers it (and says which); the unsupervised one
    /// (--unsupervised) takes none.
    #[arg(long, value_name = "REF.bvh", conflicts_with = "prior")]
    style_motion: Option<PathBuf>,
    /// Label-based (supervised model): the target style label (see `motion-stylizer styles`).
    /// With --style-motion: the reference motion's style label.
    #[arg(long, value_name = "NAME", conflicts_with = "prior")]
    label: Option<String>,
    /// Prior-based: a random style from the prior (supervised model: with a random label).
    #[arg(long)]
    prior: bool,
    /// Use the model trained without style labels.
    #[arg(long)]
    unsupervised: bool,
    /// Number of outputs (1-64). N = 1 writes OUT.bvh; N > 1 writes OUT_0.bvh ... OUT_{N-1}.bvh.
    /// Motion-based: 1 is the reference's posterior mean, more are draws from its posterior.
    #[arg(long, default_value_t = 1, value_name = "N")]
    samples: usize,
    /// Seed of the random style draws (same seed, same output bytes).
    #[arg(long, default_value_t = 0, value_name = "S")]
    seed: u64,
    /// Scale of the style codes drawn from the prior (label- and prior-based), 0-4; 1 is the
    /// paper's N(0, I). Lower: closer to the label's typical style, less variety.
    #[arg(long, default_value_t = stylize::DEFAULT_TEMPERATURE, value_name = "T")]
    temperature: f32,
    /// How far towards the style, 0-2: 0 gives back the content's motion, 1 the stylizer's
    /// output, 2 twice its change (exaggerated).
    #[arg(long, default_value_t = stylize::DEFAULT_STRENGTH, value_name = "S")]
    strength: f32,
    /// Write the output on the canonical 21-joint rig instead of the content's own rig.
    #[arg(long)]
    canonical: bool,
    /// Joint mapping of the content, JSON: canonical joint -> the content's joint (or null); see
    /// `inspect --json`.
    #[arg(long, value_name = "FILE.json")]
    map: Option<PathBuf>,
    /// Trained weights folder (manifest.json, norm.json, supervised.bin, unsupervised.bin).
    /// Default: assets/weights in the crate.
    #[arg(long, value_name = "DIR")]
    weights: Option<PathBuf>,
    /// Output path: BVH, or binary glTF when it ends in .glb.
    #[arg(short, long, value_name = "OUT.bvh|OUT.glb")]
    output: PathBuf,
}

/// The weights folder shipped with the crate.
pub fn default_weights_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets").join("weights")
}

/// Loads the weights folder, with an error that says what to do when there is none.
pub fn load_weights(dir: &Path) -> anyhow::Result<Weights> {
    if !dir.join("manifest.json").is_file() {
        bail!("no trained weights at {}; train them (README) or pass --weights DIR", dir.display());
    }
    Weights::load_dir(dir).with_context(|| format!("cannot load the weights at {}", dir.display()))
}

fn import(path: &Path, map: Option<&skeleton::ManualMap>) -> anyhow::Result<Imported> {
    let text = super::read_text(path)?;
    skeleton::import_bvh_with(&text, map).with_context(|| format!("cannot import {}", path.display()))
}

/// `OUT.bvh` for one sample; `OUT_i.bvh` for sample `i` of several.
pub fn output_path(output: &Path, index: usize, samples: usize) -> PathBuf {
    if samples == 1 {
        return output.to_path_buf();
    }
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = match output.extension() {
        Some(ext) => format!("{stem}_{index}.{}", ext.to_string_lossy()),
        None => format!("{stem}_{index}"),
    };
    output.with_file_name(name)
}

pub fn run(args: &StylizeArgs) -> anyhow::Result<()> {
    if args.style_motion.is_none() && args.label.is_none() && !args.prior {
        bail!("give a style: --style-motion REF.bvh, --label NAME or --prior");
    }
    let setting = if args.unsupervised { Setting::Unsupervised } else { Setting::Supervised };
    let dir = args.weights.clone().unwrap_or_else(default_weights_dir);
    let weights = load_weights(&dir)?;
    let label = args.label.as_deref().map(|name| weights.style(name)).transpose()?;

    let map = super::read_map(args.map.as_deref())?;
    let content = import(&args.content, map.as_ref())?;
    let reference = args.style_motion.as_deref().map(|p| import(p, None)).transpose()?;
    // Supervised motion-based without a label: the reference's label is inferred.
    let label = match (&reference, label, setting) {
        (Some(r), None, Setting::Supervised) => {
            let (style, _) = stylize::infer_label(&weights, &r.motion)?;
            let name = weights.style_name(style).unwrap_or("?");
            eprintln!("inferred the reference's label: {name} (pass --label to choose it)");
            Some(style)
        }
        (_, label, _) => label,
    };
    let source = match (&reference, label) {
        (Some(r), label) => StyleSource::Motion { motion: &r.motion, label },
        (None, Some(label)) => StyleSource::Label(label),
        (None, None) => StyleSource::Prior,
    };
    let request = Request {
        source,
        setting,
        samples: args.samples,
        seed: args.seed,
        temperature: args.temperature,
        strength: args.strength,
    };
    let motions = stylize::stylize(&weights, &content.motion, &request)?;

    let outputs: Vec<_> =
        motions.iter().map(|m| if args.canonical { m.to_bvh() } else { content.rig.from_canonical(m) }).collect();
    let rig = || if args.canonical { Rig::Canonical } else { Rig::User(content.rig.report()) };
    for (i, bvh) in outputs.iter().enumerate() {
        let path = output_path(&args.output, i, outputs.len());
        super::output::write_motion(&path, bvh, rig())?;
        eprintln!(
            "{} ({} frames) -> {} ({}, {setting})",
            args.content.display(),
            content.motion.frames(),
            path.display(),
            if args.canonical { "canonical rig".to_string() } else { format!("{} rig", content.rig.report().rig) }
        );
    }
    Ok(())
}
