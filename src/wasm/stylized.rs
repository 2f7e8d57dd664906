//! [`StylizedMotion`]: one stylized motion as a BVH on the rig it was asked for, with what a viewer
//! needs to draw it (joint positions, names, parents).

use wasm_bindgen::prelude::*;

use super::drawing;
use crate::bvh::Bvh;

/// A motion on the canonical rig or the content's own rig.
#[wasm_bindgen]
pub struct StylizedMotion {
    bvh: Bvh,
}

impl StylizedMotion {
    pub(super) fn new(bvh: Bvh) -> StylizedMotion {
        StylizedMotion { bvh }
    }
}

#[wasm_bindgen]
impl StylizedMotion {
    /// The BVH text (the same bytes the native CLI writes).
    #[wasm_bindgen(js_name = toBvh)]
    pub fn to_bvh(&self) -> String {
        self.bvh.to_bvh_string()
    }

    /// World joint positions, `frames × joints × 3` (x, y, z in the rig's units and axes), by
    /// forward kinematics of the BVH.
    pub fn positions(&self) -> Vec<f32> {
        drawing::positions(&self.bvh, 1)
    }

    #[wasm_bindgen(getter)]
    pub fn frames(&self) -> usize {
        self.bvh.frames
    }

    #[wasm_bindgen(getter)]
    pub fn fps(&self) -> f64 {
        self.bvh.fps()
    }

    /// Joint names, in the order of [`StylizedMotion::positions`].
    #[wasm_bindgen(js_name = jointNames)]
    pub fn joint_names(&self) -> Vec<String> {
        drawing::joint_names(&self.bvh)
    }

    /// Each joint's parent index, −1 for the root.
    pub fn parents(&self) -> Vec<i32> {
        drawing::parents(&self.bvh)
    }
}
