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
// coupler, the coupler body's joints and the traced point / body frame. Each
// part names its side ("input", "output") for tests and tooltips.
function emptyFrame() {
  return { fixed: [], cranks: [], sliders: [], couplerLines: [], coupler: [], point: null, bodyAngle: null };
}

const isNum = Number.isFinite;

// A dyad of a planar motion result at pose T (theta: that pose's angle):
// `ok` false when its fields are not those of its type (then nothing of it is drawn).
export function dyadAt(d, T, theta) {
  const out = { type: d?.type, fixed: null, moving: null, line: null, ok: false };
  if (!d || typeof d !== 'object') return out;
  if (d.type === 'RR' && isPoint(d.fixed) && isPoint(d.moving)) {
    out.fixed = d.fixed; out.moving = T(d.moving); out.ok = true;
  } else if (d.type === 'PR' && isPoint(d.moving) && isPoint(d.line_point) && isNum(d.line_angle_deg)) {
    out.moving = T(d.moving); out.line = { p: d.line_point, a: d.line_angle_deg * DEG, on: 'ground' }; out.ok = true;
  } else if (d.type === 'RP' && isPoint(d.fixed) && isPoint(d.line_point) && isNum(d.line_angle_deg)) {
    out.fixed = d.fixed; out.line = { p: T(d.line_point), a: d.line_angle_deg * DEG + theta, on: 'coupler' }; out.ok = true;
  }
  return out;
}

// What a dyad is, for a message: "dyad 3 (PR)".
const dyadName = (i, d) => `dyad ${i + 1}${d?.type ? ` (${d.type})` : ''}`;

// A motion four-bar assembled at a task pose from its two dyads: exact for the
// poses the dyads were synthesized for, and independent of any analysis.
// What cannot be drawn is said in `problems`.
export function frameFromDyads(result, mechanism, pose, problems = []) {
  const T = poseMap(pose);
  const f = emptyFrame();
  const list = Array.isArray(mechanism?.dyads) ? mechanism.dyads : [];
  if (!list.length) problems.push('the mechanism names no dyads');
  list.forEach((i, n) => {
    const side = n === 0 ? 'input' : 'output';
    const d = Number.isInteger(i) ? result.dyads?.[i] : undefined;
    const at = dyadAt(d, T, pose.theta);
    if (!at.ok) { problems.push(`${dyadName(i, d)}: not a dyad linkfit draws`); return; }
    if (at.fixed) f.fixed.push({ p: at.fixed, side });
    if (at.fixed && at.moving) f.cranks.push({ from: at.fixed, to: at.moving, side });
    if (at.moving) f.coupler.push(at.moving);
    if (at.line?.on === 'ground') f.sliders.push({ line: at.line, at: at.moving, side });
    if (at.line?.on === 'coupler') f.couplerLines.push({ line: at.line, at: at.fixed, side });
  });
  f.point = [pose.x, pose.y];
  f.coupler.push(f.point);
  f.bodyAngle = pose.theta;
  return f;
}

// One side of a mechanism's `linkage.joints`: RR (pivot, pin), PR (pin on a
// ground line) or RP (pivot on a line carried by the coupler); null when its
// joints are missing or malformed.
function linkageSide(J, side) {
  const line = J[side + '_slider_line'];
  const pivot = J[side + '_pivot'];
  const pin = J[side + '_pin'];
  if (line === undefined) return isPoint(pivot) && isPoint(pin) ? { side, kind: 'RR', pivot, pin } : null;
  if (!line || typeof line !== 'object' || !isPoint(line.point) || !isNum(line.angle_deg)) return null;
  const l = { p: line.point, a: line.angle_deg * DEG };
  if ((line.on ?? 'ground') === 'ground') return isPoint(pin) ? { side, kind: 'PR', pin, line: l } : null;
  if (line.on === 'coupler') return isPoint(pivot) ? { side, kind: 'RP', pivot, line: l } : null;
  return null;
}

function linkageSides(mechanism) {
  const J = mechanism?.linkage?.joints;
  if (!J || typeof J !== 'object') return null;
  return ['input', 'output'].map((side) => linkageSide(J, side));
}

// The coupler's angle in the `linkage` configuration, measured as the analysis
// measures `links.coupler.angle_deg`: the line from the input pin to the
// output pin, or an RP's line carried by the coupler (the input's first).
function couplerReferenceAngle(sides) {
  const rp = sides.find((s) => s?.kind === 'RP');
  if (rp) return rp.line.a;
  const [a, b] = sides;
  if (a?.pin && b?.pin) return Math.atan2(b.pin[1] - a.pin[1], b.pin[0] - a.pin[0]);
  return null;
}

