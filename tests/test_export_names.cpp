// File names in the Mitsuba 3 and pbrt-v4 exports read back as the same bytes: quotes,
// backslashes, newlines, tabs, `&<>'` and non-ASCII letters. The XML is read by pugixml; the
// pbrt files by a tokenizer written here from pbrt-v4's rules (a string ends at an unescaped
// `"`, a raw newline inside one is an error, `\` escapes b f n r t \ ' "; `#` comments run to
// the end of the line). A name XML cannot hold is refused, naming it, before anything is written.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <pugixml.hpp>
#include <sstream>

#include "microbrdf/error.hpp"
#include "microbrdf/scene_export.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kNames = {
    "plain.bsdf",
    "q\"uote.bsdf",
    "back\\slash.bsdf",
    "new\nline.bsdf",
    "cr\r\nlf.bsdf",
    "tab\t.bsdf",
    "amp&amp;lt<gt>.bsdf",
    "apos'.bsdf",
    "\xC3\xA9t\xC3\xA9 \xE6\x97\xA5\xE6\x9C\xAC \xF0\x9F\x98\x80.bsdf",  // été 日本 😀
    "dash -- --> end-",
    "all \" \\ \n & < > ' \\n \\\" \xC3\xBC.bsdf",
    "trailing\\"};

std::string dir_for(const std::string& tag) {
  const auto d = fs::path(::testing::TempDir()) /
                 ("microbrdf_names_" + std::to_string(::getpid()) + "_" + tag);
  fs::remove_all(d);
  return d.string();
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Token {
  bool quoted;
  std::string text;  // decoded
};

// pbrt-v4's tokenizer rules (src/pbrt/parser.cpp): ADD_FAILURE on what pbrt would reject.
std::vector<Token> pbrt_tokens(const std::string& t) {
  std::vector<Token> out;
  for (std::size_t i = 0; i < t.size();) {
    const char c = t[i];
    if (c == ' ' || c == '\n' || c == '\t' || c == '\r') {
      ++i;
    } else if (c == '#') {
      while (i < t.size() && t[i] != '\n' && t[i] != '\r') ++i;
    } else if (c == '"') {
      std::string s;
      for (++i;; ++i) {
        if (i >= t.size()) {
          ADD_FAILURE() << "premature end of file inside a quoted string";
          return out;
        }
        if (t[i] == '"') break;
        if (t[i] == '\n') {
          ADD_FAILURE() << "unterminated string (raw newline)";
          return out;
        }
        if (t[i] == '\\') {
          if (++i >= t.size()) {
            ADD_FAILURE() << "premature end of file after an escape";
            return out;
          }
          switch (t[i]) {
            case 'b':
              s += '\b';
              break;
            case 'f':
              s += '\f';
              break;
            case 'n':
              s += '\n';
              break;
            case 'r':
              s += '\r';
              break;
            case 't':
              s += '\t';
              break;
            case '\\':
              s += '\\';
              break;
            case '\'':
              s += '\'';
              break;
            case '"':
              s += '"';
              break;
            default:
              ADD_FAILURE() << "unexpected escaped character " << t[i];
          }
        } else {
          s += t[i];
        }
      }
      ++i;  // the closing quote
      out.push_back({true, s});
    } else if (c == '[' || c == ']') {
      out.push_back({false, std::string(1, c)});
      ++i;
    } else {
      std::size_t e = i;
      while (e < t.size() && !std::strchr(" \n\t\r\"[]#", t[e])) ++e;
      out.push_back({false, t.substr(i, e - i)});
      i = e;
    }
  }
  return out;
}

// The value of `"string filename"` after `Material "measured"`.
std::string pbrt_measured_filename(const std::vector<Token>& tok) {
  for (std::size_t i = 0; i + 3 < tok.size(); ++i)
    if (!tok[i].quoted && tok[i].text == "Material" && tok[i + 1].text == "measured" &&
        tok[i + 2].text == "string filename" && tok[i + 3].quoted)
      return tok[i + 3].text;
  ADD_FAILURE() << "no Material \"measured\" \"string filename\"";
  return "";
}

}  // namespace

