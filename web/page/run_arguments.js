// kaneSim.run's arguments checked as simulate's flags are: numbers (or their text), never
// coerced; the torque as one of the profile's forms, sent to the module as simulate's flag text.
// torque: undefined | number | {constant|step|sine: text} | [[t, torque], ...]
export function torqueSpec(torque) {
  const shapes = `one of a number, {constant: NM}, {step: "T,BEFORE,AFTER"}, {sine: "AMP,FREQ[,OFFSET]"} or [[t, torque], ...]`;
  if (torque === undefined || torque === null) return { kind: "none", text: "", table: [] };
  if (typeof torque === "number" || typeof torque === "string")
    return { kind: "constant", text: String(numberArgument("torque", torque)).trim(), table: [] };
  if (Array.isArray(torque)) {
    const flat = [];
    for (const pair of torque) {
      if (!Array.isArray(pair) || pair.length !== 2)
        throw new Error(`torque: a table is a list of [t, torque] pairs, got ${JSON.stringify(pair)}`);
      flat.push(numberArgument("torque table's t", pair[0]), numberArgument("torque table's torque", pair[1]));
    }
    return { kind: "table", text: "", table: flat };
  }
  const kinds = typeof torque === "object" ? Object.keys(torque) : [];
  if (kinds.length !== 1 || !["constant", "step", "sine"].includes(kinds[0]))
    throw new Error(`torque must be ${shapes}; got ${JSON.stringify(torque)}`);
  const text = torque[kinds[0]];
  if (typeof text !== "string" && typeof text !== "number")
    throw new Error(`torque: {${kinds[0]}: ...} takes simulate's text, got ${JSON.stringify(text)}`);
  if (kinds[0] === "constant") return { kind: "constant", text: String(numberArgument("torque", text)), table: [] };
  return { kind: kinds[0], text: String(text), table: [] };
}

// A number given as a number or as its text (the panel's fields): anything else is refused by
// name, never coerced (Number("") is 0, Number(true) is 1, Number("0x10") is 16).
const NUMBER_TEXT = /^\s*[-+]?((\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|Infinity|NaN)\s*$/;
export function numberArgument(name, value) {
  if (typeof value === "number") return value;
  if (typeof value === "string" && NUMBER_TEXT.test(value)) return Number(value);
  throw new Error(`${name} must be a number, got ${JSON.stringify(value) ?? String(value)}`);
}


// A panel field's text as a number, or null: the same decimal text as above (not "0x10", not
// ""), and nan / inf / -inf in any case, which go on to the loader so that its words refuse them.
export function fieldNumber(text) {
  const t = String(text).trim();
  if (/^[-+]?inf(inity)?$/i.test(t)) return t.startsWith("-") ? -Infinity : Infinity;
  if (/^[-+]?nan$/i.test(t)) return NaN;
  return NUMBER_TEXT.test(t) ? Number(t) : null;
}
