// linkfit serve: the interactive linkage designer.
//
// The task is held as a JSON tree whose numbers keep the text they were typed
// or loaded with (rawjson.js): the server reads the data's precision from those
// digits. Every solve sends that text; results are kept as the server's text.
//
// Solving paths:
// - live (planar motion with 3–5 poses, a path of 5 timed points): every drag
//   event solves, throttled to one request per animation frame, at most one in
//   flight, the latest state winning;
// - staged (more data): fast, then balanced, then thorough, each shown as it
//   finishes, cancellable.

import { Num, num, numRounded, parse, stringify, toPlain } from './rawjson.js';
import * as api from './api.js';
import { View, el } from './view.js';
import {
  DEG, poseMap, frameFromDyads, frameFromLinkage, canAnimate, drawDyads, drawFrame,
  drawFixedPivot, drawPolyline, nearestOnPolylines,
} from './draw.js';

const $ = (id) => document.getElementById(id);
const svg = $('canvas');
const view = new View(svg);
const layers = {
  grid: $('layer-grid'), curves: $('layer-curves'), boxes: $('layer-boxes'),
  dyads: $('layer-dyads'), mechanism: $('layer-mechanism'), items: $('layer-items'),
};

const state = {
  task: null, // the task tree (numbers as Num)
  result: null, // the last result, parsed
  resultText: null, // ... as the server wrote it
  resultTaskText: null, // the task text that result was solved from
  selected: 0, // index in result.mechanisms
  analysis: null, // {result, index, data}: linkfit analyze of the selected mechanism
  frame: 0, // animation step
  playing: false,
  tool: 'select',
  selectedItem: null, // index of the selected pose / point
  selectedPivot: null, // index of the selected picked fixed pivot (Delete removes it)
  statusNote: '', // said in the status bar with the result (a refinement's before / after)
  dragPose: null, // pose being dragged: the four-bars are drawn at it
  version: null,
  solveCount: 0,
  stale: false, // the last solve failed: the result shown is of an earlier task
  errorRows: [], // table rows a server error names (highlighted)
  epoch: 0, // a new task, its result cleared or a result opened: replies to earlier requests are dropped
};

// What tests (and curious designers in the console) can read.
let resolveReady;
const linkfit = {
  state: {
    get task() { return state.task && toPlain(state.task); },
    get result() { return state.result; },
    get resultText() { return state.resultText; },
    get selected() { return state.selected; },
    get analysis() { return state.analysis?.data ?? null; },
    get stale() { return state.stale; },
  },
  lastLatencyMs: null,
  lastLatencyParts: null, // {wait, request, redraw, paint} of the last, in ms
  latencies: [], // the last 64 latencies, in ms
  allLatencies: [], // every one since the page loaded (bench/serve_page_latency.py)
  ready: new Promise((resolve) => { resolveReady = resolve; }),
  isReady: false,
  get frame() { return state.frame; },
  get playing() { return state.playing; },
  get solveCount() { return state.solveCount; },
  // A live solve queued or in flight: tests wait for it to settle.
  get busy() {
    return live.inFlight || live.dirty || live.rafPending || live.paintPending || drawLater.frames > 0 || staged !== null ||
      autoTimer !== null || panelTimer !== null;
  },
  lastExport: null,
  taskText: () => taskText(),
  openTask: (text) => openTaskText(text),
  openResultText: (text) => openResultText(text),
  taskTree: () => state.task, // numbers as their texts (Num)
  // Where a point of the fixed frame is drawn, in canvas pixels.
  toScreen: (x, y) => { view.measure(); return view.toScreen([x, y]); },
};
window.linkfit = linkfit;

/* ---------- the task ---------- */

const isPath = () => state.task?.problem === 'path';
const itemsKey = () => (isPath() ? 'points' : 'poses');
const angleKey = () => (isPath() ? 'input_deg' : 'theta_deg');
const items = () => (Array.isArray(state.task?.[itemsKey()]) ? state.task[itemsKey()] : []);
const val = (n) => (n instanceof Num ? n.value : typeof n === 'number' ? n : NaN);
const taskText = () => stringify(state.task) + '\n';

const isPlanarMotion = () => state.task && !isPath() && (state.task.problem ?? 'motion') === 'motion' &&
  (state.task.space ?? 'planar') === 'planar' && state.task.linkage !== 'six-bar' &&
  items().every((p) => 'x' in p && 'y' in p);
const isEditable = () => isPlanarMotion() || (isPath() && items().every((p) => 'x' in p && 'y' in p));
const isTimedPath = () => isPath() && items().length > 0 && items().every((p) => p.input_deg !== undefined);

// Tasks solved in about a millisecond: solved on every drag event.
function isLive() {
  const n = items().length;
  if (isPlanarMotion()) return n >= 3 && n <= 5;
  return isTimedPath() && n === 5;
}

function enoughData() {
  const n = items().length;
  if (isPlanarMotion()) return n >= 3;
  if (isPath()) return n >= 5;
  return true; // other kinds: let the server say
}

function poseAt(i) {
  const p = items()[i];
  if (!p) return null;
  const pose = { x: val(p.x), y: val(p.y), theta: (val(p.theta_deg ?? new Num('0')) || 0) * DEG };
  return Number.isFinite(pose.x) && Number.isFinite(pose.y) ? pose : null;
}

function setTask(tree, { fit = true } = {}) {
  if (!tree || typeof tree !== 'object' || Array.isArray(tree)) throw new Error('a task is a JSON object');
  if ('mechanisms' in tree && !('poses' in tree) && !('points' in tree)) {
    throw new Error('this is a result file: open it with "Open result…"');
  }
  newEpoch();
  state.task = tree;
  state.selectedItem = null;
  state.selectedPivot = null;
  state.result = null;
  state.resultText = null;
  state.analysis = null;
  state.stale = false;
  state.errorRows = [];
  stopPlaying();
  $('problem').value = isPath() ? 'path' : 'motion';
  const effort = tree.options?.effort;
  if (['fast', 'balanced', 'thorough'].includes(effort)) $('effort').value = effort;
  syncConstraintPanel();
  $('stages').replaceChildren();
  $('items-body').dataset.kind = ''; // a new task: the table is rebuilt
  $('elapsed').textContent = '';
  renderTable();
  renderMechList();
  renderStatus();
  updateRefine();
  if (fit) fitView();
  draw();
}

/* ---------- editing ---------- */

// Every change of the task goes through here.
function taskEdited({ source = 'canvas', eventTime = null, dragging = false } = {}) {
  if (source !== 'table') renderTable();
  if (source !== 'panel') syncBoxFields();
  // A live pointer edit is drawn with its solve's reply, which usually comes
  // before the next frame: the poses and their mechanisms appear together, and
  // the main thread is not busy painting an intermediate picture while the
  // reply waits. A late reply: the edit is drawn two frames on, without it.
  if (eventTime !== null && isLive() && enoughData()) requestDraw(2);
  else if (dragging) requestDraw(1); // drag events may come faster than frames
  else draw();
  updateHint();
  if (!enoughData()) {
    clearResult();
    return;
  }
  // Latency is reported for pointer events only (a typed value has no pointer event).
  if (isLive()) queueLiveSolve(eventTime ?? performance.now(), eventTime !== null);
  else if (!dragging) scheduleAutoSolve();
}

function clearResult() {
  newEpoch();
  state.stale = false;
  state.result = null;
  state.resultText = null;
  state.analysis = null;
  stopPlaying();
  renderMechList();
  renderStatus();
  updateRefine();
  draw();
}

const roundLength = (x) => numRounded(x, view.decimals);
const roundAngle = (a) => numRounded(a, 3);

function addItem(world) {
  const list = items();
  const last = list[list.length - 1];
  const item = { x: roundLength(world[0]), y: roundLength(world[1]) };
  if (!isPath()) {
    item.theta_deg = last?.theta_deg instanceof Num ? new Num(last.theta_deg.text) : new Num('0');
  } else if (list.length && isTimedPath()) {
    // Continue the crank's step between the last two points (30° at first).
    const a = val(last.input_deg);
    const step = list.length >= 2 ? a - val(list[list.length - 2].input_deg) : 30;
    item.input_deg = roundAngle(a + (Number.isFinite(step) ? step : 30));
  }
  state.task[itemsKey()] = [...list, item];
  state.selectedItem = list.length;
  taskEdited();
}

function deleteItem(i) {
  const list = items();
  if (i === null || i < 0 || i >= list.length) return;
  endItemDrag(); // Delete while dragging: the drag's index would name another pose, or none
  list.splice(i, 1);
  state.selectedItem = null;
  taskEdited();
}

