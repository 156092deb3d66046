// The page: a live mechanism (its physics in a Web Worker), the parameter panel built from the
// schema, plots, offline runs as simulate makes them, bags and CSVs opened by drag and drop, a
// share link, and window.kaneSim for scripts and tests (doc/guide/browser.md).
import { MechanismView } from "./drawing.js";
import { Plots } from "./plots.js";
import { readBag, readCsv, RecordingError } from "./recordings.js";
import { fieldNumber, numberArgument, torqueSpec } from "./run_arguments.js";
import { checkShare, decodeShare, encodeShare } from "./share_link.js";
import { sliderScale } from "./slider_scale.js";
import { WorkerClient } from "./worker_client.js";

const $ = (id) => document.getElementById(id);
const LIVE_WINDOW = 20;  // [s] of sim time the live plots keep
const DEFAULT_NAME = "mechanism.yaml";

const page = {
  yaml: "",
  configName: DEFAULT_NAME,
  schema: null,
  live: null,
  running: true,
  liveData: { t: [] },
  replay: null,       // {recording, index, playing, label}
  lastRun: null,      // {values: Float64Array} for Download CSV
  previousRunData: null,  // the last run panel run's columns, for the overlay of the next
  runWorker: null,
  lastPlot: 0,
  view: new MechanismView($("mechanism")),
  plots: new Plots($("plots")),
  torqueLimit: Infinity,
};

// A message at the top of the list; one already shown is moved up and counted ("(×336)")
// instead of repeated, so a warning that comes every frame cannot push the others out.
function message(kind, text) {
  const box = $("messages");
  const same = [...box.children].find((d) => d.dataset.text === text && d.className === kind);
  const div = same || document.createElement("div");
  div.className = kind;
  div.dataset.text = text;
  div.dataset.count = same ? Number(same.dataset.count) + 1 : 1;
  div.textContent = div.dataset.count > 1 ? `${text} (×${div.dataset.count})` : text;
  div.title = "click to dismiss";
  div.onclick = () => div.remove();
  if (kind === "info") {  // a note goes by itself; a warning or a refusal stays until clicked
    clearTimeout(div.expiry);
    div.expiry = setTimeout(() => div.remove(), 8000);
  }
  box.prepend(div);
  while (box.children.length > 8) box.lastChild.remove();
}

function status(text) { $("status").textContent = text; }

// ---- the live session ---------------------------------------------------------------------

function columnIndex(name) { return page.schema.columns.findIndex((c) => c.name === name); }

function onState(state) {
  if (!page.schema) return;  // the first frame of a session arrives before open() answers
  page.liveTime = state.time;
  if (state.error) message("error", state.error);
  for (const event of state.events) message("warning", event);
  if (state.error && !state.running) setRunning(false);  // a refused step paused the worker
  const width = page.schema ? page.schema.columns.length : 0;
  if (width && state.rows.length) appendLive(state.rows, width);
  if (page.replay) return;  // a recording is on show: the live mechanism runs on unseen
  const torque = state.row ? state.row[columnIndex("applied_torque")] : 0;
  page.view.draw(state.drawing, torque, page.torqueLimit, `t = ${state.time.toFixed(3)} s`);
  $("clock").textContent = `t = ${state.time.toFixed(3)} s`;  // one physics step shows
  const now = performance.now();
  if (now - page.lastPlot > 100) {
    page.lastPlot = now;
    const t = page.liveData.t;
    const end = t.length ? t[t.length - 1] : 0;
    page.plots.draw(page.liveData, [Math.max(end - LIVE_WINDOW, t[0] || 0), Math.max(end, LIVE_WINDOW / 10)], null);
  }
}

function appendLive(rows, width) {
  const data = page.liveData;
  const names = page.schema.columns.map((c) => c.name);
  for (let r = 0; r + width <= rows.length; r += width) {
    names.forEach((name, j) => (data[name] || (data[name] = [])).push(rows[r + j]));
  }
  data.t = data.t || [];
  const e = data.energy_balance;
  if (e && e.length) data.ledger_drift = e.map((v) => v - e[0]);
  // Keep the window (and a little): the oldest rows dropped in one splice.
  const t = data.t, end = t[t.length - 1];
  let drop = 0;
  while (drop < t.length && t[drop] < end - 1.5 * LIVE_WINDOW) ++drop;
  if (drop > 1000) for (const k of Object.keys(data)) data[k].splice(0, drop);
}

