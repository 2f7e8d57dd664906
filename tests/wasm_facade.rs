//! The npm package's wasm facade (`motion_stylizer::wasm`), run in Node by wasm-bindgen's test
//! runner: `make test-wasm`, or
//! `cargo test --release --target wasm32-unknown-unknown --no-default-features --features model,wasm --test wasm_facade`.
//!
//! Every foreign-rig fixture imports (keeping its source file's own joint positions) and stylizes in
//! every mode; outputs are deterministic; the stylize options are checked; every refusal is a JS
//! `Error` with the right `code`; inputs that once could crash the module do not.
//! (Equality with the native CLI is checked on the built package: `tests/npm/`.)
#![cfg(all(target_arch = "wasm32", feature = "wasm"))]

use motion_stylizer::bvh::{Bvh, Channel};
use motion_stylizer::wasm::{Engine, ImportedMotion, StyleSpec, StylizedMotion};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test;

const MANIFEST: &[u8] = include_bytes!("../assets/weights/manifest.json");
const NORM: &[u8] = include_bytes!("../assets/weights/norm.json");
const SHARED: &[u8] = include_bytes!("../assets/weights/shared.bin");
const SUPERVISED: &[u8] = include_bytes!("../assets/weights/supervised.bin");
const UNSUPERVISED: &[u8] = include_bytes!("../assets/weights/unsupervised.bin");
const SUPERVISED_STYLE: &[u8] = include_bytes!("../assets/weights/supervised-style.bin");
const UNSUPERVISED_STYLE: &[u8] = include_bytes!("../assets/weights/unsupervised-style.bin");

/// Foreign-rig fixtures and the rig the importer must detect.
const FOREIGN: &[(&str, &str)] = &[
    ("cmu31_rest", include_str!("fixtures/foreign/cmu31_rest.bvh")),
    ("cmu31_xia_neutral_16_000", include_str!("fixtures/foreign/cmu31_xia_neutral_16_000.bvh")),
    ("iclone100_cmu_002_04", include_str!("fixtures/foreign/iclone100_cmu_002_04.bvh")),
    ("m21_walk", include_str!("fixtures/foreign/m21_walk.bvh")),
];
const RIGS: &[&str] = &["cmu31", "cmu31", "cc_base", "m21"];
const REFERENCE: &str = include_str!("fixtures/bandai/dataset-2_walk_elderly_001_f120.bvh");
const SMALL: &str = include_str!("fixtures/small.bvh");

thread_local! {
    static ENGINE: Engine = full_engine();
}

/// The shipped weights with both models and their style encoders.
fn full_engine() -> Engine {
    let mut engine = Engine::new(
        MANIFEST,
        NORM,
        Some(SHARED.to_vec()),
        Some(SUPERVISED.to_vec()),
        Some(UNSUPERVISED.to_vec()),
        "cpu",
    )
    .unwrap_or_else(|e| panic!("shipped weights: {}", message(&e)));
    for (setting, bytes) in [("supervised", SUPERVISED_STYLE), ("unsupervised", UNSUPERVISED_STYLE)] {
        engine.add_style_encoder(setting, bytes).unwrap_or_else(|e| panic!("{setting} style encoder: {}", message(&e)));
    }
    engine
}

fn prop(e: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(e, &JsValue::from_str(key)).unwrap_or(JsValue::UNDEFINED)
}

fn code(e: &JsValue) -> String {
    assert!(e.is_instance_of::<js_sys::Error>(), "not a JS Error: {e:?}");
    prop(e, "code").as_string().unwrap_or_else(|| panic!("no code on {}", message(e)))
}

fn message(e: &JsValue) -> String {
    prop(e, "message").as_string().unwrap_or_default()
}

fn err_code<T>(r: Result<T, JsValue>) -> String {
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => code(&e),
    }
}

fn import(text: &str) -> ImportedMotion {
    ImportedMotion::from_bvh(text, None).unwrap_or_else(|e| panic!("import: {}", message(&e)))
}

