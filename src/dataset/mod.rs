//! The Bandai-Namco training data: take names, the unified style-label set, and the fixed split.
//!
//! Pure functions only (no file system), so the label set also serves inference and wasm.

pub mod labels;
pub mod split;

pub use labels::{STYLES, Style};
pub use split::{Split, TakeId};
