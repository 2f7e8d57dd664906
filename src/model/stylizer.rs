//! The stylizer (the stage-2 networks as one module), the whole model, and the inference API
//! ([`Model`]): plain (non-autodiff) device, every shape and label checked with a typed error, all
//! randomness from a caller-owned seeded [`NoiseRng`] (bit-identical across runs and, by
//! construction, across native and wasm).

use burn::prelude::*;

use super::ModelError;
use super::autoencoder::{MotionAutoencoder, ae_input};
use super::config::{FRAME_MULTIPLE, ModelConfig};
use super::content::ContentEncoder;
use super::generator::Generator;
use super::init::seeded_xavier;
use super::layers::{channels as feature_slice, one_hot};
use super::regressor::{GlobalRegressor, regressor_input_from};
use super::rng::NoiseRng;
use super::style::{StyleDistribution, StyleEncoder};
use crate::features::{DIM, MODEL_DIM, ROOT_ANG_VEL, ROOT_HEIGHT};

/// The stylizer: content encoder, style encoder and generator, what the second training stage
/// trains (one per setting: supervised, unsupervised).
#[derive(Module, Debug)]
pub struct Stylizer {
    pub content_encoder: ContentEncoder,
    pub style_encoder: StyleEncoder,
    pub generator: Generator,
}

impl Stylizer {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self {
            content_encoder: ContentEncoder::new(cfg, device),
            style_encoder: StyleEncoder::new(cfg, device),
            generator: Generator::new(cfg, device),
        }
    }
}

/// Every network inference needs (the classifier is evaluation-only and kept apart).
#[derive(Module, Debug)]
pub struct MotionModel {
    pub autoencoder: MotionAutoencoder,
    pub stylizer: Stylizer,
    pub regressor: GlobalRegressor,
}

impl MotionModel {
    /// Inference only: the taps of the layers a stylization runs through computed once, see
    /// [`super::layers::ConvLayer::fold_for_inference`] — the upsampling layers' folded taps
    /// (decoder `up1`, `up2`, the generator block that upsamples) and the kernel-3, stride-1
    /// layers' split taps (decoder `first`, the other generator blocks, the regressor's three
    /// convolutions). Never on networks that are trained or get other weights afterwards.
    pub fn fold_for_inference(&mut self) {
        let decoder = &mut self.autoencoder.decoder;
        let generator = &mut self.stylizer.generator;
        let regressor = &mut self.regressor;
        for layer in [
            &mut decoder.first,
            &mut decoder.up1,
            &mut decoder.up2,
            &mut generator.block1.conv,
            &mut generator.block2.conv,
            &mut generator.block3.conv,
            &mut regressor.conv1,
            &mut regressor.conv2,
            &mut regressor.conv3,
        ] {
            layer.fold_for_inference();
        }
    }

    /// Networks with lazily initialised weights (drawn from Burn's shared generator at first
    /// use): the cheap template to load weights into. For reproducible weights use
    /// [`MotionModel::seeded`].
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self {
            autoencoder: MotionAutoencoder::new(cfg, device),
            stylizer: Stylizer::new(cfg, device),
            regressor: GlobalRegressor::new(cfg, device),
        }
    }

    /// Freshly initialised networks, every weight drawn from a generator seeded with `seed`
    /// ([`seeded_xavier`]).
    pub fn seeded(cfg: &ModelConfig, device: &Device, seed: u64) -> Self {
        seeded_xavier(Self::new(cfg, device), seed)
    }
}

/// How to turn a style posterior into a code.
#[derive(Debug)]
pub enum StyleSampling<'a> {
    /// The posterior mean (deterministic motion-based stylization).
    Mean,
    /// A sample `μ + σ ε` with `ε` from the given generator.
    Sample(&'a mut NoiseRng),
}

/// A style code per batch row, with the labels that go with it in a supervised model.
#[derive(Clone, Debug)]
pub struct StyleCode {
    /// `[B, style_dim]`.
    pub code: Tensor<2>,
    /// One label per row (supervised), `None` (unsupervised).
    pub labels: Option<Vec<usize>>,
}

