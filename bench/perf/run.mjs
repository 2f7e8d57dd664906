// `make bench-perf`: ours against what users would use instead, on the same network at the shipped
// weights, side by side in one run on one machine:
//   - ours in wasm (examples/perf_bench.rs built for wasm32-wasip1 with SIMD, as the npm package,
//     in Node's WASI: one thread) vs onnxruntime-web (npm, wasm backend, one thread, in Node) on the
//     network exported to ONNX from its PyTorch rebuild (torch_model.py);
//   - ours native (flex, THREADS threads) vs PyTorch CPU (PyPI wheel, torch.set_num_threads(THREADS));
//   - BVH parsing, ours in wasm vs three.js BVHLoader (bench/bvh_parse/run.sh);
//   - the npm package itself (pkg/, when built): cold start in a fresh Node process and BVH text in → out.
// The work: one 160-frame supervised motion-based stylization (the reference's posterior mean) and a
// label-based one with 10 samples (and with 1), network only (normalised features in and out, output
// read back), plus ours end to end (BVH text in → BVH text out).
//
// First a parity check: PyTorch and onnxruntime-web must give our outputs within 1e-4 on the same
// inputs (style noise drawn by our side and passed in), and ours in wasm must match ours native;
// the run fails otherwise. Then ROUNDS rounds, each running every side REPEATS times after a warm-up
// (the sides interleaved round by round); the medians over all runs are compared. Prints a table and
// ratios, and writes bench/results.json (every ratio is our time ÷ the other's, lower is better).
//
//   node bench/perf/run.mjs [--rounds R] [--repeats N] [--threads T] [--out FILE]
// Needs: target/release/examples/perf_bench, target/wasm32-wasip1/release/examples/perf_bench.wasm,
// bench/perf/.venv (scripts/setup-bench.sh), bench/perf/node_modules; `make bench-perf` builds them.

import { execFileSync } from 'node:child_process';
import { mkdtempSync, mkdirSync, readFileSync, rmSync, statSync, writeFileSync, readdirSync, existsSync } from 'node:fs';
import { cpus, loadavg, tmpdir, totalmem, release } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { gzipSync } from 'node:zlib';
import { clip160 } from '../wasm/clip.mjs';

const here = dirname(new URL(import.meta.url).pathname);
const root = resolve(here, '../..');
const opt = (name, dflt) => {
  const i = process.argv.indexOf(`--${name}`);
  return i >= 0 ? process.argv[i + 1] : dflt;
};
const rounds = Number(opt('rounds', 5));
const repeats = Number(opt('repeats', 5));
const threads = Number(opt('threads', 1));
const outFile = resolve(opt('out', join(root, 'bench/results.json')));
const targetDir = resolve(root, process.env.CARGO_TARGET_DIR ?? 'target');
const nativeBin = join(targetDir, 'release/examples/perf_bench');
const wasmBin = join(targetDir, 'wasm32-wasip1/release/examples/perf_bench.wasm');
const python = join(here, '.venv/bin/python');
const weightsDir = join(root, 'assets/weights');
const supervised = join(weightsDir, 'supervised.bin');
const TOLERANCE = 1e-4;
const WORK = ['net_motion', 'net_label1', 'net_label10'];
const E2E = ['e2e_motion', 'e2e_label1', 'e2e_label10'];

for (const p of [nativeBin, wasmBin, python, join(here, 'node_modules/onnxruntime-web')]) {
  if (!existsSync(p)) throw new Error(`${p} is missing: run \`make bench-perf\` (it builds and installs everything)`);
}

const work = mkdtempSync(join(tmpdir(), 'ms-perf-'));
const fixture = (f) => readFileSync(join(root, 'tests/fixtures/bandai', f), 'utf8');
writeFileSync(join(work, 'content.bvh'), clip160(fixture('dataset-2_walk_normal_001_f120.bvh')));
writeFileSync(join(work, 'style.bvh'), clip160(fixture('dataset-2_walk_elderly_001_f120.bvh')));
const dump = join(work, 'dump');
const onnxDir = join(work, 'onnx');

