// Drawing the result: dyads, four-bars (from the dyads at a task pose, or from
// the mechanism's `linkage` moved through linkfit's own analysis), Burmester
// curves, coupler curves. All functions take world coordinates and draw in
// screen pixels through the view.

import { el, pointsAttr } from './view.js';

export const DEG = Math.PI / 180;

const rotate = ([x, y], a) => [x * Math.cos(a) - y * Math.sin(a), x * Math.sin(a) + y * Math.cos(a)];
const add = (p, q) => [p[0] + q[0], p[1] + q[1]];
const sub = (p, q) => [p[0] - q[0], p[1] - q[1]];
const isPoint = (p) => Array.isArray(p) && p.length >= 2 && Number.isFinite(p[0]) && Number.isFinite(p[1]);

// The body frame E at a planar pose: a point of E to Σ.
export function poseMap(pose) {
  return (q) => add(rotate(q, pose.theta), [pose.x, pose.y]);
}

// A mechanism at one instant, in a form every mechanism type draws from:
// cranks (fixed pivot to pin), sliders on ground lines, lines carried by the
// coupler, the coupler body's joints and the traced point / body frame.
function emptyFrame() {
  return { fixed: [], cranks: [], sliders: [], couplerLines: [], coupler: [], point: null, bodyAngle: null };
}

// A dyad of a planar motion result at pose T (theta: that pose's angle).
export function dyadAt(d, T, theta) {
  const out = { type: d.type, fixed: null, moving: null, line: null };
  if (d.type === 'RR') { out.fixed = d.fixed; out.moving = T(d.moving); }
  if (d.type === 'PR') { out.moving = T(d.moving); out.line = { p: d.line_point, a: d.line_angle_deg * DEG, on: 'ground' }; }
  if (d.type === 'RP') { out.fixed = d.fixed; out.line = { p: T(d.line_point), a: d.line_angle_deg * DEG + theta, on: 'coupler' }; }
  return out;
}

// A motion four-bar assembled at a task pose from its two dyads: exact for the
// poses the dyads were synthesized for, and independent of any analysis.
export function frameFromDyads(result, mechanism, pose) {
  const T = poseMap(pose);
  const f = emptyFrame();
  for (const i of mechanism.dyads || []) {
    const d = result.dyads?.[i];
    if (!d) continue;
    const at = dyadAt(d, T, pose.theta);
    if (at.fixed) f.fixed.push(at.fixed);
    if (at.fixed && at.moving) f.cranks.push([at.fixed, at.moving]);
    if (at.moving) f.coupler.push(at.moving);
    if (at.line?.on === 'ground') f.sliders.push({ line: at.line, at: at.moving });
    if (at.line?.on === 'coupler') f.couplerLines.push({ line: at.line, at: at.fixed });
  }
  f.point = [pose.x, pose.y];
  f.coupler.push(f.point);
  f.bodyAngle = pose.theta;
  return f;
}

// The coupler's angle in the `linkage` configuration, measured as the analysis
// measures `links.coupler.angle_deg` (the line from the input pin to the
// output pin; a slider line carried by the coupler otherwise).
function couplerReferenceAngle(J) {
  if (isPoint(J.output_pin)) return Math.atan2(J.output_pin[1] - J.input_pin[1], J.output_pin[0] - J.input_pin[0]);
  if (J.output_slider_line?.on === 'coupler') return J.output_slider_line.angle_deg * DEG;
  return null;
}

// Whether an analysis can move this mechanism's linkage (a crank input and a
// coupler angle per step).
export function canAnimate(mechanism, analysis) {
  const J = mechanism?.linkage?.joints;
  return Boolean(J && isPoint(J.input_pivot) && isPoint(J.input_pin) && couplerReferenceAngle(J) !== null &&
    analysis?.links?.input?.angle_deg && analysis?.links?.coupler?.angle_deg);
}