/// The inference model of one setting: its networks with every input checked.
#[derive(Debug)]
pub struct Model {
    pub config: ModelConfig,
    pub nets: MotionModel,
    device: Device,
    /// Whether `nets.stylizer.style_encoder` holds trained weights: false for a format-3 model
    /// loaded without its style-encoder file ([`Model::without_style_encoder`]) until
    /// [`Model::set_style_encoder`]; every use of the style encoder checks it.
    style_encoder_loaded: bool,
}

fn channels(what: &'static str, got: usize, expected: usize) -> Result<(), ModelError> {
    if got == expected { Ok(()) } else { Err(ModelError::Channels { what, expected, got }) }
}

/// Checks a clip length: a positive multiple of 8 frames.
pub fn check_frames(frames: usize) -> Result<(), ModelError> {
    if frames == 0 || !frames.is_multiple_of(FRAME_MULTIPLE) {
        Err(ModelError::FrameCount { frames, multiple: FRAME_MULTIPLE })
    } else {
        Ok(())
    }
}

/// Checks training features: `[B, 260, T]` with `T` a positive multiple of 8.
pub fn check_features(what: &'static str, x: &Tensor<3>) -> Result<(), ModelError> {
    let [_, c, t] = x.dims();
    channels(what, c, DIM)?;
    check_frames(t)
}

impl Model {
    /// Wraps trained networks for inference: takes their validation copy (no autodiff, dropout
    /// off) on the device of their parameters.
    pub fn new(config: ModelConfig, nets: MotionModel) -> Self {
        let nets = nets.valid();
        let device = nets.devices().into_iter().next().unwrap_or_else(|| panic!("the model has no parameters"));
        Self { config, nets, device, style_encoder_loaded: true }
    }

    /// [`Model::new`] for networks whose style encoder is a placeholder (not trained weights):
    /// everything but the style encoder works; [`Model::style_distribution`] (motion-based
    /// styles, label inference) refuses until [`Model::set_style_encoder`].
    pub fn without_style_encoder(config: ModelConfig, nets: MotionModel) -> Self {
        Self { style_encoder_loaded: false, ..Self::new(config, nets) }
    }

    /// Puts trained style-encoder weights in (on this model's device).
    pub fn set_style_encoder(&mut self, style_encoder: StyleEncoder) {
        self.nets.stylizer.style_encoder = style_encoder.valid().to_device(&self.device);
        self.style_encoder_loaded = true;
    }

    /// Whether the style encoder's weights are loaded (see [`Model::without_style_encoder`]).
    pub fn has_style_encoder(&self) -> bool {
        self.style_encoder_loaded
    }

    /// Untrained networks on `device`, weights from `seed` (tests, benchmarks).
    pub fn seeded(config: ModelConfig, device: &Device, seed: u64) -> Self {
        let nets = MotionModel::seeded(&config, device, seed);
        Self::new(config, nets)
    }

    pub fn device(&self) -> &Device {
        &self.device
    }

    fn labels_tensor(&self, labels: Option<&[usize]>, batch: usize) -> Result<Option<Tensor<2>>, ModelError> {
        match (self.config.supervised, labels) {
            (false, None) => Ok(None),
            (false, Some(_)) => Err(ModelError::Label("the unsupervised model takes no style label".into())),
            (true, None) => Err(ModelError::Label("the supervised model needs a style label per clip".into())),
            (true, Some(labels)) => {
                if labels.len() != batch {
                    return Err(ModelError::BatchSize { what: "style labels", expected: batch, got: labels.len() });
                }
                if let Some(&bad) = labels.iter().find(|&&l| l >= self.config.num_styles) {
                    return Err(ModelError::Label(format!(
                        "label {bad} out of range (the model has {} styles)",
                        self.config.num_styles
                    )));
                }
                Ok(Some(one_hot(labels, self.config.num_styles, &self.device)))
            }
        }
    }

