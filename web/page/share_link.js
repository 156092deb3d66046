// Share links: a run's state (config, torque, duration, rate, command) as deflate-raw JSON in
// base64url, in the URL's #run= fragment, with the CRC-32 of the state's JSON beside it so that a
// link changed in transit (one character edited) is named instead of opening another config;
// and what a link must hold to be opened.

const CRC_TABLE = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});

// CRC-32 (IEEE, as zlib's) of a string's UTF-8 bytes, as 8 hex digits.
export function crc32(text) {
  let crc = 0xffffffff;
  for (const b of new TextEncoder().encode(text)) crc = CRC_TABLE[(crc ^ b) & 0xff] ^ (crc >>> 8);
  return ((crc ^ 0xffffffff) >>> 0).toString(16).padStart(8, "0");
}

export async function encodeShare(state) {
  const json = JSON.stringify(state);
  const bytes = new TextEncoder().encode(JSON.stringify({ run: json, crc32: crc32(json) }));
  const stream = new Blob([bytes]).stream().pipeThrough(new CompressionStream("deflate-raw"));
  const packed = new Uint8Array(await new Response(stream).arrayBuffer());
  let binary = "";
  for (const b of packed) binary += String.fromCharCode(b);
  return btoa(binary).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

export async function decodeShare(text) {
  if (!/^[A-Za-z0-9_-]+$/.test(text)) throw new Error("it holds characters a share link never has");
  let bytes;
  try {
    const binary = atob(text.replace(/-/g, "+").replace(/_/g, "/"));
    bytes = Uint8Array.from(binary, (c) => c.charCodeAt(0));
  } catch (e) {
    throw new Error("it is not a kane_sim share link (not base64url)");
  }
  let envelope;
  try {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate-raw"));
    envelope = JSON.parse(await new Response(stream).text());
  } catch (e) {
    throw new Error("it is not a kane_sim share link, or was cut short or changed (its data do not unpack)");
  }
  if (envelope === null || typeof envelope.run !== "string" || typeof envelope.crc32 !== "string")
    throw new Error("it carries no checksum (not a kane_sim share link, or changed)");
  if (crc32(envelope.run) !== envelope.crc32)
    throw new Error("it was changed or damaged on the way: its checksum does not match its content");
  try {
    return JSON.parse(envelope.run);
  } catch (e) {
    throw new Error("it was changed or damaged on the way (its run does not parse)");
  }
}

// What a share link must hold; anything else is named, and the page opens with its defaults.
export function checkShare(state) {
  const fail = (what) => { throw new Error(`it holds ${what}`); };
  if (typeof state !== "object" || state === null || Array.isArray(state)) fail("no run");
  if (typeof state.config !== "string") fail("no config text");
  for (const key of ["duration", "outputRate", "torqueText"])
    if (typeof state[key] !== "string" && typeof state[key] !== "number") fail(`no ${key}`);
  if (!["none", "constant", "step", "sine"].includes(state.torqueKind))
    fail(`an unknown torque kind ${JSON.stringify(state.torqueKind)}`);
  if (typeof state.command !== "number" || !isFinite(state.command)) state.command = 0;
  return state;
}

