// The page's side of a Web Worker running the physics (sim_worker.js): calls answered by id,
// the live session's frames handed to onState. Terminating it rejects what is pending.
export class WorkerClient {
  constructor(onState) {
    this.worker = new Worker(new URL("./sim_worker.js", import.meta.url), { type: "module" });
    this.pending = new Map();
    this.next = 1;
    this.worker.onmessage = (e) => {
      if (e.data.type === "reply") {
        const { resolve } = this.pending.get(e.data.id);
        this.pending.delete(e.data.id);
        resolve(e.data.result);
      } else if (onState) {
        onState(e.data);
      }
    };
    this.worker.onerror = (e) => {
      e.preventDefault();
      for (const { reject } of this.pending.values()) reject(new Error(`the physics worker failed: ${e.message}`));
      this.pending.clear();
    };
  }
  call(method, args) {
    return new Promise((resolve, reject) => {
      const id = this.next++;
      this.pending.set(id, { resolve, reject });
      this.worker.postMessage({ id, method, args });
    });
  }
  terminate(reason) {
    this.worker.terminate();
    for (const { reject } of this.pending.values()) reject(new Error(reason));
    this.pending.clear();
  }
}

