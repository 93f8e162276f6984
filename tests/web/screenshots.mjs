// tests/web/screenshots.mjs: the pictures of docs/web.md and the README, from the built page in
// headless Chromium (software WebGL2).
//   node screenshots.mjs <aniso binary> <built page folder> <docs/images folder>
import { spawn } from "node:child_process";
import path from "node:path";
import { chromium } from "playwright-core";

const [aniso, webDir, outDir] = process.argv.slice(2);
const server = spawn(path.resolve(aniso), ["serve", "--port", "0", "--root", webDir], { stdio: ["ignore", "pipe", "inherit"] });
process.on("exit", () => server.kill("SIGTERM"));  // also when a check throws
const url = await new Promise((resolve) => server.stdout.on("data", (d) => resolve(/http:\/\/127\.0\.0\.1:\d+\//.exec(String(d))[0])));
const browser = await chromium.launch({
  executablePath: process.env.ANISO_CHROMIUM || "/usr/bin/chromium",
  args: ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-sandbox",
    "--disable-background-networking", "--disable-component-update", "--no-first-run"],
});
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
server.kill("SIGTERM");
