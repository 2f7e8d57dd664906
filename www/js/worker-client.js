// The page's side of the worker (worker.js): requests as promises, progress as callbacks.

/** A worker's failure, for every request waiting on it. */
const failure = (e) => Object.assign(new Error(`the worker failed: ${e?.message ?? 'unknown error'}`), { code: 'INTERNAL' });

export class WorkerClient {
  /**
   * `start`: a worker the page's head already started ({worker, said, t0}: index.html asks it to load
   * the engine as request 0 before the page's modules arrive, and keeps what it has said so far). Its
   * answer is `first` (a promise, as call() gives), its progress, what was said before included, goes
   * to `onFirstProgress`; without one, a new worker and `first` null.
   */
  constructor(start = null, onFirstProgress = null) {
    this.worker = start?.worker ?? new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
    this.pending = new Map();
    this.nextId = 1;
    this.worker.onmessage = ({ data }) => this.receive(data);
    this.worker.onerror = (e) => {
      e.preventDefault?.();
      for (const p of this.pending.values()) p.reject(failure(e));
      this.pending.clear();
    };
    this.first = null;
    this.firstStarted = start?.t0 ?? null;
    if (start) {
      this.first = new Promise((resolve, reject) => this.pending.set(0, { resolve, reject, onProgress: onFirstProgress }));
      for (const data of start.said.splice(0)) this.receive(data);
    }
  }

  receive(data) {
    const p = this.pending.get(data.id);
    if (!p) return;
    if (data.progress) {
      p.onProgress?.(data.progress);
      return;
    }
    this.pending.delete(data.id);
    if (data.error) p.reject(Object.assign(new Error(data.error.message), data.error));
    else p.resolve(data.result);
  }

  /** Runs `op` in the worker; resolves to its result, rejects with an Error that has a `code`. */
  call(op, args, onProgress) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject, onProgress });
      this.worker.postMessage({ id, op, args });
    });
  }
}