/// An object of `(key, value)` properties.
fn object(properties: &[(&str, JsValue)]) -> JsValue {
    let o = js_sys::Object::new();
    for (key, value) in properties {
        js_sys::Reflect::set(&o, &JsValue::from_str(key), value).unwrap();
    }
    o.into()
}

/// The options object of [`Engine::stylize`] (`temperature` absent when `None`).
fn options(unsupervised: bool, samples: f64, seed: JsValue, canonical: bool, temperature: Option<f64>) -> JsValue {
    let mut properties = vec![
        ("unsupervised", JsValue::from_bool(unsupervised)),
        ("samples", JsValue::from_f64(samples)),
        ("seed", seed),
        ("canonical", JsValue::from_bool(canonical)),
    ];
    properties.extend(temperature.map(|t| ("temperature", JsValue::from_f64(t))));
    object(&properties)
}

/// Stylize with `engine`, panicking with the JS error's message.
fn run(
    engine: &Engine,
    content: &ImportedMotion,
    style: &StyleSpec,
    unsupervised: bool,
    samples: f64,
    seed: u64,
    canonical: bool,
) -> Vec<StylizedMotion> {
    engine
        .stylize(content, style, options(unsupervised, samples, JsValue::from_f64(seed as f64), canonical, None))
        .unwrap_or_else(|e| panic!("stylize: {} ({})", message(&e), code(&e)))
}

fn check_output(out: &StylizedMotion, frames: usize) {
    assert_eq!(out.frames(), frames);
    assert_eq!(out.fps(), 30.0);
    let names = out.joint_names();
    let parents = out.parents();
    assert_eq!(names.len(), parents.len());
    assert_eq!(parents[0], -1);
    assert!(parents.iter().enumerate().skip(1).all(|(i, &p)| p >= 0 && (p as usize) < i));
    let positions = out.positions();
    assert_eq!(positions.len(), frames * names.len() * 3);
    assert!(positions.iter().all(|v| v.is_finite()));
    // The BVH text imports again.
    import(&out.to_bvh());
}

#[wasm_bindgen_test]
fn every_foreign_fixture_imports_with_its_rig() {
    for ((name, text), rig) in FOREIGN.iter().zip(RIGS) {
        let c = ImportedMotion::from_bvh(text, None).unwrap_or_else(|e| panic!("{name}: {}", message(&e)));
        assert_eq!(&c.rig(), rig, "{name}");
        assert!(c.frames() >= 1, "{name}");
        assert_eq!(c.fps(), 30.0);
        assert!(c.rig_report().contains("\"matched\""), "{name}");
    }
}

#[wasm_bindgen_test]
fn every_fixture_stylizes_in_every_mode() {
    ENGINE.with(|e| {
        assert_eq!(e.backend(), "flex");
        assert_eq!(e.settings(), ["supervised", "unsupervised"]);
        assert!(e.styles().iter().any(|s| s == "old"));
        let reference = import(REFERENCE);
        for (name, text) in FOREIGN {
            let content = import(text);
            let n = content.frames();
            let joints = text.matches("JOINT").count() + 1;
            let modes: Vec<(&str, StyleSpec, bool)> = vec![
                ("label", StyleSpec::label("old".into()), false),
                ("motion+label", StyleSpec::motion(&reference, Some("old".into())), false),
                ("motion", StyleSpec::motion(&reference, None), true),
                ("prior supervised", StyleSpec::prior(), false),
                ("prior", StyleSpec::prior(), true),
                (
                    "mix",
                    StyleSpec::mix(
                        &StyleSpec::label("proud".into()),
                        &StyleSpec::motion(&reference, Some("old".into())),
                        0.3,
                    )
                    .unwrap(),
                    false,
                ),
            ];
            for (mode, style, unsupervised) in &modes {
                for canonical in [false, true] {
                    let outs = run(e, &content, style, *unsupervised, 2.0, 7, canonical);
                    assert_eq!(outs.len(), 2, "{name} {mode}");
                    for out in &outs {
                        check_output(out, n);
                        let expected = if canonical { 21 } else { joints };
                        assert_eq!(out.joint_names().len(), expected, "{name} {mode} canonical={canonical}");
                    }
                }
            }
        }
    });
}

