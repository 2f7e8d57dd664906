//! The BVH reader on real files (tests/fixtures) and on the textual variants real files come in.
use motion_stylizer::bvh::{Axis, Bvh, BvhError, Channel, Limits};
use std::path::{Path, PathBuf};

fn fixtures(dir: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(dir);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .collect();
    files.sort();
    files
}

fn read(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn parse(rel: &str) -> Bvh {
    Bvh::parse(&read(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

const ZXY: [Channel; 3] = [Channel::Rotation(Axis::Z), Channel::Rotation(Axis::X), Channel::Rotation(Axis::Y)];
const ZYX: [Channel; 3] = [Channel::Rotation(Axis::Z), Channel::Rotation(Axis::Y), Channel::Rotation(Axis::X)];
const XYZ_POS: [Channel; 3] = [Channel::Position(Axis::X), Channel::Position(Axis::Y), Channel::Position(Axis::Z)];

/// Structural invariants every parsed file satisfies.
fn check_invariants(b: &Bvh) {
    assert!(b.frames >= 1);
    assert!(b.frame_time > 0.0);
    assert_eq!(b.values.len(), b.frames * b.num_channels());
    assert!(b.values.iter().all(|v| v.is_finite()));
    assert_eq!(b.joints[0].parent, None);
    let mut offset = 0;
    for (i, j) in b.joints.iter().enumerate() {
        if i > 0 {
            assert!(j.parent.is_some_and(|p| p < i), "joint {i}");
        }
        assert_eq!(j.channel_offset, offset);
        offset += j.channels.len();
    }
}

#[test]
fn every_fixture_parses() {
    let files: Vec<PathBuf> = fixtures("bandai").into_iter().chain(fixtures("foreign")).collect();
    assert!(files.len() >= 8, "fixtures missing: {files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let b = Bvh::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        check_invariants(&b);
    }
}

#[test]
fn bandai_rig() {
    let cases = [
        ("bandai/dataset-1_walk_tired_001_f90.bvh", 90),
        ("bandai/dataset-2_raise-up-both-hands_active_001.bvh", 38),
        ("bandai/dataset-2_walk_elderly_001_f120.bvh", 120),
        ("bandai/dataset-2_walk_normal_001_f120.bvh", 120),
    ];
    for (file, frames) in cases {
        let b = parse(file);
        assert_eq!(b.joints.len(), 22, "{file}");
        assert_eq!(b.joints[0].name, "joint_Root");
        assert_eq!(b.joints[1].name, "Hips");
        assert_eq!(b.joint_index("Hips"), Some(1));
        assert_eq!(b.frames, frames, "{file}");
        assert_eq!(b.frame_time, 0.0333333);
        assert!((b.fps() - 30.0).abs() < 1e-3);
        assert_eq!(b.num_channels(), 132);
        for j in &b.joints {
            let order = [XYZ_POS.as_slice(), ZXY.as_slice()].concat();
            assert_eq!(j.channels, order, "{file} {}", j.name);
        }
        assert_eq!(b.joints.iter().filter(|j| j.end_site.is_some()).count(), 5);
    }
}

#[test]
fn bandai_values() {
    // dataset-1 writes `%g`-style numbers, scientific notation included.
    let b = parse("bandai/dataset-1_walk_tired_001_f90.bvh");
    assert_eq!(b.joints[1].offset.to_array(), [0.847027, 93.984, -452.225]);
    assert_eq!(b.joints[2].offset.to_array(), [15.7357, 0.0, 0.0]);
    let row = b.frame(0);
    assert_eq!(&row[..9], &[0.0, 0.0, 0.0, 0.0, 0.0, -0.0, 6.67187, 90.614, -440.606]);
    assert_eq!(row[5].to_bits(), (-0.0f64).to_bits());
    assert_eq!(&row[12..15], &[15.7357, 5.1072e-06, -5.51765e-07]);
    // dataset-2 writes fixed 6 decimals and a trailing space after CHANNELS.
    let b = parse("bandai/dataset-2_walk_normal_001_f120.bvh");
    assert_eq!(b.joints[1].offset.to_array(), [-0.726466, 93.3139, -2.00062]);
    assert_eq!(&b.frame(0)[6..9], &[1.12056, 93.1488, -543.347]);
}

#[test]
fn cmu31_rig() {
    let b = parse("foreign/cmu31_xia_neutral_16_000.bvh");
    assert_eq!(b.joints.len(), 31);
    assert_eq!(b.frames, 150);
    assert_eq!(b.frame_time, 0.008333);
    assert!((b.fps() - 120.0).abs() < 0.01);
    assert_eq!(b.joints[0].name, "Hips");
    assert_eq!(b.joints[0].channels, [XYZ_POS.as_slice(), ZYX.as_slice()].concat());
    assert!(b.joints[1..].iter().all(|j| j.channels == ZYX));
    assert_eq!(b.num_channels(), 6 + 30 * 3);
    assert_eq!(b.joints.iter().filter(|j| j.end_site.is_some()).count(), 7);
    assert_eq!(&b.frame(0)[..3], &[19.939872, 16.850014, 1.430627]);

    let rest = parse("foreign/cmu31_rest.bvh");
    assert_eq!(rest.joints.len(), 31);
    assert_eq!(rest.frames, 1);
    assert_eq!(rest.frame_time, 0.041667);
    let names = |b: &Bvh| b.joints.iter().map(|j| j.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&rest), names(&b));
}

#[test]
fn iclone100_rig() {
    let b = parse("foreign/iclone100_cmu_002_04.bvh");
    assert_eq!(b.joints.len(), 100);
    assert_eq!(b.joints[0].name, "CC_Base_Hip");
    assert_eq!(b.joints[0].offset.to_array(), [0.0, 105.214226, 0.000021]);
    assert_eq!(b.frames, 241);
    assert_eq!(b.frame_time, 0.016667);
    assert!((b.fps() - 60.0).abs() < 0.01);
    assert_eq!(b.num_channels(), 6 + 99 * 3);
    assert_eq!(b.joints.iter().filter(|j| j.end_site.is_some()).count(), 41);
    assert_eq!(b.joints[1].offset.to_array(), [-0.0, -0.000069, 0.000001]);
}

#[test]
fn m21_rig() {
    let b = parse("foreign/m21_walk.bvh");
    assert_eq!(b.joints.len(), 21);
    assert_eq!(b.frames, 162);
    assert_eq!(b.frame_time, 0.016667);
    assert!((b.fps() - 60.0).abs() < 0.01);
    assert_eq!(b.num_channels(), 6 + 20 * 3);
    assert_eq!(b.joints.iter().filter(|j| j.end_site.is_some()).count(), 5);
    assert_eq!(b.joints[1].name, "LeftUpLeg");
    assert_eq!(b.joints[1].offset.to_array(), [7.693656, -10.129610, 4.737288]);
}

/// Textual variants of a fixture that must parse to exactly the same [`Bvh`].
#[test]
fn layout_variants_parse_identically() {
    for file in ["bandai/dataset-1_walk_tired_001_f90.bvh", "foreign/cmu31_xia_neutral_16_000.bvh"] {
        let text = read(file);
        let want = Bvh::parse(&text).unwrap();
        let (header, motion) = text.split_at(text.find("MOTION").unwrap());
        let rows_at = motion.match_indices('\n').nth(2).unwrap().0 + 1;
        let (motion_head, rows) = motion.split_at(rows_at);
        let keywords_recased = [
            ("HIERARCHY", "hierarchy"),
            ("ROOT ", "root "),
            ("JOINT ", "Joint "),
            ("OFFSET", "offset"),
            ("CHANNELS", "Channels"),
            ("End Site", "END site"),
            ("rotation", "ROTATION"),
            ("Xposition", "xPosition"),
        ]
        .iter()
        .fold(header.to_string(), |h, (a, b)| h.replace(a, b))
            + &motion_head.replace("MOTION", "Motion").replace("Frames", "FRAMES").replace("Frame Time", "frame time")
            + rows;
        // `{` moved up onto the line of its ROOT / JOINT / End Site.
        let mut braces_up = String::new();
        for line in text.split_inclusive('\n') {
            if line.trim() == "{" {
                braces_up.truncate(braces_up.trim_end().len());
                braces_up.push_str(" {\n");
            } else {
                braces_up.push_str(line);
            }
        }
        let variants: Vec<(&str, String)> = vec![
            ("CRLF", text.replace('\n', "\r\n")),
            ("tabs", text.replace(' ', "\t")),
            ("spaces", text.replace('\t', "    ")),
            ("no final newline", text.trim_end().to_string()),
            ("trailing blank lines", format!("{text}\n\n  \t\n\r\n")),
            ("trailing spaces", text.replace('\n', " \t\n")),
            ("blank lines", text.replace('\n', "\n\n")),
            ("leading blank lines and BOM", format!("\u{feff}\n\n{text}")),
            ("keywords in other cases", keywords_recased),
            ("braces on keyword lines", braces_up),
            ("End Site spacing", text.replace("End Site", "End \t  Site")),
            ("End Site over two lines", text.replace("End Site", "End\n  Site")),
            ("Frames: tight", text.replace("Frames:\t", "Frames:").replace("Frames: ", "Frames:")),
            ("Frames: loose", text.replace("Frames:\t", "Frames  :  \t").replace("Frames: ", "Frames  :  \t")),
            ("Frame Time: tight", text.replace("Frame Time:\t", "Frame Time:").replace("Frame Time: ", "Frame Time:")),
            ("Frame Time: loose", text.replace("Frame Time:", "Frame \t Time :")),
            ("plus signs", format!("{header}{motion_head}{}", rows.replace(" 1", " +1"))),
        ];
        for (name, variant) in variants {
            let got = Bvh::parse(&variant).unwrap_or_else(|e| panic!("{file}, {name}: {e}"));
            assert_eq!(got, want, "{file}, {name}");
        }
    }
}

/// Every number rewritten in scientific notation (`1.2345e1`, `5.1072e-6`) reads back bit-identical.
#[test]
fn scientific_notation() {
    let text = read("foreign/m21_walk.bvh");
    let want = Bvh::parse(&text).unwrap();
    let mut sci = String::new();
    for line in text.split_inclusive('\n') {
        let mut first = true;
        let mut after_channels = false;
        for tok in line.split_whitespace() {
            if !first {
                sci.push(' ');
            }
            first = false;
            match tok.parse::<f64>() {
                Ok(v) if !after_channels && !line.starts_with("Frames") => sci.push_str(&format!("{v:e}")),
                _ => sci.push_str(tok),
            }
            after_channels = tok == "CHANNELS";
        }
        sci.push('\n');
    }
    assert!(sci.contains("1.53961227e2"));
    let got = Bvh::parse(&sci).unwrap();
    assert_eq!(got, want);
    // Upper-case E, explicit signs, no leading digit.
    let small = SMALL.replace("0 90 0 0 0 0 10 0 0", "0E0 9.0E+1 -0e-3 .0 0. 0 1E1 0 0");
    let b = Bvh::parse(&small).unwrap();
    assert_eq!(&b.frame(0)[..3], &[0.0, 90.0, -0.0]);
    assert_eq!(b.frame(0)[6], 10.0);
}

/// A hand-written file with two joints, an End Site and two frames.
const SMALL: &str = include_str!("fixtures/small.bvh");

#[test]
fn any_channel_layout() {
    // Channel counts 0..=6 in unusual orders, position channels below the root, case-insensitive names.
    let text = "HIERARCHY
ROOT Root
{
  OFFSET 1 2 3
  CHANNELS 0
  JOINT A
  {
    OFFSET 0 1 0
    CHANNELS 1 yrotation
    JOINT B
    {
      OFFSET 0 1 0
      CHANNELS 2 Zposition XROTATION
      End Site
      {
        OFFSET 0 0 1
      }
    }
  }
  JOINT C
  {
    OFFSET 1 0 0
    CHANNELS 6 Yrotation Zposition Xrotation Xposition Zrotation Yposition
  }
  JOINT D
  {
    OFFSET 2 0 0
    CHANNELS 4 Xposition Xrotation Yrotation Zrotation
  }
  JOINT E
  {
    OFFSET 3 0 0
    CHANNELS 5 Xposition Yposition Zrotation Xrotation Yrotation
  }
}
MOTION
Frames: 1
Frame Time: 2.5
90 7 30 1 2 3 4 5 6 8 0 0 0 9 10 0 0 0
";
    let b = Bvh::parse(text).unwrap();
    check_invariants(&b);
    let counts: Vec<usize> = b.joints.iter().map(|j| j.channels.len()).collect();
    assert_eq!(counts, [0, 1, 2, 6, 4, 5]);
    assert_eq!(
        b.joints.iter().map(|j| j.parent).collect::<Vec<_>>(),
        [None, Some(0), Some(1), Some(0), Some(0), Some(0)]
    );
    assert_eq!(b.joints[2].channels, [Channel::Position(Axis::Z), Channel::Rotation(Axis::X)]);
    assert_eq!(b.joints[2].end_site.map(|v| v.to_array()), Some([0.0, 0.0, 1.0]));
    assert_eq!(b.frame_time, 2.5);
    assert_eq!(b.fps(), 0.4);
    // B: OFFSET (0, 1, 0) with Z replaced by its Zposition channel (7).
    let (t, _) = b.local_transform(0, 2);
    assert_eq!(t.to_array(), [0.0, 1.0, 7.0]);
    // C: positions X = 4, Z = 2, Y = 6.
    let (t, _) = b.local_transform(0, 3);
    assert_eq!(t.to_array(), [4.0, 6.0, 2.0]);
    assert_eq!(b.joints[4].channel_offset, 9);
    assert_eq!(b.frame(0)[9], 8.0);
}

#[test]
fn zero_channels_and_single_frame() {
    let text = "HIERARCHY\nROOT R\n{\n OFFSET 0 0 0\n CHANNELS 0\n JOINT A\n {\n  OFFSET 0 1 0\n  CHANNELS 0\n }\n}\nMOTION\nFrames: 3\nFrame Time: 0.01\n\n";
    let b = Bvh::parse(text).unwrap();
    assert_eq!((b.frames, b.num_channels(), b.values.len()), (3, 0, 0));
    let (pos, _) = b.global_pose(2);
    assert_eq!(pos[1].to_array(), [0.0, 1.0, 0.0]);
    let err = Bvh::parse(&format!("{text}0\n")).unwrap_err();
    assert_eq!(err, BvhError::TooManyFrames { line: 16, expected: 3 });
}

#[test]
fn frame_time_any_positive() {
    for (ft, want) in [("1e-3", 1e-3), ("0.5", 0.5), ("2", 2.0), ("8.333e-03", 8.333e-3)] {
        let b = Bvh::parse(&SMALL.replace("0.0333333", ft)).unwrap();
        assert_eq!(b.frame_time, want);
    }
}

#[test]
fn global_pose_of_small_file() {
    let b = Bvh::parse(SMALL).unwrap();
    // Frame 1: root at (1, 90, 0); Spine rotated 20° about Z, its End Site 5 up along the rotated Y.
    let (pos, rot) = b.global_pose(1);
    assert_eq!(pos[0].to_array(), [1.0, 90.0, 0.0]);
    assert_eq!(pos[1].to_array(), [1.0, 100.0, 0.0]);
    let tip = pos[1] + rot[1] * b.joints[1].end_site.unwrap();
    let a = 20f64.to_radians();
    assert!((tip.x - (1.0 - 5.0 * a.sin())).abs() < 1e-12);
    assert!((tip.y - (100.0 + 5.0 * a.cos())).abs() < 1e-12);
}

#[test]
fn limits_are_configurable() {
    let text = read("bandai/dataset-1_walk_tired_001_f90.bvh");
    let small = |f: fn(&mut Limits)| {
        let mut l = Limits::default();
        f(&mut l);
        Bvh::parse_with_limits(&text, &l)
    };
    assert!(small(|_| {}).is_ok());
    assert_eq!(
        small(|l| l.max_frames = 89).unwrap_err(),
        BvhError::LimitExceeded { line: 133, what: "frames", value: 90, limit: 89 }
    );
    assert!(small(|l| l.max_frames = 90).is_ok());
    assert_eq!(
        small(|l| l.max_joints = 21).unwrap_err(),
        BvhError::LimitExceeded { line: 118, what: "joints", value: 22, limit: 21 }
    );
    assert!(matches!(
        small(|l| l.max_depth = 3).unwrap_err(),
        BvhError::LimitExceeded { line: 14, what: "hierarchy depth", value: 4, limit: 3 }
    ));
    assert_eq!(
        small(|l| l.max_bytes = 1000).unwrap_err(),
        BvhError::LimitExceeded { line: 1, what: "bytes", value: text.len() as u64, limit: 1000 }
    );
    let l = Limits { max_bytes: 1000, ..Limits::default() };
    assert!(matches!(Bvh::parse_bytes(text.as_bytes(), &l), Err(BvhError::LimitExceeded { what: "bytes", .. })));
    assert_eq!(Bvh::parse_bytes(text.as_bytes(), &Limits::default()).unwrap(), Bvh::parse(&text).unwrap());
    let d = Limits::default();
    assert_eq!((d.max_bytes, d.max_joints, d.max_depth, d.max_frames), (64 << 20, 1024, 256, 1_000_000));
}

#[test]
fn errors_name_their_line() {
    let err = Bvh::parse(&SMALL.replace("1 90 0 0 0 0 20 0 0", "1 90 0 0 0 0 20 0")).unwrap_err();
    assert_eq!(err, BvhError::WrongValueCount { line: 20, frame: 1, expected: 9, found: 8 });
    assert_eq!(err.line(), 20);
    assert_eq!(err.kind(), "WrongValueCount");
    assert_eq!(err.to_string(), "line 20: frame 1 has 8 values, expected 9");
    // Quoted tokens are cut short.
    let long = "x".repeat(10_000);
    let err = Bvh::parse(&SMALL.replace("JOINT Spine", &long)).unwrap_err();
    match err {
        BvhError::UnknownKeyword { line: 6, keyword } => assert!(keyword.len() < 50, "{keyword}"),
        e => panic!("{e:?}"),
    }
}
