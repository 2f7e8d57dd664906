//! Training steps of the two stages, with Adam and per-network global gradient-norm clipping.
//!
//! Burn's own `GradientClipping::Norm` clips each parameter tensor on its own; the reference uses
//! `torch.nn.utils.clip_grad_norm_(network.parameters(), 0.5)`, one norm over all of a network's
//! gradients, so that is done here ([`clip_grad_norm`]) and no clipping is configured in Adam.
//! Adam: β = (0.9, 0.999), ε = 1e-8 (PyTorch's defaults; Burn's default ε is 1e-5).

use burn::module::{Module, ModuleVisitor, Param};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use burn::tensor::activation::log_softmax;

use super::ModelError;
use super::autoencoder::{MotionAutoencoder, ae_input};
use super::classifier::StyleClassifier;
use super::config::{FEATURE_DIM, ModelConfig, TrainConfig};
use super::init::seeded_xavier;
use super::layers::one_hot;
use super::losses::{StylizerInputs, StylizerWeights, autoencoder_loss, l1, stylizer_loss};
use super::regressor::{GlobalRegressor, regressor_input, regressor_target};
use super::rng::NoiseRng;
use super::stylizer::{StylizerNet, check_frames};

struct SquaredNorm<'a> {
    grads: &'a GradientsParams,
    parts: Vec<Tensor<1>>,
}

impl ModuleVisitor for SquaredNorm<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.grads.get::<D>(param.id) {
            self.parts.push(g.square().sum());
        }
    }
}

struct ScaleGrads<'a> {
    grads: &'a mut GradientsParams,
    factor: f32,
}

impl ModuleVisitor for ScaleGrads<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.grads.remove::<D>(param.id) {
            self.grads.register(param.id, g * self.factor);
        }
    }
}

/// Squared-gradient sums of `module`'s parameters found in `grads` (one tensor per parameter).
fn squared_norm_parts<M: Module>(module: &M, grads: &GradientsParams) -> Vec<Tensor<1>> {
    let mut v = SquaredNorm { grads, parts: Vec::new() };
    module.visit(&mut v);
    v.parts
}

fn total_norm(parts: Vec<Tensor<1>>) -> f32 {
    if parts.is_empty() {
        return 0.0;
    }
    Tensor::cat(parts, 0).sum().into_scalar::<f32>().sqrt()
}

fn clip_factor(norm: f32, max_norm: f32) -> Option<f32> {
    let factor = max_norm / (norm + 1e-6);
    (factor < 1.0).then_some(factor)
}

/// `clip_grad_norm_` for the parameters of `module`: if the global L2 norm of their gradients
/// exceeds `max_norm`, all are scaled by `max_norm / (norm + 1e-6)`. Returns the norm before
/// clipping.
pub fn clip_grad_norm<M: Module>(module: &M, grads: &mut GradientsParams, max_norm: f32) -> f32 {
    let norm = total_norm(squared_norm_parts(module, grads));
    if let Some(factor) = clip_factor(norm, max_norm) {
        module.visit(&mut ScaleGrads { grads, factor });
    }
    norm
}

fn adam() -> ModuleOptimizer {
    AdamConfig::new().with_epsilon(1e-8).init()
}

/// Adam states as bytes: per optimizer, its length (u64 LE) and its burnpack record (moments
/// and step counts keyed by parameter id, which module records keep).
fn optimizers_to_bytes(optims: &[&ModuleOptimizer]) -> Result<Vec<u8>, ModelError> {
    let mut out = Vec::new();
    for o in optims {
        let bytes = o.into_bytes().map_err(|e| ModelError::Weights(format!("optimizer state: {e}")))?;
        out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        out.extend_from_slice(&bytes);
    }
    Ok(out)
}

