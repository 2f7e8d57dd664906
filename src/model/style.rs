//! Style encoder `E_s`: motion latent (+ one-hot label when supervised) → diagonal Gaussian
//! `N(μ, σ²)` of a global 512-D style code.
//!
//! 512→768 (k3 s2) → [concat the one-hot label tiled over time] → 768+S→768 (k3 s2) →
//! 768→512 (k3 s2) → global average pool → 512→1024 (k1, linear) = [μ ; log σ²].
//! Every conv but the last has LeakyReLU 0.2 and reflection padding.

use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{ConvLayer, ConvLayerConfig, tile_time_cbt, to_cbt};

/// A diagonal Gaussian over style codes, `[B, style_dim]` each.
#[derive(Clone, Debug)]
pub struct StyleDistribution {
    pub mean: Tensor<2>,
    pub logvar: Tensor<2>,
}

impl StyleDistribution {
    /// Reparameterised sample `μ + exp(½ log σ²) · ε` with the given noise `ε` (`[B, style_dim]`).
    pub fn sample_with(&self, eps: Tensor<2>) -> Tensor<2> {
        self.mean.clone() + (self.logvar.clone() * 0.5).exp() * eps
    }

    /// The same distribution with its graph cut (no gradient flows back through it).
    pub fn detach(&self) -> Self {
        Self { mean: self.mean.clone().detach(), logvar: self.logvar.clone().detach() }
    }

    /// Rows picked by `indices` (a permutation of the batch, say).
    pub fn select(&self, indices: Tensor<1, Int>) -> Self {
        Self { mean: self.mean.clone().select(0, indices.clone()), logvar: self.logvar.clone().select(0, indices) }
    }
}

#[derive(Module, Debug)]
pub struct StyleEncoder {
    pub down1: ConvLayer,
    pub down2: ConvLayer,
    pub down3: ConvLayer,
    pub out: ConvLayer,
    pub label_dim: usize,
    pub style_dim: usize,
}

impl StyleEncoder {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        let [h0, h1] = cfg.style_hidden;
        Self {
            down1: ConvLayerConfig::new(cfg.latent_dim, h0, 3).down().init(device),
            down2: ConvLayerConfig::new(h0 + cfg.label_dim(), h1, 3).down().init(device),
            down3: ConvLayerConfig::new(h1, cfg.style_dim, 3).down().init(device),
            out: ConvLayerConfig::new(cfg.style_dim, 2 * cfg.style_dim, 1).linear_out().init(device),
            label_dim: cfg.label_dim(),
            style_dim: cfg.style_dim,
        }
    }

    /// `z`: `[B, D_z, L]`; `label`: one-hot `[B, S]`, required iff the encoder is supervised
    /// (callers check; see [`crate::model::Model`]).
    pub fn forward(&self, z: Tensor<3>, label: Option<Tensor<2>>) -> StyleDistribution {
        let h = self.down1.forward_cbt(to_cbt(z));
        let h = match label {
            Some(label) if self.label_dim > 0 => {
                let len = h.dims()[2];
                Tensor::cat(vec![h, tile_time_cbt(label, len)], 0)
            }
            None if self.label_dim > 0 => panic!("the supervised style encoder needs a style label"),
            _ => h,
        };
        let h = self.down3.forward_cbt(self.down2.forward_cbt(h));
        // Global average pool over time, then the k1 conv on the single remaining step.
        let g = self.out.forward_cbt(h.mean_dim(2));
        let [c, b, _] = g.dims();
        let g = g.reshape([c, b]).swap_dims(0, 1);
        let d = self.style_dim;
        StyleDistribution { mean: g.clone().narrow(1, 0, d), logvar: g.narrow(1, d, d) }
    }
}
