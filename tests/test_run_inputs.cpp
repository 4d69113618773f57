// Outputs never replace an input of the run (microbrdf/run_inputs.hpp): inside a RunInputs
// scope, a committed output whose target is a file a reader opened, under any spelling, is
// refused before anything is renamed, for single files and for output groups alike; outside a
// scope (library and Python use) a program may read a file and write it back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"
#include "microbrdf/run_inputs.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("microbrdf-runinputs-" + std::to_string(::getpid()));
  Scratch() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string file(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
  std::string read(const std::string& name) const {
    std::ifstream in(dir / name);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  bool temporaries_left() const {
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().find(".tmp-") != std::string::npos) return true;
    return false;
  }
};

}  // namespace

TEST(RunInputs, AnOutputOntoAnInputIsRefusedUnderAnySpelling) {
  Scratch s;
  const std::string in = s.file("scan.npy", "scan");
  s.file("other.npy", "other");
  fs::create_symlink(in, s.dir / "link.npy");
  fs::create_hard_link(in, s.dir / "hard.npy");
  const RunInputs run;
  (void)read_file_bytes(in, 1000);
  for (const fs::path& target :
       {fs::path(in), s.dir / "." / "scan.npy", s.dir / "link.npy", s.dir / "hard.npy"}) {
    try {
      write_file_atomic(target.string(), std::string("ndf"));
      ADD_FAILURE() << "replaced the input through " << target;
    } catch (const FileError& e) {
      EXPECT_EQ(e.path(), target.string());
      EXPECT_NE(std::string(e.what()).find("of this run"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(s.temporaries_left());
  }
  EXPECT_EQ(s.read("scan.npy"), "scan");
  // A file that was not read may be replaced.
  write_file_atomic((s.dir / "other.npy").string(), std::string("new"));
  EXPECT_EQ(s.read("other.npy"), "new");
}

TEST(RunInputs, AGroupIsRefusedWholeBeforeAnyRename) {
  Scratch s;
  const std::string side = s.file("scan.json", "{}");
  s.file("out.npy", "earlier");
  const RunInputs run;
  require_regular_file(side);  // what every reader calls first
  {
    OutputGroup group;
    write_file_atomic((s.dir / "out.npy").string(), std::string("new table"));
    write_file_atomic(side, std::string("new sidecar"));
    EXPECT_THROW(group.commit(), FileError);
  }
  EXPECT_EQ(s.read("out.npy"), "earlier");  // the group's first output was not renamed either
  EXPECT_EQ(s.read("scan.json"), "{}");
  EXPECT_FALSE(s.temporaries_left());
}

TEST(RunInputs, AFolderHoldingAnInputIsNotReplaced) {
  Scratch s;
  fs::create_directories(s.dir / "report" / "img");
  std::ofstream(s.dir / "report" / "img" / "scan.npy") << "scan";
  const RunInputs run;
  (void)read_file_bytes((s.dir / "report" / "img" / "scan.npy").string(), 100);
  EXPECT_THROW(refuse_replacing_inputs_under((s.dir / "report").string()), FileError);
  EXPECT_NO_THROW(refuse_replacing_inputs_under((s.dir / "elsewhere").string()));
}

TEST(RunInputs, OutsideARunNothingIsRecorded) {
  Scratch s;
  const std::string in = s.file("scan.npy", "scan");
  (void)read_file_bytes(in, 1000);
  write_file_atomic(in, std::string("rewritten"));  // a library user writing a file back
  EXPECT_EQ(s.read("scan.npy"), "rewritten");
  {
    const RunInputs run;
    (void)read_file_bytes(in, 1000);
    EXPECT_THROW(write_file_atomic(in, std::string("x")), FileError);
  }
  // The scope ended: what it recorded is forgotten.
  write_file_atomic(in, std::string("again"));
  EXPECT_EQ(s.read("scan.npy"), "again");
}
