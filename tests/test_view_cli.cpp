// tests/test_view_cli.cpp: `aniso view` in a window, under Xvfb (Debian's xvfb: xvfb-run starts a
// virtual X server, Mesa's llvmpipe gives GLX and OpenGL 3.3 core). Each test runs the explorer's
// screenshot command and reads the PNG back: the lit sphere where the camera puts it, a slider
// changed from the command line changing the highlight as the parameter says, bad files loaded by
// the script actions shown as errors with the last good state kept. Without xvfb-run or GLX the
// tests are skipped with the reason.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <unistd.h>

#include "aniso/image/image_io.h"
#include "aniso/image/tonemap.h"
#include "aniso/io/materials.h"
#include "aniso/rgl/rgl_export.h"
#include "aniso/rgl/tensor.h"
#include "cli_fixture.h"
#include "io/json_read.h"

namespace aniso {
namespace {

// The window layout (apps/aniso/view_app.cpp): the control panel is 340 pixels wide; with one view
// open the view fills the rest, its picture below the ImGui title bar (19 pixels: a 13-pixel font
// and 3 pixels of frame padding above and below) and a 2-pixel window padding.
constexpr int kPanel = 340, kTitle = 19, kPad = 2;
// The background the views draw where no surface is (kBackground in view_app.cpp: display values,
// sRGB-encoded), as read_image() decodes it to linear.
const glm::vec3 kBackgroundLinear(render::srgb_decode(0.12f), render::srgb_decode(0.12f), render::srgb_decode(0.13f));

class ViewCli : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run is not installed (Debian's xvfb)";
  }

  // Where xvfb-run -a starts looking for a free display: spread by process, so that tests run in
  // parallel (ctest -j) rarely race for the same number (xvfb-run checks the lock file, then starts
  // Xvfb: two runs starting from the same number can both pick it, and one fails).
  static int first_display() {
    static int calls = 0;
    return 100 + int((unsigned(::getpid()) * 37u + unsigned(calls++) * 7u) % 3000u);
  }

