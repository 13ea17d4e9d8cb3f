// geomexact 3D viewer: a tetrahedral mesh drawn on a 2D canvas with an orthographic
// projection and the painter's algorithm (faces sorted by depth).  No network access.
// Only the faces that can be seen are drawn: the boundary faces of the tetrahedra alive
// at the step and kept by the clip plane (cached per step and clip), facing the viewer.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("geomexact-data").textContent);
  function decode(text, Type) {
    const raw = atob(text);
    const bytes = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  const timings = {};
  let started = performance.now();
  const xyz = decode(data.xyz, Float64Array);
  const cells = decode(data.cells, Uint32Array);
  const birth = decode(data.birth, Int32Array);
  const death = decode(data.death, Int32Array);
  const quality = decode(data.quality, Uint8Array);  // radius ratio in 1/255ths
  const creator = decode(data.creator, Uint8Array);
  const cellCount = birth.length;
  const vertexCount = xyz.length / 3;
  timings.decode = performance.now() - started;
  const canvas = document.getElementById("view");
  const context = canvas.getContext("2d");
  const state = { yaw: 0.6, pitch: 0.45, zoom: 1, step: data.options.step,
                  colour: data.options.colour, shrink: 0, all: false,
                  clipAxis: -1, clipValue: Infinity };
  const AXES = ["x", "y", "z"];
  // the bounding box's centre and radius, for the default view
  let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < xyz.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], xyz[i + k]); hi[k] = Math.max(hi[k], xyz[i + k]);
    }
  }
  if (xyz.length === 0) { lo = [0, 0, 0]; hi = [1, 1, 1]; }
  const centre = [0, 1, 2].map((k) => (lo[k] + hi[k]) / 2);
  const radius = Math.max(1e-300, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2);
  const OP_COLOURS = ["#9aa5b1", "#e07a5f", "#3d85c6", "#81b29a", "#f2cc8f", "#a06cd5", "#5fb3b3"];
  const PLAIN = [150, 170, 200], CUT = [240, 170, 110];

  // the face opposite corner i of a positive tetrahedron, oriented outward
  const FACES = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
  // every tetrahedron's centroid, and the id of each of its faces among all the distinct
  // faces of every tetrahedron of the trace (an open-addressing hash of sorted triples)
  started = performance.now();
  const centroid = new Float64Array(3 * cellCount);
  for (let c = 0; c < cellCount; c++) {
    for (let k = 0; k < 4; k++) {
      const v = cells[4 * c + k];
      for (let j = 0; j < 3; j++) centroid[3 * c + j] += xyz[3 * v + j] / 4;
    }
  }
  const faceOf = new Uint32Array(4 * cellCount);
  let faceCount = 0;
  (function () {
    let size = 2;
    while (size < 8 * cellCount) size *= 2;
    const mask = size - 1;
    const keys = new Uint32Array(3 * size), used = new Uint8Array(size), ids = new Uint32Array(size);
    for (let c = 0; c < cellCount; c++) {
      for (let f = 0; f < 4; f++) {
        let a = cells[4 * c + FACES[f][0]], b = cells[4 * c + FACES[f][1]], d = cells[4 * c + FACES[f][2]], t;
        if (a > b) { t = a; a = b; b = t; }
        if (b > d) { t = b; b = d; d = t; }
        if (a > b) { t = a; a = b; b = t; }
        let slot = (Math.imul(a, 73856093) ^ Math.imul(b, 19349663) ^ Math.imul(d, 83492791)) & mask;
        while (used[slot] && !(keys[3 * slot] === a && keys[3 * slot + 1] === b && keys[3 * slot + 2] === d)) {
          slot = (slot + 1) & mask;
        }
        if (!used[slot]) {
          used[slot] = 1; keys[3 * slot] = a; keys[3 * slot + 1] = b; keys[3 * slot + 2] = d;
          ids[slot] = faceCount++;
        }
        faceOf[4 * c + f] = ids[slot];
      }
    }
  })();
  timings.faces = performance.now() - started;

  function qualityColour(q) {
    // red (flat) -> yellow -> green (regular)
    const t = Math.max(0, Math.min(1, q));
    const r = t < 0.5 ? 220 : Math.round(220 - (t - 0.5) * 2 * 170);
    const g = t < 0.5 ? Math.round(60 + t * 2 * 160) : 200;
    return [r, g, 70];
  }
  function hexColour(text) {
    return [1, 3, 5].map((i) => parseInt(text.slice(i, i + 2), 16));
  }
  const QUALITY_COLOURS = Array.from({ length: 256 }, (_, i) => qualityColour(i / 255));
  const OP_RGB = OP_COLOURS.map(hexColour);
  function faceColour(c, cut) {
    if (state.colour === "quality") return QUALITY_COLOURS[quality[c]];
    if (state.colour === "step") return OP_RGB[creator[c] % OP_RGB.length];
    return cut ? CUT : PLAIN;
  }

  // the faces to draw at (step, all, clip): slots 4 c + f, and whether the clip opened each
  const visibleCache = new Map();
  const counts = new Uint8Array(faceCount), keptCounts = new Uint8Array(faceCount);
  function visible() {
    const key = `${state.step}|${state.all}|${state.clipAxis}|${state.clipValue}`;
    const found = visibleCache.get(key);
    if (found) { visibleCache.delete(key); visibleCache.set(key, found); return found; }
    const begun = performance.now();
    const step = state.step, axis = state.clipAxis, limit = state.clipValue;
    counts.fill(0); keptCounts.fill(0);
    const keptCells = new Uint8Array(cellCount);
    let alive = 0, kept = 0;
    for (let c = 0; c < cellCount; c++) {
      if (!(birth[c] <= step && step < death[c])) continue;
      alive++;
      const keep = axis < 0 || centroid[3 * c + axis] <= limit;
      if (keep) { keptCells[c] = 1; kept++; }
      for (let f = 0; f < 4; f++) {
        const id = faceOf[4 * c + f];
        counts[id]++;
        if (keep) keptCounts[id]++;
      }
    }
    const slots = [], cut = [];
    let cutCount = 0;
    for (let c = 0; c < cellCount; c++) {
      if (!keptCells[c]) continue;
      for (let f = 0; f < 4; f++) {
        const id = faceOf[4 * c + f];
        const boundary = keptCounts[id] === 1;
        if (!boundary && !state.all) continue;
        const opened = boundary && counts[id] === 2;
        if (opened) cutCount++;
        slots.push(4 * c + f); cut.push(opened ? 1 : 0);
      }
    }
    const result = { alive, kept, cutCount, slots: Uint32Array.from(slots), cut: Uint8Array.from(cut) };
    visibleCache.set(key, result);
    if (visibleCache.size > 8) visibleCache.delete(visibleCache.keys().next().value);
    timings.visible = performance.now() - begun;
    return result;
  }
  function resize() {
    const ratio = window.devicePixelRatio || 1;
    const box = document.getElementById("stage").getBoundingClientRect();
    const width = Math.max(1, Math.floor(box.width)), height = Math.max(1, Math.floor(box.height));
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
    canvas.style.width = width + "px";
    canvas.style.height = height + "px";
  }
  const sx = new Float64Array(vertexCount), sy = new Float64Array(vertexCount), sz = new Float64Array(vertexCount);
  function draw() {
    const begun = performance.now();
    const shown = visible();
    const slots = shown.slots, cutFlags = shown.cut;
    const w = canvas.width, h = canvas.height;
    context.setTransform(1, 0, 0, 1, 0, 0);
    context.fillStyle = "#ffffff";
    context.fillRect(0, 0, w, h);
    const cy = Math.cos(state.yaw), syaw = Math.sin(state.yaw);
    const cp = Math.cos(state.pitch), sp = Math.sin(state.pitch);
    const scale = state.zoom * 0.45 * Math.min(w, h) / radius;
    // rotate about the vertical axis, then tilt: screen right, screen up, depth (farther: larger)
    const project = (x, y, z, out, i) => {
      x -= centre[0]; y -= centre[1]; z -= centre[2];
      const x1 = cy * x + syaw * y, y1 = -syaw * x + cy * y;
      out[0][i] = x1; out[1][i] = sp * y1 + cp * z; out[2][i] = cp * y1 - sp * z;
    };
    const screen = [sx, sy, sz];
    for (let v = 0; v < vertexCount; v++) project(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2], screen, v);
    const count = slots.length;
    const fx = new Float64Array(3 * count), fy = new Float64Array(3 * count);
    const depth = new Float64Array(count), shade = new Float32Array(count);
    const keep = [];
    const corner = [new Float64Array(3), new Float64Array(3), new Float64Array(3)];
    const light = [0.3, 0.5, 0.8];
    const lightLength = Math.hypot(light[0], light[1], light[2]);
    for (let i = 0; i < count; i++) {
      const c = slots[i] >> 2, f = slots[i] & 3;
      for (let k = 0; k < 3; k++) {
        const v = cells[4 * c + FACES[f][k]];
        if (state.shrink) {
          const t = state.shrink;
          project(xyz[3 * v] + (centroid[3 * c] - xyz[3 * v]) * t,
                  xyz[3 * v + 1] + (centroid[3 * c + 1] - xyz[3 * v + 1]) * t,
                  xyz[3 * v + 2] + (centroid[3 * c + 2] - xyz[3 * v + 2]) * t, corner, k);
        } else {
          corner[0][k] = sx[v]; corner[1][k] = sy[v]; corner[2][k] = sz[v];
        }
      }
      const ux = corner[0][1] - corner[0][0], uy = corner[1][1] - corner[1][0], uz = corner[2][1] - corner[2][0];
      const vx = corner[0][2] - corner[0][0], vy = corner[1][2] - corner[1][0], vz = corner[2][2] - corner[2][0];
      const area2 = ux * vy - uy * vx;  // counter-clockwise on screen: the face looks at us
      if (!(area2 > 0)) continue;
      const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = area2;
      const length = Math.hypot(nx, ny, nz) || 1;
      shade[i] = 0.45 + 0.55 * Math.abs(nx * light[0] + ny * light[1] + nz * light[2]) / (length * lightLength);
      depth[i] = corner[2][0] + corner[2][1] + corner[2][2];
      for (let k = 0; k < 3; k++) { fx[3 * i + k] = w / 2 + corner[0][k] * scale; fy[3 * i + k] = h / 2 - corner[1][k] * scale; }
      keep.push(i);
    }
    const order = Uint32Array.from(keep);
    order.sort((p, q) => depth[q] - depth[p]);
    const painted = order.length;
    const stroke = painted <= 60000;
    context.lineWidth = painted > 20000 ? 0.5 : 1;
    context.lineJoin = "round";
    context.strokeStyle = "rgba(30, 40, 60, 0.8)";
    for (let j = 0; j < painted; j++) {
      const i = order[j];
      context.beginPath();
      context.moveTo(fx[3 * i], fy[3 * i]);
      context.lineTo(fx[3 * i + 1], fy[3 * i + 1]);
      context.lineTo(fx[3 * i + 2], fy[3 * i + 2]);
      context.closePath();
      const colour = faceColour(slots[i] >> 2, cutFlags[i]);
      const s = shade[i];
      context.fillStyle = `rgb(${Math.round(colour[0] * s)}, ${Math.round(colour[1] * s)}, ${Math.round(colour[2] * s)})`;
      context.fill();
      if (stroke) context.stroke();
    }
    timings.draw = performance.now() - begun;
    showStats(shown, painted);
  }
  function row(table, label, value) {
    const tr = document.createElement("tr");
    const th = document.createElement("th"); th.textContent = label;
    const td = document.createElement("td"); td.textContent = value;
    tr.append(th, td); table.append(tr);
  }
  function showStats(shown, painted) {
    const table = document.getElementById("stats-table");
    table.replaceChildren();
    row(table, "vertices", String(data.vertex_counts[state.step]));
    row(table, "tetrahedra", String(shown.alive));
    if (state.clipAxis >= 0) row(table, "kept by the clip", String(shown.kept));
    row(table, state.all ? "faces" : "boundary faces", String(shown.slots.length));
    if (state.clipAxis >= 0) row(table, "faces cut open", String(shown.cutCount));
    row(table, "faces drawn", String(painted));
    row(table, "volume (exact, final)", data.volume);
    row(table, "digest", data.digests[state.step]);
    table.dataset.tetrahedra = String(shown.kept);
    table.dataset.faces = String(painted);
    if (data.steps > 0) {
      document.getElementById("step-number").textContent = `step ${state.step} of ${data.steps}`;
      document.getElementById("step-label").textContent = data.labels[state.step];
    }
  }
  function showLegend() {
    const legend = document.getElementById("legend");
    legend.replaceChildren();
    const item = (colour, text) => {
      const li = document.createElement("li");
      const swatch = document.createElement("span");
      swatch.style.display = "inline-block"; swatch.style.width = "0.9em"; swatch.style.height = "0.9em";
      swatch.style.marginRight = "0.4em"; swatch.style.background = `rgb(${colour.join(",")})`;
      li.append(swatch, document.createTextNode(text)); legend.append(li);
    };
    if (state.colour === "quality") {
      item(qualityColour(0), "radius ratio 0 (flat)");
      item(qualityColour(0.5), "radius ratio 0.5");
      item(qualityColour(1), "radius ratio 1 (regular)");
    } else if (state.colour === "step") {
      data.ops.forEach((op, i) => item(OP_RGB[i % OP_RGB.length], `created by ${op}`));
    } else {
      item(PLAIN, "boundary face");
      item(CUT, "face cut open by the clip");
    }
  }
  // controls
  const colourSelect = document.getElementById("colour");
  colourSelect.value = state.colour;
  colourSelect.addEventListener("change", () => { state.colour = colourSelect.value; showLegend(); draw(); });
  const allBox = document.getElementById("all-tets");
  allBox.addEventListener("change", () => { state.all = allBox.checked; draw(); });
  const shrinkInput = document.getElementById("shrink");
  shrinkInput.addEventListener("input", () => { state.shrink = Number(shrinkInput.value); draw(); });
  const clipAxis = document.getElementById("clip-axis");
  const clipInput = document.getElementById("clip");
  const clipText = document.getElementById("clip-value");
  const CLIP_STEPS = Number(clipInput.max);
  function clipFromSlider() {
    const axis = AXES.indexOf(clipAxis.value);
    state.clipAxis = axis;
    clipInput.disabled = axis < 0;
    if (axis < 0) { state.clipValue = Infinity; clipText.textContent = ""; return; }
    const t = Number(clipInput.value) / CLIP_STEPS;
    state.clipValue = t >= 1 ? hi[axis] : lo[axis] + (hi[axis] - lo[axis]) * t;
    clipText.textContent = `${AXES[axis]} ≤ ${state.clipValue.toPrecision(6)}`;
  }
  clipAxis.addEventListener("change", () => { clipFromSlider(); draw(); });
  clipInput.addEventListener("input", () => { clipFromSlider(); draw(); });
  if (data.options.clip) {
    const axis = AXES.indexOf(data.options.clip.axis);
    const value = data.options.clip.value;
    clipAxis.value = AXES[axis];
    const span = hi[axis] - lo[axis];
    const t = span > 0 ? (value - lo[axis]) / span : 1;
    clipInput.value = String(Math.round(Math.max(0, Math.min(1, t)) * CLIP_STEPS));
    clipFromSlider();
    state.clipValue = value;  // as given, not rounded to the slider's steps
    clipText.textContent = `${AXES[axis]} ≤ ${data.options.clip.position}`;
  } else {
    clipFromSlider();
  }
  document.getElementById("fit").addEventListener("click", () => {
    state.yaw = 0.6; state.pitch = 0.45; state.zoom = 1; draw();
  });
  // the trace panel (step_controls.js): slider, buttons, play, go to step, op filter
  const steps = window.geomexactStepControls({
    current: () => state.step,
    go: (k) => { if (k !== state.step) { state.step = k; draw(); } },
  });
  if (data.steps > 0) {
    document.getElementById("trace").hidden = false;
    steps.load(data.labels.slice(1));
  }
  let dragging = null;
  canvas.addEventListener("pointerdown", (event) => {
    dragging = { x: event.clientX, y: event.clientY };
    if (canvas.setPointerCapture) canvas.setPointerCapture(event.pointerId);
  });
  canvas.addEventListener("pointermove", (event) => {
    if (!dragging) return;
    state.yaw += (event.clientX - dragging.x) * 0.01;
    state.pitch = Math.max(-1.55, Math.min(1.55, state.pitch + (event.clientY - dragging.y) * 0.01));
    dragging = { x: event.clientX, y: event.clientY };
    draw();
  });
  const stop = () => { dragging = null; };
  canvas.addEventListener("pointerup", stop);
  canvas.addEventListener("pointercancel", stop);
  canvas.addEventListener("wheel", (event) => {
    event.preventDefault();
    state.zoom *= Math.exp(-event.deltaY * 0.001);
    draw();
  }, { passive: false });
  window.addEventListener("resize", () => { resize(); draw(); });
  resize();
  showLegend();
  draw();
  window.geomexactView3d = { state, draw, timings, steps };
})();