// Node's WASI used to die of SIGSEGV now and then (seen 2026-12-04, 1 of ~10 runs; 2026-12-07, with
// the upsampling layers' Winograd products, 4–5 of 10 on Node 20 and 10 of 10 on Node 22). Cause
// (gdb, 2026-12-07): its `fd_write` is a V8 fast API call, it allocates, the allocation can start a
// garbage collection, and that collection's stack walk inside a fast call crashes — how often
// depends only on when the program's allocations make V8 collect. `wasm()` below therefore runs it
// with `--no-turbo-fast-api-calls` (0 of 16 crashes on Node 20 and 22; a WASI call goes through
// the ordinary path: microseconds, on the clock reads and the output only). A crash still seen is
// run again, at most twice, and said so; any other failure stops the benchmark.
const sh = (cmd, args, env = {}, tries = 3) => {
  try {
    return execFileSync(cmd, args, { encoding: 'utf8', env: { ...process.env, ...env }, maxBuffer: 1 << 26 });
  } catch (e) {
    if (e.signal !== 'SIGSEGV' || tries <= 1) throw e;
    console.error(`warning: ${args.find((a) => /\.(mjs|py)$/.test(a)) ?? cmd} died of SIGSEGV (exit code ${e.status}); running it again`);
    return sh(cmd, args, env, tries - 1);
  }
};
const lastJson = (text) => JSON.parse(text.trim().split('\n').at(-1));
const native = (n, dumpDir) =>
  lastJson(sh(nativeBin, [weightsDir, join(work, 'content.bvh'), join(work, 'style.bvh'), String(n), ...(dumpDir ? [dumpDir] : [])], {
    RAYON_NUM_THREADS: String(threads),
  }));
const wasm = (n, withDump) =>
  lastJson(sh(process.execPath, ['--no-warnings', '--no-turbo-fast-api-calls', join(here, 'wasi-run.mjs'), wasmBin, weightsDir, work, String(n), ...(withDump ? ['dump'] : [])]));
const torch = (n) => lastJson(sh(python, [join(here, 'torch_bench.py'), 'time', supervised, dump, String(n), String(threads)]));
const hasPkg = existsSync(join(root, 'pkg/index.js')) && existsSync(join(root, 'pkg/engine_bg.wasm'));
const pkgRun = (n) => lastJson(sh(process.execPath, ['--no-warnings', join(here, 'pkg-run.mjs'), work, String(n)]));

const f32 = (dir, name) => {
  const b = readFileSync(join(dir, name));
  return new Float32Array(b.buffer, b.byteOffset, b.byteLength / 4);
};
const maxAbsDiff = (a, b) => {
  if (a.length !== b.length) return Infinity;
  let m = 0;
  for (let i = 0; i < a.length; i++) m = Math.max(m, Math.abs(a[i] - b[i]));
  return m;
};

// ---- parity ----
console.log('parity: ours native → inputs and outputs; PyTorch rebuild; ONNX export; onnxruntime-web; ours wasm');
native(1, dump);
const dims = JSON.parse(readFileSync(join(dump, 'dims.json'), 'utf8'));
let torchParity;
try {
  torchParity = lastJson(sh(python, [join(here, 'torch_bench.py'), 'parity', supervised, dump, onnxDir]));
} catch (e) {
  console.error(e.stdout ?? '', e.stderr ?? '');
  throw new Error('PyTorch parity check failed (see above)');
}

