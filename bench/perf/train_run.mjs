// `make bench-train`: one training step of ours against the same step in PyTorch CPU, side by side in
// one run on one machine, at the shipped width (0.5) and the paper's (1.0):
//   - ours: examples/train_perf_bench.rs (Burn, flex backend, RAYON_NUM_THREADS=THREADS);
//   - PyTorch: bench/perf/torch_train.py (the PyPI wheel, torch.set_num_threads(THREADS)), the same
//     networks, losses, Adam and gradient clipping rebuilt from the weights, batch and noise ours writes.
// The steps: stage 1, the autoencoder + global regressor (`AeTrainer::step`), and stage 2, the
// supervised stylizer on the frozen autoencoder (`StylizerTrainer::step`), batch 16 × 160 frames.
//
// Parity first: from the same initial weights, batch and noise, every loss term of the first 3 steps
// of both stages must agree within 1e-4 (relative; the gradient norms within 1e-3), or the run stops.
// Then ROUNDS rounds; in each, per width, each side runs one warm-up step of each stage and REPEATS
// timed ones (which side goes first alternates round by round). Medians over all timed steps are
// compared. Prints a table, and merges into bench/results.json (the other keys kept):
//   train_step_vs_pytorch  ours ÷ PyTorch, seconds per step, per width and stage, with the CPU and threads;
//   train_step             the details: times, phases, parity, machine, per thread count run.
//
//   node bench/perf/train_run.mjs [--rounds R] [--repeats N] [--threads T] [--widths 0.5,1] [--f64]
//                                 [--quiet-wait S] [--max-busy F] [--out FILE]
// --f64: the parity check also runs PyTorch in float64 and says how far each float32 side is from it.
// --quiet-wait S (60), --max-busy F (0.1): before each timed run, wait up to S seconds until under F
// of the machine's CPU time is busy (0: don't wait).
// Needs target/release/examples/train_perf_bench and bench/perf/.venv; `make bench-train` builds them.

import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { cpus, loadavg, release, tmpdir, totalmem } from 'node:os';
import { dirname, join, resolve } from 'node:path';

const here = dirname(new URL(import.meta.url).pathname);
const root = resolve(here, '../..');
const opt = (name, dflt) => {
  const i = process.argv.indexOf(`--${name}`);
  return i >= 0 ? process.argv[i + 1] : dflt;
};
const rounds = Number(opt('rounds', 3));
const repeats = Number(opt('repeats', 3));
const threads = Number(opt('threads', 2));
const widths = opt('widths', '0.5,1').split(',').map(Number);
const f64 = process.argv.includes('--f64');
// Before each timed run, wait up to QUIET_WAIT seconds for the machine to be idle (under MAX_BUSY of
// its CPU time busy over one second): a shared machine slows OpenMP's threads (PyTorch) far more than
// rayon's, so a busy machine would flatter us. What was found is recorded either way.
const quietWait = Number(opt('quiet-wait', 60));
const maxBusy = Number(opt('max-busy', 0.1));
const outFile = resolve(opt('out', join(root, 'bench/results.json')));
const targetDir = resolve(root, process.env.CARGO_TARGET_DIR ?? 'target');
const bin = join(targetDir, 'release/examples/train_perf_bench');
const python = join(here, '.venv/bin/python');
const script = join(here, 'torch_train.py');
const STAGES = ['stylizer', 'ae'];

for (const p of [bin, python]) {
  if (!existsSync(p)) throw new Error(`${p} is missing: run \`make bench-train\` (it builds and installs everything)`);
}

const threadEnv = { RAYON_NUM_THREADS: String(threads), OMP_NUM_THREADS: String(threads), MKL_NUM_THREADS: String(threads) };
const sh = (cmd, args) =>
  execFileSync(cmd, args, { encoding: 'utf8', env: { ...process.env, ...threadEnv }, maxBuffer: 1 << 28, stdio: ['ignore', 'pipe', 'pipe'] });
const lastJson = (text) => JSON.parse(text.trim().split('\n').at(-1));
const key = (w) => w.toFixed(1);
const work = mkdtempSync(join(tmpdir(), 'ms-train-'));
const dir = (w) => join(work, `width-${key(w)}`);

