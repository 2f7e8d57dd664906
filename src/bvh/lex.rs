//! The reader's lexical pieces: byte classes, keywords, channel names and numbers (an exact fast
//! path for plain decimals).

use super::error::quote;
use super::{Axis, BvhError, Channel};

// Byte classes: 0 = part of a token, 1 = horizontal space, 2 = newline.
pub(super) const TOKEN: u8 = 0;
pub(super) const HSPACE: u8 = 1;
pub(super) const NEWLINE: u8 = 2;
static CLASS: [u8; 256] = {
    let mut t = [TOKEN; 256];
    t[b' ' as usize] = HSPACE;
    t[b'\t' as usize] = HSPACE;
    t[b'\r' as usize] = HSPACE;
    t[0x0b] = HSPACE;
    t[0x0c] = HSPACE;
    t[b'\n' as usize] = NEWLINE;
    t
};

#[inline(always)]
pub(super) fn class(b: u8) -> u8 {
    CLASS[b as usize]
}

pub(super) fn kw(tok: &[u8], keyword: &str) -> bool {
    tok.eq_ignore_ascii_case(keyword.as_bytes())
}

pub(super) fn channel_of(tok: &[u8]) -> Option<Channel> {
    if tok.len() != 9 {
        return None;
    }
    let axis = match tok[0] {
        b'X' | b'x' => Axis::X,
        b'Y' | b'y' => Axis::Y,
        b'Z' | b'z' => Axis::Z,
        _ => return None,
    };
    if tok[1..].eq_ignore_ascii_case(b"position") {
        Some(Channel::Position(axis))
    } else if tok[1..].eq_ignore_ascii_case(b"rotation") {
        Some(Channel::Rotation(axis))
    } else {
        None
    }
}

static POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// Parses a number token. Plain decimals (`-12.345678`, up to 19 digits with a mantissa ≤ 2⁵³) take an
/// exact fast path (Clinger: one correctly rounded division); everything else goes through
/// `str::parse::<f64>`, which is correctly rounded too, so the result never depends on the path.
#[inline]
pub(super) fn parse_f64(tok: &[u8], line: usize) -> Result<f64, BvhError> {
    let mut i = 0;
    let neg = match tok.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut mantissa: u64 = 0;
    let mut digits = 0u32;
    while i < tok.len() && tok[i].is_ascii_digit() {
        mantissa = mantissa.wrapping_mul(10).wrapping_add((tok[i] - b'0') as u64);
        digits += 1;
        i += 1;
    }
    let mut frac = 0usize;
    if i < tok.len() && tok[i] == b'.' {
        i += 1;
        while i < tok.len() && tok[i].is_ascii_digit() {
            mantissa = mantissa.wrapping_mul(10).wrapping_add((tok[i] - b'0') as u64);
            digits += 1;
            frac += 1;
            i += 1;
        }
    }
    if i == tok.len() && digits > 0 && digits <= 19 && mantissa <= (1u64 << 53) && frac < POW10.len() {
        let v = mantissa as f64 / POW10[frac];
        return Ok(if neg { -v } else { v });
    }
    parse_f64_slow(tok, line)
}

#[cold]
fn parse_f64_slow(tok: &[u8], line: usize) -> Result<f64, BvhError> {
    let parsed = std::str::from_utf8(tok).ok().and_then(|s| s.parse::<f64>().ok());
    match parsed {
        None => Err(BvhError::NotANumber { line, token: quote(tok) }),
        Some(v) if !v.is_finite() => Err(BvhError::NonFinite { line, token: quote(tok) }),
        Some(v) => Ok(v),
    }
}

/// Parses an unsigned decimal count (saturating at `u64::MAX`).
pub(super) fn parse_count(tok: &[u8], line: usize) -> Result<u64, BvhError> {
    if tok.is_empty() || !tok.iter().all(u8::is_ascii_digit) {
        return Err(BvhError::NotANumber { line, token: quote(tok) });
    }
    Ok(tok.iter().fold(0u64, |n, &d| n.saturating_mul(10).saturating_add((d - b'0') as u64)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast path agrees bit for bit with `str::parse` on decimals of every shape it takes.
    #[test]
    fn fast_float_path_is_exact() {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..200_000 {
            let int_digits = (next() % 8) as usize;
            let frac_digits = (next() % 12) as usize;
            let mut s = String::new();
            if next() % 2 == 0 {
                s.push('-');
            }
            for _ in 0..int_digits.max(1) {
                s.push((b'0' + (next() % 10) as u8) as char);
            }
            if frac_digits > 0 {
                s.push('.');
                for _ in 0..frac_digits {
                    s.push((b'0' + (next() % 10) as u8) as char);
                }
            }
            let want: f64 = s.parse().unwrap();
            let got = parse_f64(s.as_bytes(), 1).unwrap();
            assert_eq!(got.to_bits(), want.to_bits(), "{s}");
        }
        for s in ["9007199254740993", "0.1", "-0", "1e-05", "1.2E+3", ".5", "5.", "+7", "123456789012345678901234"] {
            let want: f64 = s.parse().unwrap();
            assert_eq!(parse_f64(s.as_bytes(), 1).unwrap().to_bits(), want.to_bits(), "{s}");
        }
        for s in ["", "-", ".", "1.2.3", "1e", "abc", "0x10", "1,5"] {
            assert!(matches!(parse_f64(s.as_bytes(), 3), Err(BvhError::NotANumber { line: 3, .. })), "{s}");
        }
        for s in ["nan", "NaN", "inf", "-infinity", "1e400"] {
            assert!(matches!(parse_f64(s.as_bytes(), 3), Err(BvhError::NonFinite { line: 3, .. })), "{s}");
        }
    }
}
