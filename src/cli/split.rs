//! `motion-stylizer split --data DIR [--seed S] -o assets/split/heldout.txt`: choose the held-out takes.

use anyhow::Context;
use motion_stylizer::dataset::{Split, corpus};
use std::path::Path;

pub fn run(data: &Path, seed: u64, output: &Path) -> anyhow::Result<()> {
    let takes: Vec<_> = corpus::list_takes(data)?.into_iter().map(|(id, _)| id).collect();
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
