// The classroom page: join with a code, then the helm, the instructor's console or a spectator's chart.
// Everything shown comes from the server's websocket (same origin, /ws); text is set with textContent only.
"use strict";

const RUDDER_MAX = 35, RUDDER_STEP = 5, MIN_SEND_MS = 50, MIN_SHIP_PX = 24;
const WIDE_PX = 760;  // a chart box this wide shows the chart and the 3D view side by side
const VIEWS = ["both", "chart", "3d"];
const TELEGRAPH = { "-4": "full astern", "-3": "half astern", "-2": "slow astern", "-1": "dead slow astern",
  "0": "stop", "1": "dead slow ahead", "2": "slow ahead", "3": "half ahead", "4": "full ahead" };
const $ = (id) => document.getElementById(id);

// What the page knows; window.vg is read by the tests and the latency benchmark.
const vg = window.vg = { role: null, ship: -1, session: "", chart: null, state: null, track: [], view: "chart", view3d: null,
  rudder: 0, telegraph: 0, seq: 0, sentAt: {}, latencies: [], lastSend: 0, pending: null, errors: [] };
let ws = null;

function send(msg) {
  if (ws && ws.readyState === 1) ws.send(JSON.stringify(msg));
}

function join() {
  const code = $("code").value.trim();
  const name = $("name").value.trim();
  const proto = location.protocol === "https:" ? "wss:" : "ws:";
  ws = new WebSocket(`${proto}//${location.host}/ws`);
  ws.onopen = () => send({ type: "join", code: code, name: name });
  ws.onmessage = (ev) => receive(JSON.parse(ev.data));
  ws.onclose = (ev) => {
    $("joinmsg").textContent = `disconnected (${ev.code}${ev.reason ? ": " + ev.reason : ""})`;
    $("msg").textContent = $("joinmsg").textContent;
  };
}

function receive(m) {
  if (m.type === "welcome") {
    vg.role = m.role; vg.ship = m.ship; vg.session = m.session; vg.chart = m.chart;
    $("join").classList.add("hidden");
    $("app").style.display = "flex";
    $("app").classList.add(`role-${m.role}`);
    $(m.role === "helm" ? "helm" : m.role === "instructor" ? "instr" : "watch").classList.remove("hidden");
    $("who").textContent = m.role === "helm" ? `helm of ship ${m.ship + 1}` : m.role;
    if (m.scene3d && window.Scene3D) {
      try {
        vg.view3d = new window.Scene3D($("view3d"), m.scene3d);
      } catch (err) {
        vg.errors.push(`3D view: ${err.message}`);
      }
      if (vg.view3d && !vg.view3d.error) {
        $("b_view").classList.remove("hidden");
        $("cam3d").classList.remove("hidden");
        vg.view = ($("chartbox").clientWidth || 0) >= WIDE_PX ? "both" : "chart";
      } else {
        vg.view3d = null;
      }
    }
    resize();
  } else if (m.type === "state") {
    vg.state = m;
    if (m.own) {
      if (m.ack >= 0 && vg.sentAt[m.ack] !== undefined) {
        vg.latencies.push(performance.now() - vg.sentAt[m.ack]);
        delete vg.sentAt[m.ack];
      }
      if (vg.seq === 0) { vg.rudder = m.own.rudder_order_deg; vg.telegraph = m.own.telegraph; }
      const s = m.ships.find((x) => x.k === vg.ship);
      if (s && s.n !== null) {
        const last = vg.track[vg.track.length - 1];
        if (!last || Math.hypot(last[0] - s.n, last[1] - s.e) > 0.5) vg.track.push([s.n, s.e]);
        if (vg.track.length > 4000) vg.track.shift();
      }
    }
    if (vg.view3d) vg.view3d.update(m, vg.ship);
    show(m);
  } else if (m.type === "refused") {
    $("joinmsg").textContent = m.error;
  } else if (m.type === "error") {
    vg.errors.push(m.error);
    $("msg").textContent = m.error;
  } else if (m.type === "debrief") {
    const url = URL.createObjectURL(new Blob([m.html], { type: "text/html" }));
    const a = $("debrieflink");
    a.href = url; a.classList.remove("hidden");
    a.textContent = "open the debrief";
    a.title = m.path ? `also written to ${m.path}` : "";
    vg.debrief = m;
  }
}