#[wasm_bindgen_test]
fn same_input_and_seed_give_the_same_bits() {
    ENGINE.with(|e| {
        let content = import(FOREIGN[3].1);
        let style = StyleSpec::label("tired".into());
        let texts = |seed| {
            run(e, &content, &style, false, 3.0, seed, false).iter().map(StylizedMotion::to_bvh).collect::<Vec<_>>()
        };
        let first = texts(11);
        assert_eq!(first, texts(11));
        assert_eq!(first, texts(11));
        assert_ne!(first, texts(12));
        assert_ne!(first[0], first[1], "samples differ");
        // A BigInt seed is the same seed as the number.
        let big = e.stylize(&content, &style, options(false, 3.0, JsValue::from(11u64), false, None)).unwrap();
        assert_eq!(first, big.iter().map(StylizedMotion::to_bvh).collect::<Vec<_>>());
        // Temperature: undefined is the library's default; 0 draws the zero code whatever the seed.
        let with_t = |seed: f64, t: Option<f64>| {
            e.stylize(&content, &style, options(false, 1.0, JsValue::from_f64(seed), false, t)).unwrap()[0].to_bvh()
        };
        let default_t = f64::from(motion_stylizer::stylize::DEFAULT_TEMPERATURE);
        assert_eq!(with_t(11.0, None), with_t(11.0, Some(default_t)));
        assert_ne!(with_t(11.0, None), with_t(11.0, Some(1.0)));
        assert_eq!(with_t(1.0, Some(0.0)), with_t(2.0, Some(0.0)));
        // A mix at t = 0 is its first source.
        let reference = import(REFERENCE);
        let a = StyleSpec::motion(&reference, None);
        let mix = StyleSpec::mix(&a, &StyleSpec::prior(), 0.0).unwrap();
        let plain = run(e, &content, &a, true, 1.0, 3, true)[0].to_bvh();
        assert_eq!(plain, run(e, &content, &mix, true, 1.0, 3, true)[0].to_bvh());
    });
}

#[wasm_bindgen_test]
fn malformed_bvh_gives_bvh_parse_with_line_and_kind() {
    // (file, reader error kind, line), from tests/bvh_malformed.rs.
    const CASES: &[(&str, &str, usize)] = &[
        (include_str!("malformed/empty.bvh"), "UnexpectedEof", 1),
        (include_str!("malformed/duplicate_joint.bvh"), "DuplicateJoint", 6),
        (include_str!("malformed/comma_decimal.bvh"), "NotANumber", 20),
        (include_str!("malformed/crlf_wrong_value_count.bvh"), "WrongValueCount", 20),
        (include_str!("malformed/frame_time_nan.bvh"), "NonFinite", 18),
        (include_str!("malformed/frames_absurd.bvh"), "LimitExceeded", 17),
        (include_str!("malformed/frames_overflow_u64.bvh"), "LimitExceeded", 17),
        (include_str!("malformed/channels_over_limit.bvh"), "LimitExceeded", 5),
    ];
    for &(text, kind, line) in CASES {
        let e = match ImportedMotion::from_bvh(text, None) {
            Ok(_) => panic!("parsed: {text:.60}"),
            Err(e) => e,
        };
        assert_eq!(code(&e), "BVH_PARSE", "{}", message(&e));
        let got_line = prop(&e, "line").as_f64().unwrap() as usize;
        let got_kind = prop(&e, "kind").as_string().unwrap();
        assert!(message(&e).starts_with(&format!("line {got_line}: ")), "{}", message(&e));
        assert_eq!((got_kind.as_str(), got_line), (kind, line), "{}", message(&e));
    }
}

