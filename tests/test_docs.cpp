// tests/test_docs.cpp: the documentation quotes what the code says. Each model page
// docs/models/<name>.md contains its parameter tables exactly as `aniso models --markdown` prints
// them (markdown_table() in src/io/params.cpp, of the tables in the model files src/models/<member>.h), and README.md gives the
// two commands up front.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aniso/io/params.h"

namespace aniso {
namespace {

// The whole file, or "" when it cannot be read (the caller reports which).
std::string read_text(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::ostringstream s;
  if (ok) s << in.rdbuf();
  return s.str();
}

TEST(Docs, ModelPagesQuoteTheGeneratedParameterTables) {
  int pages = 0;
  for (const ModelSpec* spec : model_specs()) {
    const std::string name(spec->name);
    const std::string rel = "docs/models/" + name + ".md";
    bool ok = false;
    const std::string page = read_text(std::string(ANISO_SOURCE_DIR) + "/" + rel, ok);
    ASSERT_TRUE(ok) << rel << " is missing: every model (src/models) has a page";
    ++pages;
    const std::string table = markdown_table(*spec);
    EXPECT_TRUE(page.find(table) != std::string::npos)
        << rel << " does not contain the current parameter table of `" << name << "` verbatim.\n"
        << "Regenerate it: replace the table(s) under \"## Parameters\" in " << rel << " with the output of\n"
        << "  build/release/bin/aniso models --markdown --model " << name << "\n"
        << "(from its first line \"Parameters of `" << name << "` ...\" through the last nested table; do not edit it "
        << "by hand: change its model file, src/models/<member>.h, instead). Expected text:\n"
        << table;
  }
  EXPECT_GE(pages, 7);  // lambert phong ward ashikhmin-shirley lafortune ggx metal
}

TEST(Docs, ReadmeStartsWithTheTwoCommands) {
  bool ok = false;
  const std::string readme = read_text(std::string(ANISO_SOURCE_DIR) + "/README.md", ok);
  ASSERT_TRUE(ok) << "README.md is missing";
  std::istringstream in(readme);
  std::string head, line;
  for (int i = 0; i < 15 && std::getline(in, line); ++i) head += line + "\n";
  EXPECT_TRUE(head.find("make render") != std::string::npos)
      << "README.md's first 15 lines must give `make render` (the main job):\n"
      << head;
  EXPECT_TRUE(head.find("make test") != std::string::npos) << "README.md's first 15 lines must give `make test`:\n" << head;
}

// docs/cpp.md and the README's "Use from C++" quote compiled code: every ```cpp (or ```cuda / ```cmake)
// block is preceded by `<!-- examples/cpp/FILE -->` and is a contiguous run of that file's lines,
// which tests/package builds and runs (package_find_package).
TEST(Docs, CppGuideQuotesTheCompiledExamples) {
  int blocks = 0;
  for (const char* rel : {"docs/cpp.md", "README.md"}) {
    bool ok = false;
    const std::string page = read_text(std::string(ANISO_SOURCE_DIR) + "/" + rel, ok);
    ASSERT_TRUE(ok) << rel << " is missing";
    std::istringstream in(page);
    std::string line, previous;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      const bool code = line == "```cpp" || line == "```c++" || line == "```cuda" || line == "```cmake";
      if (!code) {
        previous = line;
        continue;
      }
      const int fence = number;
      std::string block;
      while (std::getline(in, line) && line != "```") {
        ++number;
        block += line + "\n";
      }
      ++number;
      const std::string open = "<!-- ", close = " -->";
      ASSERT_TRUE(previous.starts_with(open) && previous.ends_with(close))
          << rel << ":" << fence << ": a code block must follow a line <!-- examples/cpp/FILE --> naming the file it quotes";
      const std::string file = previous.substr(open.size(), previous.size() - open.size() - close.size());
      EXPECT_TRUE(file.starts_with("examples/cpp/")) << rel << ":" << fence << ": " << file << " is not under examples/cpp/";
      bool file_ok = false;
      const std::string source = read_text(std::string(ANISO_SOURCE_DIR) + "/" + file, file_ok);
      ASSERT_TRUE(file_ok) << rel << ":" << fence << ": " << file << " does not exist";
      // A run of whole lines: the block starts at a line start of the file.
      const size_t at = source.find(block);
      EXPECT_TRUE(at != std::string::npos && (at == 0 || source[at - 1] == '\n'))
          << rel << ":" << fence << ": the block is not a run of whole lines of " << file << ":\n"
          << block;
      ++blocks;
      previous.clear();
    }
  }
  EXPECT_GE(blocks, 8) << "docs/cpp.md quotes every example (kernels, materials, loop, batch, tangents, CUDA, GLSL, fit, errors)";
}

// GitHub's heading anchors: lower case, punctuation other than '-' and '_' dropped, spaces to '-'.
std::string heading_anchor(const std::string& heading) {
  std::string a;
  for (const char ch : heading) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c))
      a += char(std::tolower(c));
    else if (c == ' ' || c == '-')
      a += '-';
    else if (c == '_' || c >= 0x80)
      a += ch;  // non-ASCII letters (θ, é) are kept
  }
  return a;
}

std::set<std::string> anchors_of(const std::string& markdown) {
  std::set<std::string> out;
  std::istringstream in(markdown);
  bool fence = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) fence = !fence;
    if (fence || line.empty() || line[0] != '#') continue;
    const size_t text = line.find_first_not_of('#');
    if (text == std::string::npos) continue;
    out.insert(heading_anchor(line.substr(line.find_first_not_of(' ', text))));
  }
  return out;
}