// --- orders -------------------------------------------------------------------------------------------------
function order(dRudder, dTele, absolute) {
  if (vg.role !== "helm") return;
  if (absolute) { if (absolute.rudder !== undefined) vg.rudder = absolute.rudder;
    if (absolute.telegraph !== undefined) vg.telegraph = absolute.telegraph; }
  vg.rudder = Math.max(-RUDDER_MAX, Math.min(RUDDER_MAX, vg.rudder + dRudder));
  vg.telegraph = Math.max(-4, Math.min(4, vg.telegraph + dTele));
  const now = performance.now();
  const wait = vg.lastSend + MIN_SEND_MS - now;
  if (wait > 0) {  // at most one order per 50 ms: the latest one goes when the time has come
    if (!vg.pending) vg.pending = setTimeout(() => { vg.pending = null; flush(); }, wait);
    return;
  }
  flush();
}

function flush() {
  vg.seq += 1;
  vg.lastSend = performance.now();
  vg.sentAt[vg.seq] = vg.lastSend;
  send({ type: "order", session: vg.session, seq: vg.seq, rudder: vg.rudder, telegraph: vg.telegraph });
}

const KEYS = { ArrowLeft: [-RUDDER_STEP, 0], KeyA: [-RUDDER_STEP, 0], ArrowRight: [RUDDER_STEP, 0],
  KeyD: [RUDDER_STEP, 0], ArrowUp: [0, 1], KeyW: [0, 1], ArrowDown: [0, -1], KeyS: [0, -1] };
document.addEventListener("keydown", (ev) => {
  if (vg.role !== "helm" || ev.target.tagName === "INPUT") return;
  if (KEYS[ev.code]) { order(KEYS[ev.code][0], KEYS[ev.code][1]); ev.preventDefault(); }
  else if (ev.code === "KeyM" || ev.code === "Space") { order(0, 0, { rudder: 0 }); ev.preventDefault(); }
  else if (ev.code === "KeyV" && vg.view3d) nextView();
});
function nextView() {
  vg.view = VIEWS[(VIEWS.indexOf(vg.view) + 1) % VIEWS.length];
  resize();
}
$("b_view").onclick = nextView;
$("cam3d").onchange = () => { if (vg.view3d) { vg.view3d.camera = $("cam3d").value; vg.view3d.request(); } };
$("b_port").onclick = () => order(-RUDDER_STEP, 0);
$("b_stbd").onclick = () => order(RUDDER_STEP, 0);
$("b_mid").onclick = () => order(0, 0, { rudder: 0 });
$("b_ahead").onclick = () => order(0, 1);
$("b_astern").onclick = () => order(0, -1);
$("b_stop").onclick = () => order(0, 0, { telegraph: 0 });
$("joinbtn").onclick = join;
$("code").addEventListener("keydown", (ev) => { if (ev.key === "Enter") join(); });

// --- the instructor ---------------------------------------------------------------------------------------------
function command(msg) { send(Object.assign({ session: vg.session }, msg)); }
$("b_pause").onclick = () => command({ type: "pause" });
$("b_resume").onclick = () => command({ type: "resume" });
$("b_resetall").onclick = () => command({ type: "reset", ship: "all" });
$("b_debrief").onclick = () => command({ type: "debrief" });
$("b_weather").onclick = () => {
  const msg = { type: "weather" };
  for (const [id, key] of [["w_ws", "wind_speed_m_s"], ["w_wd", "wind_from_deg"],
    ["w_cs", "current_speed_m_s"], ["w_cd", "current_to_deg"]]) {
    if ($(id).value !== "") msg[key] = Number($(id).value);
  }
  command(msg);
};

function cell(tr, text) { const td = document.createElement("td"); td.textContent = text; tr.appendChild(td); return td; }
function fmt(v, digits, unit) { return v === null || v === undefined ? "-" : `${v.toFixed(digits)}${unit || ""}`; }

