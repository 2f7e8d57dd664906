//! Network sizes ([`ModelConfig`]), serialisable so a weights file can carry the exact architecture
//! it was trained with. The feature sizes the networks read and write are the feature layout's
//! ([`crate::features::layout`]).
//!
//! Defaults are the paper's sizes (as its authors' code fixes them); [`ModelConfig::scaled`]
//! shrinks every *internal* width by one factor (input/output sizes fixed by the 260-D pose
//! features stay as they are).

use serde::{Deserialize, Serialize};

/// Clip lengths (frames) must be a multiple of this: the latent is at 1/4 rate, the content code
/// at 1/8.
pub const FRAME_MULTIPLE: usize = 8;

/// Architecture of all networks. Widths are channel counts of 1-D convolutions over time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ModelConfig {
    /// Motion encoder first hidden width (paper 384); also the decoder's last hidden width.
    pub ae_hidden: usize,
    /// Motion encoder second hidden width (paper 512); also the decoder's first upsampling width.
    pub ae_mid: usize,
    /// Motion latent channels `D_z` (paper 512), at 1/4 of the frame rate.
    pub latent_dim: usize,
    /// Content encoder hidden width (paper 768).
    pub content_hidden: usize,
    /// Content code channels (paper 512), at 1/8 of the frame rate.
    pub content_dim: usize,
    /// Style encoder hidden widths (paper 768, 768).
    pub style_hidden: [usize; 2],
    /// Style code size (paper 512); the encoder's last layer gives twice this (mean, log-variance).
    pub style_dim: usize,
    /// Generator style-block widths (paper 768, 1024, 768); the last block upsamples ×2.
    pub generator_hidden: [usize; 3],
    /// Global motion regressor hidden widths (paper 512, 256, 128).
    pub regressor_hidden: [usize; 3],
    /// Style classifier strided-conv widths (paper 512, 768, 512, 512); the k1 feature layer keeps
    /// the last width (the 512-D evaluation feature).
    pub classifier_hidden: [usize; 4],
    /// Number of style labels of the dataset (Aberman et al.'s dataset used by the paper has 16).
    /// Also the classifier's number of classes.
    pub num_styles: usize,
    /// Supervised stylizer: the style encoder and the generator's AdaIN get the one-hot style
    /// label. Unsupervised: no label anywhere.
    pub supervised: bool,
    /// VAE motion autoencoder (encoder's last layer gives mean and log-variance); default: the
    /// plain AE with L1 sparsity/smoothness regularisation.
    pub vae: bool,
    /// Dropout probability in the motion encoder (paper 0.2).
    pub dropout: f64,
    /// The content's posture past AdaIN (not in the paper; issue 14): the content code carries the
    /// content latent's mean over time as `latent_dim` more channels (constant along time), and
    /// the generator adds a linear map of it to its output latent. Every instance norm and AdaIN
    /// removes per-channel means over time, so without it a content's held posture (a raised
    /// arm, a crouch) reaches the output only through the style code. Default: off (the paper;
    /// not written when off, so configs without it keep their bytes).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub content_posture: bool,
}

impl Default for ModelConfig {
    fn default() -> Self {
        Self {
            ae_hidden: 384,
            ae_mid: 512,
            latent_dim: 512,
            content_hidden: 768,
            content_dim: 512,
            style_hidden: [768, 768],
            style_dim: 512,
            generator_hidden: [768, 1024, 768],
            regressor_hidden: [512, 256, 128],
            classifier_hidden: [512, 768, 512, 512],
            num_styles: 16,
            supervised: true,
            vae: false,
            dropout: 0.2,
            content_posture: false,
        }
    }
}

fn scale(width: usize, factor: f64) -> usize {
    ((width as f64 * factor).round() as usize).max(1)
}

impl ModelConfig {
    /// The paper's sizes with every internal width (hidden layers, latent, content and style
    /// codes) multiplied by `width_factor` and rounded, at least 1. `scaled(0.5)` halves them.
    /// Inputs and outputs (256/260/254/2 feature dims, the number of styles) are unchanged.
    pub fn scaled(width_factor: f64) -> Self {
        Self::default().with_width_factor(width_factor)
    }

    /// This configuration with every internal width multiplied by `width_factor`.
    pub fn with_width_factor(mut self, f: f64) -> Self {
        self.ae_hidden = scale(self.ae_hidden, f);
        self.ae_mid = scale(self.ae_mid, f);
        self.latent_dim = scale(self.latent_dim, f);
        self.content_hidden = scale(self.content_hidden, f);
        self.content_dim = scale(self.content_dim, f);
        self.style_hidden = self.style_hidden.map(|w| scale(w, f));
        self.style_dim = scale(self.style_dim, f);
        self.generator_hidden = self.generator_hidden.map(|w| scale(w, f));
        self.regressor_hidden = self.regressor_hidden.map(|w| scale(w, f));
        self.classifier_hidden = self.classifier_hidden.map(|w| scale(w, f));
        self
    }

    /// Builder: number of style labels.
    pub fn with_num_styles(mut self, num_styles: usize) -> Self {
        self.num_styles = num_styles;
        self
    }

    /// Builder: supervised (labels) or unsupervised stylizer.
    pub fn with_supervised(mut self, supervised: bool) -> Self {
        self.supervised = supervised;
        self
    }

    /// Builder: VAE or plain AE motion autoencoder.
    pub fn with_vae(mut self, vae: bool) -> Self {
        self.vae = vae;
        self
    }

    /// [`ModelConfig::content_posture`].
    pub fn with_content_posture(mut self, on: bool) -> Self {
        self.content_posture = on;
        self
    }

    /// Channels of the content code: `content_dim`, plus `latent_dim` posture channels with
    /// [`ModelConfig::content_posture`].
    pub fn content_code_dim(&self) -> usize {
        self.content_dim + if self.content_posture { self.latent_dim } else { 0 }
    }

    /// Width of the one-hot label the stylizer networks take: `num_styles` when supervised,
    /// 0 otherwise.
    pub fn label_dim(&self) -> usize {
        if self.supervised { self.num_styles } else { 0 }
    }
}
