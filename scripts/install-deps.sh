#!/usr/bin/env bash
# Installs the Debian packages aniso builds and tests with. Idempotent: packages already present
# are not touched, and when everything is present nothing is run at all (no apt-get update).
# `install-deps.sh --render`: only what the `aniso` executable needs (`make render`): no test,
# benchmark, Python or sanitizer packages.
set -euo pipefail

render_only=0
if [[ "${1:-}" == "--render" ]]; then render_only=1; fi

# What the `aniso` target (and the libraries it links) needs.
packages=(
  build-essential cmake pkg-config
  libglm-dev          # vector math in the kernels (mirrors GLSL)
  libfmt-dev          # formatting in host code
  libcli11-dev        # command-line parsing
  nlohmann-json3-dev  # material JSON
  libssl-dev          # OpenSSL libcrypto: sha256 to recognise MERL BRDF files (src/measured)
  # The renderer (src/render): ray casting, threads, images, meshes, the label font.
  libembree-dev       # Embree 3 BVH and ray intersection
  libtbb-dev          # oneTBB: parallel tiles, parallel batch evaluation (src/batch)
  libhwy-dev          # Google Highway: SIMD batch evaluation with dynamic dispatch (src/batch)
  libopenexr-dev      # .exr output and input
  libstb-dev          # stb_image (PNG, HDR), stb_image_write, stb_truetype
  libtinyobjloader-dev  # .obj meshes
  fonts-dejavu-core   # DejaVu Sans, embedded at build time for the gallery's labels
  # The GLSL twin (src/gl, docs/glsl.md): a headless GL host and the shader compiler the tests use.
  libegl-dev libgl-dev libopengl-dev  # EGL and GL headers (glvnd)
  libegl-mesa0 libgl1-mesa-dri        # Mesa's EGL (surfaceless platform) and llvmpipe
  libepoxy-dev        # GL entry points through eglGetProcAddress (works without GLX)
  # The explorer (`aniso view`, docs/explorer.md): a GLFW window with Dear ImGui (its GLFW and
  # OpenGL 3 backends are inside Debian's libimgui.a).
  libglfw3-dev libimgui-dev
)
# The tests, benchmarks, Python module and sanitizer build on top (make build, make test).
if [[ $render_only == 0 ]]; then packages+=(
  # Fitting (src/fit; not in the render-only executable, apps/aniso/cmd_render_only.cpp).
  libceres-dev        # Ceres Solver: Levenberg-Marquardt fits of measured data
  libgtest-dev        # unit and statistical tests
  libbenchmark-dev    # benchmarks
  libboost-dev        # boost::math::gamma_q for the chi-square p-values in tests
  glslang-tools       # glslangValidator: the library compiles as GLSL 3.30 core and ES 3.00
  xvfb xauth          # xvfb-run for the explorer's tests (xauth: only "recommended" by xvfb)
  # The Python module (python/, docs/python.md): built for Debian's /usr/bin/python3 and its NumPy,
  # tested with pytest; the example plots with matplotlib.
  python3-dev pybind11-dev python3-numpy
  python3-pytest      # python/tests, run by ctest
  python3-matplotlib  # examples/python (and its test, headless: MPLBACKEND=Agg); fit-db's report figure
  python3-distributed # Dask's distributed scheduler: aniso fit-db --workers / --scheduler, aniso.fit_many(client=)
  # The sanitizer build and the fuzz targets (make test-sanitize, make fuzz; docs/testing.md).
  clang               # clang++ 14: the sanitize build, so the fuzz targets can link libFuzzer
  libclang-rt-14-dev  # libFuzzer and the sanitizer runtimes for clang (only "recommended" by clang)
  clang-format        # make format / make format-check (.clang-format; .ci/run checks it first)
  # The browser explorer's tests (web/, tests/web, docs/web.md): headless Chromium (software WebGL2
  # through SwiftShader) driven by playwright-core from npm. About 2 minutes and 393 MB (chromium and the
  # 22 libraries it adds to the rest of this list); the npm package adds 14 MB and a few seconds.
  chromium
  # Blender 3.4 with Cycles, run headless (blender -b): `aniso export --to blender`'s script runs in
  # it (tests/test_export.cpp, ExportCli.BlenderScriptRunsInBlender). About 4 minutes on the shared
  # 2-core machine with the libraries it adds (288 packages without recommends).
  blender
); fi
# Node and npm: Debian's, unless a node is already installed (NodeSource's nodejs bundles npm and
# conflicts with Debian's npm package).
if [[ $render_only == 0 ]] && ! command -v node >/dev/null 2>&1; then packages+=(nodejs); fi
if [[ $render_only == 0 ]] && ! command -v npm >/dev/null 2>&1; then packages+=(npm); fi
# Optional: regenerating/checking the metal RGB table (scripts/reduce_ior.py --check).
if [[ $render_only == 0 && "${ANISO_WITH_PYTHON_TOOLS:-1}" == "1" ]]; then
  packages+=(python3-scipy)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -gt 0 ]]; then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# playwright-core for tests/web, exactly as tests/web/package-lock.json pins it (npm ci; it
# downloads no browser: the tests use /usr/bin/chromium). Skipped when already installed.
web_tests="$(dirname "$0")/../tests/web"
if [[ $render_only == 0 ]] && [[ ! -f "$web_tests/node_modules/playwright-core/package.json" ||
      "$web_tests/package-lock.json" -nt "$web_tests/node_modules/.package-lock.json" ]]; then
  echo "install-deps: npm ci in tests/web"
  (cd "$web_tests" && npm ci --no-audit --no-fund --loglevel=error)
fi
