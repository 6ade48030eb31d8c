// The live view: connects to the launcher's Foxglove WebSocket feed (subprotocol
// foxglove.sdk.v1), subscribes to the state, marker and diagnostics channels, decodes their
// CDR with the advertised ros2msg schemas (cdr.js) and draws the machine: the XPlanar table
// and the pick-and-place cell from their MarkerArrays (top view), a scope of the axes'
// SetPos / SetVelo and each node's cycle statistics. `window.motionView` exposes what the
// page knows (for tests and the browser console).
"use strict";

const feedPort = document.querySelector('meta[name="feed-port"]').content;
const view = (window.motionView = {
  connected: false, channels: 0, messages: 0,
  movers: [], axes: [], nodes: [], frames: 0,
  moverPositions: {}, // name -> [x, y] [mm], from the planar state
  transforms: {}, // canvas id -> {e, s, pad, height}: plane [m] -> canvas pixels
  // A point of the plane [m] in canvas pixels of the panel `id` (as last drawn).
  toCanvas(id, x, y) {
    const t = this.transforms[id];
    return t && [t.pad + (x - t.e[0]) * t.s, t.height - t.pad - (y - t.e[1]) * t.s];
  },
});
const markerSets = { planar: new Map(), pickplace: new Map() }; // "ns/id" -> marker
const tcpTrail = [];
const axisHistory = new Map(); // name -> [{t, pos, velo}]
const axisShown = new Map(); // name -> bool
const stats = new Map(); // node -> values
const SCOPE_SPAN = 10; // [s]
const COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"];
const AXIS_STATES = ["Undefined", "Disabled", "Standstill", "ErrorStop", "Stopping", "Homing",
  "DiscreteMotion", "ContinuousMotion", "SynchronizedMotion"];
const MOVER_STATES = ["Invalid", "Disabled", "Enabling", "Enabled", "Disabling", "Error",
  "ErrorPending", "Resetting"];
const PICKPLACE_STATES = ["DISABLED", "READY", "ERROR", "STOP", "SERVICE", "JOGPOS", "JOGNEG",
  "HOMING", "PREPARING_PATH", "MOVE_PP", "PATH_INTERRUPT"];

// ------------------------------------------------------------------ the feed

let ws = null;
let subscriptions = new Map(); // subscription id -> {topic, decode, handle}
let nextSub = 1;

function handlerFor(ch) {
  const t = ch.schemaName;
  if (t === "visualization_msgs/msg/MarkerArray") {
    if (ch.topic.includes("planar")) return (m) => takeMarkers(markerSets.planar, m);
    if (ch.topic.includes("pickplace")) return (m) => takeMarkers(markerSets.pickplace, m, true);
    return null;
  }
  if (t === "motion_msgs/msg/AxisStateArray") return takeAxes;
  if (t === "motion_msgs/msg/PlanarState") return takePlanar;
  if (t === "motion_msgs/msg/PickPlaceState") return takePickPlace;
  if (t === "diagnostic_msgs/msg/DiagnosticArray") return takeDiagnostics;
  return null;
}

function connect() {
  const url = `ws://${location.hostname}:${feedPort}`;
  ws = new WebSocket(url, ["foxglove.sdk.v1"]);
  ws.binaryType = "arraybuffer";
  subscriptions = new Map();
  ws.onopen = () => { view.connected = true; status(`connected to ${url}`); };
  ws.onclose = () => {
    view.connected = false;
    status(`not connected to ${url}; retrying…`);
    setTimeout(connect, 1000);
  };
  ws.onmessage = (ev) => {
    if (typeof ev.data === "string") return onJson(JSON.parse(ev.data));
    const bytes = new Uint8Array(ev.data);
    if (bytes[0] !== 1) return; // MessageData only
    const dv = new DataView(ev.data);
    const sub = subscriptions.get(dv.getUint32(1, true));
    if (!sub) return;
    const logTime = Number(dv.getBigUint64(5, true)) * 1e-9;
    try {
      sub.handle(sub.decode(bytes.subarray(13)), logTime);
      view.messages++;
    } catch (e) {
      console.error(`${sub.topic}: ${e}`);
    }
  };
}

