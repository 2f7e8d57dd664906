//! The stylization pipeline as a library: lengths, determinism, samples, settings and labels,
//! style mixes, weight loading errors.
//!
//! The weights are UNTRAINED (seeded networks at width 0.125, see `stylize_support`): these tests
//! check the plumbing only. Whether the style actually moves toward the reference is tested in
//! `tests/stylize_quality.rs` (ignored until trained weights are committed).
#![cfg(feature = "model")]

mod stylize_support;

use motion_stylizer::Motion;
use motion_stylizer::dataset::Style;
use motion_stylizer::stylize::{
    self, MAX_MIX_DEPTH, MAX_SAMPLES, Request, Setting, StyleSource, StylizeError, Weights, pad_features,
    padded_frames, style_code_of,
};
use stylize_support::*;

fn max_diff(a: &Motion, b: &Motion) -> f64 {
    assert_eq!(a.frames(), b.frames());
    let roots = a.root_positions().iter().zip(b.root_positions()).map(|(p, q)| (*p - *q).abs().max_element());
    let rots = a
        .rotations()
        .iter()
        .zip(b.rotations())
        .flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| (x.dot(*y).abs() - 1.0).abs()));
    roots.chain(rots).fold(0.0, f64::max)
}

fn label(w: &Weights, name: &str) -> Style {
    w.style(name).unwrap()
}

#[test]
fn padding_reflects_and_reaches_a_multiple_of_8() {
    assert_eq!([0, 1, 7, 8, 9, 38, 160].map(padded_frames), [8, 8, 8, 8, 16, 40, 160]);
    let m = import("bandai", SHORT).motion.slice(0, 3);
    let f = motion_stylizer::features::extract(&m);
    let p = pad_features(&f, 8);
    assert_eq!(p.frames(), 8);
    // 0 1 2 | 1 0 1 2 1
    for (t, src) in [0, 1, 2, 1, 0, 1, 2, 1].into_iter().enumerate() {
        assert_eq!(p.frame(t), f.frame(src), "frame {t}");
    }
    let one = motion_stylizer::features::extract(&m.slice(0, 1));
    assert!(pad_features(&one, 8).rows().all(|r| r == one.frame(0)));
}

#[test]
fn outputs_are_as_long_as_the_content_for_any_length() {
    let w = weights();
    let short = import("bandai", SHORT).motion;
    assert_eq!(short.frames(), 38);
    let walk = import("bandai", WALK).motion;
    let contents =
        [short.clone(), walk.clone(), walk.slice(0, 1), walk.slice(0, 5), walk.slice(0, 8), walk.slice(0, 9)];
    for content in &contents {
        for setting in [Setting::Supervised, Setting::Unsupervised] {
            let source =
                if setting == Setting::Supervised { StyleSource::Label(label(&w, "old")) } else { StyleSource::Prior };
            let request = Request::new(source).with_setting(setting).with_samples(2).with_seed(3);
            let out = stylize::stylize(&w, content, &request).unwrap();
            assert_eq!(out.len(), 2);
            for m in &out {
                assert_eq!(m.frames(), content.frames(), "{setting}");
            }
        }
    }
}

#[test]
fn different_labels_give_different_motions() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let run = |name: &str| {
        let request = Request::new(StyleSource::Label(label(&w, name))).with_seed(5);
        stylize::stylize(&w, &content, &request).unwrap().remove(0)
    };
    let (old, happy) = (run("old"), run("happy"));
    assert_eq!(old.frames(), 38);
    assert!(max_diff(&old, &happy) > 1e-3, "labels old and happy gave the same motion");
}

#[test]
fn same_seed_same_bits_other_seed_other_motion() {
    let w = weights();
    let content = import("bandai", WALK).motion;
    let cases = [
        (StyleSource::Label(label(&w, "tired")), Setting::Supervised),
        (StyleSource::Prior, Setting::Supervised),
        (StyleSource::Prior, Setting::Unsupervised),
    ];
    for (source, setting) in cases {
        let request = Request::new(source.clone()).with_setting(setting).with_seed(42);
        let a = stylize::stylize(&w, &content, &request).unwrap();
        let b = stylize::stylize(&w, &content, &request).unwrap();
        assert_eq!(a, b, "{source:?} {setting}: same seed, other output");
        let c = stylize::stylize(&w, &content, &request.clone().with_seed(43)).unwrap();
        assert!(max_diff(&a[0], &c[0]) > 1e-4, "{source:?} {setting}: other seed, same output");
    }
}

