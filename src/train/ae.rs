//! Stage 1: the motion autoencoder and the global motion regressor ([`AeTrainer`]), trained side
//! by side on the same batches of windows drawn uniformly over every training window.

use burn::module::Module;
use burn::optim::ModuleOptimizer;
use burn::prelude::*;

use super::data::TrainData;
use super::eval;
use super::losses::{autoencoder_loss, autoencoder_noise, l1};
use super::optim::{adam, clip_grad_norm, optimizers_from_bytes, optimizers_to_bytes};
use super::parallel::{Replica, map_parallel, row_groups, sum_grads, weighted_terms};
use super::rundir::{load_module, module_bytes};
use super::sampler::{SamplerRng, batch_tensor};
use super::settings::TrainConfig;
use super::trainer::{PhaseTimes, Trainer, step_report};
use crate::model::init::seeded_xavier;
use crate::model::regressor::{regressor_input, regressor_target};
use crate::model::{GlobalRegressor, ModelConfig, ModelError, MotionAutoencoder, NoiseRng, check_features};
use std::time::Instant;

step_report! {
    /// Losses of one autoencoder + regressor step (before the update).
    pub struct AeStepReport {
        /// Autoencoder total loss.
        pub ae_loss,
        pub reconstruction,
        pub sparsity,
        pub smoothness,
        pub kl,
        /// Regressor mean absolute error.
        pub regressor_loss,
        /// Gradient norms before clipping.
        pub ae_grad_norm,
        pub regressor_grad_norm,
    }
}

/// Autoencoder + regressor: what an `ae` checkpoint holds.
#[derive(Module, Debug)]
pub struct AeNets {
    pub autoencoder: MotionAutoencoder,
    pub regressor: GlobalRegressor,
}

impl AeNets {
    /// Lazily initialised networks (a template to load weights into).
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self { autoencoder: MotionAutoencoder::new(cfg, device), regressor: GlobalRegressor::new(cfg, device) }
    }
}

/// Stage 1: the motion autoencoder and the global motion regressor, trained side by side on the
/// same batches (their parameters and losses are disjoint, so one backward pass serves both).
pub struct AeTrainer {
    pub config: ModelConfig,
    pub train: TrainConfig,
    /// On the autodiff device.
    pub autoencoder: MotionAutoencoder,
    pub regressor: GlobalRegressor,
    optim_ae: ModuleOptimizer,
    optim_regressor: ModuleOptimizer,
    noise: NoiseRng,
    device: Device,
    /// Time per phase of the steps, when measured.
    pub phases: Option<PhaseTimes>,
}

impl AeTrainer {
    /// Fresh networks on `device.autodiff()`, weights from `seed` ([`seeded_xavier`]); `seed`
    /// also seeds the VAE noise and the device's generator (dropout masks).
    pub fn new(config: ModelConfig, train: TrainConfig, device: &Device, seed: u64) -> Self {
        let device = device.clone().autodiff();
        device.seed(seed);
        let autoencoder = seeded_xavier(MotionAutoencoder::new(&config, &device), seed);
        let regressor = seeded_xavier(GlobalRegressor::new(&config, &device), seed.wrapping_add(1));
        Self {
            config,
            train,
            autoencoder,
            regressor,
            optim_ae: adam(),
            optim_regressor: adam(),
            noise: NoiseRng::new(seed ^ 0x5eed_ae00),
            device,
            phases: None,
        }
    }

