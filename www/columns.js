// The per-point parts of an analysis as columns (issue 31 item 3): each array of `PER_POINT` (an
// array of 200,000 objects for a dense scan) travels from the worker to the page as typed-array
// columns, transferred, so that the page's thread neither deserialises nor collects an object
// per point. The core's export writes them so (src/wasm/columns.rs, the same layout); an array
// it leaves as JSON (a shape it does not write as columns) the worker packs here. Both follow
// the values, not a list of fields: every field of a point arrives (what the core adds to a
// point arrives too), and `Table.row`/`toJSON` rebuild the point exactly as the core wrote it,
// key order included, so the JSON export is unchanged.
//
// A packed array is `{$col: kind, n, ...}` (plain data: it crosses postMessage):
// - `num`: numbers, `v` a Float64Array; `numnull`: numbers or null, `v` (NaN at a null) and
//   `nul` (Uint8Array, 1 at a null);
// - `bool`: `v` a Uint8Array (0/1); `const`: every value the same `v` (null, a boolean, a string);
// - `label`: strings with few distinct values, `codes` (Int32Array) into `labels`;
//   `text`: strings, `s` their concatenation and `ends` (Int32Array) where each one ends;
// - `vec`: arrays of the same length `k` of numbers, `v` (Float64Array, n·k, point after point);
// - `table`: objects with the same keys in the same order, `keys` and `cols` (one packed array
//   per key);
// - `any`: anything else, `v` the array as it was (structured-cloned as before).
// The page unpacks (`unpack`) a `table` into a `Table`, a `num` into its Float64Array (NaN at a
// null), any other kind into a `Column`; `toJsonText` writes them back as the arrays they were.

/** The arrays of an analysis (`analyse`, `analyseRepeats`: src/wasm/analysis.rs, whose
 * `take_columns` writes the same ones) that hold a value per point, as paths (`*`: each element
 * of an array). */
export const PER_POINT = [
  'points', 'file.points', 'path_position',
  'identification.points', 'baseline.identification.points',
  'design.columns.*', 'baseline.design.columns.*',
  'diagnosis.report.where.*.ids', 'diagnosis.report.structure.entries.*.ids',
];
/** The core's operations whose answer is an analysis (packed by the worker). */
export const PACKED_OPS = ['analyse', 'analyseRepeats'];

// ------------------------------------------------------------------ packing (the worker)

const isRecord = (v) => v !== null && typeof v === 'object' && !Array.isArray(v);

/** The fields of `rows`, one array per key, when every row has the same keys in the same order
 * (else null): {keys, fields}. */
function fieldsOf(rows) {
  if (!rows.length || !isRecord(rows[0])) return null;
  const keys = Object.keys(rows[0]);
  const fields = keys.map(() => new Array(rows.length));
  for (let i = 0; i < rows.length; i++) {
    const r = rows[i];
    if (!isRecord(r)) return null;
    let j = 0;
    for (const k in r) {
      if (k !== keys[j]) return null;
      fields[j++][i] = r[k];
    }
    if (j !== keys.length) return null;
  }
  return { keys, fields };
}

