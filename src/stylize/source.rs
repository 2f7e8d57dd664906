//! What a stylization asks for: the style source ([`StyleSource`]) and the [`Request`] around it.

use super::weights::Setting;
use crate::Motion;
use crate::dataset::Style;

/// Most outputs one request may ask for.
pub const MAX_SAMPLES: usize = 64;

/// Default scale of the style codes drawn from the prior (label- and prior-based): draws are
/// `temperature · N(0, I)`. The trained style posteriors sit well inside the prior (held-out KL
/// ≈ 0.4 nats per dimension, supervised), so full-scale prior draws land where the generator never
/// saw a code; measured on 20 held-out contents (`eval --limit 20 --repeats 2`, supervised
/// label-based): temperature 1.0 → style accuracy 0.35, 0.5 → 0.55, 0.3 → 0.88 with diversity
/// well above zero, 0.0 → 0.93 with none.
pub const DEFAULT_TEMPERATURE: f32 = 0.3;

/// Largest accepted temperature.
pub const MAX_TEMPERATURE: f32 = 4.0;

/// Default style strength: the networks' output as it is.
pub const DEFAULT_STRENGTH: f32 = 1.0;

/// Largest accepted style strength ("exaggerated").
pub const MAX_STRENGTH: f32 = 2.0;

/// Default style guidance (see [`Request::guidance`]). Measured (EVALUATION.md, "Guidance";
/// 120 held-out contents × 3 repeats, shipped weights), label-based style shift 0.36 → 1.06 and
/// content accuracy 0.22 → 0.27 at 0 → 1, the classifier's accuracy 0.96 → 0.92; at 1.5 the
/// accuracy falls to 0.88 and diversity towards zero.
pub const DEFAULT_GUIDANCE: f32 = 1.0;

/// Largest accepted style guidance.
pub const MAX_GUIDANCE: f32 = 3.0;

/// Deepest nesting of [`StyleSource::Mix`].
pub const MAX_MIX_DEPTH: usize = 8;

/// Where the style code comes from (paper Fig. 4).
#[derive(Clone, Debug, PartialEq)]
pub enum StyleSource<'a> {
    /// Motion-based: the style encoder's posterior of a reference motion (any length; it is
    /// padded like the content). One sample: the posterior mean (deterministic, the seed is
    /// unused). `N > 1` samples: `N` draws `μ + σ ε` from the posterior, for diversity.
    ///
    /// `label` is the reference's style label: required by the supervised model (its style
    /// encoder and generator are conditioned on it), refused by the unsupervised one.
    Motion { motion: &'a Motion, label: Option<Style> },
    /// Label-based (supervised model only): codes from the prior `N(0, I)` with this label, one
    /// draw per sample.
    Label(Style),
    /// Prior-based: codes from the prior `N(0, I)`, one draw per sample. With the supervised
    /// model each sample also gets a label drawn uniformly from the seed ("any style").
    Prior,
    /// Interpolation `(1 − t)·a + t·b` of two sources' style codes (and, in the supervised model,
    /// of their one-hot labels, which the generator's AdaIN takes as a linear input); `t` in
    /// [0, 1]. `a`'s noise is drawn before `b`'s, so `t = 0` gives exactly `a`'s result.
    Mix { a: Box<StyleSource<'a>>, b: Box<StyleSource<'a>>, t: f32 },
}

impl<'a> StyleSource<'a> {
    /// Motion-based, without a label (the unsupervised model).
    pub fn motion(motion: &'a Motion) -> Self {
        StyleSource::Motion { motion, label: None }
    }

    /// Motion-based with the reference's style label (the supervised model).
    pub fn labelled_motion(motion: &'a Motion, label: Style) -> Self {
        StyleSource::Motion { motion, label: Some(label) }
    }

    /// `(1 − t)·a + t·b`.
    pub fn mix(a: StyleSource<'a>, b: StyleSource<'a>, t: f32) -> Self {
        StyleSource::Mix { a: Box::new(a), b: Box::new(b), t }
    }
}

/// One stylization request.
#[derive(Clone, Debug, PartialEq)]
pub struct Request<'a> {
    pub source: StyleSource<'a>,
    pub setting: Setting,
    /// Number of outputs, `1..=`[`MAX_SAMPLES`]; all go through the networks in one batch.
    pub samples: usize,
    /// Seed of every random draw (style noise, random labels). Same seed, same request → the same
    /// output, bit for bit.
    pub seed: u64,
    /// Scale of prior draws (label- and prior-based), in `[0, MAX_TEMPERATURE]`; see
    /// [`DEFAULT_TEMPERATURE`]. 1.0 is the paper's `N(0, I)`. Motion-based draws are unaffected.
    pub temperature: f32,
    /// How far the output goes towards the style, in `[0, MAX_STRENGTH]`: 0 gives back the
    /// content's motion, 1 ([`DEFAULT_STRENGTH`]) the stylizer's (guided) output, 2 twice the change (see
    /// [`stylize`](super::stylize)).
    pub strength: f32,
    /// Style guidance `g` in `[0, MAX_GUIDANCE]` ([`DEFAULT_GUIDANCE`]): the generator's latent
    /// `G_s = G(c, s)` is pushed further along what makes the style differ from the neutral style
    /// (`normal` in the supervised model; in the unsupervised one the `normal` takes' code for a
    /// reference, [`Weights::neutral_code`](super::Weights::neutral_code), and the prior's mean
    /// for prior draws) on the same content, `G_n`, and back towards the content's own latent
    /// `z_c` by half of what the neutral style loses of it: `G_s + g·((G_s − G_n) + ½(z_c −
    /// G_n))`. 0 is the networks' output as trained (one generator pass less). Unlike strength, which scales every change
    /// from the content (the generator's drift under any style included), guidance amplifies the
    /// style's own difference. [`Request::strength`] applies after it. Not applied to `normal`
    /// itself, label-based or a reference labelled (or inferred) `normal` (it has no difference
    /// from itself, and the content term would bring back the content's own style), nor with
    /// supervised weights that have no `normal` label (one's own styles).
    pub guidance: f32,
}

impl<'a> Request<'a> {
    /// One sample from `source` with the supervised model, seed 0.
    pub fn new(source: StyleSource<'a>) -> Self {
        Request {
            source,
            setting: Setting::Supervised,
            samples: 1,
            seed: 0,
            temperature: DEFAULT_TEMPERATURE,
            strength: DEFAULT_STRENGTH,
            guidance: DEFAULT_GUIDANCE,
        }
    }

    pub fn with_setting(mut self, setting: Setting) -> Self {
        self.setting = setting;
        self
    }

    pub fn with_samples(mut self, samples: usize) -> Self {
        self.samples = samples;
        self
    }

    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    pub fn with_temperature(mut self, temperature: f32) -> Self {
        self.temperature = temperature;
        self
    }

    pub fn with_strength(mut self, strength: f32) -> Self {
        self.strength = strength;
        self
    }

    pub fn with_guidance(mut self, guidance: f32) -> Self {
        self.guidance = guidance;
        self
    }
}