// Fixed pivots are picked for three poses anywhere, for four on the
// center-point curve (the nearest point of it, within 30 px of the click).
// Each gives a dyad; two give a four-bar.
function addPivot(world) {
  const n = items().length;
  if (!isPlanarMotion() || n < 3 || n > 4) {
    showError('fixed pivots are picked for three or four poses (five poses give every dyad by themselves)', 'pivot');
    return;
  }
  let p = world;
  if (n === 4) {
    const curves = state.result?.burmester_curves?.center_points;
    if (!curves) { showError('no center-point curve yet: wait for the solve', 'pivot'); return; }
    const near = nearestOnPolylines(curves, world);
    if (!near.point || near.distance * view.scale > 30) {
      showError('click on or near the center-point curve (green): four poses allow fixed pivots only there', 'pivot');
      return;
    }
    p = near.point;
  }
  clearError('pivot');
  const list = Array.isArray(state.task.fixed_pivots) ? state.task.fixed_pivots : [];
  state.task.fixed_pivots = [...list, [roundLength(p[0]), roundLength(p[1])]];
  state.selectedPivot = state.task.fixed_pivots.length - 1;
  state.selectedItem = null;
  taskEdited();
}

// A picked pivot dragged: for four poses it slides along the center-point curve.
function movePivot(i, world) {
  let p = world;
  const curves = state.result?.burmester_curves?.center_points;
  if (items().length === 4 && curves) p = nearestOnPolylines(curves, world).point || world;
  state.task.fixed_pivots[i] = [roundLength(p[0]), roundLength(p[1])];
}

function deletePivot(i) {
  const list = state.task?.fixed_pivots;
  if (!Array.isArray(list) || i === null || i < 0 || i >= list.length) return;
  endItemDrag();
  list.splice(i, 1);
  if (!list.length) delete state.task.fixed_pivots;
  state.selectedPivot = null;
  taskEdited();
}

// Delete (key or button): the selected picked pivot, else the selected pose.
function deleteSelected() {
  if (state.selectedPivot !== null) deletePivot(state.selectedPivot);
  else deleteItem(state.selectedItem);
}

function clearPivots() {
  if (!state.task || !('fixed_pivots' in state.task || 'moving_pivots' in state.task)) return;
  delete state.task.fixed_pivots;
  delete state.task.moving_pivots;
  state.selectedPivot = null;
  clearError('pivot');
  taskEdited();
}

/* ---------- constraints ---------- */

const constraints = () => (state.task.constraints ||= {});

function pruneConstraints() {
  if (state.task.constraints && Object.keys(state.task.constraints).length === 0) delete state.task.constraints;
}

// A box [[xmin, ymin], [xmax, ymax]] as numbers, ordered.
function boxValues(box) {
  const [[a, b], [c, d]] = box.map((p) => p.map(val));
  return [Math.min(a, c), Math.min(b, d), Math.max(a, c), Math.max(b, d)];
}

// A new box spans the middle of the view (fixed) or E's origin at the task's
// scale (moving): on screen at once, to be dragged and resized from there.
function defaultBox(kind) {
  const L = state.result?.scale || 20;
  if (kind === 'moving_pivots_box') return [[-L, -L], [L, L]];
  view.measure();
  const a = view.toWorld([view.width * 0.2, view.height * 0.8]);
  const b = view.toWorld([view.width * 0.8, view.height * 0.2]);
  return [a, b];
}

function syncConstraintPanel() {
  const c = state.task?.constraints || {};
  const text = (v) => (v instanceof Num ? v.text : v === undefined ? '' : String(v));
  $('c-fixed-box').checked = Array.isArray(c.fixed_pivots_box);
  $('c-moving-box').checked = Array.isArray(c.moving_pivots_box);
  $('c-max-link').value = text(c.max_link_length);
  $('c-min-link').value = text(c.min_link_length);
  $('c-min-trans').value = text(c.min_transmission_angle_deg);
  $('c-grashof').value = c.grashof || '';
  $('c-input-full').checked = c.input_rotates_fully === true;
  for (const id of ['c-max-link', 'c-min-link', 'c-min-trans']) setFieldError($(id), null);
  syncBoxFields();
}

// The boxes' corners as number fields: [[xmin, ymin], [xmax, ymax]].
const BOX_KEYS = ['fixed_pivots_box', 'moving_pivots_box'];
const BOX_FIELDS = [['xmin', 0, 0], ['ymin', 0, 1], ['xmax', 1, 0], ['ymax', 1, 1]];
const BOX_NAMES = { fixed_pivots_box: 'fixed pivots box', moving_pivots_box: 'moving pivots box' };

// The fields show the task's texts, but for the one being typed in.
function syncBoxFields() {
  for (const key of BOX_KEYS) {
    const box = state.task?.constraints?.[key];
    const on = Array.isArray(box);
    $(`${key}-fields`).hidden = !on;
    for (const [name, a, b] of BOX_FIELDS) {
      const input = $(`c-${key}-${name}`);
      if (document.activeElement === input && on) continue;
      const v = on && Array.isArray(box[a]) ? box[a][b] : undefined;
      const text = v instanceof Num ? v.text : v === undefined || v === null ? '' : String(v);
      if (input.value !== text) input.value = text;
      if (invalidFields.has(input)) setFieldError(input, null);
    }
  }
}

let panelTimer = null; // a constraint typed: its solve waits for a pause in the typing

function bindConstraintPanel() {
  const boxToggle = (id, key) => $(id).addEventListener('change', (e) => {
    if (e.target.checked) {
      constraints()[key] = defaultBox(key).map((p) => p.map(roundLength));
    } else if (state.task.constraints) {
      delete state.task.constraints[key];
      pruneConstraints();
    }
    taskEdited();
  });
  boxToggle('c-fixed-box', 'fixed_pivots_box');
  boxToggle('c-moving-box', 'moving_pivots_box');
  const solveSoon = () => {
    clearTimeout(panelTimer);
    panelTimer = setTimeout(() => { panelTimer = null; taskEdited({ source: 'panel' }); }, 250); // once typing pauses
  };
  const numberField = (id, key) => $(id).addEventListener('input', (e) => {
    const text = e.target.value.trim();
    const problem = text ? numberProblem(text) : null;
    const label = e.target.closest('label')?.firstChild?.textContent.trim() ?? key;
    setFieldError(e.target, problem && `${label}: ${problem}`);
    if (problem) return;
    if (text) constraints()[key] = num(text);
    else if (state.task.constraints) delete state.task.constraints[key];
    pruneConstraints();
    solveSoon();
  });
  // A box corner typed: written as typed (its digits kept), drawn at once.
  for (const key of BOX_KEYS) {
    for (const [name, a, b] of BOX_FIELDS) {
      $(`c-${key}-${name}`).addEventListener('input', (e) => {
        const box = state.task.constraints?.[key];
        if (!Array.isArray(box) || !Array.isArray(box[a])) return;
        const text = e.target.value.trim();
        const problem = numberProblem(text);
        setFieldError(e.target, problem && `${BOX_NAMES[key]}, ${name}: ${problem}`);
        if (problem) return;
        box[a][b] = num(text);
        draw();
        solveSoon();
      });
    }
  }
  numberField('c-max-link', 'max_link_length');
  numberField('c-min-link', 'min_link_length');
  numberField('c-min-trans', 'min_transmission_angle_deg');
  $('c-grashof').addEventListener('change', (e) => {
    if (e.target.value) constraints().grashof = e.target.value;
    else if (state.task.constraints) delete state.task.constraints.grashof;
    pruneConstraints();
    taskEdited();
  });
  $('c-input-full').addEventListener('change', (e) => {
    if (e.target.checked) constraints().input_rotates_fully = true;
    else if (state.task.constraints) delete state.task.constraints.input_rotates_fully;
    pruneConstraints();
    taskEdited();
  });
}

// A box's frame: Σ for the fixed pivots, E at the first pose for the moving ones.
function boxFrame(key) {
  if (key !== 'moving_pivots_box') return { toWorld: (p) => p, toLocal: (p) => p };
  const pose = poseAt(0) || { x: 0, y: 0, theta: 0 };
  const T = poseMap(pose);
  const c = Math.cos(pose.theta);
  const s = Math.sin(pose.theta);
  return {
    toWorld: T,
    toLocal: ([x, y]) => {
      const dx = x - pose.x;
      const dy = y - pose.y;
      return [c * dx + s * dy, -s * dx + c * dy];
    },
  };
}

/* ---------- solving ---------- */

const live = {
  inFlight: false, dirty: false, since: null, pointer: false, rafPending: false, sentThisFrame: false,
  paintPending: false, // a latency waiting for the frame that paints its picture
};

