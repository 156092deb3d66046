// Share links: a run's state (config, torque, duration, rate, command) as deflate-raw JSON in
// base64url, in the URL's #run= fragment; and what a link must hold to be opened.
export async function encodeShare(state) {
  const bytes = new TextEncoder().encode(JSON.stringify(state));
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
  try {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate-raw"));
    return JSON.parse(await new Response(stream).text());
  } catch (e) {
    throw new Error("it is not a kane_sim share link, or was cut short (its data do not unpack)");
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

