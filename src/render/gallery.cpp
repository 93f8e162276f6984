// render/gallery.cpp: the embedded default gallery and the material preview scene.
#include "aniso/render/gallery.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "aniso/image/canvas.h"

namespace aniso::render {
namespace {

// The default gallery: what the lecture is about, at a glance. Every cell is one object under the
// same studio lighting: a dim grey gradient environment plus a large warm key light (a sphere light
// up and to the left) and a small cool rim light behind, so that anisotropic highlights read as
// streaks. Read by parse_scene() like any user file.
constexpr const char* kGalleryJson = R"json({
  "columns": 4,
  "common": {
    "camera": {"position": [0, 0.35, 4.3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 30},
    "film": {"width": 256, "height": 256, "spp": 48},
    "integrator": {"max_depth": 6, "strategy": "mis"},
    "environment": {"type": "sky", "zenith": [0.16, 0.17, 0.19], "horizon": [0.30, 0.30, 0.31],
                    "ground": [0.05, 0.05, 0.05], "resolution": 256},
    "lights": [
      {"type": "sphere", "center": [-3.2, 4.0, 4.5], "radius": 0.9, "radiance": [52, 48, 42]},
      {"type": "sphere", "center": [3.5, 1.5, -3.5], "radius": 0.5, "radiance": [30, 34, 40]}
    ]
  },
  "cells": [
    {"label": "Ward, isotropic", "detail": "α = 0.12",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1,
                  "material": {"model": "ward", "kd": [0.05, 0.07, 0.12], "ks": 0.35,
                               "alpha_x": 0.12, "alpha_y": 0.12, "normalization": "balanced"}}]},
    {"label": "Ward, anisotropic", "detail": "αx = 0.05, αy = 0.35",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1,
                  "material": {"model": "ward", "kd": [0.05, 0.07, 0.12], "ks": 0.35,
                               "alpha_x": 0.05, "alpha_y": 0.35, "normalization": "balanced"}}]},
    {"label": "Ward, tangent rotated", "detail": "same material, angle_deg = 45",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "tangent": {"angle_deg": 45},
                  "material": {"model": "ward", "kd": [0.05, 0.07, 0.12], "ks": 0.35,
                               "alpha_x": 0.05, "alpha_y": 0.35, "normalization": "balanced"}}]},
    {"label": "Ashikhmin-Shirley", "detail": "nu = 10, nv = 400",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1,
                  "material": {"model": "ashikhmin-shirley", "rd": [0.35, 0.08, 0.06], "rs": 0.12,
                               "n_u": 10, "n_v": 400}}]},
    {"label": "Matte steel (Lafortune)", "detail": "the lecture's 3-lobe fit",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "matte-steel"}]},
    {"label": "Brushed gold", "detail": "measured n, k; Ward lobe + dir. diffuse",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "brushed-gold"}]},
    {"label": "Copper, directional diffuse", "detail": "measured n, k; AS lobe + dir. diffuse",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1,
                  "material": {"model": "metal", "metal": "copper",
                               "lobe": {"model": "ashikhmin-shirley", "n_u": 30, "n_v": 600},
                               "directional_diffuse": {"albedo": 0.35, "n": 3}}}]},
    {"label": "Anisotropic GGX", "detail": "αx = 0.05, αy = 0.4 (comparison)",
     "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1,
                  "material": {"model": "ggx", "kd": [0.03, 0.05, 0.03], "f0": [0.6, 0.75, 0.6],
                               "alpha_x": 0.05, "alpha_y": 0.4}}]},
    {"label": "Disc, concentric tangents", "detail": "lathe-turned aluminium",
     "camera": {"position": [0, 2.6, 3.4], "look_at": [0, -0.15, 0], "up": [0, 1, 0], "fov_deg": 30},
     "objects": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1.02,
                  "tangent": {"field": "concentric"}, "material": "brushed-aluminium"}]},
    {"label": "Disc, radial tangents", "detail": "brushed outwards from the centre",
     "camera": {"position": [0, 2.6, 3.4], "look_at": [0, -0.15, 0], "up": [0, 1, 0], "fov_deg": 30},
     "objects": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1.02,
                  "tangent": {"field": "radial"}, "material": "brushed-aluminium"}]},
    {"label": "Disc, swirl tangents", "detail": "spiral at 45° between the two",
     "camera": {"position": [0, 2.6, 3.4], "look_at": [0, -0.15, 0], "up": [0, 1, 0], "fov_deg": 30},
     "objects": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1.02,
                  "tangent": {"field": "swirl", "swirl_deg": 45}, "material": "brushed-silver"}]},
    {"label": "Torus, mesh tangents", "detail": "brushed along the ring (dp/du)",
     "camera": {"position": [0, 2.45, 4.05], "look_at": [0, -0.1, 0], "up": [0, 1, 0], "fov_deg": 30},
     "objects": [{"shape": "torus", "center": [0, 0, 0], "major_radius": 0.9, "minor_radius": 0.34,
                  "material": "brushed-copper"}]}
  ]
})json";

