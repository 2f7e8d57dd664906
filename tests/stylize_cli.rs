//! `motion-stylizer stylize` and `styles` through the binary: outputs, rigs, seeds, file names and
//! error messages.
//!
//! The weights folder holds UNTRAINED networks (see `stylize_support`): plumbing only; the quality
//! test is `tests/stylize_quality.rs` (ignored until trained weights are committed).
#![cfg(feature = "model")]

mod stylize_support;

use motion_stylizer::bvh::Bvh;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use stylize_support::*;

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_motion-stylizer")).args(args).output().expect("run the CLI")
}

fn ok(args: &[&str]) -> Output {
    let out = cli(args);
    assert!(out.status.success(), "{args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    out
}

fn fails<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(args: &[S]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_motion-stylizer")).args(args).output().expect("run the CLI");
    assert!(!out.status.success(), "{args:?} should fail");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn fixture(dir: &str, name: &str) -> String {
    fixture_path(dir, name).to_str().unwrap().to_string()
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// `stylize CONTENT --weights W -o OUT` + `extra`; returns OUT.
fn stylize(content: &str, out: &Path, extra: &[&str]) -> PathBuf {
    let w = weights_dir();
    let mut args = vec!["stylize", content, "--weights", s(w), "-o", s(out)];
    args.extend_from_slice(extra);
    ok(&args);
    out.to_path_buf()
}

#[test]
fn same_seed_same_bytes_other_seed_other_bytes() {
    let dir = out_dir("cli-seed");
    let content = fixture("bandai", SHORT);
    for extra in [&["--label", "old"][..], &["--prior", "--unsupervised"][..]] {
        let run = |seed: &str, name: &str| {
            let mut args = extra.to_vec();
            args.extend_from_slice(&["--seed", seed]);
            read(&stylize(&content, &dir.join(name), &args))
        };
        let a = run("7", "a.bvh");
        assert_eq!(a, run("7", "b.bvh"), "{extra:?}: same seed, other bytes");
        assert_ne!(a, run("8", "c.bvh"), "{extra:?}: other seed, same bytes");
        let bvh = Bvh::parse(std::str::from_utf8(&a).unwrap()).unwrap();
        assert_eq!(bvh.frames, 38);
    }
}

#[test]
fn foreign_reference_output_on_the_content_rig_or_canonical() {
    let dir = out_dir("cli-rig");
    let content = fixture("bandai", SHORT);
    let reference = fixture("foreign", "m21_walk");
    let content_bvh = Bvh::parse(&fixture_text("bandai", SHORT)).unwrap();
    for extra in [&["--unsupervised"][..], &["--label", "normal"][..]] {
        let mut args = vec!["--style-motion", reference.as_str()];
        args.extend_from_slice(extra);
        let out = stylize(&content, &dir.join("rig.bvh"), &args);
        let bvh = Bvh::parse(&String::from_utf8(read(&out)).unwrap()).unwrap();
        assert_eq!(bvh.joints.len(), content_bvh.joints.len(), "{extra:?}");
        assert_eq!(bvh.frames, 38);
        // The output re-imports as a motion of the same length.
        let again = motion_stylizer::skeleton::import(&bvh).unwrap();
        assert_eq!(again.motion.frames(), 38);

        args.push("--canonical");
        let out = stylize(&content, &dir.join("canonical.bvh"), &args);
        let bvh = Bvh::parse(&String::from_utf8(read(&out)).unwrap()).unwrap();
        assert_eq!(bvh.joints.len(), 21);
        assert_eq!(bvh.frames, 38);
    }
}

#[test]
fn samples_write_numbered_files() {
    let dir = out_dir("cli-samples");
    let content = fixture("bandai", WALK);
    stylize(&content, &dir.join("out.bvh"), &["--label", "happy", "--samples", "3", "--seed", "1"]);
    let names: Vec<String> = {
        let mut v: Vec<_> =
            std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        v.sort();
        v
    };
    assert_eq!(names, ["out_0.bvh", "out_1.bvh", "out_2.bvh"]);
    let files: Vec<_> = names.iter().map(|n| read(&dir.join(n))).collect();
    assert_ne!(files[0], files[1]);
    assert_ne!(files[1], files[2]);
    // One sample: exactly the given name.
    stylize(&content, &dir.join("single.bvh"), &["--label", "happy", "--seed", "1"]);
    assert!(dir.join("single.bvh").is_file());
}

#[test]
fn errors_are_clear_and_exit_non_zero() {
    let dir = out_dir("cli-errors");
    let w = weights_dir();
    let content = fixture("bandai", SHORT);
    let out = dir.join("out.bvh");
    let base = ["stylize", content.as_str(), "--weights", s(w), "-o", s(&out)];
    let with = |extra: &[&str]| -> Vec<String> { base.iter().chain(extra).map(|a| a.to_string()).collect() };

    let err = fails(&with(&["--label", "sleepy"]));
    assert!(err.contains("unknown style label \"sleepy\""), "{err}");
    assert!(err.contains("old") && err.contains("chimpira") && err.contains("not-confident"), "{err}");

    let err = fails(&with(&["--label", "old", "--unsupervised"]));
    assert!(err.contains("needs the supervised model"), "{err}");

    let err = fails(&with(&[]));
    assert!(err.contains("--style-motion") && err.contains("--prior"), "{err}");

    let err = fails(&with(&["--prior", "--samples", "0"]));
    assert!(err.contains("samples must be between 1 and 64"), "{err}");

    let missing = dir.join("no-weights-here");
    let err = fails(&["stylize", &content, "--label", "old", "--weights", s(&missing), "-o", s(&out)]);
    assert!(err.contains("no trained weights at") && err.contains("--weights"), "{err}");

    let err = fails(&with(&["--label", "old", "--style-motion", s(&dir.join("missing.bvh"))]));
    assert!(err.contains("missing.bvh"), "{err}");

    let err = fails(&with(&["--label", "old", "--device", "tpu"]));
    assert!(err.contains("unknown device") && err.contains("cpu, wgpu and cuda"), "{err}");
    // A device this build lacks names the cargo feature that builds it in; cuda says why it is
    // never built and what to use instead.
    if !cfg!(feature = "wgpu") {
        let err = fails(&with(&["--label", "old", "--device", "wgpu"]));
        assert!(err.contains("no wgpu device") && err.contains("--features wgpu"), "{err}");
    }
    let err = fails(&with(&["--label", "old", "--device", "cuda"]));
    assert!(err.contains("cuda device") && err.contains("--device wgpu"), "{err}");
    assert!(!out.exists(), "nothing is written on error");
}

#[test]
fn styles_lists_the_labels() {
    let out = ok(&["styles", "--weights", s(weights_dir())]);
    let text = String::from_utf8(out.stdout).unwrap();
    let labels: Vec<&str> = text.lines().collect();
    assert_eq!(labels, motion_stylizer::dataset::STYLES);
    let err = fails(&["styles", "--weights", s(&weights_dir().join("nope"))]);
    assert!(err.contains("no trained weights"), "{err}");
}

/// Supervised motion-based without --label: the reference's label is inferred (with the shipped
/// weights: the Bandai fixtures' own labels) and named on stderr; the output equals the one with
/// that label given.
#[test]
fn supervised_motion_based_infers_the_reference_label() {
    let dir = out_dir("cli-infer");
    let shipped = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/weights");
    let content = fixture("foreign", "m21_walk");
    for (reference, label) in [("dataset-2_walk_elderly_001_f120", "old"), ("dataset-1_walk_tired_001_f90", "tired")] {
        let reference = fixture("bandai", reference);
        let (inferred, given) = (dir.join(format!("{label}-inferred.bvh")), dir.join(format!("{label}-given.bvh")));
        let base = ["stylize", content.as_str(), "--style-motion", reference.as_str(), "--weights", s(&shipped)];
        let out = ok(&[&base[..], &["-o", s(&inferred)]].concat());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(&format!("inferred the reference's label: {label}")), "{stderr}");
        let out = ok(&[&base[..], &["--label", label, "-o", s(&given)]].concat());
        assert!(!String::from_utf8_lossy(&out.stderr).contains("inferred"));
        assert_eq!(read(&inferred), read(&given), "{label}");
    }
}

/// A batch: two files and a folder in one call write one output per content into the output
/// folder, each on its own rig under its own name (a folder's contents under their path below it),
/// the same bytes as one call per file; a file that fails is reported and skipped, the others
/// written, and the call fails naming it.
#[test]
fn a_batch_stylizes_files_and_folders_into_one_output_folder() {
    let dir = out_dir("cli-batch");
    let clips = dir.join("clips");
    std::fs::create_dir_all(clips.join("more")).unwrap();
    std::fs::copy(fixture_path("foreign", "cmu31_xia_neutral_16_000"), clips.join("more/xia.bvh")).unwrap();
    let (bandai, m21) = (fixture("bandai", SHORT), fixture("foreign", "m21_walk"));
    let out = dir.join("out");
    let w = weights_dir();
    ok(&["stylize", &bandai, &m21, s(&clips), "--label", "old", "--seed", "3", "--weights", s(w), "-o", s(&out)]);
    let single =
        |content: &str, name: &str| read(&stylize(content, &dir.join(name), &["--label", "old", "--seed", "3"]));
    let outputs = [
        (out.join(format!("{SHORT}.bvh")), &bandai),
        (out.join("m21_walk.bvh"), &m21),
        (out.join("more/xia.bvh"), &s(&clips.join("more/xia.bvh")).to_string()),
    ];
    for (i, (path, content)) in outputs.iter().enumerate() {
        let bytes = read(path);
        assert_eq!(bytes, single(content, &format!("single{i}.bvh")), "{}", path.display());
        // Each output on its content's own rig: the same joints as the content.
        let (a, b) = (
            Bvh::parse(std::str::from_utf8(&bytes).unwrap()).unwrap(),
            Bvh::parse(&std::fs::read_to_string(content).unwrap()).unwrap(),
        );
        assert_eq!(a.joints.len(), b.joints.len(), "{}", path.display());
    }
    // glTF outputs on request.
    let glb = dir.join("glb");
    ok(&["stylize", &bandai, &m21, "--label", "old", "--format", "glb", "--weights", s(w), "-o", s(&glb)]);
    assert_eq!(&read(&glb.join("m21_walk.glb"))[..4], b"glTF");
    // One bad file: the others are written, the call fails and names it.
    let bad = dir.join("bad.bvh");
    std::fs::write(&bad, "HIERARCHY\nROOT x\n").unwrap();
    let partial = dir.join("partial");
    let err = fails(&["stylize", s(&bad), &m21, "--label", "old", "--weights", s(w), "-o", s(&partial)]);
    assert!(err.contains("skipped") && err.contains("bad.bvh") && err.contains("1 of 2 files failed"), "{err}");
    assert!(partial.join("m21_walk.bvh").is_file());
    // Two contents with one output name are refused before anything is written.
    let err = fails(&["stylize", &m21, &m21, "--label", "old", "--weights", s(w), "-o", s(&dir.join("twice"))]);
    assert!(err.contains("same output"), "{err}");
}

/// `--part PART=STYLE`: a style per body part. With the main style for the other parts, the lower
/// body's from the main style keeps the root of the whole-body output; parts as content only
/// change the styled part; unknown parts and styles are clear errors.
#[test]
fn part_styles_through_the_cli() {
    let dir = out_dir("cli-parts");
    let content = fixture("foreign", "m21_walk");
    let whole = read(&stylize(&content, &dir.join("whole.bvh"), &["--label", "old", "--canonical"]));
    let upper = read(&stylize(
        &content,
        &dir.join("upper.bvh"),
        &["--label", "old", "--part", "upper=label:proud", "--canonical"],
    ));
    let (whole, upper) = (
        Bvh::parse(std::str::from_utf8(&whole).unwrap()).unwrap(),
        Bvh::parse(std::str::from_utf8(&upper).unwrap()).unwrap(),
    );
    assert_eq!(whole.frames, upper.frames);
    // Hips channels (root position + rotation) from the lower body = the whole-body `old` output.
    let hips = whole.joints[0].channels.len();
    let frames_differ = (0..whole.frames).any(|f| whole.frame(f)[hips..] != upper.frame(f)[hips..]);
    for f in 0..whole.frames {
        assert_eq!(whole.frame(f)[..hips], upper.frame(f)[..hips], "frame {f}: the root is the lower body's");
    }
    assert!(frames_differ, "the upper body took another style");
    // Only a part, the rest the content's own motion.
    stylize(&content, &dir.join("head.bvh"), &["--part", "head=prior"]);
    let w = weights_dir();
    for (bad, says) in
        [("arms=label:old", "lower, upper and head"), ("upper=style:old", "label:NAME"), ("upper", "PART=STYLE")]
    {
        let err = fails(&["stylize", &content, "--part", bad, "--weights", s(w), "-o", s(&dir.join("bad.bvh"))]);
        assert!(err.contains(says), "{bad}: {err}");
    }
}