function show(m) {
  $("clock").textContent = `t ${m.t_s.toFixed(0)} s`;
  $("paused").textContent = m.paused ? "PAUSED" : "";
  if (m.own) {
    const o = m.own;
    $("c_hdg").textContent = fmt(o.heading_deg, 1, "°");
    $("c_sog").textContent = fmt(o.sog_kn, 2, " kn");
    $("c_rot").textContent = fmt(o.rot_dpm, 1, " °/min");
    $("c_rudder").textContent = `${fmt(o.rudder_deg, 1, "°")} (order ${o.rudder_order_deg.toFixed(0)}°)`;
    $("c_rpm").textContent = fmt(o.rpm, 0, " rpm");
    $("c_tele").textContent = TELEGRAPH[String(o.telegraph)];
    $("c_ukc").textContent = fmt(o.ukc_m, 2, " m");
    $("c_goal").textContent = fmt(o.goal_m, 0, " m");
    $("c_timer").textContent = fmt(o.timer_s, 0, " s");
    $("c_state").textContent = o.outcome + (o.contact_with ? ` (${o.contact_with})` : "");
    const half = 50;
    const act = Math.max(-1, Math.min(1, (o.rudder_deg || 0) / RUDDER_MAX)) * half;
    $("rudderact").style.left = `${half + Math.min(0, act)}%`;
    $("rudderact").style.width = `${Math.abs(act)}%`;
    $("rudderord").style.left = `${half + o.rudder_order_deg / RUDDER_MAX * half}%`;
    const body = $("radarrows");
    body.replaceChildren();
    for (const t of m.radar || []) {  // the other ships as targets, nearest first
      const tr = document.createElement("tr");
      cell(tr, t.name); cell(tr, `${t.range_m.toFixed(0)} m`); cell(tr, `${t.bearing_deg.toFixed(0)}°`);
      cell(tr, t.tcpa_s > 0 ? `${t.dcpa_m.toFixed(0)} m` : "opening");
      cell(tr, t.tcpa_s > 0 ? `${t.tcpa_s.toFixed(0)} s` : "-");
      cell(tr, `${t.age_s.toFixed(0)} s`);
      body.appendChild(tr);
    }
  }
  if (m.class) {
    $("speccode").textContent = m.spectator_code;
    const body = $("classrows");
    body.replaceChildren();
    for (const s of m.class) {
      const tr = document.createElement("tr");
      cell(tr, String(s.k + 1)); cell(tr, s.name); cell(tr, s.code).className = "code";
      cell(tr, s.pilot ? "pilot" : s.agent ? "agent" : s.at_helm ? "yes" : "-");
      cell(tr, s.outcome + (s.contact_with ? ` (${s.contact_with})` : ""));
      cell(tr, fmt(s.sog_kn, 1)); cell(tr, fmt(s.timer_s, 0, " s"));
      const td = cell(tr, "");
      for (const [label, type] of [["reset", "reset"], ["new code", "revoke"]]) {
        const b = document.createElement("button");
        b.textContent = label;
        b.onclick = () => command({ type: type, ship: s.k });
        td.appendChild(b);
      }
      body.appendChild(tr);
    }
    const w = m.weather;
    for (const [id, key] of [["w_ws", "wind_speed_m_s"], ["w_wd", "wind_from_deg"],
      ["w_cs", "current_speed_m_s"], ["w_cd", "current_to_deg"]]) {
      if (document.activeElement !== $(id)) $(id).placeholder = w[key].toFixed(2);
    }
  }
  if (vg.role === "spectator") {
    const body = $("watchrows");
    body.replaceChildren();
    for (const s of m.ships) {
      const tr = document.createElement("tr");
      cell(tr, String(s.k + 1)); cell(tr, s.name); cell(tr, s.outcome); cell(tr, fmt(s.sog, 2, " m/s"));
      body.appendChild(tr);
    }
  }
  draw(m);
}

// --- the chart ------------------------------------------------------------------------------------------------
const HULL = (L, B) => [[0.5 * L, 0], [0.3 * L, 0.5 * B], [-0.5 * L, 0.5 * B], [-0.5 * L, -0.5 * B], [0.3 * L, -0.5 * B]];

