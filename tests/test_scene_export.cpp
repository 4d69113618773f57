// Mitsuba 3 / pbrt-v4 exports: the XML parses (pugixml) with the expected elements; the pbrt
// files tokenize into well-formed directives with typed parameters; spectrum files carry
// wavelengths in nm with the metal's optical constants.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <pugixml.hpp>
#include <sstream>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/scene_export.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

std::string scratch_dir(const std::string& tag) {
  const auto d = fs::path(::testing::TempDir()) /
                 ("microbrdf_export_" + std::to_string(::getpid()) + "_" + tag);
  fs::remove_all(d);
  return d.string();
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

RoughConductor gold() {
  RoughConductor m;
  m.alpha_u = 0.12;
  m.alpha_v = 0.3;
  m.constants = metal("Au");
  m.notes.push_back("nearest GGX of an ellipsoid NDF: its skew -- tilt -- has no equivalent");
  return m;
}

// A pbrt-v4 scene-file tokenizer: quoted strings, [ ], numbers, bare words; '#' comments.
std::vector<std::string> tokenize(const std::string& text) {
  std::vector<std::string> t;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (c == '"') {
      const std::size_t e = text.find('"', i + 1);
      EXPECT_NE(e, std::string::npos) << "unterminated string";
      if (e == std::string::npos) return t;
      t.push_back(text.substr(i, e - i + 1));
      i = e + 1;
    } else if (c == '[' || c == ']') {
      t.push_back(std::string(1, c));
      ++i;
    } else {
      std::size_t e = i;
      while (e < text.size() && !std::isspace(static_cast<unsigned char>(text[e])) &&
             text[e] != '[' && text[e] != ']' && text[e] != '"')
        ++e;
      t.push_back(text.substr(i, e - i));
      i = e;
    }
  }
  return t;
}

bool is_number(const std::string& s) {
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size();
}

// Checks the grammar: Directive ["type"] ("type name" value | [values])*; returns the
// directives with their parameter names, e.g. {"Material", "\"conductor\"", "spectrum eta", ...}.
std::vector<std::vector<std::string>> parse_pbrt(const std::string& text) {
  static const std::vector<std::string> kDirectives = {
      "LookAt",      "Camera",         "Film",         "Sampler",  "Integrator", "WorldBegin",
      "LightSource", "AttributeBegin", "AttributeEnd", "Material", "Shape"};
  const auto tok = tokenize(text);
  std::vector<std::vector<std::string>> out;
  for (std::size_t i = 0; i < tok.size();) {
    const std::string& d = tok[i];
    EXPECT_NE(std::find(kDirectives.begin(), kDirectives.end(), d), kDirectives.end())
        << "unknown directive " << d;
    std::vector<std::string> dir{d};
    ++i;
    if (d == "LookAt") {
      for (int k = 0; k < 9; ++k, ++i) EXPECT_TRUE(i < tok.size() && is_number(tok[i]));
      out.push_back(dir);
      continue;
    }
    if (i < tok.size() && tok[i].front() == '"' && tok[i].find(' ') == std::string::npos)
      dir.push_back(tok[i++]);  // the type, e.g. "conductor"
    while (i < tok.size() && tok[i].front() == '"') {
      const std::string p = tok[i].substr(1, tok[i].size() - 2);
      const auto sp = p.find(' ');
      EXPECT_NE(sp, std::string::npos) << "parameter without a type: " << p;
      const std::string type = p.substr(0, sp);
      dir.push_back(p);
      ++i;
      EXPECT_LT(i, tok.size());
      std::vector<std::string> vals;
      if (tok[i] == "[") {
        for (++i; i < tok.size() && tok[i] != "]"; ++i) vals.push_back(tok[i]);
        EXPECT_LT(i, tok.size()) << "unbalanced [";
        ++i;
      } else {
        vals.push_back(tok[i++]);
      }
      EXPECT_FALSE(vals.empty()) << p;
      for (const auto& v : vals) {
        if (type == "float" || type == "integer" || type == "rgb") {
          EXPECT_TRUE(is_number(v)) << p << " = " << v;
        } else if (type == "string" || type == "spectrum") {
          EXPECT_EQ(v.front(), '"') << p;
        } else if (type == "bool") {
          EXPECT_TRUE(v == "true" || v == "false") << p;
        }
      }
    }
    out.push_back(dir);
  }
  return out;
}

