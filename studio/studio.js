// The studio's page: edit a program, see the checker's diagnostics as you type, its matches on
// the open logs after every clean edit, a log from above with a time scrubber, and why a clicked
// object is (or is not) referred at the frame shown. Everything comes from the studio's own
// /api/ (see src/cli/studio.rs); nothing is loaded from another host.
"use strict";

const COLOURS = {
  background: "#f3f1ea", drivable: "#d4d4d4", vehicle: "#bcbcbc", bike: "#8fcf8f", bus: "#e9a9a0",
  laneEdge: "#fafafa", crossing: "#ffffff", crossingEdge: "#7a7a7a",
  referred: "#e6007e", related: "#00b3c7", ego: "#222222", other: "#9e9e9e",
};

const $ = (id) => document.getElementById(id);
const state = {
  logs: [], programs: [], scenes: {}, log: null, frame: 0, mined: null, track: null,
  programName: "", programText: "", view: null, playing: null, minedText: null,
  mining: false, dirty: false, explainTimer: null, checkTimer: null, requests: 0,
};

async function api(path, body) {
  const init = body === undefined ? {} : {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
  };
  const response = await fetch(path, init);
  const answer = await response.json();
  if (!response.ok && answer.error === undefined) answer.error = `HTTP ${response.status}`;
  return answer;
}

function status(text) { $("status").textContent = text; }

// ---- the editor ------------------------------------------------------------------------------

/// The offset in `text` (UTF-16 units, as JavaScript counts) of an editor position.
function offsetOf(text, pos) {
  let line = 0, i = 0;
  while (line < pos.line) {
    const next = text.indexOf("\n", i);
    if (next < 0) return text.length;
    i = next + 1; line++;
  }
  return Math.min(i + pos.character, text.length);
}

function escapeHtml(s) {
  return s.replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]));
}

function showDiagnostics(text, diagnostics) {
  const marks = diagnostics.map((d) => {
    let a = offsetOf(text, d.range.start), b = offsetOf(text, d.range.end);
    if (b <= a) b = Math.min(a + 1, text.length);
    if (b <= a && a > 0) a -= 1;
    return { a, b, level: d.level };
  }).sort((x, y) => x.a - y.a);
  let html = "", at = 0;
  for (const m of marks) {
    if (m.a < at) continue;
    html += escapeHtml(text.slice(at, m.a));
    html += `<mark class="${m.level}">${escapeHtml(text.slice(m.a, m.b))}</mark>`;
    at = m.b;
  }
  html += escapeHtml(text.slice(at)) + "\n";
  $("backdrop").innerHTML = html;
  const list = $("diagnostics");
  list.innerHTML = "";
  if (diagnostics.length === 0) {
    const li = document.createElement("li");
    li.className = "clean";
    li.textContent = "No errors or warnings.";
    list.append(li);
  }
  for (const d of diagnostics) {
    const li = document.createElement("li");
    li.className = d.level;
    li.textContent = `${d.range.start.line + 1}:${d.range.start.character + 1} ${d.level} ${d.code}: ${d.message}`;
    li.addEventListener("click", () => {
      const t = $("text");
      const a = offsetOf(t.value, d.range.start);
      t.focus();
      t.setSelectionRange(a, Math.max(a, offsetOf(t.value, d.range.end)));
    });
    list.append(li);
  }
}

function edited() {
  const text = $("text").value;
  $("backdrop").scrollTop = $("text").scrollTop;
  clearTimeout(state.checkTimer);
  state.checkTimer = setTimeout(() => check(text), 200);
  if (state.programName && text !== state.programText) {
    state.programName = "";
    $("program").value = "";
  }
}

async function check(text) {
  const answer = await api("/api/check", { text });
  if ($("text").value !== text) return;
  showDiagnostics(text, answer.diagnostics || []);
  const clean = (answer.diagnostics || []).every((d) => d.level !== "error");
  if (clean) mine();
}