async function openConfig(yaml, name) {
  const reply = await page.live.call("open", { yaml, name });
  if (reply.error) return reply.error;
  page.yaml = yaml;
  page.configName = name;
  page.schema = reply.schema;
  page.plots.energyColumns = reply.schema.columns.filter((c) => c.group === "energy")
                                                .map((c) => c.name);
  page.liveData = { t: [] };
  page.view.refit();
  $("config").value = yaml;
  $("mode").value = reply.schema.mode === "position" ? "position" : "effort";
  buildParameters(reply.schema);
  buildInitialState(reply.schema);
  page.torqueLimit = parseTorqueLimit(reply.yaml);  // before the slider's range is set from it
  setCommandRange();
  await control({ running: page.running, command: Number($("command-value").value) || 0 });
  return "";
}

function parseTorqueLimit(yaml) {
  const m = /torque_limit:\s*([-+0-9.eE]+|\.inf)/.exec(yaml);
  return m && m[1] !== ".inf" ? Number(m[1]) : Infinity;
}

function control(args) { return page.live.call("control", args); }

function setRunning(running) {
  page.running = running;
  $("play").textContent = running ? "Pause" : "Run";
  control({ running });
}

function setCommandRange() {
  const position = $("mode").value === "position";
  const limit = isFinite(page.torqueLimit) ? page.torqueLimit : 5;
  $("command").min = position ? -Math.PI : -limit;
  $("command").max = position ? Math.PI : limit;
  $("command-unit").textContent = position ? "rad" : "N m";
}

function setCommand(value) {
  if (!isFinite(value)) {
    message("error", `the command must be a finite number, got '${value}'`);
    return;
  }
  // In effort mode the drive applies at most command.torque_limit: the field shows what is
  // applied, and says once that it was clamped (the driver's own warning would come each frame).
  const limit = page.torqueLimit;
  if ($("mode").value !== "position" && isFinite(limit) && Math.abs(value) > limit) {
    message("warning", `torque ${value} N m clamped to ${Math.sign(value) * limit} N m (command.torque_limit)`);
    value = Math.sign(value) * limit;
  }
  $("command").value = value;
  $("command-value").value = value;
  control({ command: value });
}

// A panel's row for a schema entry: its key and doc as the tooltip, its symbol and unit as the name.
function panelRow(p) {
  const row = document.createElement("div");
  row.className = "param";
  row.title = `${p.key}${p.symbol ? " (" + p.symbol + ")" : ""}: ${p.doc}`;
  const name = document.createElement("span");
  name.className = "name";
  name.textContent = `${p.symbol || p.name}${p.unit ? " [" + p.unit + "]" : ""}`;
  return { row, name };
}

function buildParameters(schema) {
  const box = $("parameters");
  box.textContent = "";
  // The page's speed selector is its real-time factor: the node's parameter stays out.
  for (const p of schema.parameters.filter((q) => q.name !== "real_time_factor")) {
    const { row, name } = panelRow(p);
    // The slider spans what one would try (the schema's bounds cover every legal value, up to
    // 1e7 N/m): two decades either side of a positive value, logarithmic; 0 to 10 (within the
    // bounds) for a value that starts at 0. The text field takes any value the loader accepts.
    const scale = sliderScale(p);
    const range = document.createElement("input");
    range.type = "range";
    range.min = 0;
    range.max = 1000;
    range.step = 1;
    range.value = scale.toSlider(p.value);
    range.setAttribute("aria-label", p.name);
    // The value in force (after a refusal: the one kept).
    const now = (schema = page.schema) => schema.parameters.find((q) => q.name === p.name).value;
    const number = document.createElement("input");
    number.type = "text";
    number.inputMode = "decimal";
    number.value = p.value;
    number.dataset.parameter = p.name;
    const apply = async (text) => {
      const value = fieldNumber(text);
      if (value === null) {
        message("error", `${p.key}: '${text}' is not a number; keeping ${now()}`);
        range.value = scale.toSlider(now());
        number.value = now();
        return;
      }
      const reply = await page.live.call("setParameter", { name: p.name, value });
      if (reply.error) {
        message("error", `${p.key}: ${reply.error}`);
        range.value = scale.toSlider(now(reply.schema));
        number.value = now(reply.schema);
        return;
      }
      page.schema = reply.schema;
      page.yaml = reply.yaml;
      $("config").value = reply.yaml;
      range.value = scale.toSlider(value);
      number.value = value;
    };
    range.addEventListener("change", () => apply(String(scale.fromSlider(Number(range.value)))));
    number.addEventListener("change", () => apply(number.value));
    row.append(name, range, number);
    box.appendChild(row);
  }
}