    /// The training device (autodiff).
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// One Adam step on features `[B, 260, T]` (normalised; T a multiple of 8).
    pub fn step(&mut self, features: Tensor<3>) -> Result<AeStepReport, ModelError> {
        check_features("pose features", &features)?;
        let t0 = Instant::now();
        let x = features.to_device(&self.device).autodiff();
        let [b, _, t] = x.dims();
        let eps = autoencoder_noise(&self.autoencoder, b, t, &mut self.noise, &self.device);
        // Row groups side by side on the CPU's threads (`super::parallel`), each on replicas of
        // both networks and carrying its share of the batch's mean losses. Dropout draws its
        // masks from the device's one generator, so with dropout on the groups' forward passes
        // run one after the other (the masks in a fixed order) and only the backward passes
        // side by side.
        let groups = row_groups(&self.device, b, self.train.batch_chunks);
        let split = groups.len() > 1;
        let shares: Vec<f32> = groups.iter().map(|g| g.len() as f32 / b as f32).collect();
        let replicas: Vec<(Replica<MotionAutoencoder>, Replica<GlobalRegressor>)> =
            groups.iter().map(|_| (Replica::of(&self.autoencoder), Replica::of(&self.regressor))).collect();
        let train = &self.train;
        let forward = |i: usize| {
            let rows = groups[i].clone();
            let (ae, reg) = (&replicas[i].0.module, &replicas[i].1.module);
            let x = x.clone().narrow(0, rows.start, rows.len());
            let eps = eps.clone().map(|e| e.narrow(0, rows.start, rows.len()));
            let losses = autoencoder_loss(ae, x.clone(), train, eps);
            let regressor_loss = l1(reg.forward(regressor_input(x.clone())), regressor_target(x));
            let total = losses.total.clone() + regressor_loss.clone();
            // One group: its total as it is (no scaling by 1 in the graph).
            let total = if split { total * shares[i] } else { total };
            (total, losses, regressor_loss)
        };
        let parallel_forward = self.config.dropout == 0.0;
        let groups_out: Vec<_> = if parallel_forward {
            map_parallel(groups.len(), forward)
        } else {
            (0..groups.len()).map(forward).collect()
        };

        let t1 = Instant::now();
        let grads = map_parallel(groups.len(), |i| {
            let mut grads = groups_out[i].0.backward();
            let (ae, reg) = &replicas[i];
            (ae.grads(&mut grads), reg.grads(&mut grads))
        });
        let (g_ae, g_reg): (Vec<_>, Vec<_>) = grads.into_iter().unzip();
        let mut g_ae = sum_grads(&self.autoencoder, g_ae);
        let mut g_reg = sum_grads(&self.regressor, g_reg);
        let t2 = Instant::now();
        let ae_grad_norm = clip_grad_norm(&self.autoencoder, &mut g_ae, self.train.grad_clip_norm);
        let regressor_grad_norm = clip_grad_norm(&self.regressor, &mut g_reg, self.train.grad_clip_norm);
        let t3 = Instant::now();

        // The batch's terms: each group's means weighted by its share of the rows.
        let [ae_loss, reconstruction, sparsity, smoothness, kl, regressor_loss] =
            weighted_terms(shares.iter().zip(groups_out).map(|(&share, (_, ae, regressor_loss))| {
                ([ae.total, ae.reconstruction, ae.sparsity, ae.smoothness, ae.kl, regressor_loss], [share; 6])
            }));
        self.autoencoder = self.optim_ae.step(self.train.lr, self.autoencoder.clone(), g_ae);
        self.regressor = self.optim_regressor.step(self.train.regressor_lr, self.regressor.clone(), g_reg);
        if let Some(p) = &mut self.phases {
            p.add([t0, t1, t2, t3, Instant::now()]);
        }
        Ok(AeStepReport {
            ae_loss,
            reconstruction,
            sparsity,
            smoothness,
            kl,
            regressor_loss,
            ae_grad_norm,
            regressor_grad_norm,
        })
    }
}

impl Trainer for AeTrainer {
    type Report = AeStepReport;
    const SHOWN: &'static [(&'static str, &'static str)] =
        &[("loss", "ae_loss"), ("rec", "reconstruction"), ("reg", "regressor_loss")];
    const METRICS: &'static [&'static str] = &eval::AE_METRICS;

    fn train_step(&mut self, data: &TrainData, rng: &mut SamplerRng) -> anyhow::Result<AeStepReport> {
        let windows: Vec<_> = (0..data.batch).map(|_| data.sampler.window(rng)).collect();
        let x = batch_tensor(&data.clips, &windows, data.window, &data.device);
        Ok(self.step(x)?)
    }

    fn evaluate(&self, data: &TrainData) -> Vec<f64> {
        let ae = self.autoencoder.clone().valid();
        let regressor = self.regressor.clone().valid();
        eval::evaluate_ae(&ae, &regressor, &data.heldout, &data.norm, data.batch, &data.device)
    }

    fn learning_rates(&self) -> Vec<(&'static str, f64)> {
        vec![("lr", self.train.lr), ("regressor_lr", self.train.regressor_lr)]
    }

    fn weights(&self) -> anyhow::Result<Vec<u8>> {
        module_bytes(AeNets {
            autoencoder: self.autoencoder.clone().valid(),
            regressor: self.regressor.clone().valid(),
        })
    }

    fn load_weights(&mut self, bytes: &[u8]) -> anyhow::Result<()> {
        let nets = load_module(AeNets::new(&self.config, &self.device), bytes)?;
        self.autoencoder = nets.autoencoder;
        self.regressor = nets.regressor;
        Ok(())
    }

    /// Both optimizers' Adam states.
    fn optimizer_state(&self) -> Result<Vec<u8>, ModelError> {
        optimizers_to_bytes(&[&self.optim_ae, &self.optim_regressor])
    }

    fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        [self.optim_ae, self.optim_regressor] = optimizers_from_bytes(bytes)?;
        Ok(())
    }
}
