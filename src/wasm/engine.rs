//! [`Engine`]: the loaded weights on a CPU backend, and the one call that stylizes.

use std::rc::Rc;

use burn::prelude::Device;
use wasm_bindgen::prelude::*;

use super::error::{bad_request, js_error, stylize_error};
use super::motion::ImportedMotion;
use super::options::StylizeOptions;
use super::panic;
use super::style::StyleSpec;
use super::stylized::StylizedMotion;
use crate::Motion;
use crate::gltf::GltfOptions;
use crate::stylize::weights::parse_manifest;
use crate::stylize::{self, BodyPart, PartRequests, Request, Setting, StyleSource, WeightFiles, Weights};

/// The files a weights folder's `manifest.json` names, for the JS wrapper to fetch (the engine is
/// the one reader of the manifest): JSON `{format, norm, shared: {file, bytes} | null, models:
/// [{setting, file, bytes, style_encoder: {file, bytes} | null}]}`. Errors: `BAD_WEIGHTS`.
#[wasm_bindgen(js_name = weightFileList)]
pub fn weight_file_list(manifest: &[u8]) -> Result<String, JsValue> {
    panic::install();
    let manifest = parse_manifest(manifest).map_err(|e| stylize_error(&e))?;
    serde_json::to_string(&manifest.file_list()).map_err(|e| js_error("BAD_WEIGHTS", &e.to_string()))
}

/// The trained models, ready to stylize.
#[wasm_bindgen]
pub struct Engine {
    /// Shared with the async calls in flight (WebGPU): adding a model while one runs is refused.
    weights: Rc<Weights>,
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
    /// Loads the weight files' bytes (`manifest.json`, `norm.json`, format 2's `shared.bin`, and
    /// at least one of `supervised.bin`, `unsupervised.bin`) on `backend` (`"cpu"`). Errors:
    /// `BAD_WEIGHTS`, `BACKEND_UNAVAILABLE`.
    #[wasm_bindgen(constructor)]
    pub fn new(
        manifest: &[u8],
        norm: &[u8],
        shared: Option<Vec<u8>>,
        supervised: Option<Vec<u8>>,
        unsupervised: Option<Vec<u8>>,
        backend: &str,
    ) -> Result<Engine, JsValue> {
        panic::install();
        let (device, backend) = device(backend)?;
        let files = WeightFiles {
            manifest,
            norm,
            shared: shared.as_deref(),
            supervised: supervised.as_deref(),
            unsupervised: unsupervised.as_deref(),
            ..Default::default()
        };
        let mut weights = Weights::from_files_on(&device, files).map_err(|e| stylize_error(&e))?;
        weights.prepare_for_inference();
        Ok(Engine { weights: Rc::new(weights), backend })
    }

    /// As the constructor, on the browser's WebGPU device (the build with the cargo feature
    /// `webgpu`): resolves to the engine once the device is up and a test product has been read
    /// back from it. Only the async calls (`stylizeAsync`, `stylizePartsAsync`, `inferLabelAsync`)
    /// read from it. Rejects with `BACKEND_UNAVAILABLE` (no `navigator.gpu`, no adapter, the
    /// device fails, or this build has no WebGPU backend) or `BAD_WEIGHTS`.
    #[wasm_bindgen(js_name = createWebGpu)]
    pub async fn create_webgpu(
        manifest: Vec<u8>,
        norm: Vec<u8>,
        shared: Option<Vec<u8>>,
        supervised: Option<Vec<u8>>,
        unsupervised: Option<Vec<u8>>,
    ) -> Result<Engine, JsValue> {
        panic::install();
        let device = super::webgpu::device().await?;
        let files = WeightFiles {
            manifest: &manifest,
            norm: &norm,
            shared: shared.as_deref(),
            supervised: supervised.as_deref(),
            unsupervised: unsupervised.as_deref(),
            ..Default::default()
        };
        let mut weights = Weights::from_files_on(&device, files).map_err(|e| stylize_error(&e))?;
        weights.prepare_for_inference();
        Ok(Engine { weights: Rc::new(weights), backend: "webgpu" })
    }

    /// The weights to change: refused while an async stylization holds them.
    fn weights_mut(&mut self) -> Result<&mut Weights, JsValue> {
        Rc::get_mut(&mut self.weights)
            .ok_or_else(|| js_error("BUSY", "a stylization is running on this engine: wait for it, then add the model"))
    }

    /// Adds the model of `setting` (`"supervised"`, `"unsupervised"`) from its file's bytes, next
    /// to those loaded (on the shared networks, format 2). Errors: `BAD_REQUEST` (another name),
    /// `SETTING_UNAVAILABLE` (the manifest lists no such model), `BAD_WEIGHTS`.
    #[wasm_bindgen(js_name = addSetting)]
    pub fn add_setting(&mut self, setting: &str, bytes: &[u8]) -> Result<(), JsValue> {
        let setting =
            Setting::from_name(setting).ok_or_else(|| bad_request(&format!("unknown setting {setting:?}")))?;
        self.weights_mut()?.add_setting(setting, bytes).map_err(|e| stylize_error(&e))
    }

