//! `motion-stylizer stylize CONTENT.bvh (--style-motion REF.bvh [--label NAME] | --label NAME |
//! --prior) [--unsupervised] [--samples N] [--seed S] [--canonical] [--weights DIR] -o OUT.bvh`;
//! several contents or folders at once with `-o OUTDIR` (a batch: a progress bar, each file on its
//! own rig under its own name, files that fail reported and skipped).

use super::output::Rig;
use anyhow::{Context, bail};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use motion_stylizer::model::device::{self, DeviceName};
use motion_stylizer::skeleton::{self, Imported};
use motion_stylizer::stylize::{self, BodyPart, PartRequests, Request, Setting, StyleSource, Weights};
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct StylizeArgs {
    /// The motion(s) to stylize (BVH, any rig the importer knows). Several files, or folders
    /// (searched recursively for .bvh files), make a batch: then -o is a folder.
    #[arg(required = true, num_args = 1.., value_name = "CONTENT.bvh|DIR")]
    content: Vec<PathBuf>,
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
    /// Style guidance, 0-3: how much further the output goes along the difference between the
    /// style's and the neutral style's (`normal`) outputs for this content; 0 is the networks'
    /// output as trained (README and EVALUATION.md, "Guidance").
    #[arg(long, default_value_t = stylize::DEFAULT_GUIDANCE, value_name = "G")]
    guidance: f32,
    /// Write the output on the canonical 21-joint rig instead of the content's own rig.
    #[arg(long)]
    canonical: bool,
    /// Joint mapping of the content, JSON: canonical joint -> the content's joint (or null); see
    /// `inspect --json`.
    #[arg(long, value_name = "FILE.json")]
    map: Option<PathBuf>,
    /// Joint mapping of the reference motions (--style-motion, --part ...=motion:REF.bvh), as
    /// --map is the content's.
    #[arg(long, value_name = "FILE.json")]
    style_map: Option<PathBuf>,
    /// Trained weights folder (manifest.json, norm.json, supervised.bin, unsupervised.bin).
    /// Default: assets/weights in the crate.
    #[arg(long, value_name = "DIR")]
    weights: Option<PathBuf>,
    /// Output path: BVH, or binary glTF when it ends in .glb. For a batch: the output folder
    /// (created if missing), where each content keeps its name (and its path below a folder given).
    #[arg(short, long, value_name = "OUT.bvh|OUT.glb|OUTDIR")]
    output: PathBuf,
    /// A style for one body part, repeatable: PART=STYLE with PART lower (root and legs), upper
    /// (spine and arms) or head (neck and head), and STYLE label:NAME, motion:REF.bvh, prior or
    /// content (the content's own motion). Parts not given take the main style (--label,
    /// --style-motion, --prior), or keep the content when there is none.
    #[arg(long = "part", value_name = "PART=STYLE")]
    parts: Vec<String>,
    /// The format of a batch's outputs (a single output's comes from its extension).
    #[arg(long, value_enum, default_value_t = BatchFormat::Bvh)]
    format: BatchFormat,
    /// Compute device: cpu (flex) or wgpu (cargo feature `wgpu`; cuda is not built, see
    /// `src/model/device.rs`).
    #[arg(long, default_value_t = DeviceName::Cpu, value_name = "cpu|wgpu|cuda")]
    device: DeviceName,
}

/// The file format of a batch's outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BatchFormat {
    Bvh,
    Glb,
}

impl BatchFormat {
    fn extension(self) -> &'static str {
        match self {
            BatchFormat::Bvh => "bvh",
            BatchFormat::Glb => "glb",
        }
    }
}

/// One content of a batch: the file, and its output path without extension (relative to the
/// output folder).
#[derive(Debug, PartialEq, Eq)]
struct BatchItem {
    path: PathBuf,
    name: PathBuf,
}

