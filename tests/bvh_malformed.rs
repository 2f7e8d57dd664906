//! Malformed BVH: each file of tests/malformed/ fails with its own error variant on its own line, and
//! the reader never panics, hangs or overflows the stack on broken, deep or huge input.
use motion_stylizer::bvh::{Bvh, BvhError, Limits};
use std::collections::BTreeSet;
use std::path::Path;

/// `(file stem, error variant, 1-based line)` for every file in tests/malformed/.
const EXPECTED: &[(&str, &str, usize)] = &[
    ("channel_count_missing", "Unexpected", 9),
    ("channel_count_not_a_number", "NotANumber", 9),
    ("channel_count_too_few_names", "ChannelCount", 5),
    ("channel_count_too_many_names", "ChannelCount", 9),
    ("channels_over_limit", "LimitExceeded", 5),
    ("comma_decimal", "NotANumber", 20),
    ("crlf_wrong_value_count", "WrongValueCount", 20),
    ("duplicate_channel", "DuplicateChannel", 9),
    ("duplicate_end_site", "DuplicateEndSite", 14),
    ("duplicate_joint", "DuplicateJoint", 6),
    ("empty", "UnexpectedEof", 1),
    ("end_site_missing_offset", "MissingOffset", 12),
    ("end_site_with_channels", "EndSiteChildren", 13),
    ("end_site_with_children", "EndSiteChildren", 13),
    ("end_without_site", "Unexpected", 11),
    ("eof_inside_end_site", "UnexpectedEof", 13),
    ("eof_inside_hierarchy", "UnexpectedEof", 10),
    ("extra_close_brace", "Unexpected", 16),
    ("frame_time_missing", "Unexpected", 18),
    ("frame_time_nan", "NonFinite", 18),
    ("frame_time_negative", "InvalidFrameTime", 18),
    ("frame_time_zero", "InvalidFrameTime", 18),
    ("frames_absurd", "LimitExceeded", 17),
    ("frames_fractional", "NotANumber", 17),
    ("frames_line_missing", "Unexpected", 17),
    ("frames_missing_value", "Unexpected", 17),
    ("frames_negative", "NotANumber", 17),
    ("frames_overflow_u64", "LimitExceeded", 17),
    ("frames_trailing_junk", "Unexpected", 17),
    ("frames_zero", "NoFrames", 17),
    ("inf_value", "NonFinite", 19),
    ("joint_name_with_space", "Unexpected", 6),
    ("joint_named_brace", "MissingName", 6),
    ("joint_without_name", "MissingName", 6),
    // A lone CR is not a line end: the whole file is line 1, and OFFSET swallows the rest of it.
    ("lone_cr_line_endings", "OffsetArity", 1),
    ("missing_channels", "MissingChannels", 9),
    ("missing_close_brace", "Unexpected", 15),
    ("missing_motion", "UnexpectedEof", 16),
    ("missing_offset", "MissingOffset", 8),
    ("missing_open_brace", "Unexpected", 7),
    ("more_rows_than_frames", "TooManyFrames", 20),
    ("motion_keyword_misspelled", "Unexpected", 16),
    ("nan_offset", "NonFinite", 8),
    ("nan_value", "NonFinite", 19),
    ("no_hierarchy_keyword", "Unexpected", 1),
    ("no_root", "NoRoot", 2),
    ("non_numeric_value", "NotANumber", 20),
    ("not_utf8", "NotUtf8", 6),
    ("offset_four_values", "OffsetArity", 8),
    ("offset_not_a_number", "NotANumber", 8),
    ("offset_two_values", "OffsetArity", 8),
    ("offset_wrapped_line", "OffsetArity", 8),
    ("only_hierarchy", "NoRoot", 2),
    ("open_brace_in_body", "Unexpected", 10),
    ("overflowing_value", "NonFinite", 20),
    ("root_inside_joint", "SecondRoot", 10),
    ("root_without_name", "MissingName", 2),
    ("row_too_few_values", "WrongValueCount", 19),
    ("row_too_many_values", "WrongValueCount", 20),
    ("row_wrapped_over_two_lines", "WrongValueCount", 19),
    ("second_root", "SecondRoot", 16),
    ("stray_text_after_frames", "TooManyFrames", 22),
    ("truncated_mid_row", "WrongValueCount", 20),
    ("truncated_motion", "TooFewFrames", 21),
    ("unknown_channel", "UnknownChannel", 9),
    ("unknown_keyword", "UnknownKeyword", 10),
    ("whitespace_only", "UnexpectedEof", 4),
];

