// The mechanism on a canvas, from the module's drawing (each link's outline in the textbook's
// frame (0): x down, y across, as rviz shows the same shapes): the rail, the ground pivot O, the
// spring between the sliders as a zigzag, and the drive's torque as an arc at O.

const MARGIN = 30;  // [px]

export class MechanismView {
  constructor(canvas) {
    this.canvas = canvas;
    this.context = canvas.getContext("2d");
    this.bounds = null;  // [xmin, xmax, ymin, ymax] in metres, grown, never shrunk, until reset
  }

  // A new mechanism (a config, a bag): the view fits it again.
  refit() { this.bounds = null; }

  grow(drawing) {
    const b = this.bounds || [Infinity, -Infinity, Infinity, -Infinity];
    let grew = false;
    for (const link of drawing.links) {
      for (let i = 0; i < link.polygon.length; i += 2) {
        const x = link.polygon[i], y = link.polygon[i + 1];
        if (x < b[0]) { b[0] = x; grew = true; }
        if (x > b[1]) { b[1] = x; grew = true; }
        if (y < b[2]) { b[2] = y; grew = true; }
        if (y > b[3]) { b[3] = y; grew = true; }
      }
    }
    if (grew || !this.bounds) {
      // A margin of a fifth around, so ordinary motion does not refit at every frame.
      const span = Math.max(b[1] - b[0], b[3] - b[2], 0.1);
      this.bounds = [b[0] - span / 5, b[1] + span / 5, b[2] - span / 5, b[3] + span / 5];
    }
  }

  // Mechanism (x down, y across) -> canvas pixels: y to the right, x downwards.
  transform() {
    const [xmin, xmax, ymin, ymax] = this.bounds;
    const w = this.canvas.width - 2 * MARGIN, h = this.canvas.height - 2 * MARGIN;
    const scale = Math.min(w / (ymax - ymin), h / (xmax - xmin));
    const ox = MARGIN + (w - scale * (ymax - ymin)) / 2 - scale * ymin;
    const oy = MARGIN + (h - scale * (xmax - xmin)) / 2 - scale * xmin;
    return { scale, px: (x, y) => [ox + scale * y, oy + scale * x] };
  }

  draw(drawing, torque, torqueLimit, label) {
    const g = this.context;
    g.clearRect(0, 0, this.canvas.width, this.canvas.height);
    if (!drawing || !drawing.links) return;
    this.grow(drawing);
    const { scale, px } = this.transform();
    const o = drawing.origins;
    // The rail: the line the sliders run on (the mechanism's x axis, through O).
    g.strokeStyle = "#9aa3b5";
    g.lineWidth = 2;
    g.setLineDash([6, 4]);
    g.beginPath();
    g.moveTo(...px(this.bounds[0], 0));
    g.lineTo(...px(this.bounds[1], 0));
    g.stroke();
    g.setLineDash([]);
    const slider3 = Object.keys(o).find((k) => k.endsWith("slider3"));
    const slider4 = Object.keys(o).find((k) => k.endsWith("slider4"));
    if (slider3 && slider4) this.spring(px(o[slider3][0], o[slider3][1]), px(o[slider4][0], o[slider4][1]));
    for (const link of drawing.links) {
      const [r, gr, b] = link.color;
      g.fillStyle = `rgb(${255 * r},${255 * gr},${255 * b})`;
      g.strokeStyle = "#1d2430";
      g.lineWidth = 1;
      g.beginPath();
      for (let i = 0; i < link.polygon.length; i += 2) {
        const [X, Y] = px(link.polygon[i], link.polygon[i + 1]);
        if (i === 0) g.moveTo(X, Y); else g.lineTo(X, Y);
      }
      g.closePath();
      g.fill();
      g.stroke();
    }
    // Ground pivot O, hatched.
    const [Ox, Oy] = px(0, 0);
    g.fillStyle = "#1d2430";
    g.beginPath();
    g.arc(Ox, Oy, 5, 0, 2 * Math.PI);
    g.fill();
    this.torqueArrow(Ox, Oy, torque, torqueLimit, scale);
    this.labels(o, px);
    if (label) {
      g.fillStyle = "#1d2430";
      g.font = "13px monospace";
      g.fillText(label, 10, this.canvas.height - 10);
    }
  }

