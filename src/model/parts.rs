//! Weight parts (manifest formats 2 and 3): one file for the networks both stylizers share
//! (autoencoder and global motion regressor), per stylizer one file for the networks every mode
//! needs (content encoder and generator) and one for its style encoder (needed only by motion-based
//! stylization and label inference, so fetched later); format 2's stylizer files hold all three.
//! Every tensor by name in its own encoding: f16, or integers with f16 scales, dequantised at load.
//! Framed as every weights file of ours ([`super::weights::frame`]).

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::prelude::*;
use burn::tensor::{TensorData, f16};
use serde::{Deserialize, Serialize};

use super::ModelError;
use super::autoencoder::MotionAutoencoder;
use super::config::ModelConfig;
use super::content::ContentEncoder;
use super::generator::Generator;
use super::regressor::GlobalRegressor;
use super::style::StyleEncoder;
use super::stylizer::Stylizer;
use super::weights::{FrameError, frame, unframe};

const PART_MAGIC: &[u8; 8] = b"MSTYPT01";

/// The networks both stylizers are trained on and share: the motion autoencoder and the global
/// motion regressor (stage 1).
#[derive(Module, Debug)]
pub struct SharedNets {
    pub autoencoder: MotionAutoencoder,
    pub regressor: GlobalRegressor,
}

impl SharedNets {
    pub fn new(cfg: &ModelConfig, device: &Device) -> Self {
        Self { autoencoder: MotionAutoencoder::new(cfg, device), regressor: GlobalRegressor::new(cfg, device) }
    }
}

/// The networks of a stylizer that every mode needs: the content encoder and the generator
/// (label- and prior-based stylization need nothing else from it).
#[derive(Module, Debug)]
pub struct StylizerCore {
    pub content_encoder: ContentEncoder,
    pub generator: Generator,
}

/// A stylizer's style encoder, under the path it has in the [`Stylizer`] (`style_encoder.…`, so
/// that an encoding's `style_encoder=` override means the same in every format).
#[derive(Module, Debug)]
pub struct StyleEncoderPart {
    pub style_encoder: StyleEncoder,
}

impl Stylizer {
    /// The stylizer as format 3 stores it: the networks every mode needs, and the style encoder.
    pub fn split(self) -> (StylizerCore, StyleEncoderPart) {
        let Stylizer { content_encoder, style_encoder, generator } = self;
        (StylizerCore { content_encoder, generator }, StyleEncoderPart { style_encoder })
    }

    /// The stylizer from its two format-3 parts.
    pub fn from_parts(core: StylizerCore, style: StyleEncoder) -> Stylizer {
        Stylizer { content_encoder: core.content_encoder, style_encoder: style, generator: core.generator }
    }
}

/// What a part file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PartKind {
    /// [`SharedNets`].
    Shared,
    /// A whole [`Stylizer`] (its setting is the config's `supervised`): format 2.
    Stylizer,
    /// A stylizer without its style encoder ([`StylizerCore`]): format 3.
    #[serde(rename = "stylizer_core")]
    StylizerCore,
    /// A stylizer's style encoder alone ([`StyleEncoderPart`]): format 3.
    #[serde(rename = "style_encoder")]
    StyleEncoder,
}

impl core::fmt::Display for PartKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            PartKind::Shared => "shared",
            PartKind::Stylizer => "stylizer",
            PartKind::StylizerCore => "stylizer core",
            PartKind::StyleEncoder => "style encoder",
        })
    }
}

/// How one tensor is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum TensorEncoding {
    /// IEEE half floats.
    #[serde(rename = "f16")]
    F16,
    /// Symmetric integers of `bits` bits (4 or 8) with one f16 scale per group of `group`
    /// consecutive weights of an output channel (0: the whole channel), dequantised at load.
    #[serde(rename = "int")]
    Int { bits: u8, group: usize },
}

/// The encoding of a part's tensors: `large` for weight matrices and kernels of at least
/// `min_len` values, f16 for everything else (biases, norms, small layers); `overrides`: another
/// encoding for the large tensors whose path starts with a prefix (the first match).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartEncoding {
    pub large: TensorEncoding,
    pub min_len: usize,
    pub overrides: Vec<(String, TensorEncoding)>,
}

/// Large tensors: rank ≥ 2 and at least this many values.
const MIN_QUANTISED: usize = 4096;

