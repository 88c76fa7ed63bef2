// The bench view (docs/ui.md): one EventSource on /api/events?receiver=N, every panel redrawn from
// each EPOCH object; fault buttons POST the control socket's JSON to /api/control.
"use strict";

const COLORS = { GPS: "#2c6fbb", GLONASS: "#c0392b", Galileo: "#27ae60", BeiDou: "#d35400", QZSS: "#8e44ad", SBAS: "#7f8c8d" };
const TRAIL = 60;      // epochs in the position trail
const HISTORY = 300;   // epochs in the error trace
const token = new URLSearchParams(location.hash.slice(1)).get("token");
const view = { receiver: 0, last: null, epochs: 0, history: [], trail: [], source: null, info: null, raw: new Map() };
window.gpsemuView = view;  // for the browser tests and the console

const $ = (id) => document.getElementById(id);
const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]));
const num = (v, d = 2) => (v === null || v === undefined ? "–" : Number(v).toFixed(d));

async function start() {
  view.info = await (await fetch("/api/info")).json();
  const select = $("receiver");
  view.info.names.forEach((name, i) => select.add(new Option(name, i)));
  select.addEventListener("change", () => connect(Number(select.value)));
  buildFaultForms(view.info.faults);
  $("clear-all").addEventListener("click", () => control({ clear: "all" }));
  connect(0);
}

function connect(receiver) {
  if (view.source) view.source.close();
  Object.assign(view, { receiver, last: null, epochs: 0, history: [], trail: [], raw: new Map() });
  const source = new EventSource(`/api/events?receiver=${receiver}`);
  view.source = source;
  source.onopen = () => setConnection(true);
  source.onerror = () => setConnection(false);
  source.onmessage = (event) => {
    const s = JSON.parse(event.data);
    view.raw.set(s.epoch, event.data);  // the last epochs as received (two pages compare them)
    if (view.raw.size > 100) view.raw.delete(view.raw.keys().next().value);
    update(s);
  };
}

function setConnection(on) {
  const c = $("connection");
  c.textContent = on ? "live" : "reconnecting";
  c.className = "badge " + (on ? "on" : "off");
}

function update(s) {
  view.last = s;
  view.epochs += 1;
  view.history.push({ t: s.since_s, h: s.error ? s.error.horizontal_m : null, v: s.error ? s.error.vertical_m : null,
                      hacc: s.fix.h_acc_m ?? null, vacc: s.fix.v_acc_m ?? null });
  if (view.history.length > HISTORY) view.history.shift();
  if (s.error) view.trail.push([s.error.east_m, s.error.north_m]);
  if (view.trail.length > TRAIL) view.trail.shift();
  drawHeader(s);
  drawSky(s);
  drawCn0(s);
  drawFix(s);
  drawPosition(s);
  drawError();
  drawFaults(s);
  drawLink(s);
}

function drawHeader(s) {
  const f = s.fix;
  const badge = $("fix-badge");
  badge.textContent = s.silent ? "silent" : f.quality === 0 ? "no fix" : `${f.dimension}D ${f.quality_name}`;
  badge.className = "badge " + (f.quality === 0 || s.silent ? "nofix" : f.dimension === 3 ? "fix3" : "fix2");
  badge.dataset.quality = f.quality;
  const rtk = $("rtk-badge");
  rtk.textContent = "RTK " + s.rtk.state + (s.rtk.correction_age_s !== null ? ` (${num(s.rtk.correction_age_s, 1)} s)` : "");
  rtk.className = "badge rtk-" + s.rtk.state;
  $("time").textContent = s.time + `  epoch ${s.epoch}`;
}

/// Azimuth/elevation to the plot: north up, east right, the horizon at radius 100.
function skyXY(az, el) {
  const r = 100 * (90 - el) / 90, a = az * Math.PI / 180;
  return [r * Math.sin(a), -r * Math.cos(a)];
}

function sectorPath(from, to, minEl) {
  // The blocked area of a sector: from the horizon up to minEl, azimuth from..to (clockwise).
  const span = ((to - from) % 360 + 360) % 360 || 360, steps = Math.max(2, Math.ceil(span / 5));
  const outer = [], inner = [];
  for (let k = 0; k <= steps; k++) {
    const az = from + span * k / steps;
    outer.push(skyXY(az, 0));
    inner.push(skyXY(az, minEl));
  }
  const pts = outer.concat(inner.reverse());
  return "M" + pts.map((p) => p[0].toFixed(1) + "," + p[1].toFixed(1)).join("L") + "Z";
}

