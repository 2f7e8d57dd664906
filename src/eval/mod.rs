//! Evaluation (native only): does the stylization work? The paper's metrics on our held-out
//! takes, or on any folder of BVH files as contents (zero-shot).
//!
//! - [`classify`]: the style classifier (trained by `train classifier`) applied to motions;
//! - [`metrics`]: geodesic distance, foot skating, FID, confidence intervals;
//! - [`protocol`]: contents, targets, references and the rows of the table;
//! - [`report`]: the table and the JSON;
//! - [`shift`]: style shift, the classifier-free measure on kinematic descriptors.

pub mod classify;
pub mod metrics;
pub mod protocol;
pub mod report;
pub mod shift;

use std::path::{Path, PathBuf};

use anyhow::{Context, ensure};

use crate::Motion;
use crate::dataset::corpus::list_takes;
use crate::dataset::{Split, TakeId, content_class};
use crate::skeleton;
use protocol::Labelled;
use shift::{Take, descriptors};

/// The takes under `data` that `keep` selects (both sets, in [`list_takes`]' order), each imported
/// on one of `threads` threads: its id and its motion, or why it could not be imported.
pub fn import_takes(
    data: &Path,
    threads: usize,
    keep: impl Fn(&TakeId) -> bool,
) -> anyhow::Result<Vec<(TakeId, Result<Motion, String>)>> {
    let takes: Vec<(TakeId, PathBuf)> = list_takes(data)
        .with_context(|| format!("cannot list the takes in {}", data.display()))?
        .into_iter()
        .filter(|(t, _)| keep(t))
        .collect();
    let import = |path: &Path| -> Result<Motion, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        skeleton::import_bvh(&text).map(|i| i.motion).map_err(|e| format!("cannot import {}: {e}", path.display()))
    };
    let chunk = takes.len().div_ceil(threads.max(1)).max(1);
    let parts: Vec<Vec<(TakeId, Result<Motion, String>)>> = std::thread::scope(|scope| {
        let handles: Vec<_> = takes
            .chunks(chunk)
            .map(|part| scope.spawn(move || part.iter().map(|(t, p)| (t.clone(), import(p))).collect::<Vec<_>>()))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or_default()).collect()
    });
    Ok(parts.into_iter().flatten().collect())
}

/// The held-out takes of `split` among `takes`, with their unified style labels; a held-out take
/// that could not be imported is an error.
pub fn heldout_of(takes: &[(TakeId, Result<Motion, String>)], split: &Split) -> anyhow::Result<Vec<Labelled>> {
    let mut out = Vec::new();
    for (take, motion) in takes.iter().filter(|(t, _)| split.is_heldout(t)) {
        let motion = motion.clone().map_err(anyhow::Error::msg)?;
        out.push(Labelled {
            name: take.stem(),
            motion,
            style: Some(take.style().index()),
            content: content_class(&take.content),
        });
    }
    ensure!(!out.is_empty(), "no held-out takes of the split found among the takes");
    Ok(out)
}

/// The held-out takes of `split` under `data`, imported, with their unified style labels.
pub fn load_heldout(data: &Path, split: &Split) -> anyhow::Result<Vec<Labelled>> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    heldout_of(&import_takes(data, threads, |t| split.is_heldout(t))?, split)
        .with_context(|| format!("held-out takes under {}", data.display()))
}

/// Every `.bvh` file in `dir` (sorted by name) as unlabelled contents; files that cannot be
/// imported are returned separately with the reason.
pub fn load_contents(dir: &Path) -> anyhow::Result<(Vec<Labelled>, Vec<(PathBuf, String)>)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("bvh")))
        .collect();
    paths.sort();
    let (mut ok, mut failed) = (Vec::new(), Vec::new());
    for path in paths {
        let result = std::fs::read_to_string(&path)
            .map_err(|e| e.to_string())
            .and_then(|text| skeleton::import_bvh(&text).map_err(|e| e.to_string()));
        match result {
            Ok(imported) => ok.push(Labelled {
                name: path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
                motion: imported.motion,
                style: None,
                content: None,
            }),
            Err(e) => failed.push((path, e)),
        }
    }
    ensure!(!ok.is_empty(), "no importable .bvh file in {}", dir.display());
    Ok((ok, failed))
}

/// The imported takes as [`Take`]s for the style directions: content key, unified style and
/// descriptors. Takes that could not be imported are skipped with a warning (none are expected).
pub fn direction_takes(takes: &[(TakeId, Result<Motion, String>)]) -> Vec<Take> {
    takes
        .iter()
        .filter_map(|(take, motion)| match motion {
            Ok(m) => {
                Some(Take { content: take.content_key(), style: take.style().index(), descriptors: descriptors(m) })
            }
            Err(e) => {
                eprintln!("warning: skipped {e}");
                None
            }
        })
        .collect()
}
