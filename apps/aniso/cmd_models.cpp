// apps/aniso/cmd_models.cpp: `aniso models`, the models and their parameter tables
// (the model files, src/models/<member>.h) as text, or with --markdown as docs/models/*.md quote them (docs/cli.md).
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/io/materials.h"
#include "aniso/io/params.h"
#include "commands.h"
#include "io/json_read.h"
#include "io/names.h"

namespace aniso {
namespace {

int cmd_models(bool markdown, const std::string& only, bool only_given) {
  if (only_given && !find_model_spec(only)) {
    std::string names;
    std::vector<std::string> all;
    for (const ModelSpec* m : model_specs()) {
      names += fmt::format(" {}", m->name);
      all.emplace_back(m->name);
    }
    const std::string near = nearest_names(only, all);
    throw InputError(fmt::format("--model: unknown model \"{}\"{}; expected one of{}", text_escape(only),
                                 near.empty() ? "" : fmt::format(" (did you mean {}?)", near), names));
  }
  std::string out;
  if (markdown) {
    for (const ModelSpec* m : model_specs())
      if (!only_given || m->name == only) out += fmt::format("{}\n", markdown_table(*m));
    write_stdout(out);
    return 0;
  }
  // Nested tables (Lafortune lobes, metal lobes, the directional-diffuse lobe) follow their key,
  // indented, as in the markdown tables.
  const auto key = [&out](const ParamSpec& p, int depth) {
    out +=
        fmt::format("{:{}}  {:<20} {:<45} default {:<12} {}\n", "", 4 * depth, p.name, describe_range(p), default_text(p), p.doc);
  };
  const auto nested = [&out](const ParamSpec& p, const ModelSpec& sub, int depth) {
    out += fmt::format("{:{}}    keys of {} ({}):\n", "", 4 * depth,
                       p.kind == ParamKind::TaggedObject ? fmt::format("\"{}\": {{\"model\": \"{}\"}}", p.name, sub.name)
                                                         : fmt::format("\"{}\"", p.name),
                       sub.title);
  };
  for (const ModelSpec* m : model_specs()) {
    if (only_given && m->name != only) continue;
    out += fmt::format("{} ({}) -- {}\n", m->name, m->title, m->citation);
    walk_params(*m, key, nested);
  }
  write_stdout(out);
  return 0;
}

}  // namespace

void add_models_command(CLI::App& app) {
  struct Args {
    bool markdown = false;
    std::string only_model;
  };
  auto a = std::make_shared<Args>();
  auto* models = app.add_subcommand("models", "list the models and their parameter tables");
  models->add_flag("--markdown", a->markdown, "print the tables as markdown (as docs/models/*.md quote them)");
  auto* model_opt = models->add_option("--model", a->only_model, "only this model");
  models->callback(
      [a, model_opt] { run_command([&] { return cmd_models(a->markdown, a->only_model, model_opt->count() > 0); }); });
}

}  // namespace aniso