  // `xvfb-run -a aniso view ARGS`; skips the test when no GL 3.3 window can be opened there.
  // stdout goes to a file read back into Result::out, or to `stdout_path` (such as /dev/full).
  Result view(const std::vector<std::string>& args, const std::string& stdout_path = "") {
    std::string cmd = "cd ";
    // In the sanitizer build the window process runs without LeakSanitizer (ASan's other checks
    // stay on): GLFW unloads Mesa's GLX driver at exit (dlclose), so the driver's and the X
    // libraries' exit-time allocations cannot be named in tests/lsan.supp. The explorer's own
    // logic runs under LeakSanitizer in tests/test_view.cpp. Release builds ignore the variable.
    cmd.append(shell_quote(dir_.string()))
        .append(" && ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" xvfb-run -a -n ")
        .append(std::to_string(first_display()))
        .append(" -s '-screen 0 1600x1000x24 -noreset' ");
    cmd.append(shell_quote(ANISO_CLI)).append(" view");
    for (const std::string& a : args) cmd.append(" ").append(shell_quote(a));
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    cmd.append(" > ")
        .append(shell_quote(stdout_path.empty() ? out.string() : stdout_path))
        .append(" 2> ")
        .append(shell_quote(err.string()))
        .append(" < /dev/null");
    Result r;
    // `-noreset`: without it Xvfb resets when its last client (aniso) disconnects and, started with
    // SIGUSR1 ignored, signals its parent again once reset (the X server's ResetWellKnownSockets ->
    // NotifyParentProcess); xvfb-run (a dash script) traps SIGUSR1, and a trapped signal arriving
    // while its EXIT trap runs `if ! rm -r TMPDIR` makes dash take the successful rm as failed: exit 5,
    // "problem while cleaning up temporary directory" (reproduced here: with a 1-s pause in that trap,
    // the second SIGUSR1 arrives without -noreset and never with it). Xvfb's other failures still
    // replace aniso's exit status, so such a run says nothing about aniso and is run once more: that
    // exit 5 and exit 1 with "Xvfb failed to start" (no server came up on a free display in 10 tries).
    for (int attempt = 0; attempt < 2; ++attempt) {
      const int status = std::system(cmd.c_str());
      r.code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      r.out = read_file(out);
      r.err = read_file(err);
      const bool xvfb_failed =
          (r.code == 5 && contains(r.err, "xvfb-run: error: problem while cleaning up temporary directory")) ||
          (r.code == 1 && contains(r.err, "xvfb-run: error: Xvfb failed to start"));
      if (!xvfb_failed) break;
    }
    if (contains(r.err, "cannot open a window")) skip_reason_ = r.err;
    return r;
  }

  render::Image shot(const std::string& name) { return render::read_image((dir_ / name).string(), "screenshot"); }
  std::string skip_reason_;
};

#define VIEW_OR_SKIP(r)                                                          \
  do {                                                                           \
    if (!skip_reason_.empty()) GTEST_SKIP() << "no GL window: " << skip_reason_; \
  } while (0)

float lum(const RGB& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
// Within two 8-bit steps of the background.
bool is_background(const RGB& c) { return glm::length(c - kBackgroundLinear) < 0.003f; }

// The radiance a display value came from: the inverse of the views' tone curve at exposure 0
// (view_gl.cpp: Narkowicz 2015's ACES fit y = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), after
// which read_image() has undone the sRGB encoding): the positive root of
// (2.51 - 2.43 y) x^2 + (0.03 - 0.59 y) x - 0.14 y = 0.
float radiance_of(float y) {
  const double a = 2.51 - 2.43 * y, b = 0.03 - 0.59 * y, c = -0.14 * y;
  return float((-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a));
}

// The disc of non-background pixels in the view's picture: its bounding box.
struct Box {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
Box surface_box(const render::Image& img, int x_begin, int y_begin, int x_end, int y_end) {
  Box b;
  for (int y = y_begin; y < y_end; ++y)
    for (int x = x_begin; x < x_end; ++x)
      if (!is_background(img.at(x, y)))
        b.x0 = std::min(b.x0, x), b.y0 = std::min(b.y0, y), b.x1 = std::max(b.x1, x), b.y1 = std::max(b.y1, y);
  return b;
}

// The picture shows the lit sphere where the orbit camera puts it: a disc centred in the view,
// of the radius the pinhole projection gives, lit inside, background outside; the script actions
// write the material, its GLSL and its .brdf file.
TEST_F(ViewCli, ScreenshotShowsTheLitSphere) {
  const Result r = view({"--material", R"({"model": "ward", "kd": 0.5, "ks": 0.05, "alpha": 0.2})", "--views", "sphere", "--size",
                         "640x480", "--frames", "3", "--light", "0", "--screenshot", "s.png", "--save-material", "saved.json",
                         "--export-glsl", "m.glsl", "--export-brdf", "m.brdf"});
  VIEW_OR_SKIP(r);
  ASSERT_EQ(r.code, 0) << r.err;
  const render::Image img = shot("s.png");
  ASSERT_EQ(img.width, 640);
  ASSERT_EQ(img.height, 480);
  const int vx0 = kPanel + kPad, vy0 = kTitle + kPad, vw = 640 - kPanel - 2 * kPad, vh = 480 - kTitle - 2 * kPad;
  const Box b = surface_box(img, vx0 + 2, vy0 + 2, vx0 + vw - 2, vy0 + vh - 2);
  ASSERT_GE(b.x1, 0) << "no surface in the view";
  const double cx = 0.5 * (b.x0 + b.x1), cy = 0.5 * (b.y0 + b.y1);
  EXPECT_NEAR(cx, vx0 + 0.5 * vw, 3.0);
  EXPECT_NEAR(cy, vy0 + 0.5 * vh, 3.0);
  // A portrait view keeps the horizontal field of view of 30 degrees at distance 4.2: the
  // silhouette's radius on the image plane is tan(asin(1 / 4.2)) over tan(15 degrees) of half the width.
  const double radius = 0.5 * vw * std::tan(std::asin(1.0 / 4.2)) / std::tan(15.0 * kPi<double> / 180.0);
  EXPECT_NEAR(0.5 * (b.x1 - b.x0 + 1), radius, 0.04 * radius);
  EXPECT_NEAR(0.5 * (b.y1 - b.y0 + 1), radius, 0.04 * radius);
  // Lit inside (the light is behind the camera: everything the camera sees is lit, brightest at the
  // centre), background outside the disc.
  const float centre = lum(img.at(int(cx), int(cy)));
  EXPECT_GT(centre, 0.2f);
  for (double f : {0.3, 0.6, 0.85})
    for (int s : {-1, 1}) {
      EXPECT_GT(lum(img.at(int(cx + s * f * radius), int(cy))), 0.02f) << "inside at " << f;
      EXPECT_GT(lum(img.at(int(cx), int(cy + s * f * radius))), 0.02f) << "inside at " << f;
    }
  for (double f : {1.1, 1.3})
    for (int s : {-1, 1}) {
      const int y = int(cy + s * f * radius);
      if (y > vy0 && y < vy0 + vh) {
        EXPECT_TRUE(is_background(img.at(int(cx), y))) << "outside at " << f;
      }
    }
  // The script actions: the material as edited, its exports, each said on stdout as `aniso render`
  // says what it wrote (docs/cli.md, "Output streams"); the screenshot too.
  EXPECT_TRUE(contains(r.out, "wrote saved.json (material A as JSON)\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "wrote m.glsl (material A as GLSL)\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "wrote m.brdf (material A as a BRDF Explorer .brdf file)\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "wrote s.png (640x480 screenshot)\n")) << r.out;
  const MaterialDesc saved = parse_material(read_json_file((dir_ / "saved.json").string()), "saved.json");
  EXPECT_EQ(saved.model, "ward");
  EXPECT_DOUBLE_EQ(saved.params.scalar("alpha_x"), 0.2);
  EXPECT_TRUE(contains(read_file(dir_ / "m.glsl"), "aniso_f"));
  EXPECT_TRUE(contains(read_file(dir_ / "m.brdf"), "::begin shader"));
}

// The highlight's peak radiance (green channel, tone curve undone) and its width along a row and a
// column of the picture through the peak (pixels above half the peak).
struct Highlight {
  float peak = 0.0f;
  int width_x = 0, width_y = 0;
};
Highlight highlight(const render::Image& img) {
  Highlight h;
  int px = 0, py = 0;
  for (int y = kTitle + kPad; y < img.height; ++y)
    for (int x = kPanel + kPad; x < img.width; ++x)
      if (radiance_of(img.at(x, y).y) > h.peak) h.peak = radiance_of(img.at(x, y).y), px = x, py = y;
  for (int x = kPanel; x < img.width; ++x) h.width_x += radiance_of(img.at(x, py).y) > 0.5f * h.peak;
  for (int y = 0; y < img.height; ++y) h.width_y += radiance_of(img.at(px, y).y) > 0.5f * h.peak;
  return h;
}

// --set alpha_x=0.05 (from 0.2) narrows the highlight along the tangent, which at the front of the
// sphere is the picture's x axis, and leaves it as wide along the bitangent (y); the peak gets
// brighter (Ward's peak is ks / (4 pi alpha_x alpha_y): 4 times the radiance here).
TEST_F(ViewCli, SmallerAlphaXGivesANarrowerBrighterHighlight) {
  const std::string m = R"({"model": "ward", "kd": 0, "ks": 0.05, "alpha_x": 0.2, "alpha_y": 0.2})";
  const std::vector<std::string> common = {"--material", m,          "--views", "sphere",  "--size",
                                           "640x480",    "--frames", "2",       "--light", "0"};
  std::vector<std::string> wide = common, narrow = common;
  wide.insert(wide.end(), {"--screenshot", "wide.png"});
  narrow.insert(narrow.end(), {"--set", "alpha_x=0.05", "--screenshot", "narrow.png"});
  const Result rw = view(wide);
  VIEW_OR_SKIP(rw);
  ASSERT_EQ(rw.code, 0) << rw.err;
  const Result rn = view(narrow);
  ASSERT_EQ(rn.code, 0) << rn.err;
  const Highlight hw = highlight(shot("wide.png")), hn = highlight(shot("narrow.png"));
  // Ward's peak ks / (4 pi alpha_x alpha_y) grows 4 times; near the peak exp(-tan^2 theta_h (cos^2 phi
  // / alpha_x^2 + sin^2 phi / alpha_y^2)) falls to half at tan theta_h proportional to alpha along each
  // axis: the x width shrinks to a quarter, the y width stays (8-bit steps and pixel sampling: 25 %).
  EXPECT_NEAR(hn.peak / hw.peak, 4.0, 1.0) << "peak " << hn.peak << " vs " << hw.peak;
  EXPECT_NEAR(double(hn.width_x) / hw.width_x, 0.25, 0.08) << "x widths " << hn.width_x << " vs " << hw.width_x;
  EXPECT_NEAR(double(hn.width_y) / hw.width_y, 1.0, 0.25) << "y widths " << hn.width_y << " vs " << hw.width_y;
}

// A broken material file, a corrupt tangent map and a corrupt OBJ, loaded as the window's buttons
// load them: exit 0, each error on stderr and in the window (red text in the control panel), the
// last good state kept (the material as given, the sphere still drawn, nothing saved from the
// broken file).
TEST_F(ViewCli, BadFilesShowTheErrorAndKeepTheLastGoodState) {
  write("broken.json", R"({"model": "ward", "alpha_x": 0.1,)");
  write("corrupt.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR garbage", 25));
  write("corrupt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  const Result r = view({"--material",
                         R"({"model": "ward", "kd": 0.5, "ks": 0.05, "alpha": 0.2})",
                         "--views",
                         "sphere",
                         "--size",
                         "640x480",
                         "--frames",
                         "2",
                         "--light",
                         "0",
                         "--load-material",
                         (dir_ / "broken.json").string(),
                         "--load-tangent-map",
                         (dir_ / "corrupt.png").string(),
                         "--load-obj",
                         (dir_ / "corrupt.obj").string(),
                         "--save-material",
                         "saved.json",
                         "--screenshot",
                         "s.png"});
  VIEW_OR_SKIP(r);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "aniso view: error: load material")) << r.err;
  EXPECT_TRUE(contains(r.err, "broken.json")) << r.err;
  EXPECT_TRUE(contains(r.err, "load tangent map")) << r.err;
  EXPECT_TRUE(contains(r.err, "corrupt.png")) << r.err;
  EXPECT_TRUE(contains(r.err, "load OBJ")) << r.err;
  EXPECT_TRUE(contains(r.err, "corrupt.obj")) << r.err;
  const MaterialDesc saved = parse_material(read_json_file((dir_ / "saved.json").string()), "saved.json");
  EXPECT_DOUBLE_EQ(saved.params.color("kd").x, 0.5);  // the material given, not the broken one
  const render::Image img = shot("s.png");
  int red = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < kPanel; ++x) {
      const RGB c = img.at(x, y);
      red += c.x > 0.4f && c.y < 0.25f && c.z < 0.25f;
    }
  EXPECT_GT(red, 100) << "no error text in the window";
  const int cx = kPanel + kPad + (640 - kPanel - 2 * kPad) / 2, cy = kTitle + kPad + (480 - kTitle - 2 * kPad) / 2;
  EXPECT_GT(lum(img.at(cx, cy)), 0.2f) << "the sphere is not drawn";
}

// The A/B captions stay in their halves of the compare view: "A brushed-gold (edited)" is wider
// than half of this 296-pixel view and would run into "B gold": it is shortened before the split line.
// The stderr frame-time line is the window's figure: frames 3 to N - 1 (here the third alone).
TEST_F(ViewCli, CompareCaptionsStayInTheirHalves) {
  const Result r = view({"--material", "brushed-gold", "--set", "lobe.alpha_x=0.1", "--views", "compare", "--size", "640x480",
                         "--frames", "4", "--screenshot", "c.png"});
  VIEW_OR_SKIP(r);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "ms a frame")) << r.err;
  EXPECT_TRUE(contains(r.err, "(mean of 1 frame)")) << r.err;
  const render::Image img = shot("c.png");
  const int vx0 = kPanel + kPad, vw = 640 - kPanel - 2 * kPad, split = vx0 + vw / 2;
  // The captions' colours (kColA, kColB in view_app.cpp: 255, 170, 60 and 110, 190, 255), decoded to
  // linear: orange has red near 1 and little blue, blue the reverse; the caption rows are above the sphere.
  int a_left = 0, a_right = 0, b_left = 0, b_right = 0, a_last = 0;
  for (int y = kTitle + kPad; y < kTitle + kPad + 20; ++y)
    for (int x = vx0; x < vx0 + vw; ++x) {
      const RGB c = img.at(x, y);
      const bool orange = c.x > 0.5f && c.y > 0.12f && c.z<0.12f, blue = c.z> 0.5f && c.x < 0.3f;
      if (orange) (x < split ? a_left : a_right) += 1, a_last = std::max(a_last, x);
      if (blue) (x < split ? b_left : b_right) += 1;
    }
  EXPECT_GT(a_left, 30) << "no A caption";
  EXPECT_GT(b_right, 10) << "no B caption";
  EXPECT_EQ(a_right, 0) << "the A caption crosses the split line (its last pixel at " << a_last << ", the split at " << split
                        << ")";
  EXPECT_EQ(b_left, 0);
}