// The initial state's four values: a change restarts the motion there (the session checks it
// with the loader's words; a refusal keeps the value in force and says why).
function buildInitialState(schema) {
  const box = $("initial-state");
  box.textContent = "";
  for (const p of schema.initial_state) {
    const { row, name } = panelRow(p);
    const number = document.createElement("input");
    number.type = "text";
    number.inputMode = "decimal";
    number.value = p.value;
    number.dataset.initial = p.name;
    number.setAttribute("aria-label", p.key);
    number.addEventListener("change", async () => {
      const text = number.value, value = fieldNumber(text);
      if (value === null) {
        message("error", `${p.key}: '${text}' is not a number; keeping ${p.value}`);
        number.value = p.value;
        return;
      }
      const reply = await page.live.call("setInitialState", { key: p.name, value });
      if (reply.error) {
        message("error", reply.error);
        number.value = p.value;
        return;
      }
      const error = await openConfig(reply.yaml, page.configName);
      if (error) message("error", error);
      else message("info", `${p.key} = ${value}: the motion restarted there`);
    });
    row.append(name, document.createElement("span"), number);
    box.appendChild(row);
  }
}

// ---- offline runs (kaneSim.run) ---------------------------------------------------------------

async function run(options) {
  if (options === undefined || options === null) options = {};
  if (typeof options !== "object" || Array.isArray(options))
    throw new Error(`kaneSim.run takes one object {config, duration, torque, outputRate}, got ${JSON.stringify(options)}`);
  const { config, torque } = options;
  const duration = numberArgument("duration", options.duration === undefined ? 10 : options.duration);
  const outputRate = numberArgument("outputRate", options.outputRate === undefined ? 100 : options.outputRate);
  if (config !== undefined && config !== null && typeof config !== "string")
    throw new Error(`config must be YAML text, got ${typeof config}`);
  const spec = torqueSpec(torque);
  const yaml = config === undefined || config === null ? page.yaml : String(config);
  const name = config === undefined || config === null ? page.configName : "the given config";
  if (page.runWorker) page.runWorker.terminate("stopped: a new run started");
  const worker = new WorkerClient(null);
  page.runWorker = worker;
  $("run-stop").disabled = false;
  try {
    const out = await worker.call("run", { yaml, name, duration, torque: spec, outputRate });
    if (out.error) throw new Error(out.error);
    const width = out.columns.length;
    const rows = [];
    for (let i = 0; i + width <= out.values.length; i += width) rows.push(Array.from(out.values.subarray(i, i + width)));
    page.lastRun = { values: out.values };
    $("download").disabled = false;
    return { columns: out.columns, rows, warnings: out.warnings, refused: out.refused,
             wallSeconds: out.wallSeconds };
  } finally {
    worker.terminate("stopped");
    if (page.runWorker === worker) page.runWorker = null;
    $("run-stop").disabled = true;
  }
}

function tableToData(columns, rows) {
  const data = Object.fromEntries(columns.map((c) => [c, []]));
  for (const row of rows) columns.forEach((c, j) => data[c].push(row[j]));
  if (data.energy_balance) data.ledger_drift = data.energy_balance.map((v) => v - data.energy_balance[0]);
  return data;
}

