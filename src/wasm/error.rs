//! Errors as JS `Error`s with a stable `code` property (and, for BVH parse errors, the `line` and
//! the reader's error `kind`). The codes come from the library's typed errors
//! ([`ImportError::code`], [`StylizeError::code`], [`GltfError::code`]); the facade adds `BAD_REQUEST` (values from JS
//! that are not what the API takes) and `BACKEND_UNAVAILABLE`.

use wasm_bindgen::JsValue;

use crate::gltf::GltfError;
use crate::skeleton::ImportError;
use crate::stylize::StylizeError;

fn coded(code: &str, message: &str) -> js_sys::Error {
    let error = js_sys::Error::new(message);
    set(&error, "code", &JsValue::from_str(code));
    error
}

fn set(error: &js_sys::Error, key: &str, value: &JsValue) {
    // Setting a property of a fresh Error object cannot fail; the Result is ignored, not unwrapped.
    let _ = js_sys::Reflect::set(error, &JsValue::from_str(key), value);
}

/// A JS `Error` with `message` and a `code` property.
pub fn js_error(code: &str, message: &str) -> JsValue {
    coded(code, message).into()
}

/// A request the facade refuses before it reaches the pipeline.
pub fn bad_request(message: &str) -> JsValue {
    js_error("BAD_REQUEST", message)
}

/// An import failure; BVH reader errors also carry `line` (1-based) and `kind`.
pub fn import_error(e: &ImportError) -> JsValue {
    let error = coded(e.code(), &e.to_string());
    if let ImportError::Bvh(bvh) = e {
        set(&error, "line", &JsValue::from_f64(bvh.line() as f64));
        set(&error, "kind", &JsValue::from_str(bvh.kind()));
    }
    error.into()
}

/// A stylization (or weights) failure.
pub fn stylize_error(e: &StylizeError) -> JsValue {
    match e {
        StylizeError::Import(inner) => import_error(inner),
        other => js_error(other.code(), &other.to_string()),
    }
}

/// A glTF export failure ([`GltfError::code`]: `BAD_MOTION`, `TOO_LONG`).
pub fn gltf_error(e: &GltfError) -> JsValue {
    js_error(e.code(), &e.to_string())
}
