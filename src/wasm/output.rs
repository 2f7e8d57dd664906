//! [`Output`]: one stylized motion as a BVH on the rig it was asked for, with what a viewer needs
//! to draw it (joint positions, names, parents).

use wasm_bindgen::prelude::*;

use crate::bvh::Bvh;

/// A motion on the canonical rig or the content's own rig.
#[wasm_bindgen]
pub struct Output {
    bvh: Bvh,
}

impl Output {
    pub(super) fn new(bvh: Bvh) -> Output {
        Output { bvh }
    }
}

#[wasm_bindgen]
impl Output {
    /// The BVH text (the same bytes the native CLI writes).
    #[wasm_bindgen(js_name = toBvh)]
    pub fn to_bvh(&self) -> String {
        self.bvh.to_bvh_string()
    }

    /// World joint positions, `frames × joints × 3` (x, y, z in the rig's units and axes), by
    /// forward kinematics of the BVH.
    pub fn positions(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.bvh.frames * self.bvh.joints.len() * 3);
        for f in 0..self.bvh.frames {
            let (positions, _) = self.bvh.global_pose(f);
            out.extend(positions.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]));
        }
        out
    }

    #[wasm_bindgen(getter)]
    pub fn frames(&self) -> usize {
        self.bvh.frames
    }

    #[wasm_bindgen(getter)]
    pub fn fps(&self) -> f64 {
        self.bvh.fps()
    }

    /// Joint names, in the order of [`Output::positions`].
    #[wasm_bindgen(js_name = jointNames)]
    pub fn joint_names(&self) -> Vec<String> {
        self.bvh.joints.iter().map(|j| j.name.clone()).collect()
    }

    /// Each joint's parent index, −1 for the root.
    pub fn parents(&self) -> Vec<i32> {
        self.bvh.joints.iter().map(|j| j.parent.map_or(-1, |p| p as i32)).collect()
    }
}
