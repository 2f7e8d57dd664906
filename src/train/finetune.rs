//! Fine-tuning (`--from WEIGHTS`): a new run's networks start from a weights folder's instead of
//! a fresh initialisation.
//!
//! - **Labels.** The run's label set is the weights' labels, in their order, then the data's
//!   labels the weights do not know (compared without case), in the data's order
//!   ([`merged_labels`]): old labels keep their one-hot index, so their rows mean what they meant.
//! - **Growing.** The label-dependent layers are the ones whose input (style encoder's second
//!   convolution, every AdaIN's linear layer: the one-hot label is concatenated *last*) or output
//!   (the classifier's last layer) is the label count. [`grow`] copies every parameter of the old
//!   network into the new one; a parameter that is larger along exactly one axis gets the old
//!   values in the leading part of that axis and keeps the new network's (seeded Xavier)
//!   initialisation for the new labels' part.
//! - **What is kept.** The weights' width and network sizes, and their normalisation statistics
//!   (the old networks were trained on them). The autoencoder and regressor come from the
//!   supervised bundle (or the unsupervised one if there is none), each stylizer from its own
//!   setting's bundle, the classifier from the folder's `classifier.bin` when it has one (else it
//!   starts fresh).

use anyhow::{Context, bail, ensure};
use burn::module::{Module, ModuleMapper, Param};
use burn::prelude::*;
use std::collections::HashMap;
use std::path::Path;

use crate::features::NormStats;
use crate::model::weights::{float_params, load_classifier};
use crate::model::{ModelConfig, MotionModel, StyleClassifier};
use crate::stylize::{Setting, Weights};

/// What a weights folder gives a new run.
#[derive(Clone, Debug)]
pub struct FromWeights {
    pub labels: Vec<String>,
    pub norm: NormStats,
    /// The bundles' config (autoencoder, stylizer and regressor sizes).
    pub config: ModelConfig,
    pub width: f64,
    /// The classifier's config, when the folder has `classifier.bin`.
    pub classifier: Option<ModelConfig>,
}

/// Loads the weights folder `dir` (manifest format 1 or 2) on the CPU.
fn load_weights(dir: &Path) -> anyhow::Result<Weights> {
    Weights::load_dir(dir).with_context(|| format!("--from {}: cannot load the weights", dir.display()))
}

/// Reads what a new run takes from the weights folder `dir`.
pub fn read_from(dir: &Path) -> anyhow::Result<FromWeights> {
    let weights = load_weights(dir)?;
    let manifest = weights.manifest();
    let setting = weights.settings().first().copied().with_context(|| format!("--from {}: no model", dir.display()))?;
    let config = weights.model(setting)?.config.clone();
    let width = manifest.entry(setting).map_or(0.0, |m| m.width);
    let classifier = load_old_classifier(dir)?.map(|(config, _)| config);
    Ok(FromWeights { labels: manifest.styles.clone(), norm: weights.norm().clone(), config, width, classifier })
}

/// The old labels in order, then the new ones not among them (without case), in their order.
pub fn merged_labels(old: &[String], new: &[String]) -> Vec<String> {
    let mut out = old.to_vec();
    for n in new {
        if !out.iter().any(|o| o.eq_ignore_ascii_case(n)) {
            out.push(n.clone());
        }
    }
    out
}

/// The weights folder's networks for `setting` (the autoencoder stage passes `None`: the
/// supervised model's, else the unsupervised one's), on the CPU.
pub fn load_model(dir: &Path, setting: Option<Setting>) -> anyhow::Result<MotionModel> {
    let weights = load_weights(dir)?;
    let setting = match setting {
        Some(s) => s,
        None => weights.settings().first().copied().with_context(|| format!("--from {}: no model", dir.display()))?,
    };
    let model = weights
        .model(setting)
        .with_context(|| format!("--from {}: no {setting} model to start from", dir.display()))?;
    Ok(model.nets.clone())
}

/// The weights folder's classifier (`classifier.bin`) and its config, if it has one.
pub fn load_old_classifier(dir: &Path) -> anyhow::Result<Option<(ModelConfig, StyleClassifier)>> {
    let path = dir.join(super::classifier::BUNDLE);
    if !path.is_file() {
        return Ok(None);
    }
    let bytes = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let loaded = load_classifier(&bytes, &Device::flex()).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(Some(loaded))
}

/// Float parameters by path, f32.
fn params<M: Module>(module: &M) -> anyhow::Result<HashMap<String, (Vec<usize>, Vec<f32>)>> {
    let list = float_params(module).map_err(|e| anyhow::anyhow!("cannot read the weights to start from: {e}"))?;
    Ok(list.into_iter().map(|(path, shape, values)| (path, (shape, values))).collect())
}

/// Layers newer than some weights, which a network grown from those starts at zero: the posture
/// map ([`crate::model::ModelConfig::content_posture`]), zero adds nothing.
const ADDED_AT_ZERO: &[&str] = &["generator.posture"];

/// The new network's parameters replaced by the old one's (grown where needed).
struct Grow {
    path: Vec<String>,
    old: HashMap<String, (Vec<usize>, Vec<f32>)>,
    error: Option<String>,
    grown: Vec<String>,
}

/// `old` (shape `from`) copied into the leading part of `new` (shape `to`, same rank).
fn embed(old: &[f32], from: &[usize], new: &mut [f32], to: &[usize]) {
    let rank = to.len();
    let mut index = vec![0usize; rank];
    for (k, v) in old.iter().enumerate() {
        let mut rest = k;
        for d in (0..rank).rev() {
            index[d] = rest % from[d];
            rest /= from[d];
        }
        let mut flat = 0;
        for d in 0..rank {
            flat = flat * to[d] + index[d];
        }
        new[flat] = *v;
    }
}

