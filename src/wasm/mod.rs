//! The WebAssembly facade of the npm package `motion-stylizer` (feature `wasm`, wasm32 only): a
//! thin wasm-bindgen layer over [`crate::skeleton`] (import) and [`crate::stylize`] (inference).
//! The package's JS wrapper (`js/index.js`) is the public API; these classes are its engine.
//!
//! - [`Content`]: a BVH imported onto the canonical rig, with the rig to take outputs back.
//! - [`StyleSpec`]: where the style comes from (label, reference motion, prior, mix of two).
//! - [`Engine`]: the loaded weights; [`Engine::stylize`] gives one [`Output`] per sample.
//! - [`Output`]: a motion on the canonical or the content's rig: BVH text, joint positions,
//!   skeleton names and parents.
//!
//! Every failure is a JS `Error` with a stable `code` ([`error`]); nothing here panics on any
//! input (numbers from JS are validated before they become Rust integers, mixes are depth-capped
//! when they are built, everything else is refused by the library's typed errors).

mod content;
mod engine;
pub mod error;
mod output;
mod style;

pub use content::Content;
pub use engine::Engine;
pub use output::Output;
pub use style::StyleSpec;
