// The page's side of the worker (worker.js): requests as promises, progress as callbacks.

export class WorkerClient {
  constructor() {
    this.worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
    this.pending = new Map();
    this.nextId = 1;
    this.worker.onmessage = ({ data }) => {
      const p = this.pending.get(data.id);
      if (!p) return;
      if (data.progress) {
        p.onProgress?.(data.progress);
        return;
      }
      this.pending.delete(data.id);
      if (data.error) p.reject(Object.assign(new Error(data.error.message), data.error));
      else p.resolve(data.result);
    };
    this.worker.onerror = (e) => {
      e.preventDefault?.();
      const error = Object.assign(new Error(`the worker failed: ${e.message ?? 'unknown error'}`), { code: 'INTERNAL' });
      for (const p of this.pending.values()) p.reject(error);
      this.pending.clear();
    };
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