// The linkage at analysis step k (or as the result gives it, k = null): the
// crank turned to the analysed input angle, the coupler a rigid body turned by
// the analysed change of its angle about the crank pin.
export function frameFromLinkage(mechanism, analysis, k, firstPoseTheta) {
  const J = mechanism.linkage.joints;
  let pin = J.input_pin;
  let delta = 0;
  if (k !== null && canAnimate(mechanism, analysis)) {
    const phi0 = Math.atan2(J.input_pin[1] - J.input_pivot[1], J.input_pin[0] - J.input_pivot[0]);
    pin = add(J.input_pivot, rotate(sub(J.input_pin, J.input_pivot), analysis.links.input.angle_deg[k] * DEG - phi0));
    delta = analysis.links.coupler.angle_deg[k] * DEG - couplerReferenceAngle(J);
  }
  const C = (q) => add(pin, rotate(sub(q, J.input_pin), delta));
  const f = emptyFrame();
  f.fixed.push(J.input_pivot);
  f.cranks.push([J.input_pivot, pin]);
  f.coupler.push(pin);
  const line = J.output_slider_line;
  if (isPoint(J.output_pivot)) f.fixed.push(J.output_pivot);
  if (isPoint(J.output_pivot) && isPoint(J.output_pin)) f.cranks.push([J.output_pivot, C(J.output_pin)]);
  if (isPoint(J.output_pin)) f.coupler.push(C(J.output_pin));
  if (line?.on === 'ground') f.sliders.push({ line: { p: line.point, a: line.angle_deg * DEG }, at: C(J.output_pin) });
  if (line?.on === 'coupler') {
    f.couplerLines.push({ line: { p: C(line.point), a: line.angle_deg * DEG + delta }, at: J.output_pivot });
  }
  if (isPoint(J.coupler_point)) {
    f.point = C(J.coupler_point);
    f.coupler.push(f.point);
  }
  if (firstPoseTheta !== null && firstPoseTheta !== undefined) f.bodyAngle = firstPoseTheta + delta;
  return f;
}

// A long line through p at angle a, clipped by the SVG to the view.
function drawLine(layer, view, p, a, cls) {
  const reach = 2 * (view.width + view.height) / view.scale;
  const d = [Math.cos(a) * reach, Math.sin(a) * reach];
  const [x1, y1] = view.toScreen(sub(p, d));
  const [x2, y2] = view.toScreen(add(p, d));
  return el('line', { x1, y1, x2, y2, class: cls }, layer);
}

function segment(layer, view, p, q, cls) {
  const [x1, y1] = view.toScreen(p);
  const [x2, y2] = view.toScreen(q);
  return el('line', { x1, y1, x2, y2, class: cls }, layer);
}

// A ground pivot: a small hatched base under a ring.
export function drawFixedPivot(layer, view, p, attrs = {}, r = 5) {
  const [x, y] = view.toScreen(p);
  el('path', { d: `M${x},${y}l-${r + 3},${r + 7}h${2 * r + 6}z`, class: 'fixed-pivot-base' }, layer);
  return el('circle', { cx: x, cy: y, r, class: 'fixed-pivot', ...attrs }, layer);
}

function sliderBlock(layer, view, at, a, cls) {
  const [x, y] = view.toScreen(at);
  const deg = -a / DEG;
  el('rect', { x: x - 11, y: y - 6, width: 22, height: 12, rx: 2, class: cls, transform: `rotate(${deg.toFixed(2)} ${x} ${y})` }, layer);
}

