//! BVH reader: one pass over the bytes, no recursion, no per-token allocation.
//!
//! # Accepted syntax
//!
//! ```text
//! HIERARCHY
//! ROOT <name>                 one ROOT; names are one whitespace-free token on the keyword's line
//! {
//!   OFFSET <x> <y> <z>        first in every joint / End Site body, 3 numbers on its line
//!   CHANNELS <n> <names…>     second in every joint body; n ≤ 6 names on its line, each of
//!                             X|Y|Z + position|rotation, any order, none twice; `CHANNELS 0` is fine
//!   JOINT <name> { … }        children, any number, any depth (≤ Limits::max_depth)
//!   End Site { OFFSET … }     at most one per joint, no children; `End` and `Site` may be separated
//!                             by any whitespace
//! }
//! MOTION
//! Frames: <n>                 1 ≤ n ≤ Limits::max_frames; whitespace around `:` optional
//! Frame Time: <seconds>       finite and > 0
//! <row> × n                   one frame per line: exactly num_channels numbers
//! ```
//!
//! Keywords and channel names are matched ASCII-case-insensitively. Whitespace is spaces, tabs, `\r`,
//! `\x0b` and `\x0c`; lines end with `\n` or `\r\n`. Braces are separate tokens and may sit on the
//! keyword's line (`JOINT Neck {`). Blank lines are ignored everywhere, including between and after
//! frame rows; a leading UTF-8 BOM is skipped. Numbers are decimal floats with optional sign, fraction
//! and exponent (`-1.2e-05`, `.5`, `5.`); NaN and infinities are rejected. A frame row never wraps
//! onto the next line. Anything else is an error naming its 1-based line (see [`BvhError`]).
use super::error::quote;
use super::lex::{HSPACE, NEWLINE, TOKEN, channel_of, class, kw, parse_count, parse_f64};
use super::{Bvh, BvhError, BvhJoint, Channel};
use glam::DVec3;
use std::collections::HashSet;

/// Bounds on the work the reader does; input beyond them is rejected with
/// [`BvhError::LimitExceeded`] before anything proportional to the claimed size is allocated.
///
/// Defaults: `max_bytes` 64 MiB (67,108,864), `max_joints` 1024, `max_depth` 256 (nesting of joints,
/// the ROOT being depth 1), `max_frames` 1,000,000. Channels per joint are at most
/// [`MAX_CHANNELS_PER_JOINT`] = 6 (each of the six channels at most once). Memory use is linear in the
/// input size whatever the header claims: the value buffer is sized from the bytes actually left.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Limits {
    pub max_bytes: usize,
    pub max_joints: usize,
    pub max_depth: usize,
    pub max_frames: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { max_bytes: 64 << 20, max_joints: 1024, max_depth: 256, max_frames: 1_000_000 }
    }
}

/// What a BVH's header says about its size ([`Bvh::parse_header`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Header {
    pub joints: usize,
    /// Channels per frame.
    pub channels: usize,
    /// `Frames:` (≥ 1, ≤ the frame limit).
    pub frames: usize,
    /// `Frame Time:` (> 0).
    pub frame_time: f64,
}

/// Most channels a joint can have: the six distinct ones.
pub const MAX_CHANNELS_PER_JOINT: usize = 6;

impl Bvh {
    /// Parses BVH text with the default [`Limits`].
    pub fn parse(text: &str) -> Result<Bvh, BvhError> {
        Self::parse_with_limits(text, &Limits::default())
    }

    /// Parses BVH text, rejecting input beyond `limits`.
    pub fn parse_with_limits(text: &str, limits: &Limits) -> Result<Bvh, BvhError> {
        if text.len() > limits.max_bytes {
            return Err(BvhError::LimitExceeded {
                line: 1,
                what: "bytes",
                value: text.len() as u64,
                limit: limits.max_bytes as u64,
            });
        }
        Parser::new(text.as_bytes(), limits).parse()
    }

    /// Reads only what comes before the frame rows, with the default [`Limits`]: the sizes an importer
    /// needs to bound its work before anything proportional to the motion is allocated. The errors
    /// are those [`Bvh::parse`] gives for the same text, up to the `Frame Time:` line.
    pub fn parse_header(text: &str) -> Result<Header, BvhError> {
        let limits = Limits::default();
        if text.len() > limits.max_bytes {
            return Err(BvhError::LimitExceeded {
                line: 1,
                what: "bytes",
                value: text.len() as u64,
                limit: limits.max_bytes as u64,
            });
        }
        let mut p = Parser::new(text.as_bytes(), &limits);
        let (frames, frame_time) = p.header()?;
        Ok(Header { joints: p.joints.len(), channels: p.num_channels, frames, frame_time })
    }

