#!/bin/bash
# How Mitsuba 3 was built here for bench/mitsuba3/compare.py (docs/rgl.md, "In Mitsuba 3"): not
# part of the project's build or tests. Mitsuba 3 v3.8.0 and its submodules from bare git mirrors
# (MIRROR/owner+name/repo, as the session's fetch tool leaves them) at their pinned commits where
# a mirror has them, the least changes where one lacks something (each said below), variants
# scalar_rgb and scalar_spectral only, no Python, no Embree (Mitsuba's own kd-tree), no GUI.
# With a normal `git clone --recursive` of v3.8.0 steps 2 and 3 are not needed.
#
#     bench/mitsuba3/build-mitsuba.sh [MIRROR [DEST]]     # defaults /work/.mirror /work/mitsuba
#     DEST/build/mitsuba -m scalar_spectral scene.xml -o out.pfm
set -euo pipefail
M=${1:-/work/.mirror} D=${2:-/work/mitsuba}
S=$D/src B=$D/build

# x MIRROR DEST COMMIT [PREFIX]: every blob of COMMIT (under PREFIX) that the mirror has into DEST;
# an absent blob is named on stderr.
x() {
  local g=$M/$1/repo
  mkdir -p "$2"
  git --git-dir="$g" ls-tree -r "$3" ${4:+"$4"} | awk '$2 == "blob" { print $1, $3, $4 }' |
    while read -r mode h p; do
      git --git-dir="$g" cat-file -e "$h" 2>/dev/null || { echo "missing $1:$p" >&2; continue; }
      mkdir -p "$2/$(dirname "$p")"
      git --git-dir="$g" cat-file blob "$h" >"$2/$p"
      if [ "$mode" = 100755 ]; then chmod +x "$2/$p"; fi
    done
}

# 1. Sources. The mirror's newest commit (b45b0a93, 2026-08-08) needs ext/struct-jit and
#    ext/libjpeg-turbo (added 2026-06), of which no snapshot could be had: v3.8.0 (2ba36148,
#    2026-02-23) is the newest release without them.
rm -rf "$S"
x mitsuba-renderer+mitsuba3 "$S" 2ba361481801f6e158bbab2b64345f6778bd2865
x mitsuba-renderer+drjit "$S/ext/drjit" 3b3556d875d59eb56bf11bc22a0af784382f058a
x mitsuba-renderer+drjit-core "$S/ext/drjit/ext/drjit-core" 213983e47c99db0c6ab5e3dfce952e68bb9a8bd3
x mitsuba-renderer+nanothread "$S/ext/drjit/ext/drjit-core/ext/nanothread" 5d354917ea574488d133d242eda1a365a70b80e9
x mitsuba-renderer+cmake-defaults "$S/ext/drjit/ext/drjit-core/ext/nanothread/ext/cmake-defaults" \
  182fac32bf1856ffbfcfd03196d1d227e77135d1
x Tessil+robin-map "$S/ext/drjit/ext/drjit-core/ext/robin_map" 4ec1bf19c6a96125ea22062f38c2cf5b958e448e
for nb in "$S/ext/nanobind" "$S/ext/drjit/ext/nanobind"; do
  x wjakob+nanobind "$nb" 22acf11a2dac212e857f0d06ce80f808cac8fdad
  x Tessil+robin-map "$nb/ext/robin_map" 4ec1bf19c6a96125ea22062f38c2cf5b958e448e
