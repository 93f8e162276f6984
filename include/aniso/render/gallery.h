// aniso/render/gallery.h: the built-in scenes: the default gallery (`aniso render` with no arguments)
// and the material preview (`aniso render --material M`). Both are ordinary scene documents
// (docs/scenes.md), compiled into the binary and read by the same reader as a user's file.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "aniso/image/tonemap.h"
#include "aniso/render/integrator.h"

namespace aniso::render {

// The gallery document: {"common": {...scene keys...}, "columns": C, "cells": [{"label", "detail",
// ...scene keys...}]}; each cell's scene is `common` with the cell's keys laid over it.
const nlohmann::json& gallery_document();
nlohmann::json gallery_cell_scene(size_t cell);

struct GalleryOptions {
  int width = 1024;      // the whole figure; cells are laid out in gallery_document()'s columns
  int height = 0;        // 0: from the width (square cells plus label strips)
  int spp = 0;           // 0: the document's film.spp
  std::string sampler;   // empty: the document's integrator.sampler; else "sobol" or "independent"
  RenderOptions render;  // threads, seed, cancel, progress (fraction of the whole gallery)
  ToneMapOptions tonemap;
};

struct GalleryResult {
  DisplayImage image;
  // Summed over cells; spp_done: the fewest samples per pixel of any cell in the figure (0: Ctrl-C
  // came before every cell had one sample: no whole figure, nothing to write).
  RenderStats stats;
  int cells = 0, cell_width = 0, cell_height = 0;
};

// Where render_gallery puts the cells: a margin around the figure and between cells; under each
// cell a strip with the label (one line) and the detail line (smaller). Sizes scale with the width.
struct GalleryLayout {
  int cells = 0, columns = 0, rows = 0;
  int margin = 0, cell_width = 0, cell_height = 0, strip = 0, figure_height = 0;
  float label_px = 0.0f, detail_px = 0.0f;
};
GalleryLayout gallery_layout(const GalleryOptions& opt);
// A caption as render_gallery draws it in `room` pixels at `px`: the text, or, where it is wider,
// the text cut at a UTF-8 character boundary and ended with an ellipsis (empty where not even the
// ellipsis fits).
std::string fit_caption(const std::string& text, float px, int room);

GalleryResult render_gallery(const GalleryOptions& opt);

// The preview scene for one material: a sphere and a torus brushed along its circle, under the
// gallery's lighting. `material` is a preset name, a file name or a material object.
nlohmann::json preview_scene(const nlohmann::json& material);

}  // namespace aniso::render
