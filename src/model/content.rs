//! Content encoder `E_c`: motion latent (1/4 rate) → content code (1/8 rate). Instance norm
//! removes per-clip channel statistics, i.e. global style.
//!
//! 512→768 (k3 s2, IN, LeakyReLU) → 768→512 (k1, IN, LeakyReLU) → 512→512 (k1, linear).
//! With [`ModelConfig::content_posture`] the code also carries the latent's mean over time
//! (`latent_dim` channels, the same value at every step), which no instance norm sees.

use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{ConvLayer, ConvLayerConfig, from_cbt, to_cbt};

#[derive(Module, Debug)]
pub struct ContentEncoder {
    pub down: ConvLayer,
    pub mid: ConvLayer,
    pub out: ConvLayer,
    /// [`ModelConfig::content_posture`].
    pub posture: bool,
}

impl ContentEncoder {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self {
            down: ConvLayerConfig::new(cfg.latent_dim, cfg.content_hidden, 3).down().norm().init(device),
            mid: ConvLayerConfig::new(cfg.content_hidden, cfg.content_dim, 1).norm().init(device),
            out: ConvLayerConfig::new(cfg.content_dim, cfg.content_dim, 1).linear_out().init(device),
            posture: cfg.content_posture,
        }
    }

    /// `z`: `[B, D_z, L]` (L even) → content code `[B, D_c, L/2]` (`[B, D_c + D_z, L/2]` with the
    /// posture channels).
    pub fn forward(&self, z: Tensor<3>) -> Tensor<3> {
        let posture = self.posture.then(|| z.clone().mean_dim(2));
        let code = from_cbt(self.out.forward_cbt(self.mid.forward_cbt(self.down.forward_cbt(to_cbt(z)))));
        match posture {
            Some(p) => {
                let len = code.dims()[2];
                Tensor::cat(vec![code, p.repeat_dim(2, len)], 1)
            }
            None => code,
        }
    }
}