    /// Adds the style encoder of `setting` from its file's bytes (format 3: the manifest's
    /// `style_encoder` file of that setting, fetched when a reference motion is first used; a
    /// stylization that needs it fails with `STYLE_ENCODER_UNAVAILABLE` until then). A no-op
    /// where it is loaded. Errors: `BAD_REQUEST` (another name), `SETTING_UNAVAILABLE` (that
    /// model is not loaded), `BAD_WEIGHTS`.
    #[wasm_bindgen(js_name = addStyleEncoder)]
    pub fn add_style_encoder(&mut self, setting: &str, bytes: &[u8]) -> Result<(), JsValue> {
        let setting =
            Setting::from_name(setting).ok_or_else(|| bad_request(&format!("unknown setting {setting:?}")))?;
        self.weights_mut()?.add_style_encoder(setting, bytes).map_err(|e| stylize_error(&e))
    }

    /// Whether the model of `setting` is loaded with its style encoder.
    #[wasm_bindgen(js_name = hasStyleEncoder)]
    pub fn has_style_encoder(&self, setting: &str) -> bool {
        Setting::from_name(setting).is_some_and(|s| self.weights.has_style_encoder(s))
    }

    /// The settings the manifest lists, loaded or not.
    pub fn listed(&self) -> Vec<String> {
        self.weights.listed().iter().map(|s| s.as_str().to_string()).collect()
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

    /// Stylizes `content` with the style of `style`. `options` (each property optional, as is the
    /// object): `{ unsupervised, samples, seed, canonical, temperature, strength, guidance }`:
    /// `samples` outputs (1–64, default 1) from `seed` (a non-negative safe integer or a BigInt
    /// below 2^64, default 0), with the unsupervised model or the supervised one (default), each on
    /// the canonical rig or the content's own (default), prior draws scaled by `temperature`
    /// (default the library's), pushed past the neutral style's output by `guidance` (0–3, default
    /// the library's), the change scaled by `strength` (0–2, default 1; 0 is the content).
    /// Errors: see [`crate::stylize::StylizeError::code`], and `BAD_REQUEST` for options of the
    /// wrong type and `samples` or `seed` values that are not integers in range.
    pub fn stylize(
        &self,
        content: &ImportedMotion,
        style: &StyleSpec,
        options: JsValue,
    ) -> Result<Vec<StylizedMotion>, JsValue> {
        let options = StylizeOptions::from_js(&options)?;
        let source = style.source(&self.weights).map_err(|e| stylize_error(&e))?;
        let request = request_of(source, &options);
        let motions = stylize::stylize(&self.weights, &content.motion, &request).map_err(|e| stylize_error(&e))?;
        Ok(outputs(&content.rig, &motions, options.canonical))
    }

    /// [`Engine::stylize`] as a Promise of the results' array, read asynchronously: the one way
    /// to stylize on WebGPU (on the CPU it gives the same results as `stylize`).
    #[wasm_bindgen(js_name = stylizeAsync)]
    pub fn stylize_async(
        &self,
        content: &ImportedMotion,
        style: &StyleSpec,
        options: JsValue,
    ) -> Result<js_sys::Promise, JsValue> {
        let options = StylizeOptions::from_js(&options)?;
        let (weights, style) = (Rc::clone(&self.weights), style.clone());
        let (motion, rig) = (Rc::clone(&content.motion), Rc::clone(&content.rig));
        Ok(wasm_bindgen_futures::future_to_promise(async move {
            let source = style.source(&weights).map_err(|e| stylize_error(&e))?;
            let request = request_of(source, &options);
            let motions = stylize::stylize_async(&weights, &motion, &request).await.map_err(|e| stylize_error(&e))?;
            Ok(results(outputs(&rig, &motions, options.canonical)))
        }))
    }

    /// Stylizes `content` with a style per body part ([`stylize::stylize_parts`]): `lower` (the
    /// root and the legs), `upper` (spine, chest, arms), `head` (neck, head); a part without a
    /// style ([`StyleSpec::content`]) keeps the content's own motion. `options` as for
    /// [`Engine::stylize`], shared by every part. Errors: those of `stylize`, and `BAD_REQUEST`
    /// when no part has a style.
    #[wasm_bindgen(js_name = stylizeParts)]
    pub fn stylize_parts(
        &self,
        content: &ImportedMotion,
        lower: &StyleSpec,
        upper: &StyleSpec,
        head: &StyleSpec,
        options: JsValue,
    ) -> Result<Vec<StylizedMotion>, JsValue> {
        let options = StylizeOptions::from_js(&options)?;
        let specs = [(BodyPart::Lower, lower), (BodyPart::Upper, upper), (BodyPart::Head, head)];
        let mut parts = PartRequests::default();
        for (part, spec) in specs {
            if spec.is_content() {
                continue;
            }
            let source = spec.source(&self.weights).map_err(|e| stylize_error(&e))?;
            parts.set(part, request_of(source, &options));
        }
        let motions = stylize::stylize_parts(&self.weights, &content.motion, &parts).map_err(|e| stylize_error(&e))?;
        Ok(outputs(&content.rig, &motions, options.canonical))
    }

    /// [`Engine::stylize_parts`] as a Promise of the results' array, read asynchronously.
    #[wasm_bindgen(js_name = stylizePartsAsync)]
    pub fn stylize_parts_async(
        &self,
        content: &ImportedMotion,
        lower: &StyleSpec,
        upper: &StyleSpec,
        head: &StyleSpec,
        options: JsValue,
    ) -> Result<js_sys::Promise, JsValue> {
        let options = StylizeOptions::from_js(&options)?;
        let specs =
            [(BodyPart::Lower, lower.clone()), (BodyPart::Upper, upper.clone()), (BodyPart::Head, head.clone())];
        let weights = Rc::clone(&self.weights);
        let (motion, rig) = (Rc::clone(&content.motion), Rc::clone(&content.rig));
        Ok(wasm_bindgen_futures::future_to_promise(async move {
            let mut parts = PartRequests::default();
            for (part, spec) in &specs {
                if spec.is_content() {
                    continue;
                }
                let source = spec.source(&weights).map_err(|e| stylize_error(&e))?;
                parts.set(*part, request_of(source, &options));
            }
            let motions =
                stylize::stylize_parts_async(&weights, &motion, &parts).await.map_err(|e| stylize_error(&e))?;
            Ok(results(outputs(&rig, &motions, options.canonical)))
        }))
    }

    /// The supervised model's label for a reference motion given without one
    /// ([`crate::stylize::infer_label`]): its name. Errors: `SETTING_UNAVAILABLE` without the
    /// supervised model, `TOO_LONG`, `BAD_MOTION`.
    #[wasm_bindgen(js_name = inferLabel)]
    pub fn infer_label(&self, reference: &ImportedMotion) -> Result<String, JsValue> {
        let (style, _) = stylize::infer_label(&self.weights, &reference.motion).map_err(|e| stylize_error(&e))?;
        Ok(self.weights.style_name(style).unwrap_or_default().to_string())
    }

    /// [`Engine::infer_label`] as a Promise of the label's name, read asynchronously.
    #[wasm_bindgen(js_name = inferLabelAsync)]
    pub fn infer_label_async(&self, reference: &ImportedMotion) -> js_sys::Promise {
        let (weights, motion) = (Rc::clone(&self.weights), Rc::clone(&reference.motion));
        wasm_bindgen_futures::future_to_promise(async move {
            let (style, _) = stylize::infer_label_async(&weights, &motion).await.map_err(|e| stylize_error(&e))?;
            Ok(JsValue::from_str(weights.style_name(style).unwrap_or_default()))
        })
    }

    /// Internal, for the tests of the panic backstop only (not part of the package's API):
    /// panics on purpose, which traps the instance. The JS wrapper must then report `INTERNAL`
    /// with this panic's message and carry on with a fresh instance (`tests/npm/api.test.mjs`).
    #[doc(hidden)]
    #[wasm_bindgen(js_name = __panicForTests)]
    pub fn panic_for_tests(&self) {
        panic!("a deliberate panic for the tests (Engine.__panicForTests)");
    }
}

/// Canonical motions as results, on the canonical rig or the content's own (`rig`).
fn outputs(rig: &crate::skeleton::UserRig, motions: &[Motion], canonical: bool) -> Vec<StylizedMotion> {
    motions
        .iter()
        .map(|m| match canonical {
            true => StylizedMotion::new(m.to_bvh(), GltfOptions::canonical()),
            false => StylizedMotion::new(rig.from_canonical(m), GltfOptions::for_rig(rig.report())),
        })
        .collect()
}

/// Results as the JS array an async call resolves to.
fn results(outputs: Vec<StylizedMotion>) -> JsValue {
    outputs.into_iter().map(JsValue::from).collect::<js_sys::Array>().into()
}

/// The pipeline's request for `source` with the JS options (model, samples, seed, temperature,
/// strength, guidance): one place for `stylize` and every part of `stylizeParts`.
fn request_of<'a>(source: StyleSource<'a>, options: &StylizeOptions) -> Request<'a> {
    let setting = if options.unsupervised { Setting::Unsupervised } else { Setting::Supervised };
    Request::new(source)
        .with_setting(setting)
        .with_samples(options.samples)
        .with_seed(options.seed)
        .with_temperature(options.temperature)
        .with_strength(options.strength)
        .with_guidance(options.guidance)
}
