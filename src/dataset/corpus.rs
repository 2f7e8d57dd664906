//! Loads the Bandai-Namco takes from disk as 260-D features, split into training and held-out clips.
//!
//! Every take goes through the same path as a user's file (parse → retarget → 30 fps → features), so
//! training sees exactly what inference will. Training clips get a mirrored copy (left/right
//! augmentation); held-out clips do not. Native only (reads the file system).

use super::labels::Style;
use super::split::{Split, TakeId};
use crate::features::{self, Features, NormStats};
use crate::skeleton;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// One take (or its mirror image) as features.
#[derive(Clone, Debug)]
pub struct Clip {
    pub take: TakeId,
    pub style: Style,
    pub mirrored: bool,
    /// Raw (un-normalised) features.
    pub features: Features,
}

/// The loaded data set.
#[derive(Debug, Default)]
pub struct Corpus {
    /// Training takes and their mirror images.
    pub train: Vec<Clip>,
    /// Held-out takes (no mirrors).
    pub heldout: Vec<Clip>,
    /// Takes that could not be imported, with the reason (none are expected; reported, not fatal).
    pub failed: Vec<(PathBuf, String)>,
}

#[derive(Debug, Error)]
pub enum CorpusError {
    #[error("cannot list {dir}: {source} (unpack both archives into the data folder: DIR/dataset-1, DIR/dataset-2)")]
    List { dir: PathBuf, source: std::io::Error },
    #[error("{path}: not a Bandai-Namco take name")]
    BadName { path: PathBuf },
    #[error("no training takes found under {0}")]
    Empty(PathBuf),
}

/// Every take in `DIR/dataset-{1,2}/data/*.bvh`, sorted by name.
pub fn list_takes(data: &Path) -> Result<Vec<(TakeId, PathBuf)>, CorpusError> {
    let mut takes = Vec::new();
    for set in ["dataset-1", "dataset-2"] {
        let dir = data.join(set).join("data");
        let entries = std::fs::read_dir(&dir).map_err(|source| CorpusError::List { dir: dir.clone(), source })?;
        for entry in entries {
            let entry = entry.map_err(|source| CorpusError::List { dir: dir.clone(), source })?;
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            if let Some(stem) = name.strip_suffix(".bvh") {
                let id = TakeId::parse(stem).ok_or_else(|| CorpusError::BadName { path: path.clone() })?;
                takes.push((id, path));
            }
        }
    }
    takes.sort();
    Ok(takes)
}

/// Loads every take under `data`, split by `split`, on `threads` threads. `progress(done, total)` is
/// called as takes finish (from the calling thread).
pub fn load(
    data: &Path,
    split: &Split,
    threads: usize,
    mut progress: impl FnMut(usize, usize),
) -> Result<Corpus, CorpusError> {
    let takes = list_takes(data)?;
    let total = takes.len();
    let threads = threads.clamp(1, 64);
    let (tx, rx) = std::sync::mpsc::channel();
    let mut results: Vec<Option<Result<Features, String>>> = vec![None; total];
    std::thread::scope(|scope| {
        for worker in 0..threads {
            let tx = tx.clone();
            let takes = &takes;
            scope.spawn(move || {
                for i in (worker..takes.len()).step_by(threads) {
                    let r = load_one(&takes[i].1);
                    if tx.send((i, r)).is_err() {
                        return;
                    }
                }
            });
        }
        drop(tx);
        for (done, (i, r)) in rx.iter().enumerate() {
            results[i] = Some(r);
            progress(done + 1, total);
        }
    });
    let mut corpus = Corpus::default();
    for ((take, path), r) in takes.into_iter().zip(results) {
        let style = take.style();
        match r {
            Some(Ok(f)) if split.is_heldout(&take) => {
                corpus.heldout.push(Clip { take, style, mirrored: false, features: f });
            }
            Some(Ok(f)) => {
                let m = features::mirror(&f);
                corpus.train.push(Clip { take: take.clone(), style, mirrored: false, features: f });
                corpus.train.push(Clip { take, style, mirrored: true, features: m });
            }
            Some(Err(e)) => corpus.failed.push((path, e)),
            None => corpus.failed.push((path, "not loaded".into())),
        }
    }
    if corpus.train.is_empty() {
        return Err(CorpusError::Empty(data.to_path_buf()));
    }
    Ok(corpus)
}

fn load_one(path: &Path) -> Result<Features, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let imported = skeleton::import_bvh(&text).map_err(|e| e.to_string())?;
    Ok(features::extract(&imported.motion))
}

impl Corpus {
    /// Normalisation statistics of the training clips (mirrors included).
    pub fn norm_stats(&self) -> Result<NormStats, features::FeatureError> {
        NormStats::compute(self.train.iter().map(|c| &c.features))
    }
}
