//! The evaluation's style classifier applied to whole motions: its L2-normalised feature (for
//! style FID and diversity) and its predicted style (for style accuracy).

use burn::prelude::*;
use burn::tensor::TensorData;

use crate::Motion;
use crate::features::{DIM, Features, NormStats, View, extract};
use crate::model::autoencoder::ae_input;
use crate::model::weights::load_classifier;
use crate::model::{ModelConfig, ModelError, StyleClassifier};
use crate::stylize::pad_features;

/// Clips are padded (reflection) to a multiple of this many frames: the classifier halves the
/// time axis four times.
pub const CLASSIFIER_MULTIPLE: usize = 16;

/// What the classifier says of one motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Judgement {
    /// Unit-length feature vector.
    pub feature: Vec<f32>,
    /// Index of the highest-scoring style.
    pub predicted: usize,
    /// Softmax probability of every style.
    pub probabilities: Vec<f32>,
}

/// A trained style classifier with the normalisation statistics its inputs need.
pub struct Judge {
    pub config: ModelConfig,
    net: StyleClassifier,
    norm: NormStats,
    device: Device,
}

impl Judge {
    /// A trained classifier (inference copy) on `device`.
    pub fn new(config: ModelConfig, net: StyleClassifier, norm: NormStats, device: Device) -> Judge {
        Judge { config, net, norm, device }
    }

    /// From [`save_classifier`](crate::model::weights::save_classifier) bytes, on the CPU.
    pub fn from_bytes(bytes: &[u8], norm: NormStats) -> Result<Judge, ModelError> {
        Self::from_bytes_on(&Device::flex(), bytes, norm)
    }

    /// [`Judge::from_bytes`] on a given device. The f16 bundle is read on flex (which casts it to
    /// f32) and the network then moved: not every device has f16 tensors.
    pub fn from_bytes_on(device: &Device, bytes: &[u8], norm: NormStats) -> Result<Judge, ModelError> {
        let (config, net) = load_classifier(bytes, &Device::flex())?;
        let net = if *device == Device::flex() { net } else { net.to_device(device) };
        Ok(Judge { config, net, norm, device: device.clone() })
    }

    pub fn num_styles(&self) -> usize {
        self.config.num_styles
    }

    /// Judges a motion (canonical rig; its features are extracted, normalised and padded).
    pub fn judge(&self, motion: &Motion) -> Judgement {
        let mut f = extract(motion);
        self.norm.normalize(&mut f);
        self.judge_normalized(&f)
    }

    /// Judges already normalised features.
    pub fn judge_normalized(&self, f: &Features) -> Judgement {
        let len = f.frames().div_ceil(CLASSIFIER_MULTIPLE).max(1) * CLASSIFIER_MULTIPLE;
        let padded = pad_features(f, len);
        let x = Tensor::<3>::from_data(
            TensorData::new(padded.view_channels_first(View::Full), [1, DIM, len]),
            &self.device,
        );
        let out = self.net.forward(ae_input(x));
        let feature = out.feature.into_data().try_to_vec::<f32>().unwrap_or_default();
        let logits = out.logits.into_data().try_to_vec::<f32>().unwrap_or_default();
        let max = logits.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let exp: Vec<f32> = logits.iter().map(|l| (l - max).exp()).collect();
        let sum: f32 = exp.iter().sum();
        let probabilities: Vec<f32> = exp.iter().map(|e| e / sum).collect();
        let predicted = logits
            .iter()
            .enumerate()
            .fold((0, f32::NEG_INFINITY), |best, (i, &l)| if l > best.1 { (i, l) } else { best })
            .0;
        Judgement { feature, predicted, probabilities }
    }
}