    /// Parses BVH bytes (e.g. a file or a JS `Uint8Array`); they must be UTF-8.
    pub fn parse_bytes(bytes: &[u8], limits: &Limits) -> Result<Bvh, BvhError> {
        if bytes.len() > limits.max_bytes {
            return Err(BvhError::LimitExceeded {
                line: 1,
                what: "bytes",
                value: bytes.len() as u64,
                limit: limits.max_bytes as u64,
            });
        }
        match std::str::from_utf8(bytes) {
            Ok(text) => Parser::new(text.as_bytes(), limits).parse(),
            Err(e) => {
                let before = &bytes[..e.valid_up_to()];
                Err(BvhError::NotUtf8 { line: 1 + before.iter().filter(|&&b| b == b'\n').count() })
            }
        }
    }
}

struct Parser<'a> {
    s: &'a [u8],
    pos: usize,
    /// 1-based line of `pos`.
    line: usize,
    limits: &'a Limits,
    joints: Vec<BvhJoint>,
    names: HashSet<&'a [u8]>,
    /// Channels of the joints so far.
    num_channels: usize,
}

impl<'a> Parser<'a> {
    fn new(s: &'a [u8], limits: &'a Limits) -> Self {
        let s = s.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(s);
        Parser { s, pos: 0, line: 1, limits, joints: Vec::new(), names: HashSet::new(), num_channels: 0 }
    }

    /// Skips whitespace and newlines.
    fn skip_ws(&mut self) {
        while let Some(&b) = self.s.get(self.pos) {
            match class(b) {
                TOKEN => break,
                NEWLINE => self.line += 1,
                _ => {}
            }
            self.pos += 1;
        }
    }

    /// Skips spaces on the current line; true if a token follows on it.
    fn skip_hspace(&mut self) -> bool {
        while let Some(&b) = self.s.get(self.pos) {
            match class(b) {
                HSPACE => self.pos += 1,
                NEWLINE => return false,
                _ => return true,
            }
        }
        false
    }

