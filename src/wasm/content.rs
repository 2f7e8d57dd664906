//! [`Content`]: a BVH brought onto the canonical rig ([`skeleton::import_bvh`]), kept with its
//! rig so that outputs can go back onto it.

use std::rc::Rc;

use wasm_bindgen::prelude::*;

use super::error::import_error;
use crate::Motion;
use crate::skeleton::{self, FPS, UserRig};

/// An imported motion: 30 fps on the canonical rig, and the rig it came from.
#[wasm_bindgen]
pub struct Content {
    pub(super) motion: Rc<Motion>,
    pub(super) rig: Rc<UserRig>,
}

#[wasm_bindgen]
impl Content {
    /// Parses BVH text of any rig the importer accepts. Errors: `BVH_PARSE` (with `line`, `kind`),
    /// `RIG_UNMATCHED`, `RIG_DEGENERATE`, `TOO_LONG`, `BAD_MOTION`.
    #[wasm_bindgen(js_name = fromBvh)]
    pub fn from_bvh(text: &str) -> Result<Content, JsValue> {
        let imported = skeleton::import_bvh(text).map_err(|e| import_error(&e))?;
        Ok(Content { motion: Rc::new(imported.motion), rig: Rc::new(imported.rig) })
    }

    /// Frames at 30 fps (after resampling).
    #[wasm_bindgen(getter)]
    pub fn frames(&self) -> usize {
        self.motion.frames()
    }

    /// Always 30 (the canonical rate the importer resamples to).
    #[wasm_bindgen(getter)]
    pub fn fps(&self) -> f64 {
        FPS
    }

    /// The detected naming scheme: `bandai`, `cmu31`, `m21`, `cc_base`, `mixamo` or `generic`.
    #[wasm_bindgen(getter)]
    pub fn rig(&self) -> String {
        self.rig.report().rig.clone()
    }

    /// What the importer detected and derived (JSON of the rig report: matched and missing
    /// joints, scale, axes, floor, base pose).
    #[wasm_bindgen(js_name = rigReport)]
    pub fn rig_report(&self) -> String {
        serde_json::to_string(self.rig.report()).unwrap_or_else(|_| "{}".to_string())
    }
}