function onJson(msg) {
  if (msg.op !== "advertise") return;
  const subs = [];
  for (const ch of msg.channels) {
    view.channels++;
    if (ch.encoding !== "cdr" || (ch.schemaEncoding && ch.schemaEncoding !== "ros2msg")) continue;
    const handle = handlerFor(ch);
    if (!handle) continue;
    const id = nextSub++;
    subscriptions.set(id, { topic: ch.topic, decode: makeDecoder(ch.schemaName, ch.schema), handle });
    subs.push({ id, channelId: ch.id });
  }
  if (subs.length) ws.send(JSON.stringify({ op: "subscribe", subscriptions: subs }));
  status(`connected to ws://${location.hostname}:${feedPort}: ${view.channels} channels, ${subscriptions.size} shown`);
}

function status(text) { document.getElementById("status").textContent = text; }

// ------------------------------------------------------------------ what the messages say

function takeMarkers(set, msg, trail) {
  for (const m of msg.markers) {
    const key = `${m.ns}/${m.id}`;
    if (m.action === 3) { set.clear(); continue; } // DELETEALL
    if (m.action === 2) { set.delete(key); continue; } // DELETE
    set.set(key, m);
    if (trail && m.ns === "tcp") {
      tcpTrail.push([m.pose.position.x, m.pose.position.y]);
      if (tcpTrail.length > 2000) tcpTrail.shift();
    }
  }
}

function stampOf(s) { return s.sec + s.nanosec * 1e-9; }

function takeAxes(msg) {
  const t = stampOf(msg.header.stamp);
  const names = [];
  for (const a of msg.axes) {
    names.push(a.name);
    if (!axisHistory.has(a.name)) { axisHistory.set(a.name, []); axisShown.set(a.name, true); }
    const h = axisHistory.get(a.name);
    if (h.length && t < h[h.length - 1].t) h.length = 0; // time went back (restart)
    h.push({ t, pos: a.set_pos, velo: a.set_velo, state: a.motion_state });
    while (h.length && h[0].t < t - SCOPE_SPAN) h.shift();
  }
  if (names.join() !== view.axes.join()) { view.axes = names; listAxes(); }
  for (const a of msg.axes) {
    const el = document.getElementById(`axis-state-${a.name}`);
    if (el) el.textContent = `${AXIS_STATES[a.motion_state] ?? a.motion_state} ${a.set_pos.toFixed(2)}`;
  }
}

function listAxes() {
  const box = document.getElementById("axes");
  box.innerHTML = "";
  view.axes.forEach((name, i) => {
    const label = document.createElement("label");
    label.innerHTML = `<input type="checkbox" data-axis="${name}" ${axisShown.get(name) ? "checked" : ""}>` +
      `<span class="swatch" style="background:${COLORS[i % COLORS.length]}"></span>${name} ` +
      `<small id="axis-state-${name}"></small>`;
    label.querySelector("input").onchange = (e) => axisShown.set(name, e.target.checked);
    box.appendChild(label);
  });
}

function takePlanar(msg) {
  view.movers = msg.movers.map((m) => m.name);
  view.moverPositions = Object.fromEntries(msg.movers.map((m) => [m.name, [m.x, m.y]]));
  const ul = document.getElementById("movers");
  ul.innerHTML = msg.movers.map((m) =>
    `<li data-mover="${m.name}">${m.name}: ${MOVER_STATES[m.state] ?? m.state} at (${m.x.toFixed(1)}, ` +
    `${m.y.toFixed(1)}) mm${m.track ? " on " + m.track : ""}</li>`).join("");
}

function takePickPlace(msg) {
  const wp = msg.belts.reduce((n, b) => n + b.workpieces.length, 0);
  document.getElementById("pickplace-info").textContent =
    `${PICKPLACE_STATES[msg.state] ?? msg.state}; TCP (${msg.tcp_x.toFixed(1)}, ${msg.tcp_y.toFixed(1)}, ` +
    `${msg.tcp_z.toFixed(1)}) mm; gripper ${msg.gripper_closed ? "closed" : "open"}; ${wp} workpieces on the belts`;
}

function takeDiagnostics(msg) {
  for (const s of msg.status) {
    if (!s.name.endsWith(": cycle")) continue;
    const v = Object.fromEntries(s.values.map((kv) => [kv.key, kv.value]));
    stats.set(s.hardware_id, v);
  }
  view.nodes = [...stats.keys()];
  document.querySelector("#stats tbody").innerHTML = [...stats].map(([node, v]) =>
    `<tr><td>${node}</td><td>${v.period_us}</td><td>${v.cycles}</td><td>${v.overruns}</td>` +
    `<td>${v.exec_mean_us}</td><td>${v.exec_p99_us}</td><td>${v.exec_max_us}</td>` +
    `<td>${v.jitter_p99_us}</td><td>${v.jitter_max_us}</td><td>${v.lockstep}</td></tr>`).join("");
}

