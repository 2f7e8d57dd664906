//! `motion-stylizer eval --data DIR [--content DIR] [--repeats R] [--seed S] [--json OUT]`: see
//! [`motion_stylizer::eval`].

use anyhow::Context;
use burn::tensor::Device;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use motion_stylizer::dataset::Style;
use motion_stylizer::dataset::{CONTENTS, Split};
use motion_stylizer::eval::classify::Judge;
use motion_stylizer::eval::protocol::{self, Inputs};
use motion_stylizer::eval::report::{self, Provenance};
use motion_stylizer::eval::shift::Directions;
use motion_stylizer::eval::{direction_takes, heldout_of, import_takes, load_contents};
use motion_stylizer::features::NormStats;
use motion_stylizer::model::device::DeviceName;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Args, Debug)]
pub struct EvalArgs {
    /// Folder with both Bandai-Namco archives unpacked (DIR/dataset-1, DIR/dataset-2): the
    /// held-out takes give the style references, labels, the `real` row and (by default) contents.
    #[arg(long, value_name = "DIR")]
    data: PathBuf,
    /// Stylize every .bvh in this folder (any rig the importer accepts) instead of the held-out takes.
    #[arg(long, value_name = "DIR")]
    content: Option<PathBuf>,
    /// Repeats (new targets, references and noise each); the confidence intervals are over them.
    #[arg(long, default_value_t = 5, value_name = "R")]
    repeats: usize,
    /// Seed of the targets, references and style noise.
    #[arg(long, default_value_t = 0, value_name = "S")]
    seed: u64,
    /// Also write the results as JSON.
    #[arg(long, value_name = "OUT")]
    json: Option<PathBuf>,
    /// Only the contents whose name (a take's file stem, e.g. `dataset-1_walk_happy_001`, or a
    /// --content file's) starts with PREFIX, before --limit: e.g. `dataset-1_` for Bandai set 1's
    /// held-out takes, to see which contents keep their class.
    #[arg(long, value_name = "PREFIX")]
    content_prefix: Option<String>,
    /// At most this many contents (evenly spaced; 0: all).
    #[arg(long, default_value_t = 0, value_name = "N")]
    limit: usize,
    /// Trained weights folder [default: assets/weights in the crate].
    #[arg(long, value_name = "DIR")]
    weights: Option<PathBuf>,
    /// The style classifier (`train classifier` writes it as classifier.bin in its run folder)
    /// [default: assets/eval/classifier.bin in the crate].
    #[arg(long, value_name = "FILE")]
    classifier: Option<PathBuf>,
    /// Held-out split file.
    #[arg(long, default_value = "assets/split/heldout.txt", value_name = "FILE")]
    split: PathBuf,
    /// The content classifier (`train content-classifier` writes it as classifier.bin in its run
    /// folder) for content_acc and content_fid [default: assets/eval/content-classifier.bin in the
    /// crate, if it is there].
    #[arg(long, value_name = "FILE")]
    content_classifier: Option<PathBuf>,
    /// Also measure per-part styles: label-based with the target on the upper body only and on
    /// the lower body only, the style shift on each part's descriptors (a `parts` table).
    #[arg(long)]
    parts: bool,
    /// Style strength of every stylization (0-2; see `stylize --strength`).
    #[arg(long, default_value_t = motion_stylizer::stylize::DEFAULT_STRENGTH, value_name = "S")]
    strength: f32,
    /// Style guidance of every stylization (0-3; see `stylize --guidance`).
    #[arg(long, default_value_t = motion_stylizer::stylize::DEFAULT_GUIDANCE, value_name = "G")]
    guidance: f32,
    /// Temperature of the prior draws (see `stylize --temperature`).
    #[arg(long, default_value_t = motion_stylizer::stylize::DEFAULT_TEMPERATURE, value_name = "T")]
    temperature: f32,
    /// Compute device of the stylizers and classifiers: cpu (flex) or wgpu (cargo feature `wgpu`;
    /// cuda is not built, see `src/model/device.rs`).
    #[arg(long, default_value_t = DeviceName::Cpu, value_name = "cpu|wgpu|cuda")]
    device: DeviceName,
}

fn crate_path(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A path for the record: relative to the crate when inside it.
fn shown(path: &Path) -> String {
    path.strip_prefix(env!("CARGO_MANIFEST_DIR")).unwrap_or(path).display().to_string()
}

/// A trained classifier (`what`: "style", "content") from `path`, which must know `classes`
/// classes (`of`: what they are, for the error).
fn load_judge(
    device: &Device,
    path: &Path,
    what: &str,
    norm: &NormStats,
    classes: usize,
    of: &str,
) -> anyhow::Result<Judge> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read the {what} classifier {}", path.display()))?;
    let judge = Judge::from_bytes_on(device, &bytes, norm.clone())
        .with_context(|| format!("{} is not a {what} classifier", path.display()))?;
    anyhow::ensure!(
        judge.num_styles() == classes,
        "the {what} classifier {} knows {} classes, {of} {classes}",
        path.display(),
        judge.num_styles()
    );
    Ok(judge)
}