// The coupler at analysis step k, as a rigid motion of the `linkage`
// configuration: {C (a coupler point there to Σ now), delta (its turn)}, or
// null when the analysis does not give it. The coupler point's analysed
// position and the coupler's angle place it for every mechanism type; without
// a coupler point, a crank input's angle places its pin.
function couplerMotion(mechanism, analysis, k, sides = linkageSides(mechanism)) {
  if (!sides || k === null || k === undefined) return null;
  const J = mechanism.linkage.joints;
  const ref = couplerReferenceAngle(sides);
  const angle = analysis?.links?.coupler?.angle_deg?.[k];
  if (ref === null || !isNum(angle)) return null;
  const delta = angle * DEG - ref;
  const cp = analysis.coupler_point?.[k];
  if (isPoint(J.coupler_point) && isPoint(cp)) {
    return { C: (q) => add(cp, rotate(sub(q, J.coupler_point), delta)), delta };
  }
  const input = sides[0];
  const phi = analysis.links.input?.angle_deg?.[k];
  if (input?.kind === 'RR' && isNum(phi)) {
    const phi0 = Math.atan2(input.pin[1] - input.pivot[1], input.pin[0] - input.pivot[0]);
    const pin = add(input.pivot, rotate(sub(input.pin, input.pivot), phi * DEG - phi0));
    return { C: (q) => add(pin, rotate(sub(q, input.pin), delta)), delta };
  }
  return null;
}

// Whether an analysis can move this mechanism's linkage, step by step.
export function canAnimate(mechanism, analysis) {
  const sides = linkageSides(mechanism);
  return Boolean(sides && sides.every(Boolean) && analysis?.input_deg?.length &&
    couplerMotion(mechanism, analysis, 0, sides));
}

// The linkage at analysis step k (or as the result gives it, k = null): the
// coupler a rigid body moved as the analysis moves it, each side drawn by its
// type. What cannot be drawn is said in `problems`.
export function frameFromLinkage(mechanism, analysis, k, firstPoseTheta, problems = []) {
  const f = emptyFrame();
  const sides = linkageSides(mechanism);
  if (!sides) { problems.push('the mechanism has no linkage joints'); return f; }
  const motion = k === null ? null : couplerMotion(mechanism, analysis, k, sides);
  const C = motion ? motion.C : (q) => q;
  const delta = motion ? motion.delta : 0;
  sides.forEach((s, n) => {
    const side = n === 0 ? 'input' : 'output';
    if (!s) { problems.push(`its ${side} joints (not RR, PR or RP as linkfit writes them)`); return; }
    if (s.kind === 'RR') {
      const pin = C(s.pin);
      f.fixed.push({ p: s.pivot, side });
      f.cranks.push({ from: s.pivot, to: pin, side });
      f.coupler.push(pin);
    } else if (s.kind === 'PR') {
      const pin = C(s.pin);
      f.sliders.push({ line: s.line, at: pin, side });
      f.coupler.push(pin);
    } else {
      f.fixed.push({ p: s.pivot, side });
      f.couplerLines.push({ line: { p: C(s.line.p), a: s.line.a + delta }, at: s.pivot, side });
    }
  });
  const J = mechanism.linkage.joints;
  if (isPoint(J.coupler_point)) {
    f.point = C(J.coupler_point);
    f.coupler.push(f.point);
  }
  if (isNum(firstPoseTheta)) f.bodyAngle = firstPoseTheta + delta;
  return f;
}