#[test]
fn samples_are_batched_distinct_and_the_first_matches_a_single_run() {
    let w = weights();
    let content = import("bandai", WALK).motion;
    let request = Request::new(StyleSource::Label(label(&w, "proud"))).with_seed(9);
    let one = stylize::stylize(&w, &content, &request).unwrap();
    let three = stylize::stylize(&w, &content, &request.clone().with_samples(3)).unwrap();
    assert_eq!(three.len(), 3);
    // Sample i uses the i-th style draw: the first of three is the single run's (up to the
    // rounding of a batched matmul).
    assert!(max_diff(&one[0], &three[0]) < 1e-3, "{}", max_diff(&one[0], &three[0]));
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        assert!(max_diff(&three[i], &three[j]) > 1e-4, "samples {i} and {j} equal");
    }
    for bad in [0, MAX_SAMPLES + 1] {
        let err = stylize::stylize(&w, &content, &request.clone().with_samples(bad)).unwrap_err();
        assert_eq!(err, StylizeError::Samples { got: bad, max: MAX_SAMPLES });
    }
}

#[test]
fn motion_based_with_a_foreign_rig_reference() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let reference = import("foreign", "m21_walk").motion;

    // Unsupervised: no label; one sample is the posterior mean, so the seed does not matter.
    let request = Request::new(StyleSource::motion(&reference)).with_setting(Setting::Unsupervised);
    let a = stylize::stylize(&w, &content, &request).unwrap();
    let b = stylize::stylize(&w, &content, &request.clone().with_seed(77)).unwrap();
    assert_eq!(a, b);
    assert_eq!(a[0].frames(), content.frames());
    // Several samples are draws from the posterior.
    let many = stylize::stylize(&w, &content, &request.clone().with_samples(2)).unwrap();
    assert!(max_diff(&many[0], &many[1]) > 1e-4);

    // Supervised: the reference's label is needed.
    let err = stylize::stylize(&w, &content, &request.clone().with_setting(Setting::Supervised)).unwrap_err();
    assert_eq!(err, StylizeError::MotionNeedsLabel);
    let labelled = Request::new(StyleSource::labelled_motion(&reference, label(&w, "normal")));
    let out = stylize::stylize(&w, &content, &labelled).unwrap();
    assert_eq!(out[0].frames(), content.frames());
    let err = stylize::stylize(&w, &content, &labelled.with_setting(Setting::Unsupervised)).unwrap_err();
    assert_eq!(err, StylizeError::LabelWithUnsupervised);
}

#[test]
fn the_output_starts_where_the_content_starts() {
    let w = weights();
    let content = import("bandai", WALK).motion;
    let out = stylize::stylize(&w, &content, &Request::new(StyleSource::Prior)).unwrap().remove(0);
    let (p, q) = (content.root_positions()[0], out.root_positions()[0]);
    assert!((p.x - q.x).abs() < 1e-6 && (p.z - q.z).abs() < 1e-6, "{p} vs {q}");
}

#[test]
fn label_rules() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let old = label(&w, "OLD");
    assert_eq!(w.style_name(old), Some("old"));
    match w.style("sleepy") {
        Err(StylizeError::UnknownLabel { name, valid }) => {
            assert_eq!(name, "sleepy");
            assert_eq!(valid.len(), 16);
            let msg = w.style("sleepy").unwrap_err().to_string();
            assert!(msg.contains("old") && msg.contains("chimpira"), "{msg}");
        }
        other => panic!("{other:?}"),
    }
    let unsup = Request::new(StyleSource::Label(old)).with_setting(Setting::Unsupervised);
    assert_eq!(stylize::stylize(&w, &content, &unsup).unwrap_err(), StylizeError::LabelNeedsSupervised);
    let out_of_range = Request::new(StyleSource::Label(Style(16)));
    assert_eq!(
        stylize::stylize(&w, &content, &out_of_range).unwrap_err(),
        StylizeError::LabelOutOfRange { index: 16, count: 16 }
    );
}

