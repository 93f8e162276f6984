// Lists of models outside the registry (issue 41, "generated, not listed"). The sets of models
// are made in one place each: the registry's rows (aniso/brdf/registry.h), the fitter's table
// (kFittable, fittable_models()), the metal's lobes (EnumNames<SpecularLobeKind>, io/enum_names.h),
// the models whose table has rotation_deg and the registry's scalar batch path. Every list of
// three or more model names in the docs, README, the Python package, stub, tools and bindings, the
// CLI's sources, the web page, the public headers and src, and the CLI's help and `aniso models`
// output is either
//   - checked: kChecked names the set it means, and it must be that set (a new model breaks it),
//   - a choice: kChoices says why it is not a set (an example, a measured subset),
//   - elided ("ward, ggx, ...") or a list of fit-db model specs ("ward,ggx,lafortune:3"),
// so a hand copy of a set that nothing checks fails here, naming the file, line and names.
// The two tables of models (README's, docs/fitting.md's `--model` rows) are checked whole.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include "aniso/brdf/registry.h"
#include "aniso/fit/fit.h"
#include "aniso/io/params.h"
#include "cli_fixture.h"
#include "io/enum_names.h"

namespace aniso {
namespace {

const fs::path kRoot = ANISO_SOURCE_DIR;

// The sets, each from where the code makes it, in its source's order.
std::map<std::string, std::vector<std::string>> model_sets() {
  std::map<std::string, std::vector<std::string>> s;
  for (const ModelInfo& m : kModels) {
    s["models"].push_back(m.name);
    if (m.batch == BatchPath::Scalar) s["scalar batch"].push_back(m.name);
  }
  for (const std::string_view m : fittable_models()) s["fittable"].emplace_back(m);
  for (const std::string_view m : enum_names<SpecularLobeKind>()) s["metal lobes"].emplace_back(m);
  for (const ModelSpec* m : model_specs())
    if (m->find("rotation_deg")) s["oriented"].emplace_back(m->name);
  return s;
}

struct Checked {
  const char* source;  // a path under the root, or a CLI command's output ("aniso fit --help")
  const char* anchor;  // a text before the list, on the line where it starts (the nearest one counts)
  const char* set;     // the key of model_sets()
};
// The lists that mean a set, each checked to be it.
constexpr Checked kChecked[] = {
    {"docs/cli.md", "unknown model \"bogus\"; expected one of", "models"},
    {"docs/conventions.md", "Every anisotropic model (", "oriented"},
    {"docs/cpp.md", "Models without a SIMD twin", "scalar batch"},
    {"docs/python.md", "`aniso.fittable_models()`, the fitter's table:", "fittable"},
    {"docs/fitting.md", "[--metal-lobe ", "metal lobes"},
    {"docs/fit-db.md", "`metal:", "metal lobes"},
    {"docs/models/metal.md", "| `lobe` |", "metal lobes"},
    {"docs/models/metal.md", "selects which of the", "metal lobes"},
    {"include/aniso/fit/fit.h", "std::string metal_lobe", "metal lobes"},
    {"include/aniso/io/params.h", "metal_lobe_spec(", "metal lobes"},
    {"src/io/enum_names.h", "kNames[] = {", "metal lobes"},
    {"src/models/metal.h", "the specular lobe: {", "metal lobes"},
    {"python/aniso/__init__.pyi", "model: Literal[", "fittable"},
    {"python/aniso/__init__.pyi", "metal_lobe: Literal[", "metal lobes"},
    {"aniso fit --help", "--model", "fittable"},
    {"aniso fit --help", "--metal-lobe", "metal lobes"},
    {"aniso fit-db --help", "any model aniso fit fits", "fittable"},
    {"aniso fit-db --help", "metal[:", "metal lobes"},
    {"aniso models", "an object whose \"model\" is one of", "metal lobes"},
    {"aniso models", "the specular lobe: {", "metal lobes"},
};

struct Choice {
  const char* source;
  const char* anchor;
  const char* why;
};
constexpr Choice kChoices[] = {
    {"docs/fitting.md", "| file |", "the columns of the real-measurement table: the models that section fits"},
    {"docs/presets.md", "| Ngan 2005 |", "the models of Ngan 2005's published fits (data/fits/ngan2005/)"},
};

struct List {
  int line = 0;
  std::vector<std::string> names;
  std::string prefix;  // the line it starts on, up to its first name
};

bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The lists of three or more distinct model names in text: runs of names (whole words: not part of
// a path, a file name, an identifier or "ward/vector/ward") with only separators between them
// (space, comma, |, quotes, backquotes, a backslash, "\n", "and", "or"); a name after '=' is a
// value ("MODEL=lafortune"), not a member. A run that ends in an
// ellipsis is elided; one next to a fit-db model spec (NAME:ARG) is a list of specs: neither counts.
std::vector<List> find_lists(const std::string& text) {
  struct Token {
    size_t begin, end;
    std::string name;
    bool spec;
  };
  std::vector<Token> tokens;
  for (const ModelInfo& m : kModels) {
    const std::string n = m.name;
    for (size_t p = text.find(n); p != std::string::npos; p = text.find(n, p + 1)) {
      const size_t e = p + n.size();
      // Not inside a word, path or file name, nor a value after '=' (a default: "MODEL=lafortune").
      if (p > 0 && (word_char(text[p - 1]) || std::string_view("/.-=").find(text[p - 1]) != std::string::npos)) continue;
      const bool next_word = e + 1 < text.size() && word_char(text[e + 1]);
      if (e < text.size() && (word_char(text[e]) || text[e] == '/' || text[e] == '-' || (text[e] == '.' && next_word))) continue;
      tokens.push_back({p, e, n, e < text.size() && text[e] == ':' && next_word});
    }
  }
  std::sort(tokens.begin(), tokens.end(), [](const Token& a, const Token& b) { return a.begin < b.begin; });
  const auto separators = [](std::string_view s) {
    for (size_t i = 0; i < s.size();) {
      if (std::isspace(static_cast<unsigned char>(s[i])) || std::string_view(",|\"'`").find(s[i]) != std::string_view::npos) {
        ++i;
      } else if (s.substr(i, 2) == "\\n") {
        i += 2;
      } else if (s[i] == '\\') {
        ++i;
      } else if ((s.substr(i, 3) == "and" || s.substr(i, 2) == "or") && (i == 0 || !word_char(s[i - 1]))) {
        const size_t w = s.substr(i, 3) == "and" ? 3 : 2;
        if (i + w < s.size() && word_char(s[i + w])) return false;
        i += w;
      } else {
        return false;
      }
    }
    return true;
  };
  std::vector<List> out;
  for (size_t i = 0; i < tokens.size();) {
    if (tokens[i].spec) {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < tokens.size() && !tokens[j].spec &&
           separators(std::string_view(text).substr(tokens[j - 1].end, tokens[j].begin - tokens[j - 1].end)))
      ++j;
    std::vector<std::string> names;
    for (size_t k = i; k < j; ++k) names.push_back(tokens[k].name);
    const bool next_spec = j < tokens.size() && tokens[j].spec &&
                           separators(std::string_view(text).substr(tokens[j - 1].end, tokens[j].begin - tokens[j - 1].end));
    const bool prev_spec = i > 0 && tokens[i - 1].spec &&
                           separators(std::string_view(text).substr(tokens[i - 1].end, tokens[i].begin - tokens[i - 1].end));
    size_t after = tokens[j - 1].end;
    while (after < text.size() && (text[after] == ' ' || std::string_view(",|\"'`").find(text[after]) != std::string_view::npos))
      ++after;
    const std::string_view rest = std::string_view(text).substr(after, 5);
    const bool elided = rest.starts_with("...") || rest.starts_with("[...]") || rest.starts_with("\u2026");
    if (std::set<std::string>(names.begin(), names.end()).size() >= 3 && !elided && !next_spec && !prev_spec) {
      List l;
      l.line = 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(tokens[i].begin), '\n'));
      const size_t b = text.rfind('\n', tokens[i].begin);
      l.prefix = text.substr(b == std::string::npos ? 0 : b + 1, tokens[i].begin - (b == std::string::npos ? 0 : b + 1));
      l.names = std::move(names);
      out.push_back(std::move(l));
    }
    i = j;
  }
  return out;
}

TEST(ModelLists, TheScannerFindsListsAndLeavesTheRest) {
  const auto names = [](const std::string& t) {
    std::vector<std::vector<std::string>> v;
    for (const List& l : find_lists(t)) v.push_back(l.names);
    return v;
  };
  using V = std::vector<std::vector<std::string>>;
  EXPECT_EQ(names("model (lafortune | ward | ggx), lobes"), (V{{"lafortune", "ward", "ggx"}}));
  EXPECT_EQ(names("Literal[\"ward\", \"ashikhmin-shirley\",\n \"ggx\"]"), (V{{"ward", "ashikhmin-shirley", "ggx"}}));
  EXPECT_EQ(names("`ward`, `ggx` and `metal`; lambert"), (V{{"ward", "ggx", "metal"}}));
  EXPECT_EQ(names("ward, ggx, metal, ..."), V{});                                    // elided
  EXPECT_EQ(names("--models ward,ggx,metal,lafortune:3"), V{});                      // fit-db specs
  EXPECT_EQ(names("ward.h, ggx.h, metal.h; f/ward/ggx/metal"), V{});                 // files and paths
  EXPECT_EQ(names("ward, ggx"), V{});                                                // two are no list
  EXPECT_EQ(names("MODEL=ward ward | ggx | metal"), (V{{"ward", "ggx", "metal"}}));  // a default
  EXPECT_EQ(names("ward ordinary ggx, metal"), V{});                                 // a word between them
}

// Every list of models outside the registry is one of the sets, where it means one, or a declared
// choice; none is a hand copy that nothing checks.
class ModelListsCli : public Cli {};

TEST_F(ModelListsCli, EveryListOfModelsIsASetTheCodeMakesOrADeclaredChoice) {
  const auto sets = model_sets();
  for (const Checked& c : kChecked) ASSERT_TRUE(sets.count(c.set)) << c.set;
  // The sources: files, then the CLI's outputs.
  std::map<std::string, std::string> sources;
  const auto add_file = [&](const fs::path& p) { sources[fs::relative(p, kRoot).string()] = read_file(p); };
  add_file(kRoot / "README.md");
  const std::vector<std::pair<std::string, std::set<std::string>>> trees = {{"docs", {".md"}},
                                                                            {"python/aniso", {".py", ".pyi"}},
                                                                            {"python/tools", {".py"}},
                                                                            {"python/src", {".cpp", ".h"}},
                                                                            {"apps/aniso", {".cpp", ".h"}},
                                                                            {"web", {".js", ".html"}},
                                                                            {"include/aniso", {".h"}},
                                                                            {"src", {".h", ".cpp"}},
                                                                            {"examples", {".py", ".cpp", ".md"}}};
  for (const auto& [dir, exts] : trees)
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir))
      if (e.is_regular_file() && exts.count(e.path().extension().string())) add_file(e.path());
  ASSERT_GT(sources.size(), 100u);
  // argparse (fit-db's help) wraps at $COLUMNS: one line per option, so that a list starts on the
  // line of its option.
  setenv("COLUMNS", "1000", 1);
  std::vector<std::vector<std::string>> commands = {{"--help"}, {"models"}};
  const Result top = run({"--help"});
  ASSERT_EQ(top.code, 0) << top.err;
  bool in_subcommands = false;
  std::istringstream lines(top.out);
  for (std::string l; std::getline(lines, l);) {
    if (l.starts_with("Subcommands:")) in_subcommands = true;
    if (in_subcommands && l.starts_with("  ") && l.size() > 2 && l[2] != ' ')
      commands.push_back({l.substr(2, l.find(' ', 2) - 2), "--help"});
  }
  ASSERT_GT(commands.size(), 10u);
  for (const auto& args : commands) {
    const Result r = run(args);
    std::string name = "aniso";
    for (const std::string& a : args) name += " " + a;
    // fit-db's help is the Python module's: absent from a build without it.
    if (r.code != 0 && args[0] == "fit-db") continue;
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    sources[name] = r.out;
  }

  // The entry of a list: of its source, with its anchor before the list on its line, the nearest.
  const auto entry = [](const auto& table, const std::string& source, const List& l) {
    int best = -1;
    size_t at = 0;
    for (size_t i = 0; i < std::size(table); ++i) {
      const size_t p = source == table[i].source ? l.prefix.rfind(table[i].anchor) : std::string::npos;
      if (p != std::string::npos && (best < 0 || p >= at)) best = int(i), at = p;
    }
    return best;
  };
  std::set<int> checked_used, choices_used;
  for (const auto& [source, text] : sources)
    for (const List& l : find_lists(text)) {
      const std::string where = fmt::format("{}:{}: {}", source, l.line, fmt::join(l.names, " "));
      if (const int i = entry(kChecked, source, l); i >= 0) {
        checked_used.insert(i);
        const std::vector<std::string>& want = sets.at(kChecked[i].set);
        EXPECT_EQ(std::set<std::string>(l.names.begin(), l.names.end()), std::set<std::string>(want.begin(), want.end()))
            << where << ": the " << kChecked[i].set << " are " << fmt::format("{}", fmt::join(want, " "));
        EXPECT_EQ(l.names.size(), want.size()) << where << ": a name twice";
      } else if (const int c = entry(kChoices, source, l); c >= 0) {
        choices_used.insert(c);
      } else {
        ADD_FAILURE() << where
                      << ": a list of models by hand. Make it from the registry (kModels), kFittable (fittable_models(), "
                         "aniso.fittable_models()) or io/enum_names.h, or add it to kChecked with the set it means (or to "
                         "kChoices with why it is not one)";
      }
    }
  // No entry outlives its list (a CLI output that was not read, fit-db's without Python, excepted).
  for (size_t i = 0; i < std::size(kChecked); ++i)
    if (sources.count(kChecked[i].source)) {
      EXPECT_TRUE(checked_used.count(int(i))) << kChecked[i].source << ": no list at \"" << kChecked[i].anchor << "\"";
    }
  for (size_t i = 0; i < std::size(kChoices); ++i)
    EXPECT_TRUE(choices_used.count(int(i))) << kChoices[i].source << ": no list at \"" << kChoices[i].anchor << "\"";
}

