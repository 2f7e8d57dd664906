"""Reads our shipped weights (`assets/weights/*.bin`) into numpy arrays, no Rust needed.

Formats 2 and 3 (src/model/parts.rs; format 3 is today's folders): part files, b"MSTYPT01" | u32
LE header-JSON length | header JSON {part, config, tensors: [{path, shape, encoding, offset, len}]}
| payload; `shared.bin` holds the autoencoder and regressor, `supervised.bin` / `unsupervised.bin`
a stylizer (its paths without the `stylizer.` prefix; format 3: part "stylizer_core", without the
style encoder, which is in `supervised-style.bin` / `unsupervised-style.bin`, part
"style_encoder"). Format 1 bundle: b"MSTYLZ01" | u32 LE config-JSON
length | config JSON | burnpack bytes. Burnpack (burn-pack 0.22, see its lib.rs): u32 magic 0x4255524E | u16 version |
u32 metadata size | CBOR metadata {tensors: {name: {dtype, shape, data_offsets, param_id}},
metadata} | padding to 256 bytes | tensor data (offsets relative to the data section).
"""

import json
import os
import struct

import numpy as np

BUNDLE_MAGIC = b"MSTYLZ01"
PART_MAGIC = b"MSTYPT01"
BURNPACK_MAGIC = 0x4255524E
BURNPACK_HEADER = 10
ALIGN = 256


class _Cbor:
    """A minimal CBOR decoder: what burnpack's metadata uses (ints, strings, arrays, maps,
    floats, bools, null)."""

    def __init__(self, data):
        self.d = data
        self.i = 0

    def _arg(self, info):
        if info < 24:
            return info
        n = {24: 1, 25: 2, 26: 4, 27: 8}[info]
        v = int.from_bytes(self.d[self.i:self.i + n], "big")
        self.i += n
        return v

    def read(self):
        b = self.d[self.i]
        self.i += 1
        major, info = b >> 5, b & 31
        if major == 7:
            if info == 20:
                return False
            if info == 21:
                return True
            if info in (22, 23):
                return None
            if info == 25:
                v = np.frombuffer(self.d[self.i:self.i + 2], ">f2")[0]
                self.i += 2
                return float(v)
            if info == 26:
                v = struct.unpack(">f", self.d[self.i:self.i + 4])[0]
                self.i += 4
                return v
            if info == 27:
                v = struct.unpack(">d", self.d[self.i:self.i + 8])[0]
                self.i += 8
                return v
            raise ValueError(f"CBOR simple value {info}")
        if info == 31:
            raise ValueError("indefinite-length CBOR item")
        n = self._arg(info)
        if major == 0:
            return n
        if major == 1:
            return -1 - n
        if major in (2, 3):
            v = self.d[self.i:self.i + n]
            self.i += n
            return bytes(v) if major == 2 else bytes(v).decode()
        if major == 4:
            return [self.read() for _ in range(n)]
        if major == 5:
            out = {}
            for _ in range(n):
                k = self.read()
                out[k if not isinstance(k, list) else tuple(k)] = self.read()
            return out
        if major == 6:
            return self.read()
        raise ValueError(f"CBOR major type {major}")


_DTYPES = {"F16": np.float16, "F32": np.float32, "F64": np.float64, "BF16": None}


def _dtype_name(d):
    if isinstance(d, str):
        return d
    if isinstance(d, dict) and len(d) == 1:
        return next(iter(d))
    raise ValueError(f"unknown dtype encoding {d!r}")