#[test]
fn style_mixes() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let (old, happy) = (StyleSource::Label(label(&w, "old")), StyleSource::Label(label(&w, "happy")));
    let run = |source: StyleSource<'_>| stylize::stylize(&w, &content, &Request::new(source).with_seed(4));
    let alone = run(old.clone()).unwrap();
    // a's noise is drawn first, so t = 0 is exactly a.
    assert_eq!(run(StyleSource::mix(old.clone(), happy.clone(), 0.0)).unwrap(), alone);
    let half = run(StyleSource::mix(old.clone(), happy.clone(), 0.5)).unwrap();
    assert!(max_diff(&half[0], &alone[0]) > 1e-4);
    for t in [-0.1, 1.5, f32::NAN] {
        assert!(matches!(run(StyleSource::mix(old.clone(), happy.clone(), t)), Err(StylizeError::MixWeight { .. })));
    }
    let reference = import("bandai", "dataset-2_walk_elderly_001_f120").motion;
    let motion_mix = StyleSource::mix(StyleSource::motion(&reference), StyleSource::Prior, 0.3);
    let out = stylize::stylize(&w, &content, &Request::new(motion_mix).with_setting(Setting::Unsupervised)).unwrap();
    assert_eq!(out[0].frames(), content.frames());
    let mut deep = StyleSource::Prior;
    for _ in 0..=MAX_MIX_DEPTH {
        deep = StyleSource::mix(deep, StyleSource::Prior, 0.5);
    }
    assert_eq!(run(deep).unwrap_err(), StylizeError::MixTooDeep { max: MAX_MIX_DEPTH });
}

#[test]
fn style_codes_of_motions() {
    let w = weights();
    let walk = import("bandai", WALK).motion;
    let code = style_code_of(&w, Setting::Unsupervised, &walk, None).unwrap();
    assert_eq!(code.len(), config(false).style_dim);
    assert_eq!(code, style_code_of(&w, Setting::Unsupervised, &walk, None).unwrap());
    assert!(code.iter().all(|v| v.is_finite()));
    let err = style_code_of(&w, Setting::Supervised, &walk, None).unwrap_err();
    assert_eq!(err, StylizeError::MotionNeedsLabel);
    let sup = style_code_of(&w, Setting::Supervised, &walk, Some(label(&w, "normal"))).unwrap();
    assert_eq!(sup.len(), config(true).style_dim);
}

#[test]
fn weights_from_bytes_refuse_what_they_cannot_use() {
    let f = files();
    let load = |m: &[u8], n: &[u8], s: Option<&[u8]>, u: Option<&[u8]>| Weights::from_bytes(m, n, s, u);
    let bad = |r: Result<Weights, StylizeError>| match r {
        Err(StylizeError::BadWeights(msg)) => msg,
        other => panic!("expected BadWeights, got {other:?}"),
    };
    // Only one setting: the other is unavailable.
    let sup_only = load(&f.manifest, &f.norm, Some(&f.supervised), None).unwrap();
    assert_eq!(sup_only.settings(), vec![Setting::Supervised]);
    let content = import("bandai", SHORT).motion;
    let request = Request::new(StyleSource::Prior).with_setting(Setting::Unsupervised);
    assert_eq!(
        stylize::stylize(&sup_only, &content, &request).unwrap_err(),
        StylizeError::SettingUnavailable { setting: Setting::Unsupervised }
    );

    bad(load(b"{", &f.norm, Some(&f.supervised), None));
    bad(load(&f.manifest, b"{\"mean\": [0.0], \"std\": [1.0]}", Some(&f.supervised), None));
    bad(load(&f.manifest, &f.norm, None, None));
    let msg = bad(load(&f.manifest, &f.norm, Some(&f.unsupervised), None));
    assert!(msg.contains("unsupervised"), "{msg}");
    bad(load(&f.manifest, &f.norm, Some(b"garbage"), None));
    for cut in [4, 12, 40, f.supervised.len() / 2, f.supervised.len() - 1] {
        bad(load(&f.manifest, &f.norm, Some(&f.supervised[..cut]), None));
    }
    // A bundle whose config does not describe its networks, or asks for absurd widths.
    let rewrap = |cfg: &motion_stylizer::model::ModelConfig| {
        let len = u32::from_le_bytes(f.supervised[8..12].try_into().unwrap()) as usize;
        let json = serde_json::to_vec(cfg).unwrap();
        let mut out = f.supervised[..8].to_vec();
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(&json);
        out.extend_from_slice(&f.supervised[12 + len..]);
        out
    };
    bad(load(&f.manifest, &f.norm, Some(&rewrap(&config(true).with_width_factor(2.0))), None));
    let mut huge = config(true);
    huge.generator_hidden[1] = 1 << 30;
    bad(load(&f.manifest, &f.norm, Some(&rewrap(&huge)), None));
    let mut manifest = manifest();
    manifest.styles.truncate(4);
    let msg = bad(load(&serde_json::to_vec(&manifest).unwrap(), &f.norm, Some(&f.supervised), None));
    assert!(msg.contains("16") && msg.contains('4'), "{msg}");
    manifest.format = 99;
    bad(load(&serde_json::to_vec(&manifest).unwrap(), &f.norm, Some(&f.supervised), None));
}

