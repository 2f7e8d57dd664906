//! Style classifier (evaluation only: style accuracy and style FID use its features).
//!
//! Strided k3 convs (reflection pad, LeakyReLU) 256→512→768→512→512 (T → T/16), global average
//! pool, k1 conv 512→512 (linear) = the feature, L2-normalised (`v / sqrt(Σv² + 1e-8)`), then a
//! bias-free linear layer to the style classes.

use burn::nn::{Initializer, Linear, LinearConfig};
use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{ConvLayer, ConvLayerConfig, to_cbt};
use crate::features::MODEL_DIM;

#[derive(Module, Debug)]
pub struct StyleClassifier {
    pub down1: ConvLayer,
    pub down2: ConvLayer,
    pub down3: ConvLayer,
    pub down4: ConvLayer,
    pub feature: ConvLayer,
    pub output: Linear,
}

/// The classifier's outputs.
#[derive(Clone, Debug)]
pub struct ClassifierOutput {
    /// `[B, feature_dim]`, unit L2 norm per row.
    pub feature: Tensor<2>,
    /// `[B, num_styles]` unnormalised class scores.
    pub logits: Tensor<2>,
}

impl StyleClassifier {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        let [c0, c1, c2, c3] = cfg.classifier_hidden;
        Self {
            down1: ConvLayerConfig::new(MODEL_DIM, c0, 3).down().init(device),
            down2: ConvLayerConfig::new(c0, c1, 3).down().init(device),
            down3: ConvLayerConfig::new(c1, c2, 3).down().init(device),
            down4: ConvLayerConfig::new(c2, c3, 3).down().init(device),
            feature: ConvLayerConfig::new(c3, c3, 1).linear_out().init(device),
            output: LinearConfig::new(c3, cfg.num_styles.max(1))
                .with_bias(false)
                .with_initializer(Initializer::XavierNormal { gain: 1.0 })
                .init(device),
        }
    }

    /// `x`: `[B, 256, T]` (features without contacts, T a multiple of 16 for exact halvings).
    pub fn forward(&self, x: Tensor<3>) -> ClassifierOutput {
        let h = self.down2.forward_cbt(self.down1.forward_cbt(to_cbt(x)));
        let h = self.down4.forward_cbt(self.down3.forward_cbt(h));
        let g = self.feature.forward_cbt(h.mean_dim(2));
        let [c, b, _] = g.dims();
        let g = g.reshape([c, b]).swap_dims(0, 1);
        let norm = (g.clone().square().sum_dim(1) + 1e-8).sqrt();
        let feature = g / norm;
        let logits = self.output.forward(feature.clone());
        ClassifierOutput { feature, logits }
    }
}
