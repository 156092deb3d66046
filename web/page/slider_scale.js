// The parameter panel's sliders: two decades either side of a positive value, logarithmic; 0 to
// 10 (within the schema's bounds) for a value that starts at 0.
export function sliderScale(p) {
  const lo = Math.max(p.min, 0), hi = p.max;
  if (p.value > 0) {
    const a = Math.log10(Math.max(p.value / 100, lo > 0 ? lo : p.value / 100));
    const b = Math.log10(Math.min(p.value * 100, hi));
    return {
      toSlider: (v) => (v > 0 ? Math.round(1000 * (Math.log10(v) - a) / (b - a)) : 0),
      fromSlider: (x) => Number((10 ** (a + (x / 1000) * (b - a))).toPrecision(3)),
    };
  }
  const top = Math.min(hi, 10);
  return {
    toSlider: (v) => Math.round(1000 * v / top),
    fromSlider: (x) => Number(((x / 1000) * top).toPrecision(3)),
  };
}