// Every relative link in the repository's Markdown files resolves to a file in the repository (a
// user's clone has nothing beside it), and a #fragment to a heading of the target page.
TEST(Docs, EveryRelativeLinkResolvesInsideTheRepository) {
  namespace fs = std::filesystem;
  const fs::path root(ANISO_SOURCE_DIR);
  int checked = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path rel = fs::relative(entry.path(), root);
    const std::string first = rel.begin()->string();
    if (first == "build" || first == ".git" || first == "fuzz" || entry.path().extension() != ".md") continue;
    // npm's packages for the browser tests (tests/web/node_modules, not in the repository).
    if (rel.string().find("node_modules") != std::string::npos) continue;
    bool ok = false;
    const std::string text = read_text(entry.path().string(), ok);
    ASSERT_TRUE(ok) << rel;
    // Links are "](target)": a scan, not std::regex (whose recursive matcher overflows the stack on
    // long lines under AddressSanitizer).
    for (size_t at = text.find("]("); at != std::string::npos; at = text.find("](", at + 2)) {
      const size_t end = text.find_first_of(") \t\n", at + 2);
      if (end == std::string::npos || text[end] != ')') continue;
      const std::string target = text.substr(at + 2, end - at - 2);
      if (target.empty()) continue;
      if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
      const size_t hash = target.find('#');
      const std::string file = target.substr(0, hash), fragment = hash == std::string::npos ? "" : target.substr(hash + 1);
      const fs::path resolved = file.empty() ? entry.path() : (entry.path().parent_path() / file).lexically_normal();
      ++checked;
      const std::string rel_resolved = fs::relative(resolved, root).string();
      EXPECT_TRUE(rel_resolved.rfind("..", 0) != 0) << rel << ": link " << target << " leaves the repository";
      EXPECT_TRUE(fs::exists(resolved)) << rel << ": link " << target << " does not resolve (" << resolved << ")";
      if (!fragment.empty() && resolved.extension() == ".md" && fs::is_regular_file(resolved)) {
        bool ok2 = false;
        const std::set<std::string> anchors = anchors_of(read_text(resolved.string(), ok2));
        EXPECT_TRUE(anchors.count(fragment)) << rel << ": link " << target << ": no heading with anchor #" << fragment;
      }
    }
  }
  EXPECT_GT(checked, 20);
}

// The sources name docs pages in their comments and messages ("docs/cli.md", "docs/scenes.md#gl-backend"):
// every page named exists, and a named #fragment is a heading of it. Markdown links are the test
// above; this covers the code, which no Markdown renderer checks.
TEST(Docs, EveryDocsPageTheSourcesNameExists) {
  namespace fs = std::filesystem;
  const fs::path root(ANISO_SOURCE_DIR);
  const std::set<std::string> text_ext = {".h",   ".cpp",  ".cu",    ".glsl", ".inc", ".py", ".pyi",  ".js",
                                          ".mjs", ".html", ".cmake", ".txt",  ".sh",  ".in", ".toml", ".json"};
  std::vector<fs::path> files = {root / "CMakeLists.txt", root / "Makefile"};
  for (const char* dir : {"include", "src", "apps", "python", "tests", "web", "scripts", "bench", "cmake", "examples"}) {
    if (!fs::is_directory(root / dir)) continue;
    for (auto it = fs::recursive_directory_iterator(root / dir); it != fs::recursive_directory_iterator(); ++it) {
      const std::string name = it->path().filename().string();
      if (it->is_directory() && (name == "node_modules" || name == "__pycache__" || name.rfind("build", 0) == 0)) {
        it.disable_recursion_pending();
        continue;
      }
      if (it->is_regular_file() && text_ext.count(it->path().extension().string())) files.push_back(it->path());
    }
  }
  const auto page_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '/'; };
  const auto anchor_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; };
  int checked = 0;
  for (const fs::path& f : files) {
    bool ok = false;
    const std::string text = read_text(f.string(), ok);
    if (!ok) continue;
    const std::string rel = fs::relative(f, root).string();
    for (size_t at = text.find("docs/"); at != std::string::npos; at = text.find("docs/", at + 5)) {
      if (at > 0 && (page_char(text[at - 1]) || text[at - 1] == '.')) continue;  // "../docs/", "mydocs/"
      size_t end = at + 5;
      while (end < text.size() && page_char(text[end])) ++end;
      if (text.compare(end, 3, ".md") != 0) continue;
      const std::string page = text.substr(at, end + 3 - at);
      ++checked;
      ASSERT_TRUE(fs::is_regular_file(root / page)) << rel << " names " << page << ", which does not exist";
      if (end + 3 < text.size() && text[end + 3] == '#') {
        size_t a = end + 4;
        while (a < text.size() && anchor_char(text[a])) ++a;
        const std::string fragment = text.substr(end + 4, a - end - 4);
        bool ok2 = false;
        const std::set<std::string> anchors = anchors_of(read_text((root / page).string(), ok2));
        EXPECT_TRUE(fragment.empty() || anchors.count(fragment))
            << rel << " names " << page << "#" << fragment << ": no such heading";
      }
    }
  }
  EXPECT_GT(checked, 100);
}

}  // namespace
}  // namespace aniso
