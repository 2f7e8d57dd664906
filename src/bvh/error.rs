use thiserror::Error;

/// Why a BVH text was rejected. Every variant that comes from the text names its 1-based line.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BvhError {
    #[error("line {line}: {message}")]
    Syntax { line: usize, message: String },
    #[error("line {line}: expected {expected}, found {found}")]
    Unexpected { line: usize, expected: String, found: String },
    #[error("line {line}: unexpected end of file: {context}")]
    UnexpectedEof { line: usize, context: String },
    #[error("line {line}: not a number: {token:?}")]
    NotANumber { line: usize, token: String },
    #[error("line {line}: non-finite value {token:?}")]
    NonFinite { line: usize, token: String },
    #[error("line {line}: unknown keyword {keyword:?}")]
    UnknownKeyword { line: usize, keyword: String },
    #[error("line {line}: unknown channel {channel:?}")]
    UnknownChannel { line: usize, channel: String },
    #[error("line {line}: duplicate joint name {name:?}")]
    DuplicateJoint { line: usize, name: String },
    #[error("line {line}: frame {frame} has {found} values, expected {expected}")]
    WrongValueCount { line: usize, frame: usize, expected: usize, found: usize },
    #[error("line {line}: {what} {value} exceeds the limit of {limit}")]
    LimitExceeded { line: usize, what: &'static str, value: u64, limit: u64 },
    #[error("line {line}: {message}")]
    Invalid { line: usize, message: String },
}
