#!/usr/bin/env node
// A small static file server for the browser demo (out/www/ by default), with the MIME types
// browsers need for ES modules and WebAssembly (application/wasm enables streaming compilation),
// and what a static host does: gzip (level 6, for clients that accept it; images as they are) and
// ETag revalidation (`cache-control: no-cache`: a second visit gets 304s, not the files again).
//
//   node scripts/serve-www.mjs [DIR] [--port 8080] [--host 127.0.0.1]
// Tries the next ports when the one asked for is taken; prints the address to open. Also imported
// by the end-to-end tests (startServer).

import { createReadStream, readFileSync, statSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { createServer } from 'node:http';
import { extname, join, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.json': 'application/json',
  '.wasm': 'application/wasm',
  '.bvh': 'text/plain; charset=utf-8',
  '.md': 'text/plain; charset=utf-8',
  '.png': 'image/png',
  '.svg': 'image/svg+xml',
  '.ts': 'text/plain; charset=utf-8',
};

/** Already compressed (gzip would only add bytes). */
const STORED = new Set(['.png', '.jpg', '.jpeg', '.gz', '.br', '.zip']);

/** Serves `dir` on host:port (0: any free port); resolves to { url, close }. `gzip: false` sends files as they are. */
export function startServer(dir, { port = 0, host = '127.0.0.1', tries = 20, gzip = true } = {}) {
  const root = resolve(dir);
  const compressed = new Map(); // file -> { tag, bytes }
  const server = createServer((req, res) => {
    let path;
    try {
      path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    } catch {
      res.writeHead(400).end();
      return;
    }
    if (path.endsWith('/')) path += 'index.html';
    const file = resolve(join(root, path));
    let stat;
    try {
      if (file !== root && !file.startsWith(root + sep)) throw new Error('outside');
      stat = statSync(file);
      if (!stat.isFile()) throw new Error('not a file');
    } catch {
      res.writeHead(404, { 'content-type': 'text/plain' }).end('not found');
      return;
    }
    const etag = `"${stat.size.toString(16)}-${Math.floor(stat.mtimeMs).toString(16)}"`;
    const headers = {
      'content-type': TYPES[extname(file)] ?? 'application/octet-stream',
      'cache-control': 'no-cache',
      etag,
      vary: 'accept-encoding',
      'x-content-type-options': 'nosniff',
    };
    if (req.headers['if-none-match'] === etag) {
      res.writeHead(304, headers).end();
      return;
    }
    const zipped = gzip && !STORED.has(extname(file)) && /\bgzip\b/.test(req.headers['accept-encoding'] ?? '');
    if (!zipped) {
      res.writeHead(200, { ...headers, 'content-length': stat.size });
      if (req.method === 'HEAD') res.end();
      else createReadStream(file).pipe(res);
      return;
    }
    let entry = compressed.get(file);
    if (entry?.tag !== etag) {
      entry = { tag: etag, bytes: gzipSync(readFileSync(file), { level: 6 }) };
      compressed.set(file, entry);
    }
    res.writeHead(200, { ...headers, 'content-encoding': 'gzip', 'content-length': entry.bytes.length });
    res.end(req.method === 'HEAD' ? undefined : entry.bytes);
  });
  return new Promise((ok, fail) => {
    let attempt = 0;
    server.on('error', (e) => {
      if (e.code === 'EADDRINUSE' && port !== 0 && ++attempt < tries) server.listen(port + attempt, host);
      else fail(e);
    });
    server.on('listening', () => {
      const { port: p } = server.address();
      ok({ url: `http://${host === '0.0.0.0' ? 'localhost' : host}:${p}/`, close: () => server.close() });
    });
    server.listen(port, host);
  });
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  const option = (name, fallback) => {
    const i = args.indexOf(name);
    if (i < 0) return fallback;
    const value = args[i + 1];
    args.splice(i, 2);
    return value;
  };
  const port = Number(option('--port', process.env.PORT ?? 8080));
  const host = option('--host', '127.0.0.1');
  const dir = args[0] ?? 'out/www';
  const { url } = await startServer(dir, { port, host });
  console.log(`\n  Browser demo: open ${url}  (serving ${dir}/; Ctrl-C to stop)\n`);
}
