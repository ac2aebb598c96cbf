// JSON that keeps every number as the text it was written with.
//
// linkfit reads a task's precision from the digits of its numbers ("1.50" is
// precise to 0.005, "1.5" to 0.05), so the page must never round-trip the task
// through JavaScript floats: numbers live as `Num` objects holding their text,
// and the task JSON sent to the server is written from those texts.

export class Num {
  constructor(text) { this.text = String(text); }
  get value() { return Number(this.text); }
  get valid() { return JSON_NUMBER.test(this.text); }
}

const JSON_NUMBER = /^-?(0|[1-9]\d*)(\.\d+)?([eE][+-]?\d+)?$/;
// A number where the parser stands (lastIndex): sticky, so it is read whole from the text
// (no copy of a slice of it, which would cut a long number short).
const NUMBER_AT = /-?\d+(\.\d+)?([eE][+-]?\d+)?/y;

// A typed number made valid JSON without changing its digits (".5" → "0.5",
// "+2" → "2", "3." → "3"); anything else is left as typed, and is then sent as a
// string so that the server names the bad item in its error message.
export function normalizeNumberText(text) {
  let t = String(text).trim();
  if (t.startsWith('+')) t = t.slice(1);
  t = t.replace(/^(-?)\./, '$10.').replace(/\.(?=$|[eE])/, '');
  t = t.replace(/^(-?)0+(?=\d)/, '$1');
  return t;
}

export function num(text) { return new Num(normalizeNumberText(text)); }

// A number written with at most `decimals` decimals, trailing zeros kept off
// (a dragged value carries the precision of the drag, not 17 digits).
export function numRounded(value, decimals) {
  let t = value.toFixed(decimals);
  if (t.includes('.')) t = t.replace(/0+$/, '').replace(/\.$/, '');
  if (t === '-0') t = '0';
  return new Num(t);
}

export function parse(text) {
  let i = 0;
  const fail = (what) => {
    const line = text.slice(0, i).split('\n').length;
    throw new SyntaxError(`JSON line ${line}: ${what}`);
  };
  const ws = () => { while (i < text.length && ' \t\r\n'.includes(text[i])) i++; };
  const value = () => {
    ws();
    const c = text[i];
    if (c === '{') {
      i++; const obj = {}; ws();
      if (text[i] === '}') { i++; return obj; }
      for (;;) {
        ws(); if (text[i] !== '"') fail('expected a key');
        const key = string(); ws();
        if (text[i++] !== ':') fail('expected ":"');
        obj[key] = value(); ws();
        if (text[i] === ',') { i++; continue; }
        if (text[i] === '}') { i++; return obj; }
        fail('expected "," or "}"');
      }
    }
    if (c === '[') {
      i++; const arr = []; ws();
      if (text[i] === ']') { i++; return arr; }
      for (;;) {
        arr.push(value()); ws();
        if (text[i] === ',') { i++; continue; }
        if (text[i] === ']') { i++; return arr; }
        fail('expected "," or "]"');
      }
    }
    if (c === '"') return string();
    NUMBER_AT.lastIndex = i; // sticky: matched at i, however long the number
    const m = NUMBER_AT.exec(text);
    if (m) { i += m[0].length; return new Num(m[0]); }
    for (const [word, v] of [['true', true], ['false', false], ['null', null]]) {
      if (text.startsWith(word, i)) { i += word.length; return v; }
    }
    fail('unexpected ' + (c === undefined ? 'end' : `"${c}"`));
  };
  const string = () => {
    const start = i++;
    while (i < text.length && text[i] !== '"') i += text[i] === '\\' ? 2 : 1;
    if (i >= text.length) fail('unterminated string');
    i++;
    return JSON.parse(text.slice(start, i));
  };
  const v = value(); ws();
  if (i < text.length) fail('trailing characters');
  return v;
}

const isScalar = (v) => v === null || typeof v !== 'object' || v instanceof Num;
const scalar = (v) => {
  if (v instanceof Num) return v.valid ? v.text : JSON.stringify(v.text);
  if (typeof v === 'number') return Number.isFinite(v) ? String(v) : 'null';
  return JSON.stringify(v);
};

// Pretty but compact: small objects and arrays of scalars stay on one line
// (a pose a line, as the bundled task files are written).
export function stringify(v, indent = '') {
  if (isScalar(v)) return scalar(v);
  const inner = indent + '  ';
  const entries = Array.isArray(v) ? v.map((x) => [null, x]) : Object.entries(v).filter(([, x]) => x !== undefined);
  const flat = entries.every(([, x]) => isScalar(x) || (Array.isArray(x) && x.every(isScalar)) ||
    (!Array.isArray(x) && Object.values(x).every(isScalar)) || (Array.isArray(x) && x.every((y) => Array.isArray(y) && y.every(isScalar))));
  const item = ([k, x], ind) => (k === null ? '' : JSON.stringify(k) + ': ') + stringify(x, ind);
  const [open, close] = Array.isArray(v) ? ['[', ']'] : ['{', '}'];
  if (entries.length === 0) return open + close;
  const line = open + entries.map((e) => item(e, inner)).join(', ') + close;
  if (flat && line.length <= 100 && !line.includes('\n')) return line;
  return open + '\n' + entries.map((e) => inner + item(e, inner)).join(',\n') + '\n' + indent + close;
}

// The plain JavaScript value (numbers as floats): for tests and display only.
export function toPlain(v) {
  if (v instanceof Num) return v.valid ? v.value : v.text;
  if (Array.isArray(v)) return v.map(toPlain);
  if (v && typeof v === 'object') return Object.fromEntries(Object.entries(v).map(([k, x]) => [k, toPlain(x)]));
  return v;
}
