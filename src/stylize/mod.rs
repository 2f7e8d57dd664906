//! The inference pipeline: content motion + style source → stylized motions.
//!
//! No file system (except the native convenience [`Weights::load_dir`]), no threads of its own, no
//! panics on user input: everything it refuses is a [`StylizeError`]. The same code runs in the
//! browser (wasm), where the weight files are fetched and handed over as bytes
//! ([`Weights::from_bytes`]).
//!
//! ```text
//! let weights = Weights::load_dir("assets/weights")?;
//! let content = skeleton::import_bvh(&text)?;
//! let old = weights.style("old")?;
//! let request = Request::new(StyleSource::Label(old)).with_samples(3).with_seed(7);
//! let motions = stylize(&weights, &content.motion, &request)?;       // canonical rig, 30 fps
//! let bvh = content.rig.from_canonical(&motions[0]);                  // back on the user's rig
//! ```
//!
//! # Decisions
//!
//! - **Length.** The networks need a multiple of 8 frames: content and reference features are
//!   padded by reflection in time (mirror without repeating the edge, periodic if the pad is longer
//!   than the clip; a one-frame clip repeats its frame) to the next multiple of 8 (at least 8), and
//!   the output is trimmed back: every output has exactly the content's frame count. There is no
//!   minimum length; at most [`MAX_FRAMES`] (5 minutes).
//! - **Samples.** `samples = N` gives `N` outputs from `N` style codes, batched in one forward
//!   pass (the content is encoded once). Label- and prior-based: `N` draws from the prior.
//!   Motion-based: `N = 1` is the posterior mean (deterministic, the seed does not matter),
//!   `N > 1` are `N` draws from the reference's posterior (the paper's diverse motion-based
//!   stylization). At most [`MAX_SAMPLES`].
//! - **Labels.** The supervised model needs a label everywhere: label-based takes it; motion-based
//!   takes the *reference's* label (paper §3.4 a), and without one [`stylize`] refuses
//!   ([`StylizeError::MotionNeedsLabel`]); [`infer_label`] finds it (the label under which the
//!   model reconstructs the reference best; 0.834 of the held-out takes, the CLI uses it when no
//!   `--label` is given); prior-based draws a
//!   label per sample uniformly from the seed ("any style"). The unsupervised model refuses labels
//!   ([`StylizeError::LabelNeedsSupervised`], [`StylizeError::LabelWithUnsupervised`]).
//! - **Temperature.** Prior draws (label- and prior-based) are scaled by
//!   [`Request::temperature`] (default [`DEFAULT_TEMPERATURE`], measured: the paper's full-scale
//!   `N(0, I)` draws miss the label far more often with our weights).
//! - **Strength.** [`Request::strength`] `s` scales the change the stylizer makes in the motion
//!   autoencoder's latent space: the decoder gets `z_c + s·(z − z_c)`, with `z` the generator's
//!   latent and `z_c` the content's own (its encoding). 1 is the stylizer's output unchanged (the
//!   same bits), 2 doubles the change ("exaggerated"), and 0 returns the content's motion itself
//!   (not its reconstruction by the autoencoder). Extrapolating in the latent space rather than on
//!   poses keeps the decoder's own motion prior (bone lengths, foot contacts, root from the
//!   regressor): the style shift grows monotonically with `s` (tested on the shipped weights).
//! - **Guidance.** [`Request::guidance`] `g` (default [`DEFAULT_GUIDANCE`]) pushes the generator's
//!   latent further along what makes the style differ from the neutral style on the same content:
//!   `G_s + g·((G_s − G_n) + ½(z_c − G_n))`, one generator pass more (see its doc and
//!   EVALUATION.md); strength applies to the guided latent.
//! - **Label codes.** Label-based codes are drawn around the label's centre in the style space
//!   (the mean posterior of its training takes, [`Manifest`]'s `label_codes`), not around 0:
//!   `centre + temperature · N(0, I)`; weights without label codes draw around 0.
//! - **Body parts.** [`stylize_parts`] gives the lower body, the upper body and the head each
//!   their own request and combines the outputs joint by joint ([`parts`]).
//! - **Mix.** [`StyleSource::Mix`] lerps two sources' style codes (and one-hot labels).
//! - **Root.** Angular velocity from the content, ground velocity from the global motion
//!   regressor on the generated motion, height from the decoder (paper §3.3); the output starts
//!   where the content started, facing the same way; then planted feet are kept from sliding
//!   with the decoder's own foot contacts: the root's ground path is corrected ([`feet`]), then
//!   each planted ankle is held on one spot by two-bone leg IK ([`legs`]).
//! - **Randomness.** Everything is drawn from `seed` on the Rust side (ChaCha8), so the same
//!   request gives the same bits natively and in wasm.

pub mod error;
pub mod feet;
pub mod legs;
pub mod manifest;
pub mod parts;
pub mod pipeline;
pub mod source;
pub mod weights;

pub use error::StylizeError;
pub use manifest::{LabelCodes, Manifest, ModelEntry, NeutralCode, StageRecord};
pub use parts::{BodyPart, PartRequests, stylize_parts, stylize_parts_async};
pub use pipeline::{
    MAX_FRAMES, infer_label, infer_label_async, pad_features, padded_frames, style_code_of, style_code_of_async,
    stylize, stylize_async,
};
pub use source::{
    DEFAULT_GUIDANCE, DEFAULT_STRENGTH, DEFAULT_TEMPERATURE, MAX_GUIDANCE, MAX_MIX_DEPTH, MAX_SAMPLES, MAX_STRENGTH,
    MAX_TEMPERATURE, Request, StyleSource,
};
pub use weights::{Setting, WeightFiles, Weights};
