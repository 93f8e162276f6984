// The layers of docs/architecture.md ("Layers"), held by the includes: each file of include/aniso
// and src/ names only headers of its own layer and of the layers above it, plus the exceptions
// listed here, each with its reason. The check reads the `#include "..."` lines of the source tree
// (ANISO_SOURCE_DIR), a few hundred files, in milliseconds.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

namespace aniso {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = ANISO_SOURCE_DIR;

// The rows of docs/architecture.md's table, from the top: a directory (include/aniso/<dir>,
// src/<dir>) belongs to one row and may include its own row and the rows above it. The last row's
// directories do not include each other, except through kPeerExceptions.
const std::vector<std::vector<std::string>> kRows = {
    {"core", "brdf", "tangent"},                // kernels
    {"batch"},                                  // batch
    {"io"},                                     // io
    {"measured", "data", "stats", "rgl"},       // readers and tables
    {"models"},                                 // the model files
    {"image"},                                  // image
    {"render", "gl", "fit", "export", "view"},  // render / gl / fit / export / view, peers
};

struct Exception {
  std::string file;     // relative to the repository
  std::string include;  // as written in the #include
  std::string why;
};

// Peers of the last row that one of them reads (docs/architecture.md, "Layers").
const std::vector<Exception> kPeerExceptions = {
    {"include/aniso/export/export.h", "aniso/fit/fit.h", "export fits the source's GGX with the fitter"},
    {"src/gl/raster_geometry.h", "aniso/render/scene.h", "the private GL backend (aniso_gl_raster) rasterises render's scenes"},
    {"src/gl/raster_geometry.cpp", "aniso/render/geometry.h", "the private GL backend: a mesh's triangles"},
    {"src/gl/scene_checks.h", "aniso/render/scene.h", "the private GL backend"},
    {"src/gl/scene_raster.h", "aniso/render/scene.h", "the private GL backend"},
    {"src/gl/shadow_atlas.h", "aniso/render/scene.h", "the private GL backend"},
    {"src/view/explorer.h", "aniso/render/scene.h", "the explorer's preview renders with the path tracer"},
    {"src/view/preview.h", "aniso/render/scene.h", "the explorer's preview renders with the path tracer"},
    {"src/view/preview.cpp", "aniso/render/integrator.h", "the explorer's preview renders with the path tracer"},
};

// Includes that run up the layers today. Issue 41 will remove them: the presets' tables move out of
// io, which then reads no layer below it (the models' builders already have: src/models).
const std::vector<Exception> kUpwardExceptions = {
    {"src/io/presets.cpp", "aniso/data/fits.h", "the presets of the fit table (issue 41)"},
    {"src/io/presets.cpp", "aniso/data/metals.h", "the presets of the metal table (issue 41)"},
};

struct Include {
  std::string file;     // relative to the repository
  std::string include;  // as written
  int line = 0;
};

// The header a line includes with `#include "..."`, or "" for any other line.
std::string quoted_include(const std::string& l) {
  size_t i = l.find_first_not_of(" \t");
  if (i == std::string::npos || l[i] != '#') return "";
  i = l.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || l.compare(i, 7, "include") != 0) return "";
  i = l.find_first_not_of(" \t", i + 7);
  if (i == std::string::npos || l[i] != '"') return "";
  const size_t end = l.find('"', i + 1);
  return end == std::string::npos ? "" : l.substr(i + 1, end - i - 1);
}

// Every `#include "..."` of include/aniso and src/ (C++ sources and headers, the .inc tables),
// read once.
const std::vector<Include>& quoted_includes() {
  static const std::vector<Include> out = [] {
    std::vector<Include> v;
    for (const char* top : {"include/aniso", "src"})
      for (const fs::directory_entry& e : fs::recursive_directory_iterator(kRoot / top)) {
        const std::string ext = e.path().extension().string();
        if (!e.is_regular_file() || (ext != ".h" && ext != ".cpp" && ext != ".inc" && ext != ".cu")) continue;
        std::ifstream in(e.path());
        int n = 0;
        for (std::string l; std::getline(in, l);) {
          ++n;
          if (std::string inc = quoted_include(l); !inc.empty())
            v.push_back({fs::relative(e.path(), kRoot).generic_string(), std::move(inc), n});
        }
      }
    return v;
  }();
  return out;
}

// The directory of a file (include/aniso/<dir>/..., src/<dir>/...), "" for aniso/*.h at the top.
std::string dir_of_file(const std::string& f) {
  for (const std::string_view prefix : {"include/aniso/", "src/"})
    if (f.starts_with(prefix)) {
      const std::string rest = f.substr(prefix.size());
      const size_t slash = rest.find('/');
      return slash == std::string::npos ? "" : rest.substr(0, slash);
    }
  return "";
}

