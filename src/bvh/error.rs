use thiserror::Error;

/// Why a BVH text was rejected. Every variant names the 1-based line it was found on (for
/// [`BvhError::LimitExceeded`] on `bytes`, line 1). Tokens quoted from the input are cut to at most
/// 40 bytes.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BvhError {
    /// The bytes are not UTF-8 ([`Bvh::parse_bytes`](super::Bvh::parse_bytes) only).
    #[error("line {line}: input is not valid UTF-8")]
    NotUtf8 { line: usize },
    /// The text ends where `expected` was due (e.g. a missing `}` or `MOTION`).
    #[error("line {line}: unexpected end of file, expected {expected}")]
    UnexpectedEof { line: usize, expected: &'static str },
    /// A token other than the one the grammar requires here (e.g. a stray `}` or a missing `{`).
    #[error("line {line}: expected {expected}, found {found:?}")]
    Unexpected { line: usize, expected: &'static str, found: String },
    /// A word that is no BVH keyword where a keyword is due (inside a joint: `JOINT`, `End Site`, `}`).
    #[error("line {line}: unknown keyword {keyword:?}")]
    UnknownKeyword { line: usize, keyword: String },
    /// `ROOT` or `JOINT` without a name on the same line.
    #[error("line {line}: {keyword} without a name")]
    MissingName { line: usize, keyword: &'static str },
    /// `HIERARCHY` is not followed by `ROOT`.
    #[error("line {line}: the hierarchy has no ROOT")]
    NoRoot { line: usize },
    /// A second `ROOT` (only one skeleton per file is supported).
    #[error("line {line}: a second ROOT")]
    SecondRoot { line: usize },
    #[error("line {line}: duplicate joint name {name:?}")]
    DuplicateJoint { line: usize, name: String },
    /// A joint or End Site whose body does not start with `OFFSET`.
    #[error("line {line}: expected OFFSET, found {found:?}")]
    MissingOffset { line: usize, found: String },
    /// `OFFSET` without exactly three numbers on its line.
    #[error("line {line}: OFFSET has {found} values, expected 3")]
    OffsetArity { line: usize, found: usize },
    /// A joint whose `OFFSET` is not followed by `CHANNELS`.
    #[error("line {line}: expected CHANNELS, found {found:?}")]
    MissingChannels { line: usize, found: String },
    #[error("line {line}: unknown channel {channel:?}")]
    UnknownChannel { line: usize, channel: String },
    /// The same channel twice in one joint.
    #[error("line {line}: duplicate channel {channel:?}")]
    DuplicateChannel { line: usize, channel: String },
    /// `CHANNELS n` followed by a different number of channel names on its line.
    #[error("line {line}: CHANNELS declares {declared} channels but lists {found}")]
    ChannelCount { line: usize, declared: usize, found: usize },
    /// `JOINT`, `End Site` or `CHANNELS` inside an End Site.
    #[error("line {line}: an End Site cannot have children or channels")]
    EndSiteChildren { line: usize },
    /// A second End Site in the same joint.
    #[error("line {line}: a joint can have only one End Site")]
    DuplicateEndSite { line: usize },
    /// A token that should be a number and is not (also a negative or fractional count).
    #[error("line {line}: not a number: {token:?}")]
    NotANumber { line: usize, token: String },
    /// NaN or ±infinity (also a literal out of `f64` range, such as `1e999`).
    #[error("line {line}: non-finite value {token:?}")]
    NonFinite { line: usize, token: String },
    /// `Frames: 0`: a motion needs at least one frame.
    #[error("line {line}: the motion has no frames")]
    NoFrames { line: usize },
    /// `Frame Time` ≤ 0.
    #[error("line {line}: frame time {value} is not positive")]
    InvalidFrameTime { line: usize, value: f64 },
    /// A frame row with a number of values other than the channel count.
    #[error("line {line}: frame {frame} has {found} values, expected {expected}")]
    WrongValueCount { line: usize, frame: usize, expected: usize, found: usize },
    /// The text ends after `found` of the `expected` frame rows.
    #[error("line {line}: only {found} of {expected} frames")]
    TooFewFrames { line: usize, expected: usize, found: usize },
    /// More frame rows than `Frames:` announced; `line` is the first extra row.
    #[error("line {line}: more than the {expected} frames announced")]
    TooManyFrames { line: usize, expected: usize },
    /// A size beyond [`Limits`](super::Limits): `what` is `"bytes"`, `"joints"`, `"hierarchy depth"`,
    /// `"frames"` or `"channels per joint"`.
    #[error("line {line}: {what} {value} exceeds the limit of {limit}")]
    LimitExceeded { line: usize, what: &'static str, value: u64, limit: u64 },
}

/// Longest excerpt of the input quoted in an error.
pub(crate) const MAX_QUOTED: usize = 40;

impl BvhError {
    /// The 1-based line the error was found on.
    pub fn line(&self) -> usize {
        use BvhError::*;
        match *self {
            NotUtf8 { line }
            | UnexpectedEof { line, .. }
            | Unexpected { line, .. }
            | UnknownKeyword { line, .. }
            | MissingName { line, .. }
            | NoRoot { line }
            | SecondRoot { line }
            | DuplicateJoint { line, .. }
            | MissingOffset { line, .. }
            | OffsetArity { line, .. }
            | MissingChannels { line, .. }
            | UnknownChannel { line, .. }
            | DuplicateChannel { line, .. }
            | ChannelCount { line, .. }
            | EndSiteChildren { line }
            | DuplicateEndSite { line }
            | NotANumber { line, .. }
            | NonFinite { line, .. }
            | NoFrames { line }
            | InvalidFrameTime { line, .. }
            | WrongValueCount { line, .. }
            | TooFewFrames { line, .. }
            | TooManyFrames { line, .. }
            | LimitExceeded { line, .. } => line,
        }
    }

    /// The variant's name (`"TooFewFrames"`, …), for tables of expected errors.
    pub fn kind(&self) -> &'static str {
        use BvhError::*;
        match self {
            NotUtf8 { .. } => "NotUtf8",
            UnexpectedEof { .. } => "UnexpectedEof",
            Unexpected { .. } => "Unexpected",
            UnknownKeyword { .. } => "UnknownKeyword",
            MissingName { .. } => "MissingName",
            NoRoot { .. } => "NoRoot",
            SecondRoot { .. } => "SecondRoot",
            DuplicateJoint { .. } => "DuplicateJoint",
            MissingOffset { .. } => "MissingOffset",
            OffsetArity { .. } => "OffsetArity",
            MissingChannels { .. } => "MissingChannels",
            UnknownChannel { .. } => "UnknownChannel",
            DuplicateChannel { .. } => "DuplicateChannel",
            ChannelCount { .. } => "ChannelCount",
            EndSiteChildren { .. } => "EndSiteChildren",
            DuplicateEndSite { .. } => "DuplicateEndSite",
            NotANumber { .. } => "NotANumber",
            NonFinite { .. } => "NonFinite",
            NoFrames { .. } => "NoFrames",
            InvalidFrameTime { .. } => "InvalidFrameTime",
            WrongValueCount { .. } => "WrongValueCount",
            TooFewFrames { .. } => "TooFewFrames",
            TooManyFrames { .. } => "TooManyFrames",
            LimitExceeded { .. } => "LimitExceeded",
        }
    }
}

/// `bytes` as an owned string for an error message, cut to [`MAX_QUOTED`] bytes (at a char boundary).
pub(crate) fn quote(bytes: &[u8]) -> String {
    let cut = if bytes.len() <= MAX_QUOTED { bytes } else { &bytes[..MAX_QUOTED] };
    let mut s = String::from_utf8_lossy(cut).into_owned();
    if cut.len() < bytes.len() {
        // A cut inside a multi-byte char shows up as U+FFFD; drop it, then mark the cut.
        while s.ends_with('\u{FFFD}') {
            s.pop();
        }
        s.push('…');
    }
    s
}
