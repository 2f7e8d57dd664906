//! `motion-stylizer export --sup RUN --unsup RUN --ae RUN -o assets/weights`: see
//! [`motion_stylizer::train::export`].

use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ExportArgs {
    /// The supervised `stylizer` run folder.
    #[arg(long, value_name = "RUN_DIR")]
    sup: PathBuf,
    /// The unsupervised `stylizer` run folder.
    #[arg(long, value_name = "RUN_DIR")]
    unsup: PathBuf,
    /// The `ae` run folder the stylizers were trained on (provenance and norm.json).
    #[arg(long, value_name = "RUN_DIR")]
    ae: PathBuf,
    /// Output folder.
    #[arg(short, long, default_value = "assets/weights", value_name = "DIR")]
    output: PathBuf,
}

pub fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let manifest = motion_stylizer::train::export::export(&args.sup, &args.unsup, &args.ae, &args.output)?;
    for m in &manifest.models {
        let steps: Vec<String> = m.stages.iter().map(|s| format!("{} {} steps", s.stage, s.steps)).collect();
        eprintln!("{} -> {} ({})", m.setting, args.output.join(&m.file).display(), steps.join(", "));
    }
    eprintln!("manifest -> {}", args.output.join("manifest.json").display());
    Ok(())
}