#[test]
fn weights_load_from_a_folder() {
    let w = Weights::load_dir(weights_dir()).unwrap();
    assert_eq!(w.settings(), vec![Setting::Supervised, Setting::Unsupervised]);
    assert_eq!(w.styles().len(), 16);
    let missing = Weights::load_dir(weights_dir().join("nope")).unwrap_err();
    assert!(matches!(missing, StylizeError::Read { .. }), "{missing:?}");
}

/// Timing of one 160-frame stylization and of 10 samples at width 0.5 (untrained weights), in
/// the library (networks + features) and end to end through the CLI (load the weights, import,
/// stylize, write the BVHs). Prints; asserts nothing (timings depend on the machine).
/// `cargo test --release --test stylize_pipeline -- --ignored --nocapture timing`
#[test]
#[ignore]
fn timing_160_frames_width_half() {
    use burn::prelude::*;
    use motion_stylizer::model::weights::save_bundle;
    use motion_stylizer::model::{ModelConfig, MotionModel};
    let cfg = ModelConfig::scaled(0.5).with_num_styles(16);
    let bundle = save_bundle(&cfg, MotionModel::seeded(&cfg, &Device::flex(), 1)).unwrap();
    let f = files();
    let w = Weights::from_bytes(&f.manifest, &f.norm, Some(&bundle), None).unwrap();
    let walk = import("bandai", WALK).motion;
    // 160 frames: the walk and its first 40 frames again.
    let content = {
        let mut root = walk.root_positions().to_vec();
        let mut rot = walk.rotations().to_vec();
        root.extend_from_slice(&walk.root_positions()[..40]);
        rot.extend_from_slice(&walk.rotations()[..40]);
        Motion::new(root, rot).unwrap()
    };
    assert_eq!(content.frames(), 160);
    let old = w.style("old").unwrap();
    let runs = 10;
    let time = |request: &Request<'_>| {
        stylize::stylize(&w, &content, request).unwrap();
        let start = std::time::Instant::now();
        for _ in 0..runs {
            stylize::stylize(&w, &content, request).unwrap();
        }
        start.elapsed().as_secs_f64() / runs as f64
    };
    let one = time(&Request::new(StyleSource::Label(old)));
    let ten = time(&Request::new(StyleSource::Label(old)).with_samples(10));
    println!(
        "library, width 0.5, 160 frames: 1 sample {:.1} ms, 10 samples {:.1} ms ({:.2}x)",
        one * 1e3,
        ten * 1e3,
        ten / one
    );

    let dir = out_dir("timing");
    let wdir = dir.join("weights");
    std::fs::create_dir_all(&wdir).unwrap();
    let mut manifest = manifest();
    manifest.models.retain(|m| m.setting == "supervised");
    std::fs::write(wdir.join("manifest.json"), serde_json::to_vec(&manifest).unwrap()).unwrap();
    std::fs::write(wdir.join("norm.json"), &f.norm).unwrap();
    std::fs::write(wdir.join("supervised.bin"), &bundle).unwrap();
    let content_path = dir.join("content.bvh");
    std::fs::write(&content_path, import("bandai", WALK).rig.from_canonical(&content).to_bvh_string()).unwrap();
    let cli = |samples: &str| {
        let start = std::time::Instant::now();
        for _ in 0..runs {
            let status = std::process::Command::new(env!("CARGO_BIN_EXE_motion-stylizer"))
                .args(["stylize", content_path.to_str().unwrap(), "--label", "old", "--samples", samples])
                .args(["--weights", wdir.to_str().unwrap(), "-o", dir.join("out.bvh").to_str().unwrap()])
                .stderr(std::process::Stdio::null())
                .status()
                .unwrap();
            assert!(status.success());
        }
        start.elapsed().as_secs_f64() / runs as f64
    };
    let (one, ten) = (cli("1"), cli("10"));
    println!(
        "CLI end to end, width 0.5, 160 frames: 1 sample {:.1} ms, 10 samples {:.1} ms ({:.2}x)",
        one * 1e3,
        ten * 1e3,
        ten / one
    );
}

