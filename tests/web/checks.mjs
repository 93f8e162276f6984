// tests/web/checks.mjs: the checks' tally the test scripts of tests/web share (no browser needed):
// each failed check printed as "FAIL <what>", and at the end the count and the exit status.
export function checker() {
  const failures = [];
  let count = 0;
  return {
    check(ok, what) {
      count++;
      if (!ok) {
        failures.push(what);
        console.log(`FAIL ${what}`);
      }
    },
    // The summary line; exits 0 when every check passed, 1 otherwise.
    finish(t0, outDir) {
      console.log(`${count - failures.length} of ${count} checks passed in ${((Date.now() - t0) / 1000).toFixed(1)} s; screenshots in ${outDir}`);
      process.exit(failures.length ? 1 : 0);
    },
  };
}