// ------------------------------------------------------------------ drawing

function rgba(c, a) {
  const k = (x) => Math.round(Math.min(1, Math.max(0, x)) * 255);
  return `rgba(${k(c.r)},${k(c.g)},${k(c.b)},${a ?? c.a})`;
}

function yaw(q) { return Math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)); }

// Points of a marker in the plane (for the view's extent).
function markerPoints(m) {
  const p = m.pose.position;
  if (m.points.length) return m.points.map((q) => [p.x + q.x, p.y + q.y]);
  const hx = m.scale.x / 2, hy = m.scale.y / 2;
  return [[p.x - hx, p.y - hy], [p.x + hx, p.y + hy]];
}

const extents = new Map(); // canvas id -> [x0, y0, x1, y1], grows only (no jumping view)

function drawMarkers(canvas, set, trail) {
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!set.size) return;
  let e = extents.get(canvas.id);
  for (const m of set.values()) {
    if (m.type === 9) continue;
    for (const [x, y] of markerPoints(m)) {
      if (!e) e = [x, y, x, y];
      e = [Math.min(e[0], x), Math.min(e[1], y), Math.max(e[2], x), Math.max(e[3], y)];
    }
  }
  if (!e) return;
  extents.set(canvas.id, e);
  const pad = 20, w = canvas.width - 2 * pad, h = canvas.height - 2 * pad;
  const s = Math.min(w / Math.max(1e-6, e[2] - e[0]), h / Math.max(1e-6, e[3] - e[1]));
  view.transforms[canvas.id] = { e, s, pad, height: canvas.height };
  const X = (x) => pad + (x - e[0]) * s;
  const Y = (y) => canvas.height - pad - (y - e[1]) * s;
  const byKind = [...set.values()].sort((a, b) => order(a) - order(b));
  for (const m of byKind) drawMarker(ctx, m, X, Y, s);
  if (trail && trail.length > 1) {
    ctx.strokeStyle = "rgba(214,39,40,0.6)";
    ctx.lineWidth = 1;
    ctx.beginPath();
    trail.forEach(([x, y], i) => (i ? ctx.lineTo(X(x), Y(y)) : ctx.moveTo(X(x), Y(y))));
    ctx.stroke();
  }
  // Scale bar: 100 mm.
  ctx.fillStyle = "#555";
  ctx.fillRect(pad, canvas.height - 8, 0.1 * s, 2);
  ctx.font = "10px sans-serif";
  ctx.fillText("100 mm", pad + 0.1 * s + 4, canvas.height - 4);
}

// Flat things first, texts last.
function order(m) { return m.type === 9 ? 3 : m.type === 6 || m.type === 5 ? 0 : m.type === 4 ? 1 : 2; }