// ---- parity ----
const parity = {};
for (const w of widths) {
  console.log(`parity, width ${key(w)}: ours writes weights, batch and noise, and runs 3 steps of each stage; PyTorch does the same`);
  sh(bin, ['dump', dir(w), '--width', String(w), '--steps', '3']);
  let p;
  try {
    p = lastJson(sh(python, [script, 'parity', dir(w), ...(f64 ? ['--f64'] : [])]));
  } catch (e) {
    console.error(e.stdout ?? '', e.stderr ?? '');
    throw new Error(`PyTorch training parity check failed at width ${key(w)} (see above)`);
  }
  parity[key(w)] = p;
  const byStep = Object.entries(p.max_rel_diff_losses_by_step).map(([s, v]) => `${s} ${v.map((x) => x.toExponential(1)).join(' / ')}`);
  console.log(`  max relative difference: loss terms ${p.max_rel_diff_losses.toExponential(2)} (by step: ${byStep.join('; ')}), gradient norms ${p.max_rel_diff_grad_norms.toExponential(2)}`);
  if (f64) {
    console.log(`  against float64: ours ${p.ours_vs_float64.losses.toExponential(2)} (norms ${p.ours_vs_float64.grad_norms.toExponential(2)}), PyTorch ${p.torch_vs_float64.losses.toExponential(2)} (norms ${p.torch_vs_float64.grad_norms.toExponential(2)})`);
  }
}
const meta = Object.fromEntries(widths.map((w) => [key(w), JSON.parse(readFileSync(join(dir(w), 'meta.json'), 'utf8'))]));

// ---- how busy the machine is (/proc/stat, all CPUs) ----
const cpuTimes = () => {
  if (!existsSync('/proc/stat')) return null;
  const v = readFileSync('/proc/stat', 'utf8').split('\n')[0].trim().split(/\s+/).slice(1, 9).map(Number);
  const idle = v[3] + v[4];
  return { busy: v.reduce((a, b) => a + b, 0) - idle, total: v.reduce((a, b) => a + b, 0) };
};
const sleep = (ms) => Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, ms);
const busyFraction = (ms) => {
  const a = cpuTimes();
  sleep(ms);
  const b = cpuTimes();
  return a && b && b.total > a.total ? (b.busy - a.busy) / (b.total - a.total) : null;
};
const quiet = [];
const waitQuiet = (what) => {
  const start = Date.now();
  let busy = busyFraction(1000);
  while (busy != null && busy > maxBusy && Date.now() - start < quietWait * 1000) busy = busyFraction(1000);
  const waited = (Date.now() - start) / 1000 - 1;
  if (busy != null && busy > maxBusy) console.log(`  ${what}: machine still ${(100 * busy).toFixed(0)} % busy after ${waited.toFixed(0)} s, measuring anyway`);
  quiet.push({ what, busy_before: busy == null ? null : +busy.toFixed(3), waited_s: +waited.toFixed(1) });
};

// ---- timing, interleaved ----
const times = { ours: {}, torch: {}, ours_cpu: {}, torch_cpu: {} };
const phases = { ours: {}, torch: {} };
const push = (side, w, stage, v) => ((times[side][key(w)] ??= {})[stage] ??= []).push(...v);
const loads = [];
let torchInfo = {};
const ours = (w) => {
  waitQuiet(`ours ${key(w)}`);
  const r = lastJson(sh(bin, ['time', '--width', String(w), '--repeats', String(repeats)]));
  push('ours', w, 'ae', r.ae_s);
  push('ours', w, 'stylizer', r.stylizer_s);
  push('ours_cpu', w, 'ae', r.ae_cpu_s);
  push('ours_cpu', w, 'stylizer', r.stylizer_cpu_s);
  (phases.ours[key(w)] ??= []).push({ ae: r.ae_phases_s, stylizer: r.stylizer_phases_s });
};
const torch = (w) => {
  waitQuiet(`torch ${key(w)}`);
  const r = lastJson(sh(python, [script, 'time', dir(w), String(repeats), String(threads)]));
  push('torch', w, 'ae', r.ae_s);
  push('torch', w, 'stylizer', r.stylizer_s);
  push('torch_cpu', w, 'ae', r.ae_cpu_s);
  push('torch_cpu', w, 'stylizer', r.stylizer_cpu_s);
  (phases.torch[key(w)] ??= []).push({ ae: r.ae_phases_s, stylizer: r.stylizer_phases_s });
  torchInfo = { version: r.torch_version, cpu_capability: r.torch_cpu_capability, threads: r.threads };
};
for (let r = 0; r < rounds; r++) {
  loads.push(loadavg()[0]);
  for (const w of widths) {
    const order = r % 2 === 0 ? [ours, torch] : [torch, ours];
    for (const side of order) side(w);
  }
  console.log(`round ${r + 1}/${rounds} done (load average ${loadavg()[0].toFixed(2)})`);
}
const median = (v) => {
  const s = [...v].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};