// At most one request a frame and one in flight. The first change of a frame
// is sent at once (Chrome already delivers pointer moves once a frame, so
// waiting for the next frame would only add up to 16 ms of latency); later
// ones wait for the next frame or for the reply in flight, the latest winning.
function queueLiveSolve(eventTime, pointer) {
  live.since ??= eventTime; // the oldest change not yet on screen
  live.pointer ||= pointer;
  live.dirty = true;
  if (!live.inFlight && !live.sentThisFrame) pumpLive();
  else if (!live.rafPending) {
    live.rafPending = true;
    requestAnimationFrame(() => {
      live.rafPending = false;
      pumpLive();
    });
  }
}

const hasConstraints = () =>
  !!state.task?.constraints && Object.keys(state.task.constraints).length > 0;

function pumpLive() {
  if (live.inFlight || !live.dirty) return; // the reply in flight pumps again
  live.dirty = false;
  live.sentThisFrame = true;
  requestAnimationFrame(() => { live.sentThisFrame = false; });
  const since = live.since;
  const pointer = live.pointer;
  live.since = null;
  live.pointer = false;
  const text = taskText();
  cancelStaged();
  live.inFlight = true;
  // Constrained five poses: while a pose is dragged, the fast level (the exact four-bars and
  // those chosen on the Burmester curves of four poses: ~15 ms) keeps up with the pointer; the
  // bounded least-squares fit of all five (~100 ms) follows on release (endDrag).
  const effort = state.dragPose !== null && hasConstraints() ? 'fast' : undefined;
  live.lastText = effort ? null : text;
  const sent = performance.now();
  const epoch = state.epoch;
  api.solve(text, { effort })
    .then((resultText) => {
      if (epoch !== state.epoch) return; // for a task since replaced or cleared: dropped
      const received = performance.now();
      applyResult(resultText, text);
      const drawn = performance.now();
      clearError('solve');
      if (pointer) {
        // The picture is on screen with the next frame: its animation-frame
        // callback runs once the DOM changes above are committed to it.
        live.paintPending = true;
        requestAnimationFrame(() => {
          const painted = performance.now();
          live.paintPending = false;
          // Where the time went: waiting to send, the request, the redraw, the frame.
          linkfit.lastLatencyParts = {
            wait: sent - since, request: received - sent, redraw: drawn - received, paint: painted - drawn,
          };
          reportLatency(painted - since);
        });
      }
    })
    .catch((err) => { if (epoch === state.epoch) solveFailed(err.message); })
    .finally(() => {
      live.inFlight = false;
      if (live.dirty) pumpLive();
    });
}

function reportLatency(ms) {
  linkfit.lastLatencyMs = ms;
  linkfit.latencies.push(ms);
  if (linkfit.allLatencies.length < 100000) linkfit.allLatencies.push(ms);
  if (linkfit.latencies.length > 64) linkfit.latencies.shift();
  const box = $('live');
  box.textContent = `live: ${ms.toFixed(1)} ms (pointer event → painted picture)`;
  box.classList.toggle('slow', ms > 30);
}

let autoTimer = null;
function scheduleAutoSolve() {
  clearTimeout(autoTimer);
  autoTimer = setTimeout(() => { autoTimer = null; runStaged(['fast']); }, 300);
}

let staged = null; // {controller, timer}

function cancelStaged() {
  if (staged) staged.controller.abort();
}

// A new task, its result cleared, or a result file opened: every request on its way is for
// what was there before. The long ones are cancelled, nothing queued is sent, and each reply
// still to come is dropped (every request keeps the epoch it was sent in).
function newEpoch() {
  state.epoch++;
  cancelStaged();
  clearTimeout(autoTimer);
  autoTimer = null;
  live.dirty = false;
  live.since = null;
  live.pointer = false;
}

// A reply to a request of an earlier epoch: treated as cancelled.
const superseded = () => Object.assign(new Error('superseded'), { name: 'AbortError' });

// Fast first, its list shown at once, then the finer levels up to the chosen
// one; each stage is marked with its time as it finishes.
async function runStaged(levels) {
  if (!enoughData()) { updateHint(); return; }
  cancelStaged();
  const controller = new AbortController();
  const me = { controller, timer: null };
  staged = me;
  const list = $('stages');
  list.replaceChildren();
  const rows = levels.map((level) => {
    const li = document.createElement('li');
    li.dataset.testid = `stage-${level}`;
    li.setAttribute('data-testid', `stage-${level}`);
    li.textContent = `${level}: waiting`;
    list.appendChild(li);
    return li;
  });
  const start = performance.now();
  let cancelled = false;
  me.timer = setInterval(() => {
    $('elapsed').textContent = `elapsed ${((performance.now() - start) / 1000).toFixed(1)} s`;
  }, 100);
  $('cancel').disabled = false;
  $('solve').disabled = true;
  updateRefine();
  const text = taskText();
  const epoch = state.epoch;
  try {
    for (const [i, level] of levels.entries()) {
      const li = rows[i];
      li.className = 'running';
      li.textContent = `${level}: solving…`;
      const t0 = performance.now();
      try {
        const resultText = await api.solve(text, { effort: level, signal: controller.signal });
        if (epoch !== state.epoch || controller.signal.aborted) throw superseded();
        applyResult(resultText, text);
        clearError('solve');
        const r = state.result;
        li.className = 'done';
        li.textContent = `${level}: done in ${(performance.now() - t0).toFixed(0)} ms` +
          ` (solve ${fmtMs(r.solve_time_ms)}), ${r.mechanisms?.length ?? 0} mechanisms` +
          (r.mechanisms?.[0] ? `, best fit ${fmtFit(r.mechanisms[0])}` : '');
      } catch (err) {
        if (err.name === 'AbortError' || epoch !== state.epoch) {
          cancelled = true;
          li.className = 'cancelled';
          li.textContent = `${level}: cancelled after ${(performance.now() - t0).toFixed(0)} ms`;
        } else {
          li.className = 'failed';
          li.textContent = `${level}: failed`;
          solveFailed(err.message);
        }
        for (const rest of rows.slice(i + 1)) { rest.className = 'cancelled'; rest.textContent = `${rest.dataset.testid.slice(6)}: not run`; }
        break;
      }
    }
  } finally {
    clearInterval(me.timer);
    const seconds = ((performance.now() - start) / 1000).toFixed(2);
    // (Not over a new task's empty list.)
    if (rows[0]?.isConnected) $('elapsed').textContent = cancelled ? `cancelled after ${seconds} s` : `total ${seconds} s`;
    endLong(me);
  }
}

// A staged solve or a refinement ended: the buttons back, unless another one
// has started meanwhile.
function endLong(me) {
  if (staged !== me) return;
  staged = null;
  $('cancel').disabled = true;
  $('solve').disabled = false;
  updateRefine();
}

// Refinement (linkfit refine) of the selected mechanism of a result that is
// not exact: a least-squares fit, a path, a six-bar.
const canRefine = () => Boolean(state.result?.mechanisms?.[state.selected]) && !isLive() && staged === null;

function updateRefine() {
  $('refine').disabled = !canRefine();
}

async function runRefine() {
  if (!canRefine()) return;
  const index = state.selected;
  const before = state.result.mechanisms[index];
  const designText = state.resultText;
  const text = taskText();
  const epoch = state.epoch;
  const controller = new AbortController();
  const me = { controller, timer: null };
  staged = me;
  const li = document.createElement('li');
  li.setAttribute('data-testid', 'stage-refine');
  li.className = 'running';
  li.textContent = `refine mechanism ${index + 1}: running…`;
  $('stages').replaceChildren(li);
  $('cancel').disabled = false;
  $('solve').disabled = true;
  updateRefine();
  const start = performance.now();
  me.timer = setInterval(() => {
    $('elapsed').textContent = `elapsed ${((performance.now() - start) / 1000).toFixed(1)} s`;
  }, 100);
  try {
    const resultText = await api.refine(text, designText, index, controller.signal);
    if (epoch !== state.epoch || controller.signal.aborted) throw superseded();
    const after = JSON.parse(resultText).mechanisms?.[0];
    const key = fitKey(before) || fitKey(after) || 'fit';
    const note = `refined mechanism ${index + 1}: ${key.replace(/_/g, ' ')} ${fmtNum(before?.[key])} → ${fmtNum(after?.[key])}`;
    state.selected = 0;
    applyResult(resultText, text, { note });
    clearError('solve');
    li.className = 'done';
    li.textContent = `${note} (${(performance.now() - start).toFixed(0)} ms)`;
  } catch (err) {
    const aborted = err.name === 'AbortError' || epoch !== state.epoch;
    li.className = aborted ? 'cancelled' : 'failed';
    li.textContent = `refine mechanism ${index + 1}: ${aborted ? 'cancelled' : 'failed'}`;
    if (!aborted) showError(`refine: ${err.message}`, 'solve');
  } finally {
    clearInterval(me.timer);
    const seconds = ((performance.now() - start) / 1000).toFixed(2);
    if (li.isConnected) $('elapsed').textContent = li.className === 'cancelled' ? `cancelled after ${seconds} s` : `total ${seconds} s`;
    endLong(me);
  }
}

