// aniso/io/params.h: the parameter tables. One table per model (name, kind, range, default, doc) is
// the single source of truth that the JSON reader validates against, that `aniso models` prints,
// that docs/models/*.md quote, and that the Python keywords, GLSL uniforms and viewer sliders are
// generated from. Each model's table is in its model file, src/models/<member>.h, each row bound
// to the kernel field it sets (docs/architecture.md, "Adding a model").
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/io/input_error.h"

namespace aniso {

enum class ParamKind {
  Scalar,  // a number in [min, max]
  Color,   // a number or an [r, g, b] array, each in [min, max]
  Bool,
  Choice,        // one of `choices`
  String,        // free text (for example a metal name, checked by the builder)
  Object,        // a nested object validated against `sub`
  List,          // an array of objects, each validated against `sub`
  TaggedObject,  // an object whose "model" key (one of `choices`) selects its table (`tagged`): the metal's lobe
};

struct ModelSpec;

// A rule across the keys of one table that their ranges cannot express. The reader applies a
// table's rules after its keys (read_params), and `aniso web-data` exports them with the table, so
// that the page's reader (web/validate.js) applies the same ones: one copy of each rule. A failure
// is an InputError naming `key`: "<where>: key \"<key>\": <message>".
struct ParamRule {
  enum class Kind {
    Exclusive,  // `key` is not given together with any of `keys`
    KeyOrAll,   // `key` or every one of `keys` is given; else the first missing of `keys` fails once one of
                // them is given, `key` when none is
    NonZero,    // some of `keys` is non-zero
    PeakBelow,  // per channel c: exponent[c] log10(max_k |keys_k[c]|) + log10(scale[c]) <= limit; `message` is
                // a template with {cmax:g}, {scale:g}, {n:g} and {channel}
  };
  Kind kind;
  std::string_view key;
  std::array<std::string_view, 3> keys = {};
  std::string_view message = {};
  std::string_view exponent = {}, scale = {};  // PeakBelow
  double limit = 0.0;                          // PeakBelow
};

struct ParamSpec {
  std::string_view name;
  ParamKind kind = ParamKind::Scalar;
  std::string_view doc;
  double min = 0.0;
  double max = 1.0;
  bool min_exclusive = false;  // the range is (min, max] instead of [min, max]
  // Default (Scalar, Color: all three; Bool: != 0). Ignored when required.
  double default_value = 0.0;
  bool required = false;
  std::span<const std::string_view> choices = {};  // Choice; choices[0] is the default
  std::span<const ModelSpec* const> tagged = {};   // TaggedObject: the table of each choice, in order
  const ModelSpec* sub = nullptr;                  // Object, List
  int max_items = 0;                               // List
  // Anisotropic pairs (alpha_x / alpha_y, n_u / n_v, cx / cy): the other half. Giving one half
  // without the other is an error naming the partner (docs/conventions.md, "Anisotropic pairs").
  std::string_view partner = {};
  // A shorthand key that sets both halves of a pair to its value ("alpha", "n", "cxy"); it may not
  // be given together with either half. Shorthands are input only: the kernels, the GLSL uniforms
  // and fitted output use the two halves.
  std::array<std::string_view, 2> sets = {};
};

// A model's table: its parts are spans of parameters, so that a lobe shared by two models (the
// Ward lobe of `ward` and of `metal`) is written once.
struct ModelSpec {
  std::string_view name;
  std::string_view title;
  std::string_view citation;
  std::span<const std::span<const ParamSpec>> parts;
  std::span<const ParamRule> rules = {};

  // Every parameter of every part, in order.
  std::vector<const ParamSpec*> params() const;
  const ParamSpec* find(std::string_view key) const;
};

// Values read from JSON and validated; defaults filled in for every optional key that has one.
struct ParamValues;
using ParamValue = std::variant<double, glm::dvec3, bool, std::string, std::shared_ptr<ParamValues>, std::vector<ParamValues>>;

struct ParamValues {
  std::string where;  // "material.json: lobe" etc., for errors raised after validation
  std::map<std::string, ParamValue, std::less<>> values;

  bool has(std::string_view key) const { return values.find(key) != values.end(); }
  double scalar(std::string_view key) const;
  glm::dvec3 color(std::string_view key) const;
  bool boolean(std::string_view key) const;
  const std::string& text(std::string_view key) const;
  const ParamValues& object(std::string_view key) const;
  const std::vector<ParamValues>& list(std::string_view key) const;
  [[noreturn]] void fail(std::string_view key, std::string_view what) const;
};

// All model tables, in the order `aniso models` lists them (the registry's). These and the three
// below are defined with the model files (src/models/models.cpp).
std::span<const ModelSpec* const> model_specs();
const ModelSpec* find_model_spec(std::string_view name);
// The registry row (aniso/brdf/registry.h) whose name is `name`.
enum class ModelKind : int;
std::optional<ModelKind> find_model_kind(std::string_view name);

// Sub-tables used inside models (lobes).
const ModelSpec& lafortune_lobe_spec();
const ModelSpec& metal_lobe_spec(std::string_view model);  // ward | ashikhmin-shirley | ggx
const ModelSpec& directional_diffuse_spec();

// The tables nested under a key: its `sub` (Object, List), or one metal lobe table per model it
// accepts (TaggedObject); none for a plain key.
std::vector<const ModelSpec*> nested_specs(const ParamSpec& p);

// Walks a table depth first, as `aniso models` and the Python module's help print it: key(p, depth)
// for each key in order, then for each table nested under it nested(p, sub, depth) and that
// table's keys at depth + 1.
void walk_params(const ModelSpec& spec, const std::function<void(const ParamSpec& p, int depth)>& key,
                 const std::function<void(const ParamSpec& p, const ModelSpec& sub, int depth)>& nested, int depth = 0);

std::string describe_range(const ParamSpec& p);
// "0.15", "\"vector\"", "required", "(shorthand)" or "none" (optional, no default).
std::string default_text(const ParamSpec& p);

// The parameter table of a model as markdown, with the tables of its nested objects (lobes) after
// it: what docs/models/<name>.md quote (a test keeps them equal).
std::string markdown_table(const ModelSpec& spec);

}  // namespace aniso
