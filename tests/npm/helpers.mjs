// Shared paths and helpers of the npm package tests.
import { execFileSync } from 'node:child_process';
import { createServer } from 'node:http';
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { extname, join, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

export const root = fileURLToPath(new URL('../../', import.meta.url));
export const pkgDir = join(root, 'pkg');
export const fixture = (rel) => join(root, 'tests/fixtures', rel);
export const read = (path) => readFileSync(path, 'utf8');
export const tempDir = (prefix) => mkdtempSync(join(tmpdir(), prefix));

/** The package as built in pkg/ (`make pkg`). */
export const loadPackage = () => import(pathToFileURL(join(pkgDir, 'index.js')));

/** Cargo's release output folder (CARGO_TARGET_DIR or target/). */
export const releaseDir = join(resolve(root, process.env.CARGO_TARGET_DIR ?? 'target'), 'release');

/** The native CLI (MOTION_STYLIZER_BIN, default the release build of `cargo build --release`). */
export function cli(args) {
  const bin = process.env.MOTION_STYLIZER_BIN ?? join(releaseDir, 'motion-stylizer');
  return execFileSync(bin, args, { cwd: root, encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
}

const TYPES = { '.js': 'text/javascript', '.wasm': 'application/wasm', '.json': 'application/json' };

/** Serves `dir` over HTTP on 127.0.0.1 (with the MIME types browsers need); { base, close }. */
export async function serve(dir) {
  const server = createServer((req, res) => {
    const path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    try {
      const body = readFileSync(join(dir, path));
      res.setHeader('content-type', TYPES[extname(path)] ?? 'application/octet-stream');
      res.end(body);
    } catch {
      res.statusCode = 404;
      res.end();
    }
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  return { base: `http://127.0.0.1:${server.address().port}`, close: () => server.close() };
}