async function runFromPanel() {
  const kind = $("run-torque-kind").value;
  const text = $("run-torque-text").value;
  const torque = kind === "none" ? undefined : { [kind]: text };
  status("running…");
  try {
    const result = await run({ duration: $("run-duration").value, torque, outputRate: $("run-rate").value });
    for (const w of result.warnings) message("warning", w);
    if (result.refused) message("error", result.refused);
    const steps = result.rows.length ? result.rows[result.rows.length - 1][0] : 0;
    message("info", `ran ${steps} s of sim time in ${result.wallSeconds.toFixed(3)} s: ${result.rows.length} rows`);
    const data = tableToData(result.columns, result.rows);
    // Two runs on the same plots (k = 200 against k = 1000): the previous one, dashed.
    const overlay = $("run-overlay").checked && page.previousRunData ? page.previousRunData : null;
    page.previousRunData = data;
    showRecording({ kind: "run", data, joints: null, overlay,
                    states: result.rows.length, t0: result.rows[0][0],
                    t1: result.rows[result.rows.length - 1][0], notes: [] }, "this run");
    status("ready");
  } catch (e) {
    message("error", e.message);
    status("ready");
  }
}

// The last run as simulate's CSV (every number as simulate writes it, by the module's writer).
async function lastRunCsv() {
  if (!page.lastRun) throw new Error("no run yet: kaneSim.run or the Run button makes one");
  const worker = new WorkerClient(null);
  try {
    return (await worker.call("csvText", { values: page.lastRun.values })).text;
  } finally {
    worker.terminate("done");
  }
}

async function downloadCsv() {
  if (!page.lastRun) return;
  const text = await lastRunCsv();
  {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], { type: "text/csv" }));
    a.download = "kane_sim_run.csv";
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  }
}

// ---- share links ------------------------------------------------------------------------------

async function shareLink() {
  const state = { config: page.yaml, duration: $("run-duration").value, outputRate: $("run-rate").value,
                  torqueKind: $("run-torque-kind").value, torqueText: $("run-torque-text").value,
                  command: Number($("command-value").value) || 0, mode: $("mode").value };
  const hash = `#run=${await encodeShare(state)}`;
  const url = `${location.origin}${location.pathname}${hash}`;
  page.sharedHash = hash;  // this page's own link: no reload
  history.replaceState(null, "", url);
  try {
    await navigator.clipboard.writeText(url);
    message("info", "share link copied (and in the address bar): it holds the config and the torque");
  } catch (e) {
    message("info", "share link in the address bar: it holds the config and the torque");
  }
  return url;
}

// ---- recordings: bags, CSVs, runs -------------------------------------------------------------

function showRecording(recording, label) {
  if (page.replay && page.replay.timer) clearInterval(page.replay.timer);
  page.replay = { recording, index: 0, playing: false, label, timer: null };
  // One set of controls for what is shown: the recording's (Play, Step, its time, Live) while it
  // is on show; the live mechanism's (Run/Pause, Step, Reset, speed, the drive) again after.
  $("replay").hidden = false;
  $("controls").hidden = true;
  $("command-row").hidden = true;
  const n = recording.joints ? recording.joints.t.length : recording.data.t.length;
  $("replay-time").max = Math.max(n - 1, 0);
  $("replay-time").value = 0;
  page.view.refit();
  for (const note of recording.notes) message("info", note);
  return drawReplay(0);
}

async function drawReplay(index) {
  const r = page.replay;
  if (!r) return;
  r.index = index;
  const rec = r.recording;
  // t on the plots' axis: a bag's joint_states at their sim time (recordings.js pairs stamps).
  let drawing, t;
  if (rec.joints) {
    t = rec.joints.simT[index];
    drawing = (await page.live.call("drawingAtJoints", { positions: rec.joints.positions[index] })).drawing;
  } else {
    t = rec.data.t[index];
    drawing = (await page.live.call("drawingAtQ", { q1: rec.data.q1[index], q2: rec.data.q2[index] })).drawing;
  }
  if (page.replay !== r) return;
  r.t = t;
  const torqueColumn = rec.data.applied_torque;
  const k = nearest(rec.data.t, t);
  page.view.draw(drawing, torqueColumn ? torqueColumn[k] : 0, page.torqueLimit, `${r.label}: t = ${t.toFixed(3)} s`);
  $("replay-label").textContent = `${r.label}: ${index + 1} / ${Number($("replay-time").max) + 1}`;
  page.plots.draw(rec.data, null, t, rec.overlay || null);
}

