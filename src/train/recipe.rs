//! A stylizer run's recipe: the weights of its loss terms ([`StylizerWeights`], the paper's for
//! each mode and what a run adds) and the flags of `motion-stylizer train stylizer` that set them
//! ([`StylizerExtras`]). The losses themselves are in [`super::losses`].

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// Weights of the stylizer's loss `L = λ_rec L_rec + λ_hsa L_hsa + λ_cyc L_cyc + λ_kl L_kl
/// (+ λ_stats L_stats + λ_shape L_shape + λ_content_class L_content_class + λ_style_class
/// L_style_class)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StylizerWeights {
    pub rec: f32,
    pub hsa: f32,
    pub cyc: f32,
    pub kl: f32,
    /// `λ_stats` of the style-statistics loss on content-paired swaps
    /// ([`style_statistics`](super::statistics::style_statistics); not in the paper: 0 there). A
    /// run with it above 0 draws content-paired batch rows
    /// ([`super::sampler::WindowSampler::content_partner`]).
    #[serde(default)]
    pub style_stats: f32,
    /// `λ_shape` of the content-shape loss on every swap
    /// ([`content_shape`](super::statistics::content_shape); not in the paper: 0 there).
    #[serde(default)]
    pub content_shape: f32,
    /// Cross-content swaps (not in the paper; needs `style_stats` above 0): a content-paired row's
    /// swap takes its style from a take of its partner's style and *another* content, and is
    /// still judged by the partner's statistics, so the content's own posture and curves must
    /// come through the content code (rows 4k, 4k+1: the pair; 4k+2, 4k+3: the style sources;
    /// [`StylizerInputs::style_source`](super::losses::StylizerInputs::style_source)). `false`:
    /// the partner is the style source.
    #[serde(default)]
    pub cross_content: bool,
    /// Content pairs across the data sets (not in the paper; needs `style_stats` above 0): a
    /// content-paired row's partner is the same content in another style of *either* data set
    /// (Bandai's two share `walk` and `run`), so set 1's styles are also shown, with a target, on
    /// set 2's takes of those contents. `false`: partners from the row's own data set.
    #[serde(default)]
    pub cross_set: bool,
    /// With [`cross_set`](Self::cross_set): a pair across the sets is judged by its partner's
    /// statistics moved by the difference of the two sets' `normal` takes of the content
    /// ([`StatsOffset`](super::statistics::StatsOffset)), so the target carries the partner's
    /// *style* (its difference from its own set's `normal`) and not its set's capture. `false`:
    /// the partner's raw statistics.
    #[serde(default)]
    pub cross_set_relative: bool,
    /// `λ_content_class` of the content-class loss (not in the paper: 0 there): every swap `D(zᵗ)` is
    /// read by a frozen content classifier (the run's `content-judge.bin`), whose cross-entropy
    /// against the content class of the swap's content clip is added, so a style from another
    /// content or data set must keep what the content is.
    #[serde(default)]
    pub content_class: f32,
    /// `λ_style_class` of the style-class loss (not in the paper: 0 there; supervised): every
    /// swap `D(zᵗ)` is read by a frozen style classifier (the run's `style-judge.bin`), whose
    /// cross-entropy against the swap's target label (its style source's) is added.
    #[serde(default)]
    pub style_class: f32,
}

