//! [`StylizeOptions`]: the options object of [`super::Engine::stylize`], read property by property
//! (`js_sys::Reflect`) and checked before anything becomes a Rust integer.

use wasm_bindgen::JsValue;

use super::error::bad_request;
use crate::stylize::{DEFAULT_GUIDANCE, DEFAULT_STRENGTH, DEFAULT_TEMPERATURE};

/// `{ unsupervised, samples, seed, canonical, temperature, strength, guidance }`; a
/// property that is `undefined` (or
/// `null`, or an options object that is `undefined`) takes its default.
#[derive(Debug, PartialEq)]
pub(super) struct StylizeOptions {
    /// The model trained without labels. Default false.
    pub unsupervised: bool,
    /// Outputs to draw (the pipeline refuses counts outside 1–64). Default 1.
    pub samples: usize,
    /// Seed of the random draws: a non-negative safe integer or a BigInt below 2^64. Default 0.
    pub seed: u64,
    /// Outputs on the canonical rig instead of the content's own. Default false.
    pub canonical: bool,
    /// Scale of prior draws (the pipeline refuses values outside [0, 4]). Default the library's.
    pub temperature: f32,
    /// How far towards the style: 0 the content, 1 the default, 2 exaggerated (the pipeline
    /// refuses values outside [0, 2]).
    pub strength: f32,
    /// How much further from the neutral style's output (the pipeline refuses values outside
    /// [0, 3]). Default the library's.
    pub guidance: f32,
}

impl StylizeOptions {
    /// Reads and checks `options`. Errors: `BAD_REQUEST`.
    pub fn from_js(options: &JsValue) -> Result<StylizeOptions, JsValue> {
        if !(options.is_undefined() || options.is_null() || options.is_object()) {
            return Err(bad_request("the stylize options must be an object"));
        }
        let get = |key: &str| property(options, key);
        Ok(StylizeOptions {
            unsupervised: flag(&get("unsupervised")?, "unsupervised")?,
            samples: count(&get("samples")?)?,
            seed: seed(&get("seed")?)?,
            canonical: flag(&get("canonical")?, "canonical")?,
            temperature: number(&get("temperature")?, "temperature", DEFAULT_TEMPERATURE, "[0, 4]")?,
            strength: number(&get("strength")?, "strength", DEFAULT_STRENGTH, "[0, 2]")?,
            guidance: number(&get("guidance")?, "guidance", DEFAULT_GUIDANCE, "[0, 3]")?,
        })
    }
}

/// `options[key]`, `undefined` when `options` is `undefined` or `null`. A getter that throws is a
/// `BAD_REQUEST`.
fn property(options: &JsValue, key: &str) -> Result<JsValue, JsValue> {
    if options.is_undefined() || options.is_null() {
        return Ok(JsValue::UNDEFINED);
    }
    js_sys::Reflect::get(options, &JsValue::from_str(key)).map_err(|_| bad_request(&format!("cannot read {key}")))
}

fn absent(value: &JsValue) -> bool {
    value.is_undefined() || value.is_null()
}

fn flag(value: &JsValue, name: &str) -> Result<bool, JsValue> {
    if absent(value) {
        return Ok(false);
    }
    value.as_bool().ok_or_else(|| bad_request(&format!("{name} must be a boolean")))
}

/// A non-negative integral number as a count (out-of-range counts are the pipeline's to refuse).
fn count(value: &JsValue) -> Result<usize, JsValue> {
    if absent(value) {
        return Ok(1);
    }
    let n = value.as_f64().ok_or_else(|| bad_request("samples must be a number"))?;
    if n.is_finite() && n >= 0.0 && n.fract() == 0.0 {
        Ok(n.min(usize::MAX as f64) as usize)
    } else {
        Err(bad_request(&format!("samples must be a positive integer, got {n}")))
    }
}

/// Largest integer a JS number holds exactly.
const MAX_SAFE_INTEGER: f64 = 9_007_199_254_740_991.0;

fn seed(value: &JsValue) -> Result<u64, JsValue> {
    if absent(value) {
        return Ok(0);
    }
    if let Some(n) = value.as_f64() {
        if n.is_finite() && n >= 0.0 && n.fract() == 0.0 && n <= MAX_SAFE_INTEGER {
            return Ok(n as u64);
        }
        return Err(bad_request(&format!("seed must be a non-negative safe integer or a BigInt, got {n}")));
    }
    if value.is_bigint() {
        return u64::try_from(value.clone()).map_err(|_| bad_request("a BigInt seed must be in 0 ..= 2^64 - 1"));
    }
    Err(bad_request("seed must be a number or a BigInt"))
}

/// A number (`default` when absent), range-checked by the pipeline (`BAD_REQUEST` there, outside
/// `range` or not finite).
fn number(value: &JsValue, name: &str, default: f32, range: &str) -> Result<f32, JsValue> {
    if absent(value) {
        return Ok(default);
    }
    value.as_f64().map(|t| t as f32).ok_or_else(|| bad_request(&format!("{name} must be a number in {range}")))
}