impl TensorEncoding {
    /// `"f16"`, `"q8"` (int8, a scale per output channel), `"q4"`, `"q4g64"` (int4, a scale per
    /// 64 weights of an output channel), `"q6"`, ...: the CLI's spelling (4 to 8 bits).
    pub fn parse(spec: &str) -> Option<TensorEncoding> {
        let spec = spec.trim();
        if spec == "f16" {
            return Some(TensorEncoding::F16);
        }
        let rest = spec.strip_prefix('q')?;
        let (bits, group) = match rest.split_once('g') {
            Some((b, g)) => (b.parse::<u8>().ok()?, g.parse::<usize>().ok().filter(|&g| g > 0)?),
            None => (rest.parse::<u8>().ok()?, 0),
        };
        matches!(bits, 4..=8).then_some(TensorEncoding::Int { bits, group })
    }

    /// The CLI's spelling ([`TensorEncoding::parse`]).
    pub fn name(&self) -> String {
        match *self {
            TensorEncoding::F16 => "f16".into(),
            TensorEncoding::Int { bits, group: 0 } => format!("q{bits}"),
            TensorEncoding::Int { bits, group } => format!("q{bits}g{group}"),
        }
    }
}

impl PartEncoding {
    /// Every tensor in f16 (the format-1 bundles' precision).
    pub const F16: PartEncoding =
        PartEncoding { large: TensorEncoding::F16, min_len: usize::MAX, overrides: Vec::new() };

    /// `ENCODING[,PREFIX=ENCODING...]`: the large tensors' encoding ([`TensorEncoding::parse`]),
    /// then per path prefix another one, e.g. `q4g64,style_encoder=q8`.
    pub fn parse(spec: &str) -> Option<PartEncoding> {
        let mut items = spec.split(',');
        let large = TensorEncoding::parse(items.next()?)?;
        let overrides = items
            .map(|item| {
                let (prefix, enc) = item.split_once('=')?;
                Some((prefix.trim().to_string(), TensorEncoding::parse(enc)?))
            })
            .collect::<Option<Vec<_>>>()?;
        let quantised = large != TensorEncoding::F16 || overrides.iter().any(|(_, e)| *e != TensorEncoding::F16);
        Some(PartEncoding { large, min_len: if quantised { MIN_QUANTISED } else { usize::MAX }, overrides })
    }

    /// The CLI's spelling ([`PartEncoding::parse`]).
    pub fn name(&self) -> String {
        let mut name = self.large.name();
        for (prefix, enc) in &self.overrides {
            name.push_str(&format!(",{prefix}={}", enc.name()));
        }
        name
    }

    /// The encoding of the tensor at `path` (a large one, or f16).
    pub fn of(&self, path: &str, shape: &[usize]) -> TensorEncoding {
        let len: usize = shape.iter().product();
        if shape.len() < 2 || len < self.min_len {
            return TensorEncoding::F16;
        }
        let path = path.strip_prefix("stylizer.").unwrap_or(path);
        self.overrides.iter().find(|(p, _)| path.starts_with(p.as_str())).map_or(self.large, |(_, e)| *e)
    }
}

/// One tensor of a part: where its bytes are in the payload and how they are encoded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartTensor {
    pub path: String,
    pub shape: Vec<usize>,
    pub encoding: TensorEncoding,
    /// Byte range in the payload.
    pub offset: usize,
    pub len: usize,
}

/// A part file's header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartHeader {
    pub part: PartKind,
    pub config: ModelConfig,
    pub tensors: Vec<PartTensor>,
}

/// Why bytes are not a readable part file.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PartError {
    #[error("not a motion-stylizer weights part")]
    NotOurs,
    #[error("truncated")]
    Truncated,
    #[error("header: {0}")]
    Header(String),
    #[error("it holds the {found} networks, not the {expected}")]
    WrongPart { expected: PartKind, found: PartKind },
    #[error("{path}: {message}")]
    Tensor { path: String, message: String },
    #[error("no tensor for the parameter {0}")]
    Missing(String),
    #[error("tensors no parameter takes: {0}")]
    Unused(String),
}

impl From<PartError> for ModelError {
    fn from(e: PartError) -> Self {
        ModelError::Weights(e.to_string())
    }
}

/// Float parameters of a module with their paths (`a.b.weight`), as f32.
#[derive(Default)]
struct Collect {
    path: Vec<String>,
    tensors: Vec<(String, Vec<usize>, Vec<f32>)>,
    failed: Option<String>,
}

