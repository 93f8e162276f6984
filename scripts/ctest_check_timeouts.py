#!/usr/bin/env python3
"""scripts/ctest_check_timeouts.py BUILD_DIR COSTS_FILE: the guard of the suite's time
(docs/testing.md, "CI time"), run as the ctest entry ctest_every_entry_has_a_timeout.

Fails, naming them, when an entry of BUILD_DIR's suite has no TIMEOUT (a hung test would then hold
CI until its own limit), or when a name that COSTS_FILE (tests/ctest_costs.cmake) gives a COST no
longer names an entry (ctest ignores set_tests_properties on an unknown name, so a renamed slow
test would silently lose its place at the front of the queue)."""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile


def grouped_gtest_names(tests):
    """Suite.Test names of the binaries that entries run with --gtest_filter=Suite.* (one entry per
    suite); empty when every gtest test is an entry of its own."""
    binaries = {t["command"][0] for t in tests
                if len(t.get("command") or []) == 2 and re.fullmatch(r"--gtest_filter=[\w/]+\.\*", t["command"][1])}
    found = set()
    for binary in binaries:
        listing = subprocess.run([binary, "--gtest_list_tests"], capture_output=True, text=True, check=True).stdout
        suite = None
        for line in listing.splitlines():
            if re.match(r"[A-Za-z_][\w/]*\.(\s|$)", line):
                suite = line.split(".")[0]
            elif line.startswith("  ") and suite:
                found.add(f"{suite}.{line.split()[0]}")
    return found


def show_entries(build):
    """`ctest --show-only=json-v1` of BUILD_DIR's suite, run on a copy of its CTestTestfile.cmake
    tree: any ctest run in a build folder rewrites its Testing/Temporary/LastTest.log, and this
    check runs inside the suite's own run, whose log the failure digest reads afterwards
    (scripts/ctest_failure_digest.sh). The copies name tests and included files by absolute path."""
    with tempfile.TemporaryDirectory(prefix="ctest-show-") as copy:
        for root, _dirs, files in os.walk(build):
            if "CTestTestfile.cmake" in files:
                target = os.path.join(copy, os.path.relpath(root, build))
                os.makedirs(target, exist_ok=True)
                shutil.copy(os.path.join(root, "CTestTestfile.cmake"), target)
        return subprocess.run(["ctest", "--test-dir", copy, "--show-only=json-v1"], capture_output=True, text=True)


def main():
    build, costs_file = sys.argv[1], sys.argv[2]
    shown = show_entries(build)
    if shown.returncode != 0:
        print(shown.stdout, shown.stderr, sep="\n")
        return 1
    tests = json.loads(shown.stdout)["tests"]
    names = {t["name"] for t in tests}
    # gtest_discover_tests' stand-in for a test binary that is not built (that entry fails by itself):
    # its entries are unknown, so only the other entries are checked.
    not_built = any(n.endswith("_NOT_BUILT") for n in names)
    problems = []
    for t in tests:
        if t["name"].endswith("_NOT_BUILT"):
            continue
        if not any(p["name"] == "TIMEOUT" for p in t.get("properties", [])):
            problems.append(f"{t['name']}: no TIMEOUT (set one where the entry is added; docs/testing.md, \"CI time\")")
    with open(costs_file) as f:
        text = re.sub(r"#[^\n]*", "", f.read())
    costed = re.findall(r"\baniso_cost\(\s*([^\s)]+)", text)
    # With one entry per gtest suite (tests/gtest_suites.cmake), a costed gtest name is looked up in
    # the test binary's own listing.
    names |= grouped_gtest_names(tests)
    for name in costed:
        if name not in names and not (not_built and "." in name):
            problems.append(f"{name}: given a COST in {costs_file} but no such entry (renamed or removed?)")
    for p in problems:
        print(p)
    print(f"{len(tests)} entries, every one with a TIMEOUT; {len(costed)} costed entries, each found"
          if not problems else f"{len(problems)} problem(s) among {len(tests)} entries")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
