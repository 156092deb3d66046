// Time plots on canvases, the panels of plot_bag's figure (plot_run in kane_sim.plotting): q1,
// q2, u1 and u2, the torque, the energies, each load's power with their sum (dT/dt), and the
// ledger's drift E + D - W - P. Each panel draws what the data have and says nothing otherwise.

const COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
                "#7f7f7f", "#bcbd22", "#17becf"];

// [title, unit, [[column, label], ...]]; the "energy" panel takes T, each load's potential energy
// (the columns of the output table's "energy" group, Plots.energyColumns: gravity's and the
// spring's always, another load's when it is not zero throughout), E, W and D; "power" panels
// take every power_* column that is not zero throughout, and their sum.
export const PANELS = [
  ["q1, crank angle", "rad", [["q1", "q1"], ["sensor_q1", "q1 from joint_states"]]],
  ["q2, slider 4", "m", [["q2", "q2"]]],
  ["speeds", "rad/s, m/s", [["u1", "u1 [rad/s]"], ["u2", "u2 [m/s]"]]],
  ["torque", "N m", [["applied_torque", "applied M_m"]]],
  ["energy", "J", "energy"],
  ["power", "W", "power"],
  ["ledger drift (E + D - W - P)", "J", [["ledger_drift", "drift"]]],
];

export class Plots {
  constructor(container) {
    this.container = container;
    this.canvases = PANELS.map(([title]) => {
      const canvas = document.createElement("canvas");
      canvas.width = 700;
      canvas.height = 120;
      canvas.setAttribute("aria-label", title);
      container.appendChild(canvas);
      return canvas;
    });
    this.cursor = null;
    // The output table's energy columns (the schema's, set by the page when a config opens).
    this.energyColumns = ["kinetic_energy", "gravitational_energy", "spring_energy", "total_energy"];
  }

  // data: {t: [...], column: [...]}; window: [t0, t1] or null for all; cursor: a time to mark;
  // overlay: another run's data, drawn dashed under the same curves (two runs compared).
  draw(data, window, cursor, overlay = null) {
    PANELS.forEach(([title, unit, spec], i) => {
      let curves = spec === "power"    ? powerCurves(data)
                   : spec === "energy" ? energyCurves(data, this.energyColumns)
                                       : spec.filter(([k]) => data[k]);
      this.panel(this.canvases[i], `${title} [${unit}]`, data, curves, window, cursor, overlay);
    });
  }