/// The motion keeps its source file: joint names, parents, frames, frame time, and the file's own
/// joint positions (every `step`-th frame) by the crate's forward kinematics.
#[wasm_bindgen_test]
fn the_source_file_gives_its_own_joint_positions() {
    for (name, text) in FOREIGN {
        let m = import(text);
        let bvh = Bvh::parse(text).unwrap();
        let joints = bvh.joints.len();
        assert_eq!(m.source_joint_names(), bvh.joints.iter().map(|j| j.name.clone()).collect::<Vec<_>>(), "{name}");
        let parents = m.source_parents();
        assert_eq!(parents.len(), joints);
        assert_eq!(parents[0], -1);
        assert!(parents.iter().enumerate().skip(1).all(|(i, &p)| p >= 0 && (p as usize) < i), "{name}");
        assert_eq!((m.source_frames(), m.source_frame_time()), (bvh.frames, bvh.frame_time), "{name}");
        let all = m.source_positions(1);
        assert_eq!(all.len(), bvh.frames * joints * 3, "{name}");
        assert_eq!(m.source_positions(0), all, "{name}: a step of 0 is 1");
        for f in 0..bvh.frames {
            let (pose, _) = bvh.global_pose(f);
            let expected: Vec<f32> = pose.iter().flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]).collect();
            assert_eq!(&all[f * joints * 3..(f + 1) * joints * 3], expected.as_slice(), "{name} frame {f}");
            // The root's position channels are its world position, as the file has them.
            for (k, channel) in bvh.joints[0].channels.iter().enumerate() {
                if let Channel::Position(axis) = channel {
                    assert_eq!(all[f * joints * 3 + axis.index()], bvh.frame(f)[k] as f32, "{name} frame {f}");
                }
            }
        }
        let every_other = m.source_positions(2);
        assert_eq!(every_other.len(), bvh.frames.div_ceil(2) * joints * 3, "{name}");
        for (k, frame) in every_other.chunks(joints * 3).enumerate() {
            assert_eq!(frame, &all[2 * k * joints * 3..(2 * k + 1) * joints * 3], "{name}");
        }
    }
}

#[wasm_bindgen_test]
fn rigs_that_cannot_be_used_give_rig_codes() {
    assert_eq!(err_code(ImportedMotion::from_bvh(SMALL, None)), "RIG_UNMATCHED");
    // The m21 walk with every bone of zero length.
    let flat: String = FOREIGN[3]
        .1
        .lines()
        .map(|l| if l.trim_start().starts_with("OFFSET") { "OFFSET 0 0 0" } else { l })
        .collect::<Vec<_>>()
        .join("\n");
    assert_eq!(err_code(ImportedMotion::from_bvh(&flat, None)), "RIG_DEGENERATE");
}

