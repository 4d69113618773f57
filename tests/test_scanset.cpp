// Scan sets: directories, globs and manifests expand to ordered file lists; scans are read one
// at a time.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/height_preview.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/scanset.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {
fs::path make_dir() {
  fs::path d = fs::temp_directory_path() / ("microbrdf-scanset-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "sub");
  GratingParams g;
  g.nx = 16;
  g.ny = 8;
  for (const char* name : {"b.x3p", "a.x3p", "c.gwy", "sub/d.x3p"})
    write_surface(generate_grating(g), (d / name).string());
  std::ofstream(d / "notes.md") << "not a scan\n";
  return d;
}
}  // namespace

TEST(scanset, DirectoryGlobManifest) {
  fs::path d = make_dir();
  auto dir = expand_scan_inputs({d.string()});
  ASSERT_EQ(dir.size(), 3u);  // not recursive, not the .md
  EXPECT_EQ(fs::path(dir[0]).filename(), "a.x3p");
  EXPECT_EQ(fs::path(dir[2]).filename(), "c.gwy");
  auto glob = expand_scan_inputs({(d / "*.x3p").string()});
  ASSERT_EQ(glob.size(), 2u);
  EXPECT_EQ(fs::path(glob[1]).filename(), "b.x3p");
  std::ofstream(d / "list.txt") << "# comment\n\nsub/d.x3p\n  a.x3p  \n";
  auto man = expand_scan_inputs({"@" + (d / "list.txt").string()});
  ASSERT_EQ(man.size(), 2u);
  EXPECT_EQ(man[0], (d / "sub/d.x3p").string());
  EXPECT_THROW(expand_scan_inputs({(d / "*.nothing").string()}), FileError);
  EXPECT_THROW(expand_scan_inputs({"@" + (d / "missing.txt").string()}), FileError);
  std::size_t count = 0;
  for_each_scan(glob, {}, [&](std::size_t i, const std::string& path, Surface& s) {
    EXPECT_EQ(i, count++);
    EXPECT_EQ(path, glob[i]);
    EXPECT_EQ(s.nx, 16u);
  });
  EXPECT_EQ(count, 2u);
  fs::remove_all(d);
}

TEST(preview, HeightPreviewShapeAndColourBar) {
  GratingParams g;
  g.nx = 300;
  g.ny = 100;
  Surface s = generate_grating(g);
  for (std::size_t i : {0UL, 1UL, 300UL, 301UL}) s.invalidate(i);  // one whole 2x2 preview cell
  auto img = render_height_preview(s, 150);
  EXPECT_EQ(img.height, 60u);     // 150 x 50 image, at least 60 tall for the labels
  EXPECT_GT(img.width, 150u);     // plus colour bar and labels
  EXPECT_EQ(img.pixels[0], 128);  // the invalid corner is grey
  EXPECT_NE(img.pixels[3], 128);  // its neighbour is valid
  auto bad = fs::temp_directory_path() / "no-such-dir-microbrdf" / "x.png";
  EXPECT_THROW(write_png(bad.string(), img), FileError);
}