const medPhases = (side, w, stage) => {
  const all = phases[side][key(w)].map((p) => p[stage]);
  return Object.fromEntries(Object.keys(all[0]).map((k) => [k, median(all.map((p) => p[k]))]));
};

// ---- machine ----
const cpuinfo = existsSync('/proc/cpuinfo') ? readFileSync('/proc/cpuinfo', 'utf8') : '';
const field = (name) => (cpuinfo.match(new RegExp(`^${name}\\s*:\\s*(.*)$`, 'm')) ?? [])[1];
const flags = (field('flags') ?? '').split(' ');
const isa = ['avx2', 'fma', 'avx512f', 'avx512_bf16', 'amx_tile'].filter((f) => flags.includes(f));
const cpu = field('model name') ?? cpus()[0]?.model;
const machine = {
  cpu,
  vendor: field('vendor_id'),
  cpu_family: Number(field('cpu family')),
  cpu_model: Number(field('model')),
  isa,
  // gemm (Burn flex's matrix products) picks its kernels at run time from the CPU's features
  // (x86-v4 = AVX-512 where avx512f is present, else AVX2 + FMA); PyTorch reports its own.
  gemm_kernels_expected: flags.includes('avx512f') ? 'avx512' : flags.includes('avx2') && flags.includes('fma') ? 'avx2+fma' : 'scalar/sse',
  torch_cpu_capability: torchInfo.cpu_capability,
  cores: cpus().length,
  clock_mhz: Number(field('cpu MHz')) || cpus()[0]?.speed,
  memory_gib: +(totalmem() / 2 ** 30).toFixed(1),
  kernel: release(),
  torch: torchInfo.version,
  load_average_during_rounds: loads.map((l) => +l.toFixed(2)),
  // Per timed run, the fraction of all CPU time busy over the second before it, and the wait for that.
  busy_before_runs: quiet,
  load_average_end: loadavg().map((l) => +l.toFixed(2)),
  date: new Date().toISOString(),
};

// ---- FLOPs and peak (as bench/perf/run.mjs: nominal clock × FP32 FLOPs per cycle per core × threads) ----
const avx512Full = flags.includes('avx512f') && (machine.vendor !== 'AuthenticAMD' || machine.cpu_family >= 26);
const lanes = avx512Full ? 16 : flags.includes('avx2') || flags.includes('avx') ? 8 : 4;
const flopsPerCycle = 2 * lanes * 2 * (flags.includes('fma') ? 1 : 0.5);
const peak = {
  gflops: (machine.clock_mhz / 1000) * flopsPerCycle * threads,
  flops_per_cycle_per_core: flopsPerCycle,
  how: `clock (cpu MHz of /proc/cpuinfo, nominal) × ${flopsPerCycle} FP32 FLOPs per cycle per core (2 FMA pipes × ${lanes} lanes × 2) × ${threads} thread(s)`,
};
const throughput = (flops, s) => ({ gflops: flops / s / 1e9, fraction_of_peak: flops / s / 1e9 / peak.gflops });