function solveButton() {
  const all = ['fast', 'balanced', 'thorough'];
  runStaged(all.slice(0, all.indexOf($('effort').value) + 1));
}

function applyResult(resultText, sentTaskText, { note = '' } = {}) {
  const result = JSON.parse(resultText);
  state.statusNote = note;
  const previous = state.result;
  state.result = result;
  state.resultText = resultText;
  state.resultTaskText = sentTaskText;
  state.solveCount++;
  state.stale = false;
  markRows([]);
  const n = result.mechanisms?.length ?? 0;
  if (state.selected >= n) state.selected = 0;
  state.analysis = null;
  if (!previous) fitViewOnce();
  renderMechList();
  renderStatus();
  updateRefine();
  draw();
  if (state.dragPose === null) scheduleAnalysis();
  if (!linkfit.isReady) {
    linkfit.isReady = true;
    resolveReady(true);
  }
}

/* ---------- analysis and animation ---------- */

let analysisTimer = null;
let analysisController = null;

function scheduleAnalysis() {
  clearTimeout(analysisTimer);
  analysisTimer = setTimeout(fetchAnalysis, 80);
}

// The selected mechanism's analysis. One on its way for it (the one scheduled after a solve,
// when Play is pressed or a mechanism selected meanwhile) is waited for, not restarted: a
// restart would abort it, and its caller would take the mechanism for one without analysis.
let analysisPending = null; // {result, index, epoch, promise}

function fetchAnalysis() {
  const p = analysisPending;
  if (p && p.result === state.result && p.index === state.selected && p.epoch === state.epoch) return p.promise;
  const me = { result: state.result, index: state.selected, epoch: state.epoch };
  analysisPending = me;
  me.promise = loadAnalysis().finally(() => { if (analysisPending === me) analysisPending = null; });
  return me.promise;
}

async function loadAnalysis() {
  const result = state.result;
  const index = state.selected;
  const m = result?.mechanisms?.[index];
  if (!m?.linkage || result.space === 'spatial') return null;
  analysisController?.abort();
  analysisController = new AbortController();
  const epoch = state.epoch;
  try {
    const signal = analysisController.signal;
    // Its whole cycle: a crank's turn, a rocker's swing between its dead points (the task
    // gives the analysis its task range too, task_range_deg).
    const text = await api.analyze(state.resultText, state.resultTaskText, index,
      { steps: 180, range: 'whole' }, signal);
    if (state.result !== result || state.selected !== index || state.epoch !== epoch) return null; // superseded
    const data = JSON.parse(text);
    state.analysis = { result, index, data };
    const steps = data.input_deg?.length ?? 0;
    $('scrub').max = Math.max(0, steps - 1);
    state.frame = Math.min(state.frame, Math.max(0, steps - 1));
    if (!state.playing) state.frame = 0;
    $('scrub').value = state.frame;
    drawMechanism();
    return state.analysis;
  } catch (err) {
    if (err.name !== 'AbortError') showError(`analysis: ${err.message}`, 'analysis');
    return null;
  }
}

function currentAnalysis() {
  const a = state.analysis;
  return a && a.result === state.result && a.index === state.selected ? a.data : null;
}

let lastTick = 0;
let direction = 1;
let playFrame = null; // the Play loop's pending animation frame: one loop at most

async function togglePlay() {
  if (state.playing) { stopPlaying(); return; }
  if (!currentAnalysis() && !(await fetchAnalysis()) && !currentAnalysis()) {
    showError('this mechanism cannot be animated (no analysis)', 'analysis');
    return;
  }
  startPlaying();
}

function startPlaying() {
  if (!currentAnalysis()) return;
  if (!state.playing) {
    state.playing = true;
    $('play').textContent = '❚❚ Pause';
    $('play').classList.add('active');
    lastTick = performance.now();
  }
  if (playFrame === null) playFrame = requestAnimationFrame(tick);
}

function stopPlaying() {
  state.playing = false;
  resumePlay = false;
  if (playFrame !== null) cancelAnimationFrame(playFrame);
  playFrame = null;
  $('play').textContent = '▶ Play';
  $('play').classList.remove('active');
}

// About 60 analysis steps a second; a rocking input swings back and forth.
function tick(now) {
  playFrame = null;
  if (!state.playing) return;
  const a = currentAnalysis();
  if (!a) { stopPlaying(); return; }
  const n = a.input_deg.length;
  const advance = Math.floor((now - lastTick) / (1000 / 60));
  if (advance > 0 && n > 1) {
    lastTick += advance * (1000 / 60);
    for (let i = 0; i < advance; i++) {
      if (a.input_rotates_fully) state.frame = (state.frame + 1) % n;
      else {
        if (state.frame + direction < 0 || state.frame + direction >= n) direction = -direction;
        state.frame += direction;
      }
    }
    $('scrub').value = state.frame;
    drawMechanism();
  }
  playFrame = requestAnimationFrame(tick);
}

/* ---------- drawing ---------- */

// A redraw `frames` animation frames on (the sooner request wins); any draw()
// meanwhile makes it moot.
const drawLater = { frames: 0, scheduled: false };

function requestDraw(frames = 1) {
  drawLater.frames = drawLater.frames ? Math.min(drawLater.frames, frames) : frames;
  if (!drawLater.scheduled) {
    drawLater.scheduled = true;
    requestAnimationFrame(drawTick);
  }
}

function drawTick() {
  drawLater.scheduled = false;
  if (!drawLater.frames) return;
  if (--drawLater.frames) {
    drawLater.scheduled = true;
    requestAnimationFrame(drawTick);
    return;
  }
  draw();
}

// Each part of the picture is drawn on its own: one that cannot be drawn (a
// result of an unexpected shape) is said in the status bar, and the rest, and
// every later redraw (zoom, pan, drag), still happen.
const drawProblems = { picture: [], mechanism: [] };

function reportDrawProblems() {
  const all = [...new Set([...drawProblems.picture, ...drawProblems.mechanism])];
  const box = $('st-draw');
  box.textContent = all.length ? `not drawn: ${all.join('; ')}` : '';
  box.title = all.join('\n');
}

function draw() {
  drawLater.frames = 0;
  view.measure();
  const problems = [];
  for (const [what, part] of [['grid', () => view.drawGrid(layers.grid)], ['Burmester curves', drawCurves],
    ['constraint boxes', drawBoxes], ['poses', drawItems]]) {
    try { part(); } catch (err) { problems.push(`${what} (${err.message})`); }
  }
  drawProblems.picture = problems;
  drawMechanism();
}

function drawCurves() {
  layers.curves.replaceChildren();
  const curves = state.result?.burmester_curves;
  if (!curves || !isPlanarMotion()) return;
  for (const line of curves.center_points || []) drawPolyline(layers.curves, view, line, 'curve-center', { 'data-testid': 'center-point-curve' });
  const first = poseAt(0);
  if (first) {
    // Circle points are in E: shown where they are at the first pose.
    const T = poseMap(first);
    for (const line of curves.circle_points || []) drawPolyline(layers.curves, view, line.map(T), 'curve-circle', { 'data-testid': 'circle-point-curve' });
  }
}

function drawBoxes() {
  layers.boxes.replaceChildren();
  const c = state.task?.constraints;
  if (!c || !isEditable()) return;
  for (const key of ['fixed_pivots_box', 'moving_pivots_box']) {
    if (!Array.isArray(c[key])) continue;
    const b = boxValues(c[key]);
    if (!b.every(Number.isFinite)) continue;
    const F = boxFrame(key);
    const corners = [[b[0], b[1]], [b[2], b[1]], [b[2], b[3]], [b[0], b[3]]].map((p) => view.toScreen(F.toWorld(p)));
    el('polygon', { points: corners.map((p) => p.join(',')).join(' '), class: 'box', 'data-drag': 'box-move', 'data-box': key, 'data-testid': key }, layers.boxes);
    const label = el('text', { x: corners[3][0] + 4, y: corners[3][1] - 4, class: 'box-label' }, layers.boxes);
    label.textContent = key === 'fixed_pivots_box' ? 'fixed pivots' : 'moving pivots (E at pose 1)';
    // Corner k: bit 0 → the x edge is the max one, bit 1 → the y edge.
    [[0, 0], [1, 0], [1, 1], [0, 1]].forEach(([ix, iy], k) => {
      el('rect', {
        x: corners[k][0] - 5, y: corners[k][1] - 5, width: 10, height: 10, class: 'box-handle',
        'data-drag': 'box-corner', 'data-box': key, 'data-cx': ix, 'data-cy': iy, 'data-testid': `${key}-corner-${k}`,
      }, layers.boxes);
    });
  }
}

