// geomexact 3D viewer: a tetrahedral mesh drawn on a 2D canvas with an orthographic
// projection and the painter's algorithm (faces sorted by depth).  No network access.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("geomexact-data").textContent);
  function decode(text, Type) {
    const raw = atob(text);
    const bytes = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  const xyz = decode(data.xyz, Float64Array);
  const cells = decode(data.cells, Uint32Array);
  const birth = decode(data.birth, Int32Array);
  const death = decode(data.death, Int32Array);
  const quality = decode(data.quality, Float64Array);
  const creator = decode(data.creator, Uint8Array);
  const cellCount = birth.length;
  const canvas = document.getElementById("view");
  const context = canvas.getContext("2d");
  const state = { yaw: 0.6, pitch: 0.45, zoom: 1, step: data.options.step,
                  colour: data.options.colour, shrink: 0, all: false };
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
  function cellColour(c) {
    if (state.colour === "quality") return qualityColour(quality[c]);
    if (state.colour === "step") return hexColour(OP_COLOURS[creator[c] % OP_COLOURS.length]);
    return [150, 170, 200];
  }
  function aliveAt(step) {
    const alive = [];
    for (let c = 0; c < cellCount; c++) if (birth[c] <= step && step < death[c]) alive.push(c);
    return alive;
  }
  let cached = null;  // the alive tetrahedra and faces of one (step, all): rotation reuses them
  const FACES = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
  function facesToDraw(alive) {
    // [cell, a, b, c] for every face drawn: the boundary faces, or all with "all tetrahedra"
    const count = new Map();
    const list = [];
    for (const c of alive) {
      for (const f of FACES) {
        const a = cells[4 * c + f[0]], b = cells[4 * c + f[1]], d = cells[4 * c + f[2]];
        const key = [a, b, d].sort((x, y) => x - y).join(",");
        count.set(key, (count.get(key) || 0) + 1);
        list.push([c, a, b, d, key]);
      }
    }
    return state.all ? list : list.filter((face) => count.get(face[4]) === 1);
  }
  function resize() {
    const ratio = window.devicePixelRatio || 1;
    const box = document.getElementById("stage").getBoundingClientRect();
    const width = Math.max(1, Math.floor(box.width)), height = Math.max(1, Math.floor(box.height));
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
    canvas.style.width = width + "px";
    canvas.style.height = height + "px";
    cached = null;
  }
  function draw() {
    if (!cached || cached.step !== state.step || cached.all !== state.all) {
      const alive = aliveAt(state.step);
      cached = { step: state.step, all: state.all, alive, faces: facesToDraw(alive) };
    }
    const alive = cached.alive, faces = cached.faces;
    const w = canvas.width, h = canvas.height;
    context.setTransform(1, 0, 0, 1, 0, 0);
    context.fillStyle = "#ffffff";
    context.fillRect(0, 0, w, h);
    const cy = Math.cos(state.yaw), sy = Math.sin(state.yaw);
    const cp = Math.cos(state.pitch), sp = Math.sin(state.pitch);
    const scale = state.zoom * 0.45 * Math.min(w, h) / radius;
    const light = [0.3, 0.5, 0.8];
    const polygons = [];
    for (const face of faces) {
      const c = face[0];
      const centroid = [0, 0, 0];
      for (let k = 0; k < 4; k++) {
        const v = cells[4 * c + k];
        for (let j = 0; j < 3; j++) centroid[j] += xyz[3 * v + j] / 4;
      }
      const points = [];
      for (let k = 1; k < 4; k++) {
        const v = face[k];
        const p = [0, 1, 2].map((j) => xyz[3 * v + j] + (centroid[j] - xyz[3 * v + j]) * state.shrink - centre[j]);
        // rotate about the vertical axis, then tilt
        const x1 = cy * p[0] + sy * p[1], y1 = -sy * p[0] + cy * p[1], z1 = p[2];
        const y2 = cp * y1 - sp * z1, z2 = sp * y1 + cp * z1;
        points.push([x1, z2, y2]);  // screen x, screen up, depth (larger: farther)
      }
      const u = [0, 1, 2].map((j) => points[1][j] - points[0][j]);
      const v = [0, 1, 2].map((j) => points[2][j] - points[0][j]);
      const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
      const length = Math.hypot(n[0], n[1], n[2]) || 1;
      const shade = 0.45 + 0.55 * Math.abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / length;
      const depth = (points[0][2] + points[1][2] + points[2][2]) / 3;
      polygons.push({ points, depth, colour: cellColour(c), shade });
    }
    polygons.sort((p, q) => q.depth - p.depth);
    context.lineWidth = 1;
    context.strokeStyle = "rgba(30, 40, 60, 0.8)";
    for (const polygon of polygons) {
      context.beginPath();
      polygon.points.forEach((p, i) => {
        const sx = w / 2 + p[0] * scale, sy2 = h / 2 - p[1] * scale;
        if (i === 0) context.moveTo(sx, sy2); else context.lineTo(sx, sy2);
      });
      context.closePath();
      const [r, g, b] = polygon.colour.map((x) => Math.round(x * polygon.shade));
      context.fillStyle = `rgb(${r}, ${g}, ${b})`;
      context.fill();
      context.stroke();
    }
    showStats(alive.length, faces.length);
  }
  function row(table, label, value) {
    const tr = document.createElement("tr");
    const th = document.createElement("th"); th.textContent = label;
    const td = document.createElement("td"); td.textContent = value;
    tr.append(th, td); table.append(tr);
  }
  function showStats(tetrahedra, faces) {
    const table = document.getElementById("stats-table");
    table.replaceChildren();
    row(table, "vertices", String(data.vertex_counts[state.step]));
    row(table, "tetrahedra", String(tetrahedra));
    row(table, state.all ? "faces drawn" : "boundary faces", String(faces));
    row(table, "volume (exact, final)", data.volume);
    row(table, "digest", data.digests[state.step]);
    table.dataset.tetrahedra = String(tetrahedra);
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
      data.ops.forEach((op, i) => item(hexColour(OP_COLOURS[i % OP_COLOURS.length]), `created by ${op}`));
    } else {
      item([150, 170, 200], "tetrahedron");
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
  document.getElementById("fit").addEventListener("click", () => {
    state.yaw = 0.6; state.pitch = 0.45; state.zoom = 1; draw();
  });
  const stepInput = document.getElementById("step");
  if (data.steps > 0) {
    document.getElementById("trace").hidden = false;
    stepInput.max = String(data.steps);
    stepInput.value = String(state.step);
    stepInput.addEventListener("input", () => { state.step = Number(stepInput.value); draw(); });
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
  window.geomexactView3d = { state, draw };
})();
