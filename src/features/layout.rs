//! The feature layout (named slices of the 260 dims), the [`Features`] container, the model views and
//! the error type.

use crate::MotionError;
use crate::skeleton::canonical::NUM_JOINTS;
use std::ops::Range;
use thiserror::Error;

/// Dimensions per frame.
pub const DIM: usize = 260;
/// Dimensions the autoencoder sees: everything but the foot contacts.
pub const MODEL_DIM: usize = 256;
/// Dimensions the global motion regressor sees: [`MODEL_DIM`] less the root linear velocity.
pub const REGRESSOR_DIM: usize = 254;

/// Root angular velocity about +Y, radians per frame.
pub const ROOT_ANG_VEL: Range<usize> = 0..1;
/// Root (Hips) ground velocity (x, z), cm per frame, in the facing frame of the current frame.
pub const ROOT_LIN_VEL: Range<usize> = 1..3;
/// Hips height above the floor, cm.
pub const ROOT_HEIGHT: Range<usize> = 3..4;
/// Joint positions (21 × xyz), cm: x, z relative to the Hips' ground projection in the facing frame,
/// y the absolute height above the floor.
pub const POSITIONS: Range<usize> = 4..67;
/// Joint rotations (21 × 6): first column then second column of the rotation matrix.
pub const ROTATIONS: Range<usize> = 67..193;
/// Joint velocities (21 × xyz), cm per frame, in the facing frame of the current frame.
pub const VELOCITIES: Range<usize> = 193..256;
/// Foot contacts, 0 or 1: `Foot_L`, `Toes_L`, `Foot_R`, `Toes_R`.
pub const CONTACTS: Range<usize> = 256..260;

/// The feature groups, in order; normalisation shares one std per group.
pub const GROUPS: [Range<usize>; 7] =
    [ROOT_ANG_VEL, ROOT_LIN_VEL, ROOT_HEIGHT, POSITIONS, ROTATIONS, VELOCITIES, CONTACTS];

/// Index of the first position dim of joint `j` (x, y, z follow).
pub const fn position_dim(j: usize) -> usize {
    POSITIONS.start + 3 * j
}

/// Index of the first rotation dim of joint `j` (6 follow: column 0 xyz, column 1 xyz).
pub const fn rotation_dim(j: usize) -> usize {
    ROTATIONS.start + 6 * j
}

/// Index of the first velocity dim of joint `j` (x, y, z follow).
pub const fn velocity_dim(j: usize) -> usize {
    VELOCITIES.start + 3 * j
}

const _: () = assert!(POSITIONS.end - POSITIONS.start == 3 * NUM_JOINTS);
const _: () = assert!(ROTATIONS.end - ROTATIONS.start == 6 * NUM_JOINTS);
const _: () = assert!(VELOCITIES.end - VELOCITIES.start == 3 * NUM_JOINTS);
const _: () = assert!(CONTACTS.end == DIM && VELOCITIES.end == MODEL_DIM);

/// Errors of the feature stage.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FeatureError {
    #[error("features need at least one frame")]
    Empty,
    #[error("{len} values are not {frames} frames of {width}")]
    BadLength { len: usize, frames: usize, width: usize },
    #[error("frame {frame}, dim {dim}: non-finite value")]
    NonFinite { frame: usize, dim: usize },
    #[error("normalisation statistics need {DIM} finite means and positive finite stds (got {mean} and {std})")]
    BadStats { mean: usize, std: usize },
    #[error(transparent)]
    Motion(#[from] MotionError),
}

/// Which dims of a frame a consumer sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum View {
    /// All [`DIM`] dims.
    Full,
    /// The first [`MODEL_DIM`] dims (contacts dropped): what the autoencoder sees.
    Model,
    /// [`REGRESSOR_DIM`] dims: [`View::Model`] without [`ROOT_LIN_VEL`], what the regressor sees.
    Regressor,
}

impl View {
    /// Dims per frame in this view.
    pub const fn width(self) -> usize {
        match self {
            View::Full => DIM,
            View::Model => MODEL_DIM,
            View::Regressor => REGRESSOR_DIM,
        }
    }

    /// The ranges of the full layout this view keeps, in order.
    pub fn ranges(self) -> &'static [Range<usize>] {
        const FULL: &[Range<usize>] = std::slice::from_ref(&(0..DIM));
        const MODEL: &[Range<usize>] = std::slice::from_ref(&(0..MODEL_DIM));
        const REGRESSOR: &[Range<usize>] = &[ROOT_ANG_VEL, ROOT_HEIGHT.start..MODEL_DIM];
        match self {
            View::Full => FULL,
            View::Model => MODEL,
            View::Regressor => REGRESSOR,
        }
    }

    /// Index in the full layout of each of this view's dims.
    pub fn dims(self) -> impl Iterator<Item = usize> {
        self.ranges().iter().flat_map(|r| r.clone())
    }
}

/// Per-frame features of a motion: `frames × DIM` values, row-major (one row per frame), f32.
#[derive(Clone, Debug, PartialEq)]
pub struct Features {
    frames: usize,
    data: Vec<f32>,
}

