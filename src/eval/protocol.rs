//! The evaluation protocol: which contents, styles and references, and the rows of the table.
//!
//! Per repeat `r` (its own generator, from the seed and `r`), every content gets a **target
//! style** `X`, uniform over the styles that have held-out takes, other than the content's own
//! (a content from `--content DIR` has no label: any style), and a **reference**: a held-out take
//! of style `X`, uniform (never the content's own take, since its style differs). Rows:
//!
//! - `real`: the held-out takes themselves, judged against their own labels; FID against another
//!   held-out take of the same style each (the take itself if it is its style's only one).
//! - `identity`: the output is the content, unchanged; judged against the target `X`.
//! - `sup_motion`: supervised, motion-based with the reference (and its label `X`).
//! - `sup_label`: supervised, label-based with `X`.
//! - `unsup_motion`: unsupervised, motion-based with the reference.
//! - `unsup_prior`: unsupervised, style drawn from the prior (no target: no style accuracy).
//!
//! Metrics of a row, per repeat: `style_acc` (classifier's prediction = `X`), `style_fid`
//! (classifier features of the outputs against those of the references), `geodesic` (to the
//! content), `diversity` (distance between two samples of the same input, in the classifier's
//! feature space; `diversity_cm`: mean joint distance, cm), `foot_skate` (cm/s; `foot_skate_ref`:
//! the same for the row's real references, i.e. real motions of the target styles), `style_shift`
//! (classifier-free: how far the output moved from its content along the target style's
//! direction on kinematic descriptors, [`super::shift`]; only where the target style is scored;
//! the identity row's is 0 by definition). Motion-based
//! outputs are the posterior mean (what the CLI gives by default); their diversity is measured on
//! two extra draws from the posterior. Label- and prior-based outputs are the first of two
//! samples; diversity is between the two. Each value is the mean over repeats with its 95 %
//! confidence half-width. Per target label ([`LabelRow`]), pooled over repeats: style accuracy and
//! style shift of every row that has a target.

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};
use serde::Serialize;

use super::classify::{Judge, Judgement};
use super::metrics::{feature_distance, fid, foot_skate_parts, geodesic, mean_ci, position_distance};
use super::shift::{Directions, LOWER_BODY, UPPER_BODY, descriptors};
use crate::Motion;
use crate::dataset::Style;
use crate::stylize::{self, PartRequests, Request, Setting, StyleSource, StylizeError, Weights};
use std::collections::BTreeMap;

/// One motion of the evaluation with its style label, if known.
#[derive(Clone, Debug)]
pub struct Labelled {
    pub name: String,
    pub motion: Motion,
    pub style: Option<usize>,
    /// Its content class ([`crate::dataset::CONTENTS`]), if known.
    pub content: Option<usize>,
}

/// The settings (rows) in table order.
pub const ROWS: [&str; 6] = ["real", "identity", "sup_motion", "sup_label", "unsup_motion", "unsup_prior"];

/// The metrics (columns) in table order.
pub const COLUMNS: [&str; 10] = [
    "style_acc",
    "style_fid",
    "geodesic",
    "diversity",
    "diversity_cm",
    "foot_skate",
    "foot_skate_ref",
    "style_shift",
    "content_acc",
    "content_fid",
];

/// Inputs of an evaluation.
pub struct Inputs<'a> {
    pub weights: &'a Weights,
    pub judge: &'a Judge,
    /// Held-out takes: style references, and the `real` row.
    pub heldout: &'a [Labelled],
    /// The contents to stylize (held-out takes, or any motions).
    pub contents: &'a [Labelled],
    pub repeats: usize,
    pub seed: u64,
    /// The styles' directions for `style_shift` (`None`: not measured).
    pub directions: Option<&'a Directions>,
    /// The content classifier (`None`: no `content_acc`, `content_fid`).
    pub content_judge: Option<&'a Judge>,
    /// The stylizations' [`Request::strength`] and [`Request::temperature`].
    pub strength: f32,
    /// The stylizations' [`Request::guidance`].
    pub guidance: f32,
    pub temperature: f32,
    /// Also measure per-part styles ([`PartShift`]): label-based with the target on the upper
    /// body only and on the lower body only, beside the whole body.
    pub parts: bool,
}

