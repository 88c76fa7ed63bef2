// node tests/ui/hold-page.mjs URL SECONDS: keeps the bench view open in headless chromium for
// SECONDS (tools/measure-cpu --page), then prints how many epochs the page drew.
import { launchBrowser } from "./lib.mjs";

const [url, seconds] = process.argv.slice(2);
const browser = await launchBrowser();
try {
  const page = await browser.newPage();
  await page.goto(url);
  let drawn = 0;
  for (let k = 0; k < Number(seconds); k++) {
    await new Promise((r) => setTimeout(r, 1000));
    drawn = await page.evaluate(() => window.gpsemuView.epochs).catch(() => drawn);
  }
  console.error(`hold-page: the page drew ${drawn} epochs`);
} finally {
  await browser.close();
}