/// Mines the open logs with the editor's program; one round at a time, the newest text next.
async function mine() {
  if (state.mining) { state.dirty = true; return; }
  const text = $("text").value;
  if (text === state.minedText) return;
  state.mining = true;
  status("mining…");
  try {
    const answer = await api("/api/mine", { text });
    if (answer.logs) {
      state.mined = answer;
      state.minedText = text;
      const count = answer.logs.reduce((n, l) => n + (l.tracks ? l.tracks.length : 0), 0);
      status(`${count} matched tracks on ${answer.logs.length} logs in ${answer.ms.toFixed(0)} ms`);
      showMatches();
      draw();
      if (state.track) explainSoon(0);
    } else {
      status(answer.error || "the program has errors");
    }
  } finally {
    state.mining = false;
    if (state.dirty) { state.dirty = false; mine(); }
  }
}

// ---- matches -----------------------------------------------------------------------------------

function minedLog(id) {
  return state.mined ? state.mined.logs.find((l) => l.log === id) : undefined;
}

function showMatches() {
  const box = $("matches");
  box.innerHTML = "";
  if (!state.mined) return;
  // The log on the map first.
  const logs = state.mined.logs.slice().sort((a, b) => (b.log === state.log) - (a.log === state.log));
  for (const l of logs) {
    const h = document.createElement("h3");
    const n = l.tracks ? l.tracks.length : 0;
    h.textContent = `log ${l.log.slice(0, 8)}: ${l.error ? "failed" : `${n} tracks`}` +
      (l.ms !== undefined ? ` (${l.ms.toFixed(0)} ms)` : "");
    box.append(h);
    if (l.error) {
      const p = document.createElement("p");
      p.className = "error";
      p.textContent = l.error;
      box.append(p);
      continue;
    }
    for (const t of l.tracks) {
      const b = document.createElement("button");
      b.type = "button";
      b.className = "match" + (state.track === t.uuid && state.log === l.log ? " selected" : "");
      b.dataset.log = l.log;
      b.dataset.track = t.uuid;
      const first = t.frames[0], last = t.frames[t.frames.length - 1];
      b.textContent = `${t.uuid.slice(0, 8)} ${t.category} frames ${first}–${last} (${t.frames.length})`;
      b.addEventListener("click", () => select(l.log, t.uuid, first));
      box.append(b);
    }
  }
  const chosen = box.querySelector("button.selected");
  if (chosen) chosen.scrollIntoView({ block: "nearest" });
}

// ---- the map -----------------------------------------------------------------------------------

async function openLog(id) {
  if (!state.scenes[id]) {
    status(`loading log ${id.slice(0, 8)}…`);
    const scene = await api(`/api/scene?log=${encodeURIComponent(id)}`);
    if (scene.error) { status(scene.error); return false; }
    scene.byUuid = {};
    for (const t of scene.tracks) scene.byUuid[t.uuid] = t;
    state.scenes[id] = scene;
  }
  state.log = id;
  $("log").value = id;
  const scene = state.scenes[id];
  $("scrubber").max = String(scene.times.length - 1);
  state.frame = Math.min(state.frame, scene.times.length - 1);
  state.view = fit(scene);
  return true;
}

/// A view framing the ego vehicle's path with 40 m around it.
function fit(scene) {
  const ego = scene.tracks.find((t) => t.category === "EGO_VEHICLE") || scene.tracks[0];
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  const boxes = ego ? ego.boxes : [];
  for (let i = 0; i < boxes.length; i += 6) {
    x0 = Math.min(x0, boxes[i + 1]); x1 = Math.max(x1, boxes[i + 1]);
    y0 = Math.min(y0, boxes[i + 2]); y1 = Math.max(y1, boxes[i + 2]);
  }
  if (!isFinite(x0)) { x0 = -50; y0 = -50; x1 = 50; y1 = 50; }
  sizeCanvas();
  const canvas = $("map");
  const w = x1 - x0 + 80, h = y1 - y0 + 80;
  return { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale: Math.min(canvas.width / w, canvas.height / h) };
}

function toPixel(x, y) {
  const c = $("map"), v = state.view;
  return [c.width / 2 + (x - v.cx) * v.scale, c.height / 2 - (y - v.cy) * v.scale];
}