function resize() {
  const c = $("chart"), ch = vg.chart;
  if (!ch) return;
  const [n0, n1, e0, e1] = ch.bounds;
  const box = $("chartbox").clientWidth || 800, v3 = $("view3d");
  const show3d = vg.view3d !== null && vg.view !== "chart", showChart = vg.view !== "3d" || !vg.view3d;
  const room = show3d && showChart ? Math.floor((box - 8) / 2) : box;
  c.classList.toggle("hidden", !showChart);
  v3.classList.toggle("hidden", !show3d);
  $("b_view").textContent = { both: "chart + 3D", chart: "chart", "3d": "3D" }[vg.view];
  if (show3d) {
    const w3 = Math.max(260, Math.min(room, 1600));
    v3.style.width = `${w3}px`;
    v3.style.height = `${Math.round(Math.min(w3 * 0.75, window.innerHeight - 80))}px`;
    vg.view3d.request();
  }
  // the whole harbour in view: as wide as the box, or as tall as the window leaves room for
  const fit = (window.innerHeight - 60) * (e1 - e0) / (n1 - n0);
  const w = Math.round(Math.max(260, Math.min(1600, room, fit)));
  c.width = w;
  c.style.width = `${w}px`;
  c.height = Math.round(w * (n1 - n0) / (e1 - e0));
  if (vg.state) draw(vg.state);
}
window.addEventListener("resize", resize);

function draw(m) {
  const c = $("chart"), g = c.getContext("2d"), ch = vg.chart;
  if (!ch) return;
  const [n0, n1, e0, e1] = ch.bounds;
  const k = c.width / (e1 - e0);
  const X = (e) => (e - e0) * k, Y = (n) => (n1 - n) * k;
  g.clearRect(0, 0, c.width, c.height);
  const poly = (pts, fill, stroke) => {
    g.beginPath();
    pts.forEach(([n, e], i) => (i ? g.lineTo(X(e), Y(n)) : g.moveTo(X(e), Y(n))));
    g.closePath();
    if (fill) { g.fillStyle = fill; g.fill(); }
    if (stroke) { g.strokeStyle = stroke; g.stroke(); }
  };
  ch.shoals.forEach((p) => poly(p, "#e8d8a8"));
  ch.hard.forEach((p) => poly(p, "#9a9a8a", "#555"));
  g.lineWidth = 2; poly(ch.goal, null, "#1a8a1a"); g.lineWidth = 1;
  g.setLineDash([4, 4]); poly(ch.start, null, "#667"); g.setLineDash([]);
  if (vg.track.length > 1) {
    g.strokeStyle = "#c03030"; g.beginPath();
    vg.track.forEach(([n, e], i) => (i ? g.lineTo(X(e), Y(n)) : g.moveTo(X(e), Y(n))));
    g.stroke();
  }
  const ship = (n, e, hdg, L, B, fill, label) => {
    if (n === null || e === null || hdg === null) return;
    const h = hdg * Math.PI / 180, cs = Math.cos(h), sn = Math.sin(h);
    const grow = Math.max(1, MIN_SHIP_PX / (L * k));  // a small chart still shows the ship, to scale in shape
    poly(HULL(L * grow, B * grow).map(([x, y]) => [n + cs * x - sn * y, e + sn * x + cs * y]), fill, "#202020");
    g.fillStyle = "#102030"; g.font = "12px sans-serif";
    g.fillText(label, X(e) + 8, Y(n) - 6);
  };
  for (const t of m.targets || []) ship(t.n, t.e, t.hdg, t.L, t.B, "#8a8a8a", t.name);
  // a student's page: the others as its AIS has them, drawn along their course over ground, with the age
  for (const a of m.ais || []) {
    ship(a.n, a.e, a.cog, a.L, a.B, a.own ? "#2a6ad8" : "#8a8a8a", `${a.name} (AIS ${a.age_s.toFixed(0)} s)`);
  }
  for (const s of m.ships) {
    const own = s.k === vg.ship;
    const fill = own ? "#e03020" : s.outcome === "running" ? "#2a6ad8" : "#b0b0b0";
    ship(s.n, s.e, s.hdg, ch.L, ch.B, fill, s.name);
  }
}