const ort = await import('onnxruntime-web');
ort.env.wasm.numThreads = 1;
ort.env.wasm.simd = true;
ort.env.logLevel = 'error';
const { frames: T, features: C, style_dim: S, num_styles: K } = dims;
const feeds = {
  net_motion: {
    content: new ort.Tensor('float32', f32(dump, 'content.f32'), [1, C, T]),
    style: new ort.Tensor('float32', f32(dump, 'style.f32'), [1, C, T]),
    label: new ort.Tensor('float32', f32(dump, 'label1.f32'), [1, K]),
  },
  net_label1: {
    content: new ort.Tensor('float32', f32(dump, 'content.f32'), [1, C, T]),
    codes: new ort.Tensor('float32', f32(dump, 'codes10.f32').slice(0, S), [1, S]),
    labels: new ort.Tensor('float32', f32(dump, 'labels10.f32').slice(0, K), [1, K]),
  },
  net_label10: {
    content: new ort.Tensor('float32', f32(dump, 'content.f32'), [1, C, T]),
    codes: new ort.Tensor('float32', f32(dump, 'codes10.f32'), [10, S]),
    labels: new ort.Tensor('float32', f32(dump, 'labels10.f32'), [10, K]),
  },
};
const sessions = {};
const sessionOptions = { executionProviders: ['wasm'], graphOptimizationLevel: 'all', intraOpNumThreads: 1, interOpNumThreads: 1 };
for (const [name, file] of [['net_motion', 'motion.onnx'], ['net_label1', 'label1.onnx'], ['net_label10', 'label10.onnx']]) {
  sessions[name] = await ort.InferenceSession.create(readFileSync(join(onnxDir, file)), sessionOptions);
}
const runOrt = async (name) => {
  const out = await sessions[name].run(feeds[name]);
  return out.features.data;
};
const ortDiff = {
  ort_vs_ours_motion: maxAbsDiff(await runOrt('net_motion'), f32(dump, 'motion_out.f32')),
  ort_vs_ours_label10: maxAbsDiff(await runOrt('net_label10'), f32(dump, 'label10_out.f32')),
};
wasm(1, true);
const wasmDiff = {
  wasm_vs_native_motion: maxAbsDiff(f32(join(work, 'dump-wasm'), 'motion_out.f32'), f32(dump, 'motion_out.f32')),
  wasm_vs_native_label10: maxAbsDiff(f32(join(work, 'dump-wasm'), 'label10_out.f32'), f32(dump, 'label10_out.f32')),
};
const parity = { ...torchParity.max_abs_diff, ...ortDiff, ...wasmDiff };
for (const [k, v] of Object.entries(parity)) console.log(`  max |${k.replaceAll('_', ' ')}| = ${v.toExponential(2)}`);
const bad = Object.entries(parity).filter(([, v]) => !(v <= TOLERANCE));
if (bad.length) throw new Error(`parity above ${TOLERANCE}: ${bad.map(([k]) => k).join(', ')}`);
console.log(`  all within ${TOLERANCE}`);

// ---- timing, interleaved ----
const times = { ours_wasm: {}, ort_web: {}, ours_native: {}, torch: {}, ours_npm: {} };
const push = (side, name, values) => (times[side][name] ??= []).push(...values);
const loads = [];
for (let r = 0; r < rounds; r++) {
  loads.push(loadavg()[0]);
  const w = wasm(repeats, false);
  for (const k of [...WORK, ...E2E]) push('ours_wasm', k, w.all[k]);
  for (const k of WORK) {
    await runOrt(k);
    for (let i = 0; i < repeats; i++) {
      const t = performance.now();
      await runOrt(k);
      push('ort_web', k, [performance.now() - t]);
    }
  }
  const n = native(repeats);
  for (const k of [...WORK, ...E2E]) push('ours_native', k, n.all[k]);
  const p = torch(repeats);
  for (const k of WORK) push('torch', k, p.all[k]);
  if (hasPkg) {
    const q = pkgRun(repeats);
    for (const k of E2E) push('ours_npm', k, q.all[k]);
    for (const k of ['cold_load_ms', 'cold_first_stylization_ms', 'cold_total_ms']) push('ours_npm', k.replace(/_ms$/, ''), [q[k]]);
  }
  console.log(`round ${r + 1}/${rounds} done (load average ${loadavg()[0].toFixed(2)})`);
}
const median = (v) => {
  const s = [...v].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};
const med = Object.fromEntries(Object.entries(times).map(([side, m]) => [side, Object.fromEntries(Object.entries(m).map(([k, v]) => [k, median(v)]))]));

// ---- BVH parsing vs three.js (its own script; same machine, same run) ----
let bvh = null;
try {
  const text = sh(join(root, 'bench/bvh_parse/run.sh'), []);
  process.stdout.write(text.split('\n').map((l) => `  bvh_parse: ${l}`).join('\n') + '\n');
  const grab = (re) => Number((text.match(re) ?? [])[1]);
  bvh = {
    file: (text.match(/^file: (.*)$/m) ?? [])[1],
    ours_wasm_vs_threejs: grab(/ratio ours \(wasm32\) \/ three\.js: ([\d.]+)/),
    ours_native_vs_threejs: grab(/ratio ours \(native\) \/ three\.js: ([\d.]+)/),
  };
} catch (e) {
  console.error(`bvh_parse benchmark failed: ${e.message}`);
}