/// Inverse of [`optimizers_to_bytes`] for `count` optimizers.
fn optimizers_from_bytes(bytes: &[u8], count: usize) -> Result<Vec<ModuleOptimizer>, ModelError> {
    let bad = |m: &str| ModelError::Weights(format!("optimizer state: {m}"));
    let mut rest = bytes;
    let mut out = Vec::with_capacity(count);
    for _ in 0..count {
        let (len, tail) = rest.split_first_chunk::<8>().ok_or_else(|| bad("truncated"))?;
        let len = usize::try_from(u64::from_le_bytes(*len)).map_err(|_| bad("length"))?;
        let (record, tail) = tail.split_at_checked(len).ok_or_else(|| bad("truncated"))?;
        let optim = adam()
            .from_bytes(burn::tensor::Bytes::from_bytes_vec(record.to_vec()))
            .map_err(|e| bad(&e.to_string()))?;
        out.push(optim);
        rest = tail;
    }
    if !rest.is_empty() {
        return Err(bad("trailing bytes"));
    }
    Ok(out)
}

/// Reads several scalar losses with one device read.
fn read_scalars(values: Vec<Tensor<1>>) -> Vec<f32> {
    let values: Vec<Tensor<1>> = values.into_iter().map(|t| t.detach().inner()).collect();
    Tensor::cat(values, 0).into_data().try_into_vec_as::<f32>().expect("f32 losses")
}

fn check_features(what: &'static str, x: &Tensor<3>) -> Result<(), ModelError> {
    let [_, c, t] = x.dims();
    if c != FEATURE_DIM {
        return Err(ModelError::Channels { what, expected: FEATURE_DIM, got: c });
    }
    check_frames(t)
}

// ---------------------------------------------------------------------------------------------

/// Losses of one autoencoder + regressor step (before the update).
#[derive(Clone, Debug, PartialEq)]
pub struct AeStepReport {
    /// Autoencoder total loss.
    pub ae_loss: f32,
    pub reconstruction: f32,
    pub sparsity: f32,
    pub smoothness: f32,
    pub kl: f32,
    /// Regressor mean absolute error.
    pub regressor_loss: f32,
    /// Gradient norms before clipping.
    pub ae_grad_norm: f32,
    pub regressor_grad_norm: f32,
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
        }
    }

    /// The training device (autodiff).
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// Both optimizers' Adam states, for a checkpoint.
    pub fn optimizer_state(&self) -> Result<Vec<u8>, ModelError> {
        optimizers_to_bytes(&[&self.optim_ae, &self.optim_regressor])
    }

    /// Restores [`AeTrainer::optimizer_state`] (after the networks' weights).
    pub fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let mut o = optimizers_from_bytes(bytes, 2)?;
        self.optim_regressor = o.pop().expect("two");
        self.optim_ae = o.pop().expect("two");
        Ok(())
    }

    /// One Adam step on features `[B, 260, T]` (normalised; T a multiple of 8).
    pub fn step(&mut self, features: Tensor<3>) -> Result<AeStepReport, ModelError> {
        check_features("pose features", &features)?;
        let x = features.to_device(&self.device).autodiff();
        let ae = autoencoder_loss(&self.autoencoder, x.clone(), &self.train, &mut self.noise);
        let regressor_loss = l1(self.regressor.forward(regressor_input(x.clone())), regressor_target(x));

        let mut grads = (ae.total.clone() + regressor_loss.clone()).backward();
        let mut g_ae = GradientsParams::from_module(&mut grads, &self.autoencoder);
        let mut g_reg = GradientsParams::from_module(&mut grads, &self.regressor);
        let ae_grad_norm = clip_grad_norm(&self.autoencoder, &mut g_ae, self.train.grad_clip_norm);
        let regressor_grad_norm = clip_grad_norm(&self.regressor, &mut g_reg, self.train.grad_clip_norm);

        let v = read_scalars(vec![ae.total, ae.reconstruction, ae.sparsity, ae.smoothness, ae.kl, regressor_loss]);
        self.autoencoder = self.optim_ae.step(self.train.lr, self.autoencoder.clone(), g_ae);
        self.regressor = self.optim_regressor.step(self.train.regressor_lr, self.regressor.clone(), g_reg);
        Ok(AeStepReport {
            ae_loss: v[0],
            reconstruction: v[1],
            sparsity: v[2],
            smoothness: v[3],
            kl: v[4],
            regressor_loss: v[5],
            ae_grad_norm,
            regressor_grad_norm,
        })
    }
}

// ---------------------------------------------------------------------------------------------