function nearest(ts, t) {
  let lo = 0, hi = ts.length - 1;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (ts[mid] < t) lo = mid + 1; else hi = mid;
  }
  return lo;
}

function closeReplay() {
  if (page.replay && page.replay.timer) clearInterval(page.replay.timer);
  page.replay = null;
  $("replay").hidden = true;
  $("controls").hidden = false;
  $("command-row").hidden = false;
  page.view.refit();
}

function stepReplay() {
  const r = page.replay;
  if (!r) return;
  if (r.timer) playReplay();  // a step pauses, as the live Step does
  const i = Math.min(r.index + 1, Number($("replay-time").max));
  $("replay-time").value = i;
  drawReplay(i);
}

function playReplay() {
  const r = page.replay;
  if (!r) return;
  if (r.timer) {
    clearInterval(r.timer);
    r.timer = null;
    $("replay-play").textContent = "Play";
    return;
  }
  $("replay-play").textContent = "Pause";
  const times = r.recording.joints ? r.recording.joints.t : r.recording.data.t;
  const wallStart = performance.now(), tStart = times[r.index];
  r.timer = setInterval(() => {
    const t = tStart + (performance.now() - wallStart) / 1000;
    const i = Math.min(nearest(times, t), times.length - 1);
    $("replay-time").value = i;
    drawReplay(i);
    if (i >= times.length - 1) playReplay();
  }, 33);
}

async function openBag(buffer, label = "bag") {
  const recording = await readBag(buffer, page.schema);
  await showRecording(recording, label);
  return { states: recording.states, t0: recording.t0, t1: recording.t1, start: recording.start,
           end: recording.end, topics: recording.topics, notes: recording.notes };
}

async function openFile(file) {
  try {
    if (/\.csv$/i.test(file.name)) {
      const recording = readCsv(await file.text());
      await showRecording(recording, file.name);
      message("info", `${file.name}: ${recording.states} rows, t ${recording.t0} to ${recording.t1} s`);
    } else {
      const result = await openBag(await file.arrayBuffer(), file.name);
      message("info", `${file.name}: ${result.states} joint_states messages, sim time ${result.start.toFixed(3)} to ${result.end.toFixed(3)} s`);
    }
  } catch (e) {
    message("error", `${file.name}: ${e instanceof RecordingError ? e.message : "cannot be read: " + e.message}`);
  }
}

// ---- wiring -----------------------------------------------------------------------------------

function wire() {
  $("play").onclick = () => setRunning(!page.running);
  $("step").onclick = () => { setRunning(false); page.live.call("step"); };
  $("reset").onclick = () => { page.liveData = { t: [] }; page.live.call("reset"); };
  $("speed").onchange = () => control({ speed: Number($("speed").value) });
  $("mode").onchange = async () => {
    const reply = await page.live.call("setMode", { mode: $("mode").value });
    if (reply.error) { message("error", reply.error); $("mode").value = $("mode").value === "position" ? "effort" : "position"; return; }
    page.yaml = reply.yaml;
    $("config").value = reply.yaml;
    setCommandRange();
    setCommand($("mode").value === "position" ? Number(page.liveData.q1 ? page.liveData.q1[page.liveData.q1.length - 1] : 0) : 0);
  };
  $("command").oninput = () => setCommand(Number($("command").value));
  $("command-value").onchange = () => setCommand(Number($("command-value").value));
  $("command-zero").onclick = () => setCommand(0);
  $("config-apply").onclick = async () => {
    const error = await openConfig($("config").value, "the pasted config");
    if (error) message("error", error); else message("info", "config applied: the mechanism restarted");
  };
  $("config-file").onchange = async (e) => {
    const file = e.target.files[0];
    if (!file) return;
    const text = await file.text();
    const error = await openConfig(text, file.name);
    if (error) message("error", error); else message("info", `${file.name} loaded`);
    e.target.value = "";
  };
  $("run").onclick = runFromPanel;
  $("run-stop").onclick = () => { if (page.runWorker) page.runWorker.terminate("stopped by the Stop button"); };
  $("download").onclick = downloadCsv;
  $("share").onclick = shareLink;
  $("replay-time").oninput = () => drawReplay(Number($("replay-time").value));
  $("replay-play").onclick = playReplay;
  $("replay-step").onclick = stepReplay;
  $("replay-close").onclick = closeReplay;
  $("open-file").onchange = (e) => { if (e.target.files[0]) openFile(e.target.files[0]); e.target.value = ""; };
  // Anywhere on the page takes a dropped file (the drop zone's events bubble up to the body).
  const drop = $("drop");
  document.body.addEventListener("dragover", (e) => { e.preventDefault(); drop.classList.add("over"); });
  document.body.addEventListener("dragleave", () => drop.classList.remove("over"));
  document.body.addEventListener("drop", (e) => {
    e.preventDefault();
    drop.classList.remove("over");
    if (e.dataTransfer.files[0]) openFile(e.dataTransfer.files[0]);
  });
}