impl ModuleMapper for Grow {
    fn enter_module(&mut self, name: &str, _container_type: &str) {
        self.path.push(name.to_string());
    }
    fn exit_module(&mut self, _name: &str, _container_type: &str) {
        self.path.pop();
    }
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        if self.error.is_some() {
            return param;
        }
        let path = self.path.join(".");
        let Some((from, old)) = self.old.remove(&path) else {
            // A layer the weights predate that starts at zero (the network's outputs unchanged).
            if ADDED_AT_ZERO.iter().any(|p| path.starts_with(p)) {
                let device = param.lazy_device();
                let shape = param.lazy_shape();
                self.grown.push(format!("{path} (new, zero)"));
                let id = param.id;
                return param.transform_for_load(Tensor::<D>::zeros(shape, &device), id);
            }
            self.error = Some(format!("{path}: not in the weights to start from"));
            return param;
        };
        let device = param.lazy_device();
        let fresh = param.val().into_data();
        let to = fresh.shape().to_vec();
        let values = if from == to {
            old
        } else {
            let differing: Vec<usize> = (0..to.len().min(from.len())).filter(|&d| from[d] != to[d]).collect();
            if from.len() != to.len() || differing.len() != 1 || from[differing[0]] > to[differing[0]] {
                self.error = Some(format!("{path}: shape {from:?} cannot grow into {to:?}"));
                return param;
            }
            let mut new = match fresh.convert::<f32>().try_into_vec::<f32>() {
                Ok(v) => v,
                Err(e) => {
                    self.error = Some(format!("{path}: {e:?}"));
                    return param;
                }
            };
            embed(&old, &from, &mut new, &to);
            self.grown.push(format!("{path} {from:?} -> {to:?}"));
            new
        };
        let tensor = Tensor::<D>::from_data(TensorData::new(values, to), &device);
        let id = param.id;
        param.transform_for_load(tensor, id)
    }
}

/// `new` (a freshly initialised network, possibly with more labels) with every parameter of
/// `old` (module docs). Returns it and the grown parameters (`path [old] -> [new]`).
pub fn grow<M: Module>(old: &M, new: M) -> anyhow::Result<(M, Vec<String>)> {
    let mut mapper = Grow { path: Vec::new(), old: params(old)?, error: None, grown: Vec::new() };
    let grown = new.map(&mut mapper);
    if let Some(e) = mapper.error {
        bail!("the weights to start from do not fit: {e}");
    }
    ensure!(mapper.old.is_empty(), "the weights to start from have parameters the network lacks: {:?}", {
        let mut k: Vec<&String> = mapper.old.keys().collect();
        k.sort();
        k
    });
    Ok((grown, mapper.grown))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_merge_old_first_without_case() {
        let old: Vec<String> = ["normal", "old"].iter().map(|s| s.to_string()).collect();
        let new: Vec<String> = ["Old", "slowmo", "hurried"].iter().map(|s| s.to_string()).collect();
        assert_eq!(merged_labels(&old, &new), ["normal", "old", "slowmo", "hurried"]);
    }

    #[test]
    fn embed_copies_the_leading_block_along_the_grown_axis() {
        // [2, 2] into [2, 3] (axis 1 grows) and into [3, 2] (axis 0 grows).
        let old = [1.0, 2.0, 3.0, 4.0];
        let mut a = vec![0.0; 6];
        embed(&old, &[2, 2], &mut a, &[2, 3]);
        assert_eq!(a, [1.0, 2.0, 0.0, 3.0, 4.0, 0.0]);
        let mut b = vec![9.0; 6];
        embed(&old, &[2, 2], &mut b, &[3, 2]);
        assert_eq!(b, [1.0, 2.0, 3.0, 4.0, 9.0, 9.0]);
    }

    #[test]
    fn a_supervised_stylizer_grows_to_more_labels_keeping_the_old_rows() {
        use crate::model::Stylizer;
        let device = Device::flex();
        let cfg = ModelConfig::scaled(0.125).with_num_styles(2).with_supervised(true);
        let old = crate::model::init::seeded_xavier(Stylizer::new(&cfg, &device), 1);
        let bigger = cfg.clone().with_num_styles(3);
        let fresh = crate::model::init::seeded_xavier(Stylizer::new(&bigger, &device), 2);
        let (grown, changed) = grow(&old, fresh).unwrap();
        assert!(!changed.is_empty(), "label-dependent layers grow");
        // Same parameters where nothing grew, and the old block where something did.
        let (a, b) = (params(&old).unwrap(), params(&grown).unwrap());
        for (path, (shape, values)) in &a {
            let (new_shape, new_values) = &b[path];
            if shape == new_shape {
                assert_eq!(values, new_values, "{path}");
            } else {
                let axes: Vec<usize> = (0..shape.len()).filter(|&d| shape[d] != new_shape[d]).collect();
                assert_eq!(axes.len(), 1, "{path}");
                assert_eq!(new_shape[axes[0]], shape[axes[0]] + 1, "{path}: one more label");
                let mut check = new_values.clone();
                embed(values, shape, &mut check, new_shape);
                assert_eq!(&check, new_values, "{path}: the old block is kept");
            }
        }
        // A network that is smaller cannot take them.
        let smaller = Stylizer::new(&cfg.clone().with_num_styles(1), &device);
        assert!(grow(&old, smaller).is_err());
    }
}