  panel(canvas, title, data, curves, window, cursor, overlay) {
    const g = canvas.getContext("2d");
    // Drawn at the size it is shown (CSS pixels times the screen's density): its 11 px text stays
    // 11 px on a phone's 400 px as on a desktop, instead of a 700 px drawing scaled down.
    const density = globalThis.devicePixelRatio || 1;
    const W = canvas.clientWidth || canvas.width, H = canvas.clientHeight || canvas.height;
    if (canvas.width !== Math.round(W * density) || canvas.height !== Math.round(H * density)) {
      canvas.width = Math.round(W * density);
      canvas.height = Math.round(H * density);
    }
    g.setTransform(density, 0, 0, density, 0, 0);
    const left = 60, right = Math.min(150, Math.round(0.3 * W)), top = 14, bottom = 16;
    g.clearRect(0, 0, W, H);
    g.font = "11px sans-serif";
    g.fillStyle = "#1d2430";
    g.fillText(title, left, 11);
    const t = data.t || [];
    if (!t.length || !curves.length) {
      g.fillStyle = "#888";
      g.fillText(t.length ? "not in these data" : "no data yet", left + 10, H / 2);
      return;
    }
    const t0 = window ? window[0] : t[0], t1 = window ? window[1] : t[t.length - 1];
    let first = 0;
    while (first < t.length - 1 && t[first] < t0) ++first;
    let lo = Infinity, hi = -Infinity;
    for (const source of overlay ? [data, overlay] : [data]) {
      for (const [key] of curves) {
        const ys = source[key] || (key === "sum" ? sumOfPowers(source, curves) : null);
        if (!ys) continue;
        for (let i = source === data ? first : 0; i < ys.length; ++i) {
          if (isFinite(ys[i])) { lo = Math.min(lo, ys[i]); hi = Math.max(hi, ys[i]); }
        }
      }
    }
    if (!(hi >= lo)) { lo = -1; hi = 1; }
    // A constant signal (a load that is off, a held torque) gets a range around its value, not
    // one of rounding's width: its axis reads "1.5 … 2.5", not "2 / 2" or "±1e-12".
    if (hi - lo <= 1e-9 * Math.max(1, Math.abs(hi))) {
      const centre = (hi + lo) / 2, span = centre !== 0 ? Math.abs(centre) / 2 : 1;
      lo = centre - span; hi = centre + span;
    }
    const pad = (hi - lo) * 0.08;
    lo -= pad; hi += pad;
    const X = (x) => left + ((x - t0) / Math.max(t1 - t0, 1e-9)) * (W - left - right);
    const Y = (y) => top + (1 - (y - lo) / (hi - lo)) * (H - top - bottom);
    // Gridlines and labels at round values (1, 2 or 5 times a power of ten) on both axes.
    g.strokeStyle = "#eceef3";
    g.fillStyle = "#555";
    g.lineWidth = 1;
    for (const v of niceTicks(lo, hi, 4)) {
      const y = Y(v);
      g.beginPath(); g.moveTo(left, y); g.lineTo(W - right, y); g.stroke();
      g.fillText(tick(v), 2, y + 4);
    }
    const times = niceTicks(t0, t1, 6);
    times.forEach((v, i) => {
      const x = X(v);
      g.beginPath(); g.moveTo(x, top); g.lineTo(x, H - bottom); g.stroke();
      g.fillText(i === times.length - 1 ? `${tick(v)} s` : tick(v), x - 8, H - 3);
    });
    g.strokeStyle = "#ccd";
    g.strokeRect(left, top, W - left - right, H - top - bottom);
    if (overlay && overlay.t) {
      curves.forEach(([key], c) => {
        const ys = overlay[key] || (key === "sum" ? sumOfPowers(overlay, curves) : null);
        if (!ys || key === "sensor_q1") return;
        g.strokeStyle = key === "sum" ? "#000" : COLORS[c % COLORS.length];
        g.globalAlpha = 0.55;
        g.setLineDash([5, 4]);
        g.lineWidth = 1.2;
        g.beginPath();
        let started = false;
        const stride = Math.max(1, Math.floor(overlay.t.length / (2 * (W - left - right))));
        for (let i = 0; i < ys.length; i += stride) {
          if (overlay.t[i] < t0 || overlay.t[i] > t1 || !isFinite(ys[i])) continue;
          const x = X(overlay.t[i]), y = Y(ys[i]);
          if (!started) { g.moveTo(x, y); started = true; } else g.lineTo(x, y);
        }
        g.stroke();
        g.setLineDash([]);
        g.globalAlpha = 1;
      });
    }
    curves.forEach(([key, label], c) => {
      const ys = data[key] || (key === "sum" ? sumOfPowers(data, curves) : null);
      if (!ys) return;
      g.strokeStyle = key === "sum" ? "#000" : COLORS[c % COLORS.length];
      g.setLineDash(key === "sum" ? [2, 2] : []);
      g.lineWidth = 1.2;
      g.beginPath();
      const ts = key === "sensor_q1" ? data.sensor_t : t;
      let started = false;
      // At most ~2 points a pixel: long runs are thinned, not cut.
      const stride = Math.max(1, Math.floor((ts.length - first) / (2 * (W - left - right))));
      for (let i = key === "sensor_q1" ? 0 : first; i < ys.length; i += stride) {
        if (ts[i] < t0 || !isFinite(ys[i])) continue;
        const x = X(ts[i]), y = Y(ys[i]);
        if (!started) { g.moveTo(x, y); started = true; } else g.lineTo(x, y);
      }
      g.stroke();
      g.setLineDash([]);
      g.fillStyle = g.strokeStyle;
      g.fillText(label, W - right + 6, top + 10 + 12 * c);
    });
    if (cursor !== null && cursor !== undefined) {
      g.strokeStyle = "#d1242f";
      g.beginPath();
      g.moveTo(X(cursor), top);
      g.lineTo(X(cursor), H - bottom);
      g.stroke();
    }
  }
}

const ENERGY_LABELS = { kinetic_energy: "kinetic T", gravitational_energy: "gravitational V_g",
                        spring_energy: "spring V_s", total_energy: "total E" };

function energyCurves(data, columns) {
  const always = (k) => k in ENERGY_LABELS;
  const terms = columns.filter((k) => data[k] && (always(k) || data[k].some((v) => v !== 0)))
                       .sort((a, b) => (a === "total_energy") - (b === "total_energy"));
  return terms.map((k) => [k, ENERGY_LABELS[k] || k.replace(/_energy$/, "").replace(/_/g, " ") + " V"])
              .concat([["motor_work", "motor work W"], ["dissipated_energy", "dissipated D"]]
                        .filter(([k]) => data[k]));
}

function powerCurves(data) {
  const keys = Object.keys(data).filter((k) => k.startsWith("power_") &&
                                               data[k].some((v) => v !== 0));
  if (!keys.length) return [];
  return keys.map((k) => [k, k.slice(6)]).concat([["sum", "sum = dT/dt"]]);
}

function sumOfPowers(data, curves) {
  const keys = curves.map(([k]) => k).filter((k) => k !== "sum");
  return data.t.map((_, i) => keys.reduce((s, k) => s + data[k][i], 0));
}

// Round values in [lo, hi], about `count` of them: steps of 1, 2 or 5 times a power of ten.
export function niceTicks(lo, hi, count) {
  if (!(hi > lo) || !isFinite(hi - lo)) return [];
  const raw = (hi - lo) / count, power = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= 0.75 * raw);
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step)
    out.push(Math.abs(v) < 1e-9 * step ? 0 : Number(v.toPrecision(12)));
  return out;
}

function tick(v) {
  if (v === 0) return "0";
  const a = Math.abs(v);
  return a >= 1e4 || a < 1e-3 ? v.toExponential(2) : String(Number(v.toPrecision(4)));
}
