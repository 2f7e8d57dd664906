//! [`Engine`]: the loaded weights on a CPU backend, and the one call that stylizes.

use burn::prelude::Device;
use wasm_bindgen::prelude::*;

use super::content::Content;
use super::error::{bad_request, js_error, stylize_error};
use super::output::Output;
use super::style::StyleSpec;
use crate::stylize::{self, DEFAULT_TEMPERATURE, Request, Setting, Weights};

/// The trained models, ready to stylize.
#[wasm_bindgen]
pub struct Engine {
    weights: Weights,
    backend: &'static str,
}

/// The Burn device of a backend name: `flex` (the default CPU backend, wasm SIMD), or `ndarray`
/// when the build has it (feature `ndarray`).
fn device(backend: &str) -> Result<(Device, &'static str), JsValue> {
    match backend {
        "" | "cpu" | "flex" => Ok((Device::flex(), "flex")),
        #[cfg(feature = "ndarray")]
        #[allow(deprecated)]
        "ndarray" => Ok((Device::ndarray(), "ndarray")),
        other => Err(js_error("BACKEND_UNAVAILABLE", &format!("this build has no {other:?} backend"))),
    }
}

#[wasm_bindgen]
impl Engine {
    /// Loads the weight files' bytes (`manifest.json`, `norm.json`, and at least one of
    /// `supervised.bin`, `unsupervised.bin`) on `backend` (`"cpu"`). Errors: `BAD_WEIGHTS`,
    /// `BACKEND_UNAVAILABLE`.
    #[wasm_bindgen(constructor)]
    pub fn new(
        manifest: &[u8],
        norm: &[u8],
        supervised: Option<Vec<u8>>,
        unsupervised: Option<Vec<u8>>,
        backend: &str,
    ) -> Result<Engine, JsValue> {
        let (device, backend) = device(backend)?;
        let weights = Weights::from_bytes_on(&device, manifest, norm, supervised.as_deref(), unsupervised.as_deref())
            .map_err(|e| stylize_error(&e))?;
        Ok(Engine { weights, backend })
    }

    /// The style labels, in the model's order.
    pub fn styles(&self) -> Vec<String> {
        self.weights.styles().to_vec()
    }

    /// The settings loaded: `"supervised"`, `"unsupervised"`.
    pub fn settings(&self) -> Vec<String> {
        self.weights.settings().iter().map(|s| s.as_str().to_string()).collect()
    }

    /// The Burn backend the weights run on (`"flex"` or `"ndarray"`).
    #[wasm_bindgen(getter)]
    pub fn backend(&self) -> String {
        self.backend.to_string()
    }

    /// Stylizes `content` with the style of `style`: `samples` outputs (1–64) from `seed` (a
    /// non-negative safe integer or a BigInt below 2^64; `undefined` is 0), with the unsupervised
    /// model or the supervised one, each on the canonical rig or the content's own; prior draws
    /// scaled by `temperature` (`undefined`: the library's default). Errors: see
    /// [`crate::stylize::StylizeError::code`], and `BAD_REQUEST` for `samples` or `seed` values
    /// that are not integers in range.
    #[allow(clippy::too_many_arguments)]
    pub fn stylize(
        &self,
        content: &Content,
        style: &StyleSpec,
        unsupervised: bool,
        samples: f64,
        seed: JsValue,
        canonical: bool,
        temperature: Option<f64>,
    ) -> Result<Vec<Output>, JsValue> {
        let samples = count(samples)?;
        let seed = seed_of(&seed)?;
        let setting = if unsupervised { Setting::Unsupervised } else { Setting::Supervised };
        let source = style.source(&self.weights).map_err(|e| stylize_error(&e))?;
        let request = Request::new(source)
            .with_setting(setting)
            .with_samples(samples)
            .with_seed(seed)
            .with_temperature(temperature.map_or(DEFAULT_TEMPERATURE, |t| t as f32));
        let motions = stylize::stylize(&self.weights, &content.motion, &request).map_err(|e| stylize_error(&e))?;
        Ok(motions
            .iter()
            .map(|m| Output::new(if canonical { m.to_bvh() } else { content.rig.from_canonical(m) }))
            .collect())
    }
}

/// A non-negative integral number as a count (out-of-range counts are the pipeline's to refuse).
fn count(n: f64) -> Result<usize, JsValue> {
    if n.is_finite() && n >= 0.0 && n.fract() == 0.0 {
        Ok(n.min(usize::MAX as f64) as usize)
    } else {
        Err(bad_request(&format!("samples must be a positive integer, got {n}")))
    }
}

/// Largest integer a JS number holds exactly.
const MAX_SAFE_INTEGER: f64 = 9_007_199_254_740_991.0;

fn seed_of(seed: &JsValue) -> Result<u64, JsValue> {
    if seed.is_undefined() || seed.is_null() {
        return Ok(0);
    }
    if let Some(n) = seed.as_f64() {
        if n.is_finite() && n >= 0.0 && n.fract() == 0.0 && n <= MAX_SAFE_INTEGER {
            return Ok(n as u64);
        }
        return Err(bad_request(&format!("seed must be a non-negative safe integer or a BigInt, got {n}")));
    }
    if seed.is_bigint() {
        return u64::try_from(seed.clone()).map_err(|_| bad_request("a BigInt seed must be in 0 ..= 2^64 - 1"));
    }
    Err(bad_request("seed must be a number or a BigInt"))
}
