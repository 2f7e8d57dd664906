//! `motion-stylizer styles [--weights DIR]`: the style labels, one per line, in one-hot order.

use anyhow::Context;
use motion_stylizer::dataset::STYLES;
use motion_stylizer::stylize::Manifest;
use std::path::Path;

/// Labels from `DIR/manifest.json` when it exists, else the built-in label set. An explicit
/// `--weights DIR` without a manifest is an error.
pub fn run(weights: Option<&Path>) -> anyhow::Result<()> {
    let dir = weights.map(Path::to_path_buf).unwrap_or_else(super::stylize::default_weights_dir);
    let manifest_path = dir.join("manifest.json");
    let labels: Vec<String> = if manifest_path.is_file() {
        let text = super::read_text(&manifest_path)?;
        let manifest: Manifest =
            serde_json::from_str(&text).with_context(|| format!("cannot read {}", manifest_path.display()))?;
        manifest.styles
    } else if weights.is_some() {
        anyhow::bail!("no trained weights at {} (no manifest.json)", dir.display());
    } else {
        STYLES.iter().map(|s| s.to_string()).collect()
    };
    let mut out = String::new();
    for label in labels {
        out.push_str(&label);
        out.push('\n');
    }
    print!("{out}");
    Ok(())
}
