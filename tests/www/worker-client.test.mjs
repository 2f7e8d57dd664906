// The page's side of the worker (www/js/worker-client.js) taking over the worker that index.html's
// head started: what the worker said before the page's modules arrived is replayed (progress, then
// the answer to request 0), later messages arrive as usual, and new requests do not collide with 0.
// A stand-in for the Worker: no browser needed.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { WorkerClient } from '../../www/js/worker-client.js';

class FakeWorker {
  constructor() {
    this.posted = [];
  }
  postMessage(message) {
    this.posted.push(message);
  }
  /** What the worker would say next. */
  say(data) {
    this.onmessage({ data });
  }
}

test('the answer to the head\'s load, said before the page took over, is replayed with its progress', { timeout: 5000 }, async () => {
  const worker = new FakeWorker();
  const said = [
    { id: 0, progress: { stage: 'weights', loaded: 10, total: 20 } },
    { id: 0, progress: { stage: 'weights', loaded: 20, total: 20 } },
    { id: 0, result: { styles: ['normal', 'old'] } },
  ];
  const seen = [];
  const client = new WorkerClient({ worker, said, t0: 12.5 }, (p) => seen.push(p.loaded));
  assert.deepEqual(await client.first, { styles: ['normal', 'old'] });
  assert.deepEqual(seen, [10, 20]);
  assert.equal(client.firstStarted, 12.5);
  assert.equal(said.length, 0, 'the head\'s buffer is emptied');
});

test('an answer that comes after the take-over resolves the same promise; new requests start at 1', { timeout: 5000 }, async () => {
  const worker = new FakeWorker();
  const seen = [];
  const client = new WorkerClient({ worker, said: [{ id: 0, progress: { stage: 'compile' } }], t0: 0 }, (p) => seen.push(p.stage));
  const call = client.call('import', { slot: 'content' });
  assert.deepEqual(worker.posted, [{ id: 1, op: 'import', args: { slot: 'content' } }]);
  worker.say({ id: 1, result: 'imported' });
  worker.say({ id: 0, progress: { stage: 'weights', loaded: 1, total: 1 } });
  worker.say({ id: 0, result: 'loaded' });
  assert.equal(await call, 'imported');
  assert.equal(await client.first, 'loaded');
  assert.deepEqual(seen, ['compile', 'weights']);
});

test('a failure of the head\'s load rejects with its code; a worker error rejects what waits', { timeout: 5000 }, async () => {
  const worker = new FakeWorker();
  const client = new WorkerClient({ worker, said: [{ id: 0, error: { code: 'FETCH', message: 'cannot fetch weights' } }], t0: 0 });
  await assert.rejects(client.first, { code: 'FETCH', message: 'cannot fetch weights' });
  const waiting = client.call('stylize', {});
  worker.onerror({ message: 'boom', preventDefault() {} });
  await assert.rejects(waiting, { code: 'INTERNAL', message: 'the worker failed: boom' });
});

test('without a started worker there is no first answer', () => {
  globalThis.Worker = class extends FakeWorker {};
  try {
    const client = new WorkerClient();
    assert.equal(client.first, null);
    assert.ok(client.worker instanceof FakeWorker);
  } finally {
    delete globalThis.Worker;
  }
});
