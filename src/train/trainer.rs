//! What the training loop ([`super::runner`]) needs of a stage: the [`Trainer`] trait, and
//! [`step_report!`], which declares a step report's loss terms once (its fields are the
//! `loss.csv` columns, in declaration order).

use super::data::TrainData;
use super::sampler::SamplerRng;
use crate::model::ModelError;

/// One step's losses and gradient norms, by name, in `loss.csv` order.
pub trait StepReport {
    /// The terms' names (`loss.csv` columns after `step` and `elapsed_s`).
    const TERMS: &'static [&'static str];
    /// The values, in [`StepReport::TERMS`] order; the first is the loss that must stay finite.
    fn values(&self) -> Vec<f64>;
}

/// Declares a step report: a struct of `f32` terms (before the update) implementing
/// [`StepReport`] with the fields' names as its terms.
macro_rules! step_report {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[$field_meta:meta])* pub $field:ident,)+ }) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $name {
            $($(#[$field_meta])* pub $field: f32,)+
        }

        impl $crate::train::trainer::StepReport for $name {
            const TERMS: &'static [&'static str] = &[$(stringify!($field)),+];
            fn values(&self) -> Vec<f64> {
                vec![$(f64::from(self.$field)),+]
            }
        }
    };
}
pub(crate) use step_report;

/// Where a trainer's steps spend their time, summed over the steps measured (set
/// `trainer.phases = Some(PhaseTimes::default())` to measure; the CPU backend runs eagerly, so
/// each phase's seconds are its own work).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// Steps measured.
    pub steps: u64,
    /// Forward pass and losses (the frozen encoder's latents included).
    pub forward: f64,
    /// Backward pass (autodiff) and collecting each network's gradients.
    pub backward: f64,
    /// Gradient norms and clipping.
    pub clip: f64,
    /// Reading the losses back and the Adam update.
    pub update: f64,
}

impl PhaseTimes {
    /// Adds one step's phase boundaries `[start, forward, backward, clip, update]`.
    pub fn add(&mut self, marks: [std::time::Instant; 5]) {
        let secs = |i: usize| marks[i + 1].duration_since(marks[i]).as_secs_f64();
        self.steps += 1;
        self.forward += secs(0);
        self.backward += secs(1);
        self.clip += secs(2);
        self.update += secs(3);
    }
}

/// A stage's trainer as the loop drives it: a step on a batch it draws from the training data,
/// the held-out evaluation, and the state a checkpoint saves.
pub trait Trainer {
    type Report: StepReport;
    /// Terms the progress display shows: (short label, term name).
    const SHOWN: &'static [(&'static str, &'static str)];
    /// Held-out metric names (`eval.csv` columns after `step` and `elapsed_s`).
    const METRICS: &'static [&'static str];

    /// One step on a batch drawn with `rng`.
    fn train_step(&mut self, data: &TrainData, rng: &mut SamplerRng) -> anyhow::Result<Self::Report>;
    /// The held-out metrics, in [`Trainer::METRICS`] order.
    fn evaluate(&self, data: &TrainData) -> Vec<f64>;
    /// Learning rates, logged as the last columns of `loss.csv`.
    fn learning_rates(&self) -> Vec<(&'static str, f64)>;
    /// Burnpack bytes (f32) of the trained networks, and their restoration.
    fn weights(&self) -> anyhow::Result<Vec<u8>>;
    fn load_weights(&mut self, bytes: &[u8]) -> anyhow::Result<()>;
    /// The optimizers' state (`optimizer.bin`), and its restoration (after the weights).
    fn optimizer_state(&self) -> Result<Vec<u8>, ModelError>;
    fn load_optimizer_state(&mut self, bytes: &[u8]) -> Result<(), ModelError>;
    /// Other files written beside each checkpoint: (file name, bytes).
    fn artifacts(&self) -> anyhow::Result<Vec<(&'static str, Vec<u8>)>> {
        Ok(Vec::new())
    }
}
