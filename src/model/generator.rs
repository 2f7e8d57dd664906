//! Generator `G`: content code (1/8 rate) + style code (+ one-hot label when supervised) → motion
//! latent (1/4 rate).
//!
//! Three style blocks, each conv k3 (zero pad) → LeakyReLU 0.2 → AdaIN:
//! 512→768, 768→1024, then nearest ×2 and 1024→768; then 768→512 (k1, linear).
//! Every AdaIN has its own linear layer on `[style code ; one-hot label]`. With
//! [`ModelConfig::content_posture`], a linear map (no bias) of the content code's posture channels
//! is added to the output latent at every step: the content's posture past every AdaIN.

use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{AdaIn, ConvLayer, ConvLayerConfig, from_cbt, to_cbt};
use burn::nn::{Linear, LinearConfig};

/// conv k3 → LeakyReLU → AdaIN (the reference's `StyleConv1dLayer`).
#[derive(Module, Debug)]
pub struct StyleBlock {
    pub conv: ConvLayer,
    pub adain: AdaIn,
}

impl StyleBlock {
    fn new(channels_in: usize, channels_out: usize, cond_dim: usize, upsample: bool, device: &Device) -> Self {
        let conv = ConvLayerConfig::new(channels_in, channels_out, 3).zero_padded();
        let conv = if upsample { conv.up() } else { conv };
        Self { conv: conv.init(device), adain: AdaIn::new(channels_out, cond_dim, device) }
    }

    pub fn forward(&self, x: Tensor<3>, cond: Tensor<2>) -> Tensor<3> {
        from_cbt(self.forward_cbt(to_cbt(x), cond))
    }

    /// The same on the batch-inner layout `[C, B, T]` (see [`to_cbt`]).
    pub fn forward_cbt(&self, x: Tensor<3>, cond: Tensor<2>) -> Tensor<3> {
        self.adain.forward_cbt(self.conv.forward_cbt(x), cond)
    }
}

#[derive(Module, Debug)]
pub struct Generator {
    pub block1: StyleBlock,
    pub block2: StyleBlock,
    pub block3: StyleBlock,
    pub out: ConvLayer,
    /// `[D_z, D_z]` on the content's posture (see the module docs); `None` without it.
    pub posture: Option<Linear>,
    pub content_dim: usize,
    pub label_dim: usize,
}

impl Generator {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        let cond = cfg.style_dim + cfg.label_dim();
        let [g0, g1, g2] = cfg.generator_hidden;
        Self {
            block1: StyleBlock::new(cfg.content_dim, g0, cond, false, device),
            block2: StyleBlock::new(g0, g1, cond, false, device),
            block3: StyleBlock::new(g1, g2, cond, true, device),
            out: ConvLayerConfig::new(g2, cfg.latent_dim, 1).linear_out().init(device),
            posture: cfg
                .content_posture
                .then(|| LinearConfig::new(cfg.latent_dim, cfg.latent_dim).with_bias(false).init(device)),
            content_dim: cfg.content_dim,
            label_dim: cfg.label_dim(),
        }
    }

    /// `content`: `[B, D_c, L]`, `style`: `[B, style_dim]`, `label`: one-hot `[B, S]` (required
    /// iff supervised) → latent `[B, D_z, 2L]`.
    pub fn forward(&self, content: Tensor<3>, style: Tensor<2>, label: Option<Tensor<2>>) -> Tensor<3> {
        let cond = match label {
            Some(label) if self.label_dim > 0 => Tensor::cat(vec![style, label], 1),
            None if self.label_dim > 0 => panic!("the supervised generator needs a style label"),
            _ => style,
        };
        let (content, posture) = match &self.posture {
            Some(linear) => {
                let [b, c, _] = content.dims();
                let posture = content.clone().narrow(1, self.content_dim, c - self.content_dim).narrow(2, 0, 1);
                let posture = linear.forward(posture.reshape([b, c - self.content_dim]));
                (content.narrow(1, 0, self.content_dim), Some(posture.unsqueeze_dim::<3>(2)))
            }
            None => (content, None),
        };
        let x = self.block1.forward_cbt(to_cbt(content), cond.clone());
        let x = self.block2.forward_cbt(x, cond.clone());
        let x = self.block3.forward_cbt(x, cond);
        let out = from_cbt(self.out.forward_cbt(x));
        match posture {
            Some(p) => out + p,
            None => out,
        }
    }
}