void check_spd(const fs::path& p, const Spectrum& ref) {
  std::ifstream f(p);
  std::string line;
  int n = 0;
  double first = -1, last = -1;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double nm, v;
    ASSERT_TRUE(s >> nm >> v) << line;
    if (first < 0) first = nm;
    last = nm;
    EXPECT_NEAR(v, ref.at_nm(nm), 1e-5 * std::max(1.0, std::abs(v))) << p << " " << nm;
    ++n;
  }
  EXPECT_EQ(first, 360);  // nanometres, not metres or micrometres
  EXPECT_EQ(last, 830);
  EXPECT_EQ(n, 95);
}

}  // namespace

TEST(SceneExport, MitsubaRoughConductorParses) {
  const auto dir = scratch_dir("mitsuba");
  const auto m = gold();
  const auto files = export_mitsuba(m, dir, SceneExportOptions{});
  EXPECT_EQ(files.size(), 4u);
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file((fs::path(dir) / "scene.xml").c_str()));
  const auto scene = doc.child("scene");
  EXPECT_STREQ(scene.attribute("version").value(), "3.0.0");
  const auto bsdf = scene.find_child_by_attribute("bsdf", "id", "microbrdf");
  EXPECT_STREQ(bsdf.attribute("type").value(), "roughconductor");
  EXPECT_STREQ(
      bsdf.find_child_by_attribute("string", "name", "distribution").attribute("value").value(),
      "ggx");
  EXPECT_DOUBLE_EQ(
      bsdf.find_child_by_attribute("float", "name", "alpha_u").attribute("value").as_double(),
      0.12);
  EXPECT_DOUBLE_EQ(
      bsdf.find_child_by_attribute("float", "name", "alpha_v").attribute("value").as_double(), 0.3);
  EXPECT_STREQ(
      bsdf.find_child_by_attribute("spectrum", "name", "eta").attribute("filename").value(),
      "eta.spd");
  EXPECT_TRUE(scene.child("shape").child("ref"));
  EXPECT_STREQ(scene.child("emitter").attribute("type").value(), "constant");
  // The approximation is said in the file (as an XML comment that stays well-formed).
  EXPECT_NE(slurp(fs::path(dir) / "scene.xml").find("skew"), std::string::npos);
  check_spd(fs::path(dir) / "eta.spd", m.constants.n);
  check_spd(fs::path(dir) / "k.spd", m.constants.k);
  pugi::xml_document mat;
  ASSERT_TRUE(mat.load_file((fs::path(dir) / "material.xml").c_str()));
  fs::remove_all(dir);
}

TEST(SceneExport, MitsubaMeasuredReferencesTheBsdfAndCopiesTheEnvmap) {
  const auto dir = scratch_dir("mitsuba_measured");
  SceneExportOptions o;
  o.envmap = std::string(MICROBRDF_TEST_DATA) + "/../../data/envmaps/blender_studio.exr";
  export_mitsuba_measured("material.bsdf", dir, o);
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file((fs::path(dir) / "scene.xml").c_str()));
  const auto scene = doc.child("scene");
  const auto bsdf = scene.find_child_by_attribute("bsdf", "id", "microbrdf");
  EXPECT_STREQ(bsdf.attribute("type").value(), "measured");
  EXPECT_STREQ(bsdf.child("string").attribute("value").value(), "material.bsdf");
  EXPECT_STREQ(scene.child("emitter").attribute("type").value(), "envmap");
  EXPECT_TRUE(fs::exists(fs::path(dir) / "blender_studio.exr"));
  fs::remove_all(dir);
}