// ---- sizes ----
const size = (p) => (existsSync(p) ? statSync(p).size : null);
const gz = (p) => (existsSync(p) ? gzipSync(readFileSync(p), { level: 9 }).length : null);
const pkgWasm = join(root, 'pkg/engine_bg.wasm');
function packSize() {
  try {
    const out = execFileSync('npm', ['pack', '--dry-run', '--json'], { cwd: join(root, 'pkg'), encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] });
    const [info] = JSON.parse(out);
    return { tarball_bytes: info.size, unpacked_bytes: info.unpackedSize, files: info.entryCount };
  } catch {
    return null;
  }
}
const npmPack = existsSync(join(root, 'pkg/package.json')) ? packSize() : null;
const weightsFiles = Object.fromEntries(readdirSync(weightsDir).filter((f) => /\.(bin|json)$/.test(f)).map((f) => [f, size(join(weightsDir, f))]));
const sizes = {
  npm_pack: npmPack,
  engine_bg_wasm_bytes: size(pkgWasm),
  engine_bg_wasm_gzip_bytes: gz(pkgWasm),
  weights_bytes: weightsFiles,
  weights_supervised_gzip_bytes: gz(supervised),
  onnx_motion_bytes: size(join(onnxDir, 'motion.onnx')),
  ort_wasm_bytes: size(join(here, 'node_modules/onnxruntime-web/dist/ort-wasm-simd-threaded.wasm')),
  ort_wasm_gzip_bytes: gz(join(here, 'node_modules/onnxruntime-web/dist/ort-wasm-simd-threaded.wasm')),
};

// ---- FLOPs and peak ----
const cpuinfo = existsSync('/proc/cpuinfo') ? readFileSync('/proc/cpuinfo', 'utf8') : '';
const flags = (cpuinfo.match(/^flags\s*:(.*)$/m) ?? ['', ''])[1].split(' ');
const mhz = Number((cpuinfo.match(/^cpu MHz\s*:\s*([\d.]+)/m) ?? [])[1]) || cpus()[0]?.speed;
const family = Number((cpuinfo.match(/^cpu family\s*:\s*(\d+)/m) ?? [])[1]);
const model = Number((cpuinfo.match(/^model\s*:\s*(\d+)/m) ?? [])[1]);
const vendor = (cpuinfo.match(/^vendor_id\s*:\s*(\S+)/m) ?? [])[1];
// FP32 FLOPs per cycle per core: 2 FMA pipes × lanes × 2. AVX-512 at full width on AMD Zen 5
// (family 26) and Intel server cores, 256-bit datapaths on Zen 4 and earlier (AVX-512 split in two).
const avx512Full = flags.includes('avx512f') && (vendor !== 'AuthenticAMD' || family >= 26);
const lanes = avx512Full ? 16 : flags.includes('avx2') || flags.includes('avx') ? 8 : 4;
const nativeFlopsPerCycle = 2 * lanes * 2 * (flags.includes('fma') ? 1 : 0.5);
// wasm SIMD128 (no FMA without relaxed SIMD): per cycle at most 2 four-lane multiplies and 2 adds.
const wasmFlopsPerCycle = 16;
const ghz = mhz / 1000;
const peak = {
  clock_ghz: ghz,
  native_flops_per_cycle_per_core: nativeFlopsPerCycle,
  wasm_flops_per_cycle: wasmFlopsPerCycle,
  native_gflops: ghz * nativeFlopsPerCycle * threads,
  wasm_gflops: ghz * wasmFlopsPerCycle,
  how: `clock (cpu MHz of /proc/cpuinfo, nominal, no boost) × FP32 FLOPs per cycle per core: native ${nativeFlopsPerCycle} = 2 FMA pipes × ${lanes} lanes (${avx512Full ? 'AVX-512, full width' : 'AVX2'}) × 2, × ${threads} thread(s); wasm SIMD128 ${wasmFlopsPerCycle} = 2 four-lane multiplies + 2 four-lane adds (no FMA in wasm SIMD), one thread`,
};
const flops = torchParity.flops;
const fraction = (side, k) => {
  const gflops = flops[k] / (med[side][k] * 1e6);
  const p = side === 'ours_wasm' || side === 'ort_web' ? peak.wasm_gflops : peak.native_gflops;
  return { gflops, fraction_of_peak: gflops / p };
};