// ---- ratios ----
const byWidth = Object.fromEntries(
  widths.map((w) => {
    const k = key(w);
    const stages = Object.fromEntries(
      STAGES.map((stage) => {
        const o = median(times.ours[k][stage]);
        const t = median(times.torch[k][stage]);
        const ours = times.ours[k][stage];
        const theirs = times.torch[k][stage];
        return [
          stage,
          {
            ours_s: o,
            torch_s: t,
            ratio: o / t,
            // Fastest steps too: on a shared machine the least disturbed ones.
            ours_min_s: Math.min(...ours),
            torch_min_s: Math.min(...theirs),
            ratio_of_min: Math.min(...ours) / Math.min(...theirs),
            // CPU seconds (user + system, all threads) per step, medians: on a shared machine
            // they move less than wall time; at one thread the closest to a quiet machine's ratio.
            ours_cpu_s: median(times.ours_cpu[k][stage]),
            torch_cpu_s: median(times.torch_cpu[k][stage]),
            cpu_ratio: median(times.ours_cpu[k][stage]) / median(times.torch_cpu[k][stage]),
            // Per phase (each run's mean over its steps; median over the runs): forward (latents
            // and losses included), backward, clip (norms and clipping), update (losses read, Adam).
            ours_phases_s: medPhases('ours', w, stage),
            torch_phases_s: medPhases('torch', w, stage),
            // FLOPs of the step's convolutions and linear layers, forward and backward (torch_train.py).
            flops: parity[k].flops[stage],
            ours_throughput: throughput(parity[k].flops[stage], o),
            torch_throughput: throughput(parity[k].flops[stage], t),
          },
        ];
      }),
    );
    return [k, { ...stages, params: meta[k].params }];
  }),
);
const headline = {
  ...Object.fromEntries(widths.map((w) => [`width_${key(w)}`, Object.fromEntries(STAGES.map((s) => [s === 'ae' ? 'autoencoder' : s, byWidth[key(w)][s].ratio]))])),
  threads,
  // The same ratios on CPU seconds per step (user + system, all threads; see cpu_ratio above).
  by_cpu_time: Object.fromEntries(widths.map((w) => [`width_${key(w)}`, Object.fromEntries(STAGES.map((s) => [s === 'ae' ? 'autoencoder' : s, byWidth[key(w)][s].cpu_ratio]))])),
  cpu: `${cpu} (${machine.vendor} family ${machine.cpu_family} model ${machine.cpu_model}; ${isa.join(' ')})`,
  definition: `ours native (Burn flex) ÷ PyTorch CPU, seconds per training step, medians of ${rounds * repeats} steps, batch 16 × 160 frames, ${threads} thread(s) each; stylizer = the supervised stage-2 step on the frozen autoencoder (StylizerTrainer::step), autoencoder = the stage-1 autoencoder + global regressor step (AeTrainer::step); widths: 0.5 shipped, 1.0 the paper's (bench/perf/train_run.mjs)`,
};
const run = {
  widths: byWidth,
  parity: Object.fromEntries(
    Object.entries(parity).map(([k, p]) => [
      k,
      {
        max_rel_diff_losses: p.max_rel_diff_losses,
        max_rel_diff_grad_norms: p.max_rel_diff_grad_norms,
        max_rel_diff_losses_by_step: p.max_rel_diff_losses_by_step,
        tolerance_losses: p.tolerance_losses,
        tolerance_grad_norms: p.tolerance_grad_norms,
        ...(p.ours_vs_float64 ? { ours_vs_float64: p.ours_vs_float64, torch_vs_float64: p.torch_vs_float64 } : {}),
        first_step: { ours: { ae: p.ours.ae[0], stylizer: p.ours.stylizer[0] }, torch: { ae: p.torch.ae[0], stylizer: p.torch.stylizer[0] } },
      },
    ]),
  ),
  peak,
  settings: { rounds, repeats, threads, batch: 16, frames: 160, steps_per_median: rounds * repeats, dropout: 0, quiet_wait_s: quietWait, max_busy: maxBusy },
  machine,
  raw_s: times,
};