/// The contents of a batch, in a stable order: files as given (named by their file name), folders
/// searched recursively for `.bvh` files (named by their path below the folder). Two contents
/// with one output name are an error (nothing may overwrite another's output).
fn batch_items(inputs: &[PathBuf]) -> anyhow::Result<Vec<BatchItem>> {
    fn walk(dir: &Path, found: &mut Vec<PathBuf>) -> anyhow::Result<()> {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .with_context(|| format!("cannot read the folder {}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, found)?;
            } else if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("bvh")) {
                found.push(path);
            }
        }
        Ok(())
    }
    let mut items = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found = Vec::new();
            walk(input, &mut found)?;
            if found.is_empty() {
                bail!("no .bvh files in the folder {}", input.display());
            }
            for path in found {
                let name = path.strip_prefix(input).unwrap_or(&path).with_extension("");
                items.push(BatchItem { path, name });
            }
        } else {
            let stem = input.file_stem().with_context(|| format!("not a file name: {}", input.display()))?;
            items.push(BatchItem { path: input.clone(), name: PathBuf::from(stem) });
        }
    }
    let mut names: Vec<&Path> = items.iter().map(|i| i.name.as_path()).collect();
    names.sort();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        bail!("two contents would write the same output {} (give them from different folders)", w[0].display());
    }
    Ok(items)
}

/// The weights folder shipped with the crate.
pub fn default_weights_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets").join("weights")
}

/// Loads the weights folder onto the CPU, with an error that says what to do when there is none;
/// for stylizing and evaluating only ([`Weights::prepare_for_inference`]: never train them).
pub fn load_weights(dir: &Path) -> anyhow::Result<Weights> {
    load_weights_on(&burn::tensor::Device::flex(), dir)
}

/// [`load_weights`] onto `device`.
pub fn load_weights_on(device: &burn::tensor::Device, dir: &Path) -> anyhow::Result<Weights> {
    if !dir.join("manifest.json").is_file() {
        bail!("no trained weights at {}; train them (README) or pass --weights DIR", dir.display());
    }
    let mut weights =
        Weights::load_dir_on(device, dir).with_context(|| format!("cannot load the weights at {}", dir.display()))?;
    weights.prepare_for_inference();
    Ok(weights)
}

/// The compute device `--device` names, with what it is said on stderr when not the CPU.
pub fn open_device(name: DeviceName) -> anyhow::Result<burn::tensor::Device> {
    let device = device::open(name)?;
    if name != DeviceName::Cpu {
        eprintln!("device: {name} ({})", device::adapter_name(&device).unwrap_or_else(|| "?".into()));
    }
    Ok(device)
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

/// A style as the command line gives it (the main one, or a body part's).
#[derive(Clone, Debug, PartialEq)]
enum StyleArg {
    Motion { path: PathBuf, label: Option<String> },
    Label(String),
    Prior,
    Content,
}

/// `PART=STYLE` of `--part` (see [`StylizeArgs`]).
fn parse_part(text: &str) -> anyhow::Result<(BodyPart, StyleArg)> {
    let Some((part, style)) = text.split_once('=') else {
        bail!("--part {text:?}: write PART=STYLE, e.g. upper=label:angry");
    };
    let Some(part) = BodyPart::from_name(part.trim()) else {
        bail!("--part {text:?}: the parts are lower, upper and head");
    };
    let style = match style.trim().split_once(':') {
        Some(("label", name)) => StyleArg::Label(name.to_string()),
        Some(("motion", path)) => StyleArg::Motion { path: PathBuf::from(path), label: None },
        None if style.trim() == "prior" => StyleArg::Prior,
        None if style.trim() == "content" => StyleArg::Content,
        _ => bail!("--part {text:?}: the style is label:NAME, motion:REF.bvh, prior or content"),
    };
    Ok((part, style))
}

/// A [`StyleArg`]'s source: its reference imported (and, for the supervised model without a
/// label, the reference's label inferred, said on stderr). `None` for [`StyleArg::Content`].
fn resolve_style(
    style: &StyleArg,
    weights: &Weights,
    setting: Setting,
    style_map: Option<&skeleton::ManualMap>,
) -> anyhow::Result<Option<(Option<Imported>, Option<motion_stylizer::dataset::Style>)>> {
    Ok(Some(match style {
        StyleArg::Content => return Ok(None),
        StyleArg::Prior => (None, None),
        StyleArg::Label(name) => (None, Some(weights.style(name)?)),
        StyleArg::Motion { path, label } => {
            let reference = import(path, style_map)?;
            let label = match (label, setting) {
                (Some(name), _) => Some(weights.style(name)?),
                (None, Setting::Supervised) => {
                    let (style, _) = stylize::infer_label(weights, &reference.motion)?;
                    let name = weights.style_name(style).unwrap_or("?");
                    eprintln!(
                        "inferred the reference's label: {name} (of {}; pass --label to choose it)",
                        path.display()
                    );
                    Some(style)
                }
                (None, Setting::Unsupervised) => None,
            };
            (Some(reference), label)
        }
    }))
}

fn source_of<'a>(resolved: &'a (Option<Imported>, Option<motion_stylizer::dataset::Style>)) -> StyleSource<'a> {
    match resolved {
        (Some(r), label) => StyleSource::Motion { motion: &r.motion, label: *label },
        (None, Some(label)) => StyleSource::Label(*label),
        (None, None) => StyleSource::Prior,
    }
}

