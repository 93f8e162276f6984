// tests/web/screenshots.mjs: the pictures of docs/web.md and the README, from the built page in
// headless Chromium (software WebGL2).
//   node screenshots.mjs <aniso binary> <built page folder> <docs/images folder>
import path from "node:path";
import { launch, serve } from "./harness.mjs";

const [aniso, webDir, outDir] = process.argv.slice(2);
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
await browser.close();
