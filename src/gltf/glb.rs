//! The `.glb` container of an [`Animation`]: the glTF JSON (typed structs below, written with
//! `serde_json`) and one binary buffer, every buffer view 4-byte aligned, one accessor per view.

use super::{Animation, GltfError};
use glam::{DMat4, DQuat, DVec3};
use serde::Serialize;

const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const TRIANGLES: u32 = 4;

// The parts of glTF 2.0 this writer uses (field names as the spec spells them).

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Gltf<'a> {
    asset: Asset,
    scene: usize,
    scenes: [Scene<'a>; 1],
    nodes: Vec<Node<'a>>,
    skins: [Skin; 1],
    meshes: [Mesh; 1],
    materials: [Material; 1],
    animations: [AnimationJson<'a>; 1],
    buffers: [BufferJson; 1],
    buffer_views: Vec<View>,
    accessors: Vec<Accessor>,
}

#[derive(Serialize)]
struct Asset {
    version: &'static str,
    generator: &'static str,
}

#[derive(Serialize)]
struct Scene<'a> {
    name: &'a str,
    nodes: Vec<usize>,
    extras: SceneExtras,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct SceneExtras {
    metres_per_unit: f64,
    orientation: [f64; 4],
    frame_time: f64,
    frames: usize,
}

#[derive(Serialize, Default)]
struct Node<'a> {
    name: &'a str,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    children: Vec<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    translation: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rotation: Option<[f32; 4]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mesh: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    skin: Option<usize>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Skin {
    name: &'static str,
    joints: Vec<usize>,
    inverse_bind_matrices: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    skeleton: Option<usize>,
}

#[derive(Serialize)]
struct Mesh {
    name: &'static str,
    primitives: [Primitive; 1],
}

#[derive(Serialize)]
struct Primitive {
    attributes: Attributes,
    indices: usize,
    material: usize,
    mode: u32,
}

#[derive(Serialize)]
struct Attributes {
    #[serde(rename = "POSITION")]
    position: usize,
    #[serde(rename = "JOINTS_0")]
    joints: usize,
    #[serde(rename = "WEIGHTS_0")]
    weights: usize,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Material {
    name: &'static str,
    pbr_metallic_roughness: Pbr,
    double_sided: bool,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Pbr {
    base_color_factor: [f32; 4],
    metallic_factor: f32,
    roughness_factor: f32,
}

#[derive(Serialize)]
struct AnimationJson<'a> {
    name: &'a str,
    samplers: Vec<Sampler>,
    channels: Vec<ChannelJson>,
}

#[derive(Serialize)]
struct Sampler {
    input: usize,
    output: usize,
    interpolation: &'static str,
}

#[derive(Serialize)]
struct ChannelJson {
    sampler: usize,
    target: Target,
}

#[derive(Serialize)]
struct Target {
    node: usize,
    path: &'static str,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct BufferJson {
    byte_length: usize,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct View {
    buffer: usize,
    byte_offset: usize,
    byte_length: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    target: Option<u32>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Accessor {
    buffer_view: usize,
    component_type: u32,
    count: usize,
    #[serde(rename = "type")]
    kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    min: Option<Vec<f32>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max: Option<Vec<f32>>,
}

/// The binary chunk being filled, with its buffer views and accessors.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<View>,
    accessors: Vec<Accessor>,
}

impl Buffer {
    /// Appends `data` (already little-endian bytes) as one buffer view; returns the view index.
    fn view(&mut self, data: &[u8], target: Option<u32>) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views.push(View { buffer: 0, byte_offset: self.bytes.len(), byte_length: data.len(), target });
        self.bytes.extend_from_slice(data);
        self.views.len() - 1
    }

