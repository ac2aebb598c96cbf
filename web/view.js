// The canvas's world ↔ screen mapping (y up) and small SVG helpers.
//
// Everything is drawn in screen pixels, recomputed on each redraw: strokes,
// handles and labels then keep their size at any zoom without SVG transforms
// (a y-flipped transform would mirror the labels).

export const SVG_NS = 'http://www.w3.org/2000/svg';

export function el(tag, attrs = {}, parent = null) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) if (v !== undefined && v !== null) node.setAttribute(k, v);
  if (parent) parent.appendChild(node);
  return node;
}

export const pointsAttr = (pts) => pts.map(([x, y]) => `${x.toFixed(1)},${y.toFixed(1)}`).join(' ');

export class View {
  constructor(svg) {
    this.svg = svg;
    this.cx = 0; this.cy = 0; // world point at the canvas centre
    this.scale = 4; // pixels per length unit
    this.measure();
  }

  // The canvas size, read once per redraw: reading clientWidth after the
  // drawing has changed the DOM forces a layout, for every point drawn.
  measure() {
    this.width = this.svg.clientWidth || 800;
    this.height = this.svg.clientHeight || 600;
  }

  toScreen([x, y]) {
    return [this.width / 2 + (x - this.cx) * this.scale, this.height / 2 - (y - this.cy) * this.scale];
  }

  toWorld([sx, sy]) {
    return [this.cx + (sx - this.width / 2) / this.scale, this.cy - (sy - this.height / 2) / this.scale];
  }

  // The pointer's position in canvas pixels.
  eventPoint(event) {
    this.measure();
    const r = this.svg.getBoundingClientRect();
    return [event.clientX - r.left, event.clientY - r.top];
  }

  panBy(dx, dy) {
    this.cx -= dx / this.scale;
    this.cy += dy / this.scale;
  }

  // Zoom keeping the world point under the cursor fixed.
  zoomAt(screenPoint, factor) {
    const before = this.toWorld(screenPoint);
    this.scale = Math.min(1e7, Math.max(1e-6, this.scale * factor));
    const after = this.toWorld(screenPoint);
    this.cx += before[0] - after[0];
    this.cy += before[1] - after[1];
  }

  fit(points, margin = 0.12) {
    const finite = points.filter((p) => p && Number.isFinite(p[0]) && Number.isFinite(p[1]));
    if (!finite.length) return;
    const xs = finite.map((p) => p[0]);
    const ys = finite.map((p) => p[1]);
    const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
    this.cx = (x0 + x1) / 2;
    this.cy = (y0 + y1) / 2;
    const w = Math.max(x1 - x0, 1e-9);
    const h = Math.max(y1 - y0, 1e-9);
    const s = Math.min(this.width * (1 - 2 * margin) / w, this.height * (1 - 2 * margin) / h);
    this.scale = Number.isFinite(s) && s > 0 ? Math.min(s, 1e6) : this.scale;
  }

  // Decimals that resolve a pixel at this zoom (at least 3: a dragged value is
  // written as text, and its digits tell linkfit the data's precision).
  get decimals() {
    return Math.min(8, Math.max(3, Math.ceil(-Math.log10(1 / this.scale)) + 1));
  }

  drawGrid(layer) {
    layer.replaceChildren();
    const target = 40 / this.scale; // a grid line every ~40 px
    const pow = 10 ** Math.floor(Math.log10(target));
    const step = [1, 2, 5, 10].map((m) => m * pow).find((s) => s >= target);
    const [wx0, wy1] = this.toWorld([0, 0]);
    const [wx1, wy0] = this.toWorld([this.width, this.height]);
    let d = '';
    let major = '';
    for (let i = Math.ceil(wx0 / step); i * step <= wx1; i++) {
      const [sx] = this.toScreen([i * step, 0]);
      const seg = `M${sx.toFixed(1)},0V${this.height}`;
      if (i % 5 === 0) major += seg; else d += seg;
    }
    for (let i = Math.ceil(wy0 / step); i * step <= wy1; i++) {
      const [, sy] = this.toScreen([0, i * step]);
      const seg = `M0,${sy.toFixed(1)}H${this.width}`;
      if (i % 5 === 0) major += seg; else d += seg;
    }
    el('path', { d, class: 'grid-minor' }, layer);
    el('path', { d: major, class: 'grid-major' }, layer);
    const [ox, oy] = this.toScreen([0, 0]);
    el('path', { d: `M${ox.toFixed(1)},0V${this.height}M0,${oy.toFixed(1)}H${this.width}`, class: 'grid-axis' }, layer);
    const label = el('text', { x: this.width - 8, y: this.height - 8, class: 'grid-label', 'text-anchor': 'end' }, layer);
    label.textContent = `grid ${+step.toPrecision(3)}`;
  }
}
