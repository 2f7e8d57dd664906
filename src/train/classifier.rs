//! The `classifier` stage: the evaluation's style classifier ([`ClassifierTrainer`]), trained on
//! the training takes only (style-balanced windows, cross-entropy), evaluated on whole held-out
//! takes.

use burn::module::Module;
use burn::optim::{GradientsParams, ModuleOptimizer};
use burn::prelude::*;

use super::data::TrainData;
use super::losses::cross_entropy;
use super::optim::{adam, clip_grad_norm, optimizers_from_bytes, optimizers_to_bytes, read_scalars};
use super::rundir::{load_module, module_bytes};
use super::sampler::{SamplerRng, batch_tensor};
use super::settings::TrainConfig;
use super::trainer::{Trainer, step_report};
use crate::eval::classify::Judge;
use crate::model::autoencoder::ae_input;
use crate::model::init::seeded_xavier;
use crate::model::weights::save_classifier;
use crate::model::{ModelConfig, ModelError, StyleClassifier, check_features};

/// Held-out metrics (`eval.csv`): accuracy over whole held-out takes, its mean over styles
/// (every style counts the same), and the mean cross-entropy.
pub const METRICS: [&str; 3] = ["accuracy", "balanced_accuracy", "cross_entropy"];
/// The f16 bundle written beside each checkpoint: what `eval --classifier` reads.
pub const BUNDLE: &str = "classifier.bin";

step_report! {
    /// Losses of one classifier step (before the update).
    pub struct ClassifierStepReport {
        /// Cross-entropy.
        pub loss,
        /// Fraction of the batch classified correctly.
        pub accuracy,
        pub grad_norm,
    }
}

/// The style classifier of the evaluation (trained on the training takes only), with the same
/// Adam and gradient clipping as the other stages.
pub struct ClassifierTrainer {
    pub config: ModelConfig,
    pub train: TrainConfig,
    /// On the autodiff device.
    pub classifier: StyleClassifier,
    optim: ModuleOptimizer,
    device: Device,
}

impl ClassifierTrainer {
    /// A fresh classifier on `device.autodiff()`, weights from `seed`.
    pub fn new(config: ModelConfig, train: TrainConfig, device: &Device, seed: u64) -> Self {
        let device = device.clone().autodiff();
        device.seed(seed);
        let classifier = seeded_xavier(StyleClassifier::new(&config, &device), seed);
        Self { config, train, classifier, optim: adam(), device }
    }

    /// The training device (autodiff).
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// One Adam step on normalised features `[B, 260, T]` and one label per row.
    pub fn step(&mut self, features: Tensor<3>, labels: &[usize]) -> Result<ClassifierStepReport, ModelError> {
        check_features("pose features", &features)?;
        let [b, _, _] = features.dims();
        if labels.len() != b {
            return Err(ModelError::BatchSize { what: "style labels", expected: b, got: labels.len() });
        }
        if let Some(&bad) = labels.iter().find(|&&l| l >= self.config.num_styles) {
            return Err(ModelError::Label(format!("label {bad} out of range {}", self.config.num_styles)));
        }
        let x = ae_input(features.to_device(&self.device).autodiff());
        let logits = self.classifier.forward(x).logits;
        let loss = cross_entropy(logits.clone(), labels);

        let truth: Tensor<2, Int> = Tensor::from_data(
            TensorData::new(labels.iter().map(|&l| l as i64).collect::<Vec<_>>(), [b, 1]),
            &self.device,
        );
        let accuracy = logits.detach().argmax(1).equal(truth).float().mean();

        let mut grads = loss.clone().backward();
        let mut g = GradientsParams::from_module(&mut grads, &self.classifier);
        let grad_norm = clip_grad_norm(&self.classifier, &mut g, self.train.grad_clip_norm);
        let [loss, accuracy] = read_scalars([loss, accuracy]);
        self.classifier = self.optim.step(self.train.lr, self.classifier.clone(), g);
        Ok(ClassifierStepReport { loss, accuracy, grad_norm })
    }

    fn judge(&self, data: &TrainData) -> Judge {
        let net = self.classifier.clone().valid();
        Judge::new(self.config.clone(), net, data.norm.clone(), data.device.clone())
    }
}

impl Trainer for ClassifierTrainer {
    type Report = ClassifierStepReport;
    const SHOWN: &'static [(&'static str, &'static str)] = &[("loss", "loss"), ("acc", "accuracy")];
    const METRICS: &'static [&'static str] = &METRICS;

    fn train_step(&mut self, data: &TrainData, rng: &mut SamplerRng) -> anyhow::Result<ClassifierStepReport> {
        // Style-balanced: a style uniformly, a clip of it, one window of that clip.
        let windows: Vec<_> = (0..data.batch).map(|_| data.sampler.pair(rng)).collect();
        let labels: Vec<usize> = windows.iter().map(|w| w.2).collect();
        let first: Vec<_> = windows.iter().map(|w| w.0).collect();
        debug_assert!(first.iter().zip(&labels).all(|(w, l)| data.labels[w.clip] == *l));
        let x = batch_tensor(&data.clips, &first, data.window, &data.device);
        Ok(self.step(x, &labels)?)
    }

    fn evaluate(&self, data: &TrainData) -> Vec<f64> {
        let judge = self.judge(data);
        let (mut correct, mut ce) = (0usize, 0f64);
        let mut per_style = vec![(0usize, 0usize); self.config.num_styles];
        for (f, label) in &data.heldout_takes {
            let j = judge.judge_normalized(f);
            let ok = j.predicted == *label;
            correct += usize::from(ok);
            per_style[*label].0 += usize::from(ok);
            per_style[*label].1 += 1;
            ce -= f64::from(j.probabilities.get(*label).copied().unwrap_or(0.0).max(1e-12)).ln();
        }
        let total = data.heldout_takes.len().max(1) as f64;
        let recalls: Vec<f64> = per_style.iter().filter(|(_, n)| *n > 0).map(|(c, n)| *c as f64 / *n as f64).collect();
        let balanced = recalls.iter().sum::<f64>() / recalls.len().max(1) as f64;
        vec![correct as f64 / total, balanced, ce / total]
    }

    fn learning_rates(&self) -> Vec<(&'static str, f64)> {
        vec![("lr", self.train.lr)]
    }

    fn weights(&self) -> anyhow::Result<Vec<u8>> {
        module_bytes(self.classifier.clone().valid())
    }

    fn load_weights(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        self.classifier = load_module(StyleClassifier::new(&self.config, &self.device), bytes)?;
        Ok(())
    }

    fn optimizer_state(&self) -> Result<Vec<u8>, ModelError> {
        optimizers_to_bytes(&[&self.optim])
    }

    fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        [self.optim] = optimizers_from_bytes(bytes)?;
        Ok(())
    }

    fn artifacts(&self) -> anyhow::Result<Vec<(&'static str, Vec<u8>)>> {
        let bytes = save_classifier(&self.config, self.classifier.clone().valid())?;
        Ok(vec![(BUNDLE, bytes)])
    }
}