// A script action's "wrote" line to a stdout that cannot take it: exit 1 with the message every
// command gives (docs/cli.md, "Exit status"), the file itself written.
TEST_F(ViewCli, WroteLineToAFullStdoutExitsOne) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  const Result r = view({"--views", "polar", "--size", "640x480", "--frames", "1", "--save-material", "saved.json"}, "/dev/full");
  VIEW_OR_SKIP(r);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "aniso: error: stdout: write error: No space left on device")) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "saved.json"));
}

// Every view open at the default size: each view's area holds a picture (not one flat colour).
TEST_F(ViewCli, EveryViewDraws) {
  const Result r = view({"--frames", "2", "--preview-spp", "1", "--screenshot", "all.png"});
  VIEW_OR_SKIP(r);
  ASSERT_EQ(r.code, 0) << r.err;
  const render::Image img = shot("all.png");
  ASSERT_EQ(img.width, 1280);
  ASSERT_EQ(img.height, 720);
  // Seven views: four columns, two rows (view_app.cpp's grid).
  const int cw = (1280 - kPanel) / 4, rh = 720 / 2;
  for (int i = 0; i < 7; ++i) {
    const int x0 = kPanel + cw * (i % 4) + 4, y0 = rh * (i / 4) + kTitle + 4;
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (int y = y0; y < y0 + rh - kTitle - 8; y += 2)
      for (int x = x0; x < x0 + cw - 8; x += 2) {
        const double v = lum(img.at(x, y));
        sum += v, sum2 += v * v, ++n;
      }
    const double mean = sum / n, var = sum2 / n - mean * mean;
    EXPECT_GT(std::sqrt(std::max(var, 0.0)), 0.01) << "view " << i << " is flat";
  }
}