/// The manifest's label codes: label-based codes are drawn around the label's centre (all-zero
/// centres give exactly the codes around 0, other centres other motions, the same bits for the
/// same seed); codes of the wrong shape or not finite are refused.
#[test]
fn label_codes_centre_the_label_based_draws() {
    use motion_stylizer::dataset::STYLES;
    use motion_stylizer::stylize::LabelCodes;
    let f = files();
    let dim = config(true).style_dim;
    let with_codes = |codes: Vec<Vec<f32>>| {
        let mut m = manifest();
        m.models[0].label_codes = Some(LabelCodes { command: "test".into(), takes: vec![1; STYLES.len()], codes });
        Weights::from_bytes(&serde_json::to_vec(&m).unwrap(), &f.norm, Some(&f.supervised), None)
    };
    let content = import("bandai", SHORT).motion;
    let w = weights();
    let request = Request::new(StyleSource::Label(label(&w, "old"))).with_seed(4).with_samples(2);
    let plain = stylize::stylize(&w, &content, &request).unwrap();

    let zero = with_codes(vec![vec![0.0; dim]; STYLES.len()]).unwrap();
    assert_eq!(zero.label_code(label(&w, "old")), Some(&vec![0.0; dim][..]));
    assert_eq!(stylize::stylize(&zero, &content, &request).unwrap(), plain, "a zero centre is the prior's mean");

    let centred = with_codes((0..STYLES.len()).map(|l| vec![0.5 + l as f32 * 0.1; dim]).collect()).unwrap();
    let moved = stylize::stylize(&centred, &content, &request).unwrap();
    assert_ne!(moved, plain, "a centre away from 0 changes the motions");
    assert_eq!(stylize::stylize(&centred, &content, &request).unwrap(), moved, "same seed, same bits");

    let refused = |r: Result<Weights, StylizeError>| match r {
        Err(StylizeError::BadWeights(msg)) => assert!(msg.contains("label codes"), "{msg}"),
        other => panic!("expected BadWeights, got {other:?}"),
    };
    refused(with_codes(vec![vec![0.0; dim]; STYLES.len() - 1]));
    refused(with_codes(vec![vec![0.0; dim + 1]; STYLES.len()]));
    // A number beyond f32 (JSON has no NaN or infinity) is refused when the manifest is read.
    let mut m = serde_json::to_value(manifest()).unwrap();
    m["models"][0]["label_codes"] = serde_json::json!({"command": "test", "takes": vec![1; STYLES.len()], "codes": vec![vec![1e39; dim]; STYLES.len()]});
    let err = Weights::from_bytes(&serde_json::to_vec(&m).unwrap(), &f.norm, Some(&f.supervised), None).unwrap_err();
    assert!(matches!(&err, StylizeError::BadWeights(msg) if msg.contains("out of range")), "{err:?}");
}