function drawSky(s) {
  let svg = "";
  for (const m of s.sky.sky_mask) {
    svg += `<path class="sky-mask" d="${sectorPath(m.from_azimuth_deg, m.to_azimuth_deg, m.min_elevation_deg)}" fill="#88888855" data-from="${esc(m.from)}"/>`;
  }
  for (const el of [0, 30, 60]) svg += `<circle r="${100 * (90 - el) / 90}" fill="none" stroke="#ccd"/>`;
  svg += `<circle class="elevation-mask" r="${(100 * (90 - s.sky.elevation_mask_deg) / 90).toFixed(1)}" fill="none" stroke="#b22" stroke-dasharray="3 3"/>`;
  svg += `<line x1="-100" y1="0" x2="100" y2="0" stroke="#eee"/><line x1="0" y1="-100" x2="0" y2="100" stroke="#eee"/>`;
  svg += `<text x="0" y="-102" text-anchor="middle" font-size="8">N</text><text x="104" y="3" font-size="8">E</text>`;
  const counts = {};
  for (const sat of s.satellites) {
    const [x, y] = skyXY(sat.az_deg, sat.el_deg);
    const color = COLORS[sat.system] || "#000";
    const c = counts[sat.system] || (counts[sat.system] = { inView: 0, used: 0 });
    c.inView += 1;
    if (sat.used) c.used += 1;
    svg += `<g class="sat ${sat.used ? "used" : "tracked"}" data-system="${esc(sat.system)}" data-sv="${sat.sv}">` +
           `<circle cx="${x.toFixed(1)}" cy="${y.toFixed(1)}" r="5" fill="${sat.used ? color : "#fff"}" stroke="${color}" stroke-width="1.5"/>` +
           `<text x="${(x + 6).toFixed(1)}" y="${(y + 3).toFixed(1)}" font-size="6">${sat.sv}</text></g>`;
  }
  $("sky").innerHTML = svg;
  $("sky-legend").innerHTML = Object.entries(counts).map(([sys, c]) =>
    `<span data-system="${esc(sys)}"><span class="sw" style="background:${COLORS[sys] || "#000"}"></span>${esc(sys)} ${c.used}/${c.inView}</span>`).join("") +
    `<span>filled: used · hollow: tracked · dashed: elevation mask ${num(s.sky.elevation_mask_deg, 0)}°</span>`;
}

function drawCn0(s) {
  const sats = s.satellites, n = Math.max(sats.length, 1), w = 400 / n;
  let svg = "";
  for (const level of [20, 30, 40, 50]) {
    const y = 150 - level * 2.5;
    svg += `<line x1="0" x2="400" y1="${y}" y2="${y}" stroke="#eee"/><text x="1" y="${y - 1}" font-size="7" fill="#999">${level}</text>`;
  }
  sats.forEach((sat, k) => {
    const cn0 = sat.cn0_dbhz ?? 0, h = Math.min(cn0, 60) * 2.5, color = COLORS[sat.system] || "#000";
    svg += `<rect class="cn0 ${sat.used ? "used" : "tracked"}" data-system="${esc(sat.system)}" x="${(k * w + 1).toFixed(1)}" y="${150 - h}" width="${Math.max(w - 2, 1).toFixed(1)}" height="${h}" fill="${color}" fill-opacity="${sat.used ? 1 : 0.3}"/>` +
           `<text x="${(k * w + w / 2).toFixed(1)}" y="162" font-size="6" text-anchor="middle">${sat.sv}</text>`;
  });
  $("cn0").innerHTML = svg;
}

function drawFix(s) {
  const f = s.fix;
  const rows = [
    ["fix", f.quality === 0 ? "none" : `${f.dimension}D ${f.quality_name} (GGA ${f.quality})`],
    ["RTK", s.rtk.state + (s.rtk.rtcm_messages ? ` · ${s.rtk.rtcm_messages} RTCM3 messages` : "")],
    ["correction age", f.diff_age_s === null ? "–" : num(f.diff_age_s, 1) + " s"],
    ["satellites", `${f.satellites_used} used / ${f.satellites_in_view} in view`],
    ["DOP", `H ${num(f.hdop)} V ${num(f.vdop)} P ${num(f.pdop)} T ${num(f.tdop)} G ${num(f.gdop)}`],
    ["accuracy", `hAcc ${num(f.h_acc_m)} m · vAcc ${num(f.v_acc_m)} m`],
    ["GST σ", `lat ${num(f.gst_sigma_lat_m)} lon ${num(f.gst_sigma_lon_m)} alt ${num(f.gst_sigma_alt_m)} m`],
    ["position", f.quality === 0 ? "–" : `${num(f.lat_deg, 7)}, ${num(f.lon_deg, 7)}, ${num(f.alt_msl_m, 2)} m MSL`],
    ["speed", f.quality === 0 ? "–" : `${num(f.speed_mps)} m/s, course ${num(f.course_deg, 1)}°`],
    ["error", s.error ? `${num(s.error.horizontal_m)} m horizontal, ${num(s.error.vertical_m)} m vertical` : "– (no fix or no truth)"],
  ];
  $("fix-table").tBodies[0].innerHTML = rows.map(([k, v]) => `<tr><th>${k}</th><td>${esc(v)}</td></tr>`).join("");
}

