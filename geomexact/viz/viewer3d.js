// geomexact 3D viewer: a tetrahedral or mixed-cell mesh drawn on a 2D canvas with an
// orthographic projection and the painter's algorithm (faces sorted by depth).  No network
// access.  Every cell is a list of polygon faces (a tetrahedron's four triangles, a
// hexahedron's six quads, a polyhedron's polygons); each face is filled and outlined as
// its polygon.  Only the faces that can be seen are drawn: the boundary faces of the cells
// alive at the step and kept by the clip plane (cached per step and clip), facing the viewer.
// Faces are coloured by quality, cell kind, creating step, material (a page of materials) or plain.
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
  // a page of materials: each cell's index into data.material_ids (increasing ids)
  const materialRank = typeof data.materials === "string" ? decode(data.materials, Uint32Array) : null;
  const vertexCount = xyz.length / 3;
  // a mixed mesh's payload has its cells' kinds and faces; a tetrahedral one has 4 ids per
  // cell, whose faces are made here: the face opposite corner i, oriented outward
  const mixed = typeof data.faces === "string";
  const FACES = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
  let kinds, cellStart, faceStart, corners, cornerStart;
  if (mixed) {
    kinds = decode(data.kinds, Uint8Array);
    cellStart = decode(data.cell_offsets, Uint32Array);
    faceStart = decode(data.cell_face_offsets, Uint32Array);
    corners = decode(data.faces, Uint32Array);
    cornerStart = decode(data.face_offsets, Uint32Array);
  } else {
    kinds = new Uint8Array(cellCount).fill(10);
    cellStart = new Uint32Array(cellCount + 1);
    faceStart = new Uint32Array(cellCount + 1);
    corners = new Uint32Array(12 * cellCount);
    cornerStart = new Uint32Array(4 * cellCount + 1);
    for (let c = 0; c < cellCount; c++) {
      cellStart[c + 1] = 4 * (c + 1); faceStart[c + 1] = 4 * (c + 1);
      for (let f = 0; f < 4; f++) {
        cornerStart[4 * c + f + 1] = 3 * (4 * c + f + 1);
        for (let k = 0; k < 3; k++) corners[12 * c + 3 * f + k] = cells[4 * c + FACES[f][k]];
      }
    }
  }
  const slotCount = faceStart[cellCount];  // every face of every cell: its slot
  const owner = new Uint32Array(slotCount);
  for (let c = 0; c < cellCount; c++) {
    for (let f = faceStart[c]; f < faceStart[c + 1]; f++) owner[f] = c;
  }
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
  // cell kinds by VTK type, in the order they are listed (the pictures' colours)
  const KINDS = [[10, "tetrahedra", "#e07a5f"], [14, "pyramids", "#f2cc8f"],
                 [13, "wedges", "#81b29a"], [12, "hexahedra", "#9fbfe0"],
                 [42, "polyhedra", "#b48ad8"]];
  // the k-th material in increasing order of id, cycling (the pictures' colours)
  const MATERIAL_FILLS = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#b07aa1", "#edc948",
                          "#76b7b2", "#ff9da7", "#9c755f", "#bab0ac"];

  // every cell's centroid (the mean of its vertices), and the id of each face slot among
  // the distinct faces of every cell of the trace (an open-addressing hash of each face's
  // sorted vertex ids: one polygon, one id)
  started = performance.now();
  const centroid = new Float64Array(3 * cellCount);
  for (let c = 0; c < cellCount; c++) {
    const n = cellStart[c + 1] - cellStart[c];
    for (let i = cellStart[c]; i < cellStart[c + 1]; i++) {
      const v = cells[i];
      for (let j = 0; j < 3; j++) centroid[3 * c + j] += xyz[3 * v + j] / n;
    }
  }
  const faceOf = new Uint32Array(slotCount);
  let faceCount = 0;
  (function () {
    const sorted = corners.slice();
    for (let f = 0; f < slotCount; f++) {
      const s = cornerStart[f], e = cornerStart[f + 1];
      for (let i = s + 1; i < e; i++) {
        const x = sorted[i];
        let j = i - 1;
        while (j >= s && sorted[j] > x) { sorted[j + 1] = sorted[j]; j--; }
        sorted[j + 1] = x;
      }
    }
    let size = 2;
    while (size < 2 * slotCount) size *= 2;
    const mask = size - 1;
    const first = new Int32Array(size).fill(-1), ids = new Uint32Array(size);
    for (let f = 0; f < slotCount; f++) {
      const s = cornerStart[f], e = cornerStart[f + 1], n = e - s;
      let h = n;
      for (let i = s; i < e; i++) h = Math.imul(h ^ sorted[i], 0x9e3779b1) ^ (h >>> 15);
      let slot = (h ^ (h >>> 16)) & mask;
      for (;;) {
        const g = first[slot];
        if (g < 0) { first[slot] = f; ids[slot] = faceCount++; break; }
        const t = cornerStart[g];
        let same = cornerStart[g + 1] - t === n;
        for (let i = 0; same && i < n; i++) same = sorted[t + i] === sorted[s + i];
        if (same) break;
        slot = (slot + 1) & mask;
      }
      faceOf[f] = ids[slot];
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
  const KIND_RGB = new Map(KINDS.map(([type, , colour]) => [type, hexColour(colour)]));
  const MATERIAL_RGB = MATERIAL_FILLS.map(hexColour);
  function materialLabel(i) {
    const name = (data.material_names || [])[i];
    return `material ${data.material_ids[i]}` + (name ? ` (${name})` : "");
  }
  function faceColour(c, cut) {
    if (state.colour === "quality") return QUALITY_COLOURS[quality[c]];
    if (state.colour === "step") return OP_RGB[creator[c] % OP_RGB.length];
    if (state.colour === "kind") return KIND_RGB.get(kinds[c]) || PLAIN;
    if (state.colour === "material" && materialRank) return MATERIAL_RGB[materialRank[c] % MATERIAL_RGB.length];
    return cut ? CUT : PLAIN;
  }
  function countKinds(flags) {
    const counts = {};
    for (let c = 0; c < cellCount; c++) {
      if (flags[c]) counts[kinds[c]] = (counts[kinds[c]] || 0) + 1;
    }
    const named = {};
    for (const [type, name] of KINDS) if (counts[type]) named[name] = counts[type];
    return named;
  }
  function countMaterials(flags) {
    if (!materialRank) return {};
    const counts = new Array(data.material_ids.length).fill(0);
    for (let c = 0; c < cellCount; c++) if (flags[c]) counts[materialRank[c]]++;
    const named = {};
    data.material_ids.forEach((id, i) => { if (counts[i]) named[id] = counts[i]; });
    return named;
  }

  // the faces to draw at (step, all, clip): face slots, and whether the clip opened each
  const visibleCache = new Map();
  const counts = new Uint8Array(faceCount), keptCounts = new Uint8Array(faceCount);
  function visible() {
    const key = `${state.step}|${state.all}|${state.clipAxis}|${state.clipValue}`;
    const found = visibleCache.get(key);
    if (found) { visibleCache.delete(key); visibleCache.set(key, found); return found; }
    const begun = performance.now();
    const step = state.step, axis = state.clipAxis, limit = state.clipValue;
    counts.fill(0); keptCounts.fill(0);
    const aliveCells = new Uint8Array(cellCount), keptCells = new Uint8Array(cellCount);
    let alive = 0, kept = 0;
    for (let c = 0; c < cellCount; c++) {
      if (!(birth[c] <= step && step < death[c])) continue;
      alive++; aliveCells[c] = 1;
      const keep = axis < 0 || centroid[3 * c + axis] <= limit;
      if (keep) { keptCells[c] = 1; kept++; }
      for (let f = faceStart[c]; f < faceStart[c + 1]; f++) {
        const id = faceOf[f];
        counts[id]++;
        if (keep) keptCounts[id]++;
      }
    }
    const slots = [], cut = [];
    let cutCount = 0;
    for (let c = 0; c < cellCount; c++) {
      if (!keptCells[c]) continue;
      for (let f = faceStart[c]; f < faceStart[c + 1]; f++) {
        const id = faceOf[f];
        const boundary = keptCounts[id] === 1;
        if (!boundary && !state.all) continue;
        const opened = boundary && counts[id] === 2;
        if (opened) cutCount++;
        slots.push(f); cut.push(opened ? 1 : 0);
      }
    }
    const result = { alive, kept, cutCount, slots: Uint32Array.from(slots), cut: Uint8Array.from(cut),
                     aliveKinds: countKinds(aliveCells), keptKinds: countKinds(keptCells),
                     keptMaterials: countMaterials(keptCells) };
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
  // what the last frame painted: the faces and how many had each number of corners
  const frame = { painted: 0, sizes: {} };
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
    let total = 0;
    for (let i = 0; i < count; i++) total += cornerStart[slots[i] + 1] - cornerStart[slots[i]];
    const start = new Uint32Array(count + 1);
    const fx = new Float64Array(total), fy = new Float64Array(total);
    const depth = new Float64Array(count), shade = new Float32Array(count);
    const keep = [];
    let largest = 3;
    for (let i = 0; i < count; i++) largest = Math.max(largest, cornerStart[slots[i] + 1] - cornerStart[slots[i]]);
    const corner = [new Float64Array(largest), new Float64Array(largest), new Float64Array(largest)];
    const light = [0.3, 0.5, 0.8];
    const lightLength = Math.hypot(light[0], light[1], light[2]);
    let at = 0;
    for (let i = 0; i < count; i++) {
      const f = slots[i], c = owner[f], s = cornerStart[f], n = cornerStart[f + 1] - s;
      for (let k = 0; k < n; k++) {
        const v = corners[s + k];
        if (state.shrink) {
          const t = state.shrink;
          project(xyz[3 * v] + (centroid[3 * c] - xyz[3 * v]) * t,
                  xyz[3 * v + 1] + (centroid[3 * c + 1] - xyz[3 * v + 1]) * t,
                  xyz[3 * v + 2] + (centroid[3 * c + 2] - xyz[3 * v + 2]) * t, corner, k);
        } else {
          corner[0][k] = sx[v]; corner[1][k] = sy[v]; corner[2][k] = sz[v];
        }
      }
      // Newell's normal; its depth component is twice the signed area on screen, positive
      // when the outward face turns counter-clockwise: it looks at us
      let nx = 0, ny = 0, nz = 0, d = 0;
      for (let k = 0; k < n; k++) {
        const j = k + 1 === n ? 0 : k + 1;
        const x0 = corner[0][k], y0 = corner[1][k], z0 = corner[2][k];
        const x1 = corner[0][j], y1 = corner[1][j], z1 = corner[2][j];
        nx += (y0 - y1) * (z0 + z1); ny += (z0 - z1) * (x0 + x1); nz += (x0 - x1) * (y0 + y1);
        d += z0;
      }
      if (!(nz > 0)) continue;
      const length = Math.hypot(nx, ny, nz) || 1;
      shade[i] = 0.45 + 0.55 * Math.abs(nx * light[0] + ny * light[1] + nz * light[2]) / (length * lightLength);
      depth[i] = d / n;
      start[i] = at;
      for (let k = 0; k < n; k++, at++) { fx[at] = w / 2 + corner[0][k] * scale; fy[at] = h / 2 - corner[1][k] * scale; }
      start[i + 1] = at;
      keep.push(i);
    }
    const order = Uint32Array.from(keep);
    order.sort((p, q) => depth[q] - depth[p]);
    const painted = order.length;
    const stroke = painted <= 60000;
    context.lineWidth = painted > 20000 ? 0.5 : 1;
    context.lineJoin = "round";
    context.strokeStyle = "rgba(30, 40, 60, 0.8)";
    const sizes = {};
    for (let j = 0; j < painted; j++) {
      const i = order[j], s = start[i], e = s + cornerStart[slots[i] + 1] - cornerStart[slots[i]];
      sizes[e - s] = (sizes[e - s] || 0) + 1;
      context.beginPath();
      context.moveTo(fx[s], fy[s]);
      for (let k = s + 1; k < e; k++) context.lineTo(fx[k], fy[k]);
      context.closePath();
      const colour = faceColour(owner[slots[i]], cutFlags[i]);
      const t = shade[i];
      context.fillStyle = `rgb(${Math.round(colour[0] * t)}, ${Math.round(colour[1] * t)}, ${Math.round(colour[2] * t)})`;
      context.fill();
      if (stroke) context.stroke();
    }
    frame.painted = painted; frame.sizes = sizes;
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
    if (mixed) {
      row(table, "cells", String(shown.alive));
      for (const [name, n] of Object.entries(shown.aliveKinds)) row(table, name, String(n));
    } else {
      row(table, "tetrahedra", String(shown.alive));
    }
    if (state.clipAxis >= 0) {
      row(table, "kept by the clip", String(shown.kept));
      if (mixed) {
        const kept = Object.entries(shown.keptKinds).map(([name, n]) => `${n} ${name}`);
        row(table, "kept, by kind", kept.join(", ") || "none");
      }
    }
    if (materialRank) {
      for (const [id, n] of Object.entries(shown.keptMaterials)) row(table, `material ${id}`, `${n} cells`);
      table.dataset.materials = JSON.stringify(shown.keptMaterials);
    }
    row(table, state.all ? "faces" : "boundary faces", String(shown.slots.length));
    if (state.clipAxis >= 0) row(table, "faces cut open", String(shown.cutCount));
    row(table, "faces drawn", String(painted));
    row(table, "volume (exact, final)", data.volume);
    row(table, "digest", data.digests[state.step]);
    if (mixed) {
      table.dataset.cells = String(shown.kept);
      table.dataset.kinds = JSON.stringify(shown.aliveKinds);
      table.dataset.keptKinds = JSON.stringify(shown.keptKinds);
    } else {
      table.dataset.tetrahedra = String(shown.kept);
    }
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
    } else if (state.colour === "kind") {
      const present = new Set(kinds);
      for (const [type, name] of KINDS) if (present.has(type)) item(KIND_RGB.get(type), name);
    } else if (state.colour === "material" && materialRank) {
      data.material_ids.forEach((_, i) => item(MATERIAL_RGB[i % MATERIAL_RGB.length], materialLabel(i)));
    } else {
      item(PLAIN, "boundary face");
      item(CUT, "face cut open by the clip");
    }
  }
  // controls: a tetrahedral mesh is coloured by quality, a mixed one by kind
  const colourSelect = document.getElementById("colour");
  colourSelect.querySelector(`option[value="${mixed ? "quality" : "kind"}"]`).remove();
  if (!materialRank) colourSelect.querySelector('option[value="material"]').remove();
  if (mixed) document.getElementById("all-label").textContent = "all cells";
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
  window.geomexactView3d = { state, draw, timings, steps, frame };
})();