// The smallest caption size: below it DejaVu Sans's letters run together.
constexpr float kMinCaptionPx = 7.0f;

}  // namespace

const nlohmann::json& gallery_document() {
  static const nlohmann::json doc = nlohmann::json::parse(kGalleryJson);
  return doc;
}

nlohmann::json gallery_cell_scene(size_t cell) {
  const nlohmann::json& doc = gallery_document();
  nlohmann::json scene = doc.at("common");
  for (const auto& [k, v] : doc.at("cells").at(cell).items())
    if (k != "label" && k != "detail") scene[k] = v;
  scene["name"] = doc.at("cells").at(cell).at("label");
  return scene;
}

GalleryLayout gallery_layout(const GalleryOptions& opt) {
  const nlohmann::json& doc = gallery_document();
  GalleryLayout l;
  l.cells = int(doc.at("cells").size());
  l.columns = doc.at("columns").get<int>();
  l.rows = (l.cells + l.columns - 1) / l.columns;
  l.margin = std::max(4, opt.width / 128);
  l.cell_width = std::max(16, (opt.width - l.margin * (l.columns + 1)) / l.columns);
  // Captions scale with the cell, and shrink further where the widest would overrun its cell (a
  // narrow figure: --width 256), down to kMinCaptionPx; a caption still too wide is cut short
  // (fit_caption). The text width is proportional to the pixel height up to rounding, hence the
  // measurement at a large size.
  constexpr float kMeasurePx = 100.0f;
  float widest_label = 0.0f, widest_detail = 0.0f;  // at kMeasurePx
  for (const auto& cell : doc.at("cells")) {
    widest_label = std::max(widest_label, float(text_width(cell.at("label").get<std::string>(), kMeasurePx)));
    widest_detail = std::max(widest_detail, float(text_width(cell.at("detail").get<std::string>(), kMeasurePx)));
  }
  const float room = float(l.cell_width - 4);  // the caption starts 2 px in and keeps 2 px clear
  // 0.98: the width scales with the size only up to the rounding of advances and the final ceil.
  const float fit_px = std::min(room / widest_label, room / (0.8f * widest_detail)) * kMeasurePx * 0.98f;
  l.label_px = std::max(kMinCaptionPx, std::min(float(l.cell_width) * 0.07f, fit_px));
  l.detail_px = std::max(kMinCaptionPx, l.label_px * 0.8f);
  l.strip = int(l.label_px * 1.35f + l.detail_px * 1.35f) + l.margin;
  l.cell_height = l.cell_width;
  if (opt.height > 0) l.cell_height = std::max(16, (opt.height - l.margin * (l.rows + 1)) / l.rows - l.strip);
  l.figure_height = opt.height > 0 ? opt.height : l.margin + l.rows * (l.cell_height + l.strip + l.margin);
  return l;
}

std::string fit_caption(const std::string& text, float px, int room) {
  if (text_width(text, px) <= room) return text;
  const std::string ellipsis = "\u2026";
  size_t end = text.size();
  while (end > 0) {
    --end;
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;  // to the character's lead byte
    std::string cut = text.substr(0, end);
    while (!cut.empty() && cut.back() == ' ') cut.pop_back();  // no space before the ellipsis
    cut += ellipsis;
    if (text_width(cut, px) <= room) return cut;
  }
  return text_width(ellipsis, px) <= room ? ellipsis : std::string();
}

