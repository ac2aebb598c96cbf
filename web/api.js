// The `linkfit serve` HTTP API. Every call resolves to the response text (the
// result JSON is kept as the server wrote it, so "save result" saves exactly
// that) or rejects with an ApiError carrying the server's one-line message.

export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function call(url, options = {}) {
  let response;
  try {
    response = await fetch(url, options);
  } catch (err) {
    if (err.name === 'AbortError') throw err;
    throw new ApiError(0, `cannot reach the linkfit server (${err.message})`);
  }
  const text = await response.text();
  if (!response.ok) {
    let message = text || response.statusText;
    try { message = JSON.parse(text).error || message; } catch { /* not JSON: keep the text */ }
    const what = { 413: 'request too large', 503: 'server busy or time limit', 500: 'internal error' }[response.status];
    throw new ApiError(response.status, what && !message.includes(what) ? `${message} (${what})` : message);
  }
  return text;
}

const query = (params) => {
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(params)) if (v !== undefined && v !== null && v !== '') q.set(k, v);
  const s = q.toString();
  return s ? '?' + s : '';
};

const jsonPart = (fd, name, text) =>
  fd.append(name, new Blob([text], { type: 'application/json' }), name + '.json');

export async function version() {
  return JSON.parse(await call('/api/version'));
}

// A solve or refinement that may run long carries a request_id: when its fetch is aborted
// (Cancel), the server is told to stop it (POST /api/cancel), so it frees its place.
// A page reloaded or closed aborts its fetches without telling the server: on `pagehide`
// every one still in flight is cancelled by a beacon (a POST that outlives the page).
const session = Math.random().toString(36).slice(2);
let nextRequest = 0;
const inFlight = new Set(); // the request_ids sent and not yet answered
function cancellable(route, params, options) {
  if (!options.signal) return call(route + query(params), options);
  const id = `${session}-${++nextRequest}`;
  const stop = () => fetch('/api/cancel' + query({ request_id: id }), { method: 'POST' }).catch(() => {});
  options.signal.addEventListener('abort', stop, { once: true });
  inFlight.add(id);
  return call(route + query({ ...params, request_id: id }), options)
    .finally(() => {
      inFlight.delete(id);
      options.signal.removeEventListener('abort', stop);
    });
}

window.addEventListener('pagehide', () => {
  for (const id of inFlight) navigator.sendBeacon('/api/cancel' + query({ request_id: id }));
  inFlight.clear();
});

export function solve(taskText, { effort, curvePoints, signal } = {}) {
  return cancellable('/api/solve', { effort, curve_points: curvePoints }, {
    method: 'POST', body: taskText, signal, headers: { 'Content-Type': 'application/json' },
  });
}

// `mechanism` is the list index, from 0; the API counts from 1 as the CLI does.
export function analyze(resultText, taskText, mechanism, params = {}, signal) {
  const fd = new FormData();
  jsonPart(fd, 'result', resultText);
  if (taskText) jsonPart(fd, 'task', taskText);
  return call('/api/analyze' + query({ mechanism: mechanism + 1, ...params }), { method: 'POST', body: fd, signal });
}

export function exportDrawing(resultText, taskText, mechanism, format, inputDeg) {
  const fd = new FormData();
  jsonPart(fd, 'result', resultText);
  if (taskText) jsonPart(fd, 'task', taskText);
  return call('/api/export' + query({ mechanism: mechanism + 1, format, input_deg: inputDeg }), { method: 'POST', body: fd });
}

// The design is a result text; `mechanism` its list index, from 0.
export function refine(taskText, resultText, mechanism, signal) {
  const fd = new FormData();
  jsonPart(fd, 'task', taskText);
  jsonPart(fd, 'design', resultText);
  return cancellable('/api/refine', { mechanism: mechanism + 1 }, { method: 'POST', body: fd, signal });
}
