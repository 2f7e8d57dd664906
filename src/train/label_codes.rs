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
use crate::dataset::{STYLES, TakeId};
use crate::stylize::{LabelCodes, Setting, Weights, style_code_of};

/// The label codes of `weights`' supervised model from the training `takes`; `command` is
/// recorded with them. `progress(done, total)` after each take.
pub fn label_codes(
    weights: &Weights,
    takes: &[(TakeId, &Motion)],
    command: String,
    mut progress: impl FnMut(usize, usize),
) -> anyhow::Result<LabelCodes> {
    let model = weights.model(Setting::Supervised)?;
    let (labels, dim) = (model.config.num_styles, model.config.style_dim);
    ensure!(labels == STYLES.len(), "the supervised model knows {labels} labels, the data {}", STYLES.len());
    // Sums and counts per (set, label).
    let sets = [1u8, 2];
    let mut sums = vec![vec![0.0f64; dim]; sets.len() * labels];
    let mut counts = vec![0usize; sets.len() * labels];
    for (i, (take, motion)) in takes.iter().enumerate() {
        let style = take.style();
        let code = style_code_of(weights, Setting::Supervised, motion, Some(style))
            .with_context(|| format!("encoding {}", take.stem()))?;
        let set = sets.iter().position(|&s| s == take.set).context("a take of neither set")?;
        let slot = set * labels + style.index();
        for (s, c) in sums[slot].iter_mut().zip(&code) {
            *s += f64::from(*c);
        }
        counts[slot] += 1;
        progress(i + 1, takes.len());
    }
    let mut codes = Vec::with_capacity(labels);
    let mut takes_per_label = Vec::with_capacity(labels);
    for label in 0..labels {
        let present: Vec<usize> = (0..sets.len()).filter(|&s| counts[s * labels + label] > 0).collect();
        ensure!(!present.is_empty(), "no training take of the label {}", STYLES[label]);
        let mut centre = vec![0.0f64; dim];
        for &s in &present {
            let n = counts[s * labels + label] as f64;
            for (c, v) in centre.iter_mut().zip(&sums[s * labels + label]) {
                *c += v / n / present.len() as f64;
            }
        }
        // Four decimals: the manifest stays small (the codes' spread is ~0.1-1).
        codes.push(centre.iter().map(|&v| ((v * 1e4).round() / 1e4) as f32).collect());
        takes_per_label.push(present.iter().map(|&s| counts[s * labels + label]).sum());
    }
    Ok(LabelCodes { command, takes: takes_per_label, codes })
}