GalleryResult render_gallery(const GalleryOptions& opt) {
  const nlohmann::json& doc = gallery_document();
  const GalleryLayout layout = gallery_layout(opt);
  const int cells = layout.cells, columns = layout.columns, margin = layout.margin, strip = layout.strip;
  const int cell_w = layout.cell_width, cell_h = layout.cell_height;
  const float label_px = layout.label_px, detail_px = layout.detail_px;
  GalleryResult res;
  res.cells = cells;
  res.cell_width = cell_w;
  res.cell_height = cell_h;
  res.image = DisplayImage(opt.width, layout.figure_height, 255);  // white page, like a paper's figure

  std::vector<Scene> scenes;
  for (int c = 0; c < cells; ++c) {
    nlohmann::json sj = gallery_cell_scene(size_t(c));
    sj["film"]["width"] = cell_w;
    sj["film"]["height"] = cell_h;
    if (opt.spp > 0) sj["film"]["spp"] = opt.spp;
    if (!opt.sampler.empty()) sj["integrator"]["sampler"] = opt.sampler;
    scenes.push_back(parse_scene(sj, fmt::format("embedded gallery, cell {}", c), ""));
  }
  const auto add_stats = [&](const RenderStats& st) {
    res.stats.seconds += st.seconds;
    res.stats.paths += st.paths;
    res.stats.rays += st.rays;
    res.stats.nonfinite += st.nonfinite;
  };
  const auto draw_cell = [&](int c, const Image& img) {
    const int col = c % columns, row = c / columns;
    const int x = margin + col * (cell_w + margin), y = margin + row * (cell_h + strip + margin);
    blit(res.image, tonemap(img, opt.tonemap), x, y);
    const auto& cell = doc.at("cells").at(size_t(c));
    const int room = cell_w - 4;
    draw_text(res.image, x + 2, y + cell_h + int(label_px * 0.25f),
              fit_caption(cell.at("label").get<std::string>(), label_px, room), label_px, glm::u8vec3(20, 20, 20));
    draw_text(res.image, x + 2, y + cell_h + int(label_px * 1.45f),
              fit_caption(cell.at("detail").get<std::string>(), detail_px, room), detail_px, glm::u8vec3(90, 90, 90));
  };

  // Ctrl-C (RenderOptions::cancel) keeps the single image's promise for the whole figure (docs/
  // cli.md: the finished passes are written, nothing before the first complete pass): a first
  // round renders one sample per pixel of every cell, then each cell is rendered in full; an
  // interrupted figure shows each cell at the most samples it finished (at least that one). The
  // full render repeats the first round's sample (same seed and sample index): 1 / spp of the time.
  std::vector<Image> first(scenes.size());
  for (int c = 0; c < cells; ++c) {
    RenderOptions ro = opt.render;
    ro.spp = 1;
    ro.progress = nullptr;
    RenderStats st;
    first[size_t(c)] = render(scenes[size_t(c)], ro, &st);
    add_stats(st);
    if (st.cancelled || st.spp_done == 0) {  // no whole figure yet: nothing is written
      res.stats.cancelled = true;
      res.stats.spp_done = 0;
      return res;
    }
  }
  res.stats.spp_done = std::numeric_limits<int>::max();  // the fewest samples of any cell, below
  for (int c = 0; c < cells; ++c) {
    const Scene& scene = scenes[size_t(c)];
    if (res.stats.cancelled || scene.film.spp <= 1) {  // interrupted earlier, or the first round was all
      draw_cell(c, first[size_t(c)]);
      res.stats.spp_done = std::min(res.stats.spp_done, 1);
      continue;
    }
    RenderOptions ro = opt.render;
    if (opt.render.progress) ro.progress = [&, c](double f) { opt.render.progress((double(c) + f) / double(cells)); };
    RenderStats st;
    const Image img = render(scene, ro, &st);
    add_stats(st);
    const bool whole = st.spp_done > 0;  // else this cell keeps its first round's sample
    draw_cell(c, whole ? img : first[size_t(c)]);
    res.stats.spp_done = std::min(res.stats.spp_done, whole ? st.spp_done : 1);
    res.stats.cancelled = res.stats.cancelled || st.cancelled;
  }
  return res;
}

nlohmann::json preview_scene(const nlohmann::json& material) {
  const nlohmann::json& common = gallery_document().at("common");
  nlohmann::json s = common;
  // The camera looks down by 21 degrees, so that the film's top edge (15 degrees above the axis)
  // stays 6 degrees below the sky's horizon, whose band (0.3 against the ground's 0.05) would
  // otherwise be a bright line along the top rows. The gallery's rim light, at y = 1.5, would sit
  // inside this wider 16:9 frame, its disc cut by the top edge at the top right: here it is at
  // y = 3, still behind the objects, its disc 0.6 of the half-height above the frame.
  s["camera"] = {{"position", {0.0, 2.2, 6.0}}, {"look_at", {0.0, -0.1, 0.0}}, {"up", {0, 1, 0}}, {"fov_deg", 30}};
  s["lights"][1]["center"] = {3.5, 3.0, -3.5};
  s["film"] = {{"width", 640}, {"height", 360}, {"spp", 64}};
  s["objects"] =
      nlohmann::json::array({{{"shape", "sphere"}, {"center", {-1.25, 0.0, 0.0}}, {"radius", 1.0}, {"material", material}},
                             {{"shape", "torus"},
                              {"center", {1.35, -0.25, 0.0}},
                              {"major_radius", 0.95},
                              {"minor_radius", 0.36},
                              {"rotate_deg", {25, 0, 0}},
                              {"material", material}}});
  s["name"] = "material preview";
  return s;
}

}  // namespace aniso::render