/** `values` (an array) as a packed column; `transfer` gains the buffers to transfer. */
export function packColumn(values, transfer) {
  const n = values.length;
  let nums = 0, nulls = 0, bools = 0, strings = 0, arrays = 0, records = 0;
  for (const v of values) {
    if (typeof v === 'number') nums++;
    else if (v === null) nulls++;
    else if (typeof v === 'boolean') bools++;
    else if (typeof v === 'string') strings++;
    else if (Array.isArray(v)) arrays++;
    else if (typeof v === 'object') records++;
  }
  const f64 = (length, fill) => { const v = new Float64Array(length); fill(v); transfer.push(v.buffer); return v; };
  if (n > 0 && nulls === n) return { $col: 'const', n, v: null };
  if (nums + nulls === n) {
    const v = f64(n, (a) => { for (let i = 0; i < n; i++) a[i] = values[i] === null ? NaN : values[i]; });
    if (!nulls) return { $col: 'num', n, v };
    const nul = new Uint8Array(n);
    for (let i = 0; i < n; i++) nul[i] = values[i] === null ? 1 : 0;
    transfer.push(nul.buffer);
    return { $col: 'numnull', n, v, nul };
  }
  if (bools === n) {
    if (values.every((x) => x === values[0])) return { $col: 'const', n, v: values[0] };
    const v = new Uint8Array(n);
    for (let i = 0; i < n; i++) v[i] = values[i] ? 1 : 0;
    transfer.push(v.buffer);
    return { $col: 'bool', n, v };
  }
  if (strings === n) return packStrings(values, transfer);
  if (arrays === n) {
    const k = values[0].length;
    if (values.every((x) => x.length === k && x.every((y) => typeof y === 'number'))) {
      const v = f64(n * k, (a) => { for (let i = 0; i < n; i++) for (let j = 0; j < k; j++) a[i * k + j] = values[i][j]; });
      return { $col: 'vec', n, k, v };
    }
  }
  if (records === n) {
    const t = fieldsOf(values);
    if (t) return { $col: 'table', n, keys: t.keys, cols: Object.fromEntries(t.keys.map((key, j) => [key, packColumn(t.fields[j], transfer)])) };
  }
  return { $col: 'any', n, v: values };
}

/** Strings: one value → `const`; few distinct (at most a quarter of them, and no more than 64
 * among the first 256) → `label`; else `text`. */
function packStrings(values, transfer) {
  const n = values.length;
  const most = n / 4 + 1;
  const labels = (() => {
    if (new Set(values.slice(0, 256)).size > 64) return null;
    const index = new Map();
    for (const s of values) if (!index.has(s) && index.set(s, index.size).size > most) return null;
    return index;
  })();
  if (labels && labels.size === 1) return { $col: 'const', n, v: values[0] };
  if (labels) {
    const codes = new Int32Array(n);
    for (let i = 0; i < n; i++) codes[i] = labels.get(values[i]);
    transfer.push(codes.buffer);
    return { $col: 'label', n, codes, labels: [...labels.keys()] };
  }
  const ends = new Int32Array(n);
  let at = 0;
  for (let i = 0; i < n; i++) { at += values[i].length; ends[i] = at; }
  transfer.push(ends.buffer);
  return { $col: 'text', n, s: values.join(''), ends };
}

/** Visits the value at `path` (dots, `*` for each element) under `root`: `fn(holder, key)`. */
function visit(root, path, fn) {
  const walk = (holder, key, rest) => {
    const v = holder[key];
    if (v === null || typeof v !== 'object') return;
    if (!rest.length) { fn(holder, key); return; }
    const [head, ...tail] = rest;
    if (head === '*') { if (Array.isArray(v)) for (let i = 0; i < v.length; i++) walk(v, i, tail); } else walk(v, head, tail);
  };
  const [head, ...tail] = path.split('.');
  walk(root, head, tail);
}

/** The buffers of the typed arrays of the packed column `c`, added to `transfer`. */
function buffersOf(c, transfer) {
  for (const v of Object.values(c)) if (ArrayBuffer.isView(v)) transfer.push(v.buffer);
  if (c.$col === 'table') for (const col of Object.values(c.cols)) buffersOf(col, transfer);
}

/** Packs, in place, the per-point arrays (`PER_POINT`) of the analysis `a` that the core left as
 * arrays; returns the buffers of every packed column, to transfer. */
export function packAnalysis(a) {
  const transfer = [];
  for (const path of PER_POINT) {
    visit({ a }, `a.${path}`, (holder, key) => {
      if (Array.isArray(holder[key])) holder[key] = packColumn(holder[key], transfer);
      else if (holder[key].$col) buffersOf(holder[key], transfer);
    });
  }
  return transfer;
}

// ------------------------------------------------------------------ reading (the page)

