#!/usr/bin/env bash
# tests/package/package_test.sh: aniso as a C++ package, tried from outside (docs/cpp.md).
# One ctest entry per check (tests/package/CMakeLists.txt); `install` is the fixture the others use.
#
#   package_test.sh install     BUILD PREFIX        cmake --install BUILD --prefix PREFIX
#   package_test.sh headers     PREFIX              every installed header compiles alone from PREFIX
#   package_test.sh find        PREFIX WORK CLI     examples/cpp as an outside project: find_package
#   package_test.sh pkgconfig   PREFIX WORK CLI     examples built with pkg-config alone
#   package_test.sh subproject  SOURCE WORK CLI     examples/cpp with add_subdirectory(aniso)
#   package_test.sh fetch       SOURCE WORK         a FetchContent consumer (configure + the kernels)
#   package_test.sh deb         BUILD WORK          CPack's .deb: its files and Depends
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
source_dir="$(cd "$here/../.." && pwd)"
jobs="${ANISO_PACKAGE_TEST_JOBS:-2}"
fail() { echo "FAIL: $*" >&2; exit 1; }

check=$1; shift
case "$check" in
install)
  build=$1 prefix=$2
  rm -rf "$prefix"
  cmake --install "$build" --prefix "$prefix" >/dev/null
  for f in include/aniso/aniso.h include/aniso/kernels.h include/aniso/version.h \
           include/aniso/brdf/ward.glsl lib/cmake/aniso/anisoConfig.cmake lib/cmake/aniso/anisoConfigVersion.cmake \
           lib/pkgconfig/aniso.pc lib/pkgconfig/aniso-kernels.pc lib/libaniso_host.a lib/libaniso_image.a bin/aniso \
           share/aniso/web/index.html share/doc/aniso/cpp.md share/doc/aniso/examples/cpp/CMakeLists.txt; do
    [[ -e "$prefix/$f" ]] || fail "the install has no $f"
  done
  # The private headers stay private.
  if find "$prefix/include" -name '*-inl.h' -o -name json_read.h -o -name text_input.h | grep -q .; then
    fail "private headers installed: $(find "$prefix/include" -name '*-inl.h' -o -name json_read.h -o -name text_input.h)"
  fi
  [[ "$("$prefix/bin/aniso" --version)" == "aniso $(sed -n 's/^#define ANISO_VERSION "\(.*\)"$/\1/p' "$prefix/include/aniso/version.h")" ]] \
    || fail "aniso --version does not match aniso/version.h"
  echo "installed into $prefix: $(find "$prefix" -type f | wc -l) files"
  ;;
headers)
  # Each public header alone, with only the prefix and the system's include paths: no header may
  # need a private src/ header or another header included before it. glm's GLM_FORCE_XYZW_ONLY is
  # what aniso::kernels and aniso-kernels.pc define.
  prefix=$1
  cd "$prefix/include"
  find aniso -name '*.h' | sort > /tmp/aniso-headers.$$
  n=$(wc -l < /tmp/aniso-headers.$$)
  xargs -P "$jobs" -I{} sh -c 'echo "#include <{}>" | ${CXX:-c++} -std=c++20 -fsyntax-only -DGLM_FORCE_XYZW_ONLY -I"$1" -x c++ - \
      || { echo "FAIL: {} does not compile alone" >&2; exit 255; }' _ "$prefix/include" < /tmp/aniso-headers.$$
  rm -f /tmp/aniso-headers.$$
  echo "$n public headers compile alone from $prefix/include"
  ;;
find)
  prefix=$1 work=$2 cli=$3
  rm -rf "$work"
  cmake -S "$source_dir/examples/cpp" -B "$work" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" -DANISO_CLI="$cli" >/dev/null
  cmake --build "$work" -j "$jobs" >/dev/null
  ctest --test-dir "$work" --output-on-failure
  # The fitter draws its plots with aniso::image, not the renderer: the link line of a program that
  # links aniso::fit names no Embree or tinyobjloader (the link line, not ldd: Debian's gcc links
  # with --as-needed, which drops unused libraries either way), and find_package(aniso COMPONENTS
  # fit) looks for neither.
  grep -q 'libaniso_image' "$work/CMakeFiles/fit.dir/link.txt" || fail "cannot read the fit example's link line"
  if grep -oE '[^ ]*(embree|tinyobjloader|aniso_render)[^ ]*' "$work/CMakeFiles/fit.dir/link.txt"; then
    fail "the fit example's link line (aniso::fit) names the renderer's libraries"
  fi
  rm -rf "$work-fit"
  cmake -S "$source_dir/examples/cpp" -B "$work-fit" -DCMAKE_PREFIX_PATH="$prefix" -DANISO_COMPONENTS=fit >/dev/null
  if grep -E '^(embree|tinyobjloader)_DIR:' "$work-fit/CMakeCache.txt"; then fail "find_package(aniso COMPONENTS fit) looked for the renderer's packages"; fi
  grep -q '^OpenEXR_DIR:PATH=/' "$work-fit/CMakeCache.txt" || fail "find_package(aniso COMPONENTS fit) did not load the image component (OpenEXR)"
  echo "aniso::fit links no Embree; COMPONENTS fit loads kernels, host, image and fit"
  ;;
