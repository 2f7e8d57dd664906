//! The Bandai-Namco training data: take names, the unified style-label set, and the fixed split.
//!
//! `labels` and `split` are pure (no file system), so the label set also serves inference and wasm;
//! `corpus` reads the data from disk (native only).

#[cfg(not(target_arch = "wasm32"))]
pub mod corpus;
pub mod labels;
pub mod split;

pub use labels::{CONTENTS, STYLES, Style, content_class};
pub use split::{Split, TakeId};
