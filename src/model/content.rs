//! Content encoder `E_c`: motion latent (1/4 rate) → content code (1/8 rate). Instance norm
//! removes per-clip channel statistics, i.e. global style.
//!
//! 512→768 (k3 s2, IN, LeakyReLU) → 768→512 (k1, IN, LeakyReLU) → 512→512 (k1, linear).

use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{ConvLayer, ConvLayerConfig, from_cbt, to_cbt};

#[derive(Module, Debug)]
pub struct ContentEncoder {
    pub down: ConvLayer,
    pub mid: ConvLayer,
    pub out: ConvLayer,
}

impl ContentEncoder {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self {
            down: ConvLayerConfig::new(cfg.latent_dim, cfg.content_hidden, 3).down().norm().init(device),
            mid: ConvLayerConfig::new(cfg.content_hidden, cfg.content_dim, 1).norm().init(device),
            out: ConvLayerConfig::new(cfg.content_dim, cfg.content_dim, 1).linear_out().init(device),
        }
    }

    /// `z`: `[B, D_z, L]` (L even) → content code `[B, D_c, L/2]`.
    pub fn forward(&self, z: Tensor<3>) -> Tensor<3> {
        from_cbt(self.out.forward_cbt(self.mid.forward_cbt(self.down.forward_cbt(to_cbt(z)))))
    }
}
