//! A run's data: the takes loaded and split, the normalisation statistics, the normalised training
//! clips with their window sampler, and the held-out sets.

use anyhow::{Context, ensure};
use burn::prelude::*;
use std::time::Instant;

use super::eval::HeldoutSet;
use super::rundir::RunConfig;
use super::sampler::WindowSampler;
use super::settings::TrainOptions;
use crate::dataset::corpus::{self, Clip};
use crate::dataset::folder::{self, FolderListing};
use crate::dataset::{CONTENTS, Split, content_class_as_seen};
use crate::features::{Features, NormStats};
use std::collections::BTreeSet;

/// Everything a trainer draws its batches from and evaluates on.
pub struct TrainData {
    /// Normalised training clips (takes and mirrors) and each one's class, which the sampler
    /// balances: its style label, or for the content classifier its content class
    /// ([`crate::dataset::CONTENTS`]; takes of other contents are left out).
    pub clips: Vec<Features>,
    pub labels: Vec<usize>,
    /// Each clip's content group — the same content of the same data set, mirrored or not —
    /// whose takes in other styles the stylizer's content-paired rows draw from
    /// ([`WindowSampler::content_partner`]); `None` for a clip without a content.
    pub groups: Vec<Option<u32>>,
    /// The same groups with the data sets merged (content and mirroring alone), for runs whose
    /// content pairs cross the sets ([`super::losses::StylizerWeights::cross_set`]).
    pub groups_across_sets: Vec<Option<u32>>,
    /// Each clip's content alone (the same number for a content in either data set, mirrored or
    /// not): the style sources of the cross-content swaps come from another content
    /// ([`WindowSampler::style_clip_elsewhere`]); `None` for a clip without a content.
    pub contents: Vec<Option<u32>>,
    /// Each clip's content class as seen ([`content_class_as_seen`]: a mirror's side-specific
    /// content is the other side's), which the stylizer's content-class loss holds its swaps to;
    /// `None` for a content without a class.
    pub content_class: Vec<Option<usize>>,
    /// Each clip's content group's `normal` statistics (an index into `baselines`; `None` when
    /// the group has no `normal` take of the window's length, or the run has no `normal` label):
    /// the cross-set pairs' targets are moved by their difference
    /// ([`super::losses::StylizerWeights::cross_set_relative`]).
    pub baseline_of: Vec<Option<usize>>,
    pub baselines: Vec<WindowStats>,
    pub sampler: WindowSampler,
    /// The fixed held-out windows and pairs.
    pub heldout: HeldoutSet,
    /// Whole held-out takes, normalised, with their classes: the classifiers' evaluation (empty
    /// for the other stages).
    pub heldout_takes: Vec<(Features, usize)>,
    pub norm: NormStats,
    pub batch: usize,
    pub window: usize,
    pub device: Device,
}

/// Normalised copies of clips.
fn normalized(clips: &[Clip], norm: &NormStats) -> Vec<Features> {
    clips
        .iter()
        .map(|c| {
            let mut f = c.features.clone();
            norm.normalize(&mut f);
            f
        })
        .collect()
}

/// Numbers the clips' content groups: (data set, content, mirrored) for a Bandai-Namco take,
/// (content, mirrored) for a folder's file with a content, and for every clip with
/// `across_sets`; `None` without a content.
fn content_groups(clips: &[Clip], across_sets: bool) -> Vec<Option<u32>> {
    let mut ids: std::collections::HashMap<(u8, &str, bool), u32> = Default::default();
    clips
        .iter()
        .map(|c| {
            let set = if across_sets { 0 } else { c.take.as_ref().map_or(0, |t| t.set) };
            let content = c.content.as_deref()?;
            let next = ids.len() as u32;
            Some(*ids.entry((set, content, c.mirrored)).or_insert(next))
        })
        .collect()
}

/// Per-feature time statistics of windows: each channel's mean over a window and its spread
/// (standard deviation) over the window, as the style-statistics loss takes them, averaged over
/// windows.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowStats {
    pub mean: Vec<f32>,
    pub spread: Vec<f32>,
}

impl WindowStats {
    /// `self − other`, channel by channel: `(mean, spread)`.
    pub fn minus(&self, other: &WindowStats) -> (Vec<f32>, Vec<f32>) {
        let sub = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(x, y)| x - y).collect();
        (sub(&self.mean, &other.mean), sub(&self.spread, &other.spread))
    }
}