// Every dyad of a motion result at pose T, thin: its fixed pivot (tagged with
// the result's coordinates for tests), its crank and circle, or its line.
export function drawDyads(layer, view, result, pose) {
  const T = poseMap(pose);
  (result.dyads || []).forEach((d, i) => {
    if (!['RR', 'PR', 'RP'].includes(d.type) || (d.fixed && d.fixed.length !== 2)) return;
    const at = dyadAt(d, T, pose.theta);
    if (at.fixed && d.type === 'RR' && Number.isFinite(d.radius)) {
      const [cx, cy] = view.toScreen(at.fixed);
      const r = d.radius * view.scale;
      if (r < 1e5) el('circle', { cx, cy, r, class: 'dyad-circle' }, layer);
    }
    if (at.line) drawLine(layer, view, at.line.p, at.line.a, 'dyad-line');
    if (at.fixed && at.moving) segment(layer, view, at.fixed, at.moving, 'dyad-link');
    if (at.moving) {
      const [cx, cy] = view.toScreen(at.moving);
      el('circle', { cx, cy, r: 3.5, class: 'moving-pivot', 'data-testid': `moving-pivot-${i}` }, layer);
    }
    if (at.fixed) {
      drawFixedPivot(layer, view, at.fixed, {
        'data-testid': `fixed-pivot-${i}`, 'data-x': String(d.fixed[0]), 'data-y': String(d.fixed[1]),
      }, 4);
    }
  });
}

// The selected mechanism, bold.
export function drawFrame(layer, view, f) {
  if (f.fixed.length === 2) segment(layer, view, f.fixed[0], f.fixed[1], 'mech-ground');
  for (const s of f.sliders) drawLine(layer, view, s.line.p, s.line.a, 'mech-line');
  for (const c of f.couplerLines) drawLine(layer, view, c.line.p, c.line.a, 'mech-line');
  const body = f.coupler.filter(isPoint);
  if (body.length >= 2) {
    el('polygon', { points: pointsAttr(body.map((p) => view.toScreen(p))), class: 'mech-coupler', 'data-testid': 'coupler-body' }, layer);
  }
  for (const [F, M] of f.cranks) segment(layer, view, F, M, 'mech-link');
  for (const s of f.sliders) sliderBlock(layer, view, s.at, s.line.a, 'mech-slider');
  for (const c of f.couplerLines) if (c.at) sliderBlock(layer, view, c.at, c.line.a, 'mech-slider');
  for (const F of f.fixed) drawFixedPivot(layer, view, F, { class: 'fixed-pivot' }, 6);
  for (const [, M] of f.cranks) {
    const [cx, cy] = view.toScreen(M);
    el('circle', { cx, cy, r: 4.5, class: 'mech-joint' }, layer);
  }
  if (f.point) {
    const [cx, cy] = view.toScreen(f.point);
    if (f.bodyAngle !== null) {
      // The body frame E carried by the coupler: its x axis.
      const tip = [cx + 34 * Math.cos(f.bodyAngle), cy - 34 * Math.sin(f.bodyAngle)];
      el('line', { x1: cx, y1: cy, x2: tip[0], y2: tip[1], class: 'body-frame' }, layer);
    }
    el('circle', { cx, cy, r: 4, class: 'mech-joint', 'data-testid': 'coupler-point' }, layer);
  }
}

export function drawPolyline(layer, view, pts, cls, attrs = {}) {
  const good = pts.filter(isPoint);
  if (good.length < 2) return null;
  return el('polyline', { points: pointsAttr(good.map((p) => view.toScreen(p))), class: cls, ...attrs }, layer);
}

// Nearest point of a set of polylines to p, and its distance.
export function nearestOnPolylines(polylines, p) {
  let best = null;
  let bestD = Infinity;
  for (const line of polylines) {
    for (let i = 0; i + 1 < line.length; i++) {
      const a = line[i];
      const b = line[i + 1];
      const ab = sub(b, a);
      const len2 = ab[0] * ab[0] + ab[1] * ab[1];
      const t = len2 > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2)) : 0;
      const q = [a[0] + t * ab[0], a[1] + t * ab[1]];
      const d = Math.hypot(q[0] - p[0], q[1] - p[1]);
      if (d < bestD) { bestD = d; best = q; }
    }
  }
  return { point: best, distance: bestD };
}
