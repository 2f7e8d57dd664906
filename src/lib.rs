//! motion-stylizer: generative human motion stylization in latent space (Guo et al., ICLR 2024),
//! for native use and WebAssembly.
//!
//! Pipeline stages, one module each: [`bvh`] (text ↔ motion), [`skeleton`] (kinematics,
//! retargeting), [`features`] (the 260-D representation); [`gltf`] writes motions as `.glb`.

pub mod bvh;
pub mod dataset;
#[cfg(all(feature = "model", not(target_arch = "wasm32")))]
pub mod eval;
pub mod features;
pub mod gltf;
pub mod memory;
#[cfg(feature = "model")]
pub mod model;
pub mod motion;
pub mod skeleton;
#[cfg(feature = "model")]
pub mod stylize;
#[cfg(all(feature = "model", not(target_arch = "wasm32")))]
pub mod train;
#[cfg(all(feature = "wasm", target_arch = "wasm32"))]
pub mod wasm;

pub use motion::{Motion, MotionError};