// Bad command-line input is exit 2 before any window opens (no display needed).
TEST_F(Cli, ViewCommandLineErrors) {
  expect_input_error(run({"view", "--set", "no_such_key=1", "--frames", "1"}), {"no_such_key"});
  expect_input_error(run({"view", "--set", "alpha_x=-3", "--material", "brushed-gold", "--frames", "1"}), {"alpha_x"});
  expect_input_error(run({"view", "--material", "no-such-preset", "--frames", "1"}), {"no-such-preset"});
  expect_input_error(run({"view", "--views", "sphere,bogus", "--frames", "1"}), {"bogus"});
  expect_input_error(run({"view", "--size", "10x10", "--frames", "1"}), {"--size"});
  expect_input_error(run({"view", "--screenshot", "x.png"}), {"--frames"});
  expect_input_error(run({"view", "--light", "nan", "--frames", "1"}), {"--light", "finite"});
  expect_input_error(run({"view", "--tangent-field", "spiral", "--frames", "1"}), {"--tangent-field"});
}

// A tensor file opens in the explorer (--material) and shows a lit sphere; its GLSL export writes
// the tables beside the shader (docs/glsl.md "Measured materials").
TEST_F(ViewCli, ATensorFileOpensAndExportsItsGlslWithTables) {
  rgl::ExportOptions o;
  o.spectral = false;
  o.colour = 16;
  o.theta_i = 8;
  o.ndf = 32;
  const std::vector<uint8_t> bytes =
      rgl::serialize_tensor(rgl::export_rgl(rgl::brdf_source(build_material<double>(parse_material(
                                                {{"model", "ggx"}, {"kd", 0.3}, {"f0", 0.04}, {"alpha", 0.2}}, "ggx"))),
                                            o));
  write("m.bsdf", std::string(bytes.begin(), bytes.end()));
  const Result r = view({"--material", "m.bsdf", "--views", "sphere", "--size", "640x480", "--frames", "2", "--light", "0",
                         "--screenshot", "s.png", "--export-glsl", "m.glsl"});
  VIEW_OR_SKIP(r);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "wrote m.glsl.tables (material A's tables for its GLSL)\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "wrote m.glsl (material A as GLSL)\n")) << r.out;
  EXPECT_EQ(std::filesystem::file_size(dir_ / "m.glsl.tables") % (4 * 4096), 0u);
  const render::Image img = shot("s.png");
  float peak = 0.0f;
  for (int y = 0; y < img.height; ++y)
    for (int x = kPanel; x < img.width; ++x) peak = std::max(peak, lum(img.at(x, y)));
  EXPECT_GT(peak, 0.2f) << "the lit sphere of the tensor file";
}

}  // namespace
}  // namespace aniso
