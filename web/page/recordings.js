// Recordings opened in the page: a ROS 1 bag (read by @foxglove/rosbag, the page's one
// third-party library) or a simulate CSV, as columns for the plots and joint positions for the
// replay. A bag's /mechanism_state fields map to the CSV's columns through the module's column
// table (each column's message field), as plot_bag reads them; joint_states gives the pose (and,
// beside a mechanism_state, the sensors' q1).
import { Bag, MessageReader, parseMessageDefinition } from "./vendor/rosbag.js";

export const MAX_FILE_BYTES = 1 << 30;  // 1 GiB: read into memory whole
export const MAX_STATES = 2000000;       // joint_states messages kept (the rest counted, not kept)

export class RecordingError extends Error {}

const seconds = (time) => time.sec + time.nsec * 1e-9;

// The bag header record's index_pos (rosbag format 2.0: after the magic line, a record of
// header_len, fields "name=value" each with its length, data_len, data): where the index starts.
// A file cut before it is truncated; 0 is a recording that never finished (no index written).
function checkIndex(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = 13;
  if (bytes.length < at + 4) throw new RecordingError("the bag is truncated: it ends inside its header record");
  const headerLength = view.getUint32(at, true);
  at += 4;
  const end = at + headerLength;
  if (end > bytes.length) throw new RecordingError("the bag is truncated: it ends inside its header record");
  let index = null;
  while (at + 4 <= end) {
    const length = view.getUint32(at, true);
    const field = bytes.subarray(at + 4, at + 4 + length);
    const eq = field.indexOf(61);  // '='
    if (eq > 0 && new TextDecoder().decode(field.subarray(0, eq)) === "index_pos" && length - eq - 1 === 8)
      index = Number(view.getBigUint64(at + 4 + eq + 1, true));
    at += 4 + length;
  }
  if (index === null) throw new RecordingError("the bag is corrupt: its header record has no index position");
  if (index === 0)
    throw new RecordingError("the bag has no index (its recording did not finish): rosbag reindex FILE.bag repairs it");
  if (index >= bytes.length)
    throw new RecordingError(`the bag is truncated: the file ends at byte ${bytes.length}, before its index at byte ${index} (copied while being recorded, or cut short)`);
  return index;
}