/// The unsupervised model's neutral code: guidance measures a reference against it (a zero code
/// is the prior's mean, as without one), prior draws keep the prior's mean, and a mix of a
/// reference and a draw takes its share of it; a code of the wrong size or not finite is refused.
#[test]
fn the_unsupervised_neutral_code_anchors_references_only() {
    use motion_stylizer::stylize::NeutralCode;
    let f = files();
    let dim = config(false).style_dim;
    let with_code = |code: Vec<f32>| {
        let mut m = manifest();
        m.models[1].neutral_code = Some(NeutralCode { command: "test".into(), takes: 1, code });
        Weights::from_bytes(&serde_json::to_vec(&m).unwrap(), &f.norm, None, Some(&f.unsupervised))
    };
    let plain = Weights::from_bytes(&f.manifest, &f.norm, None, Some(&f.unsupervised)).unwrap();
    assert_eq!(plain.neutral_code(), None);
    let zero = with_code(vec![0.0; dim]).unwrap();
    let anchored = with_code(vec![0.5; dim]).unwrap();
    assert_eq!(anchored.neutral_code(), Some(&vec![0.5; dim][..]));

    let content = import("bandai", SHORT).motion;
    let reference = import("bandai", WALK).motion;
    let run = |w: &Weights, source: StyleSource<'_>| {
        let request = Request::new(source).with_setting(Setting::Unsupervised).with_seed(5);
        stylize::stylize(w, &content, &request).unwrap()
    };
    let by_reference = |w: &Weights| run(w, StyleSource::motion(&reference));
    assert_eq!(by_reference(&zero), by_reference(&plain), "a zero code is the prior's mean");
    assert_ne!(by_reference(&anchored), by_reference(&plain), "a reference is measured against the code");
    assert_eq!(run(&anchored, StyleSource::Prior), run(&plain, StyleSource::Prior), "prior draws keep 0");
    let mix = |w: &Weights, t: f32| run(w, StyleSource::mix(StyleSource::motion(&reference), StyleSource::Prior, t));
    assert_eq!(mix(&anchored, 1.0), mix(&plain, 1.0), "all prior: no anchor");
    assert_ne!(mix(&anchored, 0.5), mix(&plain, 0.5), "half a reference: half the anchor");
    // Without guidance the code changes nothing.
    let unguided = |w: &Weights| {
        let request = Request::new(StyleSource::motion(&reference))
            .with_setting(Setting::Unsupervised)
            .with_seed(5)
            .with_guidance(0.0);
        stylize::stylize(w, &content, &request).unwrap()
    };
    assert_eq!(unguided(&anchored), unguided(&plain));

    let refused = |r: Result<Weights, StylizeError>| match r {
        Err(StylizeError::BadWeights(msg)) => assert!(msg.contains("neutral code"), "{msg}"),
        other => panic!("expected BadWeights, got {other:?}"),
    };
    refused(with_code(vec![0.0; dim + 1]));
    refused(with_code(vec![]));
}

/// `label-codes`' neutral code: the `normal` motions' mean posterior, each group (data set)
/// weighted equally; other labels left out; none without `normal` motions.
#[test]
fn the_neutral_code_weighs_each_group_equally() {
    use motion_stylizer::train::label_codes::{LabelledMotion, neutral_code_of};
    let w = weights();
    let (walk, short, tired) =
        (import("bandai", WALK).motion, import("bandai", SHORT).motion, import("bandai", BANDAI[0]).motion);
    let (normal, old) = (label(&w, "normal"), label(&w, "old"));
    let item = |group, style, motion| LabelledMotion { name: "test".into(), group, style, motion };
    let items = [item(1, normal, &walk), item(1, normal, &short), item(2, normal, &tired), item(2, old, &short)];
    let code = neutral_code_of(&w, &items, "test".into()).unwrap().expect("a neutral code");
    assert_eq!(code.takes, 3);
    let of = |m: &Motion| style_code_of(&w, Setting::Unsupervised, m, None).unwrap();
    let (a, b, c) = (of(&walk), of(&short), of(&tired));
    for i in 0..a.len() {
        let expected = ((a[i] + b[i]) / 2.0 + c[i]) / 2.0;
        assert!((code.code[i] - expected).abs() < 1e-4, "{i}: {} against {expected}", code.code[i]);
    }
    assert!(neutral_code_of(&w, &items[3..], "test".into()).unwrap().is_none(), "no `normal` motion");
}

/// Strength: 0 gives back the content (bit for bit) without running the style source, 1 is the
/// default output, others change it; outside [0, 2] or not finite is refused.
#[test]
fn strength_scales_the_change_and_is_checked() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let request = Request::new(StyleSource::Label(label(&w, "old"))).with_seed(2);
    let at = |s: f32| stylize::stylize(&w, &content, &request.clone().with_strength(s));
    assert_eq!(at(0.0).unwrap(), vec![content.clone()]);
    assert_eq!(at(1.0).unwrap(), stylize::stylize(&w, &content, &request).unwrap());
    assert_ne!(at(1.5).unwrap(), at(1.0).unwrap());
    for s in [-0.1, 2.01, f32::NAN, f32::INFINITY] {
        let err = at(s).unwrap_err();
        assert!(matches!(err, StylizeError::Strength { max, .. } if max == 2.0), "{s}: {err:?}");
        assert_eq!(err.code(), "BAD_REQUEST");
    }
}