pub fn run(args: &StylizeArgs) -> anyhow::Result<()> {
    let main = match (&args.style_motion, &args.label, args.prior) {
        (Some(path), label, _) => Some(StyleArg::Motion { path: path.clone(), label: label.clone() }),
        (None, Some(name), _) => Some(StyleArg::Label(name.clone())),
        (None, None, true) => Some(StyleArg::Prior),
        (None, None, false) => None,
    };
    let parts: Vec<(BodyPart, StyleArg)> = args.parts.iter().map(|p| parse_part(p)).collect::<anyhow::Result<_>>()?;
    if main.is_none() && parts.is_empty() {
        bail!("give a style: --style-motion REF.bvh, --label NAME or --prior (or --part PART=STYLE)");
    }
    let setting = if args.unsupervised { Setting::Unsupervised } else { Setting::Supervised };
    let dir = args.weights.clone().unwrap_or_else(default_weights_dir);
    let weights = load_weights_on(&open_device(args.device)?, &dir)?;
    let map = super::read_map(args.map.as_deref())?;
    let style_map = super::read_map(args.style_map.as_deref())?;
    let request = |source| Request {
        source,
        setting,
        samples: args.samples,
        seed: args.seed,
        temperature: args.temperature,
        strength: args.strength,
        guidance: args.guidance,
    };
    let main_resolved =
        main.as_ref().map(|m| resolve_style(m, &weights, setting, style_map.as_ref())).transpose()?.flatten();
    let part_resolved: Vec<_> = BodyPart::ALL
        .iter()
        .map(|&part| match parts.iter().rev().find(|(p, _)| *p == part) {
            Some((_, style)) => resolve_style(style, &weights, setting, style_map.as_ref()),
            None => Ok(None),
        })
        .collect::<anyhow::Result<_>>()?;
    let mut part_requests = PartRequests::default();
    for (i, &part) in BodyPart::ALL.iter().enumerate() {
        let given = parts.iter().any(|(p, _)| *p == part);
        let resolved = if given { part_resolved[i].as_ref() } else { main_resolved.as_ref() };
        if let Some(resolved) = resolved {
            part_requests.set(part, request(source_of(resolved)));
        }
    }
    let whole = match &main_resolved {
        Some(resolved) if parts.is_empty() => Some(request(source_of(resolved))),
        _ => None,
    };
    let plan = match &whole {
        Some(request) => Plan::Whole(request),
        None => Plan::Parts(&part_requests),
    };
    let job = Job { args, weights: &weights, plan, map: map.as_ref() };
    let batch = args.content.len() > 1 || args.content.iter().any(|c| c.is_dir());
    if !batch {
        return job.one(&args.content[0], &args.output, true);
    }

    let items = batch_items(&args.content)?;
    if args.output.is_file() {
        bail!("{} is a file; a batch writes into a folder (-o OUTDIR)", args.output.display());
    }
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        ProgressBar::with_draw_target(Some(items.len() as u64), ProgressDrawTarget::stderr())
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} files, {elapsed} (ETA {eta}) {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut failed = Vec::new();
    for item in &items {
        bar.set_message(item.path.display().to_string());
        let out = args.output.join(&item.name).with_extension(args.format.extension());
        let written = out
            .parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .with_context(|| format!("cannot create the folder for {}", out.display()))
            .and_then(|()| job.one(&item.path, &out, false));
        if let Err(e) = written {
            bar.suspend(|| eprintln!("skipped {}: {e:#}", item.path.display()));
            failed.push(item.path.display().to_string());
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let done = items.len() - failed.len();
    eprintln!("stylized {done} of {} files into {}", items.len(), args.output.display());
    if !failed.is_empty() {
        bail!("{} of {} files failed: {}", failed.len(), items.len(), failed.join(", "));
    }
    Ok(())
}

/// What every content of one `stylize` call shares.
struct Job<'a> {
    args: &'a StylizeArgs,
    weights: &'a Weights,
    plan: Plan<'a>,
    map: Option<&'a skeleton::ManualMap>,
}

/// One style for the whole body, or one per body part.
enum Plan<'a> {
    Whole(&'a Request<'a>),
    Parts(&'a PartRequests<'a>),
}