function toWorld(px, py) {
  const c = $("map"), v = state.view;
  return [v.cx + (px - c.width / 2) / v.scale, v.cy - (py - c.height / 2) / v.scale];
}

function polygonPath(ctx, flat) {
  ctx.beginPath();
  for (let i = 0; i < flat.length; i += 2) {
    const [px, py] = toPixel(flat[i], flat[i + 1]);
    if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
  }
  ctx.closePath();
}

/// The box of track `t` at `frame`: [x, y, yaw, length, width] or null.
function boxAt(t, frame) {
  const b = t.boxes;
  let lo = 0, hi = b.length / 6 - 1;
  while (lo <= hi) {
    const mid = (lo + hi) >> 1, f = b[mid * 6];
    if (f === frame) return b.slice(mid * 6 + 1, mid * 6 + 6);
    if (f < frame) lo = mid + 1; else hi = mid - 1;
  }
  return null;
}

/// Per track uuid at the shown frame: "referred" or "related".
function roles() {
  const out = {};
  const l = minedLog(state.log);
  if (!l || !l.tracks) return out;
  for (const t of l.tracks) {
    if (t.frames.includes(state.frame)) {
      out[t.uuid] = "referred";
      for (const [other, f] of t.related) if (f === state.frame && !out[other]) out[other] = "related";
    }
  }
  return out;
}

/// The canvas's drawing size made its size on the page.
function sizeCanvas() {
  const canvas = $("map");
  const rect = canvas.getBoundingClientRect();
  if (rect.width > 0 && (canvas.width !== Math.round(rect.width) || canvas.height !== Math.round(rect.height))) {
    canvas.width = Math.round(rect.width);
    canvas.height = Math.round(rect.height);
  }
}

function draw() {
  sizeCanvas();
  const canvas = $("map");
  const ctx = canvas.getContext("2d");
  ctx.fillStyle = COLOURS.background;
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  const scene = state.scenes[state.log];
  if (!scene || !state.view) return;
  ctx.fillStyle = COLOURS.drivable;
  for (const p of scene.drivable) { polygonPath(ctx, p); ctx.fill(); }
  ctx.strokeStyle = COLOURS.laneEdge;
  ctx.lineWidth = 0.8;
  for (const l of scene.lanes) {
    polygonPath(ctx, l.polygon);
    ctx.fillStyle = COLOURS[l.type] || COLOURS.vehicle;
    ctx.globalAlpha = l.intersection ? 0.45 : 1;
    ctx.fill();
    ctx.globalAlpha = 1;
    ctx.stroke();
  }
  ctx.strokeStyle = COLOURS.crossingEdge;
  ctx.fillStyle = COLOURS.crossing;
  for (const p of scene.crossings) { polygonPath(ctx, p); ctx.fill(); ctx.stroke(); }
  const role = roles();
  const order = (t) => (role[t.uuid] === "referred" ? 3 : role[t.uuid] === "related" ? 2 : t.category === "EGO_VEHICLE" ? 1 : 0);
  const tracks = scene.tracks.slice().sort((a, b) => order(a) - order(b));
  for (const t of tracks) {
    const b = boxAt(t, state.frame);
    if (!b) continue;
    const [x, y, yaw, len, wid] = b;
    const [px, py] = toPixel(x, y);
    ctx.save();
    ctx.translate(px, py);
    ctx.rotate(-yaw);
    const w = Math.max(len * state.view.scale, 3), h = Math.max(wid * state.view.scale, 3);
    ctx.fillStyle = role[t.uuid] ? COLOURS[role[t.uuid]] : t.category === "EGO_VEHICLE" ? COLOURS.ego : COLOURS.other;
    ctx.fillRect(-w / 2, -h / 2, w, h);
    ctx.fillStyle = "rgba(255,255,255,0.8)";
    ctx.fillRect(w / 2 - Math.min(w / 4, 4), -h / 2, Math.min(w / 4, 4), h);
    if (t.uuid === state.track) {
      ctx.strokeStyle = "#000";
      ctx.lineWidth = 2.5;
      ctx.strokeRect(-w / 2 - 3, -h / 2 - 3, w + 6, h + 6);
    }
    ctx.restore();
  }
  const times = scene.times;
  $("clock").textContent = `${(times[state.frame] || 0).toFixed(1)} s (frame ${state.frame})`;
  $("scrubber").value = String(state.frame);
}