function niceScale(extent) {
  for (const s of [0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 5000, 20000]) if (extent <= s) return s;
  return Math.ceil(extent);
}

function drawPosition(s) {
  let extent = 0.05;
  for (const [e, n] of view.trail) extent = Math.max(extent, Math.abs(e), Math.abs(n));
  if (s.fix.h_acc_m) extent = Math.max(extent, s.fix.h_acc_m);
  const scale = niceScale(extent * 1.1), k = 100 / scale;
  let svg = `<circle r="100" fill="none" stroke="#eee"/><circle r="50" fill="none" stroke="#eee"/>`;
  svg += `<line x1="-6" x2="6" y1="0" y2="0" stroke="#000"/><line y1="-6" y2="6" x1="0" x2="0" stroke="#000"/>`;
  if (s.fix.h_acc_m && s.error) {
    svg += `<circle class="hacc" cx="${(s.error.east_m * k).toFixed(1)}" cy="${(-s.error.north_m * k).toFixed(1)}" r="${(s.fix.h_acc_m * k).toFixed(1)}" fill="#c0392b18" stroke="#c0392b55"/>`;
  }
  if (view.trail.length > 1) {
    svg += `<polyline id="trail" fill="none" stroke="#2c6fbb88" points="${view.trail.map(([e, n]) => (e * k).toFixed(1) + "," + (-n * k).toFixed(1)).join(" ")}"/>`;
  }
  if (s.error) svg += `<circle id="reported" cx="${(s.error.east_m * k).toFixed(1)}" cy="${(-s.error.north_m * k).toFixed(1)}" r="3.5" fill="#c0392b"/>`;
  $("position").innerHTML = svg;
  $("position-scale").textContent = `outer ring ${scale} m · cross: the truth · red: reported, with hAcc · blue: last ${TRAIL} epochs`;
}

function drawError() {
  const h = view.history, n = h.length;
  if (n === 0) return;
  let top = 0.1, bottom = -0.1;
  for (const p of h) {
    if (p.h !== null) top = Math.max(top, p.h);
    if (p.hacc !== null) top = Math.max(top, p.hacc);
    if (p.v !== null) { top = Math.max(top, p.v); bottom = Math.min(bottom, p.v); }
    if (p.vacc !== null) { top = Math.max(top, p.vacc); bottom = Math.min(bottom, -p.vacc); }
  }
  const x = (k) => (600 * k / Math.max(HISTORY - 1, 1)).toFixed(1);
  const y = (v) => (190 - 180 * (v - bottom) / (top - bottom)).toFixed(1);
  const line = (key) => h.map((p, k) => (p[key] === null ? null : x(k) + "," + y(p[key]))).filter(Boolean).join(" ");
  const band = (lo, hi) => {
    const up = [], down = [];
    h.forEach((p, k) => { if (p.hacc !== null || p.vacc !== null) { up.push(x(k) + "," + y(hi(p))); down.push(x(k) + "," + y(lo(p))); } });
    return up.concat(down.reverse()).join(" ");
  };
  let svg = `<line x1="0" x2="600" y1="${y(0)}" y2="${y(0)}" stroke="#999"/>`;
  svg += `<polygon class="hacc-band" fill="#c0392b22" points="${band(() => 0, (p) => p.hacc ?? 0)}"/>`;
  svg += `<polygon class="vacc-band" fill="#2c6fbb22" points="${band((p) => -(p.vacc ?? 0), (p) => p.vacc ?? 0)}"/>`;
  svg += `<polyline id="h-error" fill="none" stroke="#c0392b" stroke-width="1.5" points="${line("h")}"/>`;
  svg += `<polyline id="v-error" fill="none" stroke="#2c6fbb" stroke-width="1.5" points="${line("v")}"/>`;
  svg += `<text x="2" y="10" font-size="9">${num(top)} m</text><text x="2" y="198" font-size="9">${num(bottom)} m</text>`;
  $("error-trace").innerHTML = svg;
  const last = h[n - 1];
  $("error-now").textContent = `now: ${num(last.h)} m horizontal, ${num(last.v)} m vertical · last ${n} epochs`;
}

