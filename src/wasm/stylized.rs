//! [`StylizedMotion`]: one stylized motion as a BVH on the rig it was asked for, with what a viewer
//! needs to draw it (joint positions, names, parents), as a `.glb` ([`crate::gltf`]), and as the
//! glTF-space pose the package's three.js helper builds a `Skeleton` and an `AnimationClip` from
//! ([`ThreePose`]).

use wasm_bindgen::prelude::*;

use super::drawing;
use super::error::gltf_error;
use crate::bvh::Bvh;
use crate::gltf::{Animation, GltfOptions};

/// A motion on the canonical rig or the content's own rig.
#[wasm_bindgen]
pub struct StylizedMotion {
    bvh: Bvh,
    /// Its rig's space (units, axes) for glTF.
    gltf: GltfOptions,
}

impl StylizedMotion {
    pub(super) fn new(bvh: Bvh, gltf: GltfOptions) -> StylizedMotion {
        StylizedMotion { bvh, gltf }
    }
}

/// The skeleton and motion in glTF space (metres, Y up, facing +Z): what the `.glb` holds, as flat
/// arrays for the JS side.
#[wasm_bindgen]
pub struct ThreePose {
    animation: Animation,
}

/// Translation and rotation of each item, `[tx, ty, tz, qx, qy, qz, qw]`.
fn flat(t: &[glam::DVec3], r: &[glam::DQuat]) -> Vec<f32> {
    t.iter().zip(r).flat_map(|(t, q)| [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(|v| v as f32)).collect()
}

#[wasm_bindgen]
impl ThreePose {
    /// Each joint's rest translation and rotation, `joints × 7` (`tx ty tz qx qy qz qw`).
    pub fn rest(&self) -> Vec<f32> {
        flat(&self.animation.rest_translation, &self.animation.rest_rotation)
    }

    /// Every frame's local translations and rotations, `frames × joints × 7`.
    pub fn frames(&self) -> Vec<f32> {
        flat(&self.animation.translation, &self.animation.rotation)
    }

    /// Per joint: bit 0 its translation is animated, bit 1 its rotation.
    pub fn animated(&self) -> Vec<u8> {
        let a = &self.animation;
        (0..a.joints()).map(|j| a.animated_translation[j] as u8 | (a.animated_rotation[j] as u8) << 1).collect()
    }

    /// Seconds per frame.
    #[wasm_bindgen(getter, js_name = frameTime)]
    pub fn frame_time(&self) -> f64 {
        self.animation.frame_time
    }

    /// Metres per unit of the BVH.
    #[wasm_bindgen(getter, js_name = metresPerUnit)]
    pub fn metres_per_unit(&self) -> f64 {
        self.animation.options.metres_per_unit
    }

    /// The turn from the BVH's axes to glTF's, `[x, y, z, w]`.
    pub fn orientation(&self) -> Vec<f64> {
        let q = self.animation.options.orientation.normalize();
        vec![q.x, q.y, q.z, q.w]
    }
}

#[wasm_bindgen]
impl StylizedMotion {
    /// The BVH text (the same bytes the native CLI writes).
    #[wasm_bindgen(js_name = toBvh)]
    pub fn to_bvh(&self) -> String {
        self.bvh.to_bvh_string()
    }

    /// The motion as binary glTF (`.glb` bytes; [`crate::gltf`]). Errors: `BAD_MOTION`, `TOO_LONG`.
    #[wasm_bindgen(js_name = toGlb)]
    pub fn to_glb(&self) -> Result<Vec<u8>, JsValue> {
        crate::gltf::to_glb(&self.bvh, &self.gltf).map_err(|e| gltf_error(&e))
    }

    /// The skeleton and motion in glTF space, for the three.js helper. Errors: as [`Self::to_glb`].
    #[wasm_bindgen(js_name = threePose)]
    pub fn three_pose(&self) -> Result<ThreePose, JsValue> {
        Animation::from_bvh(&self.bvh, &self.gltf).map(|animation| ThreePose { animation }).map_err(|e| gltf_error(&e))
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
