/* geomexact viewer: a self-contained 2D mesh viewer (canvas), inlined into one HTML file.
 *
 * Data: the JSON payload in script#geomexact-data (format "geomexact-view",
 * version 1, see specs/viewer.md), or a file the user opens (OFF, Triangle .node/.ele/.poly,
 * PSLG text .pslg, triangle list .txt), parsed here.  Nothing is ever fetched: the page's
 * Content-Security-Policy forbids every network request.
 *
 * Structure: parsing (payload and files) -> Model (vertex doubles, triangle slots with an
 * "alive" flag per slot, polygons, segments, optional History for the step slider) ->
 * Renderer2D (Path2D batches in normalised coordinates, drawn with one transform per frame;
 * a cached bitmap stands in while panning when a full frame is slow) -> UI (panel, hover,
 * slider, file input).  RENDERERS maps a scene dimension to its renderer: a 3D renderer
 * (rotation, shrunk tetrahedra) plugs in there.
 */
(function () {
  "use strict";

  const FORMAT = "geomexact-view";
  const VERSION = 1;

  // ---------------------------------------------------------------------------------
  // small helpers
  // ---------------------------------------------------------------------------------
  function $(id) {
    return document.getElementById(id);
  }

  function decodeBase64(text, Type) {
    if (!text) return new Type(0);
    const binary = atob(text);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  function formatNumber(value, digits) {
    if (value === null || value === undefined || Number.isNaN(value)) return "-";
    if (typeof value !== "number") return String(value);
    if (Number.isInteger(value) && Math.abs(value) < 1e15) return value.toLocaleString("en-US");
    const shown = value.toPrecision(digits || 6);
    return shown.indexOf("e") >= 0 ? shown : String(Number(shown));
  }

  function formatCount(value) {
    return value.toLocaleString("en-US");
  }

  function escapeText(text) {
    return String(text).replace(/[&<>"]/g, function (c) {
      return { "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c];
    });
  }

  // ---------------------------------------------------------------------------------
  // exact rationals (BigInt): exact areas of hovered triangles from the exact text
  // ---------------------------------------------------------------------------------
  function bigAbs(a) {
    return a < 0n ? -a : a;
  }

  function gcd(a, b) {
    a = bigAbs(a);
    b = bigAbs(b);
    while (b) {
      const t = a % b;
      a = b;
      b = t;
    }
    return a;
  }

  function rational(n, d) {
    if (d === 0n) throw new Error("zero denominator");
    if (d < 0n) {
      n = -n;
      d = -d;
    }
    const g = gcd(n, d) || 1n;
    return { n: n / g, d: d / g };
  }

  const DECIMAL = /^([+-]?)(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?$/;

  function parseRational(text) {
    const slash = text.indexOf("/");
    if (slash >= 0) {
      return rational(BigInt(text.slice(0, slash)), BigInt(text.slice(slash + 1)));
    }
    const match = DECIMAL.exec(text);
    if (!match || (match[2] === "" && (match[3] === undefined || match[3] === ""))) {
      throw new Error("not a number: " + text);
    }
    const fraction = match[3] || "";
    let n = BigInt((match[2] || "0") + fraction);
    let d = 10n ** BigInt(fraction.length);
    const exponent = match[4] ? parseInt(match[4], 10) : 0;
    if (Math.abs(exponent) > 10000) throw new Error("exponent too large: " + text);
    if (exponent > 0) n *= 10n ** BigInt(exponent);
    else if (exponent < 0) d *= 10n ** BigInt(-exponent);
    if (match[1] === "-") n = -n;
    return rational(n, d);
  }

  function rSub(a, b) {
    return rational(a.n * b.d - b.n * a.d, a.d * b.d);
  }

  function rMul(a, b) {
    return rational(a.n * b.n, a.d * b.d);
  }

  function rationalText(r) {
    // the shortest decimal when the value terminates, else p/q (as geomexact writes it)
    let d = r.d;
    let twos = 0;
    let fives = 0;
    while (d % 2n === 0n) {
      d /= 2n;
      twos++;
    }
    while (d % 5n === 0n) {
      d /= 5n;
      fives++;
    }
    if (d !== 1n) return r.n + "/" + r.d;
    const places = Math.max(twos, fives);
    const scaled = bigAbs(r.n) * 10n ** BigInt(places) / r.d;
    let digits = scaled.toString();
    if (places > 0) {
      digits = digits.padStart(places + 1, "0");
      digits = digits.slice(0, digits.length - places) + "." + digits.slice(digits.length - places);
    }
    return (r.n < 0n ? "-" : "") + digits;
  }

  function numberOf(text) {
    // the double of a number token: decimal, or p/q
    const slash = text.indexOf("/");
    if (slash < 0) return Number(text);
    const p = text.slice(0, slash);
    const q = text.slice(slash + 1);
    const value = Number(p) / Number(q);
    if (Number.isFinite(value)) return value;
    try {
      const r = parseRational(text);
      const shift = BigInt(Math.max(r.n.toString().length, r.d.toString().length) - 300);
      const scale = shift > 0n ? 10n ** shift : 1n;
      return Number(r.n / scale) / Number(r.d / scale);
    } catch (error) {
      return NaN;
    }
  }

  // ---------------------------------------------------------------------------------
  // the model
  // ---------------------------------------------------------------------------------
  function makeModel(options) {
    const model = {
      kind: options.kind,
      dimension: options.dimension || 2,
      title: options.title || "",
      source: options.source || "",
      xy: options.xy,
      exact: options.exact || null,
      vertexTotal: options.xy.length / 2,
      vertexCount: options.xy.length / 2,
      cells: options.cells || new Uint32Array(0),
      regions: options.regions || null,
      polyOffsets: options.polyOffsets || new Uint32Array([0]),
      polyVertices: options.polyVertices || new Uint32Array(0),
      nonconvex: null,
      segCells: options.segCells || new Uint32Array(0),
      holes: options.holes || new Float64Array(0),
      seeds: options.seeds || new Float64Array(0),
      summary: options.summary || null,
      notes: options.notes || [],
      scaleExponent: options.scaleExponent || 0,
      history: null,
      step: 0,
      download: options.download || null,
    };
    model.slots = model.cells.length / 3;
    model.alive = new Uint8Array(model.slots).fill(1);
    model.aliveCount = model.slots;
    model.segSlots = model.segCells.length / 2;
    model.segAlive = new Uint8Array(model.segSlots).fill(1);
    model.polygons = model.polyOffsets.length - 1;
    model.nonconvex = new Uint8Array(Math.max(model.polygons, 0));
    if (options.nonconvex) {
      for (let i = 0; i < options.nonconvex.length; i++) model.nonconvex[options.nonconvex[i]] = 1;
    }
    return model;
  }

  function spans(offsets, index) {
    return [offsets[index - 1], offsets[index]];
  }

  function attachHistory(model, h) {
    const history = {
      steps: h.steps,
      labels: h.labels,
      addedOffsets: decodeBase64(h.added_offsets, Uint32Array),
      added: decodeBase64(h.added, Uint32Array),
      removedOffsets: decodeBase64(h.removed_offsets, Uint32Array),
      removed: decodeBase64(h.removed, Uint32Array),
      segAddedOffsets: decodeBase64(h.segment_added_offsets, Uint32Array),
      segAdded: decodeBase64(h.segment_added, Uint32Array),
      segRemovedOffsets: decodeBase64(h.segment_removed_offsets, Uint32Array),
      segRemoved: decodeBase64(h.segment_removed, Uint32Array),
      vertexCounts: decodeBase64(h.vertex_counts, Uint32Array),
      inputDigest: h.input_digest,
      finalDigest: h.final_digest,
    };
    const start = decodeBase64(h.start, Uint32Array);
    const segStart = decodeBase64(h.segment_start, Uint32Array);
    model.history = history;
    model.alive.fill(0);
    for (let i = 0; i < start.length; i++) model.alive[start[i]] = 1;
    model.aliveCount = start.length;
    model.segAlive.fill(0);
    for (let i = 0; i < segStart.length; i++) model.segAlive[segStart[i]] = 1;
    model.step = 0;
    model.vertexCount = history.vertexCounts[0];
  }

  function applyStep(model, k, forward) {
    // step k (1-based): forward = remove then add; backward = undo in reverse order
    const h = model.history;
    const alive = model.alive;
    const segAlive = model.segAlive;
    const [a0, a1] = spans(h.addedOffsets, k);
    const [r0, r1] = spans(h.removedOffsets, k);
    const [sa0, sa1] = spans(h.segAddedOffsets, k);
    const [sr0, sr1] = spans(h.segRemovedOffsets, k);
    if (forward) {
      for (let i = r0; i < r1; i++) alive[h.removed[i]] = 0;
      for (let i = a0; i < a1; i++) alive[h.added[i]] = 1;
      for (let i = sr0; i < sr1; i++) segAlive[h.segRemoved[i]] = 0;
      for (let i = sa0; i < sa1; i++) segAlive[h.segAdded[i]] = 1;
      model.aliveCount += a1 - a0 - (r1 - r0);
    } else {
      for (let i = a0; i < a1; i++) alive[h.added[i]] = 0;
      for (let i = r0; i < r1; i++) alive[h.removed[i]] = 1;
      for (let i = sa0; i < sa1; i++) segAlive[h.segAdded[i]] = 0;
      for (let i = sr0; i < sr1; i++) segAlive[h.segRemoved[i]] = 1;
      model.aliveCount -= a1 - a0 - (r1 - r0);
    }
  }

  function setStep(model, target) {
    const h = model.history;
    if (!h) return false;
    target = Math.max(0, Math.min(h.steps, target | 0));
    if (target === model.step) return false;
    while (model.step < target) {
      model.step += 1;
      applyStep(model, model.step, true);
    }
    while (model.step > target) {
      applyStep(model, model.step, false);
      model.step -= 1;
    }
    model.vertexCount = h.vertexCounts[model.step];
    return true;
  }

  function modelFromPayload(data) {
    if (!data || data.format !== FORMAT) throw new Error("not a geomexact view payload");
    if (data.version !== VERSION) throw new Error("unsupported payload version " + data.version);
    const s = data.scene;
    const history = data.history;
    const model = makeModel({
      kind: s.kind,
      dimension: s.dimension,
      title: data.title,
      source: data.source && data.source.file ? data.source.file : "",
      xy: decodeBase64(s.xy, Float64Array),
      exact: s.exact,
      cells: decodeBase64(history ? history.cells : s.triangles, Uint32Array),
      regions: s.regions ? decodeBase64(s.regions, Float64Array) : null,
      polyOffsets: s.polygon_offsets ? decodeBase64(s.polygon_offsets, Uint32Array) : null,
      polyVertices: decodeBase64(s.polygon_vertices, Uint32Array),
      nonconvex: decodeBase64(s.nonconvex, Uint32Array),
      segCells: decodeBase64(history ? history.segment_cells : s.segments, Uint32Array),
      holes: decodeBase64(s.holes, Float64Array),
      seeds: decodeBase64(s.seeds, Float64Array),
      summary: s.summary,
      notes: data.notes || [],
      scaleExponent: s.scale_exponent || 0,
      download: data.download || null,
    });
    if (model.polyOffsets.length === 0) {
      model.polyOffsets = new Uint32Array([0]);
      model.polygons = 0;
    }
    if (history) {
      attachHistory(model, history);
      const initial = data.options && Number.isInteger(data.options.step) ? data.options.step : history.steps;
      setStep(model, initial);
    }
    return model;
  }

  // ---------------------------------------------------------------------------------
  // file parsers (the page's "open" control)
  // ---------------------------------------------------------------------------------
  class ParseError extends Error {
    constructor(file, line, problem) {
      super(file + (line ? ":" + line : "") + ": " + problem);
      this.name = "ParseError";
    }
  }

  function dataLines(text) {
    // [lineNumber, tokens] of non-empty lines, comments (# …) removed
    const out = [];
    const lines = text.split(/\r\n|\n|\r/);
    for (let i = 0; i < lines.length; i++) {
      let line = lines[i];
      const hash = line.indexOf("#");
      if (hash >= 0) line = line.slice(0, hash);
      line = line.trim();
      if (line) out.push([i + 1, line.split(/[\s,]+/).filter(Boolean)]);
    }
    return out;
  }

  function checkNumber(file, line, token, what) {
    const value = numberOf(token);
    if (!Number.isFinite(value)) throw new ParseError(file, line, "cannot read '" + token + "' as " + what);
    return value;
  }

  function checkInt(file, line, token, what) {
    if (!/^[+-]?\d+$/.test(token)) {
      throw new ParseError(file, line, "cannot read '" + token + "' as " + what + " (an integer)");
    }
    return parseInt(token, 10);
  }

  function checkIndex(file, line, value, count, what) {
    if (value < 0 || value >= count) {
      throw new ParseError(file, line, what + " " + value + " is not a vertex (there are " + count + ")");
    }
    return value;
  }

  function Points() {
    this.x = [];
    this.y = [];
    this.exact = [];
  }
  Points.prototype.add = function (file, line, xs, ys) {
    this.x.push(checkNumber(file, line, xs, "a coordinate"));
    this.y.push(checkNumber(file, line, ys, "a coordinate"));
    this.exact.push(xs + " " + ys);
  };
  Points.prototype.xy = function () {
    const xy = new Float64Array(this.x.length * 2);
    for (let i = 0; i < this.x.length; i++) {
      xy[2 * i] = this.x[i];
      xy[2 * i + 1] = this.y[i];
    }
    return xy;
  };
  Points.prototype.exactText = function () {
    // the coordinates as written in the file (exact areas on hover), for files of a
    // reasonable size
    return this.exact.length <= 500000 ? this.exact : null;
  };

  function meshModel(name, points, triangles, segments, extra) {
    const polygons = extra && extra.polygons;
    return makeModel({
      kind: polygons ? "polygons" : triangles.length || !extra || !extra.pslg ? "triangles" : "pslg",
      title: name,
      source: name,
      xy: points.xy(),
      exact: points.exactText(),
      cells: new Uint32Array(triangles),
      polyOffsets: polygons ? new Uint32Array(polygons.offsets) : null,
      polyVertices: polygons ? new Uint32Array(polygons.vertices) : null,
      nonconvex: polygons ? nonconvexPolygons(points, polygons) : null,
      segCells: new Uint32Array(segments || []),
      holes: extra && extra.holes ? new Float64Array(extra.holes) : null,
      seeds: extra && extra.seeds ? new Float64Array(extra.seeds) : null,
      notes: (extra && extra.notes) || ["read in the browser (doubles; not validated: use geomexact check)"],
    });
  }

  function nonconvexPolygons(points, polygons) {
    // display only (doubles): a corner turning against the polygon's orientation
    const out = [];
    const offsets = polygons.offsets;
    const v = polygons.vertices;
    for (let p = 0; p + 1 < offsets.length; p++) {
      const s = offsets[p];
      const e = offsets[p + 1];
      let area = 0;
      for (let i = s; i < e; i++) {
        const a = v[i];
        const b = v[i + 1 < e ? i + 1 : s];
        area += points.x[a] * points.y[b] - points.x[b] * points.y[a];
      }
      const seen = new Set();
      let bad = false;
      for (let i = s; i < e && !bad; i++) {
        if (seen.has(v[i])) bad = true;
        seen.add(v[i]);
        const a = v[i === s ? e - 1 : i - 1];
        const b = v[i];
        const c = v[i + 1 < e ? i + 1 : s];
        const turn = (points.x[b] - points.x[a]) * (points.y[c] - points.y[a]) -
          (points.y[b] - points.y[a]) * (points.x[c] - points.x[a]);
        if (turn * area < 0) bad = true;
      }
      if (bad) out.push(p);
    }
    return out;
  }

  function unwrapGeomview(text) {
    // blank the old Geomview wrapper "{ appearance {…} LIST … }" around one OFF object,
    // keeping line numbers
    if (!/^\s*\{/.test(text)) return text;
    let out = text.replace(/^(\s*)\{/, "$1 ");
    out = out.replace(/appearance\s*\{[^{}]*\}/, function (m) {
      return m.replace(/[^\n]/g, " ");
    });
    out = out.replace(/\bLIST\b/, "    ");
    out = out.replace(/\}(\s*)$/, " $1");
    return out;
  }

  function parseOFF(name, text) {
    const lines = dataLines(unwrapGeomview(text));
    const tokens = [];
    for (const [number, parts] of lines) for (const t of parts) tokens.push([number, t]);
    let at = 0;
    if (!tokens.length) throw new ParseError(name, null, "empty file");
    const first = tokens[0][1];
    if (/OFF$/i.test(first)) {
      if (!/^(ST)?C?N?OFF$/i.test(first) || /^(4|n)/.test(first)) {
        throw new ParseError(name, tokens[0][0], "unsupported OFF variant '" + first + "' (planar OFF only)");
      }
      at = 1;
      if (tokens[at] && /^BINARY$/i.test(tokens[at][1])) throw new ParseError(name, tokens[at][0], "binary OFF is not supported");
    }
    function next(what) {
      if (at >= tokens.length) throw new ParseError(name, null, "file ends early: expected " + what);
      return tokens[at++];
    }
    const [countLine, nvText] = next("the vertex count");
    const nv = checkInt(name, countLine, nvText, "the vertex count");
    const nfTok = next("the face count");
    const nf = checkInt(name, nfTok[0], nfTok[1], "the face count");
    // an optional edge count on the same line as the counts
    if (at < tokens.length && tokens[at][0] === nfTok[0]) at++;
    const points = new Points();
    for (let i = 0; i < nv; i++) {
      const [line, xs] = next("vertex " + i);
      const ys = next("vertex " + i)[1];
      const zTok = next("vertex " + i);
      if (zTok[0] !== line) throw new ParseError(name, line, "vertex " + i + " needs x y z");
      points.add(name, line, xs, ys);
      if (numberOf(zTok[1]) !== 0) {
        throw new ParseError(name, line, "vertex " + i + " has z = " + zTok[1] + " (only planar meshes: 3D is not supported yet)");
      }
      while (at < tokens.length && tokens[at][0] === line) at++; // colours, normals
    }
    const triangles = [];
    const offsets = [0];
    const vertices = [];
    let allTriangles = true;
    for (let f = 0; f < nf; f++) {
      const [line, kText] = next("face " + f);
      const k = checkInt(name, line, kText, "a face size");
      if (k < 3) throw new ParseError(name, line, "face " + f + " has " + k + " vertices (< 3)");
      for (let j = 0; j < k; j++) {
        const tok = next("face " + f);
        if (tok[0] !== line) throw new ParseError(name, line, "face " + f + " lists fewer than " + k + " vertices");
        vertices.push(checkIndex(name, line, checkInt(name, line, tok[1], "a vertex index"), nv, "index"));
      }
      offsets.push(vertices.length);
      if (k !== 3) allTriangles = false;
      while (at < tokens.length && tokens[at][0] === line) at++; // face colours
    }
    if (at < tokens.length) throw new ParseError(name, tokens[at][0], "unexpected data after the last face");
    if (allTriangles) {
      for (let i = 0; i < vertices.length; i++) triangles.push(vertices[i]);
      return meshModel(name, points, triangles, []);
    }
    return meshModel(name, points, [], [], { polygons: { offsets: offsets, vertices: vertices } });
  }

  function parseNodeTable(name, text) {
    const lines = dataLines(text);
    if (!lines.length) throw new ParseError(name, null, "empty file");
    const [hline, header] = lines[0];
    const count = checkInt(name, hline, header[0], "the vertex count");
    const dim = header.length > 1 ? checkInt(name, hline, header[1], "the dimension") : 2;
    if (dim !== 2) throw new ParseError(name, hline, "dimension " + dim + " (only 2 is supported)");
    const attributes = header.length > 2 ? checkInt(name, hline, header[2], "the attribute count") : 0;
    const markers = header.length > 3 ? checkInt(name, hline, header[3], "the marker flag") : 0;
    if (lines.length - 1 < count) throw new ParseError(name, null, "the header announces " + count + " vertices, the file has " + (lines.length - 1) + " lines");
    const points = new Points();
    let base = 0;
    for (let i = 0; i < count; i++) {
      const [line, t] = lines[1 + i];
      if (t.length !== 3 + attributes + (markers ? 1 : 0)) {
        throw new ParseError(name, line, "expected " + (3 + attributes + (markers ? 1 : 0)) + " fields, found " + t.length);
      }
      const number = checkInt(name, line, t[0], "a vertex number");
      if (i === 0) {
        if (number !== 0 && number !== 1) throw new ParseError(name, line, "the first vertex is numbered " + number + " (0 or 1)");
        base = number;
      } else if (number !== base + i) {
        throw new ParseError(name, line, "vertex numbered " + number + ", expected " + (base + i));
      }
      points.add(name, line, t[1], t[2]);
    }
    return { points: points, base: base, rest: lines.slice(1 + count), count: count };
  }

  function parseEle(name, text, nodes) {
    const lines = dataLines(text);
    if (!lines.length) throw new ParseError(name, null, "empty file");
    const [hline, header] = lines[0];
    const count = checkInt(name, hline, header[0], "the triangle count");
    const corners = header.length > 1 ? checkInt(name, hline, header[1], "the corner count") : 3;
    if (corners !== 3) throw new ParseError(name, hline, corners + " corners per triangle (only 3 are supported)");
    if (lines.length - 1 !== count) throw new ParseError(name, null, "the header announces " + count + " triangles, the file has " + (lines.length - 1) + " lines");
    const triangles = new Array(count * 3);
    for (let i = 0; i < count; i++) {
      const [line, t] = lines[1 + i];
      if (t.length < 4) throw new ParseError(name, line, "a triangle needs a number and 3 corners");
      for (let j = 0; j < 3; j++) {
        const v = checkInt(name, line, t[1 + j], "a corner") - nodes.base;
        triangles[3 * i + j] = checkIndex(name, line, v, nodes.count, "corner");
      }
    }
    return triangles;
  }

  function parsePolySections(name, text, nodeFor) {
    const lines = dataLines(text);
    if (!lines.length) throw new ParseError(name, null, "empty file");
    const [hline, header] = lines[0];
    let nodes;
    let rest;
    if (checkInt(name, hline, header[0], "the vertex count") === 0) {
      nodes = nodeFor();
      if (!nodes) throw new ParseError(name, hline, "vertex count 0: open the .node file with the same name too");
      rest = lines.slice(1);
    } else {
      nodes = parseNodeTable(name, text);
      rest = nodes.rest;
    }
    let at = 0;
    const segments = [];
    const holes = [];
    const seeds = [];
    // a section: its count line, then that many lines of at least 3 fields, each given to take
    function section(countWhat, endsInside, tooShort, take) {
      const [cline, ch] = rest[at++];
      const count = checkInt(name, cline, ch[0], countWhat);
      for (let i = 0; i < count; i++) {
        if (at >= rest.length) throw new ParseError(name, null, endsInside);
        const [line, t] = rest[at++];
        if (t.length < 3) throw new ParseError(name, line, tooShort);
        take(line, t);
      }
    }
    if (at < rest.length) {
      section("the segment count", "file ends inside the segments", "a segment needs a number and 2 endpoints", function (line, t) {
        for (let j = 1; j <= 2; j++) {
          segments.push(checkIndex(name, line, checkInt(name, line, t[j], "an endpoint") - nodes.base, nodes.count, "endpoint"));
        }
      });
    }
    for (const target of [holes, seeds]) {
      if (at >= rest.length) break;
      section("a count", "file ends early", "expected a number and a point", function (line, t) {
        target.push(checkNumber(name, line, t[1], "a coordinate"), checkNumber(name, line, t[2], "a coordinate"));
      });
    }
    if (at < rest.length) throw new ParseError(name, rest[at][0], "unexpected data after the regions");
    return { nodes: nodes, segments: segments, holes: holes, seeds: seeds };
  }

  function parsePslgText(name, text) {
    const points = new Points();
    const triangles = [];
    const segments = [];
    const holes = [];
    const seeds = [];
    const pending = [];
    for (const [line, t] of dataLines(text)) {
      const tag = t[0];
      if (tag === "v") {
        if (t.length < 3) throw new ParseError(name, line, "a 'v' record needs x y");
        points.add(name, line, t[1], t[2]);
      } else if (tag === "t" || tag === "s") {
        const need = tag === "t" ? 3 : 2;
        if (t.length < need + 1) throw new ParseError(name, line, "a '" + tag + "' record needs " + need + " vertex ids");
        const ids = [];
        for (let j = 1; j <= need; j++) ids.push(checkInt(name, line, t[j], "a vertex id"));
        pending.push([line, tag, ids]);
      } else if (tag === "h" || tag === "r") {
        if (t.length < 3) throw new ParseError(name, line, "a '" + tag + "' record needs x y");
        (tag === "h" ? holes : seeds).push(checkNumber(name, line, t[1], "a coordinate"), checkNumber(name, line, t[2], "a coordinate"));
      } else if (tag !== "n") {
        throw new ParseError(name, line, "unknown record '" + tag + "' (expected v, s, h, r, t or n)");
      }
    }
    const count = points.x.length;
    for (const [line, tag, ids] of pending) {
      for (const id of ids) checkIndex(name, line, id, count, "vertex id");
      (tag === "t" ? triangles : segments).push.apply(tag === "t" ? triangles : segments, ids);
    }
    if (triangles.length && (holes.length || seeds.length)) {
      throw new ParseError(name, null, "'h' and 'r' records belong to a PSLG, not to a mesh with 't' records");
    }
    return meshModel(name, points, triangles, segments, { pslg: !triangles.length, holes: holes, seeds: seeds });
  }

  const MELLADO_SECTIONS = { vertices: "v", triangles: "t", neighbors: "n", neighbours: "n" };

  function isMelladoText(text) {
    // Mellado's programs write .txt files that start with a section header
    const first = dataLines(text.slice(0, 4096))[0];
    return Boolean(first) && Object.prototype.hasOwnProperty.call(MELLADO_SECTIONS, first[1][0].toLowerCase());
  }

  function parseMellado(name, text) {
    // sections Vertices / Triangles / Neighbors of 'v x y', 't a b c', 'n ...' lines
    // (specs/formats/mellado.md); 0-based, or 1-based when 0 is never used and N is
    const points = new Points();
    const corners = [];
    let section = null;
    for (const [line, t] of dataLines(text)) {
      const head = t[0].toLowerCase();
      if (Object.prototype.hasOwnProperty.call(MELLADO_SECTIONS, head)) {
        section = MELLADO_SECTIONS[head];
        continue;
      }
      if (section === null) throw new ParseError(name, line, "data before the first section (Vertices, Triangles or Neighbors)");
      if (head !== section) throw new ParseError(name, line, "a line of this section starts with '" + section + "', found '" + t[0] + "'");
      if (section === "v") {
        if (t.length !== 3) throw new ParseError(name, line, "a line of this section is 'v x y'");
        points.add(name, line, t[1], t[2]);
      } else if (section === "t") {
        if (t.length !== 4) throw new ParseError(name, line, "a line of this section is 't a b c'");
        corners.push([line, [1, 2, 3].map(function (j) {
          return checkInt(name, line, t[j], "a vertex index");
        })]);
      }
    }
    if (!corners.length) throw new ParseError(name, null, "the file has no Triangles section lines");
    const count = points.x.length;
    let low = Infinity;
    let high = -Infinity;
    for (const [, ids] of corners) for (const id of ids) {
      low = Math.min(low, id);
      high = Math.max(high, id);
    }
    const base = low === 1 && high === count ? 1 : 0;
    const triangles = [];
    for (const [line, ids] of corners) {
      for (const id of ids) {
        checkIndex(name, line, id - base, count, "vertex index");
        triangles.push(id - base);
      }
    }
    const notes = ["read in the browser (doubles; not validated: use geomexact check)"];
    if (base) notes.push("vertex indices are 1-based (0 is never used and N is)");
    return meshModel(name, points, triangles, [], { notes: notes });
  }

  function parseTriangleList(name, text) {
    const points = new Points();
    const ids = new Map();
    const triangles = [];
    for (const [line, t] of dataLines(text)) {
      if (t.length !== 6) throw new ParseError(name, line, "expected 6 numbers x1 y1 x2 y2 x3 y3, found " + t.length);
      for (let j = 0; j < 3; j++) {
        const key = t[2 * j] + " " + t[2 * j + 1];
        let id = ids.get(key);
        if (id === undefined) {
          id = points.x.length;
          ids.set(key, id);
          points.add(name, line, t[2 * j], t[2 * j + 1]);
        }
        triangles.push(id);
      }
    }
    return meshModel(name, points, triangles, []);
  }

  function extensionOf(name) {
    const dot = name.lastIndexOf(".");
    return dot >= 0 ? name.slice(dot).toLowerCase() : "";
  }

  function stemOf(name) {
    const dot = name.lastIndexOf(".");
    return dot >= 0 ? name.slice(0, dot) : name;
  }

  function parseFiles(files) {
    // files: [{name, text}]; returns a model.  Triangle files go together by stem.
    const byExtension = {};
    for (const file of files) {
      const extension = extensionOf(file.name);
      (byExtension[extension] = byExtension[extension] || []).push(file);
    }
    const pick = function (extension, stem) {
      const list = byExtension[extension] || [];
      for (const file of list) if (stemOf(file.name) === stem) return file;
      return null;
    };
    if (byExtension[".ele"]) {
      const ele = byExtension[".ele"][0];
      const stem = stemOf(ele.name);
      const node = pick(".node", stem);
      if (!node) throw new ParseError(ele.name, null, "open " + stem + ".node together with " + ele.name + " (select both files)");
      const nodes = parseNodeTable(node.name, node.text);
      const triangles = parseEle(ele.name, ele.text, nodes);
      let segments = [];
      const poly = pick(".poly", stem);
      const notes = ["read in the browser (doubles; not validated: use geomexact check)"];
      if (poly) {
        const sections = parsePolySections(poly.name, poly.text, function () {
          return nodes;
        });
        if (sections.nodes === nodes) {
          segments = sections.segments;
          notes.push("segments from " + poly.name);
        }
      }
      return meshModel(ele.name, nodes.points, triangles, segments, { notes: notes });
    }
    if (byExtension[".poly"]) {
      const poly = byExtension[".poly"][0];
      const sections = parsePolySections(poly.name, poly.text, function () {
        const node = pick(".node", stemOf(poly.name));
        return node ? parseNodeTable(node.name, node.text) : null;
      });
      return meshModel(poly.name, sections.nodes.points, [], sections.segments, {
        pslg: true, holes: sections.holes, seeds: sections.seeds,
      });
    }
    if (byExtension[".node"]) {
      const node = byExtension[".node"][0];
      const nodes = parseNodeTable(node.name, node.text);
      if (nodes.rest.length) throw new ParseError(node.name, nodes.rest[0][0], "unexpected data after the vertices");
      return meshModel(node.name, nodes.points, [], [], { pslg: true });
    }
    for (const extension of [".off", ".pslg", ".txt", ".mellado"]) {
      if (byExtension[extension]) {
        const file = byExtension[extension][0];
        if (extension === ".off") return parseOFF(file.name, file.text);
        if (extension === ".pslg") return parsePslgText(file.name, file.text);
        if (extension === ".mellado" || isMelladoText(file.text)) return parseMellado(file.name, file.text);
        return parseTriangleList(file.name, file.text);
      }
    }
    const names = files.map(function (f) {
      return f.name;
    }).join(", ");
    throw new ParseError(names || "(no file)", null, "no file the viewer can read (.off, .ele with its .node, .node, .poly, .pslg, .txt, .mellado)");
  }

  // ---------------------------------------------------------------------------------
  // geometry derived from the model: edges, statistics, picking
  // ---------------------------------------------------------------------------------
  function EdgeTable(capacity) {
    let size = 16;
    while (size < capacity * 2) size *= 2;
    this.mask = size - 1;
    this.ku = new Uint32Array(size).fill(0xffffffff);
    this.kv = new Uint32Array(size);
    this.count = new Uint8Array(size);
    this.used = [];
  }
  EdgeTable.prototype.add = function (a, b) {
    const u = a < b ? a : b;
    const v = a < b ? b : a;
    let h = (Math.imul(u, 0x9e3779b1) ^ Math.imul(v, 0x85ebca77)) & this.mask;
    for (;;) {
      const k = this.ku[h];
      if (k === 0xffffffff) {
        this.ku[h] = u;
        this.kv[h] = v;
        this.count[h] = 1;
        this.used.push(h);
        return;
      }
      if (k === u && this.kv[h] === v) {
        if (this.count[h] < 255) this.count[h]++;
        return;
      }
      h = (h + 1) & this.mask;
    }
  };

  function triangleMeasures(x1, y1, x2, y2, x3, y3, out) {
    // angles (degrees) at the three corners, the area and the signed cross product, in
    // doubles (display only)
    const cross = (x2 - x1) * (y3 - y1) - (y2 - y1) * (x3 - x1);
    const twice = Math.abs(cross);
    const deg = 180 / Math.PI;
    out[0] = Math.atan2(twice, (x2 - x1) * (x3 - x1) + (y2 - y1) * (y3 - y1)) * deg;
    out[1] = Math.atan2(twice, (x1 - x2) * (x3 - x2) + (y1 - y2) * (y3 - y2)) * deg;
    out[2] = 180 - out[0] - out[1];
    out[3] = twice / 2;
    out[4] = cross;
    return out;
  }

  function polygonArea(model, p) {
    const xy = model.xy;
    const v = model.polyVertices;
    const s = model.polyOffsets[p];
    const e = model.polyOffsets[p + 1];
    let twice = 0;
    for (let i = s; i < e; i++) {
      const a = v[i];
      const b = v[i + 1 < e ? i + 1 : s];
      twice += xy[2 * a] * xy[2 * b + 1] - xy[2 * b] * xy[2 * a + 1];
    }
    return twice / 2;
  }

  function computeDerived(model) {
    // unique edges, boundary edges, per-slot min angle and area, statistics
    const cells = model.cells;
    const alive = model.alive;
    const xy = model.xy;
    const table = new EdgeTable(model.aliveCount * 3 + (model.polyVertices.length || 0) + 16);
    const minAngle = new Float32Array(model.slots);
    const area = new Float64Array(model.slots);
    const m = new Float64Array(5);
    const stats = {
      minAngle: Infinity, maxAngle: -Infinity, minArea: Infinity, maxArea: -Infinity,
      totalArea: 0, faces: 0, clockwise: 0,
    };
    for (let s = 0; s < model.slots; s++) {
      if (!alive[s]) continue;
      const a = cells[3 * s];
      const b = cells[3 * s + 1];
      const c = cells[3 * s + 2];
      table.add(a, b);
      table.add(b, c);
      table.add(c, a);
      triangleMeasures(xy[2 * a], xy[2 * a + 1], xy[2 * b], xy[2 * b + 1], xy[2 * c], xy[2 * c + 1], m);
      const low = Math.min(m[0], m[1], m[2]);
      const high = Math.max(m[0], m[1], m[2]);
      minAngle[s] = low;
      area[s] = m[3];
      if (m[4] < 0) stats.clockwise++;
      if (low < stats.minAngle) stats.minAngle = low;
      if (high > stats.maxAngle) stats.maxAngle = high;
      if (m[3] < stats.minArea) stats.minArea = m[3];
      if (m[3] > stats.maxArea) stats.maxArea = m[3];
      stats.totalArea += m[3];
      stats.faces++;
    }
    const polyArea = new Float64Array(Math.max(model.polygons, 0));
    for (let p = 0; p < model.polygons; p++) {
      const s = model.polyOffsets[p];
      const e = model.polyOffsets[p + 1];
      for (let i = s; i < e; i++) table.add(model.polyVertices[i], model.polyVertices[i + 1 < e ? i + 1 : s]);
      const value = Math.abs(polygonArea(model, p));
      polyArea[p] = value;
      if (value < stats.minArea) stats.minArea = value;
      if (value > stats.maxArea) stats.maxArea = value;
      stats.totalArea += value;
      stats.faces++;
    }
    const used = table.used;
    const edges = new Uint32Array(used.length * 2);
    const boundary = [];
    for (let i = 0; i < used.length; i++) {
      const h = used[i];
      edges[2 * i] = table.ku[h];
      edges[2 * i + 1] = table.kv[h];
      if (table.count[h] === 1) boundary.push(table.ku[h], table.kv[h]);
    }
    let segments = 0;
    for (let s = 0; s < model.segSlots; s++) if (model.segAlive[s]) segments++;
    stats.edges = used.length;
    stats.boundaryEdges = boundary.length / 2;
    stats.segments = segments;
    if (!stats.faces) {
      stats.minAngle = stats.maxAngle = stats.minArea = stats.maxArea = NaN;
    }
    model.derived = {
      edges: edges, boundary: new Uint32Array(boundary), minAngle: minAngle, area: area,
      polyArea: polyArea, stats: stats, pick: null,
    };
  }

  function bounds(model) {
    const xy = model.xy;
    let x0 = Infinity;
    let y0 = Infinity;
    let x1 = -Infinity;
    let y1 = -Infinity;
    for (let i = 0; i < xy.length; i += 2) {
      const x = xy[i];
      const y = xy[i + 1];
      if (!Number.isFinite(x) || !Number.isFinite(y)) continue;
      if (x < x0) x0 = x;
      if (x > x1) x1 = x;
      if (y < y0) y0 = y;
      if (y > y1) y1 = y;
    }
    if (x0 > x1) {
      x0 = y0 = -1;
      x1 = y1 = 1;
    }
    return { x0: x0, y0: y0, x1: x1, y1: y1 };
  }

  function normalise(model) {
    // coordinates centred and scaled to about [-0.5, 0.5]: Path2D keeps single precision
    const box = bounds(model);
    const cx = (box.x0 + box.x1) / 2;
    const cy = (box.y0 + box.y1) / 2;
    const extent = Math.max(box.x1 - box.x0, box.y1 - box.y0) || 1;
    const inv = 1 / extent;
    const xy = model.xy;
    const n = new Float64Array(xy.length);
    for (let i = 0; i < xy.length; i += 2) {
      n[i] = (xy[i] - cx) * inv;
      n[i + 1] = (xy[i + 1] - cy) * inv;
    }
    model.box = box;
    model.norm = { xy: n, cx: cx, cy: cy, inv: inv, w: (box.x1 - box.x0) * inv, h: (box.y1 - box.y0) * inv };
  }

  function buildPick(model) {
    // a uniform grid over the normalised box; each face is listed in every cell its
    // bounding box meets (CSR arrays)
    const nxy = model.norm.xy;
    const faces = [];
    if (model.kind === "polygons") {
      for (let p = 0; p < model.polygons; p++) faces.push(p);
    } else if (model.kind === "triangles") {
      for (let s = 0; s < model.slots; s++) if (model.alive[s]) faces.push(s);
    } else {
      for (let v = 0; v < model.vertexCount; v++) faces.push(v);
    }
    const count = Math.max(faces.length, 1);
    const g = Math.max(1, Math.min(1024, Math.ceil(Math.sqrt(count))));
    const x0 = -0.5 - 1e-9;
    const y0 = -0.5 - 1e-9;
    const cell = (1 + 2e-9) / g;
    const boxes = new Int32Array(faces.length * 4);
    const clamp = function (value) {
      return Math.max(0, Math.min(g - 1, Math.floor(value)));
    };
    const v = model.polyVertices;
    for (let f = 0; f < faces.length; f++) {
      let bx0 = Infinity;
      let by0 = Infinity;
      let bx1 = -Infinity;
      let by1 = -Infinity;
      const visit = function (vertex) {
        const x = nxy[2 * vertex];
        const y = nxy[2 * vertex + 1];
        if (x < bx0) bx0 = x;
        if (x > bx1) bx1 = x;
        if (y < by0) by0 = y;
        if (y > by1) by1 = y;
      };
      const id = faces[f];
      if (model.kind === "polygons") {
        for (let i = model.polyOffsets[id]; i < model.polyOffsets[id + 1]; i++) visit(v[i]);
      } else if (model.kind === "triangles") {
        visit(model.cells[3 * id]);
        visit(model.cells[3 * id + 1]);
        visit(model.cells[3 * id + 2]);
      } else {
        visit(id);
      }
      boxes[4 * f] = clamp((bx0 - x0) / cell);
      boxes[4 * f + 1] = clamp((by0 - y0) / cell);
      boxes[4 * f + 2] = clamp((bx1 - x0) / cell);
      boxes[4 * f + 3] = clamp((by1 - y0) / cell);
    }
    const starts = new Uint32Array(g * g + 1);
    for (let f = 0; f < faces.length; f++) {
      for (let j = boxes[4 * f + 1]; j <= boxes[4 * f + 3]; j++) {
        for (let i = boxes[4 * f]; i <= boxes[4 * f + 2]; i++) starts[j * g + i + 1]++;
      }
    }
    for (let c = 0; c < g * g; c++) starts[c + 1] += starts[c];
    const fill = starts.slice(0, g * g);
    const items = new Uint32Array(starts[g * g]);
    for (let f = 0; f < faces.length; f++) {
      for (let j = boxes[4 * f + 1]; j <= boxes[4 * f + 3]; j++) {
        for (let i = boxes[4 * f]; i <= boxes[4 * f + 2]; i++) items[fill[j * g + i]++] = faces[f];
      }
    }
    return { g: g, x0: x0, y0: y0, cell: cell, starts: starts, items: items };
  }

  function pick(model, nx, ny, radius) {
    // the face (triangle slot / polygon) under the normalised point, or the nearest vertex
    // within radius for a PSLG; -1 when none
    if (!model.derived) return -1;
    if (!model.derived.pick) model.derived.pick = buildPick(model);
    const grid = model.derived.pick;
    const nxy = model.norm.xy;
    if (model.kind === "pslg") {
      let best = -1;
      let bestD = radius * radius;
      const i0 = Math.floor((nx - radius - grid.x0) / grid.cell);
      const i1 = Math.floor((nx + radius - grid.x0) / grid.cell);
      const j0 = Math.floor((ny - radius - grid.y0) / grid.cell);
      const j1 = Math.floor((ny + radius - grid.y0) / grid.cell);
      for (let j = Math.max(0, j0); j <= Math.min(grid.g - 1, j1); j++) {
        for (let i = Math.max(0, i0); i <= Math.min(grid.g - 1, i1); i++) {
          const c = j * grid.g + i;
          for (let k = grid.starts[c]; k < grid.starts[c + 1]; k++) {
            const vtx = grid.items[k];
            const dx = nxy[2 * vtx] - nx;
            const dy = nxy[2 * vtx + 1] - ny;
            const d = dx * dx + dy * dy;
            if (d <= bestD) {
              bestD = d;
              best = vtx;
            }
          }
        }
      }
      return best;
    }
    const i = Math.floor((nx - grid.x0) / grid.cell);
    const j = Math.floor((ny - grid.y0) / grid.cell);
    if (i < 0 || j < 0 || i >= grid.g || j >= grid.g) return -1;
    const c = j * grid.g + i;
    for (let k = grid.starts[c]; k < grid.starts[c + 1]; k++) {
      const id = grid.items[k];
      if (model.kind === "triangles") {
        const a = model.cells[3 * id];
        const b = model.cells[3 * id + 1];
        const d = model.cells[3 * id + 2];
        const ax = nxy[2 * a], ay = nxy[2 * a + 1];
        const bx = nxy[2 * b], by = nxy[2 * b + 1];
        const cx = nxy[2 * d], cy = nxy[2 * d + 1];
        const s1 = (bx - ax) * (ny - ay) - (by - ay) * (nx - ax);
        const s2 = (cx - bx) * (ny - by) - (cy - by) * (nx - bx);
        const s3 = (ax - cx) * (ny - cy) - (ay - cy) * (nx - cx);
        if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) return id;
      } else {
        const v = model.polyVertices;
        const s = model.polyOffsets[id];
        const e = model.polyOffsets[id + 1];
        let inside = false;
        for (let p = s, q = e - 1; p < e; q = p++) {
          const xp = nxy[2 * v[p]], yp = nxy[2 * v[p] + 1];
          const xq = nxy[2 * v[q]], yq = nxy[2 * v[q] + 1];
          if ((yp > ny) !== (yq > ny) && nx < ((xq - xp) * (ny - yp)) / (yq - yp) + xp) inside = !inside;
        }
        if (inside) return id;
      }
    }
    return -1;
  }

  // ---------------------------------------------------------------------------------
  // colours
  // ---------------------------------------------------------------------------------
  const QUALITY_BINS = [
    [10, "#d7301f", "< 10°"], [20, "#fc8d59", "10–20°"], [30, "#fdcc8a", "20–30°"],
    [40, "#c7e9b4", "30–40°"], [50, "#7fcdbb", "40–50°"], [Infinity, "#2c7fb8", "≥ 50°"],
  ];
  const SEQUENTIAL = ["#440154", "#46327e", "#365c8d", "#277f8e", "#1fa187", "#4ac16d", "#a0da39", "#fde725"];
  const CATEGORICAL = ["#8dd3c7", "#ffffb3", "#bebada", "#fb8072", "#80b1d3", "#fdb462", "#b3de69", "#fccde5", "#d9d9d9", "#bc80bd"];
  const PLAIN_FILL = "#e3ecf7";

  function colouring(model, mode) {
    // {bins: [{color, label}], binOf(face) -> index}
    const d = model.derived;
    if (mode === "min_angle" && model.kind === "triangles") {
      return {
        bins: QUALITY_BINS.map(function (b) {
          return { color: b[1], label: b[2] };
        }),
        binOf: function (s) {
          const a = d.minAngle[s];
          for (let i = 0; i < QUALITY_BINS.length; i++) if (a < QUALITY_BINS[i][0]) return i;
          return QUALITY_BINS.length - 1;
        },
      };
    }
    if (mode === "area") {
      const values = model.kind === "polygons" ? d.polyArea : d.area;
      const low = Math.log10(Math.max(d.stats.minArea, 1e-300));
      const high = Math.log10(Math.max(d.stats.maxArea, 1e-300));
      const span = high - low || 1;
      const bins = SEQUENTIAL.map(function (color, i) {
        const from = low + (span * i) / SEQUENTIAL.length;
        return { color: color, label: "≥ " + formatNumber(Math.pow(10, from), 3) };
      });
      return {
        bins: bins,
        binOf: function (s) {
          const t = (Math.log10(Math.max(values[s], 1e-300)) - low) / span;
          return Math.max(0, Math.min(SEQUENTIAL.length - 1, Math.floor(t * SEQUENTIAL.length)));
        },
      };
    }
    if (mode === "region" && model.regions) {
      const distinct = Array.from(new Set(Array.from(model.regions).filter(function (v) {
        return !Number.isNaN(v);
      }))).sort(function (a, b) {
        return a - b;
      });
      const index = new Map(distinct.map(function (v, i) {
        return [v, i];
      }));
      const bins = distinct.map(function (v, i) {
        return { color: CATEGORICAL[i % CATEGORICAL.length], label: "region " + formatNumber(v) };
      });
      bins.push({ color: PLAIN_FILL, label: "no region" });
      return {
        bins: bins,
        binOf: function (s) {
          const v = model.regions[s];
          return Number.isNaN(v) ? bins.length - 1 : index.get(v);
        },
      };
    }
    if (model.kind === "polygons") {
      return {
        bins: [{ color: PLAIN_FILL, label: "convex" }, { color: "#f6c6a8", label: "non-convex" }],
        binOf: function (p) {
          return model.nonconvex[p] ? 1 : 0;
        },
      };
    }
    return { bins: [{ color: PLAIN_FILL, label: "" }], binOf: function () {
      return 0;
    } };
  }

  // ---------------------------------------------------------------------------------
  // scanline fills (device pixels, pixel centres, no anti-aliasing: edges are stroked on top)
  // ---------------------------------------------------------------------------------
  const LITTLE_ENDIAN = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;
  const WHITE = 0xffffffff;

  function packColour(hex) {
    const r = parseInt(hex.slice(1, 3), 16);
    const g = parseInt(hex.slice(3, 5), 16);
    const b = parseInt(hex.slice(5, 7), 16);
    return LITTLE_ENDIAN ? ((255 << 24) | (b << 16) | (g << 8) | r) >>> 0 : ((r << 24) | (g << 16) | (b << 8) | 255) >>> 0;
  }

  const SEAM = 1e-7; // pixel centres this close to a shared edge go to both faces

  function fillSpan(px, W, row, left, right, colour) {
    const x0 = Math.max(0, Math.ceil(left - 0.5 - SEAM));
    const x1 = Math.min(W - 1, Math.floor(right - 0.5 + SEAM));
    if (x0 <= x1) px.fill(colour, row * W + x0, row * W + x1 + 1);
  }

  function fillTriangle(px, W, H, x0, y0, x1, y1, x2, y2, colour) {
    let t;
    if (y1 < y0) {
      t = x0; x0 = x1; x1 = t;
      t = y0; y0 = y1; y1 = t;
    }
    if (y2 < y0) {
      t = x0; x0 = x2; x2 = t;
      t = y0; y0 = y2; y2 = t;
    }
    if (y2 < y1) {
      t = x1; x1 = x2; x2 = t;
      t = y1; y1 = y2; y2 = t;
    }
    if (y2 - y0 <= 0) return;
    if (Math.max(x0, x1, x2) < -1 || Math.min(x0, x1, x2) > W + 1) return;
    const rowStart = Math.max(0, Math.ceil(y0 - 0.5 - SEAM));
    const rowEnd = Math.min(H - 1, Math.floor(y2 - 0.5 + SEAM));
    const long = (x2 - x0) / (y2 - y0);
    const upper = y1 > y0 ? (x1 - x0) / (y1 - y0) : 0;
    const lower = y2 > y1 ? (x2 - x1) / (y2 - y1) : 0;
    for (let row = rowStart; row <= rowEnd; row++) {
      const cy = Math.min(Math.max(row + 0.5, y0), y2);
      const xa = x0 + long * (cy - y0);
      let xb;
      if (cy < y1) xb = x0 + upper * (cy - y0);
      else if (y2 > y1) xb = x1 + lower * (cy - y1);
      else xb = cy === y1 ? Math.max(x1, x2) : x1;
      if (xa < xb) fillSpan(px, W, row, xa, xb, colour);
      else fillSpan(px, W, row, xb, xa, colour);
    }
  }

  function fillPolygon(px, W, H, xs, ys, colour) {
    // even-odd scanline fill of one polygon
    const n = xs.length;
    let top = Infinity;
    let bottom = -Infinity;
    let left = Infinity;
    let right = -Infinity;
    for (let i = 0; i < n; i++) {
      if (ys[i] < top) top = ys[i];
      if (ys[i] > bottom) bottom = ys[i];
      if (xs[i] < left) left = xs[i];
      if (xs[i] > right) right = xs[i];
    }
    if (right < -1 || left > W + 1) return;
    const rowStart = Math.max(0, Math.ceil(top - 0.5 - SEAM));
    const rowEnd = Math.min(H - 1, Math.floor(bottom - 0.5 + SEAM));
    const crossings = [];
    for (let row = rowStart; row <= rowEnd; row++) {
      const cy = row + 0.5;
      crossings.length = 0;
      for (let i = 0, j = n - 1; i < n; j = i++) {
        const yi = ys[i];
        const yj = ys[j];
        if ((yi > cy) !== (yj > cy)) crossings.push(xs[i] + ((cy - yi) * (xs[j] - xs[i])) / (yj - yi));
      }
      crossings.sort(function (a, b) {
        return a - b;
      });
      for (let c = 0; c + 1 < crossings.length; c += 2) fillSpan(px, W, row, crossings[c], crossings[c + 1], colour);
    }
  }

  // ---------------------------------------------------------------------------------
  // the 2D renderer
  // ---------------------------------------------------------------------------------
  function Renderer2D(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext("2d", { alpha: false });
    this.cache = document.createElement("canvas");
    this.view = { scale: 1, tx: 0, ty: 0, angle: 0 };
    this.cacheView = null;
    this.paths = null;
    this.lastRenderMs = 0;
    this.frameMs = 0;
    this.width = 1;
    this.height = 1;
    this.dpr = 1;
    this.options = { fill: "none", edges: true, vertices: false };
    this.hover = -1;
  }

  Renderer2D.prototype.resize = function (width, height) {
    this.dpr = window.devicePixelRatio || 1;
    this.width = Math.max(1, Math.floor(width));
    this.height = Math.max(1, Math.floor(height));
    this.canvas.width = Math.round(this.width * this.dpr);
    this.canvas.height = Math.round(this.height * this.dpr);
    this.canvas.style.width = this.width + "px";
    this.canvas.style.height = this.height + "px";
    this.cacheView = null;
  };

  Renderer2D.prototype.fit = function (model) {
    // the whole mesh in view, at the current rotation (its box's rotated extents)
    const angle = this.view.angle || 0;
    const c = Math.abs(Math.cos(angle));
    const s = Math.abs(Math.sin(angle));
    const w = Math.max(c * model.norm.w + s * model.norm.h, 1e-12);
    const h = Math.max(s * model.norm.w + c * model.norm.h, 1e-12);
    const scale = 0.92 * Math.min(this.width / w, this.height / h);
    this.view = { scale: Number.isFinite(scale) ? scale : 1, tx: this.width / 2, ty: this.height / 2,
      angle: angle };
    this.cacheView = null;
  };

  Renderer2D.prototype.toNormal = function (sx, sy) {
    // the inverse of toScreen: undo the translation and scale, then the rotation
    const v = this.view;
    const x = (sx - v.tx) / v.scale;
    const y = -(sy - v.ty) / v.scale;
    const c = Math.cos(v.angle);
    const s = Math.sin(v.angle);
    return [c * x + s * y, -s * x + c * y];
  };

  Renderer2D.prototype.toScreen = function (nx, ny) {
    // normalised coordinates (y up) to CSS pixels (y down): rotate by the view's angle
    // (counter-clockwise as seen), scale, translate
    const v = this.view;
    const c = Math.cos(v.angle);
    const s = Math.sin(v.angle);
    return [v.tx + v.scale * (c * nx - s * ny), v.ty - v.scale * (s * nx + c * ny)];
  };

  Renderer2D.prototype.worldTransform = function () {
    // the canvas transform of toScreen, in device pixels
    const v = this.view;
    const k = this.dpr * v.scale;
    const c = Math.cos(v.angle);
    const s = Math.sin(v.angle);
    this.ctx.setTransform(k * c, -k * s, -k * s, -k * c, this.dpr * v.tx, this.dpr * v.ty);
  };

  Renderer2D.prototype.rotateAt = function (sx, sy, radians) {
    // turn the view by ``radians`` (counter-clockwise as seen) about the screen point
    // (sx, sy), which stays where it is
    const v = this.view;
    const c = Math.cos(radians);
    const s = Math.sin(radians);
    const dx = v.tx - sx;
    const dy = v.ty - sy;
    v.tx = sx + c * dx + s * dy;
    v.ty = sy - s * dx + c * dy;
    v.angle = ((v.angle + radians) % (2 * Math.PI) + 2 * Math.PI) % (2 * Math.PI);
  };

  Renderer2D.prototype.zoomAt = function (sx, sy, factor) {
    const v = this.view;
    const scale = Math.max(1e-3, Math.min(1e12, v.scale * factor));
    const f = scale / v.scale;
    v.tx = sx - (sx - v.tx) * f;
    v.ty = sy - (sy - v.ty) * f;
    v.scale = scale;
  };

  Renderer2D.prototype.panBy = function (dx, dy) {
    this.view.tx += dx;
    this.view.ty += dy;
  };

  Renderer2D.prototype.buildPaths = function (model) {
    // the fill colour of every face (drawn by the scanline rasteriser) and Path2D batches,
    // in normalised coordinates, of the edges, boundary, segments and the step's changes
    const nxy = model.norm.xy;
    const d = model.derived;
    const colour = colouring(model, this.options.fill);
    const bins = colour.bins.map(function (bin) {
      return { color: bin.color, label: bin.label, count: 0 };
    });
    const faceCount = model.kind === "polygons" ? model.polygons : model.slots;
    const faceBin = new Uint8Array(Math.max(faceCount, 0));
    if (model.kind === "triangles") {
      for (let s = 0; s < model.slots; s++) {
        if (!model.alive[s]) continue;
        const bin = colour.binOf(s);
        faceBin[s] = bin;
        bins[bin].count++;
      }
    } else if (model.kind === "polygons") {
      for (let p = 0; p < model.polygons; p++) {
        const bin = colour.binOf(p);
        faceBin[p] = bin;
        bins[bin].count++;
      }
    }
    // never closePath(): in Chromium it makes building a Path2D quadratic in its size; a
    // line back to the start closes the outline
    const face = function (path, a, b, c) {
      path.moveTo(nxy[2 * a], nxy[2 * a + 1]);
      path.lineTo(nxy[2 * b], nxy[2 * b + 1]);
      path.lineTo(nxy[2 * c], nxy[2 * c + 1]);
      path.lineTo(nxy[2 * a], nxy[2 * a + 1]);
    };
    const lines = function (pairs) {
      const path = new Path2D();
      for (let i = 0; i < pairs.length; i += 2) {
        const a = pairs[i];
        const b = pairs[i + 1];
        path.moveTo(nxy[2 * a], nxy[2 * a + 1]);
        path.lineTo(nxy[2 * b], nxy[2 * b + 1]);
      }
      return path;
    };
    const segPairs = [];
    for (let s = 0; s < model.segSlots; s++) {
      if (model.segAlive[s]) segPairs.push(model.segCells[2 * s], model.segCells[2 * s + 1]);
    }
    const added = new Path2D();
    const removed = new Path2D();
    let addedCount = 0;
    let removedCount = 0;
    const h = model.history;
    if (h && model.step > 0) {
      const k = model.step;
      for (let i = h.addedOffsets[k - 1]; i < h.addedOffsets[k]; i++) {
        const s = h.added[i];
        face(added, model.cells[3 * s], model.cells[3 * s + 1], model.cells[3 * s + 2]);
        addedCount++;
      }
      for (let i = h.removedOffsets[k - 1]; i < h.removedOffsets[k]; i++) {
        const s = h.removed[i];
        if (model.alive[s]) continue;
        face(removed, model.cells[3 * s], model.cells[3 * s + 1], model.cells[3 * s + 2]);
        removedCount++;
      }
    }
    this.paths = {
      bins: bins,
      binColours: new Uint32Array(bins.map(function (bin) {
        return packColour(bin.color);
      })),
      faceBin: faceBin,
      legend: bins.length > 1 || this.options.fill !== "none" ? bins : [],
      edges: lines(d.edges),
      edgeCount: d.edges.length / 2,
      boundary: lines(d.boundary),
      segments: lines(segPairs),
      added: addedCount ? added : null,
      removed: removedCount ? removed : null,
    };
  };

  Renderer2D.prototype.rasterise = function (model) {
    // the faces filled by a scanline rasteriser into an ImageData (device pixels): for
    // hundreds of thousands of faces far faster than filling paths, and exact tiling (a
    // pixel centre on a shared edge goes to both faces: no seams)
    const W = this.canvas.width;
    const H = this.canvas.height;
    if (!this.image || this.image.width !== W || this.image.height !== H) {
      this.image = this.ctx.createImageData(W, H);
      this.pixels = new Uint32Array(this.image.data.buffer);
    }
    const px = this.pixels;
    px.fill(WHITE);
    const p = this.paths;
    const v = this.view;
    const k = this.dpr * v.scale;
    const ox = this.dpr * v.tx;
    const oy = this.dpr * v.ty;
    // device pixels of normalised (x, y): (kxx x + kxy y + ox, kyx x + kyy y + oy)
    const kxx = k * Math.cos(v.angle);
    const kyx = -k * Math.sin(v.angle);
    const kxy = kyx;
    const kyy = -kxx;
    const nxy = model.norm.xy;
    if (model.kind === "triangles") {
      const cells = model.cells;
      for (let s = 0; s < model.slots; s++) {
        if (!model.alive[s]) continue;
        const a = 2 * cells[3 * s];
        const b = 2 * cells[3 * s + 1];
        const c = 2 * cells[3 * s + 2];
        fillTriangle(px, W, H,
          kxx * nxy[a] + kxy * nxy[a + 1] + ox, kyx * nxy[a] + kyy * nxy[a + 1] + oy,
          kxx * nxy[b] + kxy * nxy[b + 1] + ox, kyx * nxy[b] + kyy * nxy[b + 1] + oy,
          kxx * nxy[c] + kxy * nxy[c + 1] + ox, kyx * nxy[c] + kyy * nxy[c + 1] + oy,
          p.binColours[p.faceBin[s]]);
      }
    } else if (model.kind === "polygons") {
      const v2 = model.polyVertices;
      const xs = [];
      const ys = [];
      for (let q = 0; q < model.polygons; q++) {
        xs.length = 0;
        ys.length = 0;
        for (let i = model.polyOffsets[q]; i < model.polyOffsets[q + 1]; i++) {
          const x = nxy[2 * v2[i]];
          const y = nxy[2 * v2[i] + 1];
          xs.push(kxx * x + kxy * y + ox);
          ys.push(kyx * x + kyy * y + oy);
        }
        fillPolygon(px, W, H, xs, ys, p.binColours[p.faceBin[q]]);
      }
    }
    this.ctx.putImageData(this.image, 0, 0);
  };

  Renderer2D.prototype.render = function (model) {
    const started = performance.now();
    const ctx = this.ctx;
    const v = this.view;
    const dpr = this.dpr;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    if (!model || !this.paths) {
      ctx.fillStyle = "#ffffff";
      ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
      return;
    }
    this.rasterise(model);
    const p = this.paths;
    const unit = 1 / v.scale;
    this.worldTransform();
    ctx.lineJoin = "miter";
    ctx.lineCap = "butt";
    if (this.options.edges && p.edgeCount) {
      // below one device pixel Skia strokes thin lines on a fast path; many edges get it
      const width = p.edgeCount > 20000 ? Math.min(0.6, 0.9 / dpr) : 0.6;
      ctx.strokeStyle = "#3b5b8c";
      ctx.lineWidth = width * unit;
      ctx.stroke(p.edges);
    }
    ctx.lineJoin = "round";
    ctx.lineCap = "round";
    ctx.strokeStyle = "#10233f";
    ctx.lineWidth = 1.6 * unit;
    ctx.stroke(p.boundary);
    ctx.strokeStyle = "#b3261e";
    ctx.lineWidth = 2.2 * unit;
    ctx.stroke(p.segments);
    if (p.added) {
      ctx.fillStyle = "rgba(255, 140, 0, 0.6)";
      ctx.fill(p.added);
      ctx.strokeStyle = "#c25400";
      ctx.lineWidth = 1.5 * unit;
      ctx.stroke(p.added);
    }
    if (p.removed) {
      ctx.setLineDash([4 * unit, 3 * unit]);
      ctx.strokeStyle = "#7b1fa2";
      ctx.lineWidth = 1.5 * unit;
      ctx.stroke(p.removed);
      ctx.setLineDash([]);
    }
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    this.drawPoints(model);
    this.lastRenderMs = performance.now() - started;
    this.saveCache();
    this.drawOverlay(model);
  };

  Renderer2D.prototype.drawOverlay = function (model) {
    // what changes without the geometry changing: the hovered face
    const v = this.view;
    const dpr = this.dpr;
    this.worldTransform();
    this.drawHover(model, 1 / v.scale);
    this.ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    this.drawVertexMark(model);
  };

  Renderer2D.prototype.slow = function () {
    // a full frame (script + rasterisation, less one vsync) too slow to follow the pointer
    return Math.max(this.lastRenderMs, this.frameMs - 17) > 35;
  };

  Renderer2D.prototype.cacheCurrent = function () {
    const c = this.cacheView;
    const v = this.view;
    return c && c.scale === v.scale && c.tx === v.tx && c.ty === v.ty && c.angle === v.angle;
  };

  Renderer2D.prototype.drawHover = function (model, unit) {
    if (this.hover < 0) return;
    const ctx = this.ctx;
    const nxy = model.norm.xy;
    const path = new Path2D();
    if (model.kind === "triangles") {
      const s = this.hover;
      if (!model.alive[s]) return;
      for (let j = 0; j <= 3; j++) {
        const a = model.cells[3 * s + (j % 3)];
        if (j === 0) path.moveTo(nxy[2 * a], nxy[2 * a + 1]);
        else path.lineTo(nxy[2 * a], nxy[2 * a + 1]);
      }
    } else if (model.kind === "polygons") {
      const v = model.polyVertices;
      const s = model.polyOffsets[this.hover];
      const e = model.polyOffsets[this.hover + 1];
      path.moveTo(nxy[2 * v[s]], nxy[2 * v[s] + 1]);
      for (let i = s + 1; i < e; i++) path.lineTo(nxy[2 * v[i]], nxy[2 * v[i] + 1]);
      path.lineTo(nxy[2 * v[s]], nxy[2 * v[s] + 1]);
    } else {
      return;
    }
    ctx.fillStyle = "rgba(17, 17, 17, 0.12)";
    ctx.fill(path);
    ctx.strokeStyle = "#111111";
    ctx.lineWidth = 2.5 * unit;
    ctx.stroke(path);
  };

  Renderer2D.prototype.drawPoints = function (model) {
    const ctx = this.ctx;
    const self = this;
    const nxy = model.norm.xy;
    const marker = function (xy, color, draw) {
      ctx.strokeStyle = color;
      ctx.lineWidth = 2;
      for (let i = 0; i < xy.length; i += 2) {
        const [x, y] = self.toScreen((xy[i] - model.norm.cx) * model.norm.inv,
          (xy[i + 1] - model.norm.cy) * model.norm.inv);
        draw(x, y);
      }
    };
    const showVertices = this.options.vertices || model.kind === "pslg" ||
      (model.kind === "triangles" && model.aliveCount === 0);
    if (showVertices && model.vertexCount <= 300000) {
      ctx.fillStyle = "#1f3b73";
      const size = model.vertexCount > 20000 ? 2 : 3;
      const w = this.width;
      const h = this.height;
      for (let i = 0; i < model.vertexCount; i++) {
        const [x, y] = this.toScreen(nxy[2 * i], nxy[2 * i + 1]);
        if (x < -4 || y < -4 || x > w + 4 || y > h + 4) continue;
        ctx.fillRect(x - size / 2, y - size / 2, size, size);
      }
    }
    marker(model.holes, "#c62828", function (x, y) {
      ctx.beginPath();
      ctx.moveTo(x - 5, y - 5);
      ctx.lineTo(x + 5, y + 5);
      ctx.moveTo(x - 5, y + 5);
      ctx.lineTo(x + 5, y - 5);
      ctx.stroke();
    });
    marker(model.seeds, "#2e7d32", function (x, y) {
      ctx.beginPath();
      ctx.moveTo(x - 6, y);
      ctx.lineTo(x + 6, y);
      ctx.moveTo(x, y - 6);
      ctx.lineTo(x, y + 6);
      ctx.stroke();
    });
  };

  Renderer2D.prototype.drawVertexMark = function (model) {
    const ctx = this.ctx;
    const nxy = model.norm.xy;
    if (model.kind === "pslg" && this.hover >= 0) {
      const [x, y] = this.toScreen(nxy[2 * this.hover], nxy[2 * this.hover + 1]);
      ctx.strokeStyle = "#111111";
      ctx.lineWidth = 2;
      ctx.strokeRect(x - 5, y - 5, 10, 10);
    }
  };

  Renderer2D.prototype.saveCache = function () {
    this.cache.width = this.canvas.width;
    this.cache.height = this.canvas.height;
    this.cache.getContext("2d").drawImage(this.canvas, 0, 0);
    this.cacheView = { scale: this.view.scale, tx: this.view.tx, ty: this.view.ty,
      angle: this.view.angle };
  };

  Renderer2D.prototype.renderCached = function () {
    // the last full frame moved and scaled to the current view (a stand-in while panning)
    const c = this.cacheView;
    const ctx = this.ctx;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = "#ffffff";
    ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
    const f = this.view.scale / c.scale;
    const dx = this.view.tx - c.tx * f;
    const dy = this.view.ty - c.ty * f;
    ctx.drawImage(this.cache, dx * this.dpr, dy * this.dpr, this.canvas.width * f, this.canvas.height * f);
  };

  const RENDERERS = { 2: Renderer2D };

  // ---------------------------------------------------------------------------------
  // the page
  // ---------------------------------------------------------------------------------
  function Viewer() {
    this.canvas = $("view");
    this.stage = $("stage");
    const Renderer = RENDERERS[2];
    this.renderer = new Renderer(this.canvas);
    this.model = null;
    this.frame = 0;
    this.slowTimer = 0;
    this.steps = null;  // the trace panel's controls (step_controls.js), made in bind()
    this.pointers = new Map();
    this.pinch = null;
    this.timings = { decode: 0, derived: 0, paths: 0 };
    this.messageTimer = 0;
  }

  Viewer.prototype.setModel = function (model) {
    const Renderer = RENDERERS[model.dimension];
    if (!Renderer) {
      throw new Error("this viewer draws 2D meshes; a " + model.dimension + "D scene needs a newer viewer");
    }
    if (!(this.renderer instanceof Renderer)) this.renderer = new Renderer(this.canvas);
    if (this.steps) this.steps.stop();
    this.model = model;
    this.renderer.hover = -1;
    normalise(model);
    this.refreshGeometry();
    this.resize();
    this.renderer.fit(model);
    this.denseDefaults(model);
    this.setupControls();
    this.showStats();
    this.requestRender();
  };

  const MIN_EDGE_PIXELS = 3;  // as geomexact.viz.pictures: below it edges are a solid smear

  Viewer.prototype.denseDefaults = function (model) {
    // a mesh whose edges are under MIN_EDGE_PIXELS when fitted opens as its picture does:
    // filled by smallest angle, edges hidden (only when no fill was chosen)
    const r = this.renderer;
    if (model.kind !== "triangles" || r.options.fill !== "none" || !model.slots) return;
    const n = model.norm.xy;
    const lengths = [];
    const every = Math.max(1, Math.floor(model.slots / 20000));
    for (let s = 0; s < model.slots; s += every) {
      if (!model.alive[s]) continue;
      const a = model.cells[3 * s];
      const b = model.cells[3 * s + 1];
      lengths.push(Math.hypot(n[2 * b] - n[2 * a], n[2 * b + 1] - n[2 * a + 1]));
    }
    if (!lengths.length) return;
    lengths.sort(function (x, y) {
      return x - y;
    });
    if (lengths[lengths.length >> 1] * r.view.scale >= MIN_EDGE_PIXELS) return;
    r.options.fill = "min_angle";
    r.options.edges = false;
    $("fill").value = "min_angle";
    $("show-edges").checked = false;
    this.refreshGeometry();
    model.notes = (model.notes || []).concat(
      ["a dense mesh: filled by smallest angle, edges hidden (as its picture)"]);
  };

  Viewer.prototype.refreshGeometry = function () {
    const t0 = performance.now();
    computeDerived(this.model);
    const t1 = performance.now();
    this.renderer.buildPaths(this.model);
    const t2 = performance.now();
    this.showLegend();
    this.timings.derived = t1 - t0;
    this.timings.paths = t2 - t1;
  };

  Viewer.prototype.resize = function () {
    const rect = this.stage.getBoundingClientRect();
    this.renderer.resize(rect.width, rect.height);
  };

  Viewer.prototype.requestRender = function (interactive) {
    const self = this;
    if (interactive === "overlay") {
      // only the hover changed: the last frame plus the overlay, when the view is the same
      if (this.renderer.cacheCurrent() && !this.frame) {
        this.renderer.renderCached();
        this.renderer.drawOverlay(this.model);
        return;
      }
      interactive = false;
    }
    if (interactive && this.renderer.slow() && this.renderer.cacheView &&
        this.renderer.cacheView.angle === this.renderer.view.angle) {
      // a full frame is slow: move the last frame now, draw properly once the user pauses
      this.renderer.renderCached();
      clearTimeout(this.slowTimer);
      this.slowTimer = setTimeout(function () {
        self.requestRender(false);
      }, 160);
      return;
    }
    if (this.frame) return;
    this.frame = requestAnimationFrame(function () {
      self.frame = 0;
      const started = performance.now();
      self.renderer.render(self.model);
      self.canvas.dataset.renders = String((parseInt(self.canvas.dataset.renders || "0", 10) || 0) + 1);
      // the canvas is rasterised after this callback: the next frame tells the real cost
      requestAnimationFrame(function () {
        self.renderer.frameMs = performance.now() - started;
      });
    });
  };

  Viewer.prototype.setupControls = function () {
    const model = this.model;
    $("title").textContent = model.title || model.source || "geomexact viewer";
    const fill = $("fill");
    const region = fill.querySelector('option[value="region"]');
    region.disabled = !model.regions;
    const quality = fill.querySelector('option[value="min_angle"]');
    quality.disabled = model.kind !== "triangles";
    if ((fill.value === "region" && !model.regions) || (fill.value === "min_angle" && model.kind !== "triangles")) {
      fill.value = "none";
      this.renderer.options.fill = "none";
      this.refreshGeometry();
    }
    const trace = $("trace");
    const h = model.history;
    trace.hidden = !h;
    if (h) {
      this.steps.load(h.labels);
      $("digests").textContent = "input " + h.inputDigest.slice(0, 12) + "… → final " + h.finalDigest.slice(0, 12) + "…";
      this.showStep();
    }
    const download = $("download");
    download.hidden = !model.download;
    $("notes").textContent = (model.notes || []).join("; ");
  };

  Viewer.prototype.showStep = function () {
    const model = this.model;
    const h = model.history;
    if (!h) return;
    this.steps.refresh();
    $("step-number").textContent = formatCount(model.step) + " / " + formatCount(h.steps);
    let text;
    if (model.step === 0) {
      text = "the input, before step 1";
    } else {
      const k = model.step;
      const added = h.addedOffsets[k] - h.addedOffsets[k - 1];
      const removed = h.removedOffsets[k] - h.removedOffsets[k - 1];
      text = "step " + k + ": " + h.labels[k - 1] + " (+" + added + " / −" + removed + " triangles)";
    }
    $("step-label").textContent = text;
  };

  Viewer.prototype.goToStep = function (target) {
    if (!this.model || !setStep(this.model, target)) return;
    this.renderer.hover = -1;
    this.hideHover();
    this.refreshGeometry();
    this.showStep();
    this.showStats();
    this.requestRender();
  };

  Viewer.prototype.showStats = function () {
    const model = this.model;
    const s = model.derived.stats;
    const rows = [];
    const row = function (id, label, value) {
      rows.push('<tr><th scope="row">' + escapeText(label) + '</th><td id="stat-' + id + '">' + escapeText(value) + "</td></tr>");
    };
    const kindNames = { triangles: "triangle mesh", polygons: "polygon mesh", pslg: "PSLG" };
    row("kind", "kind", kindNames[model.kind] || model.kind);
    row("vertices", "vertices", formatCount(model.vertexCount));
    if (model.kind === "triangles") row("triangles", "triangles", formatCount(model.aliveCount));
    if (model.kind === "polygons") {
      row("polygons", "polygons", formatCount(model.polygons));
      let nonconvex = 0;
      for (let p = 0; p < model.polygons; p++) nonconvex += model.nonconvex[p];
      row("nonconvex", "non-convex polygons", formatCount(nonconvex));
    }
    if (model.kind !== "pslg") {
      row("edges", "edges", formatCount(s.edges));
      row("boundary-edges", "boundary edges", formatCount(s.boundaryEdges));
    }
    row("segments", model.kind === "pslg" ? "segments" : "constrained edges", formatCount(s.segments));
    if (model.kind === "pslg") {
      row("holes", "holes", formatCount(model.holes.length / 2));
      row("regions", "region seeds", formatCount(model.seeds.length / 2));
    }
    if (model.kind === "triangles") {
      row("min-angle", "min angle (°)", formatNumber(s.minAngle, 5));
      row("max-angle", "max angle (°)", formatNumber(s.maxAngle, 5));
    }
    if (model.kind !== "pslg") {
      row("min-area", "min area", formatNumber(s.minArea));
      row("max-area", "max area", formatNumber(s.maxArea));
      row("total-area", "total area", formatNumber(s.totalArea, 10));
    }
    if (s.clockwise) row("clockwise", "clockwise triangles", formatCount(s.clockwise));
    const b = model.box;
    row("bbox", "bounding box", "x " + formatNumber(b.x0) + " … " + formatNumber(b.x1) + ", y " + formatNumber(b.y0) + " … " + formatNumber(b.y1));
    // coordinates beyond the doubles' comfortable range are drawn scaled exactly by 2^-k
    if (model.scaleExponent) row("scale", "drawn scale", "coordinates × 2^" + -model.scaleExponent);
    $("stats-table").innerHTML = rows.join("");
    // the exact statistics geomexact computed, for the mesh it describes
    const exact = $("exact-table");
    const summary = model.summary;
    const atEnd = !model.history || model.step === model.history.steps;
    const keys = [
      ["total_area", "total area (exact)"], ["is_delaunay", "Delaunay (exact)"],
      ["min_angle_deg", "min angle (°)"], ["digest", "digest"],
    ];
    const exactRows = [];
    if (summary && atEnd) {
      for (const [key, label] of keys) {
        if (summary[key] === undefined || summary[key] === null) continue;
        let value = summary[key];
        if (typeof value === "boolean") value = value ? "yes" : "no";
        else if (typeof value === "number") value = formatNumber(value, 8);
        exactRows.push('<tr><th scope="row">' + escapeText(label) + '</th><td id="exact-' + key.replace(/_/g, "-") + '">' + escapeText(value) + "</td></tr>");
      }
    }
    exact.innerHTML = exactRows.join("");
    $("exact").hidden = !exactRows.length;
  };

  Viewer.prototype.showLegend = function () {
    const legend = $("legend");
    const fills = this.renderer.paths ? this.renderer.paths.legend : [];
    const items = fills.filter(function (f) {
      return f.label;
    }).map(function (f) {
      return '<li><span class="swatch" style="background:' + f.color + '"></span>' + escapeText(f.label) + " <small>(" + formatCount(f.count) + ")</small></li>";
    });
    let extra = "";
    if (this.model.history) {
      extra = '<li><span class="swatch added"></span>added by the step</li><li><span class="swatch removed"></span>removed by the step</li>';
    }
    if (this.model.segSlots) extra += '<li><span class="swatch segment"></span>constrained edge</li>';
    legend.innerHTML = items.join("") + extra;
    $("legend-title").hidden = !legend.innerHTML;
  };

  Viewer.prototype.hideHover = function () {
    $("hover").hidden = true;
  };

  Viewer.prototype.describe = function (id) {
    // hover text of a triangle slot, polygon or vertex
    const model = this.model;
    const xy = model.xy;
    const point = function (v) {
      let text = "v" + v + " (" + formatNumber(xy[2 * v], 10) + ", " + formatNumber(xy[2 * v + 1], 10) + ")";
      if (model.exact && model.exact[v]) {
        const exact = model.exact[v].split(" ");
        if (String(numberOf(exact[0])) !== exact[0] || String(numberOf(exact[1])) !== exact[1]) {
          text += " exact (" + exact[0] + ", " + exact[1] + ")";
        }
      }
      return text;
    };
    const lines = [];
    if (model.kind === "triangles") {
      const a = model.cells[3 * id];
      const b = model.cells[3 * id + 1];
      const c = model.cells[3 * id + 2];
      const m = triangleMeasures(xy[2 * a], xy[2 * a + 1], xy[2 * b], xy[2 * b + 1], xy[2 * c], xy[2 * c + 1], new Float64Array(5));
      lines.push(["triangle", "(" + a + ", " + b + ", " + c + ")"]);
      lines.push(["vertices", point(a) + "\n" + point(b) + "\n" + point(c)]);
      lines.push(["angles (°)", formatNumber(m[0], 6) + ", " + formatNumber(m[1], 6) + ", " + formatNumber(m[2], 6)]);
      lines.push(["area", formatNumber(m[3], 10)]);
      const exact = this.exactArea([a, b, c]);
      if (exact) lines.push(["exact area", exact]);
      if (model.regions && !Number.isNaN(model.regions[id])) lines.push(["region", formatNumber(model.regions[id])]);
    } else if (model.kind === "polygons") {
      const v = model.polyVertices;
      const ids = Array.from(v.slice(model.polyOffsets[id], model.polyOffsets[id + 1]));
      lines.push(["polygon", "#" + id + " (" + ids.length + " vertices" + (model.nonconvex[id] ? ", non-convex" : "") + ")"]);
      lines.push(["vertices", ids.slice(0, 8).map(point).join("\n") + (ids.length > 8 ? "\n…" : "")]);
      lines.push(["area", formatNumber(Math.abs(polygonArea(model, id)), 10)]);
      const exact = this.exactArea(ids);
      if (exact) lines.push(["exact area", exact]);
    } else {
      lines.push(["vertex", point(id)]);
    }
    return lines;
  };

  Viewer.prototype.exactArea = function (ids) {
    // |shoelace| / 2 over the exact coordinates (BigInt rationals)
    const exact = this.model.exact;
    if (!exact) return null;
    try {
      const pts = ids.map(function (v) {
        const parts = exact[v].split(" ");
        return [parseRational(parts[0]), parseRational(parts[1])];
      });
      let twice = { n: 0n, d: 1n };
      for (let i = 0; i < pts.length; i++) {
        const p = pts[i];
        const q = pts[(i + 1) % pts.length];
        const term = rSub(rMul(p[0], q[1]), rMul(q[0], p[1]));
        twice = rational(twice.n * term.d + term.n * twice.d, twice.d * term.d);
      }
      const area = rational(bigAbs(twice.n), twice.d * 2n);
      const text = rationalText(area);
      return text.length > 400 ? text.slice(0, 200) + "…(" + text.length + " characters)" : text;
    } catch (error) {
      return null;
    }
  };

  Viewer.prototype.updateHover = function (sx, sy) {
    const model = this.model;
    if (!model || !model.derived) return;
    const [nx, ny] = this.renderer.toNormal(sx, sy);
    const id = pick(model, nx, ny, 8 / this.renderer.view.scale);
    const box = $("hover");
    if (id !== this.renderer.hover) {
      this.renderer.hover = id;
      this.requestRender("overlay");
    }
    if (id < 0) {
      box.hidden = true;
      return;
    }
    const lines = this.describe(id);
    const html = lines.map(function (l) {
      return "<dt>" + escapeText(l[0]) + "</dt><dd>" + escapeText(l[1]).replace(/\n/g, "<br>") + "</dd>";
    }).join("");
    box.innerHTML = "<dl>" + html + "</dl>";
    $("info").innerHTML = "<dl>" + html + "</dl>";
    box.hidden = false;
    const stage = this.stage.getBoundingClientRect();
    const left = sx + 16 + box.offsetWidth > stage.width ? sx - 16 - box.offsetWidth : sx + 16;
    const top = sy + 16 + box.offsetHeight > stage.height ? Math.max(0, sy - 16 - box.offsetHeight) : sy + 16;
    box.style.left = Math.max(0, left) + "px";
    box.style.top = top + "px";
  };

  Viewer.prototype.showMessage = function (text, isError) {
    // errors stay until clicked or replaced; notes go away after a few seconds
    const message = $("message");
    message.textContent = text;
    message.className = isError ? "error" : "note";
    message.hidden = !text;
    message.setAttribute("role", isError ? "alert" : "status");
    clearTimeout(this.messageTimer);
    if (text && !isError) {
      this.messageTimer = setTimeout(function () {
        message.hidden = true;
      }, 4000);
    }
  };

  Viewer.prototype.openFiles = function (fileList) {
    const self = this;
    const files = Array.from(fileList || []);
    if (!files.length) return;
    const tooBig = files.filter(function (f) {
      return f.size > 512 * 1024 * 1024;
    });
    if (tooBig.length) {
      this.showMessage(tooBig[0].name + ": larger than 512 MB; the viewer does not open it", true);
      return;
    }
    Promise.all(files.map(function (file) {
      return file.text().then(function (text) {
        return { name: file.name, text: text };
      });
    })).then(function (texts) {
      const model = parseFiles(texts);
      self.setModel(model);
      self.showMessage("opened " + texts.map(function (t) {
        return t.name;
      }).join(", "), false);
    }).catch(function (error) {
      self.showMessage(error.message || String(error), true);
    });
  };

  Viewer.prototype.download = function () {
    const d = this.model && this.model.download;
    if (!d) return;
    const blob = new Blob([d.text], { type: "text/plain" });
    const url = URL.createObjectURL(blob);
    const a = document.createElement("a");
    a.href = url;
    a.download = d.name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(function () {
      URL.revokeObjectURL(url);
    }, 1000);
  };

  Viewer.prototype.bind = function () {
    const self = this;
    const canvas = this.canvas;
    const r = function () {
      return self.renderer;
    };
    const local = function (event) {
      const rect = canvas.getBoundingClientRect();
      return [event.clientX - rect.left, event.clientY - rect.top];
    };
    canvas.addEventListener("wheel", function (event) {
      if (!self.model) return;
      event.preventDefault();
      const [x, y] = local(event);
      const delta = event.deltaMode === 1 ? event.deltaY * 16 : event.deltaY;
      r().zoomAt(x, y, Math.exp(-delta * 0.0015));
      self.requestRender(true);
    }, { passive: false });
    canvas.addEventListener("pointerdown", function (event) {
      if (!self.model) return;
      try {
        canvas.setPointerCapture(event.pointerId);
      } catch (error) {
        // a pointer the browser does not track (synthetic events): no capture needed
      }
      self.pointers.set(event.pointerId, local(event));
      self.pinch = null;
      self.hideHover();
    });
    canvas.addEventListener("pointermove", function (event) {
      if (!self.model) return;
      const here = local(event);
      if (!self.pointers.has(event.pointerId)) {
        if (event.pointerType === "mouse") self.updateHover(here[0], here[1]);
        return;
      }
      const before = self.pointers.get(event.pointerId);
      self.pointers.set(event.pointerId, here);
      if (self.pointers.size === 1) {
        r().panBy(here[0] - before[0], here[1] - before[1]);
      } else if (self.pointers.size === 2) {
        const [p, q] = Array.from(self.pointers.values());
        const mid = [(p[0] + q[0]) / 2, (p[1] + q[1]) / 2];
        const dist = Math.hypot(p[0] - q[0], p[1] - q[1]) || 1;
        if (self.pinch) {
          r().panBy(mid[0] - self.pinch.mid[0], mid[1] - self.pinch.mid[1]);
          r().zoomAt(mid[0], mid[1], dist / self.pinch.dist);
        }
        self.pinch = { mid: mid, dist: dist };
      }
      self.requestRender(true);
    });
    const release = function (event) {
      if (!self.pointers.has(event.pointerId)) return;
      self.pointers.delete(event.pointerId);
      self.pinch = null;
      if (!self.pointers.size) self.requestRender(false);
      if (event.pointerType !== "mouse" && self.model && event.type === "pointerup") {
        const here = local(event);
        self.updateHover(here[0], here[1]);
      }
    };
    canvas.addEventListener("pointerup", release);
    canvas.addEventListener("pointercancel", release);
    canvas.addEventListener("pointerleave", function (event) {
      if (event.pointerType === "mouse" && !self.pointers.size) {
        self.hideHover();
        if (r().hover >= 0) {
          r().hover = -1;
          self.requestRender("overlay");
        }
      }
    });
    canvas.addEventListener("dblclick", function (event) {
      if (!self.model) return;
      const [x, y] = local(event);
      r().zoomAt(x, y, event.shiftKey ? 0.5 : 2);
      self.requestRender(false);
    });
    canvas.addEventListener("keydown", function (event) {
      if (!self.model) return;
      const step = 40;
      const keys = {
        ArrowLeft: [step, 0], ArrowRight: [-step, 0], ArrowUp: [0, step], ArrowDown: [0, -step],
      };
      if (keys[event.key]) {
        r().panBy(keys[event.key][0], keys[event.key][1]);
      } else if (event.key === "+" || event.key === "=") {
        r().zoomAt(r().width / 2, r().height / 2, 1.25);
      } else if (event.key === "-") {
        r().zoomAt(r().width / 2, r().height / 2, 0.8);
      } else if (event.key === "f" || event.key === "0") {
        r().fit(self.model);
      } else if (event.key === "r" || event.key === "R") {
        // r: 15° counter-clockwise, R: clockwise, about the centre of the view
        r().rotateAt(r().width / 2, r().height / 2, (event.key === "r" ? 1 : -1) * Math.PI / 12);
      } else {
        return;
      }
      event.preventDefault();
      self.requestRender(false);
    });
    $("rotate").addEventListener("click", function () {
      if (!self.model) return;
      r().rotateAt(r().width / 2, r().height / 2, Math.PI / 12);
      self.requestRender(false);
    });
    $("fit").addEventListener("click", function () {
      if (!self.model) return;
      r().fit(self.model);
      self.requestRender(false);
    });
    $("fill").addEventListener("change", function () {
      r().options.fill = $("fill").value;
      if (!self.model) return;
      self.refreshGeometry();
      self.requestRender(false);
    });
    $("show-edges").addEventListener("change", function () {
      r().options.edges = $("show-edges").checked;
      self.requestRender(false);
    });
    $("show-vertices").addEventListener("change", function () {
      r().options.vertices = $("show-vertices").checked;
      self.requestRender(false);
    });
    $("file-input").addEventListener("change", function () {
      self.openFiles($("file-input").files);
    });
    this.stage.addEventListener("dragover", function (event) {
      event.preventDefault();
    });
    this.stage.addEventListener("drop", function (event) {
      event.preventDefault();
      self.openFiles(event.dataTransfer && event.dataTransfer.files);
    });
    this.steps = window.geomexactStepControls({
      current: function () {
        return self.model && self.model.history ? self.model.step : 0;
      },
      go: function (k) {
        self.goToStep(k);
      },
    });
    $("message").addEventListener("click", function () {
      $("message").hidden = true;
    });
    $("download").addEventListener("click", function () {
      self.download();
    });
    if (window.ResizeObserver) {
      new ResizeObserver(function () {
        if (!self.model) return;
        const before = r().view;
        const oldW = r().width;
        const oldH = r().height;
        self.resize();
        before.tx += (r().width - oldW) / 2;
        before.ty += (r().height - oldH) / 2;
        r().view = before;
        self.requestRender(false);
      }).observe(this.stage);
    }
  };

  function start() {
    const viewer = new Viewer();
    viewer.bind();
    window.geomexactViewer = {
      // a scripting hook for tests and the console (see specs/viewer.md)
      viewer: viewer,
      get model() {
        return viewer.model;
      },
      get view() {
        return viewer.renderer.view;
      },
      get lastRenderMs() {
        return viewer.renderer.lastRenderMs;
      },
      get timings() {
        return Object.assign({ render: viewer.renderer.lastRenderMs, frame: viewer.renderer.frameMs }, viewer.timings);
      },
      setStep: function (k) {
        viewer.goToStep(k);
      },
      get steps() {
        return viewer.steps;
      },
      stats: function () {
        return viewer.model ? Object.assign({}, viewer.model.derived.stats, {
          vertices: viewer.model.vertexCount, triangles: viewer.model.aliveCount,
          polygons: viewer.model.polygons, step: viewer.model.step,
        }) : null;
      },
      renderNow: function () {
        // a full frame, rasterised (the pixel read waits for it); its milliseconds
        const started = performance.now();
        viewer.renderer.render(viewer.model);
        viewer.renderer.ctx.getImageData(0, 0, 1, 1);
        return performance.now() - started;
      },
      parseFiles: parseFiles,
    };
    const element = $("geomexact-data");
    const text = element ? element.textContent.trim() : "";
    if (!text) {
      viewer.resize();
      viewer.renderer.render(null);
      viewer.showMessage("Open a mesh file (OFF, Triangle .node/.ele/.poly, PSLG text .pslg, triangle list or Mellado's text .txt) to view it.", false);
      return;
    }
    try {
      const t0 = performance.now();
      const data = JSON.parse(text);
      const model = modelFromPayload(data);
      viewer.timings.decode = performance.now() - t0;
      const fill = data.options && data.options.fill;
      if (fill && $("fill").querySelector('option[value="' + fill + '"]')) {
        $("fill").value = fill;
        viewer.renderer.options.fill = fill;
      }
      viewer.setModel(model);
    } catch (error) {
      viewer.showMessage("cannot show the embedded mesh: " + (error.message || error), true);
    }
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start);
  else start();
})();