// -> {kind: "bag", states, t0, t1 (stamps), start, end (sim time), data: {t, column...},
//     joints: {t (stamps), simT, positions: [[4]...]}, notes}
export async function readBag(buffer, schema) {
  if (buffer.byteLength > MAX_FILE_BYTES)
    throw new RecordingError(`the file is ${buffer.byteLength} bytes; the page reads bags up to ${MAX_FILE_BYTES} bytes (split it with rosbag filter)`);
  const bytes = new Uint8Array(buffer);
  const header = new TextDecoder().decode(bytes.subarray(0, 13));
  if (header !== "#ROSBAG V2.0\n")
    throw new RecordingError("not a ROS 1 bag (version 2.0): it does not start with '#ROSBAG V2.0'");
  const indexAt = checkIndex(bytes);
  const bag = new Bag({
    read: async (offset, length) => {
      if (offset + length > bytes.length) throw new RecordingError("the bag is truncated (a record runs past the end of the file): was it copied while being recorded? rosbag reindex repairs an unindexed bag");
      return bytes.subarray(offset, offset + length);
    },
    size: () => bytes.length,
  }, { parse: false });
  try {
    await bag.open();
  } catch (e) {
    throw new RecordingError(`the bag is corrupt or cut short: its index (bytes ${indexAt} to ${bytes.length}) cannot be read (${e.message})`);
  }
  const byType = (type) => [...bag.connections.values()].filter((c) => c.type === type);
  const jointConnections = byType("sensor_msgs/JointState");
  const stateConnections = byType("kane_sim/MechanismState");
  if (!jointConnections.length && !stateConnections.length)
    throw new RecordingError(`the bag has neither sensor_msgs/JointState nor kane_sim/MechanismState messages (topics: ${[...new Set([...bag.connections.values()].map((c) => `${c.topic} (${c.type})`))].join(", ") || "none"})`);
  const pick = (connections, name) => {
    const topics = [...new Set(connections.map((c) => c.topic))];
    return topics.find((t) => t.endsWith(name)) || topics[0];
  };
  const jointTopic = jointConnections.length ? pick(jointConnections, "joint_states") : null;
  const stateTopic = stateConnections.length ? pick(stateConnections, "mechanism_state") : null;
  const readers = new Map();
  for (const c of [...jointConnections, ...stateConnections])
    readers.set(c.conn, new MessageReader(parseMessageDefinition(c.messageDefinition)));
  const joints = { t: [], positions: [], names: null };
  const state = { t: [] };
  // Every column a /mechanism_state field carries (t is its sim_time), as plot_bag reads them.
  const fields = schema.columns.filter((c) => c.message_field && c.name !== "t");
  for (const c of fields) state[c.name] = [];
  // Each state's header stamp beside its sim time: the joint_states of the same tick carry the
  // same stamp (the node's and simulate's), so a joint_states' sim time is read, not guessed.
  const stateStamps = [];
  let skipped = 0, unstamped = 0;
  const topics = [jointTopic, stateTopic].filter(Boolean);
  try {
    for await (const event of bag.messageIterator({ topics })) {
      const message = readers.get(event.connectionId).readMessage(event.data);
      let stamp = message.header ? seconds(message.header.stamp) : 0;
      if (stamp === 0) { stamp = seconds(event.timestamp); ++unstamped; }
      if (event.topic === jointTopic) {
        if (joints.t.length >= MAX_STATES) { ++skipped; continue; }
        if (!joints.names) joints.names = message.name;
        const positions = schema.joints.map((name) => {
          const i = message.name.indexOf(name);
          return i >= 0 ? message.position[i] : NaN;
        });
        joints.t.push(stamp);
        joints.positions.push(positions);
      } else if (state.t.length < MAX_STATES) {
        const simTime = message.sim_time !== undefined ? message.sim_time : stamp;
        stateStamps.push(stamp);
        state.t.push(simTime);
        for (const c of fields) {
          const v = message[c.message_field.replace(/\[\d+\]$/, "")];
          const value = c.message_index >= 0 ? (v ? v[c.message_index] : NaN) : v;
          state[c.name].push(typeof value === "boolean" ? Number(value) : Number(value));
        }
      }
    }
  } catch (e) {
    if (e instanceof RecordingError) throw e;
    const text = String(e.message || e);
    if (/compression|bz2|lz4/i.test(text))
      throw new RecordingError(`the bag's chunks are compressed (${text}); the page reads uncompressed bags: rosbag decompress FILE.bag first`);
    throw new RecordingError(`the bag is corrupt or truncated: ${text}`);
  }
  if (!joints.t.length && !state.t.length)
    throw new RecordingError(`the bag's ${topics.join(" and ")} topics hold no messages`);
  if (jointTopic && joints.names && !schema.joints.some((n) => joints.names.includes(n)))
    throw new RecordingError(`${jointTopic} names none of this mechanism's joints (${schema.joints.join(", ")}); it has ${joints.names.join(", ")}`);
  const notes = [];
  if (skipped) notes.push(`kept the first ${MAX_STATES} joint_states messages of ${MAX_STATES + skipped}`);
  if (unstamped) notes.push(`${unstamped} messages had no header stamp: placed at the bag's receive times`);
  // The plots' time axis: sim time beside a mechanism state, else the joint_states' stamps from
  // the first. A joint_states' sim time is its state's of the same stamp; between states (a
  // sensor's latency) interpolated, and before the first state or after the last, that state's:
  // a node started paused stamps states at sim time 0 while its clock waits, and the replay's
  // time stays on the plots' axis.
  let data;
  if (state.t.length) {
    data = state;
    if (data.energy_balance) data.ledger_drift = data.energy_balance.map((v) => v - data.energy_balance[0]);
    if (joints.t.length) {
      joints.simT = joints.t.map((stamp) => simTimeAt(stateStamps, state.t, stamp));
      data.sensor_t = joints.simT;
      data.sensor_q1 = joints.positions.map((p) => p[0]);
    }
  } else {
    joints.simT = joints.t.map((t) => t - joints.t[0]);
    data = { t: joints.simT, q1: joints.positions.map((p) => p[0]),
             q2: joints.positions.map((p) => p[3]) };
    notes.push("joint_states only: the positions are plotted; energies and powers need /mechanism_state");
  }
  const times = joints.t.length ? joints.t : stateStamps;
  const simTimes = joints.t.length ? joints.simT : state.t;
  return { kind: "bag", states: joints.t.length, t0: times[0], t1: times[times.length - 1],
           start: simTimes[0], end: simTimes[simTimes.length - 1],
           data, joints: joints.t.length ? joints : null,
           topics: { joints: jointTopic, state: stateTopic }, notes };
}