  // The textbook's names on the drawing: the points O, A, B, C, the coordinates q1 (the crank's
  // angle from the rail) and q2 (C's distance down the rail), and the frame: x down the rail,
  // gravity along +x.
  labels(origins, px) {
    const g = this.context;
    const at = (suffix) => {
      const key = Object.keys(origins).find((k) => k.endsWith(suffix));
      return key ? px(origins[key][0], origins[key][1]) : null;
    };
    const O = px(0, 0), A = at("rod2"), B = at("slider3"), C = at("slider4");
    g.font = "bold 13px sans-serif";
    g.fillStyle = "#1d2430";
    const mark = (p, name, dx, dy) => { if (p) g.fillText(name, p[0] + dx, p[1] + dy); };
    mark(O, "O", -18, -6);
    mark(A, "A", A && A[0] >= O[0] ? 8 : -18, 4);
    mark(B, "B", 14, 4);
    mark(C, "C", 14, 4);
    g.font = "italic 12px sans-serif";
    g.fillStyle = "#3a6ee8";
    if (A) mark([(O[0] + A[0]) / 2, (O[1] + A[1]) / 2], "q1", A[0] >= O[0] ? -22 : 8, 0);
    if (C) mark([O[0], (O[1] + C[1]) / 2], "q2", -26, 0);
    // The frame and gravity, in the corner.
    const x0 = this.canvas.width - 70, y0 = 20;
    g.strokeStyle = "#1d2430";
    g.fillStyle = "#1d2430";
    g.lineWidth = 1.5;
    g.beginPath(); g.moveTo(x0, y0); g.lineTo(x0, y0 + 34); g.stroke();
    g.beginPath(); g.moveTo(x0 - 4, y0 + 28); g.lineTo(x0, y0 + 36); g.lineTo(x0 + 4, y0 + 28); g.fill();
    g.font = "12px sans-serif";
    g.fillText("x, g", x0 + 7, y0 + 30);
  }

  spring([x0, y0], [x1, y1]) {
    const g = this.context;
    const dx = x1 - x0, dy = y1 - y0, length = Math.hypot(dx, dy);
    if (length < 1) return;
    const ux = dx / length, uy = dy / length, nx = -uy, ny = ux;
    const turns = 10, width = 8;
    g.strokeStyle = "#b0462c";
    g.lineWidth = 1.5;
    g.beginPath();
    g.moveTo(x0, y0);
    for (let i = 1; i < 2 * turns; ++i) {
      const s = (i / (2 * turns)) * length, side = i % 2 ? width : -width;
      g.lineTo(x0 + ux * s + nx * side, y0 + uy * s + ny * side);
    }
    g.lineTo(x1, y1);
    g.stroke();
  }

  // M_m about the textbook's z = x × y: with x down and y to the right on the screen, z points
  // out of the screen, so a positive torque turns counter-clockwise as seen (q1 grows from
  // "down" towards "right"). The arc's length grows as the square root of |M_m| / the torque
  // limit, from 0.08 turn at the smallest torque to 0.8 turn at the limit, so 2 N m
  // under a 50 N m limit still reads as an arrow; its value is written beside it.
  torqueArrow(cx, cy, torque, limit, scale) {
    if (!torque || !isFinite(torque)) return;
    const g = this.context;
    g.save();
    const full = isFinite(limit) && limit > 0 ? limit : 5;
    const fraction = Math.sqrt(Math.min(Math.abs(torque) / full, 1));
    const sweep = (0.1 + 0.9 * fraction) * 1.6 * Math.PI;
    const radius = Math.max(22, 0.12 * scale);
    const start = -Math.PI / 2;
    // The canvas's angles grow clockwise on the screen (its y points down).
    const counterClockwise = torque > 0;
    const end = counterClockwise ? start - sweep : start + sweep;
    g.strokeStyle = "#d1242f";
    g.lineWidth = 3;
    g.beginPath();
    g.arc(cx, cy, radius, start, end, counterClockwise);
    g.stroke();
    const tx = cx + radius * Math.cos(end), ty = cy + radius * Math.sin(end);
    const dir = counterClockwise ? end - Math.PI / 2 : end + Math.PI / 2;  // onwards along the arc
    g.fillStyle = "#d1242f";
    g.beginPath();
    g.moveTo(tx + 9 * Math.cos(dir), ty + 9 * Math.sin(dir));
    g.lineTo(tx + 6 * Math.cos(dir + 2.2), ty + 6 * Math.sin(dir + 2.2));
    g.lineTo(tx + 6 * Math.cos(dir - 2.2), ty + 6 * Math.sin(dir - 2.2));
    g.closePath();
    g.fill();
    g.font = "12px sans-serif";
    g.textAlign = "right";
    g.fillText(`M_m ${formatTorque(torque)} N m`, cx - radius - 6, cy - radius);
    g.restore();
  }
}

// A torque for the drawing's label: three significant digits, no exponent for everyday values.
function formatTorque(value) {
  const magnitude = Math.abs(value);
  return magnitude >= 1e4 || magnitude < 1e-2 ? value.toExponential(2) : String(Number(value.toPrecision(3)));
}