/// A stylizer batch: per row, two clips of the same sequence and (supervised) its style label.
#[derive(Clone, Debug)]
pub struct StylizerBatch {
    /// `[B, 260, T]`, normalised features.
    pub motion1: Tensor<3>,
    /// `[B, 260, T]`, another clip of the same sequence as `motion1`'s row.
    pub motion2: Tensor<3>,
    /// One label per row (supervised) or `None`.
    pub labels: Option<Vec<usize>>,
}

/// Losses of one stylizer step (before the update), unweighted terms as in
/// [`StylizerLosses`](super::losses::StylizerLosses).
#[derive(Clone, Debug, PartialEq)]
pub struct StylizerStepReport {
    pub loss: f32,
    pub rec_latent: f32,
    pub rec_pose: f32,
    pub cyc_latent: f32,
    pub cyc_pose: f32,
    pub kl: f32,
    pub hsa: f32,
    /// Gradient norms before clipping: content + style encoders, generator.
    pub encoders_grad_norm: f32,
    pub generator_grad_norm: f32,
}

/// Stage 2: content encoder, style encoder and generator on latents of a frozen autoencoder.
pub struct StylizerTrainer {
    pub config: ModelConfig,
    pub train: TrainConfig,
    pub weights: StylizerWeights,
    /// Frozen (no gradients, dropout off), on the autodiff device so gradients flow through the
    /// decoder into the generator.
    pub autoencoder: MotionAutoencoder,
    /// On the autodiff device.
    pub net: StylizerNet,
    optim: ModuleOptimizer,
    noise: NoiseRng,
    device: Device,
}

impl StylizerTrainer {
    /// Fresh stylizer networks on `device.autodiff()` (weights from `seed`) over the given
    /// (trained) autoencoder, which may live on the plain or the autodiff device of the same
    /// backend.
    pub fn new(
        config: ModelConfig,
        train: TrainConfig,
        autoencoder: MotionAutoencoder,
        device: &Device,
        seed: u64,
    ) -> Self {
        let device = device.clone().autodiff();
        device.seed(seed);
        let autoencoder = autoencoder.valid().train().freeze();
        let net = seeded_xavier(StylizerNet::new(&config, &device), seed);
        let weights = train.stylizer_weights.unwrap_or_else(|| StylizerWeights::paper(config.supervised));
        Self {
            config,
            train,
            weights,
            autoencoder,
            net,
            optim: adam(),
            noise: NoiseRng::new(seed ^ 0x5eed_57e0),
            device,
        }
    }

    /// The training device (autodiff).
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// The optimizer's Adam state, for a checkpoint.
    pub fn optimizer_state(&self) -> Result<Vec<u8>, ModelError> {
        optimizers_to_bytes(&[&self.optim])
    }

