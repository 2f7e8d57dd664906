//! Label codes: where each style label's real takes sit in the supervised model's style space.
//!
//! Label-based stylization used to draw its style code from the prior `N(0, T²·I)` around 0 and
//! leave the style to the one-hot label's path into AdaIN. The style encoder's posteriors of real
//! takes do not sit at 0: the KL term (weight 0.1) pulls them only part of the way, and most of a
//! label's look is in the code, not in the one-hot (EVALUATION.md: label-based outputs moved 0.15
//! of the way to a real take of the style, motion-based ones from a real reference 0.35). So
//! label-based codes are drawn around the label's centre instead: the mean of the posterior means
//! of its training takes (under their own label), each data set weighted equally where it has the
//! label (set 1 has ~11 takes a style, set 2 ~400; the held-out takes are never used).

use anyhow::{Context, ensure};

use crate::Motion;
use crate::dataset::{STYLES, Style, TakeId};
use crate::stylize::pipeline::NEUTRAL_LABEL;
use crate::stylize::{LabelCodes, NeutralCode, Setting, Weights, style_code_of};

/// One training motion for [`label_codes_of`]: its label and the group it is weighed in (the
/// Bandai data sets; a folder of one's own files is one group).
pub struct LabelledMotion<'a> {
    pub name: String,
    pub group: usize,
    pub style: Style,
    pub motion: &'a Motion,
}

/// The label codes of `weights`' supervised model from the training `takes`; `command` is
/// recorded with them. `progress(done, total)` after each take.
pub fn label_codes(
    weights: &Weights,
    takes: &[(TakeId, &Motion)],
    command: String,
    progress: impl FnMut(usize, usize),
) -> anyhow::Result<LabelCodes> {
    let model = weights.model(Setting::Supervised)?;
    let labels = model.config.num_styles;
    ensure!(labels == STYLES.len(), "the supervised model knows {labels} labels, the data {}", STYLES.len());
    let items = bandai_items(takes);
    for label in 0..labels {
        ensure!(items.iter().any(|m| m.style.index() == label), "no training take of the label {}", STYLES[label]);
    }
    label_codes_of(weights, &items, command, progress)
}

/// Bandai-Namco takes as [`LabelledMotion`]s, grouped by data set.
pub fn bandai_items<'a>(takes: &[(TakeId, &'a Motion)]) -> Vec<LabelledMotion<'a>> {
    takes
        .iter()
        .map(|(take, motion)| LabelledMotion {
            name: take.stem(),
            group: usize::from(take.set),
            style: take.style(),
            motion,
        })
        .collect()
}