/// Moves the view so that track `uuid`'s box at the shown frame is in it, when it is not.
function centreOn(uuid) {
  const scene = state.scenes[state.log];
  const t = scene && scene.byUuid[uuid];
  const b = t && boxAt(t, state.frame);
  if (!b || !state.view) return;
  const [px, py] = toPixel(b[0], b[1]);
  const c = $("map");
  if (px < 40 || py < 40 || px > c.width - 40 || py > c.height - 40) {
    state.view.cx = b[0];
    state.view.cy = b[1];
  }
}

/// The object under a click at the shown frame (inside its box, or within 2 m).
function objectAt(px, py) {
  const scene = state.scenes[state.log];
  if (!scene) return null;
  const [wx, wy] = toWorld(px, py);
  let best = null, bestD = 2;
  for (const t of scene.tracks) {
    const b = boxAt(t, state.frame);
    if (!b) continue;
    const [x, y, yaw, len, wid] = b;
    const dx = wx - x, dy = wy - y;
    const u = Math.abs(dx * Math.cos(yaw) + dy * Math.sin(yaw)) - len / 2;
    const v = Math.abs(-dx * Math.sin(yaw) + dy * Math.cos(yaw)) - wid / 2;
    const d = Math.hypot(Math.max(u, 0), Math.max(v, 0));
    if (d < bestD || (d === 0 && best === null)) { best = t.uuid; bestD = d; }
  }
  return best;
}

// ---- explaining --------------------------------------------------------------------------------

async function select(log, uuid, frame) {
  if (log !== state.log && !(await openLog(log))) return;
  state.track = uuid;
  if (frame !== undefined) state.frame = frame;
  centreOn(uuid);
  draw();
  showMatches();
  explainSoon(0);
}

function explainSoon(delay) {
  clearTimeout(state.explainTimer);
  state.explainTimer = setTimeout(explain, delay);
}

async function explain() {
  if (!state.track || !state.log) return;
  const request = { text: $("text").value, log: state.log, track: state.track, frame: state.frame };
  const id = ++state.requests;
  const answer = await api("/api/explain", request);
  if (id !== state.requests) return;
  $("proof").textContent = answer.text || answer.error || "the program has errors";
  updateHash();
}

function updateHash() {
  const scene = state.scenes[state.log];
  const parts = [];
  if (state.programName) parts.push(`program=${encodeURIComponent(state.programName)}`);
  if (state.log) parts.push(`log=${encodeURIComponent(state.log)}`);
  if (state.track) parts.push(`track=${encodeURIComponent(state.track)}`);
  if (scene) parts.push(`t=${(scene.times[state.frame] || 0).toFixed(1)}`);
  history.replaceState(null, "", "#" + parts.join("&"));
}

// ---- the page ----------------------------------------------------------------------------------

async function openProgram(name) {
  const answer = await api(`/api/program?name=${encodeURIComponent(name)}`);
  if (answer.error) { status(answer.error); return; }
  state.programName = name;
  state.programText = answer.text;
  $("program").value = name;
  $("text").value = answer.text;
  edited();
}

function frameAt(scene, seconds) {
  let best = 0;
  scene.times.forEach((s, i) => { if (Math.abs(s - seconds) < Math.abs(scene.times[best] - seconds)) best = i; });
  return best;
}