// ---- ratios ----
const both = (side) => med[side].net_motion + med[side].net_label10;
const ratio = (a, b, k) => med[a][k] / med[b][k];
const results = {
  wasm_vs_onnxruntime: both('ours_wasm') / both('ort_web'),
  native_vs_pytorch: both('ours_native') / both('torch'),
  samples10_vs_1: med.ours_wasm.e2e_label10 / med.ours_wasm.e2e_label1,
  bvh_parse_vs_threejs: bvh?.ours_wasm_vs_threejs ?? null,
  definitions: {
    wasm_vs_onnxruntime: 'ours in wasm ÷ onnxruntime-web, network only, (motion-based 1 + label-based 10 samples), medians; per work in by_work',
    native_vs_pytorch: `ours native ÷ PyTorch CPU, ${threads} thread(s), network only, (motion-based 1 + label-based 10 samples), medians`,
    samples10_vs_1: 'ours in wasm, BVH text in → BVH text out, label-based: 10 samples ÷ 1 sample',
    bvh_parse_vs_threejs: 'ours compiled to wasm32 in Node ÷ three.js BVHLoader.parse in Node, same text (bench/bvh_parse)',
  },
  by_work: Object.fromEntries(
    WORK.map((k) => [k, { wasm_vs_onnxruntime: ratio('ours_wasm', 'ort_web', k), native_vs_pytorch: ratio('ours_native', 'torch', k) }]),
  ),
  bvh_in_out_160_frames_wasm_ms: {
    npm_package_label1: med.ours_npm.e2e_label1 ?? null,
    npm_package_motion: med.ours_npm.e2e_motion ?? null,
    wasip1_label1: med.ours_wasm.e2e_label1,
    wasip1_motion: med.ours_wasm.e2e_motion,
  },
  npm_cold_start_node_ms: hasPkg
    ? { load: med.ours_npm.cold_load, first_stylization: med.ours_npm.cold_first_stylization, total: med.ours_npm.cold_total }
    : null,
  samples10_vs_1_detail: {
    npm_package_e2e: hasPkg ? med.ours_npm.e2e_label10 / med.ours_npm.e2e_label1 : null,
    wasm_e2e: med.ours_wasm.e2e_label10 / med.ours_wasm.e2e_label1,
    native_e2e: med.ours_native.e2e_label10 / med.ours_native.e2e_label1,
    wasm_network: med.ours_wasm.net_label10 / med.ours_wasm.net_label1,
    native_network: med.ours_native.net_label10 / med.ours_native.net_label1,
    ort_web_network: med.ort_web.net_label10 / med.ort_web.net_label1,
    torch_network: med.torch.net_label10 / med.torch.net_label1,
  },
  median_ms: med,
  flops,
  throughput: Object.fromEntries(
    ['ours_wasm', 'ort_web', 'ours_native', 'torch'].map((side) => [side, Object.fromEntries(WORK.map((k) => [k, fraction(side, k)]))]),
  ),
  peak,
  parity: { tolerance: TOLERANCE, max_abs_diff: parity },
  bvh_parse: bvh,
  sizes,
  settings: { rounds, repeats, threads, frames: T, runs_per_median: rounds * repeats },
  machine: {
    cpu: (cpuinfo.match(/^model name\s*:\s*(.*)$/m) ?? [])[1] ?? cpus()[0]?.model,
    vendor,
    cpu_family: family,
    cpu_model: model,
    cores: cpus().length,
    clock_mhz: mhz,
    memory_gib: +(totalmem() / 2 ** 30).toFixed(1),
    kernel: release(),
    node: process.version,
    torch: torchParity.torch,
    onnxruntime_web: JSON.parse(readFileSync(join(here, 'node_modules/onnxruntime-web/package.json'), 'utf8')).version,
    load_average_during_rounds: loads.map((l) => +l.toFixed(2)),
    load_average_end: loadavg().map((l) => +l.toFixed(2)),
    date: new Date().toISOString(),
  },
  raw_ms: times,
};

