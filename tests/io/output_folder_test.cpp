// OutputSet::add_folder: a folder written as a whole in a temporary folder beside its target,
// moved into place with the other outputs or removed with everything in it, also by the signal
// handler's remove_temporaries_for_exit(); an old folder replaced only when it is empty, or with
// overwrite when it holds the marker file.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "io/output_set.hpp"
#include "io/whole_file.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;

class OutputFolders : public ::testing::Test {
 protected:
  std::string at(const std::string& name) const { return dir_ + "/" + name; }
  std::set<std::string> names() const { return test::names_in(dir_); }
  // Writes a small tree into FOLDER: m.json and 1/2/3.bin.
  static void fill(const std::string& folder, const std::string& bytes) {
    write_whole_file(folder + "/m.json", bytes);
    write_whole_file(folder + "/1/2/3.bin", bytes);
  }
  std::map<std::string, std::string> tree(const std::string& name) const {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(at(name)))
      if (e.is_regular_file()) files[fs::relative(e.path(), at(name)).string()] = test::slurp(e);
    return files;
  }

  const std::string dir_ = test::scratch_dir("output_folder");
};

TEST_F(OutputFolders, CommitMovesTheFolderWithTheFiles) {
  OutputSet set(false);
  set.add(at("a.txt"), "a").write(std::string("a"));
  fill(set.add_folder(at("t"), "m.json"), "new");
  EXPECT_EQ(names().size(), 2u);  // the two temporaries
  set.commit();
  EXPECT_EQ(names(), (std::set<std::string>{"a.txt", "t"}));
  EXPECT_EQ(tree("t"),
            (std::map<std::string, std::string>{{"1/2/3.bin", "new"}, {"m.json", "new"}}));
}

TEST_F(OutputFolders, UncommittedTheTemporaryFolderGoes) {
  {
    OutputSet set(false);
    fill(set.add_folder(at("t"), "m.json"), "new");
  }
  EXPECT_EQ(names(), std::set<std::string>{});
}

TEST_F(OutputFolders, SignalHandlerRemovesTheTemporaryFolder) {
  OutputSet set(false);
  const std::string temp = set.add_folder(at("t"), "m.json");
  fill(temp, "new");
  for (int i = 0; i < 200; ++i) write_whole_file(temp + "/many/" + std::to_string(i), "x");
  EXPECT_TRUE(remove_temporaries_for_exit());
  EXPECT_EQ(names(), std::set<std::string>{});
}

TEST_F(OutputFolders, OldFolderReplacedWithOverwriteOrPutBack) {
  fill(at("t"), "old");
  {
    OutputSet set(false);
    EXPECT_THROW(set.add_folder(at("t"), "m.json"), OutputError);
  }
  {
    OutputSet set(true);
    fill(set.add_folder(at("t"), "m.json"), "new");
    set.add(at("b.txt"), "b").write(std::string("b"));
    OutputFile& c = set.add(at("c.txt"), "c");
    c.close();
    fs::remove(c.temp_path());  // c cannot be moved: the folder stays the old one
    EXPECT_THROW(set.commit(), OutputError);
  }
  EXPECT_EQ(names(), std::set<std::string>{"t"});
  EXPECT_EQ(tree("t").at("1/2/3.bin"), "old");
  OutputSet set(true);
  write_whole_file(set.add_folder(at("t"), "m.json") + "/m.json", "new");
  set.commit();
  EXPECT_EQ(names(), std::set<std::string>{"t"});
  EXPECT_EQ(tree("t"), (std::map<std::string, std::string>{{"m.json", "new"}}));
}

TEST_F(OutputFolders, AFolderWithoutTheMarkerIsNotReplaced) {
  fs::create_directory(at("t"));
  test::spit(at("t/notes.txt"), "mine");
  OutputSet set(true);
  EXPECT_THROW(set.add_folder(at("t"), "m.json"), OutputError);
  fs::remove(at("t/notes.txt"));
  fill(set.add_folder(at("t"), "m.json"), "new");  // empty: replaced
  set.commit();
  EXPECT_EQ(tree("t").at("m.json"), "new");
}

}  // namespace
}  // namespace tincdt::io
