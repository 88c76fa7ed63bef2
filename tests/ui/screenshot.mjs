// node tests/ui/screenshot.mjs OUT.png (tools/update-screenshot): the bench view as the README
// shows it, taken by the test browser: a u-blox F9P driving a circle in an urban canyon's sky
// mask, with a jam of 10 dB started from the page's own form.
import { startGpsemu, stopGpsemu, launchBrowser, until } from "./lib.mjs";

const out = process.argv[2];
if (!out) throw new Error("usage: node tests/ui/screenshot.mjs OUT.png");
const g = await startGpsemu(["--receiver", "ublox-f9p", "--source", "sim:circle", "--sky-mask", "urban-canyon",
                             "--start-time", "2026-06-01T12:00:00Z"], { pty: false });
const browser = await launchBrowser();
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 900 });
  await page.goto(g.url);
  await until(() => page.evaluate(() => window.gpsemuView.epochs >= 60), "60 epochs on the page", 30000);
  await page.type('form[data-fault="jam"] input[name="db"]', "10");
  await page.type('form[data-fault="jam"] input[name="duration"]', "60");
  await page.click("#fault-jam-start");
  await until(() => page.$('#active-faults [data-fault="jam"][data-active="true"]'), "the jam active");
  await new Promise((r) => setTimeout(r, 3000));
  await page.screenshot({ path: out, fullPage: true });
  console.error(`wrote ${out}`);
} finally {
  await browser.close();
  await stopGpsemu(g);
}