fn malformed_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/malformed")
}

#[test]
fn every_malformed_file_fails_as_expected() {
    let on_disk: BTreeSet<String> = std::fs::read_dir(malformed_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    let listed: BTreeSet<String> = EXPECTED.iter().map(|e| e.0.to_string()).collect();
    assert_eq!(on_disk, listed, "tests/malformed/ and EXPECTED disagree");
    assert!(listed.len() >= 30);
    for &(stem, kind, line) in EXPECTED {
        let bytes = std::fs::read(malformed_dir().join(format!("{stem}.bvh"))).unwrap();
        let err = match Bvh::parse_bytes(&bytes, &Limits::default()) {
            Ok(_) => panic!("{stem}: parsed"),
            Err(e) => e,
        };
        assert_eq!((err.kind(), err.line()), (kind, line), "{stem}: {err}");
        assert!(err.to_string().starts_with(&format!("line {line}: ")), "{stem}: {err}");
        if let Ok(text) = std::str::from_utf8(&bytes) {
            assert_eq!(Bvh::parse(text), Err(err), "{stem}: parse and parse_bytes disagree");
        }
    }
}

#[test]
fn some_errors_in_full() {
    let err = |stem: &str| {
        let text = std::fs::read_to_string(malformed_dir().join(format!("{stem}.bvh"))).unwrap();
        Bvh::parse(&text).unwrap_err()
    };
    assert_eq!(err("truncated_motion"), BvhError::TooFewFrames { line: 21, expected: 3, found: 2 });
    assert_eq!(err("row_too_few_values"), BvhError::WrongValueCount { line: 19, frame: 0, expected: 9, found: 8 });
    assert_eq!(err("channel_count_too_few_names"), BvhError::ChannelCount { line: 5, declared: 6, found: 5 });
    assert_eq!(
        err("frames_absurd"),
        BvhError::LimitExceeded { line: 17, what: "frames", value: 1_000_000_000_000, limit: 1_000_000 }
    );
    assert_eq!(
        err("channels_over_limit"),
        BvhError::LimitExceeded { line: 5, what: "channels per joint", value: 7, limit: 6 }
    );
    assert_eq!(err("frame_time_negative"), BvhError::InvalidFrameTime { line: 18, value: -0.0333333 });
    assert_eq!(err("duplicate_joint"), BvhError::DuplicateJoint { line: 6, name: "Hips".into() });
    assert_eq!(err("nan_value"), BvhError::NonFinite { line: 19, token: "nan".into() });
    assert_eq!(err("more_rows_than_frames"), BvhError::TooManyFrames { line: 20, expected: 1 });
    assert_eq!(
        err("missing_close_brace"),
        BvhError::Unexpected { line: 15, expected: "JOINT, End Site or }", found: "MOTION".into() }
    );
    assert_eq!(err("extra_close_brace"), BvhError::Unexpected { line: 16, expected: "MOTION", found: "}".into() });
}

/// `depth` joints nested in one another (ROOT included), each with `CHANNELS 0`, then `frames` lines.
fn nested(depth: usize, close: bool) -> String {
    let mut s = String::with_capacity(depth * 48);
    s.push_str("HIERARCHY\n");
    for i in 0..depth {
        s.push_str(if i == 0 { "ROOT" } else { "JOINT" });
        s.push_str(&format!(" j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 0\n"));
    }
    if close {
        for _ in 0..depth {
            s.push_str("}\n");
        }
        s.push_str("MOTION\nFrames: 1\nFrame Time: 0.1\n");
    }
    s
}

#[test]
fn hundred_thousand_nested_joints() {
    let text = nested(100_000, true);
    // ROOT is line 2, joint i at line 2 + 4i: the 257th level (j256) is the first beyond max_depth.
    assert_eq!(
        Bvh::parse(&text),
        Err(BvhError::LimitExceeded { line: 2 + 4 * 256, what: "hierarchy depth", value: 257, limit: 256 })
    );
    // Without limits it still runs in constant stack: the parser is iterative.
    let unlimited = Limits { max_bytes: usize::MAX, max_joints: usize::MAX, max_depth: usize::MAX, max_frames: 1 };
    let b = Bvh::parse_with_limits(&text, &unlimited).unwrap();
    assert_eq!(b.joints.len(), 100_000);
    assert_eq!(b.joints[99_999].parent, Some(99_998));
    // Unclosed: runs out at the end of the text.
    let open = nested(100_000, false);
    assert!(matches!(Bvh::parse_with_limits(&open, &unlimited), Err(BvhError::UnexpectedEof { expected: "}", .. })));
}

#[test]
fn huge_joint_count() {
    // 5000 siblings under the root: the 1025th joint (line 2 + 4 × 1024) is refused.
    let mut text = String::from("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n");
    for i in 1..5000 {
        text.push_str(&format!("JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 0\n}}\n"));
    }
    text.push_str("}\nMOTION\nFrames: 1\nFrame Time: 0.1\n");
    let line = 6 + 5 * 1023;
    assert_eq!(Bvh::parse(&text), Err(BvhError::LimitExceeded { line, what: "joints", value: 1025, limit: 1024 }));
    assert_eq!(text.lines().nth(line - 1), Some("JOINT j1024"));
}

#[test]
fn file_over_max_bytes() {
    let text = format!("{}{}", SMALL, " ".repeat(1000));
    let limits = Limits { max_bytes: 1000, ..Limits::default() };
    let want = BvhError::LimitExceeded { line: 1, what: "bytes", value: text.len() as u64, limit: 1000 };
    assert_eq!(Bvh::parse_with_limits(&text, &limits), Err(want.clone()));
    assert_eq!(Bvh::parse_bytes(text.as_bytes(), &limits), Err(want));
    assert!(Bvh::parse(&text).is_ok());
}

#[test]
fn frame_count_at_and_over_the_limit() {
    // At the limit but truncated: reported at the end, without allocating a million rows up front.
    let text = SMALL.replace("Frames: 2", "Frames: 1000000");
    assert_eq!(Bvh::parse(&text), Err(BvhError::TooFewFrames { line: 21, expected: 1_000_000, found: 2 }));
    let text = SMALL.replace("Frames: 2", "Frames: 1000001");
    assert!(matches!(Bvh::parse(&text), Err(BvhError::LimitExceeded { line: 17, what: "frames", .. })));
}

/// A hand-written file with two joints, an End Site and two frames.
const SMALL: &str = include_str!("fixtures/small.bvh");

fn fixture(rel: &str) -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(rel)).unwrap()
}

