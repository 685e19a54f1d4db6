// The malformed-URDF corpus (tests/corpus/urdf, see its README): every file is refused with an
// error naming what is wrong (the words of its `expect:` comment), and nothing crashes (this
// binary also runs under ASan + UBSan). The corpus's unbroken base robot loads.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(KILOLOOP_CORPUS_DIR);

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  const auto e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// The words after "expect:" up to the end of the line or "-->", split at ';'.
std::vector<std::string> expected_words(const std::string& text) {
  const auto at = text.find("expect:");
  if (at == std::string::npos) return {"invalid urdf"};
  std::string line = text.substr(at + 7, text.find('\n', at) - at - 7);
  line = line.substr(0, line.find("-->"));
  std::vector<std::string> words;
  std::stringstream ss(line);
  for (std::string w; std::getline(ss, w, ';');)
    if (!trim(w).empty()) words.push_back(lower(trim(w)));
  return words;
}

std::vector<fs::path> corpus_files() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kCorpus / "urdf"))
    if (e.path().extension() == ".urdf") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(UrdfCorpus, TheBaseRobotLoads) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_file((kCorpus / "valid_arm.urdf").string(), "", "link2", &model, &why),
            Status::kOk) << why;
  EXPECT_EQ(model.nq(), 2);
}

TEST(UrdfCorpus, EveryMalformedFileIsRefusedWithItsReason) {
  const auto files = corpus_files();
  ASSERT_GE(files.size(), 20u) << "corpus missing: " << kCorpus;
  for (const fs::path& path : files) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    for (const char* tip : {"", "link2"}) {
      RobotModel model;
      std::string why;
      const Status s = model_from_urdf_file(path.string(), "", tip, &model, &why);
      EXPECT_TRUE(failed(s)) << path.filename() << " loaded (tip '" << tip << "')";
      for (const std::string& word : expected_words(text.str()))
        EXPECT_NE(lower(why).find(word), std::string::npos)
            << path.filename() << ": error lacks '" << word << "': " << why;
    }
  }
}

}  // namespace
}  // namespace kiloloop