impl ModuleVisitor for Collect {
    fn enter_module(&mut self, name: &str, _container_type: &str) {
        self.path.push(name.to_string());
    }
    fn exit_module(&mut self, _name: &str, _container_type: &str) {
        self.path.pop();
    }
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        let path = self.path.join(".");
        let data = param.val().into_data();
        let shape = data.shape().to_vec();
        match data.convert::<f32>().try_into_vec::<f32>() {
            Ok(values) => self.tensors.push((path, shape, values)),
            Err(e) => self.failed = Some(format!("{path}: {e:?}")),
        }
    }
    fn visit_int<const D: usize>(&mut self, _param: &Param<Tensor<D, burn::tensor::Int>>) {
        self.failed = Some(format!("{}: integer parameters are not supported", self.path.join(".")));
    }
    fn visit_bool<const D: usize>(&mut self, _param: &Param<Tensor<D, burn::tensor::Bool>>) {
        self.failed = Some(format!("{}: boolean parameters are not supported", self.path.join(".")));
    }
}

/// Row `r`, position `j` of a tensor viewed as output channels: rank-2 tensors are Burn linear
/// weights `[in, out]` (a channel is a column), everything else has its output channel first.
struct Rows {
    rows: usize,
    len: usize,
    columns: bool,
}

impl Rows {
    fn of(shape: &[usize]) -> Rows {
        let numel: usize = shape.iter().product();
        match shape {
            [] => Rows { rows: 1, len: numel, columns: false },
            [_, out] => Rows { rows: *out, len: numel / (*out).max(1), columns: true },
            [out, ..] => Rows { rows: *out, len: numel / (*out).max(1), columns: false },
        }
    }
    fn index(&self, r: usize, j: usize) -> usize {
        if self.columns { j * self.rows + r } else { r * self.len + j }
    }
}

/// The f16 scale and the integers of one group of weights: symmetric, the clipping threshold
/// chosen among 0.6–1.0 of the largest magnitude for the least squared error.
fn quantise_group(values: &[f32], bits: u8) -> (f16, Vec<i8>) {
    let qmax = ((1i32 << (bits - 1)) - 1) as f32;
    let max = values.iter().fold(0f32, |m, v| m.max(v.abs()));
    if max == 0.0 || !max.is_finite() {
        return (f16::from_f32(0.0), vec![0; values.len()]);
    }
    let mut best: Option<(f32, f16)> = None;
    for step in 0..=16 {
        let clip = 1.0 - 0.025 * step as f32;
        let scale = f16::from_f32(max * clip / qmax);
        let s = scale.to_f32();
        if s == 0.0 {
            continue;
        }
        let err: f32 = values
            .iter()
            .map(|&v| {
                let q = (v / s).round().clamp(-qmax, qmax);
                (v - q * s).powi(2)
            })
            .sum();
        if best.is_none_or(|(e, _)| err < e) {
            best = Some((err, scale));
        }
    }
    let scale = best.map(|(_, s)| s).unwrap_or(f16::from_f32(max / qmax));
    let s = scale.to_f32();
    let q = values.iter().map(|&v| if s == 0.0 { 0 } else { (v / s).round().clamp(-qmax, qmax) as i8 }).collect();
    (scale, q)
}

fn encode_tensor(shape: &[usize], values: &[f32], encoding: TensorEncoding, out: &mut Vec<u8>) {
    match encoding {
        TensorEncoding::F16 => {
            for &v in values {
                out.extend_from_slice(&f16::from_f32(v).to_bits().to_le_bytes());
            }
        }
        TensorEncoding::Int { bits, group } => {
            let rows = Rows::of(shape);
            let group = if group == 0 { rows.len } else { group.min(rows.len) };
            let groups = rows.len.div_ceil(group.max(1));
            let mut scales = Vec::with_capacity(rows.rows * groups * 2);
            let mut ints = Vec::with_capacity(values.len());
            for r in 0..rows.rows {
                let row: Vec<f32> = (0..rows.len).map(|j| values[rows.index(r, j)]).collect();
                for chunk in row.chunks(group.max(1)) {
                    let (scale, q) = quantise_group(chunk, bits);
                    scales.extend_from_slice(&scale.to_bits().to_le_bytes());
                    ints.extend(q);
                }
            }
            out.extend_from_slice(&scales);
            match bits {
                4 => out.extend(ints.chunks(2).map(|p| {
                    let lo = (p[0] as u8) & 0x0f;
                    let hi = (p.get(1).copied().unwrap_or(0) as u8) & 0x0f;
                    lo | (hi << 4)
                })),
                // 5 to 8 bits: a byte each (gzip, as a server sends them, takes out what is unused).
                _ => out.extend(ints.iter().map(|&q| q as u8)),
            }
        }
    }
}

