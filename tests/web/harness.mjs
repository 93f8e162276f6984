// tests/web/harness.mjs: what the scripts of tests/web share: `aniso serve --port 0` for the built
// page (stopped when the script exits), headless Debian Chromium with software WebGL2, and the
// directions of the lit sphere's pixels.
import { spawn } from "node:child_process";
import path from "node:path";
import { chromium } from "playwright-core";

export const CHROMIUM = process.env.ANISO_CHROMIUM || "/usr/bin/chromium";

// Starts the server; resolves to its URL ("http://127.0.0.1:PORT/").
export function serve(aniso, webDir) {
  const server = spawn(path.resolve(aniso), ["serve", "--port", "0", "--root", webDir], { stdio: ["ignore", "pipe", "inherit"] });
  process.on("exit", () => server.kill("SIGTERM"));  // also when a check throws
  return new Promise((resolve, reject) => {
    let buf = "";
    server.stdout.on("data", (d) => {
      buf += d;
      const m = /http:\/\/127\.0\.0\.1:(\d+)\//.exec(buf);
      if (m) resolve(m[0]);
    });
    server.on("exit", (c) => reject(new Error(`aniso serve exited with ${c}`)));
    setTimeout(() => reject(new Error("aniso serve did not start")), 10000);
  });
}

// SwiftShader (software WebGL2), no sandbox (root in CI), nothing fetched from the network.
export function launch() {
  return chromium.launch({
    executablePath: CHROMIUM,
    args: ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-sandbox",
      "--disable-background-networking", "--disable-component-update", "--no-first-run"],
  });
}

// Pixels of the page's lit sphere (readSphere(): w x h; the light's theta and phi in degrees) with
// their directions in the local frame, what the tests hold against `aniso eval`: every 23rd pixel
// on the sphere; its normal and natural tangent (Gram-Schmidt, as Frame_from_normal_tangent) and the
// light give wi, the view (+z) gives wo; pixels where wi is below 0.05 are left out.
export function spherePixels(w, h, light) {
  const t = (light.theta * Math.PI) / 180, p = (light.phi * Math.PI) / 180;
  const L = [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  const ext = 1 / 0.9, m = Math.min(w, h);
  const picks = [];
  for (let y = 8; y < h; y += 23)
    for (let x = 8; x < w; x += 23) {
      // The pixel centre in the shader's coordinates (SPHERE_FS: q = v_xy * u_extent).
      const qx = ((2 * (x + 0.5)) / w - 1) * ((ext * w) / m), qy = ((2 * (y + 0.5)) / h - 1) * ((ext * h) / m);
      const r2 = qx * qx + qy * qy;
      if (r2 >= 0.98) continue;
      const n = [qx, qy, Math.sqrt(1 - r2)];
      let tg = [n[2], 0, -n[0]];
      const d = tg[0] * n[0] + tg[2] * n[2];
      tg = tg.map((v, i) => v - d * n[i]);
      const len = Math.hypot(...tg);
      if (len < 1e-3) continue;
      tg = tg.map((v) => v / len);
      const b = [n[1] * tg[2] - n[2] * tg[1], n[2] * tg[0] - n[0] * tg[2], n[0] * tg[1] - n[1] * tg[0]];
      const local = (v) => [v[0] * tg[0] + v[1] * tg[1] + v[2] * tg[2], v[0] * b[0] + v[1] * b[1] + v[2] * b[2], v[0] * n[0] + v[1] * n[1] + v[2] * n[2]];
      const wi = local(L), wo = local([0, 0, 1]);
      if (wi[2] < 0.05) continue;
      picks.push({ x, y, wi, wo });
    }
  return picks;
}
