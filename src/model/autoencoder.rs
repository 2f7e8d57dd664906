//! Motion autoencoder: 256-D poses (contacts dropped) ↔ motion latent at 1/4 of the frame rate,
//! decoded back to all 260 feature dims.
//!
//! Encoder: 256→384 (k3 s2, dropout 0.2) → 384→512 (k3 s2, dropout 0.2) → 512→512 (k1, linear);
//! VAE variant: the last layer gives 2×512 = mean and log-variance.
//! Decoder: 512→512 (k3) → [×2, k3] 512→512 → [×2, k3] 512→384 → 384→260 (k1, linear).

use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{ConvLayer, ConvLayerConfig, from_cbt, to_cbt};
use crate::features::{DIM, MODEL_DIM};

/// What the motion encoder gives. For the plain AE `logvar` is `None` and `mean` is the latent.
#[derive(Clone, Debug)]
pub struct LatentDistribution {
    /// `[B, D_z, T/4]`: the latent (AE) or its mean (VAE).
    pub mean: Tensor<3>,
    /// `[B, D_z, T/4]` log-variance, VAE only.
    pub logvar: Option<Tensor<3>>,
}

/// Motion encoder `E`.
#[derive(Module, Debug)]
pub struct MotionEncoder {
    pub down1: ConvLayer,
    pub down2: ConvLayer,
    pub out: ConvLayer,
    pub latent_dim: usize,
    pub vae: bool,
}

impl MotionEncoder {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        let out_dim = if cfg.vae { 2 * cfg.latent_dim } else { cfg.latent_dim };
        Self {
            down1: ConvLayerConfig::new(MODEL_DIM, cfg.ae_hidden, 3).down().dropout(cfg.dropout).init(device),
            down2: ConvLayerConfig::new(cfg.ae_hidden, cfg.ae_mid, 3).down().dropout(cfg.dropout).init(device),
            out: ConvLayerConfig::new(cfg.ae_mid, out_dim, 1).linear_out().init(device),
            latent_dim: cfg.latent_dim,
            vae: cfg.vae,
        }
    }

    /// `x`: `[B, 256, T]` (T even twice over, i.e. a multiple of 4) → latent distribution at T/4.
    pub fn forward(&self, x: Tensor<3>) -> LatentDistribution {
        let h = from_cbt(self.out.forward_cbt(self.down2.forward_cbt(self.down1.forward_cbt(to_cbt(x)))));
        if self.vae {
            let d = self.latent_dim;
            LatentDistribution { mean: h.clone().narrow(1, 0, d), logvar: Some(h.narrow(1, d, d)) }
        } else {
            LatentDistribution { mean: h, logvar: None }
        }
    }
}

/// Motion decoder `D`.
#[derive(Module, Debug)]
pub struct MotionDecoder {
    pub first: ConvLayer,
    pub up1: ConvLayer,
    pub up2: ConvLayer,
    pub out: ConvLayer,
}

impl MotionDecoder {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self {
            first: ConvLayerConfig::new(cfg.latent_dim, cfg.latent_dim, 3).init(device),
            up1: ConvLayerConfig::new(cfg.latent_dim, cfg.ae_mid, 3).up().init(device),
            up2: ConvLayerConfig::new(cfg.ae_mid, cfg.ae_hidden, 3).up().init(device),
            out: ConvLayerConfig::new(cfg.ae_hidden, DIM, 1).linear_out().init(device),
        }
    }

    /// `z`: `[B, D_z, L]` → features `[B, 260, 4L]`.
    pub fn forward(&self, z: Tensor<3>) -> Tensor<3> {
        let h = self.up2.forward_cbt(self.up1.forward_cbt(self.first.forward_cbt(to_cbt(z))));
        from_cbt(self.out.forward_cbt(h))
    }
}

/// Encoder and decoder together.
#[derive(Module, Debug)]
pub struct MotionAutoencoder {
    pub encoder: MotionEncoder,
    pub decoder: MotionDecoder,
}

impl MotionAutoencoder {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self { encoder: MotionEncoder::new(cfg, device), decoder: MotionDecoder::new(cfg, device) }
    }
}

/// The autoencoder's input: the first 256 feature dims (contacts dropped). `[B, 260, T]` →
/// `[B, 256, T]`.
pub fn ae_input(features: Tensor<3>) -> Tensor<3> {
    features.narrow(1, 0, MODEL_DIM)
}
