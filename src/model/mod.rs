//! The networks of "Generative Human Motion Stylization in Latent Space" (Guo et al., ICLR 2024)
//! in Burn 0.22: architecture, seeded inference and compact f16 weights — what the wasm build
//! ships. Their losses and training steps are [`crate::train`]'s (native only).
//!
//! Layout of every sequence tensor between networks: `[batch, channels, time]` (inside a network
//! the layers work on `[channels, batch, time]`: [`layers::to_cbt`]). Frame counts `T` are multiples of 8:
//! motion latent at `T/4` ([`autoencoder`]), content code at `T/8` ([`content`]), one global style
//! code per clip ([`style`]), recombined by the AdaIN [`generator`] into a latent at `T/4`.
//!
//! Stages (as the paper): 1. motion autoencoder + global motion [`regressor`] on all data;
//! 2. the [`Stylizer`] (content encoder, style encoder, generator) on frozen latents. Inference
//! without autodiff, every input checked: [`Model`].
//!
//! Burn 0.22 notes: tensors are `Tensor<D>` (no backend type parameter); the backend is the
//! runtime [`Device`](burn::tensor::Device) (`Device::flex()`, `Device::ndarray()` with the
//! `ndarray` feature; wgpu and CUDA by name through [`device::open`]); `device.autodiff()` makes a
//! training device; `module.valid()` gives the inference copy (no autodiff, dropout off).

pub mod autoencoder;
pub mod classifier;
pub mod config;
pub mod content;
pub mod conv;
pub mod cpu_conv;
pub mod device;
pub mod generator;
pub mod init;
pub mod layers;
pub mod parts;
pub mod regressor;
pub mod rng;
pub mod style;
pub mod stylizer;
pub mod weights;

pub use autoencoder::{MotionAutoencoder, MotionDecoder, MotionEncoder};
pub use classifier::StyleClassifier;
pub use config::ModelConfig;
pub use content::ContentEncoder;
pub use generator::Generator;
pub use regressor::GlobalRegressor;
pub use rng::NoiseRng;
pub use style::{StyleDistribution, StyleEncoder};
pub use stylizer::{Model, MotionModel, StyleCode, StyleSampling, Stylizer, check_features};

/// Errors of the model API (bad shapes or labels, bad weight bytes). Nothing here panics on user
/// input.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ModelError {
    /// Clip lengths must be positive multiples of 8 frames (latent at 1/4, content at 1/8).
    #[error("clip length {frames} frames is not a positive multiple of {multiple}")]
    FrameCount { frames: usize, multiple: usize },
    /// A latent length must be a positive multiple of 2 (content code at half the latent rate).
    #[error("latent length {len} is not a positive multiple of 2")]
    LatentLength { len: usize },
    /// A tensor has the wrong number of channels.
    #[error("{what}: expected {expected} channels, got {got}")]
    Channels { what: &'static str, expected: usize, got: usize },
    /// Two tensors that go together disagree on the batch size.
    #[error("{what}: batch size {got}, expected {expected}")]
    BatchSize { what: &'static str, expected: usize, got: usize },
    /// A style label is missing (supervised model), given to an unsupervised model, or out of
    /// range.
    #[error("style label: {0}")]
    Label(String),
    /// Weight bytes could not be written or read.
    #[error("weights: {0}")]
    Weights(String),
    /// The style encoder is needed (motion-based stylization, label inference) but its weights
    /// are not loaded yet (format 3 keeps it in a file of its own, fetched when first needed).
    #[error("the style encoder of the {setting} model is not loaded")]
    StyleEncoderNotLoaded { setting: &'static str },
}
