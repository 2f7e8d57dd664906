//! `motion-stylizer split --data DIR [--seed S] -o assets/split/heldout.txt`: choose the held-out takes.

use anyhow::{Context, bail};
use motion_stylizer::dataset::{Split, TakeId};
use std::path::Path;

pub fn run(data: &Path, seed: u64, output: &Path) -> anyhow::Result<()> {
    let takes = list_takes(data)?;
    let split = Split::choose(&takes, seed);
    let header = format!(
        "Held-out takes of Bandai-Namco sets 1 and 2 ({} of {}); every other take is for training.\n\
         Made by: motion-stylizer split --data DIR --seed {seed}\n\
         Rule: ~10 % of each unified style, one take of every content with >= 3 takes (src/dataset/split.rs).",
        split.len(),
        takes.len()
    );
    if let Some(dir) = output.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    super::write_text(output, &split.to_text(&header))?;
    eprintln!("{} of {} takes held out -> {}", split.len(), takes.len(), output.display());
    Ok(())
}

/// Every take in `DIR/dataset-{1,2}/data/*.bvh`, sorted.
pub fn list_takes(data: &Path) -> anyhow::Result<Vec<TakeId>> {
    let mut takes = Vec::new();
    for set in ["dataset-1", "dataset-2"] {
        let dir = data.join(set).join("data");
        let entries = std::fs::read_dir(&dir)
            .with_context(|| format!("cannot list {} (unpack both archives into --data)", dir.display()))?;
        for entry in entries {
            let name = entry?.file_name().to_string_lossy().into_owned();
            if let Some(stem) = name.strip_suffix(".bvh") {
                match TakeId::parse(stem) {
                    Some(t) => takes.push(t),
                    None => bail!("{}: not a Bandai-Namco take name", dir.join(&name).display()),
                }
            }
        }
    }
    takes.sort();
    Ok(takes)
}