/// Style shift per body part (label-based, supervised): how far the outputs of one variant moved
/// towards the target on the lower body's descriptors ([`super::shift::LOWER_BODY`]) and on the
/// upper body's ([`super::shift::UPPER_BODY`]), pooled over repeats and contents.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PartShift {
    /// `"whole"` (the style on every part), `"upper_only"`, `"lower_only"` (the style on that part,
    /// the content's own motion on the others).
    pub variant: &'static str,
    pub outputs: usize,
    pub lower: Option<f64>,
    pub upper: Option<f64>,
}

/// The variants of [`PartShift`], in order.
pub const PART_VARIANTS: [&str; 3] = ["whole", "upper_only", "lower_only"];

/// One row of the result: per metric, the mean over repeats and the 95 % half-width (`None`:
/// does not apply to the row, or fewer than two repeats for the half-width).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Row {
    pub setting: &'static str,
    pub values: Vec<(&'static str, Option<f64>, Option<f64>)>,
}

/// One row's results for one target label, pooled over repeats and contents; for `real`, the
/// held-out takes of that style (what the outputs with that target are held to).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LabelRow {
    pub setting: &'static str,
    pub style: usize,
    /// Outputs with this target (`real`: takes of this style, once per repeat).
    pub outputs: usize,
    pub style_acc: Option<f64>,
    /// Mean shift of the outputs (`None`: the style is not scored).
    pub style_shift: Option<f64>,
    /// The content classifier's accuracy on these outputs (`None`: no content classifier, or no
    /// content with a content label): which targets keep the content and which lose it.
    pub content_acc: Option<f64>,
    /// The content classifier's mistakes on these outputs: which class a content was taken for,
    /// and how many times, most frequent first.
    pub content_mistakes: Vec<ContentMistake>,
}

/// Outputs of content `content` that the content classifier took for `taken_for`
/// ([`crate::dataset::CONTENTS`]' names).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ContentMistake {
    pub content: &'static str,
    pub taken_for: &'static str,
    pub count: usize,
}

/// What [`evaluate`] gives: the table's rows and the per-label breakdown.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Evaluation {
    pub rows: Vec<Row>,
    pub labels: Vec<LabelRow>,
    /// Per-part shifts ([`Inputs::parts`]; empty without).
    pub parts: Vec<PartShift>,
}

/// A classifier's hits: motions judged against a known class, and how many it got right.
#[derive(Default, Clone, Copy)]
struct Hits {
    correct: usize,
    judged: usize,
}

impl Hits {
    /// Counts judgement `j` of a motion of class `truth` (`None`: no class, not counted).
    fn count(&mut self, j: &Judgement, truth: Option<usize>) {
        if let Some(t) = truth {
            self.judged += 1;
            self.correct += usize::from(j.predicted == t);
        }
    }

    fn accuracy(&self) -> Option<f64> {
        (self.judged > 0).then(|| self.correct as f64 / self.judged as f64)
    }
}

/// Per target label: what the outputs with that target measured, pooled over repeats and contents.
#[derive(Default, Clone)]
struct LabelTally {
    style: Hits,
    shifts: Vec<f64>,
    content: Hits,
    /// (content, predicted) → outputs, for the wrong predictions.
    mistakes: std::collections::BTreeMap<(usize, usize), usize>,
}

impl LabelTally {
    /// The content classifier's judgement `j` of a motion of content `truth`.
    fn count_content(&mut self, j: &Judgement, truth: Option<usize>) {
        self.content.count(j, truth);
        if let Some(t) = truth.filter(|&t| t != j.predicted) {
            *self.mistakes.entry((t, j.predicted)).or_default() += 1;
        }
    }

    fn mistakes(&self) -> Vec<ContentMistake> {
        let name = |i: usize| crate::dataset::CONTENTS.get(i).copied().unwrap_or("?");
        let mut v: Vec<ContentMistake> = self
            .mistakes
            .iter()
            .map(|(&(c, p), &count)| ContentMistake { content: name(c), taken_for: name(p), count })
            .collect();
        v.sort_by(|a, b| b.count.cmp(&a.count));
        v
    }
}

impl Row {
    pub fn get(&self, metric: &str) -> Option<f64> {
        self.values.iter().find(|v| v.0 == metric).and_then(|v| v.1)
    }
}