/// The number of bytes a tensor of `numel` values in `rows` takes in `encoding`.
fn encoded_len(shape: &[usize], encoding: TensorEncoding) -> Option<usize> {
    let numel = shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d))?;
    match encoding {
        TensorEncoding::F16 => numel.checked_mul(2),
        TensorEncoding::Int { bits, group } => {
            let rows = Rows::of(shape);
            let group = if group == 0 { rows.len } else { group.min(rows.len) };
            let groups = rows.len.div_ceil(group.max(1));
            let scales = rows.rows.checked_mul(groups)?.checked_mul(2)?;
            let ints = match bits {
                4 => numel.div_ceil(2),
                5..=8 => numel,
                _ => return None,
            };
            scales.checked_add(ints)
        }
    }
}

fn decode_tensor(t: &PartTensor, bytes: &[u8]) -> Result<Vec<f32>, String> {
    let numel: usize = t.shape.iter().product();
    match t.encoding {
        TensorEncoding::F16 => {
            Ok(bytes.chunks_exact(2).map(|b| f16::from_bits(u16::from_le_bytes([b[0], b[1]])).to_f32()).collect())
        }
        TensorEncoding::Int { bits, group } => {
            let rows = Rows::of(&t.shape);
            let group = if group == 0 { rows.len } else { group.min(rows.len) }.max(1);
            let groups = rows.len.div_ceil(group);
            let (scales, ints) = bytes.split_at_checked(rows.rows * groups * 2).ok_or("truncated scales")?;
            let scale = |i: usize| f16::from_bits(u16::from_le_bytes([scales[2 * i], scales[2 * i + 1]])).to_f32();
            let int = |k: usize| -> f32 {
                if bits == 4 {
                    let b = ints[k / 2];
                    let nibble = if k % 2 == 0 { b & 0x0f } else { b >> 4 };
                    (((nibble << 4) as i8) >> 4) as f32
                } else {
                    ints[k] as i8 as f32
                }
            };
            let mut out = vec![0f32; numel];
            let mut k = 0;
            for r in 0..rows.rows {
                for j in 0..rows.len {
                    let s = scale(r * groups + j / group);
                    out[rows.index(r, j)] = int(k) * s;
                    k += 1;
                }
            }
            Ok(out)
        }
    }
}

/// Every float parameter of `module` by path (`autoencoder.encoder.down1.conv.weight`), with its
/// shape and values in f32.
pub fn float_params<M: Module>(module: &M) -> Result<Vec<(String, Vec<usize>, Vec<f32>)>, ModelError> {
    let mut collect = Collect::default();
    module.visit(&mut collect);
    match collect.failed {
        Some(message) => Err(ModelError::Weights(message)),
        None => Ok(collect.tensors),
    }
}

/// A part file of `module`: every float parameter by path, those of at least `encoding.min_len`
/// values with rank ≥ 2 in `encoding.large`, the others in f16.
pub fn save_part<M: Module>(
    kind: PartKind,
    config: &ModelConfig,
    module: M,
    encoding: &PartEncoding,
) -> Result<Vec<u8>, ModelError> {
    let params = float_params(&module)?;
    let mut payload = Vec::new();
    let mut tensors = Vec::with_capacity(params.len());
    for (path, shape, values) in params {
        let enc = encoding.of(&path, &shape);
        let offset = payload.len();
        encode_tensor(&shape, &values, enc, &mut payload);
        tensors.push(PartTensor { path, shape, encoding: enc, offset, len: payload.len() - offset });
    }
    let header = PartHeader { part: kind, config: config.clone(), tensors };
    let json = serde_json::to_vec(&header).map_err(|e| ModelError::Weights(e.to_string()))?;
    Ok(frame(PART_MAGIC, &json, &payload))
}

/// The header of a part file (its config and tensor table), without decoding any tensor.
pub fn part_header(bytes: &[u8]) -> Result<(PartHeader, &[u8]), PartError> {
    let (json, payload) = unframe(PART_MAGIC, bytes).map_err(|e| match e {
        FrameError::NotOurs => PartError::NotOurs,
        FrameError::Truncated => PartError::Truncated,
    })?;
    let header: PartHeader = serde_json::from_slice(json).map_err(|e| PartError::Header(e.to_string()))?;
    for t in &header.tensors {
        let bad = |message: &str| PartError::Tensor { path: t.path.clone(), message: message.into() };
        let expected = encoded_len(&t.shape, t.encoding).ok_or_else(|| bad("an impossible shape or encoding"))?;
        if expected != t.len {
            return Err(bad(&format!("{} bytes, its shape and encoding take {expected}", t.len)));
        }
        if t.offset.checked_add(t.len).is_none_or(|end| end > payload.len()) {
            return Err(PartError::Truncated);
        }
    }
    Ok((header, payload))
}