/// What a stylizer run adds to the paper's recipe: losses (their weights; 0: not used), the
/// cross-content swaps, and the posture path of the networks ([`ModelConfig::content_posture`]).
/// Also the flags of `motion-stylizer train stylizer` (their help is these fields' docs);
/// [`StylizerExtras::validate`] checks them.
///
/// [`ModelConfig::content_posture`]: crate::model::ModelConfig::content_posture
#[derive(clap::Args, Clone, Debug, Default, PartialEq)]
pub struct StylizerExtras {
    /// Weight of the style-statistics loss (not in the paper; new runs): every other pair of
    /// batch rows is two takes of one content in different styles, and the swap of one's
    /// content with the other's style is pulled to the other's per-feature mean and spread
    /// over time. 0: the paper's losses only.
    #[arg(long, default_value_t = 0.0, value_name = "WEIGHT")]
    pub style_stats: f32,
    /// Weight of the content-shape loss (not in the paper; new runs): every swap's decoded
    /// features, each standardised over the window (its mean and spread removed), are pulled
    /// to its content clip's, so a style changes the statistics and keeps the content's
    /// curves. 0: not used.
    #[arg(long, default_value_t = 0.0, value_name = "WEIGHT")]
    pub content_shape: f32,
    /// Weight of the homo-style alignment term (the KL between the style posteriors of two
    /// windows of one take; new runs) instead of the paper's (supervised 1, unsupervised 0.1).
    #[arg(long, value_name = "WEIGHT")]
    pub hsa: Option<f32>,
    /// Cross-content swaps (not in the paper; new runs, with --style-stats): a content-paired
    /// row's swap takes its style from a take of its partner's style and another content, and
    /// is judged by the partner's statistics, so the content's posture must come through.
    #[arg(long)]
    pub cross_content: bool,
    /// Content pairs across the data sets (not in the paper; new runs, with --style-stats): a
    /// content-paired row's partner may be the same content in a style of the other Bandai
    /// set (they share `walk` and `run`), so set 1's styles get a target on set 2's contents.
    /// Measured to cost set 1's targets their content (EVALUATION.md, "Content pairs across
    /// the sets"): kept for the record, not in the shipped recipe.
    #[arg(long)]
    pub cross_set: bool,
    /// With --cross-set: a pair across the sets is judged by its partner's statistics moved by
    /// the difference between the two sets' `normal` takes of the content, so it carries the
    /// partner's style (its difference from its own set's `normal`), not its set's capture.
    #[arg(long, requires = "cross_set")]
    pub cross_set_relative: bool,
    /// The content's posture past AdaIN (not in the paper; new runs): the generator adds a
    /// linear map of the content latent's mean over time to its output. From weights without
    /// it (--from), the map starts at zero.
    #[arg(long)]
    pub content_posture: bool,
    /// Weight of the content-class loss (not in the paper; new runs, with --content-judge):
    /// every swap (a content with another clip's style) is read by a frozen content classifier,
    /// and its cross-entropy against the content's class is added. 0: not used.
    #[arg(long, default_value_t = 0.0, value_name = "WEIGHT")]
    pub content_class: f32,
    /// The content classifier that judges the swaps for --content-class (a classifier.bin of
    /// `train content-classifier`; copied into the run folder as content-judge.bin). Train it
    /// apart from the one `eval` measures with (another seed or width), so that the evaluation
    /// does not read its own judge.
    #[arg(long, value_name = "FILE")]
    pub content_judge: Option<PathBuf>,
    /// Weight of the style-class loss (not in the paper; new supervised runs, with
    /// --style-judge): every swap is read by a frozen style classifier, and its cross-entropy
    /// against the swap's target label is added. 0: not used.
    #[arg(long, default_value_t = 0.0, value_name = "WEIGHT")]
    pub style_class: f32,
    /// The style classifier that judges the swaps for --style-class (a classifier.bin of `train
    /// classifier`; copied into the run folder as style-judge.bin). Train it apart from the one
    /// `eval` measures with.
    #[arg(long, value_name = "FILE")]
    pub style_judge: Option<PathBuf>,
}

impl StylizerExtras {
    /// Every weight finite and at least 0; the cross-content swaps and cross-set pairs only with
    /// the style statistics that judge them.
    pub fn validate(&self) -> Result<(), String> {
        for (flag, w) in [
            ("--style-stats", self.style_stats),
            ("--content-shape", self.content_shape),
            ("--hsa", self.hsa.unwrap_or(0.0)),
            ("--content-class", self.content_class),
            ("--style-class", self.style_class),
        ] {
            if !(w.is_finite() && w >= 0.0) {
                return Err(format!("{flag} {w}: the weight must be 0 or more"));
            }
        }
        for (flag, on, what) in
            [("--cross-content", self.cross_content, "swaps"), ("--cross-set", self.cross_set, "pairs")]
        {
            if on && self.style_stats <= 0.0 {
                return Err(format!(
                    "{flag} needs --style-stats above 0 (its {what} are judged by the style statistics)"
                ));
            }
        }
        for (flag, weight, judge_flag, judge, what) in [
            ("--content-class", self.content_class, "--content-judge", &self.content_judge, "content"),
            ("--style-class", self.style_class, "--style-judge", &self.style_judge, "style"),
        ] {
            match (weight > 0.0, judge) {
                (true, None) => {
                    return Err(format!(
                        "{flag} needs {judge_flag} FILE (the {what} classifier that judges the swaps)"
                    ));
                }
                (false, Some(_)) => return Err(format!("{judge_flag} is used only with {flag} above 0")),
                _ => {}
            }
        }
        Ok(())
    }

    /// Whether a run departs from the paper's recipe (its [`StylizerWeights`] are then written
    /// into the run's settings; the posture path is the model config's, and counts here only so
    /// that such a run says it departs).
    pub fn any(&self) -> bool {
        self.style_stats > 0.0
            || self.content_shape > 0.0
            || self.hsa.is_some()
            || self.cross_content
            || self.cross_set
            || self.cross_set_relative
            || self.content_posture
            || self.content_class > 0.0
            || self.style_class > 0.0
    }
}

impl StylizerWeights {
    /// Paper, supervised: (hsa, cyc, kl) = (1, 0.1, 0.1).
    pub const SUPERVISED: Self = Self {
        rec: 1.0,
        hsa: 1.0,
        cyc: 0.1,
        kl: 0.1,
        style_stats: 0.0,
        content_shape: 0.0,
        cross_content: false,
        cross_set: false,
        cross_set_relative: false,
        content_class: 0.0,
        style_class: 0.0,
    };
    /// Paper, unsupervised: (hsa, cyc, kl) = (0.1, 1, 0.01); none of the additions, as supervised.
    pub const UNSUPERVISED: Self = Self { hsa: 0.1, cyc: 1.0, kl: 0.01, ..Self::SUPERVISED };

    /// The paper's weights for the given mode.
    pub fn paper(supervised: bool) -> Self {
        if supervised { Self::SUPERVISED } else { Self::UNSUPERVISED }
    }
}
