//! Global motion regressor: predicts the root's ground velocity (x, z, features 1..3) from the
//! local motion, so a stylized motion gets a pace that matches its new style.
//!
//! Input (254 dims, the reference's `cat([M[..., 0:1], M[..., 3:]])[..., :-4]`): the root angular
//! velocity (feature 0), then features 3..256 (root height, local positions, 6D rotations, local
//! velocities); i.e. everything but the root ground velocity and the foot contacts. At inference
//! the angular velocity comes from the content motion.
//!
//! Convs k3 (reflection pad, LeakyReLU) 254→512→256→128, then 128→2 (k1, linear, no bias).

use burn::prelude::*;

use super::config::ModelConfig;
use super::layers::{ConvLayer, ConvLayerConfig, channels, from_cbt, to_cbt};
use crate::features::{MODEL_DIM, REGRESSOR_DIM, ROOT_ANG_VEL, ROOT_HEIGHT, ROOT_LIN_VEL};

#[derive(Module, Debug)]
pub struct GlobalRegressor {
    pub conv1: ConvLayer,
    pub conv2: ConvLayer,
    pub conv3: ConvLayer,
    pub out: ConvLayer,
}

impl GlobalRegressor {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        let [r0, r1, r2] = cfg.regressor_hidden;
        Self {
            conv1: ConvLayerConfig::new(REGRESSOR_DIM, r0, 3).init(device),
            conv2: ConvLayerConfig::new(r0, r1, 3).init(device),
            conv3: ConvLayerConfig::new(r1, r2, 3).init(device),
            out: ConvLayerConfig::new(r2, ROOT_LIN_VEL.len(), 1).linear_out().no_bias().init(device),
        }
    }

    /// `x`: `[B, 254, T]` (see [`regressor_input`]) → root ground velocity `[B, 2, T]`.
    pub fn forward(&self, x: Tensor<3>) -> Tensor<3> {
        let h = self.conv3.forward_cbt(self.conv2.forward_cbt(self.conv1.forward_cbt(to_cbt(x))));
        from_cbt(self.out.forward_cbt(h))
    }
}

/// The regressor's input from full features `[B, 260, T]`: feature 0 and features 3..256.
pub fn regressor_input(features: Tensor<3>) -> Tensor<3> {
    regressor_input_from(channels(features.clone(), ROOT_ANG_VEL), features)
}

/// The regressor's input with the root angular velocity `[B, 1, T]` taken from elsewhere (the
/// content motion at inference) and the rest from `features` `[B, 260, T]`.
pub fn regressor_input_from(angular_velocity: Tensor<3>, features: Tensor<3>) -> Tensor<3> {
    Tensor::cat(vec![angular_velocity, channels(features, ROOT_HEIGHT.start..MODEL_DIM)], 1)
}

/// The regressor's target from full features: the root ground velocity, features 1..3.
pub fn regressor_target(features: Tensor<3>) -> Tensor<3> {
    channels(features, ROOT_LIN_VEL)
}