/// The label codes of `weights`' supervised model from labelled training motions: per label, the
/// mean over the groups that have it of the group's mean posterior mean. A label without any
/// motion gets the prior's mean (0) and a count of 0.
pub fn label_codes_of(
    weights: &Weights,
    items: &[LabelledMotion<'_>],
    command: String,
    mut progress: impl FnMut(usize, usize),
) -> anyhow::Result<LabelCodes> {
    let model = weights.model(Setting::Supervised)?;
    let (labels, dim) = (model.config.num_styles, model.config.style_dim);
    let mut groups: Vec<usize> = items.iter().map(|m| m.group).collect();
    groups.sort_unstable();
    groups.dedup();
    // Sums and counts per (group, label).
    let mut sums = vec![vec![0.0f64; dim]; groups.len() * labels];
    let mut counts = vec![0usize; groups.len() * labels];
    for (i, item) in items.iter().enumerate() {
        ensure!(item.style.index() < labels, "{}: label {} out of range {labels}", item.name, item.style.index());
        let code = style_code_of(weights, Setting::Supervised, item.motion, Some(item.style))
            .with_context(|| format!("encoding {}", item.name))?;
        let group = groups.binary_search(&item.group).unwrap_or(0);
        let slot = group * labels + item.style.index();
        for (s, c) in sums[slot].iter_mut().zip(&code) {
            *s += f64::from(*c);
        }
        counts[slot] += 1;
        progress(i + 1, items.len());
    }
    let mut codes = Vec::with_capacity(labels);
    let mut takes_per_label = Vec::with_capacity(labels);
    for label in 0..labels {
        let present: Vec<usize> = (0..groups.len()).filter(|&s| counts[s * labels + label] > 0).collect();
        let slots = present.iter().map(|&s| (sums[s * labels + label].as_slice(), counts[s * labels + label]));
        codes.push(balanced_centre(slots.collect(), dim));
        takes_per_label.push(present.iter().map(|&s| counts[s * labels + label]).sum());
    }
    Ok(LabelCodes { command, takes: takes_per_label, codes })
}

/// The unsupervised model's neutral code from labelled training motions: per group (data set),
/// the mean posterior mean of its `normal` motions, averaged over the groups that have some
/// (set 1 has 19 `normal` takes, set 2 ~400). `None` when the weights have no unsupervised model
/// or no `normal` label, or no motion is labelled so.
pub fn neutral_code_of(
    weights: &Weights,
    items: &[LabelledMotion<'_>],
    command: String,
) -> anyhow::Result<Option<NeutralCode>> {
    let (Ok(model), Ok(normal)) = (weights.model(Setting::Unsupervised), weights.style(NEUTRAL_LABEL)) else {
        return Ok(None);
    };
    let dim = model.config.style_dim;
    let mut by_group: std::collections::BTreeMap<usize, (Vec<f64>, usize)> = Default::default();
    for item in items.iter().filter(|m| m.style == normal) {
        let code = style_code_of(weights, Setting::Unsupervised, item.motion, None)
            .with_context(|| format!("encoding {}", item.name))?;
        let (sum, count) = by_group.entry(item.group).or_insert_with(|| (vec![0.0; dim], 0));
        for (s, c) in sum.iter_mut().zip(&code) {
            *s += f64::from(*c);
        }
        *count += 1;
    }
    if by_group.is_empty() {
        return Ok(None);
    }
    Ok(Some(NeutralCode {
        command,
        takes: by_group.values().map(|(_, n)| n).sum(),
        code: balanced_centre(by_group.values().map(|(sum, n)| (sum.as_slice(), *n)).collect(), dim),
    }))
}

/// The mean over groups of each group's mean code, from each group's sum of codes and count
/// (groups with at least one motion), so that a data set with ~400 takes of a label weighs no more
/// than one with ~11. Four decimals: the manifest stays small (the codes' spread is ~0.1-1).
fn balanced_centre(groups: Vec<(&[f64], usize)>, dim: usize) -> Vec<f32> {
    let mut centre = vec![0.0f64; dim];
    for &(sum, count) in &groups {
        for (c, s) in centre.iter_mut().zip(sum) {
            *c += s / count as f64 / groups.len() as f64;
        }
    }
    centre.iter().map(|&v| ((v * 1e4).round() / 1e4) as f32).collect()
}

/// Fine-tuning's label codes: `codes` (computed from the new data's takes) merged with `old`
/// (the weights' own, from their training takes). Each old label's code becomes the mean over
/// both sets of takes — `old` and the new code weighted by their take counts — so a label the new
/// data has no files of keeps its code, and a few new takes of an old label (e.g. `normal`, whose
/// code the default guidance measures every style against) move a code made from thousands only
/// a little. New labels (past `old`'s) keep the codes of the new data. A row whose length differs
/// (another style width) is left as computed.
pub fn merge_old_codes(codes: &mut LabelCodes, old: &LabelCodes) {
    for (i, (old_row, &old_takes)) in old.codes.iter().zip(&old.takes).enumerate() {
        let (Some(row), Some(takes)) = (codes.codes.get_mut(i), codes.takes.get_mut(i)) else { continue };
        if row.len() != old_row.len() || old_takes == 0 {
            continue;
        }
        let total = old_takes + *takes;
        let (w_old, w_new) = (old_takes as f32 / total as f32, *takes as f32 / total as f32);
        for (v, o) in row.iter_mut().zip(old_row) {
            *v = w_old * o + w_new * *v;
        }
        *takes = total;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn old_codes_are_kept_or_merged_by_take_count_and_new_labels_keep_theirs() {
        let old =
            LabelCodes { command: "old".into(), takes: vec![300, 10], codes: vec![vec![1.0, 0.0], vec![0.0, 2.0]] };
        let mut codes = LabelCodes {
            command: "new".into(),
            takes: vec![100, 0, 4],
            codes: vec![vec![5.0, 4.0], vec![0.0, 0.0], vec![7.0, 7.0]],
        };
        merge_old_codes(&mut codes, &old);
        assert_eq!(codes.takes, [400, 10, 4]);
        assert_eq!(codes.codes, [vec![2.0, 1.0], vec![0.0, 2.0], vec![7.0, 7.0]]);
        assert_eq!(codes.command, "new");
    }
}
