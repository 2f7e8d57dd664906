//! `-o OUT.glb` of `retarget` and `stylize`: the binary glTF the CLI writes, read back here by a
//! small reader of our own (header, chunks, accessors, node rest transforms, animation channels)
//! and posed frame by frame: every joint's world position must be the BVH's (written by the same
//! command with `-o OUT.bvh`) in metres, Y up.

mod support;

use glam::{DQuat, DVec3};
use motion_stylizer::bvh::Bvh;
use motion_stylizer::skeleton::UserRig;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_motion-stylizer")).args(args).output().expect("run the CLI")
}

fn ok(args: &[&str]) {
    let out = cli(args);
    assert!(out.status.success(), "{args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
}

fn fixture(rel: &str) -> String {
    format!("{}/tests/fixtures/{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gltf-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A `.glb` read back: its JSON and binary chunk.
struct Glb {
    json: Value,
    bin: Vec<u8>,
}

impl Glb {
    fn read(path: &Path) -> Glb {
        let glb = std::fs::read(path).unwrap();
        let word = |at: usize| u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&glb[0..4], b"glTF", "magic");
        assert_eq!(word(4), 2, "version");
        assert_eq!(word(8), glb.len(), "length");
        let json_len = word(12);
        assert_eq!(&glb[16..20], b"JSON");
        let json: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        let at = 20 + json_len;
        assert_eq!(&glb[at + 4..at + 8], b"BIN\0");
        let bin = glb[at + 8..at + 8 + word(at)].to_vec();
        assert_eq!(json["buffers"][0]["byteLength"].as_u64().unwrap() as usize, bin.len());
        Glb { json, bin }
    }

    /// The float values of accessor `i` (tightly packed, as the writer makes them).
    fn floats(&self, i: u64) -> Vec<f64> {
        let a = &self.json["accessors"][i as usize];
        assert_eq!(a["componentType"], 5126);
        let view = &self.json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize + a["byteOffset"].as_u64().unwrap_or(0) as usize;
        let width = match a["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            t => panic!("type {t}"),
        };
        let n = a["count"].as_u64().unwrap() as usize * width;
        (0..n)
            .map(|k| f32::from_le_bytes(self.bin[start + 4 * k..start + 4 * k + 4].try_into().unwrap()) as f64)
            .collect()
    }

    /// World joint positions of every keyframe: the nodes' rest transforms, overridden by the
    /// animation's channels, composed down the node tree.
    fn posed(&self, joints: usize) -> Vec<Vec<DVec3>> {
        let nodes = self.json["nodes"].as_array().unwrap();
        let vec = |v: &Value, n: usize, default: &[f64]| -> Vec<f64> {
            v.as_array().map_or(default.to_vec(), |a| a.iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>())[..n]
                .to_vec()
        };
        let mut parent = vec![None; nodes.len()];
        for (i, node) in nodes.iter().enumerate() {
            for c in node["children"].as_array().into_iter().flatten() {
                parent[c.as_u64().unwrap() as usize] = Some(i);
            }
        }
        let anim = &self.json["animations"][0];
        let samplers = anim["samplers"].as_array().unwrap();
        let frames = self.floats(samplers[0]["input"].as_u64().unwrap()).len();
        let mut t: Vec<Vec<DVec3>> =
            nodes.iter().map(|n| vec![DVec3::from_slice(&vec(&n["translation"], 3, &[0.0; 3])); frames]).collect();
        let mut r: Vec<Vec<DQuat>> = nodes
            .iter()
            .map(|n| vec![DQuat::from_slice(&vec(&n["rotation"], 4, &[0.0, 0.0, 0.0, 1.0])); frames])
            .collect();
        for ch in anim["channels"].as_array().unwrap() {
            let sampler = &samplers[ch["sampler"].as_u64().unwrap() as usize];
            assert_eq!(sampler["interpolation"], "LINEAR");
            let values = self.floats(sampler["output"].as_u64().unwrap());
            let node = ch["target"]["node"].as_u64().unwrap() as usize;
            match ch["target"]["path"].as_str().unwrap() {
                "translation" => t[node] = values.chunks_exact(3).map(DVec3::from_slice).collect(),
                "rotation" => r[node] = values.chunks_exact(4).map(DQuat::from_slice).collect(),
                p => panic!("path {p}"),
            }
        }
        (0..frames)
            .map(|f| {
                let mut world: Vec<(DVec3, DQuat)> = Vec::with_capacity(joints);
                for j in 0..joints {
                    let local = (t[j][f], r[j][f]);
                    world.push(match parent[j] {
                        None => local,
                        Some(p) => {
                            assert!(p < j, "joints in BVH order");
                            let (pt, pr) = world[p];
                            (pt + pr * local.0, pr * local.1)
                        }
                    });
                }
                world.into_iter().map(|(p, _)| p).collect()
            })
            .collect()
    }
}

/// Asserts that the `.glb` poses every joint of every frame where `bvh` does, once scaled and turned.
fn assert_matches(glb: &Glb, bvh: &Bvh, metres_per_unit: f64, turn: DQuat) {
    let nodes = glb.json["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), bvh.joints.len() + 1, "one node per joint and the skinned mesh's");
    for (j, joint) in bvh.joints.iter().enumerate() {
        assert_eq!(nodes[j]["name"], joint.name.as_str());
    }
    assert_eq!(glb.json["skins"][0]["joints"].as_array().unwrap().len(), bvh.joints.len());
    let extras = &glb.json["scenes"][0]["extras"];
    assert!((extras["metresPerUnit"].as_f64().unwrap() - metres_per_unit).abs() < 1e-12);
    let posed = glb.posed(bvh.joints.len());
    assert_eq!(posed.len(), bvh.frames);
    let mut worst: f64 = 0.0;
    for (f, got) in posed.iter().enumerate() {
        let (want, _) = bvh.global_pose(f);
        for j in 0..bvh.joints.len() {
            worst = worst.max((got[j] - turn * (want[j] * metres_per_unit)).length());
        }
    }
    assert!(worst < 1e-4, "worst joint position error {worst} m");
    // Upright in glTF's Y-up world: the head (or last joint) above the root on the first frame.
    let head = bvh.joints.iter().position(|j| j.name.to_lowercase().contains("head")).unwrap_or(bvh.joints.len() - 1);
    assert!(posed[0][head].y - posed[0][0].y > 0.2, "the head stands above the root: {:?}", posed[0][head]);
}

#[test]
fn retarget_writes_glb_on_the_canonical_rig() {
    let (bvh_out, glb_out) = (temp("canonical.bvh"), temp("canonical.glb"));
    ok(&["retarget", &fixture("foreign/m21_walk.bvh"), "-o", s(&bvh_out)]);
    ok(&["retarget", &fixture("foreign/m21_walk.bvh"), "-o", s(&glb_out)]);
    let bvh = Bvh::parse(&std::fs::read_to_string(&bvh_out).unwrap()).unwrap();
    assert_matches(&Glb::read(&glb_out), &bvh, 0.01, DQuat::IDENTITY);
}

#[test]
fn retarget_onto_a_user_rig_writes_glb_in_metres_y_up() {
    let canonical = temp("onto-src.bvh");
    ok(&["retarget", &fixture("bandai/dataset-2_walk_normal_001_f120.bvh"), "-o", s(&canonical)]);
    for rig in [
        "foreign/cmu31_xia_neutral_16_000.bvh",
        "foreign/iclone100_cmu_002_04.bvh",
        "bandai/dataset-1_walk_tired_001_f90.bvh",
    ] {
        let name = Path::new(rig).file_stem().unwrap().to_str().unwrap();
        let (bvh_out, glb_out) = (temp(&format!("{name}.bvh")), temp(&format!("{name}.GLB")));
        ok(&["retarget", s(&canonical), "--onto", &fixture(rig), "-o", s(&bvh_out)]);
        ok(&["retarget", s(&canonical), "--onto", &fixture(rig), "-o", s(&glb_out)]);
        let bvh = Bvh::parse(&std::fs::read_to_string(&bvh_out).unwrap()).unwrap();
        let user = UserRig::from_bvh(&Bvh::parse(&std::fs::read_to_string(fixture(rig)).unwrap()).unwrap()).unwrap();
        let options = motion_stylizer::gltf::GltfOptions::for_rig(user.report());
        assert!((options.metres_per_unit - user.scale() / 100.0).abs() < 1e-15);
        assert_matches(&Glb::read(&glb_out), &bvh, options.metres_per_unit, options.orientation);
    }
}

#[test]
fn other_worlds_and_units_give_the_same_glb_pose() {
    // A rig in Z-up, facing -Z and Z-up-facing-X worlds, in other units: its .glb is in metres, Y up,
    // facing +Z, so it poses every joint where the original rig's .glb does.
    let canonical = temp("worlds-src.bvh");
    ok(&["retarget", &fixture("bandai/dataset-2_walk_elderly_001_f120.bvh"), "-o", s(&canonical)]);
    let rig = support::fixture("foreign", "m21_walk");
    let posed_onto = |rig: &Bvh, name: &str| {
        let rig_path = temp(&format!("{name}.rig.bvh"));
        std::fs::write(&rig_path, rig.to_bvh_string()).unwrap();
        let (bvh_out, glb_out) = (temp(&format!("{name}.bvh")), temp(&format!("{name}.glb")));
        ok(&["retarget", s(&canonical), "--onto", s(&rig_path), "-o", s(&bvh_out)]);
        ok(&["retarget", s(&canonical), "--onto", s(&rig_path), "-o", s(&glb_out)]);
        let bvh = Bvh::parse(&std::fs::read_to_string(&bvh_out).unwrap()).unwrap();
        let options = motion_stylizer::gltf::GltfOptions::for_rig(UserRig::from_bvh(rig).unwrap().report());
        let glb = Glb::read(&glb_out);
        assert_matches(&glb, &bvh, options.metres_per_unit, options.orientation);
        glb.posed(bvh.joints.len())
    };
    let original = posed_onto(&rig, "world-original");
    let quarter_x = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    let worlds = [
        ("z-up", quarter_x, 2.54),
        ("facing-back", DQuat::from_rotation_y(std::f64::consts::PI), 0.01),
        ("z-up-facing-x", DQuat::from_rotation_z(-std::f64::consts::FRAC_PI_2) * quarter_x, 10.0),
    ];
    for (name, q, scale) in worlds {
        let posed = posed_onto(&support::transform_world(&rig, q, scale), name);
        let worst = posed
            .iter()
            .zip(&original)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| (*p - *q).length()))
            .fold(0.0, f64::max);
        assert!(worst < 1e-4, "{name}: {worst} m from the original world's pose");
    }
}

#[cfg(feature = "model")]
#[test]
fn stylize_writes_glb_like_its_bvh() {
    let (bvh_out, glb_out) = (temp("old.bvh"), temp("old.glb"));
    let content = fixture("foreign/m21_walk.bvh");
    for out in [&bvh_out, &glb_out] {
        ok(&["stylize", &content, "--label", "old", "--seed", "3", "-o", s(out)]);
    }
    let bvh = Bvh::parse(&std::fs::read_to_string(&bvh_out).unwrap()).unwrap();
    let user = UserRig::from_bvh(&Bvh::parse(&std::fs::read_to_string(&content).unwrap()).unwrap()).unwrap();
    let options = motion_stylizer::gltf::GltfOptions::for_rig(user.report());
    assert_matches(&Glb::read(&glb_out), &bvh, options.metres_per_unit, options.orientation);

    // Several samples, on the canonical rig: OUT_0.glb, OUT_1.glb.
    let many = temp("many.glb");
    ok(&["stylize", &content, "--prior", "--samples", "2", "--canonical", "-o", s(&many)]);
    for i in 0..2 {
        let glb = Glb::read(&temp(&format!("many_{i}.glb")));
        assert_eq!(glb.json["nodes"].as_array().unwrap().len(), 22, "21 canonical joints and the mesh node");
    }
}

#[test]
fn gltf_json_is_refused_with_a_pointer_to_glb() {
    let out = cli(&["retarget", &fixture("foreign/m21_walk.bvh"), "-o", s(&temp("x.gltf"))]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(".glb"), "{err}");
    assert!(!temp("x.gltf").exists());
}