/// Loads decoded tensors onto matching parameters by path.
struct Apply<'a> {
    path: Vec<String>,
    tensors: std::collections::HashMap<&'a str, &'a PartTensor>,
    payload: &'a [u8],
    error: Option<PartError>,
}

impl ModuleMapper for Apply<'_> {
    fn enter_module(&mut self, name: &str, _container_type: &str) {
        self.path.push(name.to_string());
    }
    fn exit_module(&mut self, _name: &str, _container_type: &str) {
        self.path.pop();
    }
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        if self.error.is_some() {
            return param;
        }
        let path = self.path.join(".");
        let Some(t) = self.tensors.remove(path.as_str()) else {
            self.error = Some(PartError::Missing(path));
            return param;
        };
        let shape = param.lazy_shape();
        if shape.as_slice() != t.shape.as_slice() {
            self.error = Some(PartError::Tensor {
                path,
                message: format!("shape {:?}, the network's is {:?}", t.shape, shape.to_vec()),
            });
            return param;
        }
        let values = match decode_tensor(t, &self.payload[t.offset..t.offset + t.len]) {
            Ok(v) => v,
            Err(message) => {
                self.error = Some(PartError::Tensor { path, message });
                return param;
            }
        };
        let device = param.lazy_device();
        let tensor = Tensor::<D>::from_data(TensorData::new(values, t.shape.clone()), &device);
        let id = param.id;
        param.transform_for_load(tensor, id)
    }
}

/// Reads a part file of `expected` kind into `template` (a module of the architecture its
/// config describes, e.g. freshly built and lazily initialised), parameters in f32.
pub fn load_part<M: Module>(expected: PartKind, template: M, bytes: &[u8]) -> Result<M, PartError> {
    let (header, payload) = part_header(bytes)?;
    if header.part != expected {
        return Err(PartError::WrongPart { expected, found: header.part });
    }
    let mut apply = Apply {
        path: Vec::new(),
        tensors: header.tensors.iter().map(|t| (t.path.as_str(), t)).collect(),
        payload,
        error: None,
    };
    let module = template.map(&mut apply);
    if let Some(e) = apply.error {
        return Err(e);
    }
    if !apply.tensors.is_empty() {
        let mut unused: Vec<&str> = apply.tensors.keys().copied().collect();
        unused.sort_unstable();
        return Err(PartError::Unused(unused.join(", ")));
    }
    Ok(module)
}

/// The shared networks of a [`PartKind::Shared`] file, on `device`.
pub fn load_shared(bytes: &[u8], device: &Device) -> Result<(ModelConfig, SharedNets), PartError> {
    let (header, _) = part_header(bytes)?;
    let nets = load_part(PartKind::Shared, SharedNets::new(&header.config, device), bytes)?;
    Ok((header.config, nets))
}

/// The stylizer of a [`PartKind::Stylizer`] file, on `device`.
pub fn load_stylizer(bytes: &[u8], device: &Device) -> Result<(ModelConfig, Stylizer), PartError> {
    let (header, _) = part_header(bytes)?;
    let stylizer = load_part(PartKind::Stylizer, Stylizer::new(&header.config, device), bytes)?;
    Ok((header.config, stylizer))
}

/// The stylizer networks of a [`PartKind::StylizerCore`] file, on `device`.
pub fn load_stylizer_core(bytes: &[u8], device: &Device) -> Result<(ModelConfig, StylizerCore), PartError> {
    let (header, _) = part_header(bytes)?;
    let template = StylizerCore {
        content_encoder: ContentEncoder::new(&header.config, device),
        generator: Generator::new(&header.config, device),
    };
    Ok((header.config.clone(), load_part(PartKind::StylizerCore, template, bytes)?))
}

/// The style encoder of a [`PartKind::StyleEncoder`] file, on `device`.
pub fn load_style_encoder(bytes: &[u8], device: &Device) -> Result<(ModelConfig, StyleEncoder), PartError> {
    let (header, _) = part_header(bytes)?;
    let template = StyleEncoderPart { style_encoder: StyleEncoder::new(&header.config, device) };
    Ok((header.config.clone(), load_part(PartKind::StyleEncoder, template, bytes)?.style_encoder))
}

/// FNV-1a, 64 bits: the manifest's fingerprint of each weight file (16 hex digits).
pub fn fnv1a64(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}