    /// Restores [`StylizerTrainer::optimizer_state`] (after the networks' weights).
    pub fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        self.optim = optimizers_from_bytes(bytes, 1)?.remove(0);
        Ok(())
    }

    /// Latent of features through the frozen encoder (a sample for the VAE, as the reference),
    /// without gradient.
    fn latent(&mut self, features: Tensor<3>) -> Tensor<3> {
        let dist = self.autoencoder.encoder.forward(ae_input(features));
        let z = match dist.logvar {
            Some(logvar) => {
                let [b, d, l] = dist.mean.dims();
                let eps: Tensor<3> = self.noise.normal_tensor(b, d * l, &self.device).reshape([b, d, l]);
                dist.mean + (logvar * 0.5).exp() * eps
            }
            None => dist.mean,
        };
        z.detach()
    }

    /// One Adam step.
    pub fn step(&mut self, batch: &StylizerBatch) -> Result<StylizerStepReport, ModelError> {
        check_features("clip 1 features", &batch.motion1)?;
        check_features("clip 2 features", &batch.motion2)?;
        let [b, _, t] = batch.motion1.dims();
        if batch.motion2.dims() != [b, FEATURE_DIM, t] {
            let got = batch.motion2.dims()[0];
            return Err(ModelError::BatchSize { what: "clip 2 (same shape as clip 1)", expected: b, got });
        }
        let labels = match (self.config.supervised, &batch.labels) {
            (false, _) => None,
            (true, None) => return Err(ModelError::Label("supervised training needs style labels".into())),
            (true, Some(labels)) => {
                if labels.len() != b {
                    return Err(ModelError::BatchSize { what: "style labels", expected: b, got: labels.len() });
                }
                if let Some(&bad) = labels.iter().find(|&&l| l >= self.config.num_styles) {
                    return Err(ModelError::Label(format!("label {bad} out of range {}", self.config.num_styles)));
                }
                Some(one_hot(labels, self.config.num_styles, &self.device))
            }
        };
        let motion1 = batch.motion1.clone().to_device(&self.device).autodiff();
        let motion2 = batch.motion2.clone().to_device(&self.device).autodiff();
        let inputs = StylizerInputs {
            latent1: self.latent(motion1.clone()),
            latent2: self.latent(motion2.clone()),
            motion1,
            motion2,
            labels,
        };
        let losses = stylizer_loss(&self.net, &self.autoencoder.decoder, &inputs, &self.weights, &mut self.noise);

        let mut grads = losses.total.backward();
        let mut g = GradientsParams::from_module(&mut grads, &self.net);
        // As the reference: one norm over both encoders, one over the generator.
        let clip = self.train.grad_clip_norm;
        let mut enc_parts = squared_norm_parts(&self.net.content_encoder, &g);
        enc_parts.extend(squared_norm_parts(&self.net.style_encoder, &g));
        let encoders_grad_norm = total_norm(enc_parts);
        if let Some(factor) = clip_factor(encoders_grad_norm, clip) {
            self.net.content_encoder.visit(&mut ScaleGrads { grads: &mut g, factor });
            self.net.style_encoder.visit(&mut ScaleGrads { grads: &mut g, factor });
        }
        let generator_grad_norm = clip_grad_norm(&self.net.generator, &mut g, clip);

        let v = read_scalars(vec![
            losses.total,
            losses.rec_latent,
            losses.rec_pose,
            losses.cyc_latent,
            losses.cyc_pose,
            losses.kl,
            losses.hsa,
        ]);
        self.net = self.optim.step(self.train.lr, self.net.clone(), g);
        Ok(StylizerStepReport {
            loss: v[0],
            rec_latent: v[1],
            rec_pose: v[2],
            cyc_latent: v[3],
            cyc_pose: v[4],
            kl: v[5],
            hsa: v[6],
            encoders_grad_norm,
            generator_grad_norm,
        })
    }
}

// ---------------------------------------------------------------------------------------------

/// Losses of one classifier step (before the update).
#[derive(Clone, Debug, PartialEq)]
pub struct ClassifierStepReport {
    /// Cross-entropy.
    pub loss: f32,
    /// Fraction of the batch classified correctly.
    pub accuracy: f32,
    pub grad_norm: f32,
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

    /// The optimizer's Adam state, for a checkpoint.
    pub fn optimizer_state(&self) -> Result<Vec<u8>, ModelError> {
        optimizers_to_bytes(&[&self.optim])
    }

    /// Restores [`ClassifierTrainer::optimizer_state`] (after the network's weights).
    pub fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        self.optim = optimizers_from_bytes(bytes, 1)?.remove(0);
        Ok(())
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
        let target = one_hot(labels, self.config.num_styles, &self.device);
        let loss = -(log_softmax(logits.clone(), 1) * target).sum_dim(1).mean();

        let truth: Tensor<2, Int> = Tensor::from_data(
            TensorData::new(labels.iter().map(|&l| l as i64).collect::<Vec<_>>(), [b, 1]),
            &self.device,
        );
        let accuracy = logits.detach().argmax(1).equal(truth).float().mean();

        let mut grads = loss.clone().backward();
        let mut g = GradientsParams::from_module(&mut grads, &self.classifier);
        let grad_norm = clip_grad_norm(&self.classifier, &mut g, self.train.grad_clip_norm);
        let v = read_scalars(vec![loss, accuracy]);
        self.classifier = self.optim.step(self.train.lr, self.classifier.clone(), g);
        Ok(ClassifierStepReport { loss: v[0], accuracy: v[1], grad_norm })
    }
}