/// [`WindowStats`] of every `window`-frame window of `clips` at a stride of half a window (the
/// loss's windows fall anywhere in a take); `None` when no clip is that long.
fn window_stats(clips: &[&Features], window: usize) -> Option<WindowStats> {
    let dim = crate::features::DIM;
    let (mut mean, mut spread, mut n) = (vec![0f64; dim], vec![0f64; dim], 0usize);
    let stride = (window / 2).max(1);
    for clip in clips {
        let mut start = 0;
        while start + window <= clip.frames() {
            for c in 0..dim {
                let values = (start..start + window).map(|t| f64::from(clip.frame(t)[c]));
                let m = values.clone().sum::<f64>() / window as f64;
                let var = values.map(|v| (v - m) * (v - m)).sum::<f64>() / window as f64;
                mean[c] += m;
                // As the loss: sqrt(var + 1e-6).
                spread[c] += (var + 1e-6).sqrt();
            }
            n += 1;
            start += stride;
        }
    }
    (n > 0).then(|| WindowStats {
        mean: mean.iter().map(|v| (v / n as f64) as f32).collect(),
        spread: spread.iter().map(|v| (v / n as f64) as f32).collect(),
    })
}

/// Each content group's `normal` [`WindowStats`] (over the group's clips labelled `normal`),
/// and each clip's group's index into them.
fn normal_baselines(
    clips: &[Features],
    labels: &[usize],
    groups: &[Option<u32>],
    normal: Option<usize>,
    window: usize,
) -> (Vec<Option<usize>>, Vec<WindowStats>) {
    let mut members: std::collections::BTreeMap<u32, Vec<&Features>> = Default::default();
    if let Some(normal) = normal {
        for ((clip, &label), group) in clips.iter().zip(labels).zip(groups) {
            if let (true, Some(g)) = (label == normal, group) {
                members.entry(*g).or_default().push(clip);
            }
        }
    }
    let mut baselines = Vec::new();
    let mut index: std::collections::HashMap<u32, usize> = Default::default();
    for (g, clips) in members {
        if let Some(stats) = window_stats(&clips, window) {
            index.insert(g, baselines.len());
            baselines.push(stats);
        }
    }
    (groups.iter().map(|g| g.and_then(|g| index.get(&g).copied())).collect(), baselines)
}

/// Numbers the clips' contents (by name alone); `None` without a content.
fn content_ids(clips: &[Clip]) -> Vec<Option<u32>> {
    let mut ids: std::collections::HashMap<&str, u32> = Default::default();
    clips
        .iter()
        .map(|c| {
            let next = ids.len() as u32;
            Some(*ids.entry(c.content.as_deref()?).or_insert(next))
        })
        .collect()
}