// ---- report ----
const f = (x) => (x == null ? '—' : x.toFixed(2)).padStart(9);
console.log(`\n${T} frames, medians of ${rounds * repeats} runs (ms); ours native and PyTorch: ${threads} thread(s); wasm: 1 thread`);
console.log('work                 ours wasm   ort-web   ours nat.   PyTorch   wasm÷ort  nat.÷torch   ours npm pkg');
for (const k of [...WORK, ...E2E]) {
  const r = (a, b) => (med[a][k] != null && med[b][k] != null ? f(med[a][k] / med[b][k]) : f(null));
  console.log(`${k.padEnd(18)} ${f(med.ours_wasm[k])} ${f(med.ort_web[k])} ${f(med.ours_native[k])} ${f(med.torch[k])} ${r('ours_wasm', 'ort_web')} ${r('ours_native', 'torch')}   ${f(med.ours_npm[k])}`);
}
if (hasPkg) {
  console.log(`npm package cold start in Node (fresh process: import + compile + load weights, then the first 160-frame stylization): ${f(med.ours_npm.cold_load).trim()} + ${f(med.ours_npm.cold_first_stylization).trim()} = ${f(med.ours_npm.cold_total).trim()} ms`);
}
console.log(`\nFLOPs: motion-based ${(flops.net_motion / 1e6).toFixed(0)} M, label-based 1 sample ${(flops.net_label1 / 1e6).toFixed(0)} M, 10 samples ${(flops.net_label10 / 1e6).toFixed(0)} M`);
console.log(`peak: native ${peak.native_gflops.toFixed(0)} GFLOP/s, wasm ${peak.wasm_gflops.toFixed(0)} GFLOP/s (${peak.how})`);
for (const side of ['ours_wasm', 'ort_web', 'ours_native', 'torch']) {
  const t = results.throughput[side];
  console.log(`  ${side.padEnd(12)} ${WORK.map((k) => `${k} ${t[k].gflops.toFixed(1)} GFLOP/s (${(100 * t[k].fraction_of_peak).toFixed(1)} %)`).join(', ')}`);
}
console.log('\nratios (ours ÷ theirs, lower is better):');
for (const k of ['wasm_vs_onnxruntime', 'native_vs_pytorch', 'samples10_vs_1', 'bvh_parse_vs_threejs']) {
  console.log(`  ${k.padEnd(22)} ${results[k] == null ? '—' : results[k].toFixed(3)}   (${results.definitions[k]})`);
}
console.log(`sizes: ${JSON.stringify(sizes)}`);
console.log(`machine: ${results.machine.cpu}, ${results.machine.cores} cores, load average during rounds ${results.machine.load_average_during_rounds.join(' ')}`);
mkdirSync(dirname(outFile), { recursive: true });
// The training benchmark's keys (bench/perf/train_run.mjs, `make bench-train`) are kept as they are.
const previous = existsSync(outFile) ? JSON.parse(readFileSync(outFile, 'utf8')) : {};
for (const k of ['train_step_vs_pytorch', 'train_step']) if (k in previous) results[k] = previous[k];
// Every machine kind's latest ratios stay (vendor-family-model, as the training benchmark keys them);
// the unkeyed fields above are this run's. A file from before the keys: its run is kept under what
// its machine record says.
const machineKey = (m) => `${m.vendor ?? 'unknown'}-family${m.cpu_family}-model${m.cpu_model ?? 'unknown'}`;
const summary = (r) => ({
  wasm_vs_onnxruntime: r.wasm_vs_onnxruntime,
  native_vs_pytorch: r.native_vs_pytorch,
  samples10_vs_1: r.samples10_vs_1,
  by_work: r.by_work,
  throughput: r.throughput,
  peak: r.peak,
  median_ms: r.median_ms,
  settings: r.settings,
  machine: r.machine,
});
const byMachine = previous.by_machine ?? {};
if (!previous.by_machine && previous.machine?.cpu_family) byMachine[machineKey(previous.machine)] = summary(previous);
byMachine[machineKey(results.machine)] = summary(results);
results.by_machine = byMachine;
results.definitions.by_machine = 'per machine kind (vendor-family-model): the latest run\'s ratios, throughput, medians and machine';
writeFileSync(outFile, JSON.stringify(results, null, 2) + '\n');
console.log(`wrote ${outFile}`);
rmSync(work, { recursive: true, force: true });