    /// The token at `pos` (which must not be whitespace).
    fn token(&mut self) -> &'a [u8] {
        let start = self.pos;
        while let Some(&b) = self.s.get(self.pos) {
            if class(b) != TOKEN {
                break;
            }
            self.pos += 1;
        }
        &self.s[start..self.pos]
    }

    /// The next token on any line, with its line; `None` at the end of the text.
    fn next(&mut self) -> Option<(&'a [u8], usize)> {
        self.skip_ws();
        if self.pos >= self.s.len() { None } else { Some((self.token(), self.line)) }
    }

    /// The next token, or an error naming what was `expected`.
    fn expect_next(&mut self, expected: &'static str) -> Result<(&'a [u8], usize), BvhError> {
        self.next().ok_or(BvhError::UnexpectedEof { line: self.line, expected })
    }

    /// The next token on the current line, if any.
    fn next_on_line(&mut self) -> Option<&'a [u8]> {
        if self.skip_hspace() { Some(self.token()) } else { None }
    }

    fn expect_open_brace(&mut self) -> Result<(), BvhError> {
        let (tok, line) = self.expect_next("{")?;
        if tok != b"{" {
            return Err(BvhError::Unexpected { line, expected: "{", found: quote(tok) });
        }
        Ok(())
    }

    /// `OFFSET x y z`; the keyword is the next token.
    fn offset(&mut self) -> Result<DVec3, BvhError> {
        let (tok, line) = self.expect_next("OFFSET")?;
        if !kw(tok, "OFFSET") {
            return Err(BvhError::MissingOffset { line, found: quote(tok) });
        }
        let mut v = [0.0; 3];
        let mut found = 0;
        while let Some(tok) = self.next_on_line() {
            if found < 3 {
                v[found] = parse_f64(tok, line)?;
            }
            found += 1;
        }
        if found != 3 {
            return Err(BvhError::OffsetArity { line, found });
        }
        Ok(DVec3::from_array(v))
    }

    /// `CHANNELS n names…`; the keyword is the next token.
    fn channels(&mut self) -> Result<Vec<Channel>, BvhError> {
        let (tok, line) = self.expect_next("CHANNELS")?;
        if !kw(tok, "CHANNELS") {
            return Err(BvhError::MissingChannels { line, found: quote(tok) });
        }
        let count = self.next_on_line().ok_or(BvhError::Unexpected {
            line,
            expected: "a channel count",
            found: "end of line".into(),
        })?;
        let declared = parse_count(count, line)?;
        if declared > MAX_CHANNELS_PER_JOINT as u64 {
            return Err(BvhError::LimitExceeded {
                line,
                what: "channels per joint",
                value: declared,
                limit: MAX_CHANNELS_PER_JOINT as u64,
            });
        }
        let declared = declared as usize;
        let mut channels = Vec::with_capacity(declared);
        let mut found = 0;
        while let Some(tok) = self.next_on_line() {
            found += 1;
            if found > declared {
                continue;
            }
            let ch = channel_of(tok).ok_or_else(|| BvhError::UnknownChannel { line, channel: quote(tok) })?;
            if channels.contains(&ch) {
                return Err(BvhError::DuplicateChannel { line, channel: quote(tok) });
            }
            channels.push(ch);
        }
        if found != declared {
            return Err(BvhError::ChannelCount { line, declared, found });
        }
        Ok(channels)
    }

    /// Everything after `ROOT`/`JOINT` up to the joint's children: name, `{`, OFFSET, CHANNELS.
    fn joint_header(
        &mut self,
        keyword: &'static str,
        line: usize,
        parent: Option<usize>,
        depth: usize,
    ) -> Result<(), BvhError> {
        let name = match self.next_on_line() {
            Some(t) if t != b"{" && t != b"}" => t,
            _ => return Err(BvhError::MissingName { line, keyword }),
        };
        if self.joints.len() >= self.limits.max_joints {
            return Err(BvhError::LimitExceeded {
                line,
                what: "joints",
                value: self.joints.len() as u64 + 1,
                limit: self.limits.max_joints as u64,
            });
        }
        if depth > self.limits.max_depth {
            return Err(BvhError::LimitExceeded {
                line,
                what: "hierarchy depth",
                value: depth as u64,
                limit: self.limits.max_depth as u64,
            });
        }
        if !self.names.insert(name) {
            return Err(BvhError::DuplicateJoint { line, name: quote(name) });
        }
        self.expect_open_brace()?;
        let offset = self.offset()?;
        let channels = self.channels()?;
        let first = self.num_channels;
        self.num_channels += channels.len();
        self.joints.push(BvhJoint {
            name: String::from_utf8_lossy(name).into_owned(),
            parent,
            offset,
            channels,
            end_site: None,
            channel_offset: first,
        });
        Ok(())
    }

    /// `End Site { OFFSET x y z }` after the `End` token.
    fn end_site(&mut self) -> Result<DVec3, BvhError> {
        let (tok, line) = self.expect_next("Site")?;
        if !kw(tok, "Site") {
            return Err(BvhError::Unexpected { line, expected: "Site", found: quote(tok) });
        }
        self.expect_open_brace()?;
        let offset = self.offset()?;
        let (tok, line) = self.expect_next("}")?;
        if tok == b"}" {
            Ok(offset)
        } else if kw(tok, "JOINT") || kw(tok, "End") || kw(tok, "CHANNELS") || kw(tok, "OFFSET") {
            Err(BvhError::EndSiteChildren { line })
        } else {
            Err(BvhError::Unexpected { line, expected: "}", found: quote(tok) })
        }
    }

    fn hierarchy(&mut self) -> Result<(), BvhError> {
        let (tok, line) = self.expect_next("HIERARCHY")?;
        if !kw(tok, "HIERARCHY") {
            return Err(BvhError::Unexpected { line, expected: "HIERARCHY", found: quote(tok) });
        }
        let (tok, line) = self.next().ok_or(BvhError::NoRoot { line: self.line })?;
        if !kw(tok, "ROOT") {
            return Err(BvhError::NoRoot { line });
        }
        // Open joints, innermost last: the explicit stack that keeps deep input off the call stack.
        let mut stack: Vec<usize> = Vec::new();
        self.joint_header("ROOT", line, None, 1)?;
        stack.push(0);
        while let Some(&top) = stack.last() {
            let (tok, line) = self.expect_next("}")?;
            if tok == b"}" {
                stack.pop();
            } else if kw(tok, "JOINT") {
                let depth = stack.len() + 1;
                self.joint_header("JOINT", line, Some(top), depth)?;
                stack.push(self.joints.len() - 1);
            } else if kw(tok, "End") {
                if self.joints[top].end_site.is_some() {
                    return Err(BvhError::DuplicateEndSite { line });
                }
                let site = self.end_site()?;
                self.joints[top].end_site = Some(site);
            } else if kw(tok, "ROOT") {
                return Err(BvhError::SecondRoot { line });
            } else if kw(tok, "OFFSET") || kw(tok, "CHANNELS") || kw(tok, "MOTION") || tok == b"{" {
                return Err(BvhError::Unexpected { line, expected: "JOINT, End Site or }", found: quote(tok) });
            } else {
                return Err(BvhError::UnknownKeyword { line, keyword: quote(tok) });
            }
        }
        let (tok, line) = self.expect_next("MOTION")?;
        if kw(tok, "ROOT") {
            return Err(BvhError::SecondRoot { line });
        }
        if !kw(tok, "MOTION") {
            return Err(BvhError::Unexpected { line, expected: "MOTION", found: quote(tok) });
        }
        Ok(())
    }

    /// Matches `label` (case-insensitively) at `pos`, advancing past it.
    fn eat(&mut self, label: &str) -> bool {
        let end = self.pos + label.len();
        match self.s.get(self.pos..end) {
            Some(t) if t.eq_ignore_ascii_case(label.as_bytes()) => {
                self.pos = end;
                true
            }
            _ => false,
        }
    }

    /// A `<words…>:` label line such as `Frame Time:`; returns the value token that follows on the line.
    /// Words are separated by at least one space, `:` may have spaces around it.
    fn labelled(&mut self, words: &[&str], expected: &'static str) -> Result<(&'a [u8], usize), BvhError> {
        self.skip_ws();
        let line = self.line;
        if self.pos >= self.s.len() {
            return Err(BvhError::UnexpectedEof { line, expected });
        }
        let start = self.pos;
        let mismatch = |p: &mut Self| {
            p.pos = start;
            BvhError::Unexpected { line, expected, found: quote(p.token()) }
        };
        for (k, w) in words.iter().enumerate() {
            if k > 0 {
                let before = self.pos;
                if !self.skip_hspace() || self.pos == before {
                    return Err(mismatch(self));
                }
            }
            if !self.eat(w) {
                return Err(mismatch(self));
            }
        }
        self.skip_hspace();
        if !self.eat(":") {
            return Err(mismatch(self));
        }
        let value = self.next_on_line().ok_or(BvhError::Unexpected {
            line,
            expected: "a value after the colon",
            found: "end of line".into(),
        })?;
        if let Some(extra) = self.next_on_line() {
            return Err(BvhError::Unexpected { line, expected: "end of line", found: quote(extra) });
        }
        Ok((value, line))
    }

    fn parse(mut self) -> Result<Bvh, BvhError> {
        let (frames, frame_time) = self.header()?;
        let values = self.rows(frames, self.num_channels)?;
        Ok(Bvh { joints: std::mem::take(&mut self.joints), frame_time, frames, values })
    }

    /// The hierarchy, `Frames:` and `Frame Time:`: everything before the rows.
    fn header(&mut self) -> Result<(usize, f64), BvhError> {
        self.hierarchy()?;
        let (tok, line) = self.labelled(&["Frames"], "Frames:")?;
        let frames = parse_count(tok, line)?;
        if frames == 0 {
            return Err(BvhError::NoFrames { line });
        }
        if frames > self.limits.max_frames as u64 {
            return Err(BvhError::LimitExceeded {
                line,
                what: "frames",
                value: frames,
                limit: self.limits.max_frames as u64,
            });
        }
        let frames = frames as usize;
        let (tok, line) = self.labelled(&["Frame", "Time"], "Frame Time:")?;
        let frame_time = parse_f64(tok, line)?;
        if frame_time <= 0.0 {
            return Err(BvhError::InvalidFrameTime { line, value: frame_time });
        }
        Ok((frames, frame_time))
    }

    /// The frame rows and what follows them.
    fn rows(&mut self, frames: usize, nch: usize) -> Result<Vec<f64>, BvhError> {
        let s = self.s;
        let n = s.len();
        let mut p = self.pos;
        let mut line = self.line;
        // n values take at least 2n - 1 bytes: never reserve more than the text can hold.
        let room = (n - p).div_ceil(2);
        let mut values = Vec::with_capacity(frames.checked_mul(nch).map_or(room, |t| t.min(room)));
        let mut frame = 0;
        if nch > 0 {
            while frame < frames {
                // Blank lines, then the row's first token.
                while p < n {
                    match class(s[p]) {
                        TOKEN => break,
                        NEWLINE => line += 1,
                        _ => {}
                    }
                    p += 1;
                }
                if p >= n {
                    return Err(BvhError::TooFewFrames { line, expected: frames, found: frame });
                }
                let mut found = 0;
                loop {
                    let start = p;
                    while p < n && class(s[p]) == TOKEN {
                        p += 1;
                    }
                    if found < nch {
                        values.push(parse_f64(&s[start..p], line)?);
                    }
                    found += 1;
                    while p < n && class(s[p]) == HSPACE {
                        p += 1;
                    }
                    if p >= n || s[p] == b'\n' {
                        break;
                    }
                }
                if found != nch {
                    return Err(BvhError::WrongValueCount { line, frame, expected: nch, found });
                }
                frame += 1;
            }
        }
        self.pos = p;
        self.line = line;
        self.skip_ws();
        if self.pos < n {
            return Err(BvhError::TooManyFrames { line: self.line, expected: frames });
        }
        Ok(values)
    }
}