function buildFaultForms(kinds) {
  $("fault-forms").innerHTML = kinds.map((k) =>
    `<form class="fault-form" data-fault="${esc(k.fault)}"><h3>${esc(k.fault)}</h3>` +
    k.parameters.map((p) => `<label title="${esc(p.help)}">${esc(p.key)} <input name="${esc(p.key)}" placeholder="${esc(p.help.slice(0, 40))}"></label>`).join("") +
    `<button type="submit" class="start" id="fault-${esc(k.fault)}-start">start</button>` +
    `<button type="button" class="clear" id="fault-${esc(k.fault)}-clear">clear</button></form>`).join("");
  for (const form of document.querySelectorAll(".fault-form")) {
    const kind = form.dataset.fault;
    form.addEventListener("submit", (event) => {
      event.preventDefault();
      const request = { fault: kind, receiver: view.receiver };
      for (const input of form.querySelectorAll("input")) {
        const text = input.value.trim();
        if (text === "") continue;
        request[input.name] = text !== "" && !isNaN(Number(text)) ? Number(text) : text;
      }
      control(request);
    });
    form.querySelector(".clear").addEventListener("click", () => control({ clear: kind, receiver: view.receiver }));
  }
}

async function control(request) {
  const headers = { "Content-Type": "application/json" };
  if (token) headers["X-Gpsemu-Token"] = token;
  const message = $("fault-message");
  try {
    const answer = await fetch("/api/control", { method: "POST", headers, body: JSON.stringify(request) });
    const body = await answer.json();
    message.textContent = body.class === "ERROR" ? "refused: " + body.message
      : body.class === "FAULT" ? `${body.describe}: from the next epoch` : `cleared ${body.clear}: from the next epoch`;
  } catch (e) {
    message.textContent = "request failed: " + e;
  }
}

function drawFaults(s) {
  const active = new Set();
  $("active-faults").innerHTML = s.faults.length === 0 ? "<em>none active</em>" : s.faults.map((f) => {
    if (f.active || f.pending) active.add(f.fault);
    const left = f.remaining_s !== null ? ` · ${num(f.remaining_s, 1)} s left` : f.active ? " · until cleared" : "";
    const state = f.pending ? "starts at the next epoch" : f.active ? "active" : "scheduled";
    return `<span class="active-fault${f.pending ? " pending" : ""}" data-fault="${esc(f.fault)}" data-active="${f.active}">${esc(f.describe)} (${state}${left})</span>`;
  }).join("");
  for (const form of document.querySelectorAll(".fault-form")) form.classList.toggle("active", active.has(form.dataset.fault));
}

function drawLink(s) {
  const l = s.link;
  const budget = l.line_bytes_per_s;
  const use = budget ? Math.min(100, 100 * l.bytes_per_s / budget) : 0;
  $("link-summary").innerHTML = `${num(l.bytes_per_s, 0)} bytes/s` +
    (budget ? ` of ${budget} (line at ${l.line_baud} baud) <span class="budget${use > 90 ? " over" : ""}"><div style="width:${use}%"></div></span>` : " (no serial line: no budget)") +
    ` · late epochs <b id="late-epochs">${l.late_epochs}</b> · TX dropped ${l.tx_dropped_messages} · pages ${l.page_clients} · ctl watch ${l.watch_clients}`;
  $("outputs").tBodies[0].innerHTML = l.outputs.map((o) =>
    `<tr><td>${esc(o.name)}</td><td>${o.bytes_written}</td><td>${o.epochs_written}</td><td>${o.epochs_dropped}</td><td>${o.clients ?? "–"}</td></tr>`).join("");
  const u = s.ubx;
  $("ubx").innerHTML = !u ? "<span class='note'>NMEA receiver (no u-blox configuration)</span>" :
    `<b>u-blox, as the driver configured it:</b> ${u.frames_received} UBX frames and ${u.sentences_received} NMEA sentences received` +
    (u.bad_frames ? ` (${u.bad_frames} bad)` : "") + ` · answered ${u.acks} ACK, ${u.naks} NAK, ${u.ignored} ignored, ${u.resets} resets · ` +
    `rate ${u.meas_period_ms} ms x ${u.nav_rate_cycles} (${num(u.solution_hz, 2)} Hz) · port baud ${u.port_baud || "–"}` +
    (u.line_baud ? ` (line ${u.line_baud})` : "") + `<br>messages on: ` +
    (u.enabled.map((m) => `${esc(m.message)}${m.rate > 1 ? "/" + m.rate : ""}`).join(", ") || "none");
}

start();