pkgconfig)
  # Without CMake: the compiler line pkg-config gives. The kernels example with aniso-kernels alone
  # (glm only, no library), the eval example with aniso (every library), compared with the CLI.
  prefix=$1 work=$2 cli=$3
  rm -rf "$work" && mkdir -p "$work"
  export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
  ${CXX:-c++} -std=c++20 -O2 "$source_dir/examples/cpp/kernels_only.cpp" $(pkg-config --cflags --libs aniso-kernels) -o "$work/kernels_only"
  ${CXX:-c++} -std=c++20 -O2 "$source_dir/examples/cpp/eval.cpp" $(pkg-config --cflags --libs aniso) -o "$work/eval"
  sh "$source_dir/examples/cpp/compare_with_cli.sh" "$cli" 1e-6 "$work/kernels_only" > "$work/kernels_only.txt" \
    || { cat "$work/kernels_only.txt"; fail "kernels_only (pkg-config) disagrees with $cli"; }
  sh "$source_dir/examples/cpp/compare_with_cli.sh" "$cli" 1e-6 "$work/eval" brushed-gold 30 0 30 180 45 20 60 200 80 0 80 180 \
    > "$work/eval.txt" || { cat "$work/eval.txt"; fail "eval (pkg-config) disagrees with $cli"; }
  tail -n 1 "$work/eval.txt"
  echo "pkg-config: $(pkg-config --modversion aniso); built and checked kernels_only and eval"
  ;;
subproject)
  # add_subdirectory(aniso): only the libraries an example links are built (no executable, tests,
  # benchmarks, fuzz targets or Python module: they default to OFF in a subproject). Two examples
  # only, the kernels and the host library: the others need the same build of every library.
  src=$1 work=$2 cli=$3
  rm -rf "$work"
  cmake -S "$source_dir/examples/cpp" -B "$work" -DCMAKE_BUILD_TYPE=Release -DANISO_SOURCE_DIR="$src" -DANISO_CLI="$cli" >/dev/null
  for t in aniso aniso_tests aniso_python aniso_bench; do
    if cmake --build "$work" --target help | grep -qx "\.\.\. $t"; then fail "the subproject defines target $t"; fi
  done
  cmake --build "$work" -j "$jobs" --target kernels_only eval >/dev/null
  ctest --test-dir "$work" --output-on-failure -R '^(kernels_only|eval)$'
  ;;
fetch)
  # FetchContent from a source tree: configure only, then build the kernels-only example (no
  # library is compiled for it).
  src=$1 work=$2
  rm -rf "$work" && mkdir -p "$work/consumer"
  cat > "$work/consumer/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.25)
project(fetch_consumer CXX)
include(FetchContent)
FetchContent_Declare(aniso SOURCE_DIR "$src")
FetchContent_MakeAvailable(aniso)
add_executable(kernels_only "$source_dir/examples/cpp/kernels_only.cpp")
target_link_libraries(kernels_only PRIVATE aniso::kernels)
# The host library's target exists too (not built here).
if(NOT TARGET aniso::aniso OR NOT TARGET aniso::host)
  message(FATAL_ERROR "FetchContent did not define aniso::aniso and aniso::host")
endif()
CMAKE
  cmake -S "$work/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$work/build" -j "$jobs" --target kernels_only >/dev/null
  "$work/build/kernels_only" >/dev/null
  echo "FetchContent: configured, kernels_only built and run"
  ;;
deb)
  build=$1 work=$2
  rm -rf "$work" && mkdir -p "$work"
  (cd "$build" && cpack -G DEB -B "$work" >/dev/null)
  deb=$(ls "$work"/aniso_*_amd64.deb) || fail "cpack wrote no aniso_*_amd64.deb in $work"
  version=$(sed -n 's/^#define ANISO_VERSION "\(.*\)"$/\1/p' "$build/include/aniso/version.h")
  [[ "$(basename "$deb")" == "aniso_${version}_amd64.deb" ]] || fail "package name $(basename "$deb"), expected aniso_${version}_amd64.deb"
  dpkg-deb -c "$deb" | awk '{print $6}' > "$work/files.txt"
  for f in ./usr/bin/aniso ./usr/include/aniso/aniso.h ./usr/include/aniso/kernels.h ./usr/include/aniso/version.h \
           ./usr/lib/cmake/aniso/anisoConfig.cmake ./usr/lib/pkgconfig/aniso.pc \
           ./usr/lib/libaniso_host.a ./usr/share/aniso/web/index.html ./usr/share/doc/aniso/cpp.md; do
    grep -qx "$f" "$work/files.txt" || fail "$(basename "$deb") has no $f"
  done
  grep -q '^./usr/lib/python3/dist-packages/aniso/_aniso.*\.so$' "$work/files.txt" || fail "$(basename "$deb") has no Python module"
  depends=$(dpkg-deb -f "$deb" Depends)
  for p in libglm-dev libfmt-dev nlohmann-json3-dev libtbb-dev libembree-dev libceres-dev libepoxy-dev python3-numpy libc6 libglfw3; do
    [[ ",$depends," == *"$p"* ]] || fail "Depends lacks $p: $depends"
  done
  echo "$(basename "$deb"): $(wc -l < "$work/files.txt") entries; Depends: $depends"
  ;;
*)
  fail "unknown check $check"
  ;;
esac
