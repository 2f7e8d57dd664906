//! Weights to and from bytes in compact f16 (half the size of f32; the browser downloads bytes).
//!
//! Format of one network: Burn's burnpack record (`ModuleRecord::into_bytes`), every float
//! parameter cast to F16 first. Loading applies the record to a freshly built (lazily
//! initialised, so nothing random is computed) module of the same architecture and casts the
//! parameters back to F32.
//!
//! Every file of ours that carries weights has one framing ([`frame`] / [`unframe`]): an 8-byte
//! magic | JSON header length (u32 LE) | JSON header | payload. A *bundle* ([`save_bundle`] /
//! [`load_bundle`]) is `b"MSTYLZ01"` with the [`ModelConfig`] as header and the burnpack bytes of a
//! [`MotionModel`] as payload; the evaluation's classifier is `b"MSTYCL01"`, the same way; training
//! checkpoints frame their metadata and f32 weights the same way too.

use burn::module::{Module, ModuleMapper, Param};
use burn::prelude::*;
use burn::store::ModuleRecord;
use burn::tensor::{Bytes, FloatDType};

use super::ModelError;
use super::classifier::StyleClassifier;
use super::config::ModelConfig;
use super::stylizer::MotionModel;

const BUNDLE_MAGIC: &[u8; 8] = b"MSTYLZ01";
const CLASSIFIER_MAGIC: &[u8; 8] = b"MSTYCL01";

struct CastFloats(FloatDType);

impl ModuleMapper for CastFloats {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let dtype = self.0;
        param.map(|t| t.cast(dtype))
    }
}

fn weights_err(e: impl core::fmt::Display) -> ModelError {
    ModelError::Weights(e.to_string())
}

/// Every float parameter of `module` in f16, as burnpack bytes.
pub fn to_f16_bytes<M: Module>(module: M) -> Result<Vec<u8>, ModelError> {
    let module = module.map(&mut CastFloats(FloatDType::F16));
    let bytes = module.into_record().into_bytes().map_err(weights_err)?;
    Ok(bytes.to_vec())
}

/// Loads bytes from [`to_f16_bytes`] into `template` (a module of the same architecture, e.g.
/// freshly built by `Net::new(&config, &device)`), parameters back in f32. Fails with a typed
/// error on bytes that are not a record of that architecture.
pub fn from_f16_bytes<M: Module>(template: M, bytes: &[u8]) -> Result<M, ModelError> {
    let record = ModuleRecord::from_bytes(Bytes::from_bytes_vec(bytes.to_vec())).map_err(weights_err)?;
    let module = template.try_load_record(record).map_err(weights_err)?;
    Ok(module.map(&mut CastFloats(FloatDType::F32)))
}

/// Config + all inference networks in one byte buffer (f16 weights).
pub fn save_bundle(config: &ModelConfig, model: MotionModel) -> Result<Vec<u8>, ModelError> {
    save_with(BUNDLE_MAGIC, config, model)
}

/// Reads a [`save_bundle`] buffer onto `device` (plain, for inference).
pub fn load_bundle(bytes: &[u8], device: &Device) -> Result<(ModelConfig, MotionModel), ModelError> {
    let (config, weights) = split_bundle(BUNDLE_MAGIC, "a motion-stylizer weights bundle", bytes)?;
    let model = from_f16_bytes(MotionModel::new(&config, device), weights)?;
    Ok((config, model))
}

/// Config + the evaluation's style classifier in one byte buffer (f16 weights), the layout of
/// [`save_bundle`] under the magic `b"MSTYCL01"`.
pub fn save_classifier(config: &ModelConfig, classifier: StyleClassifier) -> Result<Vec<u8>, ModelError> {
    save_with(CLASSIFIER_MAGIC, config, classifier)
}

/// Reads a [`save_classifier`] buffer onto `device`.
pub fn load_classifier(bytes: &[u8], device: &Device) -> Result<(ModelConfig, StyleClassifier), ModelError> {
    let (config, weights) = split_bundle(CLASSIFIER_MAGIC, "a style classifier bundle", bytes)?;
    let classifier = from_f16_bytes(StyleClassifier::new(&config, device), weights)?;
    Ok((config, classifier))
}

fn save_with<M: Module>(magic: &[u8; 8], config: &ModelConfig, module: M) -> Result<Vec<u8>, ModelError> {
    let json = serde_json::to_vec(config).map_err(weights_err)?;
    Ok(frame(magic, &json, &to_f16_bytes(module)?))
}

/// `magic` | `header.len()` (u32 LE) | `header` | `payload`.
pub fn frame(magic: &[u8; 8], header: &[u8], payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(12 + header.len() + payload.len());
    out.extend_from_slice(magic);
    out.extend_from_slice(&(header.len() as u32).to_le_bytes());
    out.extend_from_slice(header);
    out.extend_from_slice(payload);
    out
}

/// Why bytes are not a [`frame`] with the expected magic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Another magic, or fewer bytes than a magic and a length.
    NotOurs,
    /// The header is longer than the bytes.
    Truncated,
}

/// The header and the payload of a [`frame`] with `magic`.
pub fn unframe<'a>(magic: &[u8; 8], bytes: &'a [u8]) -> Result<(&'a [u8], &'a [u8]), FrameError> {
    let (found, rest) = bytes.split_first_chunk::<8>().ok_or(FrameError::NotOurs)?;
    if found != magic {
        return Err(FrameError::NotOurs);
    }
    let (len, rest) = rest.split_first_chunk::<4>().ok_or(FrameError::NotOurs)?;
    let len = usize::try_from(u32::from_le_bytes(*len)).map_err(|_| FrameError::Truncated)?;
    rest.split_at_checked(len).ok_or(FrameError::Truncated)
}

/// The config of a bundle, read from its header without touching the weights.
pub fn bundle_config(bytes: &[u8]) -> Result<(ModelConfig, &[u8]), ModelError> {
    split_bundle(BUNDLE_MAGIC, "a motion-stylizer weights bundle", bytes)
}

/// The config and the weight bytes of a bundle with `magic`.
fn split_bundle<'a>(magic: &[u8; 8], what: &str, bytes: &'a [u8]) -> Result<(ModelConfig, &'a [u8]), ModelError> {
    let (json, weights) = unframe(magic, bytes).map_err(|e| match e {
        FrameError::NotOurs => ModelError::Weights(format!("not {what}")),
        FrameError::Truncated => ModelError::Weights(format!("not {what} (truncated)")),
    })?;
    let config: ModelConfig = serde_json::from_slice(json).map_err(|e| ModelError::Weights(format!("config: {e}")))?;
    Ok((config, weights))
}

pub use super::parts::*;