done
x mitsuba-renderer+libjpeg "$S/ext/libjpeg" d3841d172c83f709151a9654e5aaed006cc81ff7
x mitsuba-renderer+pugixml "$S/ext/pugixml" 7e9d5fa64a052d3df4b629d24f1e7fe12f83c3ea
x mitsuba-renderer+tinyformat "$S/ext/tinyformat" 635345c75bd95891ee041ac51ce74ebc891d5bab
x fastfloat+fast_float "$S/ext/fastfloat" 052975dd5f8166d0f9e4a215fa75a349d5985b91
# Pins absent from their mirrors, the newest commit instead: libpng (pin cfcd1dc4; newest
# 634f876, 2025-06-26) and OpenEXR (pin 2b5ab693; newest dbabb6f9, OpenEXR 2.5.5, the pin of
# Mitsuba v3.0 to v3.5). zlib is Debian's (ext/CMakeLists.txt builds its own only on Windows);
# libpng, libjpeg and OpenEXR have no system option there.
x mitsuba-renderer+libpng "$S/ext/libpng" HEAD
x mitsuba-renderer+openexr "$S/ext/openexr" HEAD
# resources/data (mitsuba-data @ its pin): only what copy-resources copies, ior/ (the named
# conductors' spectra) and sunsky/output.
x mitsuba-renderer+mitsuba-data "$S/resources/data" a4addd0b991d1a0622db2ac98401fd45d8070e91 ior
x mitsuba-renderer+mitsuba-data "$S/resources/data" a4addd0b991d1a0622db2ac98401fd45d8070e91 sunsky/output

# 2. No asmjit (pin cae01e39 absent; the mirror's newest, 53cee0c, is v3.0's, another API): the
#    struct converter's interpreted path, which include/mitsuba/core/struct.h:9-13 picks where
#    asmjit is not used (non-x86), Mitsuba's asmjit runtime (core/jit.h, core/jit.cpp, serving
#    only that converter) compiled out, and no asmjit target built or linked.
sed -i 's/^ #if defined(DRJIT_X86_64) && defined(DRJIT_X86_SSE42)$/ #if 0 \/\/ no asmjit here/' \
  "$S/include/mitsuba/core/struct.h"
sed -i 's/^#if defined(DRJIT_X86_64)$/#if 0 \/\/ no asmjit here (was: defined(DRJIT_X86_64))/' \
  "$S/include/mitsuba/core/jit.h" "$S/src/core/jit.cpp"
# shellcheck disable=SC2016 # a literal ${...} of CMake
sed -i 's/^if (\${CMAKE_SYSTEM_PROCESSOR} MATCHES "x86_64|AMD64")$/if (FALSE) # no asmjit here/' "$S/ext/CMakeLists.txt"
sed -i 's/^if (CMAKE_SYSTEM_PROCESSOR MATCHES "(x86_64)|(amd64)|(AMD64)")$/if (FALSE) # no asmjit here/' \
  "$S/CMakeLists.txt" "$S/src/core/CMakeLists.txt"
sed -i 's/^if (CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")$/if (FALSE) # no asmjit here/' "$S/src/mitsuba/CMakeLists.txt"
[ "$(grep -c "no asmjit here" "$S"/include/mitsuba/core/{struct,jit}.h "$S"/src/core/jit.cpp "$S"/ext/CMakeLists.txt \
  "$S"/CMakeLists.txt "$S"/src/{core,mitsuba}/CMakeLists.txt | awk -F: '{ s += $2 } END { print s }')" = 9 ] ||
  { echo "the asmjit edits did not all apply" >&2; exit 1; }

# 3. Dr.Jit symbols that v3.8.0's libmitsuba and plugins reference even without the JIT and
#    autodiff libraries (`nm -D --undefined-only` over libmitsuba.so and plugins/*.so), in a small
#    library linked into the executable. jit_flag's callers are the object-traversal macros for
#    frozen functions (include/mitsuba/core/fwd.h:410, "Only traverse the scene for frozen
#    functions") and JIT loop recording: it answers as drjit-core's default flags (jit.h:1664).
#    jit_freeze_discard (src/films/hdrfilm.cpp:263, every variant) drops a frozen function's
#    recording: without the JIT nothing is recorded. jit_log prints warnings and errors, as
#    drjit-core by default; jit_raise throws, as drjit-core's; jit_fail and ad_traverse (autodiff of
#    attached variables) stop with a message, so that a call would be seen.
mkdir -p "$D/stub"
cat >"$D/stub/drjit_scalar_stub.cpp" <<'EOF'
#include <drjit-core/jit.h>
#include <drjit/autodiff.h>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

