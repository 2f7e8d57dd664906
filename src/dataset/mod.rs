//! The training data: the Bandai-Namco take names, the unified style-label set and the fixed split;
//! or a folder of the user's own labelled BVH files ([`folder`]).
//!
//! `labels` and `split` are pure (no file system), so the label set also serves inference and wasm;
//! `corpus` reads the data from disk (native only).

#[cfg(not(target_arch = "wasm32"))]
pub mod corpus;
#[cfg(not(target_arch = "wasm32"))]
pub mod folder;
pub mod labels;
pub mod split;

pub use labels::{CONTENTS, STYLES, Style, content_class, content_class_as_seen};
pub use split::{Split, TakeId};