/// Whatever the outcome, it is sane: an error names a line of the input, a success writes back.
fn check(bytes: &[u8]) {
    let lines = 1 + bytes.iter().filter(|&&b| b == b'\n').count();
    match Bvh::parse_bytes(bytes, &Limits::default()) {
        Err(e) => assert!((1..=lines).contains(&e.line()), "{e} (input has {lines} lines)"),
        Ok(b) => {
            let again = Bvh::parse(&b.to_bvh_string()).expect("our output parses");
            assert_eq!((again.joints.len(), again.frames), (b.joints.len(), b.frames));
        }
    }
}

#[test]
fn every_truncation_of_a_real_file() {
    let bytes = fixture("foreign/cmu31_rest.bvh");
    for len in 0..=bytes.len() {
        check(&bytes[..len]);
    }
    // A larger file with every rig feature, every 61st prefix.
    let bytes = fixture("bandai/dataset-2_raise-up-both-hands_active_001.bvh");
    for len in (0..=bytes.len()).step_by(61) {
        check(&bytes[..len]);
    }
}

#[test]
fn random_byte_flips() {
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut rand = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let bases = [
        fixture("foreign/cmu31_rest.bvh"),
        fixture("foreign/m21_walk.bvh")[..8000].to_vec(),
        SMALL.as_bytes().to_vec(),
    ];
    let interesting = b" \t\r\n{}:.-+e0123456789ENXYZ";
    let mut parsed = 0;
    for round in 0..3000 {
        let mut bytes = bases[round % bases.len()].clone();
        for _ in 0..1 + rand() % 8 {
            let at = (rand() % bytes.len() as u64) as usize;
            let r = rand();
            match r % 4 {
                0 => bytes[at] = (r >> 8) as u8,
                1 => bytes[at] = interesting[(r >> 8) as usize % interesting.len()],
                2 => {
                    bytes.remove(at);
                }
                _ => bytes.insert(at, interesting[(r >> 8) as usize % interesting.len()]),
            }
        }
        check(&bytes);
        check(String::from_utf8_lossy(&bytes).as_bytes());
        parsed += Bvh::parse_bytes(&bytes, &Limits::default()).is_ok() as usize;
    }
    // Some mutants (a changed digit, say) are still valid files.
    assert!(parsed > 0);
}