// The directory an include names: "aniso/<dir>/..." (public) or "<dir>/..." (private, src/<dir>).
// "" for the top-level public headers (aniso/version.h, the umbrella headers).
std::string dir_of_include(const std::string& inc) {
  std::string rest = inc.starts_with("aniso/") ? inc.substr(6) : inc;
  const size_t slash = rest.find('/');
  return slash == std::string::npos ? "" : rest.substr(0, slash);
}

int row_of(const std::string& dir) {
  for (size_t r = 0; r < kRows.size(); ++r)
    if (std::find(kRows[r].begin(), kRows[r].end(), dir) != kRows[r].end()) return int(r);
  return -1;
}

bool listed(const std::vector<Exception>& list, const Include& i) {
  return std::any_of(list.begin(), list.end(), [&](const Exception& e) { return e.file == i.file && e.include == i.include; });
}

std::string where(const Include& i) { return i.file + ":" + std::to_string(i.line) + " includes \"" + i.include + "\""; }

TEST(Layers, EveryDirectoryHasARow) {
  for (const char* top : {"include/aniso", "src"})
    for (const fs::directory_entry& e : fs::directory_iterator(kRoot / top))
      if (e.is_directory()) {
        EXPECT_GE(row_of(e.path().filename().string()), 0)
            << top << "/" << e.path().filename().string() << " is in no row of kRows (docs/architecture.md, \"Layers\")";
      }
}

TEST(Layers, EachFileIncludesItsOwnLayerAndTheLayersAbove) {
  const std::vector<Include>& all = quoted_includes();
  ASSERT_GT(all.size(), 100u) << "the source tree was not found at " << kRoot;
  for (const Include& i : all) {
    const std::string from = dir_of_file(i.file), to = dir_of_include(i.include);
    if (from.empty() || to.empty() || from == to) continue;
    const int rf = row_of(from), rt = row_of(to);
    if (rf < 0 || rt < 0) continue;  // EveryDirectoryHasARow names it
    if (rt < rf || (rt == rf && rf != int(kRows.size()) - 1)) continue;
    if (rt == rf) {
      EXPECT_TRUE(listed(kPeerExceptions, i))
          << where(i) << ": " << from << " and " << to << " are peers, which do not include each other (kPeerExceptions)";
    } else {
      EXPECT_TRUE(listed(kUpwardExceptions, i)) << where(i) << ": " << to << " is a layer below " << from;
    }
  }
}

TEST(Layers, KernelsIncludeNoHostHeader) {
  // Header-only, nvcc-compiled, no allocation (docs/architecture.md): only the kernels' own headers.
  for (const Include& i : quoted_includes())
    if (row_of(dir_of_file(i.file)) == 0) {
      EXPECT_TRUE(i.include.starts_with("aniso/")) << where(i) << ": a kernel includes no private header";
      EXPECT_EQ(row_of(dir_of_include(i.include)), 0) << where(i) << ": a kernel includes only kernels";
    }
}

TEST(Layers, PublicHeadersIncludeNoPrivateHeader) {
  for (const Include& i : quoted_includes())
    if (i.file.starts_with("include/")) {
      EXPECT_TRUE(i.include.starts_with("aniso/")) << where(i) << ": an installed header includes only installed headers";
    }
}

TEST(Layers, NoLibraryIncludesTheFrontEnds) {
  // apps/aniso and python/src are the top layer: nothing in include/ or src/ names their headers.
  std::set<std::string> front;
  for (const char* dir : {"apps/aniso", "python/src"})
    for (const fs::directory_entry& e : fs::directory_iterator(kRoot / dir))
      if (e.path().extension() == ".h") front.insert(e.path().filename().string());
  ASSERT_FALSE(front.empty());
  for (const Include& i : quoted_includes()) {
    EXPECT_EQ(i.include.find("apps/"), std::string::npos) << where(i);
    EXPECT_EQ(i.include.find("python/"), std::string::npos) << where(i);
    if (front.count(fs::path(i.include).filename().string())) {
      EXPECT_TRUE(fs::exists(kRoot / "src" / i.include) || fs::exists(kRoot / "include" / i.include) ||
                  fs::exists((kRoot / i.file).parent_path() / i.include))
          << where(i) << ": a header of the front ends (apps/aniso, python/src)";
    }
  }
}

TEST(Layers, EveryListedExceptionIsStillThere) {
  // An exception that no file needs any more is taken off its list, so that it cannot come back.
  const std::vector<Include>& all = quoted_includes();
  for (const std::vector<Exception>* list : {&kPeerExceptions, &kUpwardExceptions})
    for (const Exception& e : *list)
      EXPECT_TRUE(
          std::any_of(all.begin(), all.end(), [&](const Include& i) { return i.file == e.file && i.include == e.include; }))
          << e.file << " no longer includes \"" << e.include << "\": remove it from the exceptions (" << e.why << ")";
}

}  // namespace
}  // namespace aniso