int jit_flag(JitFlag flag) { return ((uint32_t) JitFlag::Default & (uint32_t) flag) != 0; }

void jit_freeze_discard(JitBackend, const char *) {}

void jit_log(LogLevel level, const char *fmt, ...) {
    if ((uint32_t) level > (uint32_t) LogLevel::Warn)
        return;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void jit_raise(const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof(buf), fmt, ap);
    va_end(ap);
    throw std::runtime_error(buf);
}

void jit_fail(const char *fmt, ...) noexcept {
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "jit_fail (drjit scalar stub): ");
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    abort();
}

void ad_traverse(drjit::ADMode, uint32_t) {
    fprintf(stderr, "ad_traverse called in a build without Dr.Jit's autodiff library\n");
    abort();
}
EOF
clang++ -std=c++17 -O2 -fPIC -shared -I"$S/ext/drjit/include" -I"$S/ext/drjit/ext/drjit-core/include" \
  -I"$S/ext/drjit/ext/drjit-core/ext/nanothread/include" "$D/stub/drjit_scalar_stub.cpp" \
  -o "$D/stub/libdrjit-scalar-stub.so"

# 4. Configure. NB_DIR: Mitsuba's headers include nanobind's intrusive ref (core/object.h:6), whose
#    path ext/CMakeLists.txt:378 takes from NB_DIR, set only when Python is found.
touch "$S/ext/openexr/OpenEXR/IlmImf/dwaLookups.h" # placeholder, regenerated in step 5
cmake -S "$S" -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DMI_ENABLE_PYTHON=OFF -DMI_ENABLE_EMBREE=OFF -DMI_DEFAULT_VARIANTS="scalar_rgb,scalar_spectral" \
  -DNB_DIR="$S/ext/nanobind" -DDRJIT_ENABLE_LLVM=OFF -DDRJIT_ENABLE_CUDA=OFF \
  -DCMAKE_EXE_LINKER_FLAGS="-L$D/stub -ldrjit-scalar-stub -Wl,-rpath,$D/stub"

# 5. OpenEXR's generated dwaLookups.h (its blob is absent from the mirror): made by its own
#    generator, dwaLookups.cpp, as OpenEXR's maintainers make it.
nice -n 5 ninja -C "$B" -j2 Half IlmThread Iex
E=$S/ext/openexr
clang++ -O2 -std=c++14 -I"$E/IlmBase/Half" -I"$E/IlmBase/IlmThread" -I"$E/IlmBase/Iex" -I"$E/IlmBase/Imath" \
  -I"$E/OpenEXR/IlmImf" -I"$B/ext/openexr/OpenEXR/config" -I"$B/ext/openexr/IlmBase/config" \
  "$E/OpenEXR/IlmImf/dwaLookups.cpp" -o "$B/dwaLookups" -L"$B" -lHalf-mitsuba -lIlmThread-mitsuba -lIex-mitsuba \
  -lpthread -Wl,-rpath,"$B"
"$B/dwaLookups" >"$E/OpenEXR/IlmImf/dwaLookups.h" 2>/dev/null

# 6. The executable, the resources (rgb2spec's srgb.coeff, the ior spectra) and the plugins the
#    comparison's scenes use (Mitsuba loads plugins by name at run time: a missing one is an error
#    naming it).
plugins=""
for p in measured roughconductor conductor diffuse blendbsdf principled twosided area constant point hdrfilm path \
  direct box independent perspective sphere merge srgb uniform regular irregular d65 rawconstant bitmap; do
  plugins="$plugins plugins/$p.so"
done
# shellcheck disable=SC2086
nice -n 5 ninja -C "$B" -j2 mitsuba-bin copy-resources $plugins
"$B/mitsuba" --help | head -1
