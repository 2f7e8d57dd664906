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

use crate::dataset::Split;
use crate::dataset::corpus::list_takes;
use crate::skeleton;
use protocol::Labelled;
use shift::{Take, descriptors};

/// The held-out takes of `split` under `data`, imported, with their unified style labels.
pub fn load_heldout(data: &Path, split: &Split) -> anyhow::Result<Vec<Labelled>> {
    let takes = list_takes(data).with_context(|| format!("cannot list the takes in {}", data.display()))?;
    let mut out = Vec::new();
    for (take, path) in takes.into_iter().filter(|(t, _)| split.is_heldout(t)) {
        let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
        let imported = skeleton::import_bvh(&text).with_context(|| format!("cannot import {}", path.display()))?;
        out.push(Labelled { name: take.stem(), motion: imported.motion, style: Some(take.style().index()) });
    }
    ensure!(!out.is_empty(), "no held-out takes of the split found under {}", data.display());
    Ok(out)
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
            }),
            Err(e) => failed.push((path, e)),
        }
    }
    ensure!(!ok.is_empty(), "no importable .bvh file in {}", dir.display());
    Ok((ok, failed))
}

/// Every take under `data` (both sets, training and held-out) as a [`Take`] for the style
/// directions: its content key, unified style and descriptors. Takes that cannot be imported are
/// skipped with a warning (none are expected). Imported on `threads` threads.
pub fn load_takes(data: &Path, threads: usize) -> anyhow::Result<Vec<Take>> {
    let takes = list_takes(data).with_context(|| format!("cannot list the takes in {}", data.display()))?;
    let chunk = takes.len().div_ceil(threads.max(1)).max(1);
    let parts: Vec<Vec<Take>> = std::thread::scope(|scope| {
        let handles: Vec<_> = takes
            .chunks(chunk)
            .map(|part| {
                scope.spawn(move || {
                    let mut out = Vec::with_capacity(part.len());
                    for (take, path) in part {
                        let imported = std::fs::read_to_string(path)
                            .map_err(|e| e.to_string())
                            .and_then(|text| skeleton::import_bvh(&text).map_err(|e| e.to_string()));
                        match imported {
                            Ok(i) => out.push(Take {
                                content: take.content_key(),
                                style: take.style().index(),
                                descriptors: descriptors(&i.motion),
                            }),
                            Err(e) => eprintln!("warning: skipped {}: {e}", path.display()),
                        }
                    }
                    out
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or_default()).collect()
    });
    let out: Vec<Take> = parts.into_iter().flatten().collect();
    ensure!(!out.is_empty(), "no takes found under {}", data.display());
    Ok(out)
}