    /// A float accessor of elements of `kind` ("SCALAR", "VEC3", "VEC4", "MAT4"), with its bounds
    /// where asked.
    fn floats(&mut self, values: &[f32], kind: &'static str, target: Option<u32>, bounds: bool) -> usize {
        let width = components(kind);
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let buffer_view = self.view(&bytes, target);
        let (mut min, mut max) = (None, None);
        if bounds {
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for chunk in values.chunks_exact(width) {
                for (k, &v) in chunk.iter().enumerate() {
                    lo[k] = lo[k].min(v);
                    hi[k] = hi[k].max(v);
                }
            }
            (min, max) = (Some(lo), Some(hi));
        }
        let count = values.len() / width;
        self.accessors.push(Accessor { buffer_view, component_type: FLOAT, count, kind, min, max });
        self.accessors.len() - 1
    }

    /// An unsigned-integer accessor: 16-bit where every value fits, else 32-bit. Returns the
    /// accessor and whether it is 16-bit.
    fn integers(&mut self, values: &[u32], kind: &'static str, target: Option<u32>) -> (usize, bool) {
        let short = values.iter().all(|&v| v <= u16::MAX as u32);
        let bytes: Vec<u8> = if short {
            values.iter().flat_map(|&v| (v as u16).to_le_bytes()).collect()
        } else {
            values.iter().flat_map(|v| v.to_le_bytes()).collect()
        };
        let buffer_view = self.view(&bytes, target);
        let component_type = if short { UNSIGNED_SHORT } else { UNSIGNED_INT };
        let count = values.len() / components(kind);
        self.accessors.push(Accessor { buffer_view, component_type, count, kind, min: None, max: None });
        (self.accessors.len() - 1, short)
    }
}

fn components(kind: &str) -> usize {
    match kind {
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT4" => 16,
        _ => 1,
    }
}

fn vec3(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// A unit quaternion in f32, `[x, y, z, w]`, normalised after the conversion.
fn quat(q: DQuat) -> [f32; 4] {
    let v = [q.x as f32, q.y as f32, q.z as f32, q.w as f32];
    let len = v.iter().map(|c| c * c).sum::<f32>().sqrt();
    v.map(|c| c / len)
}

/// The skin's mesh: one octahedral bone from `a` to `b` per link (rest pose, glTF world space),
/// every vertex bound to joint `joint` with weight 1. Positions, joint indices, triangle indices.
#[derive(Default)]
struct Bones {
    positions: Vec<f32>,
    joints: Vec<u32>,
    indices: Vec<u32>,
}

impl Bones {
    fn push(&mut self, a: DVec3, b: DVec3, joint: usize) {
        let axis = b - a;
        let length = axis.length();
        let d = axis / length;
        let (u, v) = d.any_orthonormal_pair();
        let width = 0.08 * length;
        let centre = a + axis * 0.2;
        let base = (self.positions.len() / 3) as u32;
        let ring = [u, v, -u, -v].map(|e| centre + e * width);
        for p in [a, b].into_iter().chain(ring) {
            self.positions.extend(vec3(p));
            self.joints.extend([joint as u32, 0, 0, 0]);
        }
        for i in 0..4u32 {
            let (r, next) = (base + 2 + i, base + 2 + (i + 1) % 4);
            // Counter-clockwise seen from outside: towards the tip, then towards the base.
            self.indices.extend([r, next, base + 1, next, r, base]);
        }
    }
}

/// The `.glb` bytes of `a`.
pub(super) fn write(a: &Animation) -> Result<Vec<u8>, GltfError> {
    let n = a.joints();
    let mut buffer = Buffer::default();

    // Nodes: the joints, then the skinned mesh's node (a root, as glTF asks).
    let mut nodes: Vec<Node> = (0..n)
        .map(|j| Node {
            name: &a.names[j],
            translation: Some(vec3(a.rest_translation[j])),
            rotation: (a.rest_rotation[j] != DQuat::IDENTITY).then(|| quat(a.rest_rotation[j])),
            ..Node::default()
        })
        .collect();
    for j in 0..n {
        if let Some(p) = a.parents[j] {
            nodes[p].children.push(j);
        }
    }
    let roots: Vec<usize> = (0..n).filter(|&j| a.parents[j].is_none()).collect();

    // The skin: inverse bind matrices of the rest pose, and a mesh of bone shapes.
    let (rest_pos, rest_rot) = a.rest_world();
    let inverse_bind: Vec<f32> = (0..n)
        .flat_map(|j| DMat4::from_rotation_translation(rest_rot[j], rest_pos[j]).inverse().to_cols_array())
        .map(|v| v as f32)
        .collect();
    let scale = rest_pos.iter().map(|p| (*p - rest_pos[0]).length()).fold(0.0, f64::max);
    let tiny = 1e-6 * scale.max(1e-3);
    let mut bones = Bones::default();
    for j in 0..n {
        if let Some(p) = a.parents[j]
            && (rest_pos[j] - rest_pos[p]).length() > tiny
        {
            bones.push(rest_pos[p], rest_pos[j], p);
        }
        if let Some(e) = a.end_sites[j] {
            let tip = rest_pos[j] + rest_rot[j] * e;
            if (tip - rest_pos[j]).length() > tiny {
                bones.push(rest_pos[j], tip, j);
            }
        }
    }
    if bones.indices.is_empty() {
        // A skeleton without extent: a small marker at the root, so that the mesh is not empty.
        bones.push(rest_pos[0], rest_pos[0] + DVec3::Y * 0.05, 0);
    }
    let position = buffer.floats(&bones.positions, "VEC3", Some(ARRAY_BUFFER), true);
    let (joints, short) = buffer.integers(&bones.joints, "VEC4", Some(ARRAY_BUFFER));
    if !short {
        return Err(GltfError::TooManyJoints { joints: n, max: super::MAX_JOINTS });
    }
    let weights: Vec<f32> = (0..bones.joints.len() / 4).flat_map(|_| [1.0, 0.0, 0.0, 0.0]).collect();
    let weights = buffer.floats(&weights, "VEC4", Some(ARRAY_BUFFER), false);
    let (indices, _) = buffer.integers(&bones.indices, "SCALAR", Some(ELEMENT_ARRAY_BUFFER));
    let inverse_bind_matrices = buffer.floats(&inverse_bind, "MAT4", None, false);
    let mesh_node = nodes.len();
    nodes.push(Node { name: "skeleton", mesh: Some(0), skin: Some(0), ..Node::default() });

    // The animation: shared keyframe times, then one sampler per animated property.
    let times: Vec<f32> = (0..a.frames).map(|f| (f as f64 * a.frame_time) as f32).collect();
    if times.windows(2).any(|w| w[1] <= w[0]) {
        let reason = format!("{} frames of {} s do not have distinct 32-bit keyframe times", a.frames, a.frame_time);
        return Err(GltfError::TooLarge { reason });
    }
    let input = buffer.floats(&times, "SCALAR", None, true);
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    for j in 0..n {
        let frames = (0..a.frames).map(|f| f * n + j);
        let mut track = |values: Vec<f32>, kind: &'static str, path: &'static str| {
            let output = buffer.floats(&values, kind, None, false);
            channels.push(ChannelJson { sampler: samplers.len(), target: Target { node: j, path } });
            samplers.push(Sampler { input, output, interpolation: "LINEAR" });
        };
        if a.animated_translation[j] {
            track(frames.clone().flat_map(|k| vec3(a.translation[k])).collect(), "VEC3", "translation");
        }
        if a.animated_rotation[j] {
            track(frames.flat_map(|k| quat(a.rotation[k])).collect(), "VEC4", "rotation");
        }
    }
    while !buffer.bytes.len().is_multiple_of(4) {
        buffer.bytes.push(0);
    }

    let o = &a.options;
    let q = o.orientation.normalize();
    let mut scene_nodes = roots.clone();
    scene_nodes.push(mesh_node);
    let gltf = Gltf {
        asset: Asset { version: "2.0", generator: concat!("motion-stylizer ", env!("CARGO_PKG_VERSION")) },
        scene: 0,
        scenes: [Scene {
            name: &o.animation_name,
            nodes: scene_nodes,
            extras: SceneExtras {
                metres_per_unit: o.metres_per_unit,
                orientation: [q.x, q.y, q.z, q.w],
                frame_time: a.frame_time,
                frames: a.frames,
            },
        }],
        nodes,
        skins: [Skin {
            name: "skeleton",
            joints: (0..n).collect(),
            inverse_bind_matrices,
            skeleton: (roots.len() == 1).then(|| roots[0]),
        }],
        meshes: [Mesh {
            name: "skeleton",
            primitives: [Primitive {
                attributes: Attributes { position, joints, weights },
                indices,
                material: 0,
                mode: TRIANGLES,
            }],
        }],
        materials: [Material {
            name: "bone",
            pbr_metallic_roughness: Pbr {
                base_color_factor: [0.93, 0.55, 0.3, 1.0],
                metallic_factor: 0.0,
                roughness_factor: 0.7,
            },
            double_sided: true,
        }],
        animations: [AnimationJson { name: &o.animation_name, samplers, channels }],
        buffers: [BufferJson { byte_length: buffer.bytes.len() }],
        buffer_views: buffer.views,
        accessors: buffer.accessors,
    };
    let text = serde_json::to_vec(&gltf).map_err(|e| GltfError::Malformed { reason: format!("glTF JSON: {e}") })?;
    container(text, &buffer.bytes)
}

/// The GLB container: a 12-byte header, the JSON chunk (padded with spaces), the BIN chunk.
fn container(mut text: Vec<u8>, bin: &[u8]) -> Result<Vec<u8>, GltfError> {
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let too_large = || GltfError::TooLarge { reason: format!("{total} bytes: a .glb holds at most 4 GiB") };
    let length = u32::try_from(total).map_err(|_| too_large())?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend(length.to_le_bytes());
    for (chunk, kind) in [(&text[..], b"JSON"), (bin, b"BIN\0")] {
        out.extend((chunk.len() as u32).to_le_bytes());
        out.extend_from_slice(kind);
        out.extend_from_slice(chunk);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::{GltfOptions, to_glb};
    use crate::bvh::Bvh;

    /// The JSON and BIN chunks of a `.glb`, checking its header and chunk layout.
    fn chunks(glb: &[u8]) -> (serde_json::Value, Vec<u8>) {
        let word = |at: usize| u32::from_le_bytes(glb[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(word(4), 2);
        assert_eq!(word(8), glb.len());
        let json_len = word(12);
        assert_eq!(&glb[16..20], b"JSON");
        assert_eq!(json_len % 4, 0);
        let json = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        let at = 20 + json_len;
        let bin_len = word(at);
        assert_eq!(&glb[at + 4..at + 8], b"BIN\0");
        assert_eq!(at + 8 + bin_len, glb.len());
        (json, glb[at + 8..].to_vec())
    }

    #[test]
    fn the_container_and_its_json_hold_together() {
        let text = "HIERARCHY\nROOT A\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n JOINT B\n {\n  OFFSET 1 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 1 0 0\n  }\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n0 0 0 0 0 0\n90 0 0 0 0 0\n";
        let glb = to_glb(&Bvh::parse(text).unwrap(), &GltfOptions::canonical()).unwrap();
        let (json, bin) = chunks(&glb);
        assert_eq!(json["buffers"][0]["byteLength"], bin.len());
        assert_eq!(json["nodes"].as_array().unwrap().len(), 3, "two joints and the mesh node");
        assert_eq!(json["nodes"][0]["children"], serde_json::json!([1]));
        assert_eq!(json["animations"][0]["channels"].as_array().unwrap().len(), 2, "two rotations");
        assert_eq!(
            json["accessors"][json["animations"][0]["samplers"][0]["input"].as_u64().unwrap() as usize]["max"][0],
            0.5
        );
        for view in json["bufferViews"].as_array().unwrap() {
            assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
            assert!(view["byteOffset"].as_u64().unwrap() + view["byteLength"].as_u64().unwrap() <= bin.len() as u64);
        }
    }
}
