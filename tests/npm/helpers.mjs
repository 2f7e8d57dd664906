// Shared paths and helpers of the npm package tests.
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
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