pub fn run(args: &EvalArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.repeats >= 1, "--repeats must be at least 1");
    let t0 = Instant::now();
    let weights_dir = args.weights.clone().unwrap_or_else(super::stylize::default_weights_dir);
    let device = super::stylize::open_device(args.device)?;
    let weights = super::stylize::load_weights_on(&device, &weights_dir)?;
    let classifier_path = args.classifier.clone().unwrap_or_else(|| crate_path("assets/eval/classifier.bin"));
    let judge =
        load_judge(&device, &classifier_path, "style", weights.norm(), weights.styles().len(), "the weights' styles")?;

    let content_path = match &args.content_classifier {
        Some(p) => Some(p.clone()),
        None => Some(crate_path("assets/eval/content-classifier.bin")).filter(|p| p.is_file()),
    };
    let content_judge = match &content_path {
        Some(path) => {
            Some(load_judge(&device, path, "content", weights.norm(), CONTENTS.len(), "the content classes")?)
        }
        None => {
            eprintln!("no content classifier (assets/eval/content-classifier.bin): no content_acc, content_fid");
            None
        }
    };

    let split_text = super::read_text(&args.split)?;
    let split = Split::parse(&split_text).with_context(|| format!("split file {}", args.split.display()))?;
    // Every take once: the held-out ones are the references and the `real` row, all of them give
    // the style directions.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let takes = import_takes(&args.data, threads, |_| true)?;
    let heldout =
        heldout_of(&takes, &split).with_context(|| format!("held-out takes under {}", args.data.display()))?;
    let mut contents = match &args.content {
        None => heldout.clone(),
        Some(dir) => {
            let (ok, failed) = load_contents(dir)?;
            for (path, why) in failed {
                eprintln!("warning: skipped {}: {why}", path.display());
            }
            ok
        }
    };
    if let Some(prefix) = &args.content_prefix {
        let all = contents.len();
        contents.retain(|c| c.name.starts_with(prefix.as_str()));
        anyhow::ensure!(
            !contents.is_empty(),
            "--content-prefix {prefix:?}: none of the {all} contents' names starts with it"
        );
    }
    if args.limit > 0 && contents.len() > args.limit {
        let n = contents.len();
        contents = (0..args.limit).map(|i| contents[i * n / args.limit].clone()).collect();
    }
    let takes = direction_takes(&takes);
    let normal = Style::from_name("normal").map(|s| s.index()).context("no `normal` style label")?;
    let directions = Directions::from_takes(&takes, normal);
    eprintln!("style directions from {} takes", takes.len());
    eprintln!("{} contents, {} held-out takes, {} repeats", contents.len(), heldout.len(), args.repeats);

    let bar = ProgressBar::with_draw_target(Some((contents.len() * args.repeats) as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} contents | {per_sec} | ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let inputs = Inputs {
        weights: &weights,
        judge: &judge,
        heldout: &heldout,
        contents: &contents,
        repeats: args.repeats,
        seed: args.seed,
        directions: Some(&directions),
        content_judge: content_judge.as_ref(),
        strength: args.strength,
        guidance: args.guidance,
        temperature: args.temperature,
        parts: args.parts,
    };
    let evaluation = protocol::evaluate(&inputs, &mut |done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();

    println!("{}", report::to_table(&evaluation.rows));
    println!("{}", report::labels_table(&evaluation, Some(&directions), weights.styles()));
    if !evaluation.parts.is_empty() {
        println!("{}", report::parts_table(&evaluation.parts));
    }
    let provenance = Provenance {
        command: std::env::args().collect::<Vec<_>>().join(" "),
        weights: shown(&weights_dir),
        classifier: shown(&classifier_path),
        content_classifier: content_path.as_deref().map(shown),
        contents: args.content.as_ref().map_or("heldout".into(), |d| d.display().to_string()),
        num_contents: contents.len(),
        num_heldout: heldout.len(),
        repeats: args.repeats,
        seed: args.seed,
        seconds: t0.elapsed().as_secs_f64(),
    };
    if let Some(path) = &args.json {
        let json = serde_json::to_string_pretty(&report::to_json(
            &evaluation,
            Some(&directions),
            weights.styles(),
            &provenance,
        ))?;
        super::write_text(path, &(json + "\n"))?;
        eprintln!("results -> {}", path.display());
    }
    Ok(())
}
