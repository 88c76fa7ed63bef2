// The bench view in a real headless browser (Debian's chromium through puppeteer-core): a gpsemu
// u-blox M8N (GPS, GLONASS, QZSS, SBAS; no Galileo or BeiDou) at 10 Hz on a pty with --ui. The page
// loads, its sky plot shows satellites of those systems only, as many as the pty's GSV lists; the
// error trace moves; "start" on the outage form makes the pty's next epoch after the answer have
// no fix and the page show the outage active; "clear" brings the fix back; a reload keeps working;
// a second browser at the same time receives the same epochs byte for byte.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { startGpsemu, stopGpsemu, launchBrowser, until, parseGga, ptyState } from "./lib.mjs";

let g, browser;
before(async () => {
  g = await startGpsemu(["--receiver", "ublox-m8n"]);
  browser = await launchBrowser();
});
after(async () => {
  if (browser) await browser.close();
  if (g) {
    const status = await stopGpsemu(g);
    assert.equal(status, 0, g.log);
  }
});

const snapshot = (page) => page.evaluate(() => window.gpsemuView.last);
const epochs = (page) => page.evaluate(() => window.gpsemuView.epochs);

/// The GGA of the epoch `seconds` of the day (to the centisecond), once it has been read.
const ggaAt = (seconds) => until(() => g.lines.map((l) => parseGga(l.text)).find((q) => q && Math.abs(q.seconds - seconds) < 0.005),
                                 () => `the GGA of ${seconds.toFixed(2)} s on the pty (${ptyState(g)})`);

/// The epoch time (seconds of the UTC day) `since_s` after the first epoch, from a snapshot.
function secondsOfDay(s, sinceS) {
  const first = Date.parse(s.time) / 1000 - s.since_s;
  return Math.round(((first + sinceS) % 86400) * 100) / 100;
}

/// Clicks `selector` and returns the JSON answer of the /api/control request it made.
async function clickControl(page, selector) {
  const [response] = await Promise.all([page.waitForResponse((r) => r.url().endsWith("/api/control")), page.click(selector)]);
  assert.equal(response.status(), 200, await response.text());
  return response.json();
}

test("the page shows the receiver's systems, a moving error trace, and an outage at a click", async () => {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 1400 });
  await page.goto(g.url);
  await until(() => page.$$eval("#sky g.sat", (s) => s.length > 0), "satellites in the sky plot");

  const systems = await page.$$eval("#sky g.sat", (s) => [...new Set(s.map((e) => e.dataset.system))].sort());
  assert.ok(systems.includes("GPS") && systems.includes("GLONASS"), `systems shown: ${systems}`);
  for (const sys of systems) assert.ok(["GPS", "GLONASS", "QZSS", "SBAS"].includes(sys), `an M8N has no ${sys}: ${systems}`);
  // As many satellites as the pty's GSV of the same epoch lists (field 3: satellites in view).
  const s = await snapshot(page);
  const shown = await page.$$eval("#sky g.sat", (e) => e.length);
  assert.equal(shown, s.satellites.length);
  const hhmmss = s.time.slice(11, 19).replaceAll(":", "") + "." + s.time.slice(20, 22);
  await until(() => g.lines.some((l) => l.text.includes("GGA," + hhmmss)), () => `that epoch's GGA on the pty (${ptyState(g)})`);
  const at = g.lines.findIndex((l) => l.text.includes("GGA," + hhmmss));
  const gsvTotals = {};
  for (let k = at; k < g.lines.length && !g.lines[k].text.includes("GGA,") || k === at; k++) {
    const m = g.lines[k].text.match(/^\$(..)GSV,\d+,\d+,(\d+)/);
    if (m) gsvTotals[m[1]] = Number(m[2]);
  }
  const inGsv = Object.values(gsvTotals).reduce((a, b) => a + b, 0);
  assert.equal(inGsv, s.fix.satellites_in_view, `GSV totals ${JSON.stringify(gsvTotals)}`);
  assert.equal(shown, inGsv);

  // The error trace moves: more points, and new values.
  const before = await page.$eval("#h-error", (e) => e.getAttribute("points"));
  await until(async () => (await page.$eval("#h-error", (e) => e.getAttribute("points"))) !== before, "the error trace to move");
  const points = await page.$eval("#h-error", (e) => e.getAttribute("points").split(" ").length);
  assert.ok(points >= 3, `${points} points`);

  // Outage: the pty's next epoch after the answer has no fix, the page shows it active.
  const started = await clickControl(page, "#fault-outage-start");
  assert.equal(started.class, "FAULT");
  const last = await snapshot(page);
  const t0 = secondsOfDay(last, started.after_epoch_s);
  assert.ok((await ggaAt(t0)).quality >= 1, "the epoch before the click had a fix");
  assert.equal((await ggaAt(t0 + 0.1)).quality, 0, "the next epoch after the click has no fix");
  await until(() => page.$('#active-faults [data-fault="outage"][data-active="true"]'), "the outage shown active");
  await until(() => page.$eval("#fix-badge", (e) => e.textContent === "no fix"), "the fix badge to say no fix");

  // Clear: the fix comes back on the pty and on the page.
  const cleared = await clickControl(page, "#fault-outage-clear");
  assert.equal(cleared.class, "CLEAR");
  const t1 = secondsOfDay(await snapshot(page), cleared.after_epoch_s);
  await until(() => g.lines.map((l) => parseGga(l.text)).some((q) => q && q.seconds > t1 && q.quality >= 1), () => `a fix on the pty after clear (${ptyState(g)})`);
  await until(() => page.$eval("#fix-badge", (e) => e.dataset.quality !== "0"), "the page to show a fix again");
  await until(async () => !(await page.$('#active-faults [data-fault="outage"]')), "the outage gone from the page");

  // A reload keeps working: new epochs arrive on the reloaded page.
  await page.reload();
  await until(async () => (await page.evaluate(() => window.gpsemuView && window.gpsemuView.epochs)) >= 3, "epochs after the reload");
  await page.close();
});

test("two browsers at once see the same epochs", async () => {
  const other = await launchBrowser();
  try {
    const a = await browser.newPage();
    const b = await other.newPage();
    await Promise.all([a.goto(g.url), b.goto(g.url)]);
    await until(async () => (await epochs(a)) >= 10 && (await epochs(b)) >= 10, "ten epochs on both pages");
    const rawA = new Map(await a.evaluate(() => [...window.gpsemuView.raw]));
    const rawB = new Map(await b.evaluate(() => [...window.gpsemuView.raw]));
    const common = [...rawA.keys()].filter((k) => rawB.has(k));
    assert.ok(common.length >= 5, `${common.length} epochs seen by both`);
    for (const k of common) assert.equal(rawA.get(k), rawB.get(k), `epoch ${k}`);
    const s = JSON.parse(rawA.get(common.at(-1)));
    assert.ok(s.link.page_clients >= 2, `page clients ${s.link.page_clients}`);
  } finally {
    await other.close();
  }
});