/// Guidance: the default is [`stylize::DEFAULT_GUIDANCE`] (1), 0 another motion (the networks'
/// output as trained); outside [0, 3] or not finite is refused; strength 0 is still the content.
#[test]
fn guidance_is_the_default_and_is_checked() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let request = Request::new(StyleSource::Label(label(&w, "old"))).with_seed(2);
    assert_eq!(request.guidance, stylize::DEFAULT_GUIDANCE);
    let at = |g: f32| stylize::stylize(&w, &content, &request.clone().with_guidance(g));
    assert_eq!(at(1.0).unwrap(), stylize::stylize(&w, &content, &request).unwrap());
    assert_ne!(at(0.0).unwrap(), at(1.0).unwrap());
    assert_eq!(
        stylize::stylize(&w, &content, &request.clone().with_guidance(2.0).with_strength(0.0)).unwrap(),
        vec![content.clone()]
    );
    for g in [-0.1, 3.01, f32::NAN, f32::INFINITY] {
        let err = at(g).unwrap_err();
        assert!(matches!(err, StylizeError::Guidance { max, .. } if max == 3.0), "{g}: {err:?}");
        assert_eq!(err.code(), "BAD_REQUEST");
    }
}

/// Guidance measures a style against `normal`, so `normal` itself is not guided: label-based, or a
/// reference labelled `normal` (without this, the content term brought the content's own style
/// back into a `normal` reference's output); a reference of another label is.
#[test]
fn the_neutral_style_is_not_guided_by_label_nor_by_reference() {
    let w = weights();
    let content = import("bandai", SHORT).motion;
    let reference = import("bandai", WALK).motion;
    let at = |source: StyleSource<'_>, g: f32| {
        stylize::stylize(&w, &content, &Request::new(source).with_seed(3).with_guidance(g)).unwrap()
    };
    let normal = label(&w, "normal");
    assert_eq!(at(StyleSource::Label(normal), 1.0), at(StyleSource::Label(normal), 0.0));
    let by_reference = |g| at(StyleSource::labelled_motion(&reference, normal), g);
    assert_eq!(by_reference(1.0), by_reference(0.0));
    let old = |g| at(StyleSource::labelled_motion(&reference, label(&w, "old")), g);
    assert_ne!(old(1.0), old(0.0));
}

/// Per-body-part styles: each part's joints (local rotations) come from its own request's output,
/// the root and legs from the lower body's; a part without a request keeps the content's; parts
/// with one request equal the whole-body stylization; bad part requests are typed errors.
#[test]
fn body_parts_take_their_joints_from_their_own_request() {
    use motion_stylizer::stylize::{BodyPart, PartRequests, stylize_parts};
    let w = weights();
    let content = import("bandai", WALK).motion;
    let old = Request::new(StyleSource::Label(label(&w, "old"))).with_seed(1);
    let proud = Request::new(StyleSource::Label(label(&w, "proud"))).with_seed(2);
    let whole_old = stylize::stylize(&w, &content, &old).unwrap().remove(0);
    let whole_proud = stylize::stylize(&w, &content, &proud).unwrap().remove(0);
    let parts = PartRequests { lower: Some(old.clone()), upper: Some(proud.clone()), head: None };
    let mixed = stylize_parts(&w, &content, &parts).unwrap().remove(0);
    assert_eq!(mixed.root_positions(), whole_old.root_positions(), "root from the lower body's output");
    for (f, pose) in mixed.rotations().iter().enumerate() {
        for (part, source) in
            [(BodyPart::Lower, &whole_old), (BodyPart::Upper, &whole_proud), (BodyPart::Head, &content)]
        {
            for &j in part.joints() {
                // Equal up to the renormalisation of the combined motion's quaternions.
                let d = (pose[j].dot(source.rotations()[f][j]).abs() - 1.0).abs();
                assert!(d < 1e-12, "frame {f}, joint {j} of {part:?}: {d}");
            }
        }
    }
    assert!(max_diff(&mixed, &whole_old) > 1e-3 && max_diff(&mixed, &whole_proud) > 1e-3);
    // One request for every part: the whole-body output itself.
    let all_old = PartRequests { lower: Some(old.clone()), upper: Some(old.clone()), head: Some(old.clone()) };
    assert!(max_diff(&stylize_parts(&w, &content, &all_old).unwrap()[0], &whole_old) < 1e-12);
    // No part, or parts with other sample counts: BAD_REQUEST.
    let none = stylize_parts(&w, &content, &PartRequests::default()).unwrap_err();
    assert_eq!(none.code(), "BAD_REQUEST");
    let counts = PartRequests { lower: Some(old.clone().with_samples(2)), upper: Some(proud), head: None };
    assert_eq!(stylize_parts(&w, &content, &counts).unwrap_err().code(), "BAD_REQUEST");
}