impl TrainData {
    /// Loads the takes of `opts.data` (the Bandai-Namco layout, split by the run's split file, or a
    /// folder of the user's files with the run's held-out files); `norm` is the run's
    /// statistics (`None`: computed from the training clips). Fills in `config`'s counts and says
    /// what was loaded through `say`.
    pub fn load(
        opts: &TrainOptions,
        config: &mut RunConfig,
        norm: Option<NormStats>,
        device: &Device,
        say: &dyn Fn(String),
    ) -> anyhow::Result<TrainData> {
        let t_load = Instant::now();
        let mut last_report = Instant::now();
        let loading = |done: usize, total: usize| {
            if done == total || last_report.elapsed().as_secs_f64() > 5.0 {
                say(format!("loading takes: {done}/{total}"));
                last_report = Instant::now();
            }
        };
        let corpus = match &config.folder {
            None => {
                let split_text = std::fs::read_to_string(&config.split)
                    .with_context(|| format!("cannot read the split file {} (--split)", config.split))?;
                let split = Split::parse(&split_text).with_context(|| format!("split file {}", config.split))?;
                corpus::load(&opts.data, &split, opts.loader_threads(), loading)
                    .with_context(|| format!("cannot load the data in {}", opts.data.display()))?
            }
            Some(run_folder) => {
                let read = FolderListing::read(&opts.data)?;
                let listing = read.relabelled(&run_folder.labels).with_context(|| {
                    format!(
                        "{}: labels.csv has labels ({}) the run does not know ({}): a run keeps its label set",
                        opts.data.display(),
                        read.labels.names.join(", "),
                        run_folder.labels.join(", ")
                    )
                })?;
                let heldout: BTreeSet<String> = run_folder.heldout.iter().cloned().collect();
                folder::load(&opts.data, &listing, &heldout, opts.loader_threads(), loading)?.0
            }
        };
        for (path, why) in &corpus.failed {
            eprintln!("warning: skipped {}: {why}", path.display());
        }
        let norm = match norm {
            Some(n) => n,
            None => corpus.norm_stats().context("normalisation statistics")?,
        };
        let window = config.settings.window;
        // The class each clip is balanced and judged by; unlabelled clips (a folder's) are one
        // more class after the labels, and only in the stages that train without labels.
        let contents = config.stage == "content-classifier";
        let needs_labels =
            config.stage == "classifier" || (config.stage == "stylizer" && config.supervised == Some(true));
        let unlabelled = corpus.labels.len();
        let class = |c: &Clip| {
            if contents {
                // A mirror's side-specific content is the other side's (a mirrored left turn turns right).
                c.content.as_deref().and_then(|name| content_class_as_seen(name, c.mirrored))
            } else {
                match c.style {
                    Some(s) => Some(s.index()),
                    None if needs_labels => None,
                    None => Some(unlabelled),
                }
            }
        };
        let keep = |v: &[Clip]| v.iter().filter(|c| class(c).is_some()).cloned().collect::<Vec<_>>();
        let train = keep(&corpus.train);
        ensure!(
            !train.is_empty(),
            "{}: no training clip for the {} stage (it trains on labelled files: labels.csv)",
            opts.data.display(),
            config.stage
        );
        let mut heldout_clips = keep(&corpus.heldout);
        if heldout_clips.is_empty() && config.folder.is_some() {
            say("no held-out files (a label needs 5 files before one is held out): evaluating on the training files"
                .to_string());
            heldout_clips = train.iter().filter(|c| !c.mirrored).cloned().collect();
        }
        let clips = normalized(&train, &norm);
        let labels: Vec<usize> = train.iter().filter_map(class).collect();
        let groups = content_groups(&train, false);
        let groups_across_sets = content_groups(&train, true);
        let content_of = content_ids(&train);
        let content_class =
            train.iter().map(|c| c.content.as_deref().and_then(|n| content_class_as_seen(n, c.mirrored))).collect();
        // Only for a run that judges cross-set pairs relative to `normal`; a supervised
        // stylizer's labels are styles (`normal` among them).
        let relative = config.train.stylizer_weights.is_some_and(|w| w.cross_set_relative);
        let normal = (relative && needs_labels && !contents && config.stage == "stylizer")
            .then(|| corpus.labels.iter().position(|l| l == "normal"))
            .flatten();
        let (baseline_of, baselines) = normal_baselines(&clips, &labels, &groups, normal, window);
        if normal.is_some() {
            let with = baseline_of.iter().filter(|b| b.is_some()).count();
            say(format!(
                "normal baselines: {} content groups, covering {with} of {} clips",
                baselines.len(),
                clips.len()
            ));
        }
        let frames: Vec<usize> = clips.iter().map(Features::frames).collect();
        let sampler = WindowSampler::new(&frames, &labels, window);
        ensure!(sampler.eligible() > 0, "no training take has {window} frames or more (--window {window})");
        let heldout = HeldoutSet::new(&heldout_clips, &norm, window, opts.eval_windows);
        let heldout_takes = if config.stage.ends_with("classifier") {
            normalized(&heldout_clips, &norm).into_iter().zip(heldout_clips.iter().filter_map(class)).collect()
        } else {
            Vec::new()
        };
        config.train_clips = sampler.eligible();
        config.train_clips_skipped = sampler.skipped();
        config.eval_windows = heldout.len();
        config.heldout_skipped = heldout.skipped;

        let frames_of = |v: &[Clip]| v.iter().map(|c| c.features.frames()).sum::<usize>();
        let (train_frames, heldout_frames) = (frames_of(&train), frames_of(&heldout_clips));
        say(format!(
            "data: {} training clips (takes + mirrors, {train_frames} frames), {} held-out takes ({heldout_frames} \
             frames), loaded in {:.1} s",
            train.len(),
            heldout_clips.len(),
            t_load.elapsed().as_secs_f64()
        ));
        say(format!(
            "window {window} frames: {} training clips used, {} skipped as shorter ({} distinct windows); {} held-out \
             windows, {} held-out takes skipped",
            sampler.eligible(),
            sampler.skipped(),
            sampler.windows(),
            heldout.len(),
            heldout.skipped
        ));
        if contents {
            let names: Vec<String> = sampler.styles().iter().map(|(s, n)| format!("{} {n}", CONTENTS[*s])).collect();
            say(format!("content classes (clips): {}", names.join(", ")));
        } else if config.stage != "ae" {
            let name = |s: usize| corpus.labels.get(s).map_or("unlabelled", String::as_str);
            let names: Vec<String> = sampler.styles().iter().map(|(s, n)| format!("{} {n}", name(*s))).collect();
            say(format!("styles (clips): {}", names.join(", ")));
        }
        Ok(TrainData {
            clips,
            labels,
            groups,
            groups_across_sets,
            contents: content_of,
            content_class,
            baseline_of,
            baselines,
            sampler,
            heldout,
            heldout_takes,
            norm,
            batch: config.settings.batch,
            window,
            device: device.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::TakeId;

    fn clip(stem: &str, mirrored: bool) -> Clip {
        let take = TakeId::parse(stem).expect("a Bandai take name");
        Clip {
            content: Some(take.content.clone()),
            take: Some(take),
            name: stem.to_string(),
            style: None,
            mirrored,
            features: Features::new(1, vec![0.0; crate::features::DIM]).expect("one frame"),
        }
    }

    /// `frames` frames, every channel `f(t)`.
    fn features(frames: usize, f: impl Fn(usize) -> f32) -> Features {
        let dim = crate::features::DIM;
        Features::new(frames, (0..frames).flat_map(|t| std::iter::repeat_n(f(t), dim)).collect()).expect("frames")
    }

    #[test]
    fn normal_baselines_average_the_normal_windows_of_each_content_group() {
        // `normal` is label 1. Group 0: a normal take at 1, a normal take alternating 0/2, and a
        // take in another style; group 1: a normal take at 3; group 2: a normal take shorter
        // than a window.
        let clips = [
            features(8, |_| 1.0),
            features(8, |t| if t % 2 == 0 { 0.0 } else { 2.0 }),
            features(8, |_| 9.0),
            features(8, |_| 3.0),
            features(3, |_| 5.0),
        ];
        let labels = [1, 1, 0, 1, 1];
        let groups = [Some(0), Some(0), Some(0), Some(1), Some(2)];
        let (of, baselines) = normal_baselines(&clips, &labels, &groups, Some(1), 4);
        assert_eq!(baselines.len(), 2, "group 0 and group 1 (group 2 has no 4-frame window)");
        assert_eq!(of, vec![Some(0), Some(0), Some(0), Some(1), None]);
        // Group 0: the windows of both normal takes (3 each at stride 2; the other style's take at
        // 9 left out): means 1 and 1, spreads ~0 and 1, on average 0.5 (the loss's 1e-6 under
        // the root adds 0.0005).
        let b = &baselines[0];
        assert!(
            (b.mean[0] - 1.0).abs() < 1e-6 && (b.spread[7] - 0.5005).abs() < 1e-3,
            "{:?}",
            (b.mean[0], b.spread[7])
        );
        let (mean, spread) = baselines[1].minus(b);
        assert!((mean[3] - 2.0).abs() < 1e-6 && (spread[3] + 0.5).abs() < 1e-3);
        // Without a `normal` label, no baseline.
        let (of, baselines) = normal_baselines(&clips, &labels, &groups, None, 4);
        assert!(baselines.is_empty() && of.iter().all(Option::is_none));
    }

    #[test]
    fn content_groups_keep_the_data_sets_apart_unless_asked_to_merge_them() {
        let clips = [
            clip("dataset-1_walk_happy_001", false),
            clip("dataset-2_walk_normal_001", false),
            clip("dataset-2_walk_elderly_002", false),
            clip("dataset-1_walk_happy_001", true),
            clip("dataset-2_walk_normal_001", true),
            clip("dataset-1_run_angry_001", false),
        ];
        let by_set = content_groups(&clips, false);
        // Set 1's walk, set 2's walk (two takes), each mirrored apart, and set 1's run.
        assert_eq!(by_set[1], by_set[2]);
        assert_ne!(by_set[0], by_set[1]);
        assert_ne!(by_set[0], by_set[3], "a mirror is its own group");
        let distinct: BTreeSet<_> = by_set.iter().collect();
        assert_eq!(distinct.len(), 5);

        let across = content_groups(&clips, true);
        // One content, one group, whichever set: the walks meet; mirrors and the run stay apart.
        assert!(across[0] == across[1] && across[1] == across[2], "{across:?}");
        assert_eq!(across[3], across[4]);
        assert_ne!(across[0], across[3]);
        assert_ne!(across[5], across[0]);
        let distinct: BTreeSet<_> = across.iter().collect();
        assert_eq!(distinct.len(), 3);
    }
}
