// The physics, off the page's thread: the WebAssembly module (kane_sim.js) in a module Web
// Worker. Two kinds of work: a live session (advanced on this worker's own clock, its rows and
// drawing posted to the page every frame) and one-off runs (kaneSim.run). The page stops a long
// run by terminating the worker that runs it, so this file never has to poll for a stop.
import createKaneSim from "./kane_sim.js";

const modulePromise = createKaneSim();
let session = null;
let live = { running: false, speed: 1, command: 0, sampleEvery: 1, timer: null, last: 0 };

function post(type, body) {
  self.postMessage({ type, ...body });
}

function frame() {
  const now = performance.now();
  const wall = Math.min((now - live.last) / 1000, 0.1);  // a stalled tab does not jump ahead
  live.last = now;
  let rows = new Float64Array(0);
  let error = "";
  if (live.running && wall > 0) {
    const out = session.advance(Math.min(wall * live.speed, 60), live.command, live.sampleEvery);
    if (out.error) {
      error = out.error;
      live.running = false;
    } else {
      rows = out.values;
    }
  }
  sendState(rows, error);
}

function sendState(rows, error) {
  post("state", {
    rows,
    row: session.row(),
    drawing: session.drawing(),
    time: session.time(),
    events: session.events(),
    running: live.running,
    error: error || "",
  });
}

const handlers = {
  async open({ yaml, name }) {
    const kane = await modulePromise;
    const next = new kane.Session();
    const error = next.open(yaml, name);
    if (error) {
      next.delete();
      return { error };
    }
    if (session) session.delete();
    session = next;
    const rate = session.physicsRate();
    live.sampleEvery = Math.max(1, Math.round(rate / 100));  // plot rows at ~100 Hz
    if (!live.timer) {
      live.last = performance.now();
      live.timer = setInterval(frame, 16);
    }
    sendState(new Float64Array(0), "");
    return { error: "", schema: JSON.parse(session.schema()), yaml: session.configYaml(),
             physicsRate: rate };
  },
  control({ running, speed, command }) {
    if (running !== undefined) live.running = running;
    if (speed !== undefined) live.speed = speed;
    if (command !== undefined) live.command = command;
    live.last = performance.now();
    return { error: "" };
  },
  step() {
    // One physics step at the command in force (paused or not).
    const out = session.advance(1 / session.physicsRate(), live.command, 1);
    sendState(out.error ? new Float64Array(0) : out.values, out.error);
    return { error: out.error };
  },
  reset() {
    session.reset();
    sendState(new Float64Array(0), "");
    return { error: "" };
  },
  setParameter({ name, value }) {
    const error = session.setParameter(name, value);
    return { error, yaml: session.configYaml(), schema: JSON.parse(session.schema()) };
  },
  setInitialState({ key, value }) {
    const error = session.setInitialState(key, value);
    return { error, yaml: session.configYaml() };
  },
  setMode({ mode }) {
    const error = session.setMode(mode);
    return { error, yaml: session.configYaml(), schema: JSON.parse(session.schema()) };
  },
  drawingAtJoints({ positions }) {
    return { error: "", drawing: session.drawingAtJoints(positions) };
  },
  drawingAtQ({ q1, q2 }) {
    return { error: "", drawing: session.drawingAtQ(q1, q2) };
  },
  async run({ yaml, name, duration, torque, outputRate }) {
    const kane = await modulePromise;
    const t0 = performance.now();
    const out = kane.runCase(yaml, name, duration, torque.kind, torque.text, torque.table,
                             outputRate);
    out.wallSeconds = (performance.now() - t0) / 1000;
    return out;
  },
  async csvText({ values }) {
    const kane = await modulePromise;
    return { error: "", text: kane.csvText(values) };
  },
};

self.onmessage = async (event) => {
  const { id, method, args } = event.data;
  try {
    const result = await handlers[method](args || {});
    post("reply", { id, result });
  } catch (e) {
    // A config nested thousands deep exhausts the browser's JavaScript stack (emscripten's C++
    // exceptions unwind through JavaScript) before yaml-cpp's own depth limit says so.
    const text = e instanceof RangeError && /call stack/i.test(e.message)
      ? `${(args && args.name) || "the config"}: config file: '${(args && args.name) || "the config"}' is nested too deeply (a config needs two levels: section, key)`
      : String(e && e.message ? e.message : e);
    post("reply", { id, result: { error: text } });
  }
};
