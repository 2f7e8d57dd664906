//! `assets/weights/manifest.json`: what the shipped weights are and how they were made.
//!
//! The folder holds `manifest.json`, `norm.json` (the training split's [`NormStats`]) and one f16
//! bundle per stylizer setting (`supervised.bin`, `unsupervised.bin`; each holds its config, the
//! autoencoder, the stylizer networks and the global motion regressor — see
//! [`crate::model::weights::save_bundle`]). Written by `motion-stylizer export`, read by inference.
//!
//! [`NormStats`]: crate::features::NormStats

use serde::{Deserialize, Serialize};

/// Current manifest format.
pub const FORMAT: u32 = 1;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: u32,
    /// Licence of the weights (trained on CC BY-NC 4.0 data).
    pub licence: String,
    /// Style labels in one-hot order (the unified label set, [`crate::dataset::STYLES`]).
    pub styles: Vec<String>,
    /// File name of the normalisation statistics, relative to the manifest.
    pub norm: String,
    /// Training window, frames.
    pub window: usize,
    /// The held-out split file the training used (repository path) and its held-out take count.
    pub split: String,
    pub heldout_takes: usize,
    /// Per setting: `"supervised"`, `"unsupervised"`.
    pub models: Vec<ModelEntry>,
}

/// One shipped bundle and its provenance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelEntry {
    /// `"supervised"` or `"unsupervised"`.
    pub setting: String,
    /// Bundle file name, relative to the manifest.
    pub file: String,
    /// Width factor relative to the paper's sizes.
    pub width: f64,
    /// Training stages that produced it, in order (autoencoder first, then the stylizer).
    pub stages: Vec<StageRecord>,
    /// Supervised model: where each label's real takes sit in its style space, the centre that
    /// label-based codes are drawn around (written by `motion-stylizer label-codes`). Absent:
    /// label-based codes are drawn around 0, the prior's mean.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label_codes: Option<LabelCodes>,
}

/// Per label, the mean of the style encoder's posterior means over the label's training takes
/// (each data set weighted equally where it has the label: set 1 has ~11 takes a style, set 2
/// ~400), in one-hot order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LabelCodes {
    /// The exact command that wrote them.
    pub command: String,
    /// Training takes encoded, per label (one-hot order).
    pub takes: Vec<usize>,
    /// `[num_styles][style_dim]`.
    pub codes: Vec<Vec<f32>>,
}

/// How one training stage ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageRecord {
    /// `"ae"` or `"stylizer"`.
    pub stage: String,
    /// The exact command line.
    pub command: String,
    pub steps: u64,
    pub seed: u64,
    pub batch: usize,
    pub window: usize,
    /// Wall-clock training time, seconds, and seconds per step on the machine it ran on.
    pub seconds: f64,
    pub seconds_per_step: f64,
    pub machine: String,
    /// Final training losses (moving averages) by name, and held-out metrics by name.
    pub final_losses: std::collections::BTreeMap<String, f64>,
    pub heldout: std::collections::BTreeMap<String, f64>,
}
