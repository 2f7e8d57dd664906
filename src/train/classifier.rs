//! The `classifier` stage: the evaluation's style classifier, trained on the training takes
//! only (style-balanced windows, cross-entropy), evaluated on whole held-out takes.

use burn::module::Module;
use burn::prelude::*;

use super::sampler::{SamplerRng, WindowSampler, batch_tensor};
use super::{Runner, module_bytes};
use crate::dataset::corpus::Clip;
use crate::eval::classify::Judge;
use crate::features::{Features, NormStats};
use crate::model::train::ClassifierTrainer;
use crate::model::weights::save_classifier;

/// Loss terms of a step (`loss.csv`).
pub const TERMS: [&str; 3] = ["loss", "accuracy", "grad_norm"];
/// Held-out metrics (`eval.csv`): accuracy over whole held-out takes, its mean over styles
/// (every style counts the same), and the mean cross-entropy.
pub const METRICS: [&str; 3] = ["accuracy", "balanced_accuracy", "cross_entropy"];
/// The f16 bundle written beside each checkpoint: what `eval --classifier` reads.
pub const BUNDLE: &str = "classifier.bin";

pub(super) struct ClassifierRunner {
    pub trainer: ClassifierTrainer,
    pub clips: Vec<Features>,
    pub styles: Vec<usize>,
    pub sampler: WindowSampler,
    /// Whole held-out takes, normalised, with their labels.
    pub heldout: Vec<(Features, usize)>,
    pub norm: NormStats,
    pub batch: usize,
    pub window: usize,
    pub device: Device,
}

impl ClassifierRunner {
    /// Normalised whole held-out takes and their labels.
    pub fn heldout_takes(clips: &[Clip], norm: &NormStats) -> Vec<(Features, usize)> {
        clips
            .iter()
            .map(|c| {
                let mut f = c.features.clone();
                norm.normalize(&mut f);
                (f, c.style.index())
            })
            .collect()
    }

    fn judge(&self) -> Judge {
        let net = self.trainer.classifier.clone().valid();
        Judge::new(self.trainer.config.clone(), net, self.norm.clone(), self.device.clone())
    }
}

impl Runner for ClassifierRunner {
    fn terms(&self) -> &'static [&'static str] {
        &TERMS
    }

    fn shown(&self) -> Vec<(&'static str, usize)> {
        vec![("loss", 0), ("acc", 1)]
    }

    fn lrs(&self) -> Vec<(&'static str, f64)> {
        vec![("lr", self.trainer.train.lr)]
    }

    fn metrics(&self) -> &'static [&'static str] {
        &METRICS
    }

    fn step(&mut self, rng: &mut SamplerRng) -> anyhow::Result<Vec<f64>> {
        // Style-balanced: a style uniformly, a clip of it, one window of that clip.
        let windows: Vec<_> = (0..self.batch).map(|_| self.sampler.pair(rng)).collect();
        let labels: Vec<usize> = windows.iter().map(|w| w.2).collect();
        let first: Vec<_> = windows.iter().map(|w| w.0).collect();
        debug_assert!(first.iter().zip(&labels).all(|(w, l)| self.styles[w.clip] == *l));
        let x = batch_tensor(&self.clips, &first, self.window, &self.device);
        let r = self.trainer.step(x, &labels)?;
        Ok([r.loss, r.accuracy, r.grad_norm].map(f64::from).to_vec())
    }

    fn evaluate(&self) -> Vec<f64> {
        let judge = self.judge();
        let n = self.judge_styles();
        let (mut correct, mut ce) = (0usize, 0f64);
        let mut per_style = vec![(0usize, 0usize); n];
        for (f, label) in &self.heldout {
            let j = judge.judge_normalized(f);
            let ok = j.predicted == *label;
            correct += usize::from(ok);
            per_style[*label].0 += usize::from(ok);
            per_style[*label].1 += 1;
            ce -= f64::from(j.probabilities.get(*label).copied().unwrap_or(0.0).max(1e-12)).ln();
        }
        let total = self.heldout.len().max(1) as f64;
        let recalls: Vec<f64> = per_style.iter().filter(|(_, n)| *n > 0).map(|(c, n)| *c as f64 / *n as f64).collect();
        let balanced = recalls.iter().sum::<f64>() / recalls.len().max(1) as f64;
        vec![correct as f64 / total, balanced, ce / total]
    }

    fn weights(&self) -> anyhow::Result<Vec<u8>> {
        module_bytes(self.trainer.classifier.clone().valid())
    }

    fn optimizer_state(&self) -> anyhow::Result<Vec<u8>> {
        Ok(self.trainer.optimizer_state()?)
    }

    fn load_optimizer_state(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        Ok(self.trainer.load_optimizer_state(bytes)?)
    }

    fn artifacts(&self) -> anyhow::Result<Vec<(&'static str, Vec<u8>)>> {
        let bytes = save_classifier(&self.trainer.config, self.trainer.classifier.clone().valid())?;
        Ok(vec![(BUNDLE, bytes)])
    }
}

impl ClassifierRunner {
    fn judge_styles(&self) -> usize {
        self.trainer.config.num_styles
    }
}