/// Opens what the address's fragment names (`#program=…&log=…&track=…&t=…`, as `mine` prints
/// and the report links): the program, the log, the frame nearest `t` seconds, the track's proof.
async function applyHash() {
  const hash = new URLSearchParams(location.hash.slice(1));
  const log = state.logs.find((l) => l.id === hash.get("log")) ? hash.get("log") : state.log || (state.logs[0] && state.logs[0].id);
  if (log && log !== state.log) await openLog(log);
  const program = hash.get("program") || (state.programName ? null : state.programs.includes("stopped_car") ? "stopped_car" : state.programs[0]);
  if (program && program !== state.programName) await openProgram(program);
  const scene = state.scenes[state.log];
  if (scene && hash.get("t") !== null) state.frame = frameAt(scene, Number(hash.get("t")));
  if (hash.get("track")) {
    const scene = state.scenes[state.log];
    const uuid = hash.get("track");
    const full = scene ? scene.tracks.find((t) => t.uuid.startsWith(uuid)) : null;
    state.track = full ? full.uuid : uuid;
    centreOn(state.track);
    explainSoon(0);
  }
  showMatches();
  draw();
}

async function start() {
  const answer = await api("/api/logs");
  state.logs = answer.logs;
  state.programs = answer.programs;
  for (const p of state.programs) $("program").append(new Option(p, p));
  $("describe").hidden = !answer.synthesize;
  $("describe").addEventListener("submit", async (e) => {
    e.preventDefault();
    const description = $("description").value;
    $("write").disabled = true;
    status("the LLM is writing the rule…");
    try {
      const written = await api("/api/synth", { description });
      if (typeof written.program === "string") {
        state.programName = "";
        $("program").value = "";
        $("text").value = written.program;
        edited();
      }
      status(written.error || `written in ${written.rounds} round(s); checking and mining…`);
    } finally {
      $("write").disabled = false;
    }
  });
  for (const l of state.logs) $("log").append(new Option(`${l.id.slice(0, 8)} (${l.city}, ${l.tracks} tracks)`, l.id));
  await applyHash();
  draw();

  $("text").addEventListener("input", edited);
  $("text").addEventListener("scroll", () => { $("backdrop").scrollTop = $("text").scrollTop; });
  $("program").addEventListener("change", (e) => { if (e.target.value) openProgram(e.target.value); });
  $("log").addEventListener("change", async (e) => {
    state.track = null;
    if (await openLog(e.target.value)) { draw(); showMatches(); updateHash(); }
  });
  $("scrubber").addEventListener("input", (e) => {
    state.frame = Number(e.target.value);
    draw();
    if (state.track) explainSoon(150);
  });
  $("play").addEventListener("click", () => {
    if (state.playing) {
      clearInterval(state.playing); state.playing = null; $("play").textContent = "Play";
      if (state.track) explainSoon(0);
      return;
    }
    $("play").textContent = "Pause";
    state.playing = setInterval(() => {
      const scene = state.scenes[state.log];
      if (!scene) return;
      state.frame = (state.frame + 1) % scene.times.length;
      draw();
    }, 100);
  });
  const canvas = $("map");
  let drag = null;
  canvas.addEventListener("mousedown", (e) => { drag = { x: e.offsetX, y: e.offsetY, moved: false }; });
  canvas.addEventListener("mousemove", (e) => {
    if (!drag || !state.view) return;
    const dx = e.offsetX - drag.x, dy = e.offsetY - drag.y;
    if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
    if (drag.moved) {
      state.view.cx -= dx / state.view.scale;
      state.view.cy += dy / state.view.scale;
      drag.x = e.offsetX; drag.y = e.offsetY;
      draw();
    }
  });
  canvas.addEventListener("mouseup", (e) => {
    const moved = drag && drag.moved;
    drag = null;
    if (moved) return;
    const uuid = objectAt(e.offsetX, e.offsetY);
    if (uuid) select(state.log, uuid);
  });
  canvas.addEventListener("wheel", (e) => {
    if (!state.view) return;
    e.preventDefault();
    const [wx, wy] = toWorld(e.offsetX, e.offsetY);
    state.view.scale *= e.deltaY < 0 ? 1.2 : 1 / 1.2;
    const [nx, ny] = toWorld(e.offsetX, e.offsetY);
    state.view.cx += wx - nx; state.view.cy += wy - ny;
    draw();
  }, { passive: false });
  window.addEventListener("resize", draw);
  window.addEventListener("hashchange", applyHash);
}

start().catch((e) => status(`the studio failed to start: ${e}`));
