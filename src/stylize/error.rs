//! [`StylizeError`]: everything the inference pipeline can refuse, typed. Nothing in
//! [`crate::stylize`] panics on user input (motions, requests, weight bytes).

use crate::features::FeatureError;
use crate::model::ModelError;
use crate::skeleton::ImportError;

use super::weights::Setting;

/// Why a stylization (or loading its weights) failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum StylizeError {
    /// A style label name that the weights do not know.
    #[error("unknown style label {name:?}; the labels are: {}", valid.join(", "))]
    UnknownLabel { name: String, valid: Vec<String> },
    /// A [`Style`](crate::dataset::Style) index beyond the model's labels.
    #[error("style label #{index} is out of range: the model has {count} labels")]
    LabelOutOfRange { index: usize, count: usize },
    /// The weights hold no model for this setting.
    #[error("the {setting} model is not in these weights")]
    SettingUnavailable { setting: Setting },
    /// A request that needs the style encoder (a reference motion, or a label to infer) of a
    /// model loaded without it: format 3 keeps each style encoder in a file of its own, which a
    /// loader adds when first needed ([`super::Weights::add_style_encoder`]).
    #[error(
        "the {setting} model's style encoder is not loaded (its file is fetched when a reference motion is first used)"
    )]
    StyleEncoderUnavailable { setting: Setting },
    /// A label-based request to the unsupervised model (it knows no labels).
    #[error(
        "label-based stylization needs the supervised model; the unsupervised one takes a reference motion or the prior"
    )]
    LabelNeedsSupervised,
    /// A motion-based request to the supervised model without the reference motion's style label
    /// (the supervised style encoder is conditioned on it, paper §3.4 a).
    #[error(
        "the supervised model needs the style label of the reference motion; give it, or use the unsupervised model"
    )]
    MotionNeedsLabel,
    /// A label given with a reference motion to the unsupervised model (it would be ignored).
    #[error("the unsupervised model takes no style label; leave the label out or use the supervised model")]
    LabelWithUnsupervised,
    /// `samples` outside `1..=max`.
    #[error("samples must be between 1 and {max}, got {got}")]
    Samples { got: usize, max: usize },
    /// A content or reference motion longer than the pipeline accepts.
    #[error("the {what} motion has {frames} frames; at most {max} (30 fps) are accepted")]
    TooLong { what: &'static str, frames: usize, max: usize },
    /// A style mix weight that is not a finite number in [0, 1].
    #[error("style mix weight must be in [0, 1], got {t}")]
    MixWeight { t: f32 },
    /// A prior temperature that is not a finite number in [0, max].
    #[error("temperature must be between 0 and {max}, got {got}")]
    Temperature { got: f32, max: f32 },
    /// A style strength that is not a finite number in [0, max].
    #[error("strength must be between 0 and {max}, got {got}")]
    Strength { got: f32, max: f32 },
    /// A style guidance that is not a finite number in [0, max].
    #[error("guidance must be between 0 and {max}, got {got}")]
    Guidance { got: f32, max: f32 },
    /// Per-body-part requests that cannot be combined (none given, sample counts that differ).
    #[error("body parts: {0}")]
    Parts(String),
    /// Style mixes nested deeper than the limit.
    #[error("style mixes are nested deeper than {max}")]
    MixTooDeep { max: usize },
    /// Weight files (manifest, normalisation statistics, bundles) that cannot be used.
    #[error("bad weights: {0}")]
    BadWeights(String),
    /// A weight file that cannot be read (native loader only).
    #[error("cannot read {path}: {message}")]
    Read { path: String, message: String },
    /// A BVH that cannot be brought onto the canonical rig.
    #[error(transparent)]
    Import(#[from] ImportError),
    /// The networks produced values the feature stage refuses (not finite).
    #[error("the networks' output cannot be turned into a motion: {0}")]
    Features(#[from] FeatureError),
    /// An error of the model API (a bug of the pipeline if it ever shows).
    #[error("model: {0}")]
    Model(String),
}

impl StylizeError {
    /// A stable, machine-readable name of the failure class (the npm package's `error.code`):
    /// `UNKNOWN_LABEL`, `SETTING_UNAVAILABLE`, `STYLE_ENCODER_UNAVAILABLE`, `BAD_REQUEST` (a request the model cannot serve:
    /// samples, temperature, strength, guidance, mix weight or depth, body parts, a label where none fits or none where one is needed),
    /// `TOO_LONG`, `BAD_WEIGHTS`, `MODEL_OUTPUT`, `INTERNAL`, or the import's code
    /// ([`ImportError::code`]).
    pub fn code(&self) -> &'static str {
        use StylizeError::*;
        match self {
            UnknownLabel { .. } | LabelOutOfRange { .. } => "UNKNOWN_LABEL",
            SettingUnavailable { .. } => "SETTING_UNAVAILABLE",
            StyleEncoderUnavailable { .. } => "STYLE_ENCODER_UNAVAILABLE",
            LabelNeedsSupervised
            | MotionNeedsLabel
            | LabelWithUnsupervised
            | Samples { .. }
            | MixWeight { .. }
            | MixTooDeep { .. }
            | Temperature { .. }
            | Strength { .. }
            | Guidance { .. }
            | Parts(_) => "BAD_REQUEST",
            TooLong { .. } => "TOO_LONG",
            BadWeights(_) | Read { .. } => "BAD_WEIGHTS",
            Import(e) => e.code(),
            Features(_) => "MODEL_OUTPUT",
            Model(_) => "INTERNAL",
        }
    }
}

impl From<ModelError> for StylizeError {
    fn from(e: ModelError) -> Self {
        match e {
            ModelError::Weights(m) => StylizeError::BadWeights(m),
            ModelError::StyleEncoderNotLoaded { setting } => {
                StylizeError::StyleEncoderUnavailable { setting: Setting::from_name(setting).unwrap_or_default() }
            }
            other => StylizeError::Model(other.to_string()),
        }
    }
}
