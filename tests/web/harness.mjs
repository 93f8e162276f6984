// tests/web/harness.mjs: what the scripts of tests/web share: `aniso serve --port 0` for the built
// page (stopped when the script exits) and headless Debian Chromium with software WebGL2.
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