async function start() {
  wire();
  page.live = new WorkerClient(onState);
  const response = await fetch(DEFAULT_NAME);
  if (!response.ok) throw new Error(`${DEFAULT_NAME} not served (${response.status})`);
  let yaml = await response.text();
  let shared = null;
  if (location.hash.startsWith("#run=")) {
    try {
      shared = checkShare(await decodeShare(location.hash.slice(5)));
    } catch (e) {
      message("error", `the share link cannot be opened: ${e.message}; the default config is loaded`);
    }
  }
  if (shared) {
    const error = await openConfig(shared.config, "the shared config");
    if (error) {
      message("error", `the share link's config is refused: ${error}; the default config is loaded`);
      shared = null;
    }
  }
  if (!shared) {
    const error = await openConfig(yaml, DEFAULT_NAME);
    if (error) throw new Error(error);
  }
  if (shared) {
    $("run-duration").value = shared.duration;
    $("run-rate").value = shared.outputRate;
    $("run-torque-kind").value = shared.torqueKind;
    $("run-torque-text").value = shared.torqueText;
    setCommand(shared.command);
    await runFromPanel();
  }
  status("ready");
}

// A share link pasted into this tab's address bar: open it as a fresh page would.
window.addEventListener("hashchange", () => {
  if (location.hash.startsWith("#run=") && location.hash !== page.sharedHash) location.reload();
});

const ready = start();
window.kaneSim = {
  ready,
  // {config (YAML text, optional), duration [s], torque, outputRate [Hz]} -> {columns, rows}
  run: async (options) => { await ready; return run(options); },
  // an ArrayBuffer of a ROS 1 bag -> {states, t0, t1} once the page shows it
  openBag: async (buffer) => { await ready; return openBag(buffer); },
  // a simulate CSV's text -> {states, t0, t1} once the page shows it
  openCsv: async (text) => {
    await ready;
    const r = readCsv(text);
    await showRecording(r, "CSV");
    return { states: r.states, t0: r.t0, t1: r.t1 };
  },
  shareLink: async () => { await ready; return shareLink(); },
  // the last run as simulate's CSV text (what Download CSV saves)
  csv: async () => { await ready; return lastRunCsv(); },
  live: () => ({ running: page.running, rows: page.liveData.t.length, time: page.liveTime }),
  // what the replay shows: {label, states, last: [t, q1, q2], at: the slider's time on the
  // plots' axis}, or null when live
  shown: () => {
    if (!page.replay) return null;
    const { data, states, overlay } = page.replay.recording;
    const n = data.t.length - 1;
    const o = overlay ? overlay.t.length - 1 : -1;
    return { label: page.replay.label, states, last: [data.t[n], data.q1[n], data.q2[n]],
             at: page.replay.t,
             overlay: overlay ? [overlay.t[o], overlay.q1[o], overlay.q2[o]] : null };
  },
};
ready.catch((e) => { status("failed"); message("error", e.message); });