// The sim time at a header stamp, from the states' (stamp, sim time) pairs in stamp order: the
// pair's own at an equal stamp, linear between two, the end's beyond the ends.
export function simTimeAt(stamps, simTimes, stamp) {
  const last = stamps.length - 1;
  if (!(stamp > stamps[0])) return simTimes[0];
  if (!(stamp < stamps[last])) return simTimes[last];
  let lo = 0, hi = last;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (stamps[mid] <= stamp) lo = mid; else hi = mid;
  }
  if (stamps[lo] === stamp) return simTimes[lo];
  const f = (stamp - stamps[lo]) / (stamps[hi] - stamps[lo]);
  return simTimes[lo] + f * (simTimes[hi] - simTimes[lo]);
}

// A number as simulate writes one (std::to_chars: digits, a point, an exponent), or nan / inf.
const NUMBER = /^[-+]?((\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|nan|inf)$/i;

// A simulate CSV -> the same shape (no joint_states: the replay poses the mechanism from q1, q2).
export function readCsv(text) {
  const lines = text.split(/\r?\n/).filter((l) => l.trim() && !l.startsWith("#"));
  if (lines.length < 2) throw new RecordingError("the CSV has no rows (a header and at least one row)");
  const header = lines[0].split(",").map((s) => s.trim());
  for (const needed of ["t", "q1", "q2"])
    if (!header.includes(needed)) throw new RecordingError(`the CSV has no '${needed}' column: not a simulate CSV (its header: ${header.slice(0, 8).join(",")}...)`);
  const data = Object.fromEntries(header.map((h) => [h, []]));
  for (let i = 1; i < lines.length; ++i) {
    const cells = lines[i].split(",");
    if (cells.length !== header.length)
      throw new RecordingError(`CSV line ${i + 1} has ${cells.length} values; the header has ${header.length}`);
    cells.forEach((cell, j) => {
      const text = cell.trim();
      if (!NUMBER.test(text))
        throw new RecordingError(`CSV line ${i + 1}, column ${header[j]}: '${cell}' is not a number`);
      const v = /nan/i.test(text) ? NaN : /inf/i.test(text) ? (text.startsWith("-") ? -Infinity : Infinity) : Number(text);
      if (!Number.isFinite(v) && ["t", "q1", "q2"].includes(header[j]))
        throw new RecordingError(`CSV line ${i + 1}, column ${header[j]}: '${cell}' is not finite; the replay needs t, q1 and q2`);
      if (header[j] === "t" && data.t.length && v < data.t[data.t.length - 1])
        throw new RecordingError(`CSV line ${i + 1}: t = ${v} s comes before the row above (t = ${data.t[data.t.length - 1]} s)`);
      data[header[j]].push(v);
    });
  }
  if (data.energy_balance) data.ledger_drift = data.energy_balance.map((v) => v - data.energy_balance[0]);
  return { kind: "csv", states: data.t.length, t0: data.t[0], t1: data.t[data.t.length - 1], data,
           joints: null, notes: [] };
}
