//! Loads the Bandai-Namco takes from disk as 260-D features, split into training and held-out clips.
//!
//! Every take goes through the same path as a user's file (parse → retarget → 30 fps → features), so
//! training sees exactly what inference will. Training clips get a mirrored copy (left/right
//! augmentation); held-out clips do not. Native only (reads the file system).

use super::labels::{STYLES, Style};
use super::split::{Split, TakeId};
use crate::features::{self, Features, NormStats};
use crate::skeleton;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// One take (or its mirror image) as features.
#[derive(Clone, Debug)]
pub struct Clip {
    /// The Bandai-Namco take (`None` for a file of a user's folder, [`super::folder`]).
    pub take: Option<TakeId>,
    /// The take's stem, or the file's path relative to the data folder.
    pub name: String,
    /// The content (Bandai: the take's; a folder: `labels.csv`'s `content` column, if any).
    pub content: Option<String>,
    /// The style label, an index into [`Corpus::labels`] (`None`: an unlabelled file).
    pub style: Option<Style>,
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
    /// The label set the clips' styles index, in one-hot order ([`super::STYLES`] for the
    /// Bandai-Namco data).
    pub labels: Vec<String>,
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
    progress: impl FnMut(usize, usize),
) -> Result<Corpus, CorpusError> {
    let takes = list_takes(data)?;
    let paths: Vec<PathBuf> = takes.iter().map(|t| t.1.clone()).collect();
    let results = par_map(&paths, threads, |p| load_one(p), progress);
    let mut corpus = Corpus { labels: STYLES.iter().map(|s| s.to_string()).collect(), ..Corpus::default() };
    for ((take, path), r) in takes.into_iter().zip(results) {
        let clip = |take: &TakeId, mirrored: bool, features: Features| Clip {
            take: Some(take.clone()),
            name: take.stem(),
            content: Some(take.content.clone()),
            style: Some(take.style()),
            mirrored,
            features,
        };
        match r {
            Ok(f) if split.is_heldout(&take) => corpus.heldout.push(clip(&take, false, f)),
            Ok(f) => {
                let m = features::mirror(&f);
                corpus.train.push(clip(&take, false, f));
                corpus.train.push(clip(&take, true, m));
            }
            Err(e) => corpus.failed.push((path, e)),
        }
    }
    if corpus.train.is_empty() {
        return Err(CorpusError::Empty(data.to_path_buf()));
    }
    Ok(corpus)
}

/// `f` over `items` on `threads` threads (1-64); `progress(done, total)` from the calling thread as
/// items finish. Results in `items` order.
pub fn par_map<T: Sync, R: Send>(
    items: &[T],
    threads: usize,
    f: impl Fn(&T) -> Result<R, String> + Sync,
    mut progress: impl FnMut(usize, usize),
) -> Vec<Result<R, String>> {
    let total = items.len();
    let threads = threads.clamp(1, 64);
    let (tx, rx) = std::sync::mpsc::channel();
    let mut results: Vec<Option<Result<R, String>>> = (0..total).map(|_| None).collect();
    std::thread::scope(|scope| {
        for worker in 0..threads {
            let tx = tx.clone();
            let f = &f;
            scope.spawn(move || {
                for i in (worker..items.len()).step_by(threads) {
                    if tx.send((i, f(&items[i]))).is_err() {
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
    results.into_iter().map(|r| r.unwrap_or_else(|| Err("not loaded".into()))).collect()
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
