// Helpers of the bench view's browser tests and tools/update-screenshot: a gpsemu with --ui, its
// pty read line by line, and Debian's chromium through puppeteer-core.
import { spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import puppeteer from "puppeteer-core";

export const binary = process.env.GPSEMU_BINARY || new URL("../../build/emulator/gpsemu", import.meta.url).pathname;
export const chromium = process.env.GPSEMU_CHROMIUM || "/usr/bin/chromium";

/// Waits until `predicate()` is truthy (polled every 50 ms) or throws `what` after `timeoutMs`
/// (`what` a function: called then, for a message saying what was seen instead).
export async function until(predicate, what, timeoutMs = 15000) {
  const end = Date.now() + timeoutMs;
  for (;;) {
    const value = await predicate();
    if (value) return value;
    if (Date.now() > end) throw new Error(`timed out waiting for ${typeof what === "function" ? what() : what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/// A running gpsemu with --ui on a free port, writing to a pty of its own (read into `.lines`) or,
/// with pty false, to a file; `extra`: more arguments. Its log is kept in `.log`.
export async function startGpsemu(extra = [], { pty = true } = {}) {
  const dir = fs.mkdtempSync(path.join(process.env.TMPDIR || os.tmpdir(), "gpsemu-ui-"));
  const link = path.join(dir, "gps");
  const output = pty ? `pty:${link}` : `file:${path.join(dir, "out.nmea")}`;
  const args = ["--rate", "10", "--ui", "127.0.0.1:0", "--output", output, ...extra];
  const child = spawn(binary, args, { stdio: ["ignore", "ignore", "pipe"] });
  const g = { child, dir, link, log: "", url: null, lines: [], reader: null, readerEnd: null };
  child.stderr.on("data", (d) => { g.log += d; });
  const match = await until(() => g.log.match(/bench view: (http:\/\/\S+)/) || (child.exitCode !== null && "exit"),
                            "the bench view's address in the log");
  if (match === "exit") throw new Error("gpsemu exited: " + g.log);
  g.url = match[1];
  if (pty) readPty(g);
  return g;
}

/// Reads the pty's NMEA lines into g.lines as { text, at } (at: Date.now() when read).
function readPty(g) {
  const stream = fs.createReadStream(g.link, { encoding: "latin1", highWaterMark: 4096 });
  let pending = "";
  stream.on("data", (chunk) => {
    pending += chunk;
    let nl;
    while ((nl = pending.indexOf("\n")) >= 0) {
      g.lines.push({ text: pending.slice(0, nl).replace(/\r$/, ""), at: Date.now() });
      pending = pending.slice(nl + 1);
    }
  });
  // Kept for the message of a test that waits for a line in vain (stopGpsemu's destroy is neither).
  stream.on("error", (e) => { g.readerEnd = `read error: ${e.message}`; });
  stream.on("end", () => { g.readerEnd = "end of file"; });
  g.reader = stream;
}

/// What a test waiting for the pty saw: lines read, the last GGA, the reader's end and the log's tail.
export function ptyState(g) {
  const gga = g.lines.filter((l) => /^\$..GGA,/.test(l.text)).at(-1);
  return `${g.lines.length} lines read, the last GGA ${gga ? `"${gga.text}" ${Date.now() - gga.at} ms ago` : "none"}` +
         `${g.readerEnd ? `, the reader's ${g.readerEnd}` : ""}; gpsemu's log ends:\n${g.log.split("\n").slice(-12).join("\n")}`;
}

export async function stopGpsemu(g) {
  if (g.reader) g.reader.destroy();
  if (g.child.exitCode === null) {
    g.child.kill("SIGTERM");
    await until(() => g.child.exitCode !== null, "gpsemu to exit", 20000);
  }
  fs.rmSync(g.dir, { recursive: true, force: true });
  return g.child.exitCode;
}

export async function launchBrowser() {
  return puppeteer.launch({
    executablePath: chromium,
    headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run"],
  });
}

/// GGA's time (hhmmss.ss as seconds of the day) and quality.
export function parseGga(text) {
  const f = text.split("*")[0].split(",");
  if (!/^\$..GGA$/.test(f[0])) return null;
  const t = f[1];
  const seconds = t ? Number(t.slice(0, 2)) * 3600 + Number(t.slice(2, 4)) * 60 + Number(t.slice(4)) : null;
  return { seconds, quality: Number(f[6] || 0) };
}