#[wasm_bindgen_test]
fn bad_requests_give_their_codes() {
    ENGINE.with(|e| {
        let content = import(FOREIGN[3].1);
        let reference = import(REFERENCE);
        let label = StyleSpec::label("old".into());
        let call = |style: &StyleSpec, unsupervised: bool, samples: f64, seed: JsValue| {
            err_code(e.stylize(&content, style, options(unsupervised, samples, seed, false, None)))
        };
        let zero = JsValue::from_f64(0.0);
        assert_eq!(call(&StyleSpec::label("grumpy".into()), false, 1.0, zero.clone()), "UNKNOWN_LABEL");
        assert_eq!(
            call(&StyleSpec::motion(&reference, Some("grumpy".into())), false, 1.0, zero.clone()),
            "UNKNOWN_LABEL"
        );
        for samples in [0.0, 65.0, 2.5, -1.0, f64::NAN, f64::INFINITY, 1e300] {
            assert_eq!(call(&label, false, samples, zero.clone()), "BAD_REQUEST", "samples {samples}");
        }
        for seed in [-1.0, 1.5, f64::NAN, 2f64.powi(60)] {
            assert_eq!(call(&label, false, 1.0, JsValue::from_f64(seed)), "BAD_REQUEST", "seed {seed}");
        }
        assert_eq!(call(&label, false, 1.0, JsValue::from_str("7")), "BAD_REQUEST");
        assert_eq!(call(&label, false, 1.0, JsValue::bigint_from_str("-1")), "BAD_REQUEST");
        assert_eq!(call(&label, false, 1.0, JsValue::bigint_from_str("18446744073709551616")), "BAD_REQUEST");
        assert_eq!(call(&label, true, 1.0, zero.clone()), "BAD_REQUEST", "label with the unsupervised model");
        assert_eq!(call(&StyleSpec::motion(&reference, None), false, 1.0, zero.clone()), "BAD_REQUEST");
        assert_eq!(call(&StyleSpec::motion(&reference, Some("old".into())), true, 1.0, zero.clone()), "BAD_REQUEST");
        for temperature in [-0.5, 4.5, f64::NAN, f64::INFINITY] {
            let r = e.stylize(&content, &label, options(false, 1.0, zero.clone(), false, Some(temperature)));
            assert_eq!(err_code(r), "BAD_REQUEST", "temperature {temperature}");
        }
        for t in [-0.1, 1.5, f64::NAN] {
            let mix = StyleSpec::mix(&label, &StyleSpec::prior(), t).unwrap();
            assert_eq!(call(&mix, false, 1.0, zero.clone()), "BAD_REQUEST", "t {t}");
        }
        // Mixes nest up to 8 deep and no deeper.
        let mut spec = StyleSpec::prior();
        for _ in 0..8 {
            spec = StyleSpec::mix(&spec, &StyleSpec::prior(), 0.5).unwrap();
        }
        assert_eq!(run(e, &content, &spec, true, 1.0, 0, true).len(), 1);
        assert_eq!(err_code(StyleSpec::mix(&spec, &StyleSpec::prior(), 0.5)), "BAD_REQUEST");
    });
}

/// The options object: absent properties (or no object) are the defaults; properties of the wrong
/// type, a non-object and a getter that throws are `BAD_REQUEST`s that say what is wrong.
#[wasm_bindgen_test]
fn stylize_options_take_defaults_and_refuse_wrong_types() {
    ENGINE.with(|e| {
        let content = import(FOREIGN[3].1);
        let label = StyleSpec::label("old".into());
        let defaults = run(e, &content, &label, false, 1.0, 0, false)[0].to_bvh();
        for o in [JsValue::UNDEFINED, JsValue::NULL, object(&[]), object(&[("samples", JsValue::NULL)])] {
            let outs = e.stylize(&content, &label, o).unwrap_or_else(|e| panic!("{}", message(&e)));
            assert_eq!(outs.len(), 1);
            assert_eq!(outs[0].to_bvh(), defaults);
        }
        let throwing = js_sys::Object::new();
        let getter = js_sys::Object::new();
        js_sys::Reflect::set(&getter, &"get".into(), &js_sys::Function::new_no_args("throw new Error('no')")).unwrap();
        js_sys::Object::define_property(&throwing, &"samples".into(), &getter);
        let cases = [
            (JsValue::from_str("fast"), "the stylize options must be an object"),
            (object(&[("unsupervised", "yes".into())]), "unsupervised must be a boolean"),
            (object(&[("canonical", JsValue::from_f64(1.0))]), "canonical must be a boolean"),
            (object(&[("samples", "2".into())]), "samples must be a number"),
            (object(&[("samples", JsValue::from_f64(2.5))]), "samples must be a positive integer, got 2.5"),
            (object(&[("seed", "7".into())]), "seed must be a number or a BigInt"),
            (object(&[("temperature", "1".into())]), "temperature must be a number in [0, 4]"),
            (throwing.into(), "cannot read samples"),
        ];
        for (o, expected) in cases {
            let err = match e.stylize(&content, &label, o) {
                Ok(_) => panic!("expected {expected:?}"),
                Err(err) => err,
            };
            assert_eq!((code(&err).as_str(), message(&err).as_str()), ("BAD_REQUEST", expected));
        }
    });
}