// The dyads and the selected mechanism (drawn alone on each animation step).
function drawMechanism() {
  const problems = [];
  try {
    drawMechanismParts(problems);
  } catch (err) {
    problems.push(`mechanism ${state.selected + 1} (${err.message})`);
  }
  drawProblems.mechanism = problems;
  reportDrawProblems();
}

function drawMechanismParts(problems) {
  layers.dyads.replaceChildren();
  layers.mechanism.replaceChildren();
  // A failed solve leaves the last result drawn, greyed: out of date.
  for (const layer of [layers.curves, layers.dyads, layers.mechanism]) layer.classList.toggle('stale', state.stale);
  const r = state.result;
  if (!r || r.space === 'spatial' || !isEditable()) { $('anim-angle').textContent = ''; return; }
  const motion = r.problem !== 'path' && Array.isArray(r.dyads);
  const poseIndex = state.dragPose ?? 0;
  const pose = motion ? poseAt(poseIndex) : null;
  if (motion && pose) drawDyads(layers.dyads, view, r, pose, problems);
  const m = Array.isArray(r.mechanisms) ? r.mechanisms[state.selected] : null;
  if (!m || typeof m !== 'object') { $('anim-angle').textContent = ''; return; }
  const a = currentAnalysis();
  const firstTheta = motion ? poseAt(0)?.theta ?? null : null;
  const hasDyads = Array.isArray(m.dyads);
  let frame = null;
  let angleText = '';
  if (state.dragPose !== null && motion && pose && hasDyads) {
    frame = frameFromDyads(r, m, pose, problems); // live: exactly at the pose being dragged
  } else if (m.linkage && a && canAnimate(m, a)) {
    drawPolyline(layers.mechanism, view, a.coupler_point || [], 'coupler-curve', { 'data-testid': 'coupler-curve' });
    const k = Math.min(state.frame, a.input_deg.length - 1);
    frame = frameFromLinkage(m, a, k, firstTheta, problems);
    const value = Number(a.input_deg[k]);
    angleText = (a.input === 'slider' || Array.isArray(a.input_position)
      ? `slider at ${value.toFixed(2)}` : `input ${value.toFixed(1)}°`) + `, step ${k + 1}/${a.input_deg.length}`;
  } else if (m.linkage) {
    frame = frameFromLinkage(m, null, null, firstTheta, problems);
  } else if (motion && pose && hasDyads) {
    frame = frameFromDyads(r, m, pose, problems);
  } else {
    problems.push(`mechanism ${state.selected + 1} (${m.type ?? 'no type'}): no linkage or dyads to draw`);
  }
  $('anim-angle').textContent = angleText;
  if (frame) drawFrame(layers.mechanism, view, frame);
}

function drawItems() {
  const layer = layers.items;
  layer.replaceChildren();
  if (!state.task || !isEditable()) return;
  // Picked fixed pivots (three or four poses).
  (state.task.fixed_pivots || []).forEach((p, i) => {
    const w = [val(p[0]), val(p[1])];
    if (!w.every(Number.isFinite)) return;
    const [x, y] = view.toScreen(w);
    el('path', {
      d: `M${x},${y - 8}l8,8l-8,8l-8,-8z`, class: 'picked-pivot' + (state.selectedPivot === i ? ' selected' : ''),
      'data-drag': 'pivot', 'data-index': i, 'data-testid': `picked-pivot-${i}`,
    }, layer);
  });
  const first = poseAt(0);
  (state.task.moving_pivots || []).forEach((p, i) => {
    const w = [val(p[0]), val(p[1])];
    if (!first || !w.every(Number.isFinite)) return;
    const [x, y] = view.toScreen(poseMap(first)(w));
    el('rect', { x: x - 5, y: y - 5, width: 10, height: 10, class: 'picked-pivot', 'data-testid': `given-moving-pivot-${i}` }, layer);
  });
  items().forEach((item, i) => {
    const wx = val(item.x);
    const wy = val(item.y);
    if (!Number.isFinite(wx) || !Number.isFinite(wy)) return;
    const [x, y] = view.toScreen([wx, wy]);
    const g = el('g', { class: 'pose' + (state.selectedItem === i ? ' selected' : '') }, layer);
    if (!isPath()) {
      const t = (val(item.theta_deg) || 0) * DEG;
      const tip = [x + 48 * Math.cos(t), y - 48 * Math.sin(t)];
      const yTip = [x - 24 * Math.sin(t), y - 24 * Math.cos(t)];
      el('line', { x1: x, y1: y, x2: yTip[0], y2: yTip[1], class: 'pose-axis-y' }, g);
      el('line', { x1: x, y1: y, x2: tip[0], y2: tip[1], class: 'pose-axis' }, g);
      el('path', { d: arrowHead(tip, t), class: 'pose-axis' }, g);
      el('circle', { cx: tip[0], cy: tip[1], r: 6, class: 'pose-angle', 'data-drag': 'pose-angle', 'data-index': i, 'data-testid': `pose-${i}-angle` }, g);
      el('circle', { cx: x, cy: y, r: 7, class: 'pose-origin', 'data-drag': 'pose-origin', 'data-index': i, 'data-testid': `pose-${i}-origin` }, g);
    } else {
      el('circle', { cx: x, cy: y, r: 6, class: 'point', 'data-drag': 'point', 'data-index': i, 'data-testid': `point-${i}` }, g);
    }
    const label = el('text', { x: x - 14, y: y + 18, class: 'pose-label' }, g);
    label.textContent = String(i + 1);
  });
}

function arrowHead([x, y], t) {
  const back = (a) => [x - 9 * Math.cos(t + a), y + 9 * Math.sin(t + a)];
  const [l, r] = [back(0.4), back(-0.4)];
  return `M${l[0]},${l[1]}L${x},${y}L${r[0]},${r[1]}`;
}

let fittedOnce = false;
function fitViewOnce() {
  if (!fittedOnce) { fittedOnce = true; fitView(); }
}

function fitView() {
  view.measure();
  const pts = items().map((p) => [val(p.x), val(p.y)]);
  const m = state.result?.mechanisms?.[state.selected];
  const J = m?.linkage?.joints;
  if (J) for (const v of Object.values(J)) if (Array.isArray(v)) pts.push(v);
  for (const p of state.task?.fixed_pivots || []) pts.push(p.map(val));
  // The selected mechanism's coupler curve too, once analysed: its whole motion in view.
  for (const p of currentAnalysis()?.coupler_point || []) if (Array.isArray(p)) pts.push(p);
  if (pts.length) view.fit(pts);
  draw();
}

/* ---------- pointer interaction ---------- */

let drag = null;
const ITEM_DRAGS = ['pose-origin', 'pose-angle', 'point'];

// A drag of a pose, point or picked pivot ends when what it holds is deleted (Delete pressed
// while dragging): its index would name another one, or none.
function endItemDrag() {
  if (!drag || !(ITEM_DRAGS.includes(drag.kind) || drag.kind === 'pivot')) return;
  const id = drag.pointerId;
  drag = null;
  state.dragPose = null;
  if (id !== undefined && svg.hasPointerCapture(id)) svg.releasePointerCapture(id);
}

function eventTime(e) {
  // The event's own timestamp (same clock as performance.now()) includes the
  // time it waited in the input queue: the honest start of the latency.
  const now = performance.now();
  return e.timeStamp > 0 && e.timeStamp <= now ? e.timeStamp : now;
}

svg.addEventListener('pointerdown', (e) => {
  svg.focus({ preventScroll: true });
  const p = view.eventPoint(e);
  let target = e.target.closest('[data-drag]');
  if (state.tool === 'pivot' && target?.dataset.drag === 'box-move') target = null; // a click in a box picks
  if (e.button === 1 || (e.button === 0 && !target)) {
    drag = { kind: 'pan', last: p, start: p, moved: false, button: e.button };
  } else if (e.button === 0) {
    const kind = target.dataset.drag;
    const index = Number(target.dataset.index);
    drag = { kind, index, start: p, world: view.toWorld(p), moved: false };
    if (kind === 'pose-origin' || kind === 'point') {
      const it = items()[index];
      drag.offset = [val(it.x) - drag.world[0], val(it.y) - drag.world[1]];
      state.selectedItem = index;
      renderTable();
    }
    if (kind === 'pose-angle') { state.selectedItem = index; renderTable(); }
    if (kind === 'pivot') { state.selectedPivot = index; state.selectedItem = null; renderTable(); }
    else state.selectedPivot = null;
    if (kind.startsWith('box')) {
      drag.box = target.dataset.box;
      drag.corner = [Number(target.dataset.cx), Number(target.dataset.cy)];
      drag.orig = boxValues(state.task.constraints[drag.box]);
      drag.localStart = boxFrame(drag.box).toLocal(drag.world);
    }
  } else return;
  drag.pointerId = e.pointerId;
  svg.setPointerCapture(e.pointerId);
  e.preventDefault();
});