impl Features {
    /// Wraps `frames × DIM` row-major values. The values may be anything (e.g. a network's output);
    /// [`crate::features::reconstruct`] checks that they are finite.
    pub fn new(frames: usize, data: Vec<f32>) -> Result<Features, FeatureError> {
        if frames == 0 {
            return Err(FeatureError::Empty);
        }
        if Some(data.len()) != frames.checked_mul(DIM) {
            return Err(FeatureError::BadLength { len: data.len(), frames, width: DIM });
        }
        Ok(Features { frames, data })
    }

    /// Wraps row-major values of width [`DIM`], inferring the frame count.
    pub fn from_rows(data: Vec<f32>) -> Result<Features, FeatureError> {
        if !data.len().is_multiple_of(DIM) {
            return Err(FeatureError::BadLength { len: data.len(), frames: data.len() / DIM, width: DIM });
        }
        Features::new(data.len() / DIM, data)
    }

    /// Builds features from a view's values (`frames × view.width()`, row-major); the dims the view
    /// lacks are zero.
    pub fn from_view(view: View, frames: usize, values: &[f32]) -> Result<Features, FeatureError> {
        let width = view.width();
        if frames == 0 {
            return Err(FeatureError::Empty);
        }
        if Some(values.len()) != frames.checked_mul(width) {
            return Err(FeatureError::BadLength { len: values.len(), frames, width });
        }
        let mut f = Features { frames, data: vec![0.0; frames * DIM] };
        f.write_view(view, values)?;
        Ok(f)
    }

    pub(crate) fn zeros(frames: usize) -> Features {
        Features { frames, data: vec![0.0; frames * DIM] }
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// All values, row-major.
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// All values, row-major, mutable.
    pub fn data_mut(&mut self) -> &mut [f32] {
        &mut self.data
    }

    /// The values, consuming the features.
    pub fn into_data(self) -> Vec<f32> {
        self.data
    }

    /// Frame `t`'s [`DIM`] values. Panics if `t >= frames()`.
    pub fn frame(&self, t: usize) -> &[f32] {
        &self.data[t * DIM..(t + 1) * DIM]
    }

    /// Frame `t`'s [`DIM`] values, mutable. Panics if `t >= frames()`.
    pub fn frame_mut(&mut self, t: usize) -> &mut [f32] {
        &mut self.data[t * DIM..(t + 1) * DIM]
    }

    /// Iterator over the frames' rows.
    pub fn rows(&self) -> std::slice::ChunksExact<'_, f32> {
        self.data.chunks_exact(DIM)
    }

    /// Frames `start..end` (clamped to the features; at least one frame is kept).
    pub fn slice(&self, start: usize, end: usize) -> Features {
        let end = end.clamp(1, self.frames);
        let start = start.min(end - 1);
        Features { frames: end - start, data: self.data[start * DIM..end * DIM].to_vec() }
    }

    /// The values of `view`, frame-major (`frames × view.width()`).
    pub fn view(&self, view: View) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.frames * view.width());
        for row in self.rows() {
            for r in view.ranges() {
                out.extend_from_slice(&row[r.clone()]);
            }
        }
        out
    }

    /// The values of `view`, channel-major (`view.width() × frames`): the `[channels, time]` layout
    /// of a 1-D convolution.
    pub fn view_channels_first(&self, view: View) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.frames * view.width());
        for d in view.dims() {
            out.extend(self.data.iter().skip(d).step_by(DIM).take(self.frames));
        }
        out
    }

    /// Overwrites the dims of `view` with `values` (frame-major, `frames × view.width()`).
    pub fn write_view(&mut self, view: View, values: &[f32]) -> Result<(), FeatureError> {
        let width = view.width();
        if values.len() != self.frames * width {
            return Err(FeatureError::BadLength { len: values.len(), frames: self.frames, width });
        }
        for (row, src) in self.data.chunks_exact_mut(DIM).zip(values.chunks_exact(width)) {
            let mut k = 0;
            for r in view.ranges() {
                let n = r.len();
                row[r.clone()].copy_from_slice(&src[k..k + n]);
                k += n;
            }
        }
        Ok(())
    }

    /// Overwrites the root linear velocity of every frame with `values` (`frames × 2`, x then z per
    /// frame), e.g. with the global motion regressor's prediction.
    pub fn set_root_linear_velocity(&mut self, values: &[f32]) -> Result<(), FeatureError> {
        if values.len() != self.frames * 2 {
            return Err(FeatureError::BadLength { len: values.len(), frames: self.frames, width: 2 });
        }
        for (row, v) in self.data.chunks_exact_mut(DIM).zip(values.chunks_exact(2)) {
            row[ROOT_LIN_VEL].copy_from_slice(v);
        }
        Ok(())
    }

    /// The first non-finite value, as (frame, dim).
    pub fn first_non_finite(&self) -> Option<(usize, usize)> {
        self.data.iter().position(|v| !v.is_finite()).map(|i| (i / DIM, i % DIM))
    }
}