    /// Features `[B, 260, T]` (or the 256 without contacts) → motion latent `[B, D_z, T/4]`.
    /// `T` must be a positive multiple of 8. The VAE variant gives its posterior mean.
    pub fn encode(&self, features: Tensor<3>) -> Result<Tensor<3>, ModelError> {
        let [_, c, t] = features.dims();
        check_frames(t)?;
        let x = match c {
            DIM => ae_input(features),
            MODEL_DIM => features,
            _ => return Err(ModelError::Channels { what: "pose features", expected: DIM, got: c }),
        };
        Ok(self.nets.autoencoder.encoder.forward(x).mean)
    }

    /// Motion latent `[B, D_z, L]` (L even) → content code `[B, D_c, L/2]`.
    pub fn content(&self, latent: Tensor<3>) -> Result<Tensor<3>, ModelError> {
        let [_, c, l] = latent.dims();
        channels("motion latent", c, self.config.latent_dim)?;
        if l == 0 || !l.is_multiple_of(2) {
            return Err(ModelError::LatentLength { len: l });
        }
        Ok(self.nets.stylizer.content_encoder.forward(latent))
    }

    /// The style posterior of a motion latent `[B, D_z, L]`; `labels` (one per row) iff the model
    /// is supervised.
    pub fn style_distribution(
        &self,
        latent: Tensor<3>,
        labels: Option<&[usize]>,
    ) -> Result<StyleDistribution, ModelError> {
        if !self.style_encoder_loaded {
            let setting = if self.config.supervised { "supervised" } else { "unsupervised" };
            return Err(ModelError::StyleEncoderNotLoaded { setting });
        }
        let [b, c, l] = latent.dims();
        channels("motion latent", c, self.config.latent_dim)?;
        if l == 0 {
            return Err(ModelError::LatentLength { len: l });
        }
        let label = self.labels_tensor(labels, b)?;
        Ok(self.nets.stylizer.style_encoder.forward(latent, label))
    }

    /// Motion-based style: the posterior of the style motion's latent, its mean or a sample.
    pub fn style_from_motion(
        &self,
        latent: Tensor<3>,
        labels: Option<&[usize]>,
        sampling: StyleSampling<'_>,
    ) -> Result<StyleCode, ModelError> {
        let batch = latent.dims()[0];
        let dist = self.style_distribution(latent, labels)?;
        let code = match sampling {
            StyleSampling::Mean => dist.mean,
            StyleSampling::Sample(rng) => {
                let eps = rng.normal_tensor(batch, self.config.style_dim, &self.device);
                dist.sample_with(eps)
            }
        };
        Ok(StyleCode { code, labels: labels.map(<[usize]>::to_vec) })
    }

    /// Label-based style (supervised): a code sampled from the prior `N(0, I)` with the given
    /// label, one row per label.
    pub fn style_from_label(&self, labels: &[usize], rng: &mut NoiseRng) -> Result<StyleCode, ModelError> {
        if !self.config.supervised {
            return Err(ModelError::Label("label-based stylization needs a supervised model".into()));
        }
        self.labels_tensor(Some(labels), labels.len())?;
        let code = rng.normal_tensor(labels.len(), self.config.style_dim, &self.device);
        Ok(StyleCode { code, labels: Some(labels.to_vec()) })
    }

    /// Prior-based style (unsupervised): `batch` codes sampled from `N(0, I)`.
    pub fn style_from_prior(&self, batch: usize, rng: &mut NoiseRng) -> Result<StyleCode, ModelError> {
        if self.config.supervised {
            return Err(ModelError::Label("a supervised model needs a label; use style_from_label".into()));
        }
        Ok(StyleCode { code: rng.normal_tensor(batch, self.config.style_dim, &self.device), labels: None })
    }