#[wasm_bindgen_test]
fn weights_that_cannot_be_used_give_bad_weights() {
    let load = |m: &[u8], n: &[u8], s: Option<&[u8]>, u: Option<&[u8]>| {
        err_code(Engine::new(m, n, Some(SHARED.to_vec()), s.map(<[u8]>::to_vec), u.map(<[u8]>::to_vec), "cpu"))
    };
    assert_eq!(load(b"{", NORM, Some(SUPERVISED), None), "BAD_WEIGHTS");
    assert_eq!(load(MANIFEST, b"[]", Some(SUPERVISED), None), "BAD_WEIGHTS");
    assert_eq!(load(MANIFEST, NORM, None, None), "BAD_WEIGHTS");
    assert_eq!(load(MANIFEST, NORM, Some(UNSUPERVISED), None), "BAD_WEIGHTS", "swapped bundles");
    assert_eq!(load(MANIFEST, NORM, Some(&SUPERVISED[..SUPERVISED.len() / 2]), None), "BAD_WEIGHTS");
    assert_eq!(load(MANIFEST, NORM, Some(b"garbage"), None), "BAD_WEIGHTS");
    assert_eq!(load(MANIFEST, NORM, Some(SUPERVISED), Some(b"")), "BAD_WEIGHTS");
    // Format 2 without the shared networks, or with a stylizer in their place.
    assert_eq!(err_code(Engine::new(MANIFEST, NORM, None, Some(SUPERVISED.to_vec()), None, "cpu")), "BAD_WEIGHTS");
    assert_eq!(
        err_code(Engine::new(MANIFEST, NORM, Some(SUPERVISED.to_vec()), Some(SUPERVISED.to_vec()), None, "cpu")),
        "BAD_WEIGHTS"
    );
    assert_eq!(
        err_code(Engine::new(MANIFEST, NORM, Some(SHARED.to_vec()), Some(SUPERVISED.to_vec()), None, "webgpu")),
        "BACKEND_UNAVAILABLE"
    );
    // One model only: the other setting is unavailable until it is added.
    let mut only = Engine::new(MANIFEST, NORM, Some(SHARED.to_vec()), Some(SUPERVISED.to_vec()), None, "cpu").unwrap();
    assert_eq!(only.settings(), ["supervised"]);
    assert_eq!(only.listed(), ["supervised", "unsupervised"]);
    let content = import(FOREIGN[3].1);
    let r = only.stylize(&content, &StyleSpec::prior(), options(true, 1.0, JsValue::UNDEFINED, false, None));
    assert_eq!(err_code(r), "SETTING_UNAVAILABLE");
    assert_eq!(err_code(only.add_setting("unsupervised", SUPERVISED)), "BAD_WEIGHTS");
    assert_eq!(err_code(only.add_setting("other", UNSUPERVISED)), "BAD_REQUEST");
    only.add_setting("unsupervised", UNSUPERVISED).unwrap();
    assert_eq!(only.settings(), ["supervised", "unsupervised"]);
    let lazy =
        only.stylize(&content, &StyleSpec::prior(), options(true, 1.0, JsValue::UNDEFINED, false, None)).unwrap();
    let eager = ENGINE.with(|e| {
        e.stylize(&content, &StyleSpec::prior(), options(true, 1.0, JsValue::UNDEFINED, false, None)).unwrap()
    });
    assert_eq!(lazy[0].to_bvh(), eager[0].to_bvh(), "a model added later gives the same bytes");
    // Format 3: label- and prior-based run without the style encoders; a reference motion needs
    // its setting's, which can be added later (the other's file, or damaged bytes, refused).
    let reference = import(REFERENCE);
    let by_motion = |e: &Engine| {
        e.stylize(&content, &StyleSpec::motion(&reference, None), options(true, 1.0, JsValue::UNDEFINED, false, None))
    };
    assert!(!only.has_style_encoder("unsupervised"));
    assert_eq!(err_code(by_motion(&only)), "STYLE_ENCODER_UNAVAILABLE");
    assert_eq!(err_code(only.add_style_encoder("unsupervised", SUPERVISED_STYLE)), "BAD_WEIGHTS");
    assert_eq!(err_code(only.add_style_encoder("unsupervised", UNSUPERVISED)), "BAD_WEIGHTS");
    assert!(!only.has_style_encoder("unsupervised"));
    only.add_style_encoder("unsupervised", UNSUPERVISED_STYLE).unwrap();
    assert!(only.has_style_encoder("unsupervised") && !only.has_style_encoder("supervised"));
    let lazy = by_motion(&only).unwrap();
    let eager = ENGINE.with(|e| by_motion(e).unwrap());
    assert_eq!(lazy[0].to_bvh(), eager[0].to_bvh(), "a style encoder added later gives the same bytes");
    // The engine's manifest reader: the files to fetch.
    let list: serde_json::Value =
        serde_json::from_str(&motion_stylizer::wasm::weight_file_list(MANIFEST).unwrap()).unwrap();
    assert_eq!(list["shared"]["file"], "shared.bin");
    assert_eq!(list["shared"]["bytes"], SHARED.len());
    assert_eq!(list["models"][1]["setting"], "unsupervised");
    assert_eq!(list["models"][1]["style_encoder"]["file"], "unsupervised-style.bin");
    assert_eq!(list["models"][1]["style_encoder"]["bytes"], UNSUPERVISED_STYLE.len());
    assert_eq!(list["norm"]["bytes"], NORM.len());
    assert_eq!(err_code(motion_stylizer::wasm::weight_file_list(b"{}")), "BAD_WEIGHTS");
}

