// tests/web/screenshots.mjs: the pictures of docs/web.md and the README, from the built page in
// headless Chromium (software WebGL2).
//   node screenshots.mjs <aniso binary> <built page folder> <docs/images folder> [measured file]
// With a measured file (an RGL tensor file of the RGL database: ../shared/data/rgl-real/, never
// copied into the project) also web-measured.png, that file opened in the page.
import path from "node:path";
import { launch, serve } from "./harness.mjs";

const [aniso, webDir, outDir, measured] = process.argv.slice(2);
const url = await serve(aniso, webDir);
const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1240, height: 800 } });
const ready = () => page.waitForFunction(() => window.anisoExplorer && window.anisoExplorer.idle() && window.anisoExplorer.state.redraws > 0, null, { timeout: 300000 });
// Brushed gold (A) against polished gold (B), split, log plots.
await page.goto(`${url}#compare=split&log=1&tangent_angle=30`);
await ready();
await page.screenshot({ path: path.join(outDir, "web-explorer.png") });
// A bad material file: the CLI's message, the last good state kept.
await page.evaluate(() => window.anisoExplorer.setMaterial('{"model": "ward", "alpha_x": 0, "alpha_y": 0.2}', "bad.json"));
await page.waitForFunction(() => window.anisoExplorer.idle());
await page.screenshot({ path: path.join(outDir, "web-error.png"), clip: { x: 0, y: 0, width: 900, height: 420 } });
if (measured) {
  // The file as material A on a fresh page (every view: taller), log plots, the light at 40 degrees.
  const m = await browser.newPage({ viewport: { width: 1240, height: 1000 } });
  await m.goto(`${url}#log=1&theta=40&phi=30`);
  await m.waitForFunction(() => window.anisoExplorer && window.anisoExplorer.idle() && window.anisoExplorer.state.redraws > 0, null, { timeout: 300000 });
  await m.setInputFiles("#load", measured);
  await m.waitForFunction(() => window.anisoExplorer.state.fileLoads > 0 && window.anisoExplorer.idle(), null, { timeout: 300000 });
  const err = await m.evaluate(() => window.anisoExplorer.error());
  if (err) throw new Error(err);
  await m.screenshot({ path: path.join(outDir, "web-measured.png") });
}
await browser.close();
process.exit(0);  // the server (harness.mjs) stops with the script
