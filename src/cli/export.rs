//! `motion-stylizer export --sup RUN --unsup RUN --ae RUN -o assets/weights`, or
//! `motion-stylizer export --from WEIGHTS_DIR -o OUT --shared q8 --stylizer q4g64` (with
//! `--sup RUN` / `--unsup RUN`: a fine-tuned run's stylizer replaces the folder's): see
//! [`motion_stylizer::train::export`].

use anyhow::Context;
use clap::Args;
use motion_stylizer::model::weights::PartEncoding;
use motion_stylizer::stylize::Setting;
use motion_stylizer::train::export::{EncodingChoice, Encodings};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// The supervised `stylizer` run folder.
    #[arg(long, value_name = "RUN_DIR", required_unless_present = "from")]
    sup: Option<PathBuf>,
    /// The unsupervised `stylizer` run folder.
    #[arg(long, value_name = "RUN_DIR", required_unless_present = "from")]
    unsup: Option<PathBuf>,
    /// The `ae` run folder the stylizers were trained on (provenance and norm.json).
    #[arg(long, value_name = "RUN_DIR", required_unless_present = "from")]
    ae: Option<PathBuf>,
    /// Instead of runs: an existing weights folder (format 1, 2 or 3), written again in format 3;
    /// with --sup and/or --unsup, runs fine-tuned from it (`train stylizer --from`) replace its
    /// stylizers.
    #[arg(long, value_name = "WEIGHTS_DIR", conflicts_with = "ae")]
    from: Option<PathBuf>,
    /// Encoding of the shared networks' large layers: f16, q8 (int8, a scale per output
    /// channel), q4 (int4), q4g64 (int4, a scale per 64 weights of an output channel), ...
    /// Default: with --from, the folder's own; otherwise f16.
    #[arg(long, value_name = "ENCODING")]
    shared: Option<String>,
    /// Encoding of each stylizer's large layers (as --shared), with per path prefix another one:
    /// `q7,style_encoder=q8g32`. Default: with --from, the folder's own; otherwise f16.
    #[arg(long, value_name = "ENCODING")]
    stylizer: Option<String>,
    /// Encoding of the unsupervised stylizer's large layers, if not --stylizer's (a browser
    /// fetches it apart, when first used: its own size budget).
    #[arg(long, value_name = "ENCODING")]
    unsupervised: Option<String>,
    /// Output folder.
    #[arg(short, long, default_value = "assets/weights", value_name = "DIR")]
    output: PathBuf,
}

pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let parse = |flag: &str, spec: &str| {
        PartEncoding::parse(spec)
            .with_context(|| format!("--{flag} {spec:?}: not an encoding (f16, q8, q4, q4g64, ...)"))
    };
    let chosen = |flag: &str, spec: &Option<String>| spec.as_deref().map(|spec| parse(flag, spec)).transpose();
    let stylizer = chosen("stylizer", &args.stylizer)?;
    let unsupervised = chosen("unsupervised", &args.unsupervised)?.or_else(|| stylizer.clone());
    // With --from, what is not chosen keeps the folder's encoding (`EncodingChoice`); from runs, f16.
    let choice = EncodingChoice { shared: chosen("shared", &args.shared)?, supervised: stylizer, unsupervised };
    let manifest = match (&args.from, &args.sup, &args.unsup, &args.ae) {
        (Some(from), None, None, _) => motion_stylizer::train::export::repack(from, &args.output, choice)?,
        (Some(from), sup, unsup, _) => {
            let runs: Vec<(Setting, &std::path::Path)> = [(Setting::Supervised, sup), (Setting::Unsupervised, unsup)]
                .into_iter()
                .filter_map(|(s, d)| d.as_deref().map(|d| (s, d)))
                .collect();
            motion_stylizer::train::export::replace_stylizers(from, &runs, &args.output, choice)?
        }
        (None, Some(sup), Some(unsup), Some(ae)) => {
            motion_stylizer::train::export::export(sup, unsup, ae, &args.output, choice.over(Encodings::default()))?
        }
        _ => anyhow::bail!("give --sup, --unsup and --ae, or --from"),
    };
    if let Some(s) = &manifest.shared {
        eprintln!("shared -> {} ({} bytes, {})", args.output.join(&s.file.file).display(), s.file.bytes, s.encoding);
    }
    for m in &manifest.models {
        let steps: Vec<String> = m.stages.iter().map(|s| format!("{} {} steps", s.stage, s.steps)).collect();
        eprintln!(
            "{} -> {} ({} bytes, {}; {})",
            m.setting,
            args.output.join(&m.file).display(),
            m.bytes.unwrap_or(0),
            m.encoding.as_deref().unwrap_or("f16"),
            steps.join(", ")
        );
    }
    eprintln!("manifest -> {}", args.output.join("manifest.json").display());
    Ok(())
}