/// The m21 walk with its frame rows' numbers (or its OFFSETs) scaled by `k`, or other header
/// edits: inputs at the edges of the arithmetic.
fn m21_edited(edit: impl Fn(&str, bool) -> String) -> String {
    let (head, motion) = FOREIGN[3].1.split_once("MOTION").unwrap();
    format!("{}MOTION{}", edit(head, true), edit(motion, false))
}

/// Every number of `text` times `k`, on frame rows (`offsets_only = false`) or OFFSET lines.
fn scale_numbers(text: &str, k: f64, offsets_only: bool) -> String {
    text.lines()
        .map(|l| {
            if l.contains("Frame") || (offsets_only && !l.trim_start().starts_with("OFFSET")) {
                return l.to_string();
            }
            l.split_whitespace()
                .map(|w| w.parse::<f64>().map_or_else(|_| w.to_string(), |v| format!("{:e}", v * k)))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .map(|l| l + "\n")
        .collect()
}

/// Inputs that could crash the module (a wasm trap leaves it unusable): extreme scales, one frame,
/// absurd frame times, a tiny file that resamples to 990,001 frames (~0.9 GB while importing).
/// Each gives a result or a coded error, and the module keeps working afterwards.
#[wasm_bindgen_test]
fn hostile_inputs_give_results_or_codes_never_a_trap() {
    ENGINE.with(|e| {
        let frame_rows = |text: &str| {
            text.lines().filter(|l| l.trim_start().starts_with(|c: char| c == '-' || c.is_ascii_digit())).count()
        };
        let with_frame_time = |ft: &str, rows: Option<usize>| {
            m21_edited(|part, head| {
                if head {
                    return part.to_string();
                }
                let lines: Vec<&str> = part.lines().filter(|l| !l.trim().is_empty()).collect();
                let data: Vec<&str> = lines
                    .iter()
                    .copied()
                    .filter(|l| !l.starts_with("Frame"))
                    .take(rows.unwrap_or(usize::MAX))
                    .collect();
                format!("\nFrames: {}\nFrame Time: {ft}\n{}\n", data.len(), data.join("\n"))
            })
        };
        let cases: Vec<(&str, String, Option<&str>)> = vec![
            ("motion ×1e6", m21_edited(|p, h| if h { p.to_string() } else { scale_numbers(p, 1e6, false) }), None),
            (
                "motion ×1e300",
                m21_edited(|p, h| if h { p.to_string() } else { scale_numbers(p, 1e300, false) }),
                Some("RIG_DEGENERATE"),
            ),
            ("motion ×0", m21_edited(|p, h| if h { p.to_string() } else { scale_numbers(p, 0.0, false) }), None),
            ("offsets ×1e30", m21_edited(|p, h| if h { scale_numbers(p, 1e30, true) } else { p.to_string() }), None),
            (
                "offsets ×1e-300",
                m21_edited(|p, h| if h { scale_numbers(p, 1e-300, true) } else { p.to_string() }),
                Some("RIG_DEGENERATE"),
            ),
            ("one frame", with_frame_time("0.0166667", Some(1)), None),
            ("frame time 1e-300", with_frame_time("1e-300", None), None),
            ("frame time 1e300", with_frame_time("1e300", None), Some("TOO_LONG")),
            ("9,301 frames at 30 fps", with_frame_time("310", Some(2)), Some("TOO_LONG")),
            ("990,001 frames at 30 fps", with_frame_time("33000", Some(2)), Some("TOO_LONG")),
        ];
        for (name, text, expected) in &cases {
            assert!(frame_rows(text) >= 1, "{name}");
            let outcome = ImportedMotion::from_bvh(text, None).and_then(|content| {
                let reference = ImportedMotion::from_bvh(text, None)?;
                let styles = [
                    (StyleSpec::label("old".into()), false),
                    (StyleSpec::motion(&reference, None), true),
                    (StyleSpec::prior(), false),
                ];
                for (style, unsupervised) in &styles {
                    for out in
                        e.stylize(&content, style, options(*unsupervised, 2.0, JsValue::from_f64(1.0), false, None))?
                    {
                        check_output(&out, content.frames());
                    }
                }
                Ok(())
            });
            match (outcome, expected) {
                (Ok(()), None) => {}
                (Err(err), Some(code_)) => assert_eq!(&code(&err), code_, "{name}: {}", message(&err)),
                (Ok(()), Some(code_)) => panic!("{name}: expected {code_}"),
                (Err(err), None) => panic!("{name}: {} ({})", message(&err), code(&err)),
            }
        }
        // Still working.
        assert_eq!(run(e, &import(FOREIGN[3].1), &StyleSpec::label("old".into()), false, 1.0, 0, false).len(), 1);
    });
}

/// Regression: the ndarray backend used to panic (a wasm trap: `Unsupported dtype F16` in
/// burn-ndarray) when loading the f16 weights; the bundles are now read on flex and moved. (The
/// shipped weights' large layers are 8-bit since 2026-12-04; their biases, norms and small layers
/// are still f16, and all of it is dequantised to f32 on flex first.)
/// Runs when built with the ndarray backend (`make test-wasm` does: `--features model,wasm,ndarray`).
#[cfg(feature = "ndarray")]
#[wasm_bindgen_test]
fn ndarray_backend_loads_the_f16_weights_and_stylizes() {
    let nd = Engine::new(MANIFEST, NORM, Some(SHARED.to_vec()), Some(SUPERVISED.to_vec()), None, "ndarray")
        .unwrap_or_else(|e| panic!("{}", message(&e)));
    assert_eq!(nd.backend(), "ndarray");
    let content = import(FOREIGN[3].1);
    let style = StyleSpec::label("old".into());
    let out = run(&nd, &content, &style, false, 1.0, 7, false);
    check_output(&out[0], content.frames());
    // The same motion as on flex, up to float rounding.
    let flex = ENGINE.with(|e| run(e, &content, &style, false, 1.0, 7, false)[0].positions());
    let worst = out[0].positions().iter().zip(&flex).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
    let size = flex.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    assert!(worst <= 1e-4 * size, "ndarray vs flex: {worst} (motion size {size})");
}