/// What one repeat measured for one row, summed over contents.
#[derive(Default, Clone)]
struct Tally {
    style: Hits,
    features: Vec<Vec<f32>>,
    references: Vec<Vec<f32>>,
    geodesic: Vec<f64>,
    diversity: Vec<f64>,
    diversity_cm: Vec<f64>,
    /// Foot skating of the outputs, pooled: sum of speeds and count (`foot_skate_parts`).
    skate: (f64, usize),
    /// The same for the real motions the outputs are compared with (references of the target style).
    reference_skate: (f64, usize),
    shift: Vec<f64>,
    /// Content classifier: outputs whose content class it predicts, of those with a class.
    content: Hits,
    /// Content classifier features of the outputs and of their contents.
    content_features: Vec<Vec<f32>>,
    content_references: Vec<Vec<f32>>,
}

fn pool(into: &mut (f64, usize), (sum, count): (f64, usize)) {
    into.0 += sum;
    into.1 += count;
}

fn pooled_mean((sum, count): (f64, usize)) -> Option<f64> {
    (count > 0).then(|| sum / count as f64)
}

impl Tally {
    fn judge(&mut self, j: Judgement, target: Option<usize>, reference: &[f32]) {
        self.style.count(&j, target);
        self.features.push(j.feature);
        self.references.push(reference.to_vec());
    }

    /// The content classifier's judgement of an output whose content is `content` (`of_content`:
    /// its judgement of the content itself).
    fn judge_content(&mut self, j: Judgement, content: Option<usize>, of_content: &[f32]) {
        self.content.count(&j, content);
        self.content_features.push(j.feature);
        self.content_references.push(of_content.to_vec());
    }

    fn per_repeat(&self) -> [Option<f64>; COLUMNS.len()] {
        let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
        [
            self.style.accuracy(),
            fid(&self.features, &self.references),
            mean(&self.geodesic),
            mean(&self.diversity),
            mean(&self.diversity_cm),
            pooled_mean(self.skate),
            pooled_mean(self.reference_skate),
            mean(&self.shift),
            self.content.accuracy(),
            fid(&self.content_features, &self.content_references),
        ]
    }
}

/// Progress callback: (done, total) content evaluations.
pub type Progress<'a> = dyn FnMut(usize, usize) + 'a;

fn below(rng: &mut ChaCha8Rng, n: usize) -> usize {
    (rng.next_u64() % n as u64) as usize
}