// Chrome delivers pointermove once a frame, at its start: up to a frame after
// the pointer moved. pointerrawupdate comes as the move arrives, so a live
// solve is on its way (and often back) before that frame begins.
const MOVE_EVENT = 'onpointerrawupdate' in window ? 'pointerrawupdate' : 'pointermove';

svg.addEventListener(MOVE_EVENT, (e) => {
  if (!drag) return;
  const t = eventTime(e);
  const p = view.eventPoint(e);
  if (Math.hypot(p[0] - drag.start[0], p[1] - drag.start[1]) > 3) drag.moved = true;
  if (drag.kind === 'pan') {
    if (!drag.moved) return;
    svg.classList.add('panning');
    view.panBy(p[0] - drag.last[0], p[1] - drag.last[1]);
    drag.last = p;
    requestDraw(1);
    return;
  }
  if (!drag.moved) return;
  const w = view.toWorld(p);
  const it = items()[drag.index];
  // What the drag holds is gone (deleted while dragged): the drag ends.
  if (drag.kind === 'pivot' ? !state.task.fixed_pivots?.[drag.index] : ITEM_DRAGS.includes(drag.kind) && !it) {
    endItemDrag();
    return;
  }
  switch (drag.kind) {
    case 'pose-origin':
    case 'point':
      it.x = roundLength(w[0] + drag.offset[0]);
      it.y = roundLength(w[1] + drag.offset[1]);
      if (drag.kind === 'pose-origin') state.dragPose = drag.index;
      break;
    case 'pose-angle': {
      const a = Math.atan2(w[1] - val(it.y), w[0] - val(it.x)) / DEG;
      // Keep the angle near the typed one (no jump from 179° to -179°).
      const old = val(it.theta_deg) || 0;
      it.theta_deg = roundAngle(a + 360 * Math.round((old - a) / 360));
      state.dragPose = drag.index;
      break;
    }
    case 'pivot':
      movePivot(drag.index, w);
      break;
    case 'box-move':
    case 'box-corner': {
      const F = boxFrame(drag.box);
      const l = F.toLocal(w);
      const [dx, dy] = [l[0] - drag.localStart[0], l[1] - drag.localStart[1]];
      let [x0, y0, x1, y1] = drag.orig;
      if (drag.kind === 'box-move') { x0 += dx; x1 += dx; y0 += dy; y1 += dy; } else {
        if (drag.corner[0]) x1 += dx; else x0 += dx;
        if (drag.corner[1]) y1 += dy; else y0 += dy;
      }
      state.task.constraints[drag.box] = [[roundLength(Math.min(x0, x1)), roundLength(Math.min(y0, y1))],
        [roundLength(Math.max(x0, x1)), roundLength(Math.max(y0, y1))]];
      break;
    }
    default:
      return;
  }
  taskEdited({ eventTime: t, dragging: true });
});

function endDrag(e) {
  if (!drag) return;
  const d = drag;
  drag = null;
  svg.classList.remove('panning');
  if (svg.hasPointerCapture(e.pointerId)) svg.releasePointerCapture(e.pointerId);
  if (d.kind === 'pan') {
    if (!d.moved && d.button === 0 && e.type === 'pointerup') {
      const w = view.toWorld(d.start);
      if (state.tool === 'add' && isEditable()) addItem(w);
      else if (state.tool === 'pivot') addPivot(w);
      else { state.selectedItem = null; state.selectedPivot = null; renderTable(); draw(); }
    }
    return;
  }
  const wasDragging = state.dragPose !== null;
  state.dragPose = null;
  if (d.moved && !(isLive() && live.lastText === taskText())) {
    taskEdited({ eventTime: eventTime(e) }); // the final state; analysis follows its result
  } else {
    // Solved already (or on its way: its reply schedules the analysis).
    draw();
    if (wasDragging && !live.inFlight && !live.dirty) scheduleAnalysis();
  }
}
svg.addEventListener('pointerup', endDrag);
svg.addEventListener('pointercancel', endDrag);

svg.addEventListener('wheel', (e) => {
  e.preventDefault();
  view.zoomAt(view.eventPoint(e), Math.exp(-e.deltaY * (e.deltaMode === 1 ? 0.05 : 0.0015)));
  draw();
}, { passive: false });

new ResizeObserver(() => draw()).observe(svg);

function setTool(tool) {
  state.tool = tool;
  document.querySelectorAll('.tool').forEach((b) => b.classList.toggle('active', b.dataset.tool === tool));
  svg.classList.toggle('mode-add', tool === 'add');
  svg.classList.toggle('mode-pivot', tool === 'pivot');
  updateHint();
}

document.addEventListener('keydown', (e) => {
  if (e.target.closest('input, textarea, select')) return;
  if (e.key === 'Delete' || e.key === 'Backspace') { deleteSelected(); e.preventDefault(); }
  else if (e.key === 'a') setTool('add');
  else if (e.key === 's' || e.key === 'Escape') setTool('select');
  else if (e.key === 'p') setTool('pivot');
  else if (e.key === 'f') fitView();
  else if (e.key === ' ') { togglePlay(); e.preventDefault(); }
});

function updateHint() {
  const n = items().length;
  let hint = '';
  if (!isEditable()) hint = 'this task is not drawn on the plane: press Solve for its result';
  else if (isPath()) hint = n < 5 ? `path: add points (${n} of at least 5)` : isLive() ? 'five timed points: drag them, solved live' : 'path: choose an effort and Solve';
  else if (n < 3) hint = `add poses (${n} of at least 3): Add, then click`;
  else if (n === 3 || n === 4) {
    const picked = Array.isArray(state.task.fixed_pivots) ? state.task.fixed_pivots.length : 0;
    hint = n === 3 ? '3 poses: Pick pivot, click anywhere' : '4 poses: Pick pivot, click on the green curve';
    hint += picked === 1 ? ' (1 picked: one more for a four-bar)' : picked ? ` (${picked} picked: drag to move)` : ' (two: a four-bar)';
  }
  else if (n === 5) hint = 'five poses: drag a pose, every dyad and four-bar follows live';
  else hint = `${n} poses, least squares: choose an effort and Solve (fast runs after each edit)`;
  $('hint').textContent = hint;
}

/* ---------- table panel ---------- */

function renderTable() {
  const body = $('items-body');
  // While the rows stay the same (a drag), only their values change: the
  // inputs are updated in place instead of rebuilt on every pointer move.
  if (isEditable() && body.rows.length === items().length && body.dataset.kind === angleKey() && items().length) {
    items().forEach((item, i) => {
      const row = body.rows[i];
      row.classList.toggle('selected', state.selectedItem === i);
      row.classList.toggle('error-row', state.errorRows.includes(i));
      ['x', 'y', angleKey()].forEach((key, k) => {
        const input = row.cells[k + 1].firstChild;
        const text = item[key] instanceof Num ? item[key].text : item[key] ?? '';
        if (input.value !== text && document.activeElement !== input) {
          input.value = text;
          if (invalidFields.has(input)) setFieldError(input, null); // shows the task's value again
        }
      });
    });
    return;
  }
  body.dataset.kind = angleKey();
  for (const input of body.querySelectorAll('input.invalid')) setFieldError(input, null);
  body.replaceChildren();
  $('angle-head').textContent = isPath() ? 'input°' : 'θ°';
  if (!isEditable()) {
    const tr = body.insertRow();
    const td = tr.insertCell();
    td.colSpan = 5;
    td.textContent = 'not a planar motion or path task: edit it as a file';
    return;
  }
  items().forEach((item, i) => {
    const tr = body.insertRow();
    tr.dataset.testid = `item-row-${i}`;
    tr.setAttribute('data-testid', `item-row-${i}`);
    tr.classList.toggle('selected', state.selectedItem === i);
    tr.classList.toggle('error-row', state.errorRows.includes(i));
    tr.insertCell().textContent = String(i + 1);
    for (const key of ['x', 'y', angleKey()]) {
      const input = document.createElement('input');
      input.value = item[key] instanceof Num ? item[key].text : item[key] ?? '';
      input.setAttribute('data-testid', `item-${i}-${key}`);
      input.addEventListener('focus', () => { state.selectedItem = i; state.selectedPivot = null; drawItems(); });
      input.addEventListener('input', () => {
        const text = input.value.trim();
        const it = items()[i]; // the row's item now (rows outlive a drag's edits)
        if (!it) return;
        const problem = text === '' && key === 'input_deg' ? null : numberProblem(text);
        setFieldError(input, problem && `${isPath() ? 'point' : 'pose'} ${i + 1}, ${key}: ${problem}`);
        if (problem) return; // not sent: the task keeps its last number
        if (text === '') delete it[key];
        else it[key] = num(text);
        taskEdited({ source: 'table' });
      });
      tr.insertCell().appendChild(input);
    }
    const del = document.createElement('button');
    del.textContent = '×';
    del.title = 'delete';
    del.addEventListener('click', () => deleteItem(i));
    tr.insertCell().appendChild(del);
  });
}