TEST(ExportNames, PbrtNamesReadBackByteForByte) {
  const auto dir = dir_for("pbrt");
  const auto plain = pbrt_tokens(slurp([&] {
    export_pbrt_measured("plain.bsdf", dir, {}, {"the BRDF (plain) as a table: plain.bsdf"});
    return fs::path(dir) / "scene.pbrt";
  }()));
  for (const auto& name : kNames) {
    fs::remove_all(dir);
    // The name also appears in a note, written as a comment: it must not leak out of it.
    export_pbrt_measured(name, dir, {}, {"the BRDF (" + name + ") as a table: " + name});
    for (const char* f : {"material.pbrt", "scene.pbrt"}) {
      const auto tok = pbrt_tokens(slurp(fs::path(dir) / f));
      EXPECT_EQ(pbrt_measured_filename(tok), name) << f;
      if (std::string(f) == "scene.pbrt") {
        EXPECT_EQ(tok.size(), plain.size()) << name;
      }
    }
  }
  // Bytes that are not UTF-8 are a file name like any other for pbrt.
  const std::string latin1 = "caf\xE9 \xFF.bsdf";
  fs::remove_all(dir);
  export_pbrt_measured(latin1, dir, {});
  EXPECT_EQ(pbrt_measured_filename(pbrt_tokens(slurp(fs::path(dir) / "material.pbrt"))), latin1);
  // The tokenizer can fail: a raw newline in a string is caught.
  EXPECT_NONFATAL_FAILURE(pbrt_tokens("Material \"measured\" \"string filename\" \"a\nb\""),
                          "raw newline");
  fs::remove_all(dir);
}

TEST(ExportNames, MitsubaNamesReadBackByteForByte) {
  const auto dir = dir_for("mitsuba");
  const std::string env_src = std::string(MICROBRDF_DATA) + "/envmaps/blender_studio.exr";
  const auto envs = dir + "_env";
  fs::create_directories(envs);
  for (const auto& name : kNames) {
    fs::remove_all(dir);
    // The name is the .bsdf's, the environment map's (copied beside the scene) and in a note.
    const fs::path env = fs::path(envs) / (name + ".exr");
    fs::copy_file(env_src, env, fs::copy_options::overwrite_existing);
    SceneExportOptions o;
    o.envmap = env.string();
    export_mitsuba_measured(name, dir, o, {"the BRDF (" + name + ") as a table: " + name});
    for (const char* f : {"material.xml", "scene.xml"}) {
      pugi::xml_document doc;
      const auto r =
          doc.load_file((fs::path(dir) / f).c_str(), pugi::parse_default | pugi::parse_comments);
      ASSERT_TRUE(r) << f << ": " << r.description() << " for " << name;
      const auto bsdf = doc.child("scene").find_child_by_attribute("bsdf", "id", "microbrdf");
      EXPECT_EQ(std::string(bsdf.child("string").attribute("value").value()), name) << f;
      // The note's comment holds the name (its "--" broken up, which XML requires).
      std::string note = bsdf.first_child().value();
      EXPECT_NE(note.find("the BRDF ("), std::string::npos) << f;
      if (std::string(f) == "scene.xml") {
        const auto emitter = doc.child("scene").child("emitter");
        EXPECT_EQ(std::string(emitter.child("string").attribute("value").value()), name + ".exr");
        EXPECT_TRUE(fs::exists(fs::path(dir) / (name + ".exr")));
      }
    }
  }
  fs::remove_all(envs);
  fs::remove_all(dir);
}

TEST(ExportNames, MitsubaRefusesWhatXmlCannotHoldBeforeWriting) {
  const auto dir = dir_for("refused");
  for (const std::string& name :
       {std::string("caf\xE9.bsdf"), std::string("\xFF\xFE.bsdf"), std::string("over\xC0\xAF.bsdf"),
        std::string("bell\x07.bsdf"), std::string("esc\x1B[0m.bsdf")}) {
    try {
      export_mitsuba_measured(name, dir, {});
      ADD_FAILURE() << "accepted " << name;
    } catch (const FileError& e) {
      EXPECT_EQ(e.path(), name);
      EXPECT_TRUE(std::string(e.what()).find("not UTF-8") != std::string::npos ||
                  std::string(e.what()).find("control character") != std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(dir)) << "written before the refusal: " << name;
  }
  // A note (a comment, read by people) with such bytes is written with them spelled out, and the
  // document stays well-formed.
  export_mitsuba_measured("ok.bsdf", dir, {}, {"from caf\xE9\x07.binary -- a -"});
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file((fs::path(dir) / "scene.xml").c_str(),
                            pugi::parse_default | pugi::parse_comments));
  const std::string text = slurp(fs::path(dir) / "scene.xml");
  EXPECT_NE(text.find("caf\\xE9\\x07.binary - - a - -->"), std::string::npos) << text;
  fs::remove_all(dir);
}