TEST(SceneExport, PbrtConductorAndMeasuredTokenize) {
  const auto dir = scratch_dir("pbrt");
  const auto m = gold();
  export_pbrt(m, dir, SceneExportOptions{});
  const auto d = parse_pbrt(slurp(fs::path(dir) / "scene.pbrt"));
  bool material = false, world = false, sphere = false;
  for (const auto& dirv : d) {
    if (dirv[0] == "WorldBegin") world = true;
    if (dirv[0] == "Shape") sphere = dirv.size() > 1 && dirv[1] == "\"sphere\"";
    if (dirv[0] == "Material") {
      material = true;
      EXPECT_EQ(dirv[1], "\"conductor\"");
      for (const char* p : {"spectrum eta", "spectrum k", "float uroughness", "float vroughness",
                            "bool remaproughness"})
        EXPECT_NE(std::find(dirv.begin(), dirv.end(), p), dirv.end()) << p;
    }
  }
  EXPECT_TRUE(material && world && sphere);
  EXPECT_NE(slurp(fs::path(dir) / "scene.pbrt").find("skew"), std::string::npos);
  check_spd(fs::path(dir) / "eta.spd", m.constants.n);
  const auto dm = dir + "_m";
  export_pbrt_measured("material.bsdf", dm, SceneExportOptions{});
  bool measured = false;
  for (const auto& dirv : parse_pbrt(slurp(fs::path(dm) / "scene.pbrt")))
    if (dirv[0] == "Material") measured = dirv[1] == "\"measured\"" && dirv[2] == "string filename";
  EXPECT_TRUE(measured);
  // The tokenizer test can fail: an unbalanced bracket is caught.
  EXPECT_NONFATAL_FAILURE(parse_pbrt("Shape \"sphere\" \"float radius\" [ 1\n"), "unbalanced");
  fs::remove_all(dir);
  fs::remove_all(dm);
}

TEST(SceneExport, NearestGgxOfAnEllipsoidIsAFitAndSaysSo) {
  // Untilted, the ellipsoid NDF is the GGX NDF (Dong eq. 10 with R = I): the fit finds it.
  const auto flat =
      nearest_rough_conductor(EllipsoidDistribution({0.1, 0.3, 0, 0, 0}), metal("Al"));
  EXPECT_NEAR(flat.alpha_u, 0.1, 0.002);
  EXPECT_NEAR(flat.alpha_v, 0.3, 0.006);
  ASSERT_EQ(flat.notes.size(), 1u);
  EXPECT_NE(flat.notes[0].find("nearest GGX of the ellipsoid"), std::string::npos);
  EXPECT_NE(flat.notes[0].find("skew"), std::string::npos);
  // A tilted peak: still a GGX near the ellipsoid's widths, with the note.
  const auto tilted =
      nearest_rough_conductor(EllipsoidDistribution({0.1, 0.3, 8 * M_PI / 180, 0, 0}), metal("Al"));
  EXPECT_GT(tilted.alpha_u, 0.08);
  EXPECT_LT(tilted.alpha_u, 0.12);
  EXPECT_GT(tilted.alpha_v, 0.25);
  EXPECT_LT(tilted.alpha_v, 0.35);
  EXPECT_NE(tilted.notes.at(0).find("theta_x 8 deg"), std::string::npos) << tilted.notes[0];
  // theta_z turns the axes: the renderers cannot, so that is a second note.
  const auto turned =
      nearest_rough_conductor(EllipsoidDistribution({0.1, 0.3, 0, 0, 0.4}), metal("Al"));
  ASSERT_EQ(turned.notes.size(), 2u);
  EXPECT_NE(turned.notes[1].find("texture coordinates"), std::string::npos);
}

TEST(SceneExport, GgxGoesAsItIsAndAQuarterTurnSwapsTheAxes) {
  const auto g = nearest_rough_conductor(GgxDistribution(0.1, 0.3, 0), metal("Cu"));
  EXPECT_DOUBLE_EQ(g.alpha_u, 0.1);
  EXPECT_DOUBLE_EQ(g.alpha_v, 0.3);
  EXPECT_TRUE(g.notes.empty());
  EXPECT_EQ(g.constants.name, metal("Cu").name);
  const auto q = nearest_rough_conductor(GgxDistribution(0.1, 0.3, M_PI / 2), metal("Cu"));
  EXPECT_DOUBLE_EQ(q.alpha_u, 0.3);
  EXPECT_DOUBLE_EQ(q.alpha_v, 0.1);
  EXPECT_TRUE(q.notes.empty());
  // Beckmann: the nearest GGX, said.
  const auto b = nearest_rough_conductor(BeckmannDistribution(0.2), metal("Cu"));
  EXPECT_NEAR(b.alpha_u, b.alpha_v, 1e-3);
  EXPECT_GT(b.alpha_u, 0.1);
  EXPECT_LT(b.alpha_u, 0.3);
  ASSERT_EQ(b.notes.size(), 1u);
  EXPECT_NE(b.notes[0].find("Beckmann"), std::string::npos);
}