const COLUMN_NAMES = {
  x: 'x', y: 'y', theta: 'theta_deg', theta_deg: 'theta_deg', angle: 'theta_deg', angle_deg: 'theta_deg',
  'θ': 'theta_deg', deg: 'theta_deg', input: 'input_deg', input_deg: 'input_deg', phi: 'input_deg',
  weight: 'weight',
};

// A typed or pasted table: whitespace, comma, semicolon or tab separated, an
// optional header naming the columns. Values stay as typed.
const NUMBER_TEXT = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/;
const DECIMAL_COMMA = /[-+]?\d*,\d+/;

// A line's fields: a line with semicolons or tabs is separated by them (and
// spaces); its commas can only be decimal commas, refused with a hint. Else
// spaces and commas separate, and a comma between digits on a line that is
// separated by spaces is taken for a decimal comma and refused too.
function splitTableLine(no, l) {
  if (/[;\t]/.test(l)) return l.split(/[\s;]+/).filter(Boolean);
  if (/\d,\d/.test(l) && /[^\s,]\s+[^\s,]/.test(l)) {
    throw new Error(`table line ${no}: '${DECIMAL_COMMA.exec(l)[0]}' is not a number (use a decimal point)`);
  }
  return l.split(/[\s,]+/).filter(Boolean);
}

function parseTable(text) {
  const lines = text.split(/\r?\n/).map((l, i) => [i + 1, l.trim()]).filter(([, l]) => l && !l.startsWith('#'));
  if (!lines.length) throw new Error('the table is empty');
  let columns = null;
  const first = splitTableLine(...lines[0]);
  // A header names columns: a word that is not a number.
  if (first.some((t) => !NUMBER_TEXT.test(t) && /[A-Za-zθφ°_]/.test(t))) {
    columns = first.map((t) => {
      const name = COLUMN_NAMES[t.toLowerCase().replace(/[()°]/g, '')];
      if (!name) throw new Error(`table header: unknown column "${t}" (x, y, theta_deg, input_deg, weight)`);
      return name;
    });
    lines.shift();
  }
  let path = isPath();
  if (columns) path = columns.includes('input_deg') || (!columns.includes('theta_deg') && path);
  if (!columns) {
    const n = first.length;
    if (path) columns = n === 2 ? ['x', 'y'] : ['x', 'y', 'input_deg', 'weight'].slice(0, n);
    else columns = ['x', 'y', 'theta_deg', 'weight'].slice(0, n);
    if (n < 2 || n > 4) throw new Error(`table line ${lines[0][0]}: expected 2 to 4 values, got ${n}`);
  }
  const rows = lines.map(([no, l]) => {
    const cells = splitTableLine(no, l);
    const bad = cells.findIndex((t) => numberProblem(t));
    if (bad >= 0 && bad < columns.length) throw new Error(`table line ${no}, ${columns[bad]}: ${numberProblem(cells[bad])}`);
    if (cells.length !== columns.length) throw new Error(`table line ${no}: expected ${columns.length} values, got ${cells.length}`);
    return Object.fromEntries(columns.map((c, k) => [c, num(cells[k])]));
  });
  return { path, rows };
}

function tableAsText() {
  const keys = isPath() ? (isTimedPath() ? ['x', 'y', 'input_deg'] : ['x', 'y']) : ['x', 'y', 'theta_deg'];
  return keys.join('\t') + '\n' + items().map((p) => keys.map((k) => (p[k] instanceof Num ? p[k].text : '')).join('\t')).join('\n');
}

function applyTable() {
  try {
    const { path, rows } = parseTable($('table-text').value);
    const keep = state.task.constraints;
    const tree = path ? { problem: 'path', points: rows } : { problem: 'motion', space: 'planar', poses: rows };
    if (keep) tree.constraints = keep;
    setTask(tree);
    clearError();
    taskEdited();
  } catch (err) {
    showError(err.message);
  }
}

function switchProblem(kind) {
  if (kind === (isPath() ? 'path' : 'motion')) return;
  const list = items().map((p) => ({ x: p.x, y: p.y }));
  const tree = kind === 'path' ? { problem: 'path', points: list } :
    { problem: 'motion', space: 'planar', poses: list.map((p) => ({ ...p, theta_deg: new Num('0') })) };
  if (state.task.constraints) {
    tree.constraints = state.task.constraints;
    if (kind === 'path') delete tree.constraints.moving_pivots_box;
  }
  setTask(tree, { fit: false });
  taskEdited();
}

/* ---------- mechanism list, status, errors ---------- */

const fmtMs = (ms) => (Number.isFinite(ms) ? `${ms < 10 ? ms.toFixed(3) : ms.toFixed(1)} ms` : '–');
const fmtNum = (x) => (Number.isFinite(x) ? (Math.abs(x) >= 1e-3 && Math.abs(x) < 1e5 ? x.toPrecision(4) : x.toExponential(2)) : '–');

const FIT_KEYS = ['max_pose_error', 'max_point_error', 'max_angle_error_deg'];
const fitKey = (m) => FIT_KEYS.find((key) => Number.isFinite(m?.[key])) ?? null;
const fitOf = (m) => (fitKey(m) ? m[fitKey(m)] : NaN);
const fmtFit = (m) => fmtNum(fitOf(m));

const fmtDeg = (x) => (Number.isFinite(x) ? x.toFixed(1) : '?');
function transmissionOf(m) {
  const t = m.transmission_angle_deg;
  if (Array.isArray(t) && t.length >= 2) return `${fmtDeg(t[0])}–${fmtDeg(t[1])}`;
  if (Number.isFinite(m.transmission_angle_min_deg)) return `${fmtDeg(m.transmission_angle_min_deg)}–${fmtDeg(m.transmission_angle_max_deg)}`;
  return '–';
}
const listText = (v) => (Array.isArray(v) ? v.map(String).join(', ') : v ? String(v) : '') || '–';
const plainText = (v) => (v === undefined || v === null ? '' : typeof v === 'object' ? JSON.stringify(v) : String(v));

function renderMechList() {
  const body = $('mech-body');
  body.replaceChildren();
  const table = $('mech-body').closest('table');
  table.classList.toggle('stale', state.stale);
  $('mech-stale').hidden = !state.stale;
  const list = Array.isArray(state.result?.mechanisms) ? state.result.mechanisms : [];
  list.forEach((m, i) => {
    if (!m || typeof m !== 'object') m = {};
    const tr = body.insertRow();
    tr.setAttribute('data-testid', `mechanism-row-${i}`);
    if (i === state.selected) tr.className = 'selected';
    const defects = Array.isArray(m.defects) && m.defects.length > 0;
    const cells = [String(i + 1), plainText(m.type), plainText(m.grashof), listText(m.defects),
      transmissionOf(m), fmtFit(m), listText(m.violates)];
    cells.forEach((text, k) => {
      const td = tr.insertCell();
      td.textContent = text;
      if (k === 3 && defects) td.className = 'defective';
      if (k === 6) td.className = 'violates';
    });
    tr.title = m.chosen ? `chosen: ${m.chosen}` : '';
    tr.addEventListener('click', () => selectMechanism(i));
  });
}

// A mechanism selected while playing (or while the one selected just before was to play on)
// plays once its analysis comes; the latest selection's, only.
let resumePlay = false;
let selections = 0;

function selectMechanism(i) {
  if (i === state.selected) return;
  const wasPlaying = state.playing || resumePlay;
  stopPlaying();
  resumePlay = wasPlaying;
  state.selected = i;
  state.frame = 0;
  renderMechList();
  updateRefine();
  drawMechanism();
  const mine = ++selections;
  fetchAnalysis().then((a) => {
    if (mine !== selections || !resumePlay) return; // selected again since, or stopped
    resumePlay = false;
    if (a) startPlaying();
  });
}