// A long line through p at angle a, clipped by the SVG to the view.
// Centred on the foot of the view's centre: seen however far away p lies.
function drawLine(layer, view, p, a, cls, attrs = {}) {
  const reach = 2 * (view.width + view.height) / view.scale;
  const u = [Math.cos(a), Math.sin(a)];
  const t = (view.cx - p[0]) * u[0] + (view.cy - p[1]) * u[1];
  const foot = add(p, [u[0] * t, u[1] * t]);
  const d = [u[0] * reach, u[1] * reach];
  const [x1, y1] = view.toScreen(sub(foot, d));
  const [x2, y2] = view.toScreen(add(foot, d));
  return el('line', { x1, y1, x2, y2, class: cls, ...attrs }, layer);
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

function sliderBlock(layer, view, at, a, cls, attrs = {}) {
  const [x, y] = view.toScreen(at);
  const deg = -a / DEG;
  return el('rect', {
    x: x - 11, y: y - 6, width: 22, height: 12, rx: 2, class: cls, transform: `rotate(${deg.toFixed(2)} ${x} ${y})`,
    'data-x': String(at[0]), 'data-y': String(at[1]), 'data-angle': String(a), ...attrs,
  }, layer);
}

const lineAttrs = (line) => ({ 'data-x': String(line.p[0]), 'data-y': String(line.p[1]), 'data-angle': String(line.a) });

// Every dyad of a motion result at pose T, thin: its fixed pivot (tagged with
// the result's coordinates for tests), its crank and circle; a slider's (PR)
// ground line and its block at the moving pivot; an RP's fixed pivot, its
// block there and the line through it that the coupler carries. A dyad of an
// unknown shape is skipped and named in `problems`.
export function drawDyads(layer, view, result, pose, problems = []) {
  const T = poseMap(pose);
  const dyads = Array.isArray(result.dyads) ? result.dyads : [];
  dyads.forEach((d, i) => {
    const at = dyadAt(d, T, pose.theta);
    if (!at.ok) { problems.push(`${dyadName(i, d)}: not a dyad linkfit draws`); return; }
    const g = el('g', { class: 'dyad', 'data-testid': `dyad-${i}`, 'data-type': d.type }, layer);
    if (d.type === 'RR' && isNum(d.radius)) {
      const [cx, cy] = view.toScreen(at.fixed);
      const r = d.radius * view.scale;
      if (r < 1e5) el('circle', { cx, cy, r, class: 'dyad-circle' }, g);
    }
    if (at.line) drawLine(g, view, at.line.p, at.line.a, 'dyad-line');
    if (at.fixed && at.moving) segment(g, view, at.fixed, at.moving, 'dyad-link');
    if (d.type === 'PR') sliderBlock(g, view, at.moving, at.line.a, 'dyad-block', { 'data-testid': `dyad-block-${i}` });
    if (d.type === 'RP') sliderBlock(g, view, at.fixed, at.line.a, 'dyad-block', { 'data-testid': `dyad-block-${i}` });
    if (at.moving) {
      const [cx, cy] = view.toScreen(at.moving);
      el('circle', { cx, cy, r: 3.5, class: 'moving-pivot', 'data-testid': `moving-pivot-${i}` }, g);
    }
    if (at.fixed) {
      drawFixedPivot(g, view, at.fixed, {
        'data-testid': `fixed-pivot-${i}`, 'data-x': String(d.fixed[0]), 'data-y': String(d.fixed[1]),
      }, 4);
    }
  });
}

// The selected mechanism, bold. Its parts carry their world coordinates
// (data-x, data-y, data-angle in radians) and side for tests.
export function drawFrame(layer, view, f) {
  if (f.fixed.length === 2) segment(layer, view, f.fixed[0].p, f.fixed[1].p, 'mech-ground');
  for (const s of f.sliders) {
    drawLine(layer, view, s.line.p, s.line.a, 'mech-line', { 'data-testid': `mech-line-${s.side}`, ...lineAttrs(s.line) });
  }
  for (const c of f.couplerLines) {
    drawLine(layer, view, c.line.p, c.line.a, 'mech-line', { 'data-testid': `mech-line-${c.side}`, ...lineAttrs(c.line) });
  }
  const body = f.coupler.filter(isPoint);
  if (body.length >= 2) {
    el('polygon', { points: pointsAttr(body.map((p) => view.toScreen(p))), class: 'mech-coupler', 'data-testid': 'coupler-body' }, layer);
  }
  for (const c of f.cranks) {
    const line = segment(layer, view, c.from, c.to, 'mech-link');
    line.setAttribute('data-testid', `mech-crank-${c.side}`);
    line.setAttribute('data-from', `${c.from[0]},${c.from[1]}`);
    line.setAttribute('data-to', `${c.to[0]},${c.to[1]}`);
  }
  for (const s of f.sliders) sliderBlock(layer, view, s.at, s.line.a, 'mech-slider', { 'data-testid': `mech-slider-${s.side}` });
  for (const c of f.couplerLines) sliderBlock(layer, view, c.at, c.line.a, 'mech-slider', { 'data-testid': `mech-slider-${c.side}` });
  for (const F of f.fixed) drawFixedPivot(layer, view, F.p, { class: 'fixed-pivot', 'data-testid': `mech-pivot-${F.side}` }, 6);
  for (const c of f.cranks) {
    const [cx, cy] = view.toScreen(c.to);
    el('circle', { cx, cy, r: 4.5, class: 'mech-joint' }, layer);
  }
  for (const s of f.sliders) {
    const [cx, cy] = view.toScreen(s.at);
    el('circle', { cx, cy, r: 3.5, class: 'mech-joint' }, layer);
  }
  if (f.point) {
    const [cx, cy] = view.toScreen(f.point);
    if (f.bodyAngle !== null) {
      // The body frame E carried by the coupler: its x axis.
      const tip = [cx + 34 * Math.cos(f.bodyAngle), cy - 34 * Math.sin(f.bodyAngle)];
      el('line', { x1: cx, y1: cy, x2: tip[0], y2: tip[1], class: 'body-frame' }, layer);
    }
    el('circle', { cx, cy, r: 4, class: 'mech-joint', 'data-testid': 'coupler-point', 'data-x': String(f.point[0]), 'data-y': String(f.point[1]) }, layer);
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
