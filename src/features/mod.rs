//! The 260-D pose features. (Being written.)