/** A packed column of any kind but `num` and `table`: `at(i)`, iteration, `toJSON()` (the array). */
export class Column {
  constructor(c) { this.c = c; this.length = c.n; }
  /** The value of point `i` as the core sent it. */
  at(i) {
    const c = this.c;
    switch (c.$col) {
      case 'num': return c.v[i];
      case 'numnull': return c.nul[i] ? null : c.v[i];
      case 'bool': return c.v[i] === 1;
      case 'const': return c.v;
      case 'label': return c.labels[c.codes[i]];
      case 'text': return c.s.slice(i ? c.ends[i - 1] : 0, c.ends[i]);
      case 'vec': return Array.from(c.v.subarray(i * c.k, (i + 1) * c.k));
      case 'table': return new Table(c).row(i);
      default: return c.v[i];
    }
  }
  *[Symbol.iterator]() { for (let i = 0; i < this.length; i++) yield this.at(i); }
  /** The values as an array. */
  toArray() {
    const c = this.c, out = new Array(this.length);
    if (c.$col === 'label') for (let i = 0; i < out.length; i++) out[i] = c.labels[c.codes[i]];
    else for (let i = 0; i < out.length; i++) out[i] = this.at(i);
    return out;
  }
  toJSON() { return this.toArray(); }
}

/** Points as columns (a packed `table`): typed columns for the views, rows for the exports. */
export class Table {
  constructor(c) { this.c = c; this.length = c.n; this.keys = c.keys; }
  packed(key) {
    const c = this.c.cols[key];
    if (!c) throw new Error(`the points have no field "${key}" (fields: ${this.keys.join(', ')})`);
    return c;
  }
  /** The numbers of field `key` (Float64Array; NaN where the core sent null). */
  num(key) {
    const c = this.packed(key);
    if (c.$col === 'num' || c.$col === 'numnull') return c.v;
    throw new Error(`the field "${key}" of the points is not a number (${c.$col})`);
  }
  /** Field `key` of each point, as the core sent it (`at(i)`). */
  col(key) { return new Column(this.packed(key)); }
  /** Field `key` of each point when it is an object: its fields as columns. */
  table(key) {
    const c = this.packed(key);
    if (c.$col === 'table') return new Table(c);
    throw new Error(`the field "${key}" of the points is not an object (${c.$col})`);
  }
  /** Field `key` when every point has a list of `k` numbers: {k, v} (v: point after point). */
  vec(key) {
    const c = this.packed(key);
    if (c.$col === 'vec') return { k: c.k, v: c.v };
    throw new Error(`the field "${key}" of the points is not a list of numbers (${c.$col})`);
  }
  /** Point `i` as the core sent it. */
  row(i) {
    const out = {};
    for (const key of this.keys) out[key] = new Column(this.c.cols[key]).at(i);
    return out;
  }
  /** Every point as the core sent it (for the exports; the views read columns). */
  rows() {
    const cols = this.keys.map((key) => new Column(this.c.cols[key]));
    return Array.from({ length: this.length }, (_, i) => Object.fromEntries(this.keys.map((key, j) => [key, cols[j].at(i)])));
  }
  toJSON() { return this.rows(); }
}

/** A packed column as the page reads it: `Table`, Float64Array (`num`, `numnull`) or `Column`. */
function reader(c) {
  if (c.$col === 'table') return new Table(c);
  if (c.$col === 'num' || c.$col === 'numnull') return c.v;
  return new Column(c);
}

/** The page's side of `packAnalysis`: each packed array of `a` becomes its reader, in place. */
export function unpackAnalysis(a) {
  for (const path of PER_POINT) visit({ a }, `a.${path}`, (holder, key) => { if (holder[key].$col) holder[key] = reader(holder[key]); });
  return a;
}

/** JSON text of a value holding readers: each written as the array the core sent. */
export function toJsonText(value, space) {
  return JSON.stringify(value, (_, v) => (ArrayBuffer.isView(v) ? Array.from(v) : v), space);
}