// ---- report ----
const f = (x, d = 3) => x.toFixed(d).padStart(9);
console.log(`\nseconds per training step, batch 16 × 160 frames, medians of ${rounds * repeats} steps, ${threads} thread(s) each`);
console.log('width  step          ours   PyTorch  ours÷torch  (fastest: ours, PyTorch, ratio)   forward / backward / clip / update: ours | PyTorch');
for (const w of widths) {
  for (const stage of STAGES) {
    const s = byWidth[key(w)][stage];
    const ph = (p) => [p.forward, p.backward, p.clip, p.update].map((x) => x.toFixed(3)).join(' / ');
    const fastest = `(${s.ours_min_s.toFixed(3)}, ${s.torch_min_s.toFixed(3)}, ${s.ratio_of_min.toFixed(2)})`;
    console.log(`${key(w).padEnd(6)} ${stage.padEnd(9)} ${f(s.ours_s)} ${f(s.torch_s)} ${f(s.ratio, 2)}   ${fastest.padEnd(28)} ${ph(s.ours_phases_s)} | ${ph(s.torch_phases_s)}`);
    console.log(`${''.padEnd(6)} ${'  cpu s'.padEnd(9)} ${f(s.ours_cpu_s)} ${f(s.torch_cpu_s)} ${f(s.cpu_ratio, 2)}   (CPU seconds per step, all threads)`);
  }
}
console.log(`GFLOP/s (share of the ${peak.gflops.toFixed(0)} GFLOP/s peak: ${peak.how}):`);
for (const w of widths) {
  for (const stage of STAGES) {
    const s = byWidth[key(w)][stage];
    const tp = (x) => `${x.gflops.toFixed(1)} (${(100 * x.fraction_of_peak).toFixed(0)} %)`;
    console.log(`  ${key(w)} ${stage.padEnd(9)} ${(s.flops / 1e9).toFixed(1)} GFLOP per step; ours ${tp(s.ours_throughput)}, PyTorch ${tp(s.torch_throughput)}`);
  }
}
const busiest = Math.max(...quiet.map((q) => q.busy_before ?? 0));
console.log(`machine: ${headline.cpu}, ${machine.cores} cores, PyTorch ${machine.torch} (${machine.torch_cpu_capability}), load average during rounds ${machine.load_average_during_rounds.join(' ')}, CPU busy before the timed runs at most ${(100 * busiest).toFixed(0)} %`);

const results = existsSync(outFile) ? JSON.parse(readFileSync(outFile, 'utf8')) : {};
// Every machine kind keeps its own results (the CPU changes between sessions): keyed by vendor,
// family and model; the unkeyed fields hold the latest run's.
const machineKey = (m) => `${m.vendor}-family${m.cpu_family}-model${m.cpu_model}`;
const train = results.train_step ?? {};
const byMachine = train.by_machine ?? {};
for (const [t, r] of Object.entries(train.by_threads ?? {})) {
  // Runs recorded before results were kept per machine.
  if (r.machine?.vendor) (byMachine[machineKey(r.machine)] ??= { by_threads: {} }).by_threads[t] ??= r;
}
const thisMachine = machineKey(machine);
(byMachine[thisMachine] ??= { by_threads: {} }).by_threads[String(threads)] = run;
byMachine[thisMachine].vs_pytorch = { ...(byMachine[thisMachine].vs_pytorch ?? {}), [String(threads)]: headline };
// The headline is the 2-thread run (`make bench-train`'s default) when this machine has one: a
// later 1-thread run (`BENCH_TRAIN_THREADS=1`) is kept beside it, not in its place.
results.train_step_vs_pytorch = byMachine[thisMachine].vs_pytorch['2'] ?? headline;
results.train_step = {
  definition: 'per machine kind (vendor-family-model) and thread count: ours and PyTorch seconds per step (medians), ours per phase, parity of the first 3 steps, the machine; by_threads: the latest machine\'s; written by bench/perf/train_run.mjs (make bench-train)',
  by_threads: byMachine[thisMachine].by_threads,
  by_machine: byMachine,
};
writeFileSync(outFile, JSON.stringify(results, null, 2) + '\n');
console.log(`wrote train_step_vs_pytorch and train_step.by_threads["${threads}"] into ${outFile}`);
rmSync(work, { recursive: true, force: true });