// The first backquoted name of column `column` of each row of the markdown table under the line
// that starts with `header`.
std::vector<std::string> table_column(const std::string& text, const std::string& header, size_t column) {
  std::vector<std::string> out;
  std::istringstream in(text);
  bool inside = false;
  for (std::string l; std::getline(in, l);) {
    if (!inside) {
      inside = l.starts_with(header);
      continue;
    }
    if (!l.starts_with("|")) break;
    if (l.starts_with("|---")) continue;
    std::vector<std::string> cells;
    for (size_t b = 1, e; (e = l.find(" |", b)) != std::string::npos; b = e + 2) cells.push_back(l.substr(b, e - b));
    if (column >= cells.size()) continue;
    const size_t q = cells[column].find('`'), r = cells[column].find('`', q + 1);
    if (q != std::string::npos && r != std::string::npos) out.push_back(cells[column].substr(q + 1, r - q - 1));
  }
  return out;
}

TEST(ModelLists, TheTablesOfModelsAreTheRegistrysAndTheFittersRows) {
  const auto sets = model_sets();
  EXPECT_EQ(table_column(read_file(kRoot / "README.md"), "| model | JSON `model` | page |", 1), sets.at("models"))
      << "README.md, \"Models\": one row per registry row, in its order";
  EXPECT_EQ(table_column(read_file(kRoot / "docs" / "fitting.md"), "| `--model` | fitted | fixed |", 0), sets.at("fittable"))
      << "docs/fitting.md, \"Models and their parameters\": one row per kFittable row, in its order";
}

}  // namespace
}  // namespace aniso