function renderStatus() {
  $('st-version').textContent = state.version ? `linkfit ${state.version}` : '';
  const r = state.result;
  $('st-method').textContent = r ? `method: ${r.method ?? '–'}${r.effort ? ` (${r.effort})` : ''}` : '';
  $('st-time').textContent = r ? `solve_time_ms: ${fmtMs(r.solve_time_ms)}` : '';
  $('st-refine').textContent = r ? state.statusNote : '';
  const notes = Array.isArray(r?.notes) ? r.notes.map(plainText) : [];
  // Each note whole, on its own line (the bar wraps; long notes scroll within it).
  $('st-notes').replaceChildren(...notes.map((note) => {
    const li = document.createElement('li');
    li.textContent = note;
    return li;
  }));
  const toggle = $('notes-toggle');
  toggle.hidden = !notes.length;
  toggle.textContent = notes.length ? `${notesOpen ? '▾' : '▴'} notes (${notes.length}): ${notes[0]}` : '';
  toggle.setAttribute('aria-expanded', String(notesOpen && notes.length > 0));
  $('notes-panel').hidden = !(notesOpen && notes.length);
}

// The notes panel stays open or closed, as chosen, across results.
let notesOpen = false;
function toggleNotes(open = !notesOpen) {
  notesOpen = open;
  renderStatus();
}

// A solve that failed: its message, naming the table's rows, and the result
// shown greyed as out of date until a solve succeeds.
function solveFailed(message) {
  showError(withRows(message), 'solve');
  state.stale = true;
  renderMechList();
  drawMechanism();
}

// The server names poses and points as the task's JSON does (poses[1], from
// 0): said as the table's rows too (row 2), and those rows highlighted.
function withRows(message) {
  const rows = [];
  const text = String(message).replace(/\b(poses|points)\[(\d+)\]((?:\.\w+)*)/g, (all, key, i) => {
    if (key === itemsKey()) rows.push(Number(i));
    return `${all} (row ${Number(i) + 1})`;
  });
  markRows(rows);
  return text;
}

function markRows(rows) {
  state.errorRows = rows;
  [...$('items-body').rows].forEach((tr, i) => tr.classList.toggle('error-row', rows.includes(i)));
}

// Why a typed text is not a number to send, or null. Nothing that is not one
// is sent: a decimal comma would be read as two values, or refused.
function numberProblem(text) {
  if (text === '') return 'empty (type a number)';
  if (num(text).valid) return null;
  if (/^[-+]?(\d+,\d*|\d*,\d+)$/.test(text)) return `'${text}' is not a number (use a decimal point)`;
  return `'${text}' is not a number`;
}

// Fields typed with something that is not a number: marked, said in the error
// bar (the last one typed), and left out of the task until corrected.
const invalidFields = new Map();
function setFieldError(input, message) {
  input.classList.toggle('invalid', Boolean(message));
  if (message) input.setAttribute('aria-invalid', 'true'); else input.removeAttribute('aria-invalid');
  if (message) invalidFields.set(input, message); else invalidFields.delete(input);
  for (const field of invalidFields.keys()) if (!field.isConnected) invalidFields.delete(field);
  if (message) showError(message, 'field');
  else if (invalidFields.size) showError([...invalidFields.values()].pop(), 'field');
  else clearError('field');
}

let errorSource = null;
function showError(message, source = 'other') {
  errorSource = source;
  $('error-text').textContent = message;
  $('error-bar').hidden = false;
}

// A success clears only the error of its own kind (a good solve does not hide
// a file that failed to open).
function clearError(source) {
  if (source && errorSource !== source) return;
  $('error-bar').hidden = true;
  errorSource = null;
}

/* ---------- files ---------- */

function download(name, text, type) {
  const url = URL.createObjectURL(new Blob([text], { type }));
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 5000);
  linkfit.lastExport = { name, text, type };
}

const STYLE_PROPS = ['fill', 'fill-opacity', 'stroke', 'stroke-width', 'stroke-dasharray', 'stroke-linecap',
  'stroke-linejoin', 'stroke-opacity', 'opacity', 'font-size', 'font-family', 'font-weight'];

// The canvas as a standalone SVG: the stylesheet's rules inlined on every element.
function pictureSvg() {
  const clone = svg.cloneNode(true);
  const from = svg.querySelectorAll('*');
  const to = clone.querySelectorAll('*');
  from.forEach((node, i) => {
    const cs = getComputedStyle(node);
    to[i].setAttribute('style', STYLE_PROPS.map((p) => `${p}:${cs.getPropertyValue(p)}`).join(';'));
    to[i].removeAttribute('class');
  });
  clone.setAttribute('xmlns', 'http://www.w3.org/2000/svg');
  clone.setAttribute('width', view.width);
  clone.setAttribute('height', view.height);
  clone.setAttribute('viewBox', `0 0 ${view.width} ${view.height}`);
  clone.removeAttribute('style');
  clone.insertBefore(el('rect', { width: '100%', height: '100%', fill: '#fff' }), clone.firstChild);
  return '<?xml version="1.0" encoding="UTF-8"?>\n' + new XMLSerializer().serializeToString(clone) + '\n';
}

async function exportCad(format) {
  if (!state.result?.mechanisms?.length) { showError('nothing to export: no mechanism listed'); return; }
  try {
    const text = await api.exportDrawing(state.resultText, state.resultTaskText, state.selected, format);
    download(`mechanism_${state.selected + 1}.${format}`, text, format === 'svg' ? 'image/svg+xml' : 'application/dxf');
  } catch (err) {
    showError(`export: ${err.message}`, 'export');
  }
}

function readFile(input, handle) {
  input.addEventListener('change', async () => {
    const file = input.files[0];
    input.value = '';
    if (!file) return;
    try {
      handle(await file.text(), file.name);
    } catch (err) {
      showError(`${file.name}: ${err.message}`, 'file');
    }
  });
}

// A task file's text: drawn, and solved (live, or its fast stage).
function openTaskText(text) {
  setTask(parse(text));
  fittedOnce = false; // fitted to the poses now, and to them with a mechanism when it comes
  clearError();
  if (isLive() || !enoughData()) taskEdited(); else { updateHint(); runStaged(['fast']); }
}

// A result file's text: listed and drawn over the task shown.
function openResultText(text) {
  const result = JSON.parse(text);
  if (!result || !Array.isArray(result.mechanisms)) throw new Error('not a linkfit result (no "mechanisms")');
  newEpoch(); // a solve on its way would replace the result opened
  stopPlaying();
  state.selected = 0;
  applyResult(text, taskText());
  clearError();
}

function bindFiles() {
  $('open-task').addEventListener('click', () => $('file-task').click());
  $('open-result').addEventListener('click', () => $('file-result').click());
  readFile($('file-task'), openTaskText);
  readFile($('file-result'), openResultText);
  $('save-task').addEventListener('click', () => download('task.json', taskText(), 'application/json'));
  $('save-result').addEventListener('click', () => {
    if (!state.resultText) { showError('no result to save yet'); return; }
    download('result.json', state.resultText.endsWith('\n') ? state.resultText : state.resultText + '\n', 'application/json');
  });
  $('save-svg').addEventListener('click', () => download('linkfit_picture.svg', pictureSvg(), 'image/svg+xml'));
  $('export-dxf').addEventListener('click', () => exportCad('dxf'));
  $('export-cad-svg').addEventListener('click', () => exportCad('svg'));
}

/* ---------- start ---------- */

function bindUi() {
  document.querySelectorAll('.tool').forEach((b) => b.addEventListener('click', () => setTool(b.dataset.tool)));
  $('clear-pivots').addEventListener('click', clearPivots);
  $('delete-item').addEventListener('click', deleteSelected);
  $('fit-view').addEventListener('click', fitView);
  $('problem').addEventListener('change', (e) => switchProblem(e.target.value));
  $('solve').addEventListener('click', solveButton);
  $('cancel').addEventListener('click', cancelStaged);
  $('refine').addEventListener('click', runRefine);
  $('play').addEventListener('click', togglePlay);
  $('scrub').addEventListener('input', (e) => {
    stopPlaying();
    state.frame = Number(e.target.value);
    if (!currentAnalysis()) fetchAnalysis(); else drawMechanism();
  });
  $('error-close').addEventListener('click', () => clearError());
  $('notes-toggle').addEventListener('click', () => toggleNotes());
  $('notes-close').addEventListener('click', () => toggleNotes(false));
  $('table-apply').addEventListener('click', applyTable);
  document.querySelector('.paste').addEventListener('toggle', (e) => {
    if (e.target.open && !$('table-text').value.trim()) $('table-text').value = tableAsText();
  });
  bindConstraintPanel();
  bindFiles();
  setTool('select');
}

async function start() {
  bindUi();
  api.version().then((v) => { state.version = v.version; renderStatus(); })
    .catch((err) => showError(`server: ${err.message}`, 'version'));
  try {
    const response = await fetch('examples/four_bar_5_poses.json');
    if (!response.ok) throw new Error(`HTTP ${response.status}`);
    setTask(parse(await response.text()));
    taskEdited();
  } catch (err) {
    showError(`the bundled example did not load: ${err.message}`);
    setTask({ problem: 'motion', space: 'planar', poses: [] });
  }
}

start();
