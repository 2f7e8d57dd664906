//! The WebAssembly facade of the npm package `motion-stylizer` (feature `wasm`, wasm32 only): a
//! thin wasm-bindgen layer over [`crate::skeleton`] (import) and [`crate::stylize`] (inference).
//! The package's JS wrapper (`js/index.js`) is the public API; these classes are its engine, and
//! they carry the JS wrapper's names.
//!
//! - [`ImportedMotion`] (JS `Motion`): a BVH imported onto the canonical rig, with the rig to take
//!   outputs back, and the parsed file itself (its own joint positions, for drawing it).
//! - [`StyleSpec`]: where the style comes from (label, reference motion, prior, mix of two).
//! - [`Engine`]: the loaded weights; [`Engine::stylize`] gives one [`StylizedMotion`] per sample
//!   (and `stylizeAsync`, the one call a WebGPU engine, [`Engine::create_webgpu`], answers).
//! - [`StylizedMotion`]: a motion on the canonical or the content's rig: BVH text, joint
//!   positions, skeleton names and parents.
//!
//! Every failure is a JS `Error` with a stable `code` ([`error`]); nothing here panics on any
//! input (values from JS are validated before they become Rust values, mixes are depth-capped
//! when they are built, everything else is refused by the library's typed errors). As a backstop
//! for bugs, [`panic`] records the message of any panic (which traps the instance) for the JS
//! wrapper to report as `INTERNAL` before it starts a fresh instance.

mod drawing;
mod engine;
pub mod error;
mod motion;
mod options;
pub mod panic;
mod style;
mod stylized;
mod webgpu;

pub use engine::{Engine, weight_file_list};
pub use motion::{ImportedMotion, inspect_bvh};
pub use style::StyleSpec;
pub use stylized::{StylizedMotion, ThreePose};
