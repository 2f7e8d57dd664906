//! [`ImportedMotion`] (JS `Motion`): a BVH brought onto the canonical rig ([`skeleton::import`]),
//! kept with its rig, so that outputs can go back onto it, and with the parsed file, so that the
//! file can be drawn as it was given (its own joint positions, by [`Bvh::global_pose`]).

use std::rc::Rc;

use wasm_bindgen::prelude::*;

use super::drawing;
use super::error::import_error;
use super::panic;
use crate::Motion;
use crate::bvh::Bvh;
use crate::skeleton::{self, FPS, ImportError, ManualMap, UserRig};

/// An imported motion: 30 fps on the canonical rig, the rig it came from, and the source file.
#[wasm_bindgen(js_name = Motion)]
pub struct ImportedMotion {
    pub(super) motion: Rc<Motion>,
    pub(super) rig: Rc<UserRig>,
    source: Bvh,
}

#[wasm_bindgen(js_class = Motion)]
impl ImportedMotion {
    /// Parses BVH text of any rig the importer accepts; `map`: a manual joint mapping's JSON
    /// (canonical joint → the file's joint, as `inspectBvh`'s `map`), applied over the automatic
    /// match. Errors: `BVH_PARSE` (with `line`, `kind`), `BAD_MAP`, `RIG_UNMATCHED`,
    /// `RIG_DEGENERATE`, `NOT_HUMAN`, `TOO_LONG`, `BAD_MOTION`.
    #[wasm_bindgen(js_name = fromBvh)]
    pub fn from_bvh(text: &str, map: Option<String>) -> Result<ImportedMotion, JsValue> {
        panic::install();
        let source = Bvh::parse(text).map_err(|e| import_error(&ImportError::from(e)))?;
        let manual = manual_map(map.as_deref())?;
        let imported = skeleton::import_with(&source, manual.as_ref()).map_err(|e| import_error(&e))?;
        Ok(ImportedMotion { motion: Rc::new(imported.motion), rig: Rc::new(imported.rig), source })
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

    /// The source file's joint names (file order: a parent before its children).
    #[wasm_bindgen(js_name = sourceJointNames)]
    pub fn source_joint_names(&self) -> Vec<String> {
        drawing::joint_names(&self.source)
    }

    /// The source file's parent index of each joint, −1 for the root.
    #[wasm_bindgen(js_name = sourceParents)]
    pub fn source_parents(&self) -> Vec<i32> {
        drawing::parents(&self.source)
    }

    /// The source file's frame count (its `Frames:`).
    #[wasm_bindgen(getter, js_name = sourceFrames)]
    pub fn source_frames(&self) -> usize {
        self.source.frames
    }

    /// The source file's seconds per frame (its `Frame Time:`).
    #[wasm_bindgen(getter, js_name = sourceFrameTime)]
    pub fn source_frame_time(&self) -> f64 {
        self.source.frame_time
    }

    /// World joint positions of the source file's frames `0, step, 2·step, …` (a `step` of 0 is
    /// 1), `frames × joints × 3` in the file's units and axes, by its forward kinematics.
    #[wasm_bindgen(js_name = sourcePositions)]
    pub fn source_positions(&self, step: usize) -> Vec<f32> {
        drawing::positions(&self.source, step)
    }
}

/// A manual mapping from its JSON, if given (`BAD_MAP` when it is not one).
fn manual_map(map: Option<&str>) -> Result<Option<ManualMap>, JsValue> {
    map.map(ManualMap::from_json).transpose().map_err(|e| import_error(&e))
}

/// What the importer makes of BVH text, also when it cannot import it: the JSON of
/// `motion-stylizer inspect --json` (without `file`): `rig`, `joint_names`, `matched`, `missing`,
/// `synthesised`, `retargetable`, `error` ({code, message}), `map` (the mapping used, or the best
/// guesses, every canonical joint present, ready to edit and pass back as `map`). Throws only for
/// text that is no BVH (`BVH_PARSE`) or a `map` that is no mapping (`BAD_MAP`).
#[wasm_bindgen(js_name = inspectBvh)]
pub fn inspect_bvh(text: &str, map: Option<String>) -> Result<String, JsValue> {
    panic::install();
    let source = Bvh::parse(text).map_err(|e| import_error(&ImportError::from(e)))?;
    let manual = manual_map(map.as_deref())?;
    let (found, _) = skeleton::inspect(&source, manual.as_ref());
    Ok(found.to_json(&source).to_string())
}