    /// Content code `[B, D_c, L]` + style → motion latent `[B, D_z, 2L]`.
    pub fn generate(&self, content: Tensor<3>, style: &StyleCode) -> Result<Tensor<3>, ModelError> {
        let label = self.labels_tensor(style.labels.as_deref(), style.code.dims()[0])?;
        self.generate_with(content, style.code.clone(), label)
    }

    /// [`Model::generate`] with the labels as rows `[B, num_styles]` (one-hot, or mixes of two
    /// labels), given iff the model is supervised.
    pub fn generate_with(
        &self,
        content: Tensor<3>,
        code: Tensor<2>,
        label: Option<Tensor<2>>,
    ) -> Result<Tensor<3>, ModelError> {
        let [b, c, l] = content.dims();
        channels("content code", c, self.config.content_code_dim())?;
        if l == 0 {
            return Err(ModelError::LatentLength { len: 0 });
        }
        let [sb, sc] = code.dims();
        channels("style code", sc, self.config.style_dim)?;
        if sb != b {
            return Err(ModelError::BatchSize { what: "style code", expected: b, got: sb });
        }
        match (&label, self.config.supervised) {
            (None, false) => {}
            (Some(_), false) => return Err(ModelError::Label("the unsupervised model takes no style label".into())),
            (None, true) => return Err(ModelError::Label("the supervised model needs a style label per clip".into())),
            (Some(rows), true) => {
                let [lb, lc] = rows.dims();
                channels("style labels", lc, self.config.num_styles)?;
                if lb != b {
                    return Err(ModelError::BatchSize { what: "style labels", expected: b, got: lb });
                }
            }
        }
        Ok(self.nets.stylizer.generator.forward(content, code, label))
    }

    /// Motion latent `[B, D_z, L]` → features `[B, 260, 4L]` (normalised, as the training data).
    pub fn decode(&self, latent: Tensor<3>) -> Result<Tensor<3>, ModelError> {
        let [_, c, l] = latent.dims();
        channels("motion latent", c, self.config.latent_dim)?;
        if l == 0 {
            return Err(ModelError::LatentLength { len: 0 });
        }
        Ok(self.nets.autoencoder.decoder.forward(latent))
    }

    /// Root ground velocity `[B, 2, T]` predicted from `features` `[B, 260, T]`, with the root
    /// angular velocity taken from `angular_velocity` `[B, 1, T]` (the content motion's).
    pub fn root_velocity(&self, features: Tensor<3>, angular_velocity: Tensor<3>) -> Result<Tensor<3>, ModelError> {
        channels("pose features", features.dims()[1], DIM)?;
        channels("angular velocity", angular_velocity.dims()[1], 1)?;
        Ok(self.nets.regressor.forward(regressor_input_from(angular_velocity, features)))
    }

    /// The output features `[B, 260, T]` of decoded features `[B, 260, T]`: the root angular
    /// velocity `[B, 1, T]` given (the content's), the root ground velocity from the regressor,
    /// everything from the root height on the decoder's (paper §3.3, and the reference's generation
    /// script).
    pub fn with_root(&self, decoded: Tensor<3>, angular_velocity: Tensor<3>) -> Result<Tensor<3>, ModelError> {
        let velocity = self.root_velocity(decoded.clone(), angular_velocity.clone())?;
        Ok(Tensor::cat(vec![angular_velocity, velocity, feature_slice(decoded, ROOT_HEIGHT.start..DIM)], 1))
    }

    /// End to end: content motion features `[B, 260, T]` + a style → stylized features
    /// `[B, 260, T]`, with the content's root angular velocity ([`Model::with_root`]).
    pub fn stylize(&self, content_features: Tensor<3>, style: &StyleCode) -> Result<Tensor<3>, ModelError> {
        channels("pose features", content_features.dims()[1], DIM)?;
        let latent = self.encode(content_features.clone())?;
        let content = self.content(latent)?;
        let out = self.decode(self.generate(content, style)?)?;
        self.with_root(out, feature_slice(content_features, ROOT_ANG_VEL))
    }
}