impl Job<'_> {
    /// Stylizes one content into `output` (its samples as `output_i`), on the content's rig or the
    /// canonical one; `report`: one line per file written.
    fn one(&self, content_path: &Path, output: &Path, report: bool) -> anyhow::Result<()> {
        let args = self.args;
        let content = import(content_path, self.map)?;
        let motions = match self.plan {
            Plan::Whole(request) => stylize::stylize(self.weights, &content.motion, request)?,
            Plan::Parts(parts) => stylize::stylize_parts(self.weights, &content.motion, parts)?,
        };
        let outputs: Vec<_> =
            motions.iter().map(|m| if args.canonical { m.to_bvh() } else { content.rig.from_canonical(m) }).collect();
        let rig = || if args.canonical { Rig::Canonical } else { Rig::User(content.rig.report()) };
        for (i, bvh) in outputs.iter().enumerate() {
            let path = output_path(output, i, outputs.len());
            super::output::write_motion(&path, bvh, rig())?;
            if report {
                eprintln!(
                    "{} ({} frames) -> {} ({}, {})",
                    content_path.display(),
                    content.motion.frames(),
                    path.display(),
                    if args.canonical {
                        "canonical rig".to_string()
                    } else {
                        format!("{} rig", content.rig.report().rig)
                    },
                    if args.unsupervised { Setting::Unsupervised } else { Setting::Supervised }
                );
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_items_name_files_by_name_and_folder_contents_by_their_path() {
        let dir = std::env::temp_dir().join(format!("ms-batch-items-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("clips/sub")).unwrap();
        for f in ["clips/b.bvh", "clips/a.BVH", "clips/sub/b.bvh", "clips/notes.txt", "one.bvh"] {
            std::fs::write(dir.join(f), "").unwrap();
        }
        let items = batch_items(&[dir.join("one.bvh"), dir.join("clips")]).unwrap();
        let names: Vec<_> = items.iter().map(|i| i.name.to_string_lossy().into_owned()).collect();
        assert_eq!(names, ["one", "a", "b", "sub/b"]);
        // The same name twice would overwrite an output: refused.
        let err = batch_items(&[dir.join("one.bvh"), dir.join("one.bvh")]).unwrap_err();
        assert!(err.to_string().contains("same output"), "{err}");
        std::fs::create_dir_all(dir.join("empty")).unwrap();
        assert!(batch_items(&[dir.join("empty")]).unwrap_err().to_string().contains("no .bvh files"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