/// Runs the evaluation (see the module docs).
pub fn evaluate(inputs: &Inputs<'_>, progress: &mut Progress<'_>) -> Result<Evaluation, StylizeError> {
    let judged_heldout: Vec<Judgement> = inputs.heldout.iter().map(|h| inputs.judge.judge(&h.motion)).collect();
    let heldout_skate: Vec<(f64, usize)> = inputs.heldout.iter().map(|h| foot_skate_parts(&h.motion)).collect();
    let n_styles = inputs.judge.num_styles();
    let mut by_style: Vec<Vec<usize>> = vec![Vec::new(); n_styles];
    for (i, h) in inputs.heldout.iter().enumerate() {
        if let Some(s) = h.style.filter(|s| *s < n_styles) {
            by_style[s].push(i);
        }
    }
    let styles: Vec<usize> = (0..n_styles).filter(|s| !by_style[*s].is_empty()).collect();
    let total = inputs.repeats * inputs.contents.len();
    let mut per_row: Vec<Vec<[Option<f64>; COLUMNS.len()]>> = vec![Vec::new(); ROWS.len()];
    let mut done = 0;
    let mut labels: Vec<BTreeMap<usize, LabelTally>> = vec![BTreeMap::new(); ROWS.len()];
    // Per part variant: (shifts on the lower body's descriptors, on the upper body's).
    let mut part_shifts: Vec<(Vec<f64>, Vec<f64>)> = vec![(Vec::new(), Vec::new()); PART_VARIANTS.len()];
    let content_descriptors: Vec<_> =
        inputs.contents.iter().map(|c| inputs.directions.map(|_| descriptors(&c.motion))).collect();
    // The content classifier's view of every content and held-out take, judged once.
    let content_of = |motions: &mut dyn Iterator<Item = &Motion>| -> Vec<Option<Judgement>> {
        motions.map(|m| inputs.content_judge.map(|j| j.judge(m))).collect()
    };
    let contents_judged = content_of(&mut inputs.contents.iter().map(|c| &c.motion));
    let heldout_content = content_of(&mut inputs.heldout.iter().map(|h| &h.motion));
    for r in 0..inputs.repeats {
        let mut rng = ChaCha8Rng::seed_from_u64(inputs.seed ^ (r as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let mut tallies: Vec<Tally> = vec![Tally::default(); ROWS.len()];

        // `real`: every held-out take against its own label.
        for (i, h) in inputs.heldout.iter().enumerate() {
            let Some(style) = h.style.filter(|s| *s < n_styles) else { continue };
            let same = &by_style[style];
            let others: Vec<usize> = same.iter().copied().filter(|&k| k != i).collect();
            let pick = if others.is_empty() { i } else { others[below(&mut rng, others.len())] };
            tallies[0].judge(judged_heldout[i].clone(), Some(style), &judged_heldout[pick].feature);
            // Per style, the real takes' accuracies: what the outputs of that target are held to.
            let entry = labels[0].entry(style).or_default();
            entry.style.count(&judged_heldout[i], Some(style));
            // Content accuracy of the real takes (no content FID: they are the contents).
            if let Some(j) = &heldout_content[i] {
                entry.count_content(j, h.content);
                tallies[0].content.count(j, h.content);
            }
            pool(&mut tallies[0].skate, heldout_skate[i]);
            pool(&mut tallies[0].reference_skate, heldout_skate[pick]);
        }

        for ((content, content_d), content_j) in inputs.contents.iter().zip(&content_descriptors).zip(&contents_judged)
        {
            let candidates: Vec<usize> = styles.iter().copied().filter(|s| Some(*s) != content.style).collect();
            if candidates.is_empty() {
                continue;
            }
            let target = candidates[below(&mut rng, candidates.len())];
            let ref_index = by_style[target][below(&mut rng, by_style[target].len())];
            let reference = &inputs.heldout[ref_index];
            let ref_feature = judged_heldout[ref_index].feature.clone();
            let seed = rng.next_u64();
            let label = Style(target as u8);
            let reference_skate = heldout_skate[ref_index];

            let shift_of = |output: &Motion| -> Option<f64> {
                let (dirs, content_d) = (inputs.directions?, content_d.as_ref()?);
                dirs.shift(target, content_d, &descriptors(output))
            };
            // identity
            let judged = inputs.judge.judge(&content.motion);
            let entry = labels[1].entry(target).or_default();
            entry.style.count(&judged, Some(target));
            if let Some(s) = shift_of(&content.motion) {
                tallies[1].shift.push(s);
                entry.shifts.push(s);
            }
            tallies[1].judge(judged, Some(target), &ref_feature);
            if let Some(j) = content_j {
                entry.count_content(j, content.content);
                tallies[1].judge_content(j.clone(), content.content, &j.feature);
            }
            tallies[1].geodesic.push(0.0);
            pool(&mut tallies[1].skate, foot_skate_parts(&content.motion));
            pool(&mut tallies[1].reference_skate, reference_skate);

            let sources: [(usize, Setting, StyleSource<'_>, bool); 4] = [
                (2, Setting::Supervised, StyleSource::labelled_motion(&reference.motion, label), true),
                (3, Setting::Supervised, StyleSource::Label(label), false),
                (4, Setting::Unsupervised, StyleSource::motion(&reference.motion), true),
                (5, Setting::Unsupervised, StyleSource::Prior, false),
            ];
            for (row, setting, source, motion_based) in sources {
                if !inputs.weights.has(setting) {
                    continue;
                }
                let request = Request::new(source)
                    .with_setting(setting)
                    .with_seed(seed)
                    .with_strength(inputs.strength)
                    .with_guidance(inputs.guidance)
                    .with_temperature(inputs.temperature);
                if row == 3
                    && inputs.parts
                    && let (Some(dirs), Some(content_d)) = (inputs.directions, content_d.as_ref())
                {
                    let whole = stylize::stylize(inputs.weights, &content.motion, &request)?;
                    let upper = PartRequests { upper: Some(request.clone()), ..Default::default() };
                    let lower = PartRequests { lower: Some(request.clone()), ..Default::default() };
                    let variants = [
                        whole,
                        stylize::stylize_parts(inputs.weights, &content.motion, &upper)?,
                        stylize::stylize_parts(inputs.weights, &content.motion, &lower)?,
                    ];
                    for (tally, outputs) in part_shifts.iter_mut().zip(&variants) {
                        let d = descriptors(&outputs[0]);
                        tally.0.extend(dirs.shift_on(target, content_d, &d, &LOWER_BODY));
                        tally.1.extend(dirs.shift_on(target, content_d, &d, &UPPER_BODY));
                    }
                }
                let (output, pair) = if motion_based {
                    let mean = stylize::stylize(inputs.weights, &content.motion, &request)?.remove(0);
                    let draws = stylize::stylize(inputs.weights, &content.motion, &request.clone().with_samples(2))?;
                    (mean, draws)
                } else {
                    let samples = stylize::stylize(inputs.weights, &content.motion, &request.with_samples(2))?;
                    (samples[0].clone(), samples)
                };
                let t = &mut tallies[row];
                let judged = inputs.judge.judge(&output);
                let of_content = match (inputs.content_judge, content_j) {
                    (Some(judge), Some(of_content)) => Some((judge.judge(&output), of_content)),
                    _ => None,
                };
                if row != 5 {
                    let entry = labels[row].entry(target).or_default();
                    entry.style.count(&judged, Some(target));
                    if let Some(s) = shift_of(&output) {
                        t.shift.push(s);
                        entry.shifts.push(s);
                    }
                    if let Some((j, _)) = &of_content {
                        entry.count_content(j, content.content);
                    }
                }
                let target = (row != 5).then_some(target);
                t.judge(judged, target, &ref_feature);
                if let Some((j, of_content)) = of_content {
                    t.judge_content(j, content.content, &of_content.feature);
                }
                if let Some(g) = geodesic(&content.motion, &output) {
                    t.geodesic.push(g);
                }
                let (a, b) = (inputs.judge.judge(&pair[0]), inputs.judge.judge(&pair[1]));
                t.diversity.push(feature_distance(&a.feature, &b.feature));
                if let Some(d) = position_distance(&pair[0], &pair[1]) {
                    t.diversity_cm.push(d);
                }
                pool(&mut t.skate, foot_skate_parts(&output));
                pool(&mut t.reference_skate, reference_skate);
            }
            done += 1;
            progress(done, total);
        }
        for (row, t) in tallies.iter().enumerate() {
            per_row[row].push(t.per_repeat());
        }
    }

    let label_rows = labels
        .iter()
        .enumerate()
        .flat_map(|(row, by_label)| {
            by_label.iter().map(move |(&style, t)| LabelRow {
                setting: ROWS[row],
                style,
                outputs: t.style.judged,
                style_acc: t.style.accuracy(),
                style_shift: (!t.shifts.is_empty()).then(|| t.shifts.iter().sum::<f64>() / t.shifts.len() as f64),
                content_acc: t.content.accuracy(),
                content_mistakes: t.mistakes(),
            })
        })
        .collect();
    let rows = ROWS
        .iter()
        .enumerate()
        .map(|(row, &setting)| {
            let values = COLUMNS
                .iter()
                .enumerate()
                .map(|(c, &name)| {
                    let v: Vec<f64> = per_row[row].iter().filter_map(|m| m[c]).collect();
                    // A metric counts only if every repeat measured it.
                    let stats = (v.len() == per_row[row].len()).then(|| mean_ci(&v)).flatten();
                    let not_applicable =
                        (row <= 1 && name.starts_with("diversity")) || (row == 5 && name == "style_acc");
                    match stats {
                        Some((m, ci)) if !not_applicable => (name, Some(m), ci),
                        _ => (name, None, None),
                    }
                })
                .collect();
            Row { setting, values }
        })
        .collect();
    let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    let parts = if inputs.parts {
        PART_VARIANTS
            .iter()
            .zip(&part_shifts)
            .map(|(&variant, (lower, upper))| PartShift {
                variant,
                outputs: lower.len().max(upper.len()),
                lower: mean(lower),
                upper: mean(upper),
            })
            .collect()
    } else {
        Vec::new()
    };
    Ok(Evaluation { rows, labels: label_rows, parts })
}