function drawMarker(ctx, m, X, Y, s) {
  const p = m.pose.position;
  ctx.fillStyle = rgba(m.color);
  ctx.strokeStyle = rgba(m.color, 1);
  ctx.lineWidth = Math.max(1, m.scale.x * s);
  switch (m.type) {
    case 1: case 3: { // CUBE, CYLINDER
      ctx.save();
      ctx.translate(X(p.x), Y(p.y));
      ctx.rotate(-yaw(m.pose.orientation));
      if (m.type === 3) {
        ctx.beginPath();
        ctx.ellipse(0, 0, (m.scale.x * s) / 2, (m.scale.y * s) / 2, 0, 0, 2 * Math.PI);
        ctx.fill();
      } else {
        ctx.fillRect((-m.scale.x * s) / 2, (-m.scale.y * s) / 2, m.scale.x * s, m.scale.y * s);
        ctx.strokeStyle = "rgba(0,0,0,0.5)";
        ctx.lineWidth = 1;
        ctx.strokeRect((-m.scale.x * s) / 2, (-m.scale.y * s) / 2, m.scale.x * s, m.scale.y * s);
      }
      ctx.restore();
      break;
    }
    case 2: // SPHERE
      ctx.beginPath();
      ctx.arc(X(p.x), Y(p.y), Math.max(2, (m.scale.x * s) / 2), 0, 2 * Math.PI);
      ctx.fill();
      break;
    case 4: case 5: { // LINE_STRIP, LINE_LIST
      ctx.lineWidth = Math.max(1, m.scale.x * s);
      ctx.beginPath();
      m.points.forEach((q, i) => {
        const x = X(p.x + q.x), y = Y(p.y + q.y);
        const move = m.type === 4 ? i === 0 : i % 2 === 0;
        if (move) ctx.moveTo(x, y); else ctx.lineTo(x, y);
      });
      ctx.stroke();
      break;
    }
    case 6: case 7: case 8: { // CUBE_LIST, SPHERE_LIST, POINTS
      m.points.forEach((q, i) => {
        const c = m.colors[i] ?? m.color;
        ctx.fillStyle = rgba(c);
        const w = Math.max(2, m.scale.x * s), h = Math.max(2, m.scale.y * s);
        const x = X(p.x + q.x), y = Y(p.y + q.y);
        if (m.type === 6) {
          ctx.fillRect(x - w / 2, y - h / 2, w, h);
          ctx.strokeStyle = "rgba(255,255,255,0.9)";
          ctx.lineWidth = 1;
          ctx.strokeRect(x - w / 2, y - h / 2, w, h);
        } else {
          ctx.beginPath();
          ctx.arc(x, y, w / 2, 0, 2 * Math.PI);
          ctx.fill();
        }
      });
      break;
    }
    case 9: // TEXT_VIEW_FACING
      ctx.fillStyle = "#111";
      ctx.font = "bold 12px sans-serif";
      ctx.textAlign = "center";
      ctx.fillText(m.text, X(p.x), Y(p.y) + 4);
      ctx.textAlign = "left";
      break;
  }
}

function drawScope(canvas, field, unit) {
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const shown = view.axes.filter((a) => axisShown.get(a));
  let tEnd = -Infinity, lo = Infinity, hi = -Infinity;
  for (const a of shown) {
    const h = axisHistory.get(a) || [];
    if (h.length) tEnd = Math.max(tEnd, h[h.length - 1].t);
    for (const q of h) { lo = Math.min(lo, q[field]); hi = Math.max(hi, q[field]); }
  }
  const left = 70, right = 10, top = 8, bottom = 22;
  const w = canvas.width - left - right, h = canvas.height - top - bottom;
  ctx.strokeStyle = "#999";
  ctx.strokeRect(left, top, w, h);
  ctx.fillStyle = "#333";
  ctx.font = "11px sans-serif";
  ctx.fillText(`${field === "pos" ? "SetPos" : "SetVelo"} [${unit}]`, 4, top + 10);
  if (!isFinite(tEnd)) return;
  if (hi - lo < 1e-9) { hi += 1; lo -= 1; }
  const X = (t) => left + ((t - (tEnd - SCOPE_SPAN)) / SCOPE_SPAN) * w;
  const Y = (v) => top + h - ((v - lo) / (hi - lo)) * h;
  ctx.fillText(hi.toPrecision(4), 4, top + 24);
  ctx.fillText(lo.toPrecision(4), 4, top + h);
  for (let k = 0; k <= SCOPE_SPAN; k += 2) {
    ctx.fillText(`${(k - SCOPE_SPAN).toFixed(0)} s`, X(tEnd - SCOPE_SPAN + k) - 8, canvas.height - 6);
  }
  view.axes.forEach((a, i) => {
    if (!axisShown.get(a)) return;
    const hist = axisHistory.get(a) || [];
    ctx.strokeStyle = COLORS[i % COLORS.length];
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    hist.forEach((q, k) => (k ? ctx.lineTo(X(q.t), Y(q[field])) : ctx.moveTo(X(q.t), Y(q[field]))));
    ctx.stroke();
  });
}

function frame() {
  drawMarkers(document.getElementById("planar"), markerSets.planar);
  drawMarkers(document.getElementById("pickplace"), markerSets.pickplace, tcpTrail);
  drawScope(document.getElementById("scope-pos"), "pos", "u");
  drawScope(document.getElementById("scope-velo"), "velo", "u/s");
  view.frames++;
  requestAnimationFrame(frame);
}

connect();
requestAnimationFrame(frame);