def read_burnpack(data):
    """{tensor name: float32 array} from burnpack bytes."""
    magic, version, meta_len = struct.unpack_from("<IHI", data, 0)
    if magic != BURNPACK_MAGIC:
        raise ValueError("not a burnpack record")
    meta = _Cbor(memoryview(data)[BURNPACK_HEADER:BURNPACK_HEADER + meta_len]).read()
    start = BURNPACK_HEADER + meta_len
    start = (start + ALIGN - 1) // ALIGN * ALIGN
    out = {}
    for name, t in meta["tensors"].items():
        dtype = _DTYPES.get(_dtype_name(t["dtype"]))
        if dtype is None:
            raise ValueError(f"{name}: dtype {t['dtype']!r} not supported")
        a, b = t["data_offsets"]
        arr = np.frombuffer(data, dtype=dtype, count=(b - a) // np.dtype(dtype).itemsize, offset=start + a)
        out[name] = arr.reshape([int(s) for s in t["shape"]]).astype(np.float32)
    return out


def _unframe(data, magic, path, what):
    """(header JSON, payload) of our framing (src/model/weights.rs `frame`): magic | u32 LE
    header length | header JSON | payload."""
    if data[:8] != magic:
        raise ValueError(f"{path}: not {what}")
    (n,) = struct.unpack_from("<I", data, 8)
    return json.loads(data[12:12 + n]), memoryview(data)[12 + n:]


def _decode_int(raw, shape, bits, group, where):
    """float32 values of an integer-encoded tensor, as `src/model/parts.rs` `decode_tensor`
    dequantises them (the same f32 product int × f16 scale, so the same bits): the tensor seen as
    `rows` output channels of `length` weights (rank 2 `[in, out]`: the columns; otherwise the
    first axis), one f16 scale per `group` weights of a channel (0: the whole channel), then the
    integers channel by channel (4 bits: two a byte, low nibble first; 5 to 8: a signed byte each)."""
    count = int(np.prod(shape, dtype=np.int64))
    rows = shape[1] if len(shape) == 2 else (shape[0] if shape else 1)
    length = count // max(rows, 1)
    group = length if group == 0 else min(group, length)
    group = max(group, 1)
    groups = -(-length // group)
    n_scales = rows * groups
    n_ints = -(-count // 2) if bits == 4 else count
    if len(raw) != 2 * n_scales + n_ints:
        raise ValueError(f"{where}: {len(raw)} bytes for shape {shape} in q{bits}g{group}")
    scales = np.frombuffer(raw, dtype="<f2", count=n_scales).astype(np.float32).reshape(rows, groups)
    body = np.frombuffer(raw, dtype=np.uint8, offset=2 * n_scales)
    if bits == 4:
        nibbles = np.stack([body & 0x0F, body >> 4], axis=1).reshape(-1)[:count].astype(np.int16)
        ints = np.where(nibbles >= 8, nibbles - 16, nibbles).astype(np.float32)
    else:
        ints = body.view(np.int8).astype(np.float32)
    ints = ints.reshape(rows, length)
    per_weight = np.repeat(scales, group, axis=1)[:, :length]
    values = (ints * per_weight).astype(np.float32)
    if len(shape) == 2:
        return values.T.reshape(shape)
    return values.reshape(shape)


def _parse_encoding(spec, where):
    """(bits, group) of a tensor's header encoding, None for f16: `"f16"` or
    `{"int": {"bits": B, "group": G}}` (serde's form of `TensorEncoding`)."""
    if spec == "f16":
        return None
    try:
        bits, group = int(spec["int"]["bits"]), int(spec["int"]["group"])
    except (TypeError, KeyError, ValueError):
        raise ValueError(f"{where}: unknown encoding {spec!r}") from None
    if not 4 <= bits <= 8 or group < 0:
        raise ValueError(f"{where}: unknown encoding {spec!r}")
    return bits, group


def read_part(path):
    """(header dict, {parameter path: float32 array}) of a part file (format 2 or 3): f16 tensors,
    or integers with f16 scales dequantised exactly as ours are."""
    with open(path, "rb") as f:
        data = f.read()
    header, payload = _unframe(data, PART_MAGIC, path, "a motion-stylizer weights part")
    out = {}
    for t in header["tensors"]:
        where = f"{path}: {t['path']}"
        count = int(np.prod(t["shape"], dtype=np.int64))
        if t["offset"] + t["len"] > len(payload):
            raise ValueError(f"{where}: {t['len']} bytes past the end")
        enc = _parse_encoding(t["encoding"], where)
        if enc is None:
            if t["len"] != 2 * count:
                raise ValueError(f"{where}: {t['len']} bytes for shape {t['shape']}")
            arr = np.frombuffer(payload, dtype="<f2", count=count, offset=t["offset"])
            out[t["path"]] = arr.reshape(t["shape"]).astype(np.float32)
        else:
            raw = payload[t["offset"]:t["offset"] + t["len"]]
            out[t["path"]] = _decode_int(raw, list(t["shape"]), enc[0], enc[1], where)
    return header, out


def read_bundle(path):
    """(config dict, {parameter path: float32 array}) of one model: a format-1 bundle, or a
    format-2 stylizer part or format-3 stylizer core with the `shared.bin` (and, format 3, the
    `<setting>-style.bin`) beside it (paths as format 1's: `autoencoder.…`, `regressor.…`,
    `stylizer.…`)."""
    with open(path, "rb") as f:
        magic = f.read(8)
    if magic == PART_MAGIC:
        header, stylizer = read_part(path)
        if header["part"] not in ("stylizer", "stylizer_core"):
            raise ValueError(f"{path}: holds the {header['part']} networks, not a stylizer")
        beside = lambda name: os.path.join(os.path.dirname(os.path.abspath(path)), name)
        if header["part"] == "stylizer_core":
            stem = os.path.splitext(os.path.basename(path))[0]
            style_header, style = read_part(beside(f"{stem}-style.bin"))
            if style_header["part"] != "style_encoder" or style_header["config"] != header["config"]:
                raise ValueError(f"{path}: the {stem}-style.bin beside it is not its style encoder")
            stylizer.update(style)
        shared_header, tensors = read_part(beside("shared.bin"))
        if shared_header["part"] != "shared":
            raise ValueError(f"{path}: the shared.bin beside it holds the {shared_header['part']} networks")
        tensors.update({"stylizer." + k: v for k, v in stylizer.items()})
        return header["config"], tensors
    with open(path, "rb") as f:
        data = f.read()
    config, payload = _unframe(data, BUNDLE_MAGIC, path, "a motion-stylizer weights bundle or part")
    return config, read_burnpack(payload)


if __name__ == "__main__":
    import sys

    config, tensors = read_bundle(sys.argv[1])
    print(json.dumps(config))
    for k, v in tensors.items():
        print(k, v.shape)
